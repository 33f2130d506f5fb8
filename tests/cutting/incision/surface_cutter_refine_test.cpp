// The surface cutter's local refinement ahead of the cut (surface_cutter_refine.cpp): a tissue
// coarse next to the lattice (a 10 cm icosphere of 4-7 mm edges, a CAD-like box of 12 triangles, a pad on a
// 4 mm grid) is cut without subdividing all of it. After the cut: a groove as long as the stroke, a closed
// two-manifold with its Euler characteristic, no zero-area face, no vertex moved outside the lattice's hull,
// the faces far from the stroke equal to the input's (the same vertices, bit for bit), flat faces still flat
// (linear midpoints), curved ones rounder (PN triangles), and the same bytes whatever the budget or the
// grouping of samples into calls.
#include "incise/incision/surface_cutter.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <vector>

#include "incise/incision/stroke_path.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/shapes.h"

using namespace incise;
using namespace incise::incision;

namespace {

StrokePathOptions alongX(const Eigen::Vector3d& start_m, double length_m) {
  StrokePathOptions path;
  path.start_m = start_m;
  path.length_m = length_m;
  return path;
}

CutterOptions withRefine(CutterOptions::Refine refine, int budget = 0) {
  CutterOptions options;
  options.refine = refine;
  options.max_inversions_per_call = budget;
  return options;
}

struct CutResult {
  CutStats stats;
  Eigen::AlignedBox3d hull;  // the union of every lattice column's control-point hull
  std::vector<bool> bound;   // per vertex of the result: parameterised by the incision
};

// Cuts the stroke sample by sample (as the simulation does), finishes it and lets it open fully.
CutResult cut(mesh::SurfaceMesh& mesh, const StrokePathOptions& path, const CutterOptions& options) {
  const Stroke stroke = strokeAlongPath(mesh, path);
  SurfaceCutter cutter(mesh, options);
  cutter.begin(stroke.first, stroke.blade_direction);
  for (const StrokeSample& s : stroke.samples) cutter.extend(s);
  cutter.finish();
  while (cutter.pending()) cutter.advance(stroke.samples.back().time_s);
  cutter.advance(stroke.samples.back().time_s + 1.0);
  CutResult r{cutter.stats(), {}, {}};
  for (int j = 0; j < cutter.incision()->finalColumns(); ++j) r.hull.extend(cutter.incision()->columnBox(j));
  for (const auto v : mesh.mesh().vertices()) r.bound.push_back(cutter.binding(v).has_value());
  return r;
}

// The checks every refined cut must pass against its input.
// far_faces: the input has faces away from the stroke (not a box whose every face spans the cut).
void checkRefinedCut(const mesh::SurfaceMesh& input, const mesh::SurfaceMesh& mesh, const CutResult& r,
                     bool far_faces_expected = true) {
  const mesh::ManifoldReport before = mesh::checkManifold(input.mesh()), after = mesh::checkManifold(mesh.mesh());
  INFO(after.first_problem);
  REQUIRE(r.stats.failure.empty());
  REQUIRE(after.closed_two_manifold);
  REQUIRE(after.euler_characteristic == before.euler_characteristic);
  REQUIRE(after.degenerate_faces == 0);
  const IncisionFigures& f = r.stats.figures.back();
  INFO("groove " << f.groove_length_m << " m along " << f.stroke_length_m << " m: " << describeShortfall(f));
  REQUIRE(f.shortfall == Shortfall::None);
  REQUIRE(f.refined_vertices > 0);
  REQUIRE(f.refined_faces == 2 * f.refined_vertices);  // a closed mesh: two faces more per edge bisected
  REQUIRE(r.stats.refined_vertices == f.refined_vertices);
  REQUIRE(r.stats.refine_refused == 0);
  REQUIRE(r.stats.refine_limited == 0);
  // A groove as long as the stroke, within the lattice's padding at its two ends (order spacings each).
  const CutterOptions defaults;
  REQUIRE(f.groove_length_m >= f.stroke_length_m - defaults.incision.order * defaults.incision.spacing_m);
  REQUIRE(f.groove_length_m <= f.stroke_length_m + defaults.incision.spacing_m);

  const mesh::TriMesh& in = input.mesh();
  const mesh::TriMesh& out = mesh.mesh();
  // No vertex moved outside the lattice's hull: every input vertex that moved was, and stays, inside it.
  Eigen::AlignedBox3d hull = r.hull;
  hull.min().array() -= 1e-9;
  hull.max().array() += 1e-9;
  for (const auto v : in.vertices()) {
    if (out.point(v) == in.point(v)) continue;
    REQUIRE(hull.contains(mesh::toEigen(in.point(v))));
    REQUIRE(hull.contains(mesh::toEigen(out.point(v))));
  }
  // ... and so did every vertex that refinement added and the cut then moved (the others stay where made).
  for (const auto v : out.vertices()) {
    if (static_cast<size_t>(v.idx()) < in.n_vertices() || !r.bound[static_cast<size_t>(v.idx())]) continue;
    REQUIRE(hull.contains(mesh::toEigen(out.point(v))));
  }
  // The faces far from the stroke (beyond two of the input's longest edges from the hull) are the input's:
  // the same vertices, in order, at the same positions.
  const double margin_m = 2.0 * mesh::edgeLengths(in).longest_m;
  Eigen::AlignedBox3d near = r.hull;
  near.min().array() -= margin_m;
  near.max().array() += margin_m;
  int far_faces = 0;
  for (const auto f_in : in.faces()) {
    Eigen::AlignedBox3d bounds;
    for (auto v = in.cfv_iter(f_in); v.is_valid(); ++v) bounds.extend(mesh::toEigen(in.point(*v)));
    if (bounds.intersects(near)) continue;
    ++far_faces;
    auto a = in.cfv_iter(f_in);
    auto b = out.cfv_iter(f_in);
    for (int k = 0; k < 3; ++k, ++a, ++b) {
      REQUIRE(*a == *b);
      REQUIRE(out.point(*b) == in.point(*a));
    }
  }
  REQUIRE((far_faces > 0 || !far_faces_expected));
}

// Mean distance of the refinement's new vertices that the cut did not move from a sphere of radius r
// around the origin.
double meanOffSphere_m(const mesh::SurfaceMesh& input, const mesh::SurfaceMesh& mesh, const CutResult& r,
                       double radius_m) {
  double sum_m = 0.0;
  int count = 0;
  for (const auto v : mesh.mesh().vertices()) {
    if (static_cast<size_t>(v.idx()) < input.mesh().n_vertices() || r.bound[static_cast<size_t>(v.idx())]) continue;
    if (mesh.kind(v) != mesh::VertexKind::Original) continue;
    sum_m += std::abs(mesh::toEigen(mesh.mesh().point(v)).norm() - radius_m);
    ++count;
  }
  REQUIRE(count > 0);
  return sum_m / count;
}

}  // namespace

