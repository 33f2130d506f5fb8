// After its first frame, the sim thread allocates nothing. Each shipped scenario
// named here is replayed frame by frame on this thread, as replay's fast pace does it (the poses released at
// their times, a geometry stream attached and its reader pulling between frames, as under `incise view`),
// with every heap allocation made inside Simulation::frame counted (alloc_counter.h: operator new and the
// malloc family replaced in this test executable only). Frame 0 is the warm-up; every later frame must
// allocate nothing, through every incision's begin, cut, settle, the tets and the mesh's growth.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "alloc_counter.h"
#include "incise/incision/surface_cutter.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/geometry_stream.h"
#include "incise/sim/simulation.h"
#include "shipped_scenario.h"

namespace {

using incise::test::allocationsOnThisThread;
using incise::test::CountAllocations;

struct AllocatingFrames {
  std::int64_t frames = 0;
  std::int64_t allocating_frames = 0;  // after frame 0
  std::int64_t allocations = 0, bytes = 0;
  std::int64_t first_allocating_frame = -1;
  int incisions = 0;
  incise::incision::ThroughCut through = incise::incision::ThroughCut::None;  // the last incision's
  int pieces = 0;
};

// The scenario replayed as replay's fast pace does, each frame's allocations counted (frame 0 not).
// `first_pose_frame`: no pose is fed before that frame (a live device, or a real-time replay whose feeder
// thread starts late: the first contact query then comes after frame 0).
// `trace`: another shipped trace's poses instead of the scenario's own (traces/<trace>.csv).
// `against_clock`: frames as a real-time replay runs them (the cut's work also stops at its deadline; a
// through-cut's Boolean goes to the world's worker thread).
AllocatingFrames countFrames(const std::string& name, std::int64_t first_pose_frame = 0, const std::string& trace = "",
                             bool against_clock = false) {
  auto l = incise::test::loadShipped(name);
  if (!trace.empty())
    l.poses = incise::devices::TraceReader::readAll(std::string(INCISE_SCENARIOS_DIR) + "/traces/" + trace + ".csv");
  incise::sim::World& world = *l.world;
  incise::sim::GeometryStream stream;
  incise::sim::GeometryMirror mirror;
  const std::int64_t period_us = l.scenario.periodUs();
  incise::sim::Simulation sim(world, nullptr, period_us, l.poses.front().time_s);
  sim.attachGeometry(&stream);
  const double end_s = l.poses.back().time_s + l.scenario.settle_s;
  AllocatingFrames out;
  std::size_t fed = 0;
  for (std::int64_t k = 0;; ++k) {
    incise::sim::FrameInfo info;
    info.frame = k;
    info.dt_s = static_cast<double>(period_us) * 1e-6;
    info.t_s = static_cast<double>(k) * info.dt_s;
    info.against_clock = against_clock;
    const double t_s = sim.frameTime(k);
    while (k >= first_pose_frame && fed < l.poses.size() && l.poses[fed].time_s <= t_s + 1e-12)
      sim.pushPose(l.poses[fed++]);
    const auto before = allocationsOnThisThread();
    {
      const CountAllocations counting(k > 0);
      sim.frame(info);
    }
    const auto after = allocationsOnThisThread();
    if (after.calls > before.calls) {
      ++out.allocating_frames;
      out.allocations += after.calls - before.calls;
      out.bytes += after.bytes - before.bytes;
      if (out.first_allocating_frame < 0) out.first_allocating_frame = k;
    }
    mirror.pull(stream);  // the reader (the viewer's thread), not counted
    mirror.clearChanges();
    ++out.frames;
    if (fed == l.poses.size() && !world.pending() && t_s >= end_s) break;
  }
  out.incisions = world.incisions();
  const auto& figures = world.cutter().stats().figures;
  if (!figures.empty()) out.through = figures.back().through, out.pieces = figures.back().pieces;
  return out;
}

void requireNoAllocation(const std::string& name, int incisions_at_least, std::int64_t first_pose_frame = 0,
                         const std::string& trace = "") {
  const AllocatingFrames f = countFrames(name, first_pose_frame, trace);
  INFO(name << " " << trace << ": " << f.frames << " frames, " << f.incisions << " incisions; " << f.allocating_frames
            << " frames after the first allocated (" << f.allocations << " allocations, " << f.bytes
            << " bytes; the first in frame " << f.first_allocating_frame
            << "). INCISE_ALLOC_TRACE=N prints the first N allocations' stacks.");
  CHECK(f.incisions >= incisions_at_least);
  CHECK(f.allocations == 0);
}

}  // namespace

TEST_CASE("alloc: the counter sees this thread's allocations and no other's", "[alloc]") {
  const auto before = allocationsOnThisThread();
  {
    const CountAllocations counting;
    std::vector<int> v(1000);
    v[10] = 1;
    CHECK(v[10] == 1);
  }
  std::vector<int> uncounted(1000);
  const auto after = allocationsOnThisThread();
  CHECK(after.calls == before.calls + 1);
  CHECK(after.bytes == before.bytes + static_cast<std::int64_t>(1000 * sizeof(int)));
}

TEST_CASE("alloc: bunny-crossing allocates nothing on the sim thread after its first frame", "[alloc]") {
  requireNoAllocation("bunny-crossing", 2);
}

TEST_CASE("alloc: poses that first arrive after frame 0 allocate nothing either", "[alloc]") {
  // Found under load in the real-time test below: the contact queries' face stamps were sized by the first
  // query, so whichever frame saw the first pose allocated them. They are sized at load now.
  requireNoAllocation("bunny-crossing", 2, 5);
}

TEST_CASE("alloc: bunny-tets allocates nothing on the sim thread after its first frame", "[alloc]") {
  requireNoAllocation("bunny-tets", 1);
}

