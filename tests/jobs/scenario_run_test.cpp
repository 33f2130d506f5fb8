#include "incise/jobs/scenario_run.h"

#include <catch2/catch.hpp>

#include "incise/mesh/surface_mesh.h"
#include "support/temp_dir.h"

TEST_CASE("scenario_run: a scenario's run holds its world, its poses and its projected plan", "[jobs]") {
  const incise::jobs::ScenarioRun run = incise::jobs::loadScenarioRun(INCISE_SCENARIOS_DIR "/pad-straight.json");
  CHECK(run.scenario.name == "pad-straight");
  CHECK(run.poses.size() > 1000);
  REQUIRE(run.plan.has_value());
  CHECK(run.plan->stations.size() > 10);
  CHECK(run.world->incisions() == 0);
}

TEST_CASE("scenario_run: the tissue's fingerprint is the one its traces carry", "[jobs]") {
  const incise::jobs::ScenarioRun run = incise::jobs::loadScenarioRun(INCISE_SCENARIOS_DIR "/pad-straight.json");
  const std::string hash = incise::jobs::tissueHashText(run.world->tissue());
  CHECK(hash.size() == 16);
  CHECK(incise::jobs::traceTissueHash({"generator: x", std::string("tissue: ") + hash}) == hash);
  CHECK(incise::jobs::traceTissueHash({"generator: x"}).empty());
  CHECK(incise::jobs::hexText(0xabcull) == "0000000000000abc");
}

TEST_CASE("scenario_run: warnings go to the caller's hook, errors name the file", "[jobs]") {
  incise::test::TempDir dir;
  const auto bad = dir.write("bad.json", R"({ "tissue": { "mesh": "none.obj" }, "pose_source": { "kind": "trace",
    "path": "t.csv" } })");
  CHECK_THROWS_WITH(incise::jobs::loadScenarioRun(bad.string()), Catch::Contains("bad.json"));
  std::vector<std::string> heard;
  incise::jobs::warnWith([&](const std::string& text) { heard.push_back(text); }, "a note");
  CHECK(heard == std::vector<std::string>{"a note"});
}
