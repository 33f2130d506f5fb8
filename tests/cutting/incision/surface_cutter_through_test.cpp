// Cuts through the tissue: a blade deeper than the tissue is thick splits its far side too, and a piece cut
// free is a closed piece of its own with its volume.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/self_intersection.h"
#include "incise/mesh/shapes.h"
#include "incise/mesh/solid.h"
#include "incise/mesh/thickness.h"
#include "incise/tets/tet_cutter.h"
#include "incise/tets/tetrahedralize.h"
#include "stroke_fixture.h"

using namespace incise;
using namespace incise::incision;

namespace {

constexpr double kSlabM = 0.003, kSideM = 0.04, kGridM = 0.001;

mesh::SurfaceMesh throughSlab() { return mesh::makeSkinPad(Eigen::Vector3d(kSideM, kSlabM, kSideM), kGridM); }

// A stroke along +x at z = z_m from x0_m to x1_m, the blade's tip depth going linearly from depth0_m to
// depth1_m.
Stroke strokeAcross(const mesh::SurfaceMesh& tissue, double x0_m, double x1_m, double z_m, double depth0_m,
                    double depth1_m) {
  StrokePathOptions path;
  path.start_m = Eigen::Vector3d(x0_m, 0.0, z_m);
  path.length_m = x1_m - x0_m;
  Stroke stroke = strokeAlongPath(tissue, path);
  const auto depthAt = [&](const StrokeSample& s) {
    return depth0_m + (depth1_m - depth0_m) * (s.point_m.x() - x0_m) / (x1_m - x0_m);
  };
  stroke.first.depth_m = depthAt(stroke.first);
  for (StrokeSample& s : stroke.samples) s.depth_m = depthAt(s);
  return stroke;
}

CutterOptions throughOptions() {
  CutterOptions options;
  options.incision.depth_m = 0.005;
  options.incision.beta_m = 0.0025;  // lattice below the skin: (normal_controls / 2) beta >= depth / 0.8
  return options;
}

const IncisionFigures& cut(mesh::SurfaceMesh& tissue, const Stroke& stroke) {
  static CutterOptions options = throughOptions();
  auto cutter = std::make_unique<SurfaceCutter>(tissue, options);
  cutter->begin(stroke.first, stroke.blade_direction);
  cutter->extend(stroke.samples);
  cutter->settle();
  INFO(cutter->stats().failure);
  REQUIRE(cutter->stats().failure.empty());
  static IncisionFigures figures;
  figures = cutter->stats().figures.back();
  return figures;
}

void requireValidSolid(const mesh::SurfaceMesh& tissue, int euler) {
  const mesh::ManifoldReport report = mesh::checkManifold(tissue.mesh());
  INFO(report.first_problem);
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == euler);
  REQUIRE(mesh::findSelfIntersections(tissue.mesh()).empty());
}

}  // namespace

TEST_CASE("A stroke through a 3 mm slab from edge to edge leaves two closed pieces with the slab's halves' volumes",
          "[surface_cutter][through]") {
  mesh::SurfaceMesh tissue = throughSlab();
  const double z_m = 0.0003;  // off the grid lines
  const IncisionFigures& f = cut(tissue, strokeAcross(tissue, -0.0199, 0.0199, z_m, 0.004, 0.004));
  REQUIRE(f.through_samples > 0);
  REQUIRE(f.through == ThroughCut::Made);
  REQUIRE(f.pieces == 2);
  requireValidSolid(tissue, 4);  // two spheres
  const std::vector<mesh::Piece> parts = mesh::pieces(tissue.mesh());
  REQUIRE(parts.size() == 2);
  // The halves z < z_m and z > z_m, less half the kerf's width each, and less the wound's V: the DFFD's
  // opening pushes the lips aside (opening_m / 2 wide at the skin, 0 at the floor 2.4 mm down), into the
  // tissue around them, whose volume it does not keep: about 1.5% of each half here.
  const double big_m3 = (0.5 * kSideM + z_m - 0.5 * SurfaceCutter::kKerfM) * kSideM * kSlabM;
  const double small_m3 = (0.5 * kSideM - z_m - 0.5 * SurfaceCutter::kKerfM) * kSideM * kSlabM;
  CHECK(parts[0].volume_m3 == Approx(big_m3).epsilon(0.02));
  CHECK(parts[1].volume_m3 == Approx(small_m3).epsilon(0.02));
  // Their difference places the cut: 2 z_m across the slab.
  CHECK(parts[0].volume_m3 - parts[1].volume_m3 == Approx(2.0 * z_m * kSideM * kSlabM).epsilon(0.03));
  CHECK(f.piece_volumes_m3[0] == parts[0].volume_m3);
  CHECK(f.piece_volumes_m3[1] == parts[1].volume_m3);
}

