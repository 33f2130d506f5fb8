// Tests for cutting/tets/src/tet_cutter_rebase.cpp: a second incision starts from the first one's settled mesh
// by redoing only what the first changed. The result is checked against a new TetCutter built from that
// settled mesh (numbered as the rebase numbers it), whatever budget the rebase runs under.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "incise/incision/surface_cutter.h"
#include "incise/tets/tet_cutter.h"
#include "tet_fixture.h"

namespace incise::tets {
namespace {

using testing::bunnyTissue;

// The cutter's settled mesh, numbered as its rebase numbers it: every base tet's first child at the base
// tet's place, then the other children in base-tet order; the nodes any child uses, in index order, at
// their deformed positions. Built from the public raw view, not from the rebase's code.
TetMesh settledInRebaseOrder(const TetCutter& tets) {
  std::vector<std::array<int, 4>> order;
  for (int t = 0; t < tets.baseTetCount(); ++t)
    if (!tets.children(t).empty()) order.push_back(tets.children(t)[0].nodes);
  for (int t = 0; t < tets.baseTetCount(); ++t)
    for (size_t c = 1; c < tets.children(t).size(); ++c) order.push_back(tets.children(t)[c].nodes);
  std::vector<int> remap(static_cast<size_t>(tets.nodeCount()), -1);
  for (const auto& tet : order)
    for (const int n : tet) remap[static_cast<size_t>(n)] = 0;
  TetMesh mesh;
  for (int n = 0; n < tets.nodeCount(); ++n) {
    if (remap[static_cast<size_t>(n)] < 0) continue;
    remap[static_cast<size_t>(n)] = static_cast<int>(mesh.nodes_m.size());
    mesh.nodes_m.push_back(tets.nodePosition(n));
  }
  for (const auto& tet : order)
    mesh.tets.push_back({remap[static_cast<size_t>(tet[0])], remap[static_cast<size_t>(tet[1])],
                         remap[static_cast<size_t>(tet[2])], remap[static_cast<size_t>(tet[3])]});
  return mesh;
}

// The bunny's surface cut by two strokes (the second across the first), its tets following.
struct TwoStrokes {
  mesh::SurfaceMesh surface = bunnyTissue().surface;
  incision::SurfaceCutter cutter{surface, incision::CutterOptions{}};
  incision::Stroke first = incision::testing::backStroke(bunnyTissue().surface, 0.03);
  incision::Stroke second = incision::testing::backStroke(
      bunnyTissue().surface, 0.025, 0.0, Eigen::Vector3d(0.0, 0.0, 0.005), Eigen::Vector3d::UnitZ(), 10.0);

