// Tests for cutting/incision/src/surface_cutter_texture.cpp: texture coordinates through an incision (splits,
// refinement, flips, the seam's copies, walls) and a through-cut (mesh::differenceOf's pieces).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <memory>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/shapes.h"
#include "stroke_fixture.h"

using namespace incise;
using namespace incise::incision;
using incise::incision::testing::backStroke;
using incise::incision::testing::bunny;
using incise::incision::testing::kPlanarMap;
using incise::incision::testing::mapPlanar;
using incise::incision::testing::planar;

namespace {

// Where a vertex was before the incision moved it: its rest position if bound, else where it is.
Eigen::Vector3d restOf(const SurfaceCutter& cutter, const mesh::SurfaceMesh& s, mesh::TriMesh::VertexHandle v) {
  const auto b = cutter.binding(v);
  return b ? b->rest_m : mesh::toEigen(s.mesh().point(v));
}

std::unique_ptr<SurfaceCutter> cutAlong(mesh::SurfaceMesh& s, const Stroke& stroke, const CutterOptions& options) {
  auto cutter = std::make_unique<SurfaceCutter>(s, options);
  cutter->begin(stroke.first, stroke.blade_direction);
  cutter->extend(stroke.samples);
  cutter->finish();
  cutter->settle();
  INFO(cutter->stats().failure);
  REQUIRE(cutter->stats().failure.empty());
  return cutter;
}

}  // namespace

TEST_CASE("Texture coordinates of a planar map come out exact at every skin corner of a cut, walls get theirs",
          "[surface_cutter][texture]") {
  mesh::SurfaceMesh s = bunny(1);
  mapPlanar(s);
  CutterOptions options;
  options.refine = CutterOptions::Refine::Linear;
  const Stroke stroke = backStroke(s, 0.03);
  const auto cutter = cutAlong(s, stroke, options);
  const IncisionFigures& figures = cutter->stats().figures.back();
  REQUIRE(figures.shortfall == Shortfall::None);
  REQUIRE(figures.groove_length_m > 0.02);
  REQUIRE(cutter->stats().refined_vertices > 0);  // refinement's splits are among those checked
  const mesh::TriMesh& m = s.mesh();
  int skin_corners = 0, moved = 0, wall_faces = 0;
  double worst = 0.0;
  for (const auto f : m.faces()) {
    const mesh::FaceCorners c = mesh::faceCorners(s, f);
    if (s.kind(f) == mesh::FaceKind::Wall) {
      ++wall_faces;
      for (const Eigen::Vector2d& uv : c.uv) {
        // Along the stroke (0 to 3 cm, with the lattice's ends) and down to the blade's depth, per 1 cm tile.
        CHECK(uv.x() > -1.0);
        CHECK(uv.x() < 4.0);
        CHECK(uv.y() > -0.05);
        CHECK(uv.y() < 1.05 * options.incision.depth_m / mesh::kWallTextureTile_m);
      }
      continue;
    }
    for (std::size_t i = 0; i < 3; ++i) {
      ++skin_corners;
      const Eigen::Vector3d rest = restOf(*cutter, s, c.vertex[i]);
      moved += (rest - mesh::toEigen(m.point(c.vertex[i]))).norm() > 1e-5;
      worst = std::max(worst, (c.uv[i] - planar(rest)).norm());
    }
  }
  INFO("skin corners " << skin_corners << ", moved " << moved << ", wall faces " << wall_faces);
  CHECK(wall_faces > 50);
  CHECK(moved > 50);  // the lips opened: their coordinates are the rest frame's, not where they are now
  CHECK(worst < 1e-9);
}

