// Tests for the texture coordinates and materials the global DFFD's outputs keep (global_dffd_split.cpp,
// global_dffd_openings.cpp, clip_cap.cpp): a sphere with two planar charts meeting along a texture seam
// that crosses the discontinuity plane, and a material per chart, split open, stitched and capped. Every
// corner's coordinate is its chart's map at its rest position (to 1e-9), every face keeps the material of
// the face it is a piece of, caps are walls mapped on their plane, and a capped mesh's OBJ names the walls'
// material.
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "global_dffd/global_dffd_fixture.h"

#include "incise/global_dffd/clip_cap.h"
#include "incise/global_dffd/global_dffd.h"
#include "incise/mesh/shapes.h"
#include "incise/mesh/surface_query.h"
#include "support/temp_dir.h"

namespace incise::global_dffd::texture_test {
namespace {

// Two planar maps, each a linear function of the rest position.
Eigen::Vector2d chart(int which, const Eigen::Vector3d& x) {
  return which == 0 ? Eigen::Vector2d(40.0 * x.x() + 3.0 * x.z() + 0.5, 40.0 * x.y() - 7.0 * x.z() + 0.25)
                    : Eigen::Vector2d(-25.0 * x.y() + 11.0 * x.x() + 2.0, 30.0 * x.z() + 5.0 * x.x() - 1.0);
}

// The chart of a face of the model: by its centroid's y (the seam crosses the plane x = 0 at the bar).
int chartOfCentroid(const Eigen::Vector3d& centroid) { return centroid.y() < 0.002 ? 0 : 1; }

std::array<Eigen::Vector3d, 3> corners(const mesh::TriMesh& m, mesh::TriMesh::FaceHandle f) {
  std::array<Eigen::Vector3d, 3> x;
  auto h = m.halfedge_handle(f);
  for (size_t i = 0; i < 3; ++i, h = m.next_halfedge_handle(h)) x[i] = mesh::toEigen(m.point(m.to_vertex_handle(h)));
  return x;
}

// A sphere (the global DFFD tests' model) with the two charts and a material per chart.
mesh::SurfaceMesh texturedSphere() {
  mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d(0.0, 0.004, 0.0), 0.012, 3);
  sphere.addTexCoords();
  const int materials[2] = {sphere.addMaterial({"skin_a", {"Kd 0.9 0.7 0.6"}}),
                            sphere.addMaterial({"skin_b", {"Kd 0.8 0.6 0.5"}})};
  const mesh::TriMesh& m = sphere.mesh();
  for (const auto f : m.faces()) {
    const auto x = corners(m, f);
    const int which = chartOfCentroid((x[0] + x[1] + x[2]) / 3.0);
    sphere.setMaterial(f, materials[which]);
    for (const auto h : m.fh_range(f))
      sphere.setTexCoord(h, chart(which, mesh::toEigen(m.point(m.to_vertex_handle(h)))));
  }
  return sphere;
}

// The chart (material index) of the model's face containing point p (a piece's centroid), if any.
std::optional<int> sourceChart(const mesh::SurfaceMesh& model, const Eigen::Vector3d& p) {
  const mesh::TriMesh& m = model.mesh();
  for (const auto f : m.faces()) {
    const auto x = corners(m, f);
    if ((mesh::closestPointOnTriangle(p, x[0], x[1], x[2]) - p).norm() < 1e-12) return model.material(f);
  }
  return std::nullopt;
}

using fixture::bar;
using fixture::options;

// Over the faces of a split: the largest error of a corner's coordinate against its face's chart at its
// rest position, faces whose material is not their source's, faces with no source (a stitching strip's),
// and the corners on a discontinuity plane.
struct SplitCheck {
  double worst_uv = 0.0;
  int wrong_material = 0, without_source = 0, corners_checked = 0;
  int plane_corners = 0;
};

SplitCheck checkSplit(const DffdSplit& split, const mesh::SurfaceMesh& model) {
  SplitCheck c;
  for (size_t f = 0; f < split.faces.size(); ++f) {
    const auto& t = split.faces[f];
    const Eigen::Vector3d centroid = (split.rest_m[t[0]] + split.rest_m[t[1]] + split.rest_m[t[2]]) / 3.0;
    const std::optional<int> source = sourceChart(model, centroid);
    if (!source) {
      ++c.without_source;
      continue;
    }
    c.wrong_material += split.face_material[f] != *source;
    for (size_t i = 0; i < 3; ++i) {
      const auto v = static_cast<size_t>(t[i]);
      const double error = (split.face_uv[f][i] - chart(*source, split.rest_m[v])).norm();
      c.plane_corners += split.plane[v] >= 0;
      c.worst_uv = std::max(c.worst_uv, error);
      ++c.corners_checked;
    }
  }
  return c;
}

TEST_CASE("global_dffd texture: the open split keeps every corner's chart exactly, across the seam", "[cutting]") {
  const mesh::SurfaceMesh model = texturedSphere();
  const GlobalDffd dffd({bar()}, options());
  const DffdSplit split = splitAtDiscontinuities(model, dffd, Openings::Leave);
  REQUIRE(split.face_uv.size() == split.faces.size());
  REQUIRE(split.face_material.size() == split.faces.size());
  REQUIRE(split.materials == model.materials());
  REQUIRE(split.faces.size() > model.mesh().n_faces());  // the plane split faces
  const SplitCheck c = checkSplit(split, model);
  CHECK(c.without_source == 0);
  CHECK(c.wrong_material == 0);
  CHECK(c.corners_checked == 3 * static_cast<int>(split.faces.size()));
  CHECK(c.worst_uv < 1e-9);
  // The meshes made from it carry them, corner by corner: at rest, each corner its chart's map; welded
  // (vertices renumbered, positions deformed), each face the split's coordinates.
  const mesh::SurfaceMesh rest = split.surface();
  REQUIRE(rest.hasTexCoords());
  REQUIRE(rest.materials() == model.materials());
  double worst_rest = 0.0;
  for (const auto f : rest.mesh().faces())
    for (const auto h : rest.mesh().fh_range(f))
      worst_rest = std::max(worst_rest,
                            (rest.texCoord(h) -
                             chart(rest.material(f), mesh::toEigen(rest.mesh().point(rest.mesh().to_vertex_handle(h)))))
                                .norm());
  CHECK(worst_rest < 1e-9);
  std::vector<Eigen::Vector3d> positions(split.rest_m.size());
  deformSplit(split, dffd, positions);
  const mesh::SurfaceMesh welded = weldClosedLips(split, positions);
  REQUIRE(welded.hasTexCoords());
  REQUIRE(welded.mesh().n_faces() == split.faces.size());
  double worst_welded = 0.0;
  for (const auto f : welded.mesh().faces()) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (const auto h : welded.mesh().fh_range(f)) sum += welded.texCoord(h);
    const auto& uv = split.face_uv[static_cast<size_t>(f.idx())];
    worst_welded = std::max(worst_welded, (sum - (uv[0] + uv[1] + uv[2])).norm());
    CHECK(welded.material(f) == split.face_material[static_cast<size_t>(f.idx())]);
  }
  CHECK(worst_welded < 1e-12);
}

