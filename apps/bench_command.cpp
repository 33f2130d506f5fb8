// `incise bench [SCENARIO...] [--seconds S]`: the latency benchmark. Replays each scenario in real time at
// its rate, over and over on a fresh tissue, until S seconds of frames have run, and prints JSON: per
// scenario the frame, haptic and cut times (p50 / p99 / p99.9 / max), pose-to-visible latency in frames,
// deadline misses, the targets, and the machine.
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "data_dir.h"
#include "incise/sim/simulation.h"
#include "machine_info.h"
#include "progress.h"
#include "scenario_run.h"

namespace incise::apps {

namespace {

struct BenchArgs {
  std::vector<std::string> scenarios{shippedFile("bunny-straight.json"), shippedFile("bunny-curved.json"),
                                     shippedFile("bunny-crossing.json")};
  double seconds = 60.0;
  std::int64_t spin_us = 200;  // sleep_until wakes up to ~1 ms late on this VM; a haptic loop spins the rest
};

nlohmann::json summary(const sim::SampleSummary& s) {
  return {{"p50", s.p50}, {"p99", s.p99}, {"p999", s.p999}, {"max", s.max}, {"count", s.count}};
}

nlohmann::json benchScenario(const std::string& path, double seconds, std::int64_t spin_us) {
  sim::LatencyStats stats(static_cast<std::size_t>(seconds * 1000.0 * 1.2) + 10000);
  std::string name;
  int replays = 0;
  double wall_s = 0.0;
  std::int64_t overruns = 0;
  Progress progress("bench " + std::filesystem::path(path).stem().string(), seconds);
  while (static_cast<double>(stats.frames()) * 1e-3 < seconds) {
    LoadedScenario run;
    try {
      run = loadScenarioRun(path);
    } catch (const std::exception& e) {
      failWith("bench", e.what());
    }
    name = run.scenario.name;
    sim::ReplayOptions options;
    options.pace = sim::ReplayPace::RealTime;
    options.period_us = run.scenario.periodUs();
    options.settle_s = run.scenario.settle_s;
    options.stats = &stats;
    options.spin_us = spin_us;
    options.pin_threads = true;
    options.realtime_priority = true;  // SCHED_FIFO when the process may have it
    const sim::ReplayReport report = sim::replay(*run.world, run.poses, options);
    wall_s += report.wall_s;
    overruns += report.loop.overruns;
    ++replays;
    progress.update(static_cast<double>(stats.frames()) * 1e-3);
  }
  progress.finish();
  const sim::LatencySummary s = stats.summary();
  return {{"scenario", name},
          {"replays", replays},
          {"frames", s.frames},
          {"wall_s", wall_s},
          {"frame_us", summary(s.frame_us)},
          {"haptic_us", summary(s.haptic_us)},
          {"cut_us", summary(s.cut_us)},
          {"period_error_us", summary(s.period_error_us)},
          {"pose_to_visible_frames", summary(s.pose_to_visible_frames)},
          {"deadline_misses", s.deadline_misses},
          {"loop_overruns", overruns},
          {"meets_targets", s.frame_us.p99 <= 500.0 && s.haptic_us.p99 <= 50.0 && s.pose_to_visible_frames.p99 <= 3.0 &&
                                s.deadline_misses == 0}};
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = app.add_subcommand("bench", "Real-time latency benchmark over scenarios; prints JSON");
  cmd->add_option("scenarios", args->scenarios, "scenario files")->capture_default_str();
  cmd->add_option("--spin-us", args->spin_us, "busy-wait this long before each frame's deadline")
      ->capture_default_str()
      ->check(CLI::Range(0, 900));
  cmd->add_option("--seconds", args->seconds, "seconds of frames per scenario")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  cmd->callback([args] {
    nlohmann::json report = {
        {"benchmark", "realtime_replay_latency"},
        {"targets",
         {{"frame_us_p99", 500}, {"haptic_us_p99", 50}, {"pose_to_visible_frames_p99", 3}, {"deadline_misses", 0}}},
        {"seconds_per_scenario", args->seconds},
        {"spin_us", args->spin_us},
        {"machine", bench::machineInfo()},
        {"results", nlohmann::json::array()}};
    for (const auto& path : args->scenarios)
      report["results"].push_back(benchScenario(path, args->seconds, args->spin_us));
    std::printf("%s\n", report.dump(2).c_str());
  });
}

}  // namespace incise::apps
