// Tests for cutting/tets/src/tet_cutter.cpp, tet_cutter_separate.cpp and tet_split.cpp: single tets split in
// every case, and the bunny's tets cut along a stroke with the surface cutter's incision: volume,
// conformity, separation, agreement with the drawn surface, determinism, budgets, bad input.
#include "incise/tets/tet_cutter.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include <catch2/catch.hpp>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/surface_query.h"
#include "incise/mesh/vertex_grid.h"
#include "incise/tets/tetrahedralize.h"
#include "stroke_fixture.h"
#include "tet_fixture.h"
#include "tet_split.h"

namespace incise::tets {
namespace {

// follow()'s budget switch and view()'s argument, by name.

// ---------------------------------------------------------------------------------------------------------
// One tet, split by hand-made signs and edge points.

struct Sink final : detail::SteinerSink {
  std::vector<Eigen::Vector3d> points;
  int add(const Eigen::Vector3d& x_m, int) override {
    points.push_back(x_m);
    return 100 + static_cast<int>(points.size()) - 1;
  }
};

const std::array<Eigen::Vector3d, 4> kCorners = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                                 Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1)};

// How tetInput's tet is split: along phi = 0, or conformingly only (a crack-front tet: kept one piece).
enum class Mode { Cut, ConformingOnly };

// phi per node; points at the linear zero crossing on every edge whose ends have opposite signs (ids 10+e),
// or only on `only_edges` for a conforming (not cut) subdivision.
detail::SplitInput tetInput(std::array<double, 4> phi, Mode mode, std::vector<int> only_edges = {}) {
  detail::SplitInput in;
  const bool cut = mode == Mode::Cut;
  in.cut = cut;
  for (int i = 0; i < 4; ++i) in.nodes[i] = {i, kCorners[i], phi[i] < 0 ? -1 : phi[i] > 0 ? 1 : 0};
  for (int e = 0; e < 6; ++e) {
    const int a = detail::kTetEdges[e][0], b = detail::kTetEdges[e][1];
    const bool crossing = phi[a] * phi[b] < 0;
    const bool wanted = cut ? crossing : std::find(only_edges.begin(), only_edges.end(), e) != only_edges.end();
    if (!wanted) continue;
    const double lambda = phi[a] / (phi[a] - phi[b]);
    in.edge_points[e] = {10 + e, (1 - lambda) * kCorners[a] + lambda * kCorners[b], 0};
  }
  return in;
}

struct Split {
  TetMesh mesh;
  std::vector<int> side;
  std::vector<std::uint8_t> cut_faces;
};

Split runSplit(const detail::SplitInput& in) {
  Sink sink;
  detail::SubTet out[detail::kMaxChildren];
  const detail::SplitResult r = detail::splitTet(in, sink, out);
  REQUIRE_FALSE(r.degenerate);
  Split s;
  s.mesh.nodes_m.assign(110, Eigen::Vector3d::Zero());
  for (int i = 0; i < 4; ++i) s.mesh.nodes_m[i] = in.nodes[i].x_m;
  for (int e = 0; e < 6; ++e)
    if (in.edge_points[e].id >= 0) s.mesh.nodes_m[10 + e] = in.edge_points[e].x_m;
  for (size_t k = 0; k < sink.points.size(); ++k) s.mesh.nodes_m[100 + k] = sink.points[k];
  for (int c = 0; c < r.count; ++c) {
    s.mesh.tets.push_back(out[c].nodes);
    s.side.push_back(out[c].side);
    s.cut_faces.push_back(out[c].cut_faces);
  }
  return s;
}

// The faces marked as cut, as sorted node triples, and their total area.
double cutArea(const Split& s, std::set<std::array<int, 3>>* faces = nullptr) {
  double area = 0;
  for (size_t t = 0; t < s.mesh.tets.size(); ++t)
    for (int i = 0; i < 4; ++i) {
      if (!(s.cut_faces[t] >> i & 1u)) continue;
      auto f = faceOpposite(s.mesh.tets[t], i);
      const Eigen::Vector3d& a = s.mesh.nodes_m[f[0]];
      area += 0.5 * (s.mesh.nodes_m[f[1]] - a).cross(s.mesh.nodes_m[f[2]] - a).norm();
      std::sort(f.begin(), f.end());
      if (faces) faces->insert(f);
    }
  return area;
}

void requireValidSplit(const Split& s) {
  REQUIRE(volume(s.mesh) == Approx(1.0 / 6.0).epsilon(1e-12));
  for (size_t t = 0; t < s.mesh.tets.size(); ++t) REQUIRE(tetVolume(s.mesh, static_cast<int>(t)) > 1e-6);
  const TetCheck check = checkConforming(s.mesh);
  REQUIRE(check.conforming);
  REQUIRE(check.boundary_faces >= 4);
}

