// The generator of recordings and the replay of recordings: a stroke synthesised into reports from a real
// descriptor and replayed through the same parser and profile gives the stroke back (pens to the tablet's
// resolution; the SpaceNavigator's velocity control closed-loop to a fraction of a millimetre), and a
// recording written to a file and read back replays to the same poses bit for bit.
#include <catch2/catch.hpp>

#include <cmath>
#include <tuple>
#include <vector>

#include "hid_fixture.h"
#include "incise/devices/hid_recording_poses.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_synth.h"
#include "support/temp_dir.h"

using namespace incise::devices;
using namespace incise::test;

namespace {

// The input pose at the replayed pose's time (the last one after the stroke: the pen leaving).
const PoseSample& at(const std::vector<PoseSample>& poses, double t_s) {
  return poses[std::min(poses.size() - 1, static_cast<std::size_t>(std::llround(t_s * 1000.0)))];
}

}  // namespace

TEST_CASE("hid_synth: pen strokes come back through the replay to the tablets' resolution", "[devices][hid]") {
  const auto poses = stroke();
  struct Case {
    const char* descriptor;
    std::uint16_t vid, pid;
    double tip_tolerance_m, angle_tolerance_rad;
  };
  // Wacom: 5 um, 8191 pressure levels, 1-degree tilt, twist. XP-Pen: 6 um, tilt in degrees, no twist: the
  // blade's roll is not carried, so only its axis is compared.
  for (const Case c :
       {Case{kWacomDescriptor, 0x056a, 0x0357, 2e-5, 0.03}, Case{kXpPenDescriptor, 0x28bd, 0x095b, 2e-5, 0.03}}) {
    INFO(c.descriptor);
    const HidRecording recording =
        synthesizeHidRecording(shippedDevice(c.descriptor, c.vid, c.pid), tabletOverArea(), poses);
    CHECK(recording.reports.size() == 201 + 1);  // 200 Hz over 1 s, plus the pen leaving
    const HidRecordingPoses replayed = posesFromHidRecording(recording, 0, tabletOverArea());
    CHECK(replayed.profile == HidProfileKind::Pen);
    CHECK(replayed.bad_reports == 0);
    int cutting = 0;
    for (const PoseSample& p : replayed.poses) {
      const PoseSample& want = at(poses, p.time_s);
      if (want.buttons == 0) continue;
      ++cutting;
      CHECK(p.buttons == 1u);
      CHECK((p.tip_m - want.tip_m).norm() < c.tip_tolerance_m);
      const Eigen::Vector3d axis = p.orientation * Eigen::Vector3d::UnitZ(),
                            want_axis = want.orientation * Eigen::Vector3d::UnitZ();
      CHECK(std::acos(std::min(1.0, axis.dot(want_axis))) < c.angle_tolerance_rad);
    }
    CHECK(cutting == 161);
    CHECK(replayed.poses.back().buttons == 0u);  // out of range at the end: lifted
    CHECK(replayed.poses.back().tip_m.z() == Approx(0.05 + tabletOverArea().pen.lift_m));
  }
}

TEST_CASE("hid_synth: the SpaceNavigator's closed-loop velocity control follows the stroke", "[devices][hid]") {
  const auto poses = stroke();
  HidMapping m;
  m.six_dof.start_m = poses.front().tip_m;
  m.six_dof.start_orientation = poses.front().orientation;
  m.six_dof.max_speed_m_per_s = 0.2;
  m.six_dof.max_rate_rad_per_s = 2.0;
  const HidRecording recording =
      synthesizeHidRecording(shippedDevice(kSpaceNavigatorDescriptor, 0x046d, 0xc626), m, poses, {125.0});
  const HidRecordingPoses replayed = posesFromHidRecording(recording, 0, m);
  CHECK(replayed.profile == HidProfileKind::SixDof);
  REQUIRE(replayed.poses.size() > 200);
  double worst_m = 0.0, worst_rad = 0.0;
  for (const PoseSample& p : replayed.poses) {
    if (p.time_s < 0.2 || p.time_s > 0.88) continue;  // after the step down into the cut, before the step up
    const PoseSample& want = at(poses, p.time_s);
    worst_m = std::max(worst_m, (p.tip_m - want.tip_m).norm());
    worst_rad = std::max(worst_rad, p.orientation.angularDistance(want.orientation));
  }
  CHECK(worst_m < 1e-4);
  CHECK(worst_rad < 0.02);
  // The button follows the stroke (pressed from 0.1 s to 0.9 s), one report per change.
  const auto pressed =
      std::count_if(replayed.poses.begin(), replayed.poses.end(), [](const PoseSample& p) { return p.buttons == 1u; });
  CHECK(pressed > 150);
  CHECK(replayed.poses.back().buttons == 0u);
}

TEST_CASE("hid_synth: a recording written, read back and replayed twice gives the same poses bit for bit",
          "[devices][hid]") {
  const TempDir dir;
  const auto path = dir.path() / "pen.hid";
  const HidRecording recording =
      synthesizeHidRecording(shippedDevice(kWacomDescriptor, 0x056a, 0x0357), tabletOverArea(), stroke());
  {
    HidRecordingWriter writer(path, recording.devices[0]);
    for (const auto& r : recording.reports) writer.write(r.time_us, r.bytes);
    writer.close();
  }
  const HidRecording back = readHidRecording(path);
  REQUIRE(back.reports.size() == recording.reports.size());
  for (std::size_t i = 0; i < back.reports.size(); ++i) {
    REQUIRE(back.reports[i].bytes == recording.reports[i].bytes);
    REQUIRE(back.reports[i].time_us == recording.reports[i].time_us);
  }
  const auto a = posesFromHidRecording(back, 0, tabletOverArea()).poses;
  const auto b = posesFromHidRecording(readHidRecording(path), 0, tabletOverArea()).poses;
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) REQUIRE(a[i] == b[i]);
}

