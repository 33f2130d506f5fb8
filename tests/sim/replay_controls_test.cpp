// The replay's controls for a viewer (sim/src/simulation.cpp): pause, speed and stop. Pausing a real-time
// replay or running it at another speed does not change the frames, so the geometry is the same bits;
// stopping ends it early with the frames run.
#include "incise/sim/simulation.h"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <thread>

#include "incise/devices/trace_csv.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/sim/scenario.h"

using namespace incise;

namespace {

struct Result {
  sim::ReplayReport report;
  std::uint64_t hash;
};

template <typename Configure>
Result run(Configure&& configure) {
  const sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/bunny-straight.json");
  sim::World world(sim::loadTissue(s), s.world);
  const auto poses = devices::TraceReader::readAll(s.trace);
  sim::ReplayOptions o;
  o.pace = sim::ReplayPace::RealTime;
  o.period_us = s.periodUs();
  o.settle_s = s.settle_s;
  configure(o);
  Result r{sim::replay(world, poses, o), 0};
  r.hash = mesh::geometryHash(world.tissue());
  return r;
}

}  // namespace

TEST_CASE("replay_controls: a pause mid-stroke and another speed leave the frames and the geometry unchanged",
          "[sim][threads]") {
  const Result plain = run([](sim::ReplayOptions&) {});
  std::atomic<bool> pause{false};
  std::thread toggler([&] {  // a viewer's Space key: 300 ms of pause in the middle of the stroke
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    pause.store(true);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    pause.store(false);
  });
  const auto start = std::chrono::steady_clock::now();
  const Result paused = run([&](sim::ReplayOptions& o) { o.pause = &pause; });
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  toggler.join();
  CHECK(paused.report.frames == plain.report.frames);
  CHECK(paused.hash == plain.hash);
  CHECK(wall_s > plain.report.wall_s + 0.2);  // the pause really held the run
  const Result fast = run([](sim::ReplayOptions& o) { o.speed = 3.0; });
  CHECK(fast.report.frames == plain.report.frames);
  CHECK(fast.hash == plain.hash);
  // Paced at 3x: never ahead of its schedule (a third of the simulated time), and done sooner than the run at
  // 1x when the machine kept 3x's schedule (no deadline skipped). How much sooner depends on the machine's
  // load (the frames' own time, late wake-ups), so no ratio; a machine that could not keep it (a sanitizer
  // build beside another real-time test) takes the frames' own time at either speed.
  CHECK(fast.report.wall_s >= 0.99 * plain.report.simulated_s / 3.0);
  if (fast.report.loop.skipped_deadlines == 0) CHECK(fast.report.wall_s < plain.report.wall_s);
}

TEST_CASE("replay_controls: stop_requested and stop_after_s end the replay early", "[sim]") {
  const Result stopped = run([](sim::ReplayOptions& o) {
    o.stop_requested = [start = std::chrono::steady_clock::now()] {
      return std::chrono::steady_clock::now() - start > std::chrono::milliseconds(300);
    };
  });
  CHECK(stopped.report.stopped_early);
  CHECK(stopped.report.frames < 800);
  const Result at = run([](sim::ReplayOptions& o) {
    o.pace = sim::ReplayPace::Fast;
    o.stop_after_s = 0.25;
  });
  CHECK(at.report.stopped_early);
  CHECK(at.report.frames == 251);  // frames 0..250: the one at 0.25 s ends it
  CHECK_THROWS_WITH(run([](sim::ReplayOptions& o) { o.speed = 0.0; }), Catch::Contains("speed"));
}