TEST_CASE("tet_split: a corner cut off through three edges", "[cutting]") {
  const Split s = runSplit(tetInput({-1.0, 1.0, 1.0, 1.0}, Mode::Cut));
  requireValidSplit(s);
  // The - piece is the corner tet (volume (1/2)^3 / 6) and the cut is the triangle through the midpoints.
  double minus = 0;
  for (size_t t = 0; t < s.mesh.tets.size(); ++t)
    if (s.side[t] < 0) minus += tetVolume(s.mesh, static_cast<int>(t));
  CHECK(minus == Approx(1.0 / 48.0).epsilon(1e-12));
  CHECK(cutArea(s) == Approx(2 * std::sqrt(3.0) / 4.0 * 0.5).epsilon(1e-12));  // both sides mark it
}

TEST_CASE("tet_split: a quad cut through four edges", "[cutting]") {
  const Split s = runSplit(tetInput({-1.0, -1.0, 1.0, 1.0}, Mode::Cut));
  requireValidSplit(s);
  std::set<std::array<int, 3>> faces;
  cutArea(s, &faces);
  CHECK(faces.size() == 2);  // the quad as two triangles, marked from both sides
  for (size_t t = 0; t < s.mesh.tets.size(); ++t) CHECK(std::abs(s.side[t]) == 1);
}

TEST_CASE("tet_split: cuts through a node, through two nodes and along a face", "[cutting]") {
  SECTION("a node and two edges") {
    const Split s = runSplit(tetInput({0.0, -1.0, 1.0, 1.0}, Mode::Cut));
    requireValidSplit(s);
    // The triangle node 0 - midpoint(1, 2) - midpoint(1, 3), marked from both sides.
    const double area = 0.5 * Eigen::Vector3d(0.5, 0.5, 0).cross(Eigen::Vector3d(0.5, 0, 0.5)).norm();
    CHECK(cutArea(s) == Approx(2 * area).epsilon(1e-12));
  }
  SECTION("two nodes and an edge") {
    const Split s = runSplit(tetInput({0.0, 0.0, -1.0, 2.0}, Mode::Cut));
    requireValidSplit(s);
    CHECK(s.mesh.tets.size() == 2);
  }
  SECTION("a face on the cut: no split, the face marked") {
    const Split s = runSplit(tetInput({0.0, 0.0, 0.0, 1.0}, Mode::Cut));
    requireValidSplit(s);
    REQUIRE(s.mesh.tets.size() == 1);
    CHECK(s.cut_faces[0] == (1u << 3));
    CHECK(s.side[0] == 1);
  }
}

TEST_CASE("tet_split: a crack-front tet keeps its split edges without separating", "[cutting]") {
  for (const std::vector<int>& edges : {std::vector<int>{0}, std::vector<int>{0, 1}, std::vector<int>{0, 1, 2}}) {
    const Split s = runSplit(tetInput({-1.0, 1.0, 1.0, 1.0}, Mode::ConformingOnly, edges));
    requireValidSplit(s);
    CHECK(cutArea(s) == 0);
    // Every point on an edge is used (the faces it lies on are split there).
    for (const int e : edges) {
      bool used = false;
      for (const auto& t : s.mesh.tets) used = used || std::find(t.begin(), t.end(), 10 + e) != t.end();
      CHECK(used);
    }
  }
}

TEST_CASE("tet_split: two tets sharing a face triangulate it the same way", "[cutting]") {
  // Tets (0,1,2,3) and (1,0,2,4) share face 0-1-2; points on edges 0-1 and 0-2 of that face.
  const Eigen::Vector3d below(0.2, 0.3, -1.0);
  detail::SplitInput a = tetInput({-1.0, 1.0, 1.0, 1.0}, Mode::Cut);
  detail::SplitInput b;
  b.cut = false;
  const std::array<int, 4> ids = {1, 0, 2, 4};
  for (int i = 0; i < 4; ++i) b.nodes[i] = {ids[i], ids[i] == 4 ? below : kCorners[ids[i]], 1};
  b.edge_points[0] = a.edge_points[0];  // edge (1,0) of b is edge (0,1) of a
  b.edge_points[3] = a.edge_points[1];  // edge (0,2) of b is its local (1,2)
  Split sa = runSplit(a), sb = runSplit(b);
  sb.mesh.nodes_m[4] = below;
  TetMesh both = sa.mesh;
  for (const auto& t : sb.mesh.tets) both.tets.push_back(t);
  both.nodes_m[4] = below;
  const TetCheck check = checkConforming(both);
  CHECK(check.conforming);
  CHECK(check.non_manifold_faces == 0);
}