TEST_CASE("global_dffd texture: the stitched split keeps every corner's chart and textures every face", "[cutting]") {
  const mesh::SurfaceMesh model = texturedSphere();
  GlobalDffd dffd({bar()}, options());
  const DffdSplit split = splitAtDiscontinuities(model, dffd, Openings::Close);
  REQUIRE(split.left_open == 0);
  REQUIRE(split.face_uv.size() == split.faces.size());
  REQUIRE(split.face_material.size() == split.faces.size());
  const SplitCheck c = checkSplit(split, model);
  // A face with a corner welded onto the other lip's vertex is off the model (no source, not checked: that
  // corner keeps its own lip's coordinate); every other face is exact.
  CHECK(c.without_source < static_cast<int>(split.faces.size()) / 10);
  CHECK(c.wrong_material == 0);
  CHECK(c.worst_uv < 1e-9);
  CHECK(c.corners_checked == 3 * (static_cast<int>(split.faces.size()) - c.without_source));
  CHECK(c.plane_corners > 100);
  dffd.stitch(0, stitchLevel(split, dffd, 0));
  const mesh::SurfaceMesh out = deformSplit(split, dffd);
  CHECK(boundaryLoops(out.mesh()) == 0);
  CHECK(out.hasTexCoords());
  CHECK(out.materials() == model.materials());
}