TEST_CASE("alloc: the tets' second incision (their rebase) allocates nothing either", "[alloc]") {
  requireNoAllocation("bunny-tets", 2, 0, "bunny-crossing");  // the crossing trace's two strokes
}

TEST_CASE("alloc: a simulated tissue's steps and cuts allocate nothing on the sim thread either", "[alloc]") {
  // pad-tension: tets with a material, stepped at 100 Hz of simulated time, the cut's journal applied to the
  // model in the frame it is made.
  requireNoAllocation("pad-tension", 1);
}

TEST_CASE("alloc: a cut through the slab against the clock allocates nothing on the sim thread either", "[alloc]") {
  // slab-through: the blade deeper than the slab is thick. The Boolean difference (CGAL, allocating) runs on
  // the world's worker; the sim thread applies its changes in a later frame within the mesh's reserved room.
  const AllocatingFrames f = countFrames("slab-through", 0, "", true);
  INFO(f.frames << " frames, " << f.allocating_frames << " allocating (the first " << f.first_allocating_frame << "), "
                << f.allocations << " allocations");
  CHECK(f.through == incise::incision::ThroughCut::Made);
  CHECK(f.pieces == 2);
  CHECK(f.allocations == 0);
}

TEST_CASE("alloc: bunny-crossing at 4 kHz allocates nothing on the sim thread after its first frame", "[alloc]") {
  requireNoAllocation("bunny-crossing-4khz", 2);
}

TEST_CASE("alloc: every other shipped trace and stroke scenario allocates nothing after its first frame", "[alloc]") {
  // The pads refine the skin ahead of the cut: its bisections and the coarse grid are counted too.
  for (const char* name : {"bunny-straight", "bunny-curved", "bunny-back", "pad-straight", "pad-s-curve"})
    requireNoAllocation(name, 1);
}

namespace {

// A haptic device's stand-in on the loop thread: from its second call on (frame 1) it has the thread count
// its allocations, and publishes the count after every call (the frames' work after the force is counted
// at the next call; the last frame's, never).
class CountingSink final : public incise::sim::ForceSink {
 public:
  void apply(const Eigen::Vector3d&, double) noexcept override {
    if (calls_++ == 1) counting_.emplace(true);
    allocations_.store(allocationsOnThisThread().calls - at_start_, std::memory_order_relaxed);
    if (calls_ == 1) at_start_ = allocationsOnThisThread().calls;
  }
  std::int64_t allocations() const noexcept { return allocations_.load(std::memory_order_relaxed); }
  std::int64_t calls() const noexcept { return calls_; }

 private:
  std::int64_t calls_ = 0, at_start_ = 0;
  std::optional<CountAllocations> counting_;  // ends with the sink (the loop thread has finished by then)
  std::atomic<std::int64_t> allocations_{0};
};

}  // namespace

TEST_CASE("alloc: in real time the loop thread allocates nothing after its first frame", "[alloc][threads]") {
  // The real-time pace: the FixedRateLoop's own thread runs the frames (and the loop's bookkeeping between
  // them) while a feeder thread releases the poses and a reader thread takes the snapshots.
  auto l = incise::test::loadShipped("bunny-crossing");
  incise::sim::ReplayOptions options;
  options.pace = incise::sim::ReplayPace::RealTime;
  options.settle_s = l.scenario.settle_s;
  CountingSink sink;
  const auto report = incise::sim::replay(*l.world, l.poses, options, &sink);
  INFO(report.frames << " frames, " << sink.calls() << " forces; " << sink.allocations()
                     << " allocations on the loop thread after frame 0");
  REQUIRE(l.world->incisions() >= 2);
  REQUIRE(sink.calls() > 1000);
  CHECK(sink.allocations() == 0);
}

TEST_CASE("alloc: a simulated tissue in real time: no allocation on the loop thread nor on its physics thread",
          "[alloc][threads]") {
  // pad-tension against the clock, its stroke after a press (a dent): the loop thread hands the physics
  // steps over; the physics thread takes the press, applies the cut's changes and steps. The physics thread
  // is counted from its second step's start to its last step's start (the hook runs on it before each step).
  auto l = incise::test::loadShipped("pad-tension");
  l.poses = incise::test::followedBy(incise::test::padPressPoses({}), l.poses);
  incise::sim::ReplayOptions options;
  options.pace = incise::sim::ReplayPace::RealTime;
  options.settle_s = l.scenario.settle_s;
  std::optional<CountAllocations> counting;
  std::int64_t at_second = 0, physics_allocations = 0, last_step = 0;
  options.physics_before_step = [&](std::int64_t k) {
    if (k == 2) {
      counting.emplace(true);
      at_second = allocationsOnThisThread().calls;
    }
    if (k >= 2) physics_allocations = allocationsOnThisThread().calls - at_second;
    last_step = k;
  };
  CountingSink sink;
  const auto report = incise::sim::replay(*l.world, l.poses, options, &sink);
  counting.reset();  // on this thread now: restores its flag (the physics thread has ended)
  INFO(report.frames << " frames, " << sink.calls() << " forces; " << sink.allocations()
                     << " allocations on the loop thread after frame 0; " << physics_allocations
                     << " on the physics thread from step 2 to step " << last_step);
  REQUIRE(l.world->incisions() >= 1);
  REQUIRE(last_step > 100);
  REQUIRE(l.world->physics()->counters().cuts_applied > 0);  // 35 in Release; fewer where steps fall behind
  REQUIRE(l.world->physics()->counters().pressed_steps > 50);
  CHECK(sink.allocations() == 0);
  CHECK(physics_allocations == 0);
}