// ---------------------------------------------------------------------------------------------------------
// The bunny's tets cut along a stroke.

using testing::bunnyTissue;
using testing::Tissue;

struct Run {
  mesh::SurfaceMesh surface;
  TetView rest, deformed;
  TetCutStats stats;
  double snap_m = 0;
};

// Cuts the bunny's back along a 3 cm stroke, `group` samples per call, then finishes and settles.
Run cutBunny(int group = 1, int budget = 0,
             std::function<void(const TetCutter&, const incision::SurfaceCutter&)> each = {},
             const Tissue& tissue = bunnyTissue()) {
  Run run{tissue.surface, {}, {}, {}};
  incision::SurfaceCutter cutter(run.surface, incision::CutterOptions{});
  TetCutterOptions options;
  options.max_inversions_per_call = budget;
  TetCutter tets(tissue.tets, options);
  const incision::Stroke stroke = incision::testing::backStroke(tissue.surface, 0.03);
  REQUIRE(stroke.samples.size() > 100);
  cutter.begin(stroke.first, stroke.blade_direction);
  for (size_t i = 0; i < stroke.samples.size(); i += static_cast<size_t>(group)) {
    const size_t end = std::min(stroke.samples.size(), i + static_cast<size_t>(group));
    cutter.extend(std::span(stroke.samples.data() + i, end - i));
    tets.follow(*cutter.incision(), cutter.stats().incisions);
    if (each && i % 100 == 0) each(tets, cutter);
  }
  cutter.finish();
  cutter.advance(1e9);
  while (cutter.pending()) cutter.advance(1e9);
  tets.follow(*cutter.incision(), cutter.stats().incisions, TetBudget::All);
  REQUIRE_FALSE(tets.pending());
  run.rest = tets.view(TetShape::Rest);
  run.deformed = tets.view(TetShape::Deformed);
  run.stats = tets.stats();
  run.snap_m = tets.snapToleranceM();
  return run;
}

const Run& bunnyRun() {
  static const Run run = cutBunny();
  return run;
}

void checkCut(const Run& run, const Tissue& tissue) {
  const double original = volume(tissue.tets);
  CHECK(run.stats.tets_cut > 40);
  CHECK(run.stats.edge_points > 15);
  CHECK(run.stats.duplicated_nodes > 20);
  CHECK(run.stats.failure.empty());
  CHECK(std::abs(volume(run.rest.mesh) - original) <= 1e-9 * original);
  CHECK(run.rest.inverted_tets == 0);
  CHECK(run.deformed.inverted_tets == 0);
  CHECK(run.rest.min_split_volume_m3 > 0);
  CHECK(run.rest.min_split_dihedral_deg > 0.5);
  // The opened wound adds volume: the tissue is pushed aside, not compressed into nothing.
  CHECK(volume(run.deformed.mesh) > 0.99 * original);
}

void checkSeparated(const Run& run, const Tissue& tissue) {
  for (const TetView* v : {&run.rest, &run.deformed}) {
    const TetCheck check = checkConforming(v->mesh);
    INFO(check.first_problem);
    REQUIRE(check.conforming);
    // Two tets on opposite sides share a face only where the cut ends (its front: nodes that stay single).
    int across = 0, at_front = 0;
    for (size_t t = 0; t < v->mesh.tets.size(); ++t)
      for (int i = 0; i < 4; ++i) {
        const int n = v->mesh.neighbours[t][i];
        if (n < 0 || v->side[t] * v->side[static_cast<size_t>(n)] >= 0) continue;
        const auto f = faceOpposite(v->mesh.tets[t], i);
        const bool front =
            std::all_of(f.begin(), f.end(), [&](int x) { return v->node_cut[static_cast<size_t>(x)] == 3; });
        front ? ++at_front : ++across;
      }
    CHECK(across == 0);
    CHECK(at_front < 20);
  }
  // The cut opened new boundary: the wound's walls.
  CHECK(boundaryFaces(run.rest.mesh).size() > boundaryFaces(tissue.tets).size() + 100);
}