TEST_CASE("A texture seam and a material boundary crossing the stroke stay where they were through the cut",
          "[surface_cutter][texture]") {
  mesh::SurfaceMesh s = bunny(1);
  const double seam_x_m = 0.003;  // the stroke runs from x = -12 mm to 18 mm
  const Eigen::Vector2d shift(0.5, 0.0);
  mapPlanar(s, seam_x_m, shift);
  // Material 1 on the shifted side (the same faces), 0 on the other.
  s.addMaterial({"left", {}});
  s.addMaterial({"right", {}});
  for (const auto f : s.mesh().faces()) {
    const mesh::FaceCorners c = mesh::faceCorners(s, f);
    s.setMaterial(f, (c.uv[0] - planar(mesh::toEigen(s.mesh().point(c.vertex[0])))).norm() > 0.25 ? 1 : 0);
  }
  const auto cutter = cutAlong(s, backStroke(s, 0.03), CutterOptions{});
  REQUIRE(cutter->stats().figures.back().groove_length_m > 0.02);
  // Every skin face keeps one of the two maps at all three corners; split faces of both are there.
  int plain = 0, shifted = 0, neither = 0;
  for (const auto f : s.mesh().faces()) {
    if (s.kind(f) == mesh::FaceKind::Wall) continue;
    const mesh::FaceCorners c = mesh::faceCorners(s, f);
    bool is_plain = true, is_shifted = true;
    for (std::size_t i = 0; i < 3; ++i) {
      const Eigen::Vector2d expected = planar(restOf(*cutter, s, c.vertex[i]));
      is_plain = is_plain && (c.uv[i] - expected).norm() < 1e-9;
      is_shifted = is_shifted && (c.uv[i] - expected - shift).norm() < 1e-9;
    }
    if (s.kind(f) == mesh::FaceKind::Split) plain += is_plain, shifted += is_shifted;
    neither += !is_plain && !is_shifted;
    CHECK(s.material(f) == (is_shifted ? 1 : 0));
  }
  INFO("split faces plain " << plain << ", shifted " << shifted);
  CHECK(neither == 0);
  CHECK(plain > 10);
  CHECK(shifted > 10);
}

TEST_CASE("A through-cut's pieces keep the tissue's texture coordinates, its kerf gets the wall's",
          "[surface_cutter][texture][through]") {
  mesh::SurfaceMesh slab = mesh::makeSkinPad(Eigen::Vector3d(0.04, 0.003, 0.04), 0.001);
  mapPlanar(slab);
  StrokePathOptions path;
  path.start_m = Eigen::Vector3d(-0.0199, 0.0, 0.0003);
  path.length_m = 0.0398;
  Stroke stroke = strokeAlongPath(slab, path);
  stroke.first.depth_m = 0.004;
  for (StrokeSample& sample : stroke.samples) sample.depth_m = 0.004;
  CutterOptions options;
  options.incision.depth_m = 0.005;
  options.incision.beta_m = 0.0025;
  const auto cutter = cutAlong(slab, stroke, options);
  REQUIRE(cutter->stats().figures.back().through == ThroughCut::Made);
  REQUIRE(cutter->stats().figures.back().pieces == 2);
  // Skin corners: the planar map where the vertex is now, to within the wound's opening (its lips moved
  // sideways by at most opening_m / 2: the map's largest gain x that), never a default (0, 0).
  const double tolerance = kPlanarMap.norm() * 0.5 * options.incision.opening_m + 1e-9;
  int skin = 0, kerf = 0;
  for (const auto f : slab.mesh().faces()) {
    const mesh::FaceCorners c = mesh::faceCorners(slab, f);
    if (slab.kind(f) == mesh::FaceKind::Wall) {
      ++kerf;
      for (const Eigen::Vector2d& uv : c.uv) CHECK(uv.allFinite());
      continue;
    }
    ++skin;
    for (std::size_t i = 0; i < 3; ++i)
      CHECK((c.uv[i] - planar(mesh::toEigen(slab.mesh().point(c.vertex[i])))).norm() <= tolerance);
  }
  CHECK(skin > 1000);
  CHECK(kerf > 20);
}
