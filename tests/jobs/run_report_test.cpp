#include "incise/jobs/run_report.h"

#include <catch2/catch.hpp>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"

TEST_CASE("run_report: a replay's report has the mesh's hash and summary and the cut's figures", "[jobs]") {
  using namespace incise;
  jobs::ScenarioRun run = jobs::loadScenarioRun(INCISE_SCENARIOS_DIR "/pad-straight.json");
  const sim::ReplayOptions options = jobs::scenarioReplayOptions(run.scenario, sim::ReplayPace::Fast);
  CHECK(options.period_us == 1000);
  CHECK(options.settle_s == run.scenario.settle_s);
  const sim::ReplayReport report = sim::replay(*run.world, run.poses, options);
  const nlohmann::json json = jobs::replayReport(run, options, report);
  CHECK(json["geometry_hash"] == jobs::hexText(mesh::geometryHash(run.world->tissue())));
  CHECK(json["mode"] == "fast");
  CHECK(json["frames"] == report.frames);
  CHECK(json["mesh"]["closed_two_manifold"] == true);
  CHECK(json["cut_failure"] == "");
  CHECK(json["note"] == "");
  REQUIRE(json["incision_figures"].size() == 1);
  CHECK(json["incision_figures"][0]["shortfall"] == "none");
  CHECK_FALSE(json.contains("tets"));
}

TEST_CASE("run_report: a replay that never cut the tissue says so, and it is no failure", "[jobs]") {
  incise::sim::ReplayReport report;
  report.poses = 12;
  report.incisions = 0;
  CHECK_THAT(incise::jobs::noIncision(report), Catch::StartsWith("no incision: none of the 12 poses cut the tissue"));
  CHECK(incise::jobs::cutFailure({}).empty());
  report.incisions = 1;
  CHECK(incise::jobs::noIncision(report).empty());
}

TEST_CASE("run_report: the timing summary takes nearest ranks", "[jobs]") {
  const nlohmann::json t = incise::jobs::timingSummary({4.0, 1.0, 3.0, 2.0});
  CHECK(t["count"] == 4);
  CHECK(t["p50_us"] == 2.0);
  CHECK(t["p99_us"] == 4.0);
  CHECK(t["max_us"] == 4.0);
  CHECK(t["mean_us"] == 2.5);
  CHECK(incise::jobs::timingSummary({}) == nlohmann::json{{"count", 0}});
}
