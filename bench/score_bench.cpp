// Scoring a 60 s training session against its --fast replay (target: scoring <= 2x the replay's time).
// The session: the shipped pad-straight scenario (the skin pad, its 5 cm plan) with 12 generated strokes of
// 4 cm at 1 cm/s, 1 s apart, side by side across the pad (60 s of poses at 1 kHz, 12 incisions). Each round
// times sim::replay (ReplayPace::Fast, as `incise replay --fast`) on a fresh world, then sim::scoreSession
// (the same replay plus the measurements) on the same poses; the figure is the median over the rounds of
// score / replay. Prints one JSON document: the figure, the target, both times, the machine.
//   incise_bench_score [--rounds N]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "incise/measure/machine_info.h"
#include "incise/measure/percentile.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/score.h"
#include "incise/sim/simulation.h"
#include "incise/sim/stroke_poses.h"

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::vector<incise::sim::StrokeSpec> sixtySeconds() {
  std::vector<incise::sim::StrokeSpec> strokes;
  for (int k = 0; k < 12; ++k) {
    incise::sim::StrokeSpec s;
    s.start_m = Eigen::Vector3d(-0.02, 0.01, -0.0395 + 0.007 * k);
    s.direction = Eigen::Vector3d::UnitX();
    s.length_m = 0.04;
    s.speed_m_per_s = 0.01;
    s.pause_s = 0.94;  // with the 30 ms descent and rise: 5 s per stroke
    strokes.push_back(s);
  }
  return strokes;
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 3;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--rounds") == 0) rounds = std::stoi(argv[i + 1]);
  const incise::sim::Scenario scenario = incise::sim::loadScenario(INCISE_SCENARIOS_DIR "/pad-straight.json");
  const incise::mesh::SurfaceMesh tissue = incise::sim::loadTissue(scenario);
  const auto poses = incise::sim::posesForStrokes(tissue, sixtySeconds(), scenario.world, scenario.rate_hz);
  std::vector<double> replay_s, score_s, ratio;
  incise::sim::Score score;
  for (int r = 0; r < rounds; ++r) {
    incise::sim::World world(tissue, scenario.world);
    incise::sim::ReplayOptions options;
    options.period_us = scenario.periodUs();
    options.settle_s = scenario.settle_s;
    Clock::time_point start = Clock::now();
    incise::sim::replay(world, poses, options);
    replay_s.push_back(secondsSince(start));
    start = Clock::now();
    score = incise::sim::scoreSession(scenario, tissue, poses);
    score_s.push_back(secondsSince(start));
    ratio.push_back(score_s.back() / replay_s.back());
  }
  const double session_s = poses.back().time_s - poses.front().time_s;
  const nlohmann::json report = {{"benchmark", "score"},
                                 {"session_s", session_s},
                                 {"poses", poses.size()},
                                 {"incisions", score.incisions},
                                 {"rounds", rounds},
                                 {"replay_fast_s_median", incise::measure::percentile(replay_s, 0.5)},
                                 {"score_s_median", incise::measure::percentile(score_s, 0.5)},
                                 {"score_over_replay_median", incise::measure::percentile(ratio, 0.5)},
                                 {"score_over_replay_max", incise::measure::percentile(ratio, 1.0)},
                                 {"target_score_over_replay", 2.0},
                                 {"meets_target", incise::measure::percentile(ratio, 0.5) <= 2.0},
                                 {"machine", incise::measure::machineInfo()}};
  std::printf("%s\n", report.dump(2).c_str());
  return 0;
}
