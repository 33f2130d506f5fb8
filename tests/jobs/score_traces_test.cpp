#include "incise/jobs/score_traces.h"

#include <catch2/catch.hpp>

#include <fstream>

#include "support/temp_dir.h"

namespace {

const char* kPad = INCISE_SCENARIOS_DIR "/pad-straight.json";
const char* kPadTrace = INCISE_SCENARIOS_DIR "/traces/pad-straight.csv";

}  // namespace

TEST_CASE("score_traces: a shipped trace is read, scored and printed as incise score's line", "[jobs]") {
  using namespace incise;
  const jobs::ScoringScenario scoring = jobs::loadScoringScenario(kPad);
  std::vector<std::string> warnings;
  const auto poses = jobs::readScoreTrace(kPadTrace, scoring, [&](const std::string& w) { warnings.push_back(w); });
  CHECK(warnings.empty());
  const sim::Score score = sim::scoreSession(scoring.scenario, scoring.tissue, poses);
  const auto line = nlohmann::ordered_json::parse(jobs::scoreLine("pad.csv", score));
  CHECK(line.begin().key() == "trace");
  CHECK(line["trace"] == "pad.csv");
  CHECK(line["plan"]["share_within_lateral_tolerance"].get<double>() > 0.9);
  const auto summary = jobs::scoreSummary({line, line});
  CHECK(summary["summary"]["traces"] == 2);
  CHECK(summary["summary"]["mean"]["economy"] == line["economy"]);
  CHECK(summary["summary"]["mean"].contains("plan.share_uncut"));
}

TEST_CASE("score_traces: traces from another tissue, empty or without a fingerprint", "[jobs]") {
  using namespace incise;
  const jobs::ScoringScenario scoring = jobs::loadScoringScenario(kPad);
  CHECK_THROWS_WITH(jobs::readScoreTrace(INCISE_SCENARIOS_DIR "/traces/bunny-straight.csv", scoring),
                    Catch::Contains("bunny-straight.csv: recorded on another tissue (its comment says tissue ") &&
                        Catch::Contains("pad-straight's tissue is " + scoring.tissue_hash));
  test::TempDir dir;
  std::string head, text = test::readFile(kPadTrace), bare;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("# tissue:", 0) != 0) bare += line + "\n";
    if (head.size() < 300 && line[0] != '0' && line[0] != '1') head += line + "\n";
  }
  CHECK_THROWS_WITH(jobs::readScoreTrace(dir.write("empty.csv", head), scoring),
                    Catch::EndsWith("empty.csv: the trace is empty (no pose to score)"));
  std::vector<std::string> warnings;
  const auto poses =
      jobs::readScoreTrace(dir.write("bare.csv", bare), scoring, [&](const std::string& w) { warnings.push_back(w); });
  CHECK(poses.size() > 1000);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::EndsWith("bare.csv carries no tissue hash; scored on pad-straight's tissue"));
}
