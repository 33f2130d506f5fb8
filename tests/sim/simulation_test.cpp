// Simulation driven directly, frame by frame on the test's thread (no loop, no feeder, no reader thread).
#include "incise/sim/simulation.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/shapes.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/stroke_poses.h"

using namespace incise;
using Eigen::Vector3d;

namespace {

// A slab whose top face is the plane z = 0: the identity orientation's blade (local -z) points into it.
mesh::SurfaceMesh slabBox() {
  return mesh::makeBox(Eigen::AlignedBox3d(Vector3d(-0.05, -0.05, -0.04), Vector3d(0.05, 0.05, 0.0)), 10);
}

// The cut button is bit 0 and the poses leave it up: contact and force, never an incision.
sim::WorldOptions noCutting() {
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  return options;
}

devices::PoseSample poseAt(const Vector3d& tip, double t_s) {
  devices::PoseSample p;
  p.time_s = t_s;
  p.tip_m = tip;
  return p;
}

sim::FrameInfo frameInfo(std::int64_t frame, double dt_s = 0.001) {
  sim::FrameInfo info;
  info.frame = frame;
  info.dt_s = dt_s;
  info.t_s = static_cast<double>(frame) * dt_s;
  return info;
}

struct RecordingSink : sim::ForceSink {
  struct Call {
    Vector3d force_N;
    double t_s;
  };
  std::vector<Call> calls;
  RecordingSink() { calls.reserve(64); }
  void apply(const Vector3d& force_N, double t_s) noexcept override { calls.push_back({force_N, t_s}); }
};

}  // namespace

TEST_CASE("simulation: a pose pushed is taken in the next frame and published with that frame", "[sim]") {
  sim::World world(slabBox(), noCutting());
  sim::Simulation simulation(world, nullptr, 1000, 2.5);
  sim::Snapshot snap;
  REQUIRE_FALSE(simulation.takeSnapshot(snap));  // nothing published yet
  REQUIRE(simulation.frameTime(0) == 2.5);
  REQUIRE(simulation.frameTime(4) == Approx(2.504).margin(1e-12));

  const Vector3d tip(0.01, -0.02, 0.003);  // 3 mm above the slab
  REQUIRE(simulation.pushPose(poseAt(tip, 0.0)));
  REQUIRE(simulation.posesTaken() == 0);  // still queued
  simulation.frame(frameInfo(0));
  REQUIRE(simulation.posesTaken() == 1);
  REQUIRE(simulation.takeSnapshot(snap));
  CHECK(snap.frame == 0);
  CHECK(snap.t_s == 2.5);
  CHECK(snap.profile.poses == 1);
  CHECK(snap.profile.queue_backlog == 0);
  CHECK(snap.haptic.poses == 1);
  CHECK(snap.haptic.tip_m == tip);
  CHECK_FALSE(snap.haptic.contact);
  CHECK(snap.haptic.force_N == Vector3d::Zero());
  CHECK(snap.incisions == 0);
  REQUIRE_FALSE(simulation.takeSnapshot(snap));  // nothing newer

  // Two poses before the next frame: both taken, oldest first, the tool at the newest.
  const Vector3d next(0.012, -0.02, 0.002), newest(0.014, -0.02, 0.001);
  REQUIRE(simulation.pushPose(poseAt(next, 0.001)));
  REQUIRE(simulation.pushPose(poseAt(newest, 0.002)));
  simulation.frame(frameInfo(1));
  REQUIRE(simulation.takeSnapshot(snap));
  CHECK(snap.frame == 1);
  CHECK(snap.t_s == Approx(2.501).margin(1e-12));
  CHECK(snap.profile.poses == 2);
  CHECK(snap.haptic.poses == 2);
  CHECK(snap.haptic.poses_rejected == 0);
  CHECK(snap.haptic.tip_m == newest);
  REQUIRE(simulation.posesTaken() == 3);

  // A frame without poses: the tool stays where it was.
  simulation.frame(frameInfo(2));
  REQUIRE(simulation.takeSnapshot(snap));
  CHECK(snap.frame == 2);
  CHECK(snap.profile.poses == 0);
  CHECK(snap.haptic.poses == 0);
  CHECK(snap.haptic.tip_m == newest);

  // A pose not after the previous one in time is taken from the queue but rejected by the world.
  REQUIRE(simulation.pushPose(poseAt(tip, 0.001)));
  simulation.frame(frameInfo(3));
  REQUIRE(simulation.takeSnapshot(snap));
  CHECK(snap.profile.poses == 1);
  CHECK(snap.haptic.poses == 0);
  CHECK(snap.haptic.poses_rejected == 1);
  CHECK(snap.haptic.tip_m == newest);

  // Every frame recorded once in the simulation's own statistics.
  CHECK(simulation.stats().frames() == 4);
  CHECK(simulation.posesDropped() == 0);
}