TEST_CASE("hid_synth: synthesised reports round-trip through extractor and encoder bit for bit", "[devices][hid]") {
  const HidMapping pen = tabletOverArea();
  HidMapping six_dof;
  six_dof.six_dof.start_m = stroke().front().tip_m;
  for (const auto& [name, id, mapping] :
       {std::tuple{kWacomDescriptor, HidDeviceId{0x056a, 0x0357}, pen},
        std::tuple{kXpPenDescriptor, HidDeviceId{0x28bd, 0x095b}, pen},
        std::tuple{kSpaceNavigatorDescriptor, HidDeviceId{0x046d, 0xc626}, six_dof}}) {
    INFO(name);
    const HidRecording recording = synthesizeHidRecording(shippedDevice(name, id.vid, id.pid), mapping, stroke());
    const HidDescriptor d = parseHidDescriptor(recording.devices[0].descriptor);
    const HidReportDecoder decoder(d);
    const HidReportEncoder encoder(d);
    std::vector<HidValue> values(decoder.maxValues());
    for (const HidRecordedReport& r : recording.reports) {
      const HidDecoded decoded = decoder.decode(r.bytes, values);
      REQUIRE(decoded.status == HidDecodeStatus::Ok);
      auto again = encoder.blank(*decoded.layout);
      const auto payload = std::span(again).subspan(d.uses_report_ids ? 1 : 0);
      for (std::size_t i = 0; i < decoded.values; ++i)
        writeHidElement(payload, decoded.layout->fields[values[i].field], values[i].element, values[i].logical);
      REQUIRE(again == r.bytes);
    }
  }
}

TEST_CASE("hid_recording_poses: bad reports counted, a device without a profile refused", "[devices][hid]") {
  HidRecording recording =
      synthesizeHidRecording(shippedDevice(kXpPenDescriptor, 0x28bd, 0x095b), tabletOverArea(), stroke());
  recording.reports[5].bytes.resize(3);
  recording.reports[5].line = 17;
  recording.reports[6].bytes[0] = 0x42;
  const HidRecordingPoses replayed = posesFromHidRecording(recording, 0, tabletOverArea(), "pen.hid");
  CHECK(replayed.bad_reports == 2);
  CHECK(replayed.first_bad_line == 17);
  CHECK_THROWS_WITH(posesFromHidRecording(recording, 3, {}, "pen.hid"),
                    "pen.hid: device 3: no such device (the recording has 1)");
  recording.devices[0].descriptor = {0x05, 0x01, 0x09, 0x30, 0x15, 0x00, 0x25,
                                     0x01, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02};
  CHECK_THROWS_AS(posesFromHidRecording(recording, 0, {}, "pen.hid"), HidProfileError);
}

TEST_CASE("hid_synth: a 6-DOF device with one combined report (axes and buttons together)", "[devices][hid]") {
  // Multi-axis Controller, report 1: X Y Z Rx Ry Rz (16 bits, -350..350, absolute), buttons 1-2, padding.
  HidRecordedDevice combined;
  combined.vid = 0x1234;
  combined.pid = 0x0001;
  combined.descriptor = {0x05, 0x01, 0x09, 0x08, 0xa1, 0x01, 0x85, 0x01, 0x16, 0xa2, 0xfe, 0x26, 0x5e, 0x01,
                         0x75, 0x10, 0x95, 0x06, 0x09, 0x30, 0x09, 0x31, 0x09, 0x32, 0x09, 0x33, 0x09, 0x34,
                         0x09, 0x35, 0x81, 0x02, 0x05, 0x09, 0x19, 0x01, 0x29, 0x02, 0x15, 0x00, 0x25, 0x01,
                         0x75, 0x01, 0x95, 0x02, 0x81, 0x02, 0x95, 0x06, 0x81, 0x03, 0xc0};
  const auto poses = stroke();
  HidMapping m;
  m.six_dof.start_m = poses.front().tip_m;
  m.six_dof.start_orientation = poses.front().orientation;
  m.six_dof.max_speed_m_per_s = 0.2;
  m.six_dof.max_rate_rad_per_s = 2.0;
  REQUIRE(chooseHidProfile(parseHidDescriptor(combined.descriptor)).kind == HidProfileKind::SixDof);
  const HidRecording recording = synthesizeHidRecording(combined, m, poses, {125.0});
  for (const auto& r : recording.reports) REQUIRE(r.bytes.size() == 14);  // ID + 12 axis bytes + 1 button byte
  const HidRecordingPoses replayed = posesFromHidRecording(recording, 0, m);
  double worst_m = 0.0, worst_rad = 0.0;
  int pressed = 0;
  for (const PoseSample& p : replayed.poses) {
    pressed += p.buttons == 1u ? 1 : 0;
    if (p.time_s < 0.2 || p.time_s > 0.88) continue;
    const PoseSample& want = at(poses, p.time_s);
    worst_m = std::max(worst_m, (p.tip_m - want.tip_m).norm());
    worst_rad = std::max(worst_rad, p.orientation.angularDistance(want.orientation));
  }
  CHECK(worst_m < 1e-4);  // each report carries all six axes: sending one group keeps the other's held values
  CHECK(worst_rad < 0.02);
  CHECK(pressed > 150);
}
