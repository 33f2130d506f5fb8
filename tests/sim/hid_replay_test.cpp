// The shipped HID recordings as scenarios: a pen stroke recorded from a Wacom or XP-Pen descriptor and a
// SpaceNavigator stroke, replayed through the HID parser and profile into the simulation: the same bytes
// give the same geometry (twice, and fast or in real time), and the cut is a closed two-manifold groove
// about as long as the stroke.
#include <catch2/catch.hpp>

#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_recording_poses.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario.h"
#include "incise/sim/simulation.h"

using namespace incise;

namespace {

struct HidRun {
  std::uint64_t hash = 0;
  double groove_m = 0.0, stroke_m = 0.0;
  int incisions = 0;
};

HidRun replayHid(const char* name, sim::ReplayPace pace) {
  const sim::Scenario s = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
  REQUIRE(s.source == sim::Scenario::Source::HidRecording);
  const auto replayed =
      devices::posesFromHidRecording(devices::readHidRecording(s.hid.path), s.hid.device, s.hid.mapping);
  REQUIRE(replayed.bad_reports == 0);
  sim::World world(sim::loadTissue(s), s.world);
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = s.periodUs();
  options.settle_s = s.settle_s;
  sim::replay(world, replayed.poses, options);
  REQUIRE(mesh::checkManifold(world.tissue().mesh()).closed_two_manifold);
  HidRun run;
  run.hash = mesh::geometryHash(world.tissue());
  run.incisions = world.incisions();
  for (const auto& f : world.cutter().stats().figures)
    run.groove_m += f.groove_length_m, run.stroke_m += f.stroke_length_m;
  return run;
}

}  // namespace

TEST_CASE("hid_replay: a Wacom pen recording replayed twice cuts the same closed groove", "[sim][hid]") {
  const HidRun a = replayHid("bunny-pen-wacom", sim::ReplayPace::Fast);
  const HidRun b = replayHid("bunny-pen-wacom", sim::ReplayPace::Fast);
  CHECK(a.hash == b.hash);
  CHECK(a.incisions == 1);
  CHECK(a.stroke_m > 0.05);
  CHECK(a.groove_m > 0.95 * a.stroke_m);
}

TEST_CASE("hid_replay: XP-Pen and SpaceNavigator recordings, the same geometry fast and in real time",
          "[sim][hid][slow]") {
  for (const char* name : {"bunny-pen-xppen", "bunny-spacenavigator"}) {
    INFO(name);
    const HidRun fast = replayHid(name, sim::ReplayPace::Fast);
    const HidRun realtime = replayHid(name, sim::ReplayPace::RealTime);
    CHECK(fast.hash == realtime.hash);
    CHECK(fast.incisions == 1);
    CHECK(fast.groove_m > 0.9 * fast.stroke_m);
    CHECK(fast.stroke_m > 0.04);
  }
}
