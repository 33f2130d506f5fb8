// Tests for cutting/tets/src/tet_cutter_deform.cpp (TetCutter::redeform, setSide): the tets' deformed nodes
// depend on the incision's samples and its opening alone, never on how the work fell into follow() calls —
// the budget per call, how the samples were grouped between calls, when the incision's opening was brought
// up to date. The incision is driven directly (no surface cutter), so each schedule sets those freely.
#include <algorithm>
#include <cstddef>
#include <vector>

#include <catch2/catch.hpp>

#include "incise/incision/incision.h"
#include "incise/tets/tet_cutter.h"
#include "tet_fixture.h"

namespace incise::tets {
namespace {

using testing::bunnyTissue;

// How a stroke's samples reach the incision and the tets.
struct Schedule {
  int budget = 0;                // the tets' inversions per call (0: none)
  std::vector<int> groups{1};    // samples added between calls, cycled
  int update_every = 1;          // the opening brought up to date after every n-th group (at its last time)
  int follows = 1;               // follow() calls after each group (0: the tets catch up only at the end)
  double settle_step_s = 0.001;  // after the stroke, the opening's updates this far apart
};

// The bunny's tets after a 3 cm stroke over its back under `schedule`, the wound settled and the tets
// caught up: deformed.
TetView cutUnder(const Schedule& schedule) {
  const testing::Tissue& tissue = bunnyTissue();
  const incision::Stroke stroke = incision::testing::backStroke(tissue.surface, 0.03);
  incision::Incision incision(incision::IncisionOptions{}, stroke.first, stroke.blade_direction);
  TetCutterOptions options;
  options.max_inversions_per_call = schedule.budget;
  TetCutter tets(tissue.tets, options);
  std::vector<int> changed;
  double t_s = stroke.first.time_s;
  std::size_t next = 0;
  for (std::size_t group = 0; next < stroke.samples.size(); ++group) {
    const std::size_t size = static_cast<std::size_t>(schedule.groups[group % schedule.groups.size()]);
    for (const std::size_t end = std::min(stroke.samples.size(), next + size); next < end; ++next) {
      incision.extend(stroke.samples[next]);
      t_s = stroke.samples[next].time_s;
    }
    if (group % static_cast<std::size_t>(schedule.update_every) == 0) incision.updateOpening(t_s, changed);
    for (int f = 0; f < schedule.follows; ++f) tets.follow(incision, 1);
  }
  incision.finish();
  const double end_s = t_s;
  while (t_s < end_s + 0.2) {  // the wound settles (retraction_time_s = 0.05) while the tets catch up
    t_s += schedule.settle_step_s;
    incision.updateOpening(t_s, changed);
    tets.follow(incision, 1);
  }
  for (int calls = 0; tets.pending() && calls < 1000000; ++calls) tets.follow(incision, 1);
  REQUIRE_FALSE(tets.pending());
  REQUIRE(tets.stats().failure.empty());
  REQUIRE(tets.stats().tets_cut > 40);
  return tets.view(TetShape::Deformed);
}

void requireSameBits(const TetView& a, const TetView& b) {
  REQUIRE(a.mesh.tets == b.mesh.tets);
  REQUIRE(a.side == b.side);
  REQUIRE(a.mesh.nodes_m.size() == b.mesh.nodes_m.size());
  int differ = 0;
  for (std::size_t n = 0; n < a.mesh.nodes_m.size(); ++n) differ += a.mesh.nodes_m[n] != b.mesh.nodes_m[n] ? 1 : 0;
  INFO(differ << " of " << a.mesh.nodes_m.size() << " deformed nodes differ");
  REQUIRE(differ == 0);
}

}  // namespace

TEST_CASE("tet_cutter: the settled tets are the same bits whatever the budget and however the work falls into calls",
          "[cutting]") {
  const TetView reference = cutUnder(Schedule{});
  CHECK(reference.inverted_tets == 0);
  SECTION("one inversion per call") { requireSameBits(cutUnder(Schedule{1}), reference); }
  SECTION("samples in uneven groups, the opening updated every other group and settling in 7 ms steps") {
    requireSameBits(cutUnder(Schedule{0, {5, 1, 12, 3}, 2, 1, 0.007}), reference);
  }
  SECTION("three inversions per call, two calls per group, the opening updated every third group") {
    requireSameBits(cutUnder(Schedule{3, {2, 9, 1}, 3, 2, 0.013}), reference);
  }
  SECTION("the tets follow only once the stroke has ended, one inversion per call") {
    requireSameBits(cutUnder(Schedule{1, {40}, 1, 0, 0.003}), reference);
  }
}

TEST_CASE("tet_cutter: tets that have caught up are the same bits as an unbudgeted cutter's, at every step",
          "[cutting]") {
  // Two cutters follow one incision: one does all that is final in each call, the other two inversions a
  // call, called again until it has caught up. Whenever it has (compared after every step it was behind,
  // and every 50 samples), the meshes agree bit for bit, while the stroke goes on and once it has settled.
  const testing::Tissue& tissue = bunnyTissue();
  const incision::Stroke stroke = incision::testing::backStroke(tissue.surface, 0.03);
  incision::Incision incision(incision::IncisionOptions{}, stroke.first, stroke.blade_direction);
  TetCutter all(tissue.tets);
  TetCutterOptions options;
  options.max_inversions_per_call = 2;
  TetCutter budgeted(tissue.tets, options);
  std::vector<int> changed;
  int compared = 0, behind = 0;
  const auto step = [&](double t_s, bool compare) {
    incision.updateOpening(t_s, changed);
    all.follow(incision, 1, TetBudget::All);
    budgeted.follow(incision, 1);
    const bool was_behind = budgeted.pending();
    behind += was_behind ? 1 : 0;
    while (budgeted.pending()) budgeted.follow(incision, 1);
    if (!compare && !was_behind) return;
    requireSameBits(budgeted.view(TetShape::Deformed), all.view(TetShape::Deformed));
    ++compared;
  };
  for (std::size_t i = 0; i < stroke.samples.size(); ++i) {
    incision.extend(stroke.samples[i]);
    step(stroke.samples[i].time_s, i % 50 == 49);
  }
  incision.finish();
  const double end_s = stroke.samples.back().time_s;
  for (int ms = 1; ms <= 200; ++ms) step(end_s + 0.001 * ms, ms % 20 == 0);
  CHECK(behind >= 10);  // the budgeted cutter really was behind, at the columns with the most nodes
  CHECK(compared >= behind + 10);
  REQUIRE(all.stats().tets_cut > 40);
}

TEST_CASE("tet_cutter: settled cuts along varied strokes leave no tet inverted, snapped nodes moving by their own u",
          "[cutting]") {
  // Nodes snapped onto the cut (up to 0.2 median edges from it) move as the tissue at their own u on the side
  // they lie on; moved as the lip instead, a snapped node drags its uncut neighbours flat (the 20 mm stroke
  // bent by 5 mm leaves one tet inverted so).
  const testing::Tissue& tissue = bunnyTissue();
  int strokes = 0;
  for (const double length_m : {0.02, 0.03, 0.04})
    for (const double bend_m : {0.0, 0.005})
      for (const double offset_m : {-0.004, 0.0, 0.004}) {
        const incision::Stroke stroke = incision::testing::backStroke(tissue.surface, length_m, bend_m,
                                                                      Eigen::Vector3d(-0.012, 0.0, 0.015 + offset_m));
        incision::Incision incision(incision::IncisionOptions{}, stroke.first, stroke.blade_direction);
        TetCutter tets(tissue.tets);
        std::vector<int> changed;
        for (const incision::StrokeSample& sample : stroke.samples) {
          incision.extend(sample);
          incision.updateOpening(sample.time_s, changed);
          tets.follow(incision, 1);
        }
        incision.finish();
        incision.updateOpening(stroke.samples.back().time_s + 1.0, changed);  // settled
        tets.follow(incision, 1, TetBudget::All);
        INFO("stroke " << length_m << " m, bent " << bend_m << " m, offset " << offset_m << " m");
        REQUIRE(tets.stats().failure.empty());
        REQUIRE(tets.stats().tets_cut > 30);
        const TetView deformed = tets.view(TetShape::Deformed);
        CHECK(checkConforming(deformed.mesh).conforming);
        CHECK(deformed.inverted_tets == 0);
        ++strokes;
      }
  CHECK(strokes == 18);
}

}  // namespace incise::tets