TEST_CASE("A through stroke inside the slab leaves one piece with a slot through it", "[surface_cutter][through]") {
  mesh::SurfaceMesh tissue = throughSlab();
  const double volume_m3 = mesh::pieces(tissue.mesh()).at(0).volume_m3;
  const IncisionFigures& f = cut(tissue, strokeAcross(tissue, -0.01, 0.01, 0.0003, 0.004, 0.004));
  REQUIRE(f.through == ThroughCut::Made);
  REQUIRE(f.pieces == 1);
  requireValidSolid(tissue, 0);  // a torus: the slot goes through
  CHECK(f.piece_volumes_m3[0] < volume_m3);
  CHECK(f.piece_volumes_m3[0] == Approx(volume_m3).epsilon(0.01));
}

TEST_CASE("A stroke whose tip goes through only along its second half slots the slab there only",
          "[surface_cutter][through]") {
  mesh::SurfaceMesh tissue = throughSlab();
  // 1 mm deep at x = -10 mm to 5 mm at x = +10 mm: through (>= 3 mm) from x = 0 on.
  const IncisionFigures& f = cut(tissue, strokeAcross(tissue, -0.01, 0.01, 0.0003, 0.001, 0.005));
  REQUIRE(f.through == ThroughCut::Made);
  REQUIRE(f.pieces == 1);
  requireValidSolid(tissue, 0);
  // The far side is split only under the through part (x > 0, and the kerf's reach before it).
  const mesh::TriMesh& m = tissue.mesh();
  double far_split_min_x = 1.0;
  for (const auto v : m.vertices())
    if (tissue.kind(v) != mesh::VertexKind::Original && m.point(v)[1] < -kSlabM + 1e-9)
      far_split_min_x = std::min(far_split_min_x, m.point(v)[0]);
  CHECK(far_split_min_x > -2.0 * SurfaceCutter::kKerfReachSpacings * throughOptions().incision.spacing_m);
  CHECK(far_split_min_x < 0.002);
}

TEST_CASE("A stroke that stays above the far side cuts nothing through", "[surface_cutter][through]") {
  mesh::SurfaceMesh tissue = throughSlab();
  const IncisionFigures& f = cut(tissue, strokeAcross(tissue, -0.01, 0.01, 0.0003, 0.002, 0.002));
  CHECK(f.through_samples == 0);
  CHECK(f.through == ThroughCut::None);
  requireValidSolid(tissue, 2);
}

// The slab's rest tets after `stroke` cut through it, followed sample by sample, and the tet cutter's snap
// tolerance.
static std::vector<double> tetPiecesAfter(mesh::SurfaceMesh& tissue, const Stroke& stroke, double& snap_m) {
  tets::TetrahedralizeOptions o;
  o.max_volume_m3 = 2e-9;
  const tets::TetMesh volume = tets::tetrahedralize(tissue, o);
  const CutterOptions options = throughOptions();
  SurfaceCutter cutter(tissue, options);
  tets::TetCutter follower(volume, tets::TetCutterOptions{});
  cutter.begin(stroke.first, stroke.blade_direction);
  for (const StrokeSample& s : stroke.samples) {
    cutter.extend(s);
    follower.follow(*cutter.incision(), cutter.stats().incisions);
  }
  cutter.finish();
  cutter.settle();
  follower.follow(*cutter.incision(), cutter.stats().incisions, tets::TetBudget::All);
  REQUIRE_FALSE(follower.pending());
  INFO(follower.stats().failure);
  REQUIRE(follower.stats().failure.empty());
  const tets::TetView rest = follower.view(tets::TetShape::Rest);
  REQUIRE(rest.inverted_tets == 0);
  snap_m = follower.snapToleranceM();
  return tets::pieceVolumes(rest.mesh);
}

TEST_CASE("The tets follow a cut through the slab: two pieces with the halves' volumes", "[surface_cutter][through]") {
  mesh::SurfaceMesh tissue = throughSlab();
  const double z_m = 0.0003;
  Stroke stroke = strokeAcross(tissue, -0.0199, 0.0199, z_m, 0.004, 0.004);
  SECTION("through from the first sample") {}
  SECTION("the blade still going in over the first 0.3 mm: the rim at the slab's edge is cut through too") {
    // As a replay's blade that descends at the stroke's start: the first stations are shallow and not
    // through, so their columns' lattice ends above the rim's lowest nodes. The tets between them and the
    // slab's edge must still be cut down to the far side.
    stroke.first.depth_m = 0.0005;
    for (StrokeSample& s : stroke.samples)
      if (s.point_m.x() < -0.0196) s.depth_m = 0.0005 + 0.0035 * (s.point_m.x() + 0.0199) / 0.0003;
  }
  double snap_m = 0.0;
  const std::vector<double> pieces = tetPiecesAfter(tissue, stroke, snap_m);
  REQUIRE(pieces.size() == 2);
  // The tets are split on the cut's plane (no kerf), whose nodes within the snap tolerance lie on it: the
  // halves to within that, and together the whole slab.
  INFO("snap tolerance " << snap_m << " m");
  const double slice_m3 = snap_m * kSideM * kSlabM;
  CHECK(std::abs(pieces[0] - (0.5 * kSideM + z_m) * kSideM * kSlabM) <= slice_m3);
  CHECK(std::abs(pieces[1] - (0.5 * kSideM - z_m) * kSideM * kSlabM) <= slice_m3);
  CHECK(pieces[0] + pieces[1] == Approx(kSideM * kSideM * kSlabM).epsilon(1e-9));
}