TEST_CASE("simulation: a full queue drops the pose and counts it, a frame takes at most kMaxPosesPerFrame", "[sim]") {
  sim::World world(slabBox(), noCutting());
  sim::Simulation simulation(world, nullptr, 1000, 0.0);
  constexpr auto capacity = static_cast<int>(sim::Simulation::kQueueCapacity);
  constexpr int per_frame = sim::Simulation::kMaxPosesPerFrame;
  const Vector3d tip(0.0, 0.0, 0.01);
  int t = 0;
  for (; t < capacity; ++t) REQUIRE(simulation.pushPose(poseAt(tip, 1e-6 * t)));
  for (int k = 0; k < 10; ++k) REQUIRE_FALSE(simulation.pushPose(poseAt(tip, 1e-6 * (t + k))));
  REQUIRE(simulation.posesDropped() == 10);

  sim::Snapshot snap;
  simulation.frame(frameInfo(0));
  REQUIRE(simulation.takeSnapshot(snap));
  CHECK(snap.profile.poses == per_frame);
  CHECK(snap.profile.queue_backlog == capacity - per_frame);
  CHECK(snap.haptic.poses == per_frame);
  CHECK(simulation.posesTaken() == per_frame);

  // Room again: a push succeeds, and the count of drops stays.
  REQUIRE(simulation.pushPose(poseAt(tip, 1.0)));
  CHECK(simulation.posesDropped() == 10);
  std::int64_t frame = 1;
  while (simulation.posesTaken() < capacity + 1) {
    REQUIRE(frame < 100);
    simulation.frame(frameInfo(frame++));
  }
  REQUIRE(simulation.takeSnapshot(snap));
  CHECK(snap.profile.queue_backlog == 0);
  CHECK(simulation.posesTaken() == capacity + 1);
  CHECK(frame == (capacity + 1 + per_frame - 1) / per_frame);  // ceil: 17 frames in all
  CHECK(snap.haptic.poses_rejected == 0);
}

TEST_CASE("simulation: the ForceSink gets each frame's haptic force at the frame's time", "[sim]") {
  const sim::WorldOptions options = noCutting();
  sim::World world(slabBox(), options);
  RecordingSink sink;
  sim::Simulation simulation(world, &sink, 2000, 1.0);  // 500 Hz
  sim::Snapshot snap;

  // Above the surface: zero force.
  REQUIRE(simulation.pushPose(poseAt(Vector3d(0.003, 0.004, 0.002), 0.0)));
  simulation.frame(frameInfo(0, 0.002));
  REQUIRE(sink.calls.size() == 1);
  CHECK(sink.calls[0].force_N == Vector3d::Zero());
  CHECK(sink.calls[0].t_s == 1.0);

  // 1 mm in, held still: the penalty spring along the outward normal +z, the same force in the snapshot.
  REQUIRE(simulation.pushPose(poseAt(Vector3d(0.003, 0.004, -0.001), 0.002)));
  simulation.frame(frameInfo(1, 0.002));
  REQUIRE(simulation.pushPose(poseAt(Vector3d(0.003, 0.004, -0.001), 0.004)));
  simulation.frame(frameInfo(2, 0.002));
  REQUIRE(sink.calls.size() == 3);
  CHECK(sink.calls[1].t_s == Approx(1.002).margin(1e-12));
  CHECK(sink.calls[2].t_s == Approx(1.004).margin(1e-12));
  CHECK(sink.calls[1].force_N.z() > 0.0);  // spring plus damping of the 1.5 m/s push in
  const Vector3d spring = sink.calls[2].force_N;
  CHECK(spring.x() == Approx(0.0).margin(1e-12));
  CHECK(spring.y() == Approx(0.0).margin(1e-12));
  CHECK(spring.z() == Approx(options.tissue.stiffness_N_per_m * 0.001).epsilon(1e-9));
  REQUIRE(simulation.takeSnapshot(snap));
  CHECK(snap.frame == 2);
  CHECK(snap.haptic.contact);
  CHECK_FALSE(snap.haptic.cutting);  // the button is up
  CHECK(snap.haptic.force_N == spring);
  CHECK(snap.haptic.penetration_m == Approx(0.001).epsilon(1e-9));

  // A frame without a pose still calls the sink, with the force of the tool where it stays.
  simulation.frame(frameInfo(3, 0.002));
  REQUIRE(sink.calls.size() == 4);
  CHECK(sink.calls[3].t_s == Approx(1.006).margin(1e-12));
  CHECK(sink.calls[3].force_N == spring);
  CHECK(world.incisions() == 0);
}