void checkBoundary(const Run& run) {
  const auto faces = boundaryFaces(run.deformed.mesh);
  // Closed two-manifold: every boundary edge in exactly two boundary faces, with opposite directions.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : faces)
    for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    INFO("edge " << edge.first << "-" << edge.second);
    REQUIRE(count == 1);
    REQUIRE(directed.count({edge.second, edge.first}) == 1);
  }
  // Same geometry as the surface cutter's mesh: every boundary node lies on that surface, within the snap
  // tolerance (a node snapped onto the cut opens with the lips from where it is) and a quarter of the
  // opening (the two meshes' different chords of the curved walls).
  double worst_m = 0;
  mesh::VertexGrid grid(0.002);
  const mesh::TriMesh& surface = run.surface.mesh();
  for (const auto v : surface.vertices())
    if (!surface.status(v).deleted()) grid.insert(v.idx(), mesh::toEigen(surface.point(v)));
  std::set<int> nodes;
  for (const auto& f : faces) nodes.insert(f.begin(), f.end());
  int open_nodes = 0, worst_node = -1;
  double worst_moved = 0;
  for (const int n : nodes) {
    const Eigen::Vector3d& x = run.deformed.mesh.nodes_m[static_cast<size_t>(n)];
    // Tets the blade's bottom passes through are cut whole: below the blade the cut's rim is a slit inside
    // the tissue, nearly shut (each side moves less than 1/8 of the opening), not part of the drawn surface.
    const double moved_m = (x - run.rest.mesh.nodes_m[static_cast<size_t>(n)]).norm();
    if (run.deformed.node_cut[static_cast<size_t>(n)] != 0 && moved_m < 0.125 * incision::IncisionOptions{}.opening_m)
      continue;
    if (run.deformed.node_cut[static_cast<size_t>(n)] != 0) ++open_nodes;
    const auto closest = mesh::closestSurfacePoint(surface, grid, x, 0.006);
    REQUIRE(closest.has_value());
    if ((closest->point_m - x).norm() > worst_m) {
      worst_m = (closest->point_m - x).norm();
      worst_node = n, worst_moved = moved_m;
    }
  }
  INFO("worst distance " << worst_m << " at node " << worst_node << " (cut " << run.deformed.node_cut[worst_node]
                         << ", at " << run.rest.mesh.nodes_m[worst_node].transpose() << ", moved " << worst_moved
                         << ")");
  CHECK(open_nodes > 20);
  CHECK(worst_m < run.snap_m + 0.25 * incision::IncisionOptions{}.opening_m);
}

TEST_CASE("tet_cutter: the cut splits tets, duplicates nodes and keeps the volume", "[cutting]") {
  checkCut(bunnyRun(), bunnyTissue());
}

TEST_CASE("tet_cutter: the mesh stays conforming and no face is shared across the cut", "[cutting]") {
  checkSeparated(bunnyRun(), bunnyTissue());
}

TEST_CASE("tet_cutter: the tets' boundary is a closed surface matching the cut surface mesh", "[cutting]") {
  checkBoundary(bunnyRun());
}

TEST_CASE("tet_cutter: on a tissue of more than 200k tets every check holds", "[cutting][slow]") {
  const Tissue& fine = bunnyTissue(1.2e-9);
  REQUIRE(fine.tets.tets.size() > 200000);
  const Run run = cutBunny(1, 32, {}, fine);
  checkCut(run, fine);
  checkSeparated(run, fine);
  checkBoundary(run);
}

TEST_CASE("tet_cutter: same samples give the same bytes, however they are grouped and budgeted", "[cutting]") {
  const Run& one = bunnyRun();
  const Run again = cutBunny(1);
  CHECK(again.rest.mesh.nodes_m == one.rest.mesh.nodes_m);
  CHECK(again.rest.mesh.tets == one.rest.mesh.tets);
  CHECK(again.deformed.mesh.nodes_m == one.deformed.mesh.nodes_m);
  const Run all = cutBunny(100000);
  CHECK(all.rest.mesh.nodes_m == one.rest.mesh.nodes_m);
  CHECK(all.rest.mesh.tets == one.rest.mesh.tets);
  CHECK(all.deformed.mesh.nodes_m == one.deformed.mesh.nodes_m);
  const Run budgeted = cutBunny(1, 5);
  CHECK(budgeted.rest.mesh.tets == one.rest.mesh.tets);
  CHECK(budgeted.deformed.mesh.nodes_m == one.deformed.mesh.nodes_m);
}

TEST_CASE("tet_cutter: volume and conformity hold after every step of the stroke", "[cutting]") {
  const double original = volume(bunnyTissue().tets);
  int checks = 0;
  cutBunny(1, 0, [&](const TetCutter& tets, const incision::SurfaceCutter&) {
    const TetView v = tets.view(TetShape::Rest);
    CHECK(std::abs(volume(v.mesh) - original) <= 1e-9 * original);
    CHECK(checkConforming(v.mesh).conforming);
    CHECK(tets.view(TetShape::Deformed).inverted_tets == 0);
    ++checks;
  });
  CHECK(checks > 3);
}