TEST_CASE("surface_cutter refine: a coarse 10 cm icosphere (4-7 mm edges) is cut along a 3.5 cm stroke", "[cutting]") {
  // The user's case (a closed hand model of 1,197 vertices at 10 cm, one edge split and exit 0 before).
  const mesh::SurfaceMesh input = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.05, 3);
  REQUIRE(mesh::edgeLengths(input.mesh()).mean_m > 0.004);
  mesh::SurfaceMesh mesh = input;
  const CutResult r = cut(mesh, alongX({-0.0175, 0.1, 0.0011}, 0.035), withRefine(CutterOptions::Refine::Linear));
  checkRefinedCut(input, mesh, r);
  // Refinement stays along the stroke: a few hundred vertices, not a whole-mesh subdivision's 16x.
  INFO(r.stats.refined_vertices << " vertices added to " << input.mesh().n_vertices());
  REQUIRE(r.stats.refined_vertices < 2 * static_cast<int>(input.mesh().n_vertices()));
}

TEST_CASE("surface_cutter refine: a CAD-like box of 12 triangles is cut, and its flat faces stay flat", "[cutting]") {
  // Linear midpoints, and PN triangles too: the box's edges and corners are creases, halved straight.
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.05, -0.02, -0.05), Eigen::Vector3d(0.05, 0, 0.05));
  for (const auto refine : {CutterOptions::Refine::Linear, CutterOptions::Refine::PnTriangles})
    for (const Eigen::Vector3i& divisions : {Eigen::Vector3i(1, 1, 1), Eigen::Vector3i(1, 1, 40)}) {
      INFO("divisions " << divisions.transpose() << ", refine " << toString(refine));
      const mesh::SurfaceMesh input = mesh::makeBox(box, divisions);
      mesh::SurfaceMesh mesh = input;
      const CutResult r = cut(mesh, alongX({-0.02, 0.05, 0.003}, 0.04), withRefine(refine));
      checkRefinedCut(input, mesh, r, false);
      // Every vertex the cut did not move lies on one of the box's planes, exactly.
      for (const auto v : mesh.mesh().vertices()) {
        if (r.bound[static_cast<size_t>(v.idx())]) continue;
        const Eigen::Vector3d p = mesh::toEigen(mesh.mesh().point(v));
        bool on_plane = false;
        for (int a = 0; a < 3; ++a) on_plane |= p[a] == box.min()[a] || p[a] == box.max()[a];
        REQUIRE(on_plane);
      }
    }
}

