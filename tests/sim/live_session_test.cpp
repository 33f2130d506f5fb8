// A live run (sim/src/live_session.cpp): a producer thread pushes poses as they happen, stamped by the
// session's clock, while the loop runs; the session's copy of the poses, replayed as a trace through a fresh
// world, gives the same cut byte for byte; a viewer's mirror on another thread ends with the same mesh.
#include "incise/sim/live_session.h"

#include <catch2/catch.hpp>

#include <atomic>
#include <thread>

#include "incise/devices/trace_csv.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/scenario.h"
#include "shipped_scenario.h"

using namespace incise;

namespace {

using Loaded = test::ShippedScenario;
Loaded load(const char* name) { return test::loadShipped(name); }

}  // namespace

TEST_CASE("live_session: poses pushed live cut as their recording replays, byte for byte", "[sim][threads]") {
  Loaded l = load("bunny-straight");
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  stream.seed(*l.world, mirror);
  sim::LiveOptions options;
  options.period_us = l.scenario.periodUs();
  options.settle_s = l.scenario.settle_s;
  options.geometry = &stream;
  sim::LiveSession session(*l.world, options);
  CHECK_FALSE(session.push(l.poses.front()));  // not started: refused
  std::atomic<bool> done{false};
  std::thread viewer([&] {  // a viewer's thread
    while (!done.load(std::memory_order_acquire)) {
      mirror.pull(stream);
      mirror.clearChanges();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    mirror.pull(stream);
  });
  session.start();
  CHECK_THROWS_AS(session.start(), std::logic_error);
  std::thread producer([&] {  // the "mouse": the trace's motion at its own pace, stamped by the session's clock
    const auto begin = std::chrono::steady_clock::now();
    for (devices::PoseSample p : l.poses) {
      std::this_thread::sleep_until(begin + std::chrono::duration<double>(p.time_s - l.poses.front().time_s));
      p.time_s = session.nowS();
      session.push(p);
    }
  });
  producer.join();
  const sim::ReplayReport live = session.stop();
  done.store(true, std::memory_order_release);
  viewer.join();
  REQUIRE(live.geometry_flushed);
  CHECK(live.incisions == 1);
  CHECK(live.poses + live.poses_dropped == static_cast<std::int64_t>(session.poses().size()));
  CHECK(session.poses().size() == l.poses.size());
  CHECK(mirror.exact());
  CHECK(session.stop().frames == live.frames);  // once; the same report after
  CHECK_FALSE(session.push(l.poses.back()));    // stopped: refused

  Loaded again = load("bunny-straight");
  sim::ReplayOptions replay;
  replay.period_us = options.period_us;
  replay.settle_s = options.settle_s;
  const sim::ReplayReport replayed = sim::replay(*again.world, session.poses(), replay);
  CHECK(replayed.incisions == 1);
  CHECK(mesh::geometryHash(again.world->tissue()) == mesh::geometryHash(l.world->tissue()));
  CHECK(again.world->cutter().stats().edges_split == l.world->cutter().stats().edges_split);
}

TEST_CASE("live_session: bad options are refused with their values", "[sim]") {
  Loaded l = load("bunny-straight");
  sim::LiveOptions bad;
  bad.period_us = 0;
  CHECK_THROWS_WITH(sim::LiveSession(*l.world, bad), Catch::Contains("period_us"));
  sim::LiveSession idle(*l.world, sim::LiveOptions{});
  CHECK(idle.nowS() == 0.0);
  CHECK(idle.stop().frames == 0);  // never started: nothing ran
}