TEST_CASE("tet_cutter: a second incision crossing the first cuts the already cut tets", "[cutting]") {
  const Tissue& tissue = bunnyTissue();
  mesh::SurfaceMesh surface = tissue.surface;
  incision::SurfaceCutter cutter(surface, incision::CutterOptions{});
  TetCutter tets(tissue.tets);
  const auto stroke = [&](const incision::Stroke& s) {
    cutter.settle();  // the tets catch up with the previous incision before begin() replaces it
    if (cutter.incision()) tets.follow(*cutter.incision(), cutter.stats().incisions, TetBudget::All);
    cutter.begin(s.first, s.blade_direction);
    for (const auto& sample : s.samples) {
      cutter.extend(sample);
      tets.follow(*cutter.incision(), cutter.stats().incisions);
    }
    cutter.finish();
    cutter.advance(1e9);
    tets.follow(*cutter.incision(), cutter.stats().incisions, TetBudget::All);
  };
  stroke(incision::testing::backStroke(tissue.surface, 0.03));
  const int first_cut = tets.stats().tets_cut;
  const TetView after_first = tets.view(TetShape::Deformed);
  stroke(incision::testing::backStroke(tissue.surface, 0.025, 0.0, Eigen::Vector3d(0.0, 0.0, 0.005),
                                       Eigen::Vector3d::UnitZ(), 10.0));
  REQUIRE(tets.stats().incisions == 2);
  REQUIRE(tets.stats().failure.empty());
  CHECK(tets.stats().tets_cut > first_cut + 20);
  const TetView rest = tets.view(TetShape::Rest), deformed = tets.view(TetShape::Deformed);
  // The second incision's rest state is the first one's settled result.
  CHECK(std::abs(volume(rest.mesh) - volume(after_first.mesh)) <= 1e-9 * volume(after_first.mesh));
  for (const TetView* v : {&rest, &deformed}) {
    const TetCheck check = checkConforming(v->mesh);
    INFO(check.first_problem);
    CHECK(check.conforming);
    CHECK(v->inverted_tets == 0);
  }
}

TEST_CASE("tet_cutter: a stroke too short for its wound to open cuts no tet (and no skin)", "[cutting]") {
  const Tissue& tissue = bunnyTissue();
  mesh::SurfaceMesh surface = tissue.surface;
  incision::SurfaceCutter cutter(surface, incision::CutterOptions{});
  TetCutter tets(tissue.tets, TetCutterOptions{});
  const incision::Stroke stroke = incision::testing::backStroke(tissue.surface, 0.0015);
  cutter.begin(stroke.first, stroke.blade_direction);
  for (const auto& sample : stroke.samples) {
    cutter.extend(sample);
    tets.follow(*cutter.incision(), cutter.stats().incisions);
  }
  cutter.finish();
  while (cutter.pending()) cutter.advance(1e9);
  tets.follow(*cutter.incision(), cutter.stats().incisions, TetBudget::All);
  REQUIRE(cutter.stats().figures.back().shortfall == incision::Shortfall::TooShort);
  CHECK(tets.stats().tets_cut == 0);
  CHECK(tets.view(TetShape::Rest).mesh.tets.size() == tissue.tets.tets.size());
  CHECK(surface.mesh().n_faces() == tissue.surface.mesh().n_faces());
}

TEST_CASE("tet_cutter: bad tissue and options are refused at load", "[cutting]") {
  TetMesh broken = bunnyTissue().tets;
  std::swap(broken.tets[0][0], broken.tets[0][1]);  // inverted
  CHECK_THROWS_AS(TetCutter(broken), mesh::MeshError);
  CHECK_THROWS_AS(TetCutter(TetMesh{}), mesh::MeshError);
  TetCutterOptions o;
  o.snap_tolerance_m = -1;
  CHECK_THROWS_AS(TetCutter(bunnyTissue().tets, o), std::invalid_argument);
  o = {};
  o.max_inversions_per_call = -2;
  CHECK_THROWS_AS(TetCutter(bunnyTissue().tets, o), std::invalid_argument);
}

TEST_CASE("tet_split: a point on top of a node is reported as degenerate, not written as a valid split", "[cutting]") {
  detail::SplitInput in = tetInput({-1e-300, 1.0, 1.0, 1.0}, Mode::Cut);
  Sink sink;
  detail::SubTet out[detail::kMaxChildren];
  CHECK(detail::splitTet(in, sink, out).degenerate);
}

}  // namespace
}  // namespace incise::tets