  // The first stroke, cut and settled, `tets` caught up with it (budgeted calls per sample, then all).
  void cutFirst(TetCutter& tets) {
    cutter.begin(first.first, first.blade_direction);
    for (const incision::StrokeSample& s : first.samples) {
      cutter.extend(s);
      tets.follow(*cutter.incision(), cutter.stats().incisions);
    }
    cutter.finish();
    cutter.settle();
    tets.follow(*cutter.incision(), cutter.stats().incisions, TetBudget::All);
  }
  void beginSecond() { cutter.begin(second.first, second.blade_direction); }
  // The second stroke's samples with every cutter in `all` following each in turn, then the end.
  void cutSecond(std::initializer_list<TetCutter*> all) {
    for (const incision::StrokeSample& s : second.samples) {
      cutter.extend(s);
      for (TetCutter* t : all) t->follow(*cutter.incision(), cutter.stats().incisions);
    }
    cutter.finish();
    cutter.settle();
    for (TetCutter* t : all) t->follow(*cutter.incision(), cutter.stats().incisions, TetBudget::All);
  }
};

void requireSameView(const TetView& a, const TetView& b) {
  REQUIRE(a.mesh.nodes_m.size() == b.mesh.nodes_m.size());
  REQUIRE(a.mesh.tets == b.mesh.tets);
  CHECK(a.mesh.nodes_m == b.mesh.nodes_m);  // bit for bit
  CHECK(a.side == b.side);
  CHECK(a.split == b.split);
  CHECK(a.node_cut == b.node_cut);
}

TEST_CASE("tet_cutter rebase: a second incision cuts as a new cutter on the settled mesh would", "[cutting]") {
  TwoStrokes run;
  TetCutterOptions options;
  options.max_inversions_per_call = 32;
  TetCutter kept(bunnyTissue().tets, options);
  run.cutFirst(kept);
  REQUIRE(kept.stats().tets_cut > 20);
  options.snap_tolerance_m = kept.snapToleranceM();
  TetCutter fresh(settledInRebaseOrder(kept), options);
  // The tets' lag behind the lattice comes from the median edge: measured at load by `kept`, on the settled
  // mesh by `fresh`; the comparison needs the same lag.
  const double spacing_m = incision::CutterOptions{}.incision.spacing_m;
  REQUIRE(std::ceil(2.0 * kept.medianEdgeM() / spacing_m) == std::ceil(2.0 * fresh.medianEdgeM() / spacing_m));

  run.beginSecond();
  kept.follow(*run.cutter.incision(), run.cutter.stats().incisions, TetBudget::All);  // the rebase
  fresh.follow(*run.cutter.incision(), run.cutter.stats().incisions, TetBudget::All);
  REQUIRE(kept.checkIndexes().empty());
  CHECK(kept.stats().rebased_tets > 100);
  CHECK(kept.stats().rebased_tets < kept.baseTetCount() / 10);  // what the first incision changed, no more
  run.cutSecond({&kept, &fresh});
  REQUIRE(kept.stats().failure.empty());
  REQUIRE(fresh.stats().failure.empty());
  CHECK(fresh.stats().tets_cut > 20);  // the second stroke cut tets
  requireSameView(kept.view(TetShape::Deformed), fresh.view(TetShape::Deformed));
  CHECK(kept.checkIndexes().empty());
  requireSameView(kept.view(TetShape::Rest), fresh.view(TetShape::Rest));
  CHECK(kept.stats().reserve_overflows == 0);
}

TEST_CASE("tet_cutter rebase: spread over many calls, it gives the same mesh as at once", "[cutting]") {
  TwoStrokes run;
  TetCutterOptions options;
  options.max_inversions_per_call = 1;
  TetCutter spread(bunnyTissue().tets, options), at_once(bunnyTissue().tets, options);
  // The first stroke the same way for both (every call unlimited): only the rebase's calls differ.
  run.cutter.begin(run.first.first, run.first.blade_direction);
  for (const incision::StrokeSample& s : run.first.samples) {
    run.cutter.extend(s);
    for (TetCutter* t : {&spread, &at_once}) t->follow(*run.cutter.incision(), 1, TetBudget::All);
  }
  run.cutter.finish();
  run.cutter.settle();
  for (TetCutter* t : {&spread, &at_once}) t->follow(*run.cutter.incision(), 1, TetBudget::All);

  run.beginSecond();
  REQUIRE(run.cutter.incision()->finalColumns() < run.cutter.incision()->options().order);  // no column yet
  int calls = 0;
  do {
    spread.follow(*run.cutter.incision(), 2);
    ++calls;
  } while (spread.pending() && calls < 100000);
  at_once.follow(*run.cutter.incision(), 2, TetBudget::All);
  INFO(calls << " calls for " << spread.stats().rebased_tets << " rebased tets");
  CHECK(calls > spread.stats().rebased_tets / 2);  // one unit per call: two tets each, then edges, nodes
  CHECK_FALSE(at_once.pending());
  CHECK(spread.checkIndexes().empty());
  for (const incision::StrokeSample& s : run.second.samples) {
    run.cutter.extend(s);
    for (TetCutter* t : {&spread, &at_once}) t->follow(*run.cutter.incision(), 2, TetBudget::All);
  }
  REQUIRE(spread.stats().tets_cut > at_once.stats().tets_cut / 2);
  requireSameView(spread.view(TetShape::Deformed), at_once.view(TetShape::Deformed));
}

}  // namespace
}  // namespace incise::tets
