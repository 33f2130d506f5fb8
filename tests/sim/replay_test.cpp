#include "incise/cutting/surface_cutter.h"
#include "incise/cutting/tet_cutter.h"
#include "incise/sim/simulation.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <thread>

#include "incise/cutting/mesh_hash.h"
#include "incise/devices/trace_csv.h"
#include "incise/sim/scenario.h"

using namespace incise;

namespace {

struct Run {
  sim::ReplayReport report;
  std::uint64_t hash;
  int seam_vertices;
};

Run replayScenario(const char* name, sim::ReplayPace pace, sim::ForceSink* sink = nullptr) {
  const sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
  sim::World world(sim::loadTissue(s), s.world);
  const auto poses = devices::TraceReader::readAll(s.trace);
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = s.periodUs();
  options.settle_s = s.settle_s;
  Run run{sim::replay(world, poses, options, sink), cutting::geometryHash(world.tissue()),
          world.cutter().stats().vertices_duplicated};
  REQUIRE(cutting::checkManifold(world.tissue().mesh()).closed_two_manifold);
  return run;
}

// A force sink that records the forces and, at one frame, stalls the sim thread for 3 ms.
struct StallingSink : sim::ForceSink {
  std::atomic<int> frames{0};
  std::atomic<double> max_force_N{0.0};
  int stall_at = -1;
  void apply(const Eigen::Vector3d& f, double) noexcept override {
    if (frames++ == stall_at) std::this_thread::sleep_for(std::chrono::milliseconds(3));
    if (f.norm() > max_force_N) max_force_N = f.norm();
  }
};

}  // namespace

TEST_CASE("replay: fast and real-time replays give the same geometry", "[sim]") {
  const Run fast = replayScenario("bunny-straight", sim::ReplayPace::Fast);
  const Run realtime = replayScenario("bunny-straight", sim::ReplayPace::RealTime);
  REQUIRE(fast.seam_vertices > 50);
  REQUIRE(fast.hash == realtime.hash);
  REQUIRE(fast.report.frames == realtime.report.frames);
  REQUIRE(realtime.report.poses == fast.report.poses);
  REQUIRE(realtime.report.poses_dropped == 0);
  // Frames in real time last as long as the trace (plus settling): the loop really paced them.
  REQUIRE(realtime.report.wall_s > 0.9 * realtime.report.simulated_s);
  REQUIRE(fast.report.latency.frames == fast.report.frames);
}

TEST_CASE("replay: a tet tissue is cut, the same fast and in real time", "[sim]") {
  const auto cut = [](sim::ReplayPace pace) {
    const sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/bunny-tets.json");
    sim::World world(sim::loadTissue(s), s.world);
    REQUIRE(world.tets() != nullptr);
    sim::ReplayOptions options;
    options.pace = pace;
    options.period_us = s.periodUs();
    options.settle_s = s.settle_s;
    sim::replay(world, devices::TraceReader::readAll(s.trace), options);
    REQUIRE_FALSE(world.tets()->pending());
    REQUIRE(world.tets()->stats().failure.empty());
    return world.tets()->view(cutting::TetShape::Deformed);
  };
  const cutting::TetView fast = cut(sim::ReplayPace::Fast), realtime = cut(sim::ReplayPace::RealTime);
  REQUIRE(fast.split.end() - std::find(fast.split.begin(), fast.split.end(), 1) > 50);  // pieces of cut tets
  REQUIRE(cutting::checkConforming(fast.mesh).conforming);
  REQUIRE(fast.inverted_tets == 0);
  REQUIRE(fast.mesh.nodes_m == realtime.mesh.nodes_m);
  REQUIRE(fast.mesh.tets == realtime.mesh.tets);
  REQUIRE(fast.side == realtime.side);
}

TEST_CASE("replay: the crossing scenario gives the same geometry fast and in real time", "[sim][slow]") {
  REQUIRE(replayScenario("bunny-crossing", sim::ReplayPace::Fast).hash ==
          replayScenario("bunny-crossing", sim::ReplayPace::RealTime).hash);
}

TEST_CASE("replay: snapshots are read from another thread while the loop runs", "[sim][threads]") {
  const sim::Scenario s = sim::loadScenario(INCISE_SCENARIOS_DIR "/bunny-curved.json");
  sim::World world(sim::loadTissue(s), s.world);
  const auto poses = devices::TraceReader::readAll(s.trace);
  sim::ReplayOptions options;
  options.pace = sim::ReplayPace::RealTime;
  std::int64_t last_frame = -1;
  int seen = 0, out_of_order = 0, columns_went_back = 0, last_done = 0, last_incisions = 0, timed = 0;
  options.observer = [&](const sim::Snapshot& snapshot) {  // runs on the reader thread
    ++seen;
    if (snapshot.frame <= last_frame) ++out_of_order;
    if (snapshot.frame > 0 && snapshot.profile.frame_us > 0.0 && snapshot.profile.publish_us >= 0.0) ++timed;
    if (snapshot.incisions == last_incisions && snapshot.columns_done < last_done) ++columns_went_back;
    last_frame = snapshot.frame;
    last_done = snapshot.columns_done;
    last_incisions = snapshot.incisions;
  };
  const sim::ReplayReport report = sim::replay(world, poses, options);
  REQUIRE(report.snapshots_read == seen);
  REQUIRE(seen > 100);  // about one every 2 ms over ~1.4 s
  REQUIRE(out_of_order == 0);
  REQUIRE(columns_went_back == 0);
  REQUIRE(timed >= seen - 1);  // every snapshot after the first carries the previous frame's times
  REQUIRE(last_frame == report.frames - 1);
}

TEST_CASE("replay: period error and deadline misses are measured and reported", "[sim]") {
  StallingSink sink;
  sink.stall_at = 300;
  const Run run = replayScenario("bunny-straight", sim::ReplayPace::RealTime, &sink);
  REQUIRE(sink.frames == run.report.frames);
  REQUIRE(sink.max_force_N > 0.1);  // the sink received real forces
  REQUIRE(run.report.latency.deadline_misses >= 1);
  REQUIRE(run.report.latency.frame_us.max >= 3000.0);
  REQUIRE(run.report.loop.overruns + run.report.loop.skipped_deadlines >= 1);
  REQUIRE(run.report.latency.period_error_us.max > 0.0);
  // The cut still finished, and the stall changed nothing in it.
  REQUIRE(run.hash == replayScenario("bunny-straight", sim::ReplayPace::Fast).hash);
}

TEST_CASE("replay: pose-to-visible latency stays within 3 frames", "[sim]") {
  const Run run = replayScenario("bunny-curved", sim::ReplayPace::Fast);
  REQUIRE(run.report.latency.pose_to_visible_frames.count > 20);
  REQUIRE(run.report.latency.pose_to_visible_frames.p99 <= 3.0);
}
