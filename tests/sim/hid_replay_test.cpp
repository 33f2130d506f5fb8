// The shipped HID recordings as scenarios: a pen stroke recorded from a Wacom or XP-Pen descriptor and a
// SpaceNavigator stroke, replayed through the HID parser and profile into the simulation: the same bytes
// give the same geometry (twice, and fast or in real time), and the cut is a closed two-manifold groove
// about as long as the stroke. And every pen descriptor shipped, as a user would try it: a recording made
// with it replaces pad-pen-wacom's, nothing but the path changes, and the groove is the source stroke's.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_recording_poses.h"
#include "incise/devices/hid_synth.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario.h"
#include "incise/sim/simulation.h"
#include "incise/sim/stroke_poses.h"
#include "support/temp_dir.h"

using namespace incise;

namespace {

struct HidRun {
  std::uint64_t hash = 0;
  double groove_m = 0.0, stroke_m = 0.0;
  int incisions = 0;
};

sim::Scenario scenario(const std::string& name) {
  return sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
}

HidRun replayPoses(const sim::Scenario& s, const std::vector<devices::PoseSample>& poses, sim::ReplayPace pace) {
  sim::World world(sim::loadTissue(s), s.world);
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = s.periodUs();
  options.settle_s = s.settle_s;
  sim::replay(world, poses, options);
  REQUIRE(mesh::checkManifold(world.tissue().mesh()).closed_two_manifold);
  HidRun run;
  run.hash = mesh::geometryHash(world.tissue());
  run.incisions = world.incisions();
  for (const auto& f : world.cutter().stats().figures)
    run.groove_m += f.groove_length_m, run.stroke_m += f.stroke_length_m;
  return run;
}

// A hid-recording scenario as it is: its recording through the parser and profile, then the replay.
HidRun replayHid(const sim::Scenario& s, sim::ReplayPace pace) {
  REQUIRE(s.source == sim::Scenario::Source::HidRecording);
  const auto replayed =
      devices::posesFromHidRecording(devices::readHidRecording(s.hid.path), s.hid.device, s.hid.mapping);
  REQUIRE(replayed.bad_reports == 0);
  return replayPoses(s, replayed.poses, pace);
}

HidRun replayHid(const char* name, sim::ReplayPace pace) { return replayHid(scenario(name), pace); }

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

TEST_CASE("hid_replay: a recording from every shipped pen, swapped into pad-pen-wacom, cuts the source's groove",
          "[sim][hid]") {
  // The source: pad-pen-wacom's synthesis strokes (pad-straight) replayed as they are.
  const sim::Scenario pen = scenario("pad-pen-wacom");
  const sim::Scenario source = sim::loadScenario(pen.hid.synthesis.from);
  const auto strokes = sim::posesForStrokes(sim::loadTissue(source), source.strokes, source.world, source.rate_hz);
  const HidRun reference = replayPoses(source, strokes, sim::ReplayPace::Fast);
  REQUIRE(reference.groove_m > 0.04);
  const incise::test::TempDir dir;
  int pens = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(INCISE_SCENARIOS_DIR) + "/hid/descriptors")) {
    if (entry.path().extension() != ".txt") continue;
    devices::HidRecordedDevice device;
    device.name = entry.path().stem().string();
    device.descriptor = devices::loadHexBytes(entry.path());
    if (!devices::findHidPen(devices::parseHidDescriptor(device.descriptor)).pen) continue;
    INFO(entry.path().filename().string());
    ++pens;
    // The recording a user of this tablet would make, written where pad-pen-wacom's path is swapped to.
    const auto recording =
        devices::synthesizeHidRecording(device, pen.hid.mapping, strokes, {pen.hid.synthesis.rate_hz});
    sim::Scenario swapped = pen;
    swapped.hid.path = dir.path() / (device.name + ".hid");
    devices::HidRecordingWriter writer(swapped.hid.path, recording.devices[0]);
    for (const auto& r : recording.reports) writer.write(r.time_us, r.bytes);
    writer.close();
    const HidRun run = replayHid(swapped, sim::ReplayPace::Fast);
    CHECK(run.incisions == 1);
    CHECK(std::abs(run.groove_m - reference.groove_m) <= 0.05 * reference.groove_m);
  }
  CHECK(pens == 28);
}
