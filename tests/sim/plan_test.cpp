// sim/src/plan.cpp and the scenario's "plan" and "tissue.shape" keys (scenario.cpp): projection onto the
// tissue, and the bad plans refused with the file and the point.
#include "incise/sim/plan.h"

#include <catch2/catch.hpp>

#include "incise/mesh/surface_mesh.h"
#include "scenario_fixture.h"

namespace {

using Catch::Matchers::Contains;
using incise::sim::ScenarioError;

std::string padScenario(const std::string& plan) {
  return R"({"tissue": {"shape": "pad", "size_m": [0.1, 0.02, 0.1], "grid_m": 0.002},
             "pose_source": {"kind": "strokes", "strokes": [{"start_m": [0, 0.01, 0]}]},
             "plan": )" +
         plan + "}";
}

std::string refusal(const std::string& name, const std::string& plan) {
  try {
    const auto file = incise::test::scenarioDir().scenario(name, padScenario(plan));
    const incise::sim::Scenario s = incise::sim::loadScenario(file);
    incise::sim::projectPlan(s.plan, incise::sim::loadTissue(s), s.world.cutter.incision.spacing_m, s.file);
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("plan: projected onto the pad's top, stations at most a lattice spacing apart", "[score]") {
  const auto file = incise::test::scenarioDir().scenario(
      "plan-ok", padScenario(R"({"points_m": [[-0.02, 0.003, 0.001], [0.02, -0.002, 0.001]], "depth_m": 0.003})"));
  const incise::sim::Scenario s = incise::sim::loadScenario(file);
  CHECK(s.shape.given);
  CHECK(s.plan.lateral_tolerance_m == 0.002);  // the defaults
  CHECK(s.plan.depth_tolerance_m == 0.001);
  const incise::sim::Plan plan = incise::sim::projectPlan(s.plan, incise::sim::loadTissue(s), 0.0005, s.file);
  CHECK(plan.length_m == Approx(0.04));
  CHECK(plan.depth_m == 0.003);
  for (const auto& station : plan.stations) CHECK(station.point_m.y() == Approx(0.0).margin(1e-12));
  for (std::size_t i = 1; i < plan.stations.size(); ++i)
    CHECK(plan.stations[i].s_m - plan.stations[i - 1].s_m <= 0.0005 + 1e-12);
  const incise::sim::PlanLocation at = incise::sim::locate(plan, Eigen::Vector3d(0.0, -0.003, 0.002));
  CHECK(at.s_m == Approx(0.02));
  CHECK(std::abs(at.lateral_m) == Approx(0.001));
  CHECK(at.height_m == Approx(-0.003));
  CHECK(at.beyond_m == 0.0);
  CHECK(incise::sim::locate(plan, Eigen::Vector3d(0.023, 0.0, 0.001)).beyond_m == Approx(0.003));
}

TEST_CASE("plan: bad plans are refused naming the file and the point", "[score]") {
  CHECK_THAT(refusal("plan-off", R"({"points_m": [[0, 0, 0], [0.01, 0, 0], [0.3, 0, 0]]})"),
             Contains("plan-off.json") && Contains("plan.points_m[2]") && Contains("does not project onto the tissue"));
  CHECK_THAT(refusal("plan-short", R"({"points_m": [[0, 0, 0], [0.0002, 0, 0]]})"),
             Contains("plan-short.json") && Contains("shorter than one lattice spacing"));
  CHECK_THAT(refusal("plan-tol", R"({"points_m": [[0, 0, 0], [0.01, 0, 0]], "lateral_tolerance_m": 0})"),
             Contains("plan-tol.json") && Contains("plan.lateral_tolerance_m") && Contains("must be > 0"));
  CHECK_THAT(refusal("plan-dtol", R"({"points_m": [[0, 0, 0], [0.01, 0, 0]], "depth_tolerance_m": -0.001})"),
             Contains("plan.depth_tolerance_m") && Contains("must be > 0"));
  CHECK_THAT(refusal("plan-one", R"({"points_m": [[0, 0, 0]]})"), Contains("plan.points_m") && Contains("at least 2"));
  CHECK_THAT(refusal("plan-nan", R"({"points_m": [[0, 0, 0], [0, "x", 0]]})"), Contains("plan.points_m[1]"));
}

TEST_CASE("plan: a pad tissue is made, not read, a mesh and a shape together are refused", "[score]") {
  const auto pad = incise::test::scenarioDir().scenario(
      "pad-only", R"({"tissue": {"shape": "pad"}, "pose_source": {"kind": "strokes", "strokes": [{}]}})");
  const incise::sim::Scenario s = incise::sim::loadScenario(pad);
  CHECK(incise::sim::loadTissue(s).mesh().n_faces() == 44000);  // the default pad: 10 x 10 x 2 cm, 1 mm grid
  CHECK_FALSE(s.plan.given);
  const auto both = incise::test::scenarioDir().scenario(
      "pad-both",
      R"({"tissue": {"shape": "pad", "mesh": "meshes/bunny.obj"}, "pose_source": {"kind": "strokes", "strokes": [{}]}})");
  CHECK_THROWS_WITH(incise::sim::loadScenario(both), Contains("pad-both.json") && Contains("either mesh or shape"));
  const auto other = incise::test::scenarioDir().scenario(
      "pad-other", R"({"tissue": {"shape": "cube"}, "pose_source": {"kind": "strokes", "strokes": [{}]}})");
  CHECK_THROWS_WITH(incise::sim::loadScenario(other), Contains("tissue.shape") && Contains("pad"));
}