namespace {

// A stroke's poses fed one a frame, with `pause_frames` frames without a pose (the blade held still in
// the tissue, as a live device that sends nothing while still: the later poses' times are that much later)
// before pose `pause_before` (none when negative), then frames until the cut has no work left. Returns the
// pose-to-visible latencies the snapshots show: per frame whose snapshot shows more final columns, the
// frames until a snapshot shows them cut (the pose that made them final came in that same frame).
struct PausedStroke {
  std::vector<int> expected;
  std::vector<std::int64_t> made_at;  // the frames whose snapshot showed more final columns
  sim::LatencySummary summary;
};

PausedStroke pausedStroke(std::int64_t pause_before, int pause_frames) {
  sim::WorldOptions options;
  options.cut_budget_us = 20.0;  // a few inversions a frame: the cut trails the stroke by some frames
  const mesh::SurfaceMesh tissue =
      mesh::subdivided(mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01), 2);
  sim::StrokeSpec stroke;
  stroke.start_m = Vector3d(-0.012, 0.0, 0.015);
  stroke.length_m = 0.02;
  std::vector<devices::PoseSample> poses = sim::posesForStrokes(tissue, {stroke}, options, 1000.0);
  const auto pause_after = static_cast<std::size_t>(pause_before < 0 ? poses.size() : pause_before);
  for (std::size_t k = pause_after; k < poses.size(); ++k) poses[k].time_s += 0.001 * pause_frames;
  sim::World world(tissue, options);
  sim::Simulation simulation(world, nullptr, 1000, 0.0);
  struct Made {
    int columns;
    std::int64_t frame;
  };
  std::vector<Made> made;
  std::vector<int> done_at;  // per frame, columns cut
  int final_columns = 0;
  std::size_t next = 0;
  sim::Snapshot snap;
  for (std::int64_t frame = 0; next < poses.size() || world.pending() || frame < 2000; ++frame) {
    const bool paused = next == pause_after && pause_frames-- > 0;
    if (next < poses.size() && !paused) REQUIRE(simulation.pushPose(poses[next++]));
    simulation.frame(frameInfo(frame));
    REQUIRE(simulation.takeSnapshot(snap));
    REQUIRE(snap.incisions <= 1);
    if (snap.columns_final > final_columns) made.push_back({final_columns = snap.columns_final, frame});
    done_at.push_back(snap.columns_done);
  }
  PausedStroke out;
  for (const Made& m : made) {
    out.made_at.push_back(m.frame);
    auto frame = m.frame;
    while (done_at[static_cast<std::size_t>(frame)] < m.columns) ++frame;
    out.expected.push_back(static_cast<int>(frame - m.frame));
  }
  out.summary = simulation.stats().summary();
  return out;
}

}  // namespace

TEST_CASE("simulation: pose-to-visible counts each cut once, from the frame its pose came, idle frames add nothing",
          "[sim]") {
  // Without a pause first; then 300 frames without a pose before a pose that makes columns final (the
  // middle one of the run without a pause: one pose a frame from frame 0, so frame k took pose k).
  const PausedStroke straight = pausedStroke(-1, 0);
  const std::int64_t before = straight.made_at[straight.made_at.size() / 2];
  for (const int pause_frames : {0, 300}) {
    INFO(pause_frames << " frames without a pose before pose " << before);
    const PausedStroke run = pause_frames == 0 ? straight : pausedStroke(before, pause_frames);
    REQUIRE(run.expected.size() > 20);
    const sim::SampleSummary& s = run.summary.pose_to_visible_frames;
    CHECK(s.count == run.expected.size());
    double sum = 0.0;
    for (const int e : run.expected) sum += e;
    CHECK(s.max == *std::max_element(run.expected.begin(), run.expected.end()));
    CHECK(s.mean == Approx(sum / static_cast<double>(run.expected.size())));
    CHECK(*std::max_element(run.expected.begin(), run.expected.end()) > 0);  // the budget made the cut trail
    CHECK(s.max < 100);  // far below the pause: the frames without a pose are not counted
  }
}

TEST_CASE("simulation: a non-positive period is refused", "[sim]") {
  sim::World world(slabBox(), noCutting());
  REQUIRE_THROWS_AS(sim::Simulation(world, nullptr, 0, 0.0), std::invalid_argument);
  REQUIRE_THROWS_AS(sim::Simulation(world, nullptr, -1000, 0.0), std::invalid_argument);
}