TEST_CASE("surface_cutter refine: a pad on a 4 mm grid is cut along a grid line, beside it and diagonally",
          "[cutting]") {
  const mesh::SurfaceMesh input = mesh::makeSkinPad(Eigen::Vector3d(0.1, 0.02, 0.1), 0.004);
  for (const auto& [start, direction] : std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>{
           {{-0.02, 0.05, 0.0}, Eigen::Vector3d::UnitX()},
           {{-0.02, 0.05, 0.0013}, Eigen::Vector3d::UnitX()},
           {{-0.02, 0.05, -0.02}, Eigen::Vector3d(1, 0, 1).normalized()}}) {
    INFO("start " << start.transpose() << ", direction " << direction.transpose());
    mesh::SurfaceMesh mesh = input;
    StrokePathOptions path = alongX(start, 0.03);
    path.direction = direction;
    checkRefinedCut(input, mesh, cut(mesh, path, withRefine(CutterOptions::Refine::Linear)));
  }
}

TEST_CASE("surface_cutter refine: PN-triangle midpoints put a coarse sphere's new vertices nearer the sphere",
          "[cutting]") {
  const double radius_m = 0.05;
  const mesh::SurfaceMesh input = mesh::makeSphere(Eigen::Vector3d::Zero(), radius_m, 3);
  mesh::SurfaceMesh linear = input, pn = input;
  const StrokePathOptions path = alongX({-0.0175, 0.1, 0.0011}, 0.035);
  const CutResult rl = cut(linear, path, withRefine(CutterOptions::Refine::Linear));
  const CutResult rp = cut(pn, path, withRefine(CutterOptions::Refine::PnTriangles));
  checkRefinedCut(input, pn, rp);
  const double linear_m = meanOffSphere_m(input, linear, rl, radius_m);
  const double pn_m = meanOffSphere_m(input, pn, rp, radius_m);
  INFO("mean distance from the sphere: linear " << linear_m << " m, PN " << pn_m << " m");
  REQUIRE(pn_m < 0.5 * linear_m);
}

TEST_CASE("surface_cutter refine: the same bytes whatever the budget and the grouping of samples", "[cutting]") {
  const mesh::SurfaceMesh input = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.05, 3);
  const StrokePathOptions path = alongX({-0.0175, 0.1, 0.0011}, 0.035);
  mesh::SurfaceMesh unlimited = input;
  cut(unlimited, path, withRefine(CutterOptions::Refine::Linear));
  for (const int budget : {1, 7, 64}) {
    INFO("budget " << budget);
    mesh::SurfaceMesh mesh = input;
    cut(mesh, path, withRefine(CutterOptions::Refine::Linear, budget));
    REQUIRE(mesh::geometryHash(mesh) == mesh::geometryHash(unlimited));
  }
  // All samples in one call.
  mesh::SurfaceMesh once = input;
  const Stroke stroke = strokeAlongPath(once, path);
  SurfaceCutter cutter(once, withRefine(CutterOptions::Refine::Linear));
  cutter.begin(stroke.first, stroke.blade_direction);
  cutter.extend(stroke.samples);
  cutter.finish();
  cutter.advance(stroke.samples.back().time_s + 1.0);
  REQUIRE(mesh::geometryHash(once) == mesh::geometryHash(unlimited));
}

TEST_CASE("surface_cutter refine: off, the coarse sphere is cut as it is and the figures say why", "[cutting]") {
  mesh::SurfaceMesh mesh = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.05, 3);
  const CutResult r = cut(mesh, alongX({-0.0175, 0.1, 0.0011}, 0.035), withRefine(CutterOptions::Refine::Off));
  REQUIRE(r.stats.refined_vertices == 0);
  REQUIRE(r.stats.figures.back().shortfall == Shortfall::CoarseMesh);
}

TEST_CASE("surface_cutter refine: bad options are refused at construction", "[cutting]") {
  mesh::SurfaceMesh mesh = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.05, 2);
  CutterOptions options;
  options.refine_edge_m = -0.001;
  REQUIRE_THROWS_AS(SurfaceCutter(mesh, options), std::invalid_argument);
  options.refine_edge_m = 0.0;
  options.max_refine_splits_per_column = -1;
  REQUIRE_THROWS_AS(SurfaceCutter(mesh, options), std::invalid_argument);
  REQUIRE(refineEdgeLength(CutterOptions{}) == Approx(0.0015));
}