// Over a clipped mesh: the worst tissue corner against its chart at its position, the worst cap corner
// against planarTexCoords, and the count of cap (wall) faces.
struct ClipCheck {
  double worst_tissue = 0.0, worst_cap = 0.0;
  int caps = 0, wrong_material = 0;
};

ClipCheck checkClipped(const mesh::SurfaceMesh& clipped, const mesh::SurfaceMesh& model) {
  ClipCheck c;
  const mesh::TriMesh& m = clipped.mesh();
  for (const auto f : m.faces()) {
    const mesh::FaceCorners k = mesh::faceCorners(clipped, f);
    std::array<Eigen::Vector3d, 3> x;
    for (size_t i = 0; i < 3; ++i) x[i] = mesh::toEigen(m.point(k.vertex[i]));
    if (clipped.kind(f) == mesh::FaceKind::Wall) {
      ++c.caps;
      const auto planar = mesh::planarTexCoords(x);
      for (size_t i = 0; i < 3; ++i) c.worst_cap = std::max(c.worst_cap, (k.uv[i] - planar[i]).norm());
      continue;
    }
    const std::optional<int> source = sourceChart(model, (x[0] + x[1] + x[2]) / 3.0);
    c.wrong_material += !source || clipped.material(f) != *source;
    for (size_t i = 0; source && i < 3; ++i)
      c.worst_tissue = std::max(c.worst_tissue, (k.uv[i] - chart(*source, x[i])).norm());
  }
  return c;
}

TEST_CASE("global_dffd texture: a clipped and capped mesh keeps its charts, the caps are mapped walls", "[cutting]") {
  const mesh::SurfaceMesh model = texturedSphere();
  for (const KeepSide keep : {KeepSide::Below, KeepSide::Above}) {
    const mesh::SurfaceMesh clipped = clipAndCap(model, 0, 0.0011, keep);
    REQUIRE(clipped.hasTexCoords());
    REQUIRE(clipped.materials() == model.materials());
    const ClipCheck c = checkClipped(clipped, model);
    CHECK(c.caps > 10);
    CHECK(c.wrong_material == 0);
    CHECK(c.worst_tissue < 1e-9);
    CHECK(c.worst_cap < 1e-9);
  }
  // cappedDeform's output keeps them (its caps are walls); the OBJ names the walls' material for the caps.
  const mesh::SurfaceMesh out = cappedDeform(model, GlobalDffd({bar()}, options()));
  REQUIRE(out.hasTexCoords());
  REQUIRE(out.hasMaterials());
  int walls = 0;
  for (const auto f : out.mesh().faces()) walls += out.kind(f) == mesh::FaceKind::Wall;
  CHECK(walls > 20);
  const test::TempDir dir;
  mesh::saveObj(out, dir.path() / "capped.obj");
  std::ifstream obj(dir.path() / "capped.obj");
  std::stringstream text;
  text << obj.rdbuf();
  CHECK(text.str().find("usemtl incise_wall") != std::string::npos);
  CHECK(text.str().find("usemtl skin_b") != std::string::npos);
  CHECK(std::filesystem::exists(dir.path() / "capped.mtl"));
  const mesh::SurfaceMesh back = mesh::loadSurfaceMesh(dir.path() / "capped.obj");
  CHECK(back.hasTexCoords());
}

}  // namespace
}  // namespace incise::global_dffd::texture_test