namespace {

// An ellipsoid with semi-axes (3, 10, 20) mm about the origin: a fin 6 mm thick whose top ridge (y = 10 mm)
// curves with a radius of 0.9 mm across it. Latitude-longitude rings: 48 from pole to pole, 96 around.
mesh::SurfaceMesh fin() {
  const Eigen::Vector3d axes_m(0.003, 0.01, 0.02);
  constexpr int kRings = 48, kAround = 96;
  std::vector<Eigen::Vector3d> points{Eigen::Vector3d(0.0, axes_m.y(), 0.0)};
  for (int i = 1; i < kRings; ++i)
    for (int j = 0; j < kAround; ++j) {
      const double theta = M_PI * i / kRings, phi = 2.0 * M_PI * j / kAround;
      points.emplace_back(axes_m.x() * std::sin(theta) * std::cos(phi), axes_m.y() * std::cos(theta),
                          axes_m.z() * std::sin(theta) * std::sin(phi));
    }
  points.emplace_back(0.0, -axes_m.y(), 0.0);
  const int last = static_cast<int>(points.size()) - 1;
  const auto at = [](int i, int j) { return 1 + (i - 1) * kAround + j % kAround; };
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j < kAround; ++j) faces.push_back({0, at(1, j + 1), at(1, j)});
  for (int i = 1; i + 1 < kRings; ++i)
    for (int j = 0; j < kAround; ++j) {
      faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      faces.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  for (int j = 0; j < kAround; ++j) faces.push_back({last, at(kRings - 1, j), at(kRings - 1, j + 1)});
  mesh::SurfaceMesh out;
  std::vector<mesh::TriMesh::VertexHandle> handles;
  for (const Eigen::Vector3d& p : points) handles.push_back(out.addVertex(p));
  for (const auto& f : faces) out.mesh().add_face(handles[f[0]], handles[f[1]], handles[f[2]]);
  return out;
}

}  // namespace

TEST_CASE("Over a thin fin's ridge every row of the lattice ends inside the tissue, clear of its far side",
          "[surface_cutter][through]") {
  // Guards against rows that lag the surface's normal up the fin's flank (Incision::stationNormal) reaching
  // towards its far side sideways, which the thickness straight below each vertex does not see: a row ended
  // 0.06 mm short of it, and the opened walls left the tissue (247 pairs of faces crossing in this stroke;
  // 15 once every row ends within kFloorOfThickness, 0.8, of the tissue along it).
  mesh::SurfaceMesh tissue = fin();
  const mesh::SurfaceRays rays(tissue.mesh());
  StrokePathOptions path;
  path.start_m = Eigen::Vector3d(0.0028403877053226985, 0.05, 0.005416062454870226);
  path.direction = Eigen::Vector3d(std::cos(3.45124260025839), 0.0, std::sin(3.45124260025839));
  path.length_m = 0.01858534329374016;
  const Stroke stroke = strokeAlongPath(tissue, path);
  CutterOptions options;
  options.incision.depth_m = 0.0035935217282423173;
  SurfaceCutter cutter(tissue, options);
  cutter.begin(stroke.first, stroke.blade_direction);
  cutter.extend(stroke.samples);
  cutter.settle();
  REQUIRE(cutter.stats().figures.back().row_limited_stations > 0);
  // Station s's row (Eq. 2, the middle plane of column s + order - 1): from G_s along -N_s, the blade's
  // depth d_s = beta_s depth_m / beta_m, read from the rows' spacing beta_s.
  const Incision& incision = *cutter.incision();
  const int n = options.incision.normal_controls;
  for (int s = 0; s < incision.stationCount(); ++s) {
    const int column = s + options.incision.order - 1;
    const Eigen::Vector3d g = incision.rest().control(2, column, n / 2);
    const Eigen::Vector3d up = incision.rest().control(2, column, n / 2 - 1) - g;
    const double depth_m = up.norm() * options.incision.depth_m / options.incision.beta_m;
    const double far_m = rays.firstCrossing(g - 1e-5 * up.normalized(), -up.normalized(), depth_m / 0.8);
    INFO("station " << s << " of " << incision.stationCount() << ": the row " << depth_m << " m, the far side " << far_m
                    << " m along it");
    REQUIRE(std::isinf(far_m));
  }
}
