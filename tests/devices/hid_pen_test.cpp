// The pen finder on every tablet descriptor we have (scenarios/hid/descriptors/: hid-tools' and the kernel's
// HID tests, see the README there), one test case each: a pen where the kernel maps a stylus, found in the
// report and collection it is in, reading what the device has, and a stroke synthesised through it comes back
// through the replay to the tablet's resolution; a descriptor without a pen is named for what it is. Then the
// finder's rules one at a time on descriptors written here: a pen spread over two reports, what a message
// says when a usage is missing or relative, and a touch screen.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "hid_fixture.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_recording_poses.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_synth.h"

using namespace incise::devices;
using namespace incise::test;

namespace {

struct Tablet {
  const char* file;
  std::uint16_t vid, pid;
  int report_id;                 // the pen's first input report; -1: no pen
  const char* path;              // the pen's tool collection; for no pen, how describeHidTools starts
  std::int64_t pressure_levels;  // 0: none
  bool tilt, twist, in_range;
};

std::int64_t levels(const HidElement& e) { return e ? e.field->logical_max - e.field->logical_min + 1 : 0; }

// The stroke's pose that a replayed pose carries: the one at the start of its report period (200 Hz).
const PoseSample& source(const std::vector<PoseSample>& poses, double t_s) {
  const auto period = static_cast<std::size_t>(std::floor(t_s * 200.0 + 1e-6));
  return poses[std::min(poses.size() - 1, period * 5)];
}

void checkNotPen(const HidDescriptor& d, const Tablet& t) {
  const HidPenSearch search = findHidPen(d);
  CHECK_FALSE(search.pen.has_value());
  CHECK(search.reason.rfind("no pen: no Stylus, Pen, Digitizer or Light Pen collection; its input is ", 0) == 0);
  CHECK(describeHidTools(search.tools).rfind(t.path, 0) == 0);
  CHECK(chooseHidProfile(d).kind != HidProfileKind::Pen);
}

void checkFound(const HidPen& pen, const Tablet& t) {
  CHECK(pen.layouts().front()->id == t.report_id);
  CHECK(pen.tool.kind == HidToolKind::Pen);
  CHECK(pen.tool.path == t.path);
  CHECK(levels(pen[HidPenRole::TipPressure]) == t.pressure_levels);
  CHECK(static_cast<bool>(pen[HidPenRole::TiltX] && pen[HidPenRole::TiltY]) == t.tilt);
  CHECK(static_cast<bool>(pen[HidPenRole::Twist]) == t.twist);
  CHECK(static_cast<bool>(pen[HidPenRole::InRange]) == t.in_range);
}

// The stroke through the descriptor and back: the surface point to a count of the tablet's resolution, the
// depth to a pressure level (or tip_depth_m without pressure), the axis to a degree of tilt (or straight up).
void checkRoundTrip(const HidPen& pen, const Tablet& t) {
  const HidMapping mapping = tabletOverArea();
  const auto poses = stroke();
  const HidRecording recording = synthesizeHidRecording(shippedDevice(t.file, t.vid, t.pid), mapping, poses);
  const HidRecordingPoses replayed = posesFromHidRecording(recording, 0, mapping);
  CHECK(replayed.profile == HidProfileKind::Pen);
  CHECK(replayed.bad_reports == 0);
  const double x_res_m = 0.2 / static_cast<double>(levels(pen[HidPenRole::X]) - 1);
  const double y_res_m = 0.12 / static_cast<double>(levels(pen[HidPenRole::Y]) - 1);
  const double depth_res_m = t.pressure_levels > 0 ? 0.02 / static_cast<double>(t.pressure_levels - 1) : 0.0;
  int cutting = 0;
  for (const PoseSample& p : replayed.poses) {
    const PoseSample& want = source(poses, p.time_s);
    if (want.buttons == 0) continue;
    ++cutting;
    CHECK(p.buttons == 1u);
    CHECK(std::abs(p.tip_m.x() - want.tip_m.x()) <= x_res_m + 1e-9);
    CHECK(std::abs(p.tip_m.y() - want.tip_m.y()) <= y_res_m + 1e-9);
    if (t.pressure_levels > 0)
      CHECK(std::abs(p.tip_m.z() - want.tip_m.z()) <= depth_res_m + 1e-9);
    else
      CHECK(p.tip_m.z() == Approx(0.05 - mapping.pen.tip_depth_m));
    const Eigen::Vector3d axis = p.orientation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d want_axis = t.tilt ? want.orientation * Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitZ();
    CHECK(std::acos(std::min(1.0, axis.dot(want_axis))) < 0.03);
  }
  CHECK(cutting == 161 * static_cast<int>(pen.layouts().size()));
  REQUIRE_FALSE(replayed.poses.empty());
  CHECK(replayed.poses.back().buttons == 0u);  // the pen left: lifted, or hovering where it was
  CHECK(replayed.poses.back().tip_m.z() == Approx(0.05 + (t.in_range ? mapping.pen.lift_m : mapping.pen.hover_m)));
}

void checkTablet(const Tablet& t) {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(t.file));
  if (t.report_id < 0) return checkNotPen(d, t);
  const HidPenSearch search = findHidPen(d);
  INFO(search.reason);
  REQUIRE(search.pen.has_value());
  CHECK(chooseHidProfile(d).kind == HidProfileKind::Pen);
  CHECK(search.reason.rfind("pen: input report " + std::to_string(t.report_id) + " (" + t.path, 0) == 0);
  checkFound(*search.pen, t);
  checkRoundTrip(*search.pen, t);
}

// Every descriptor in scenarios/hid/descriptors/, what it is. A new file there without a row fails the
// "every descriptor has a case" test.
const Tablet kTablets[] = {
    {"3dconnexion_spacenavigator_046d_c626.txt", 0x046d, 0xc626, -1, "6-dof (Multi-axis Controller", 0, false, false,
     false},
    {"atmel_03eb_8409.txt", 0x03eb, 0x8409, 3, "Usage 0x000d:0x0000 > Stylus", 255, false, false, true},
    {"atmel_03eb_840b.txt", 0x03eb, 0x840b, 3, "Pen > Stylus", 255, false, false, true},
    {"egalax_0eef_7224.txt", 0x0eef, 0x7224, 2, "Touch Screen > Stylus", 0, false, false, true},
    {"egalax_0eef_72fa.txt", 0x0eef, 0x72fa, 2, "Touch Screen > Stylus", 0, false, false, true},
    {"egalax_0eef_7336.txt", 0x0eef, 0x7336, 2, "Touch Screen > Stylus", 0, false, false, true},
    {"egalax_0eef_7337.txt", 0x0eef, 0x7337, 2, "Touch Screen > Stylus", 0, false, false, true},
    {"egalax_0eef_73f4.txt", 0x0eef, 0x73f4, 2, "Touch Screen > Stylus", 0, false, false, true},
    {"elan_04f3_2a49.txt", 0x04f3, 0x2a49, 7, "Pen > Stylus", 4097, false, false, true},
    {"goodix_27c6_0e00.txt", 0x27c6, 0x0e00, 8, "Pen > Stylus", 4096, true, true, true},
    {"goodix_gxtp_27c6_0113.txt", 0x27c6, 0x0113, 8, "Pen > Stylus", 4096, true, false, true},
    {"huion_kamvas_pro_19_256c_006b.txt", 0x256c, 0x006b, 10, "Pen > Stylus", 16384, true, false, true},
    {"irtouch_6615_0070.txt", 0x6615, 0x0070, 32, "Pen > Stylus", 0, false, false, false},
    {"nexio_1870_0100.txt", 0x1870, 0x0100, 5, "Pen > Stylus", 0, false, false, true},
    {"nexio_1870_010d.txt", 0x1870, 0x010d, 5, "Pen > Stylus", 0, false, false, true},
    {"ntrig_1b96_0c01.txt", 0x1b96, 0x0c01, 1, "Pen > Stylus", 257, false, false, true},
    {"ntrig_1b96_0c03.txt", 0x1b96, 0x0c03, 1, "Pen > Stylus", 257, false, false, true},
    {"ntrig_1b96_0f00.txt", 0x1b96, 0x0f00, 1, "Pen > Stylus", 257, false, false, true},
    {"ntrig_1b96_0f04.txt", 0x1b96, 0x0f04, 1, "Pen > Stylus", 257, false, false, true},
    {"smart_0b8c_0092.txt", 0x0b8c, 0x0092, 7, "Pen > Stylus", 16, false, false, false},
    {"wacom_dth2452_touch_056a_0383.txt", 0x056a, 0x0383, -1, "touch (Touch Screen", 0, false, false, false},
    {"wacom_opaque_ctl_tablet_056a_9999.txt", 0x056a, 0x9999, 16, "Digitizer > Stylus", 4096, false, false, true},
    {"wacom_opaque_tablet_056a_9999.txt", 0x056a, 0x9999, 1, "Digitizer > Stylus", 0, false, false, true},
    {"wacom_pth460_v105_056a_0392.txt", 0x056a, 0x0392, 16, "Digitizer > Stylus", 8192, true, true, true},
    {"wacom_pth660_intuos_pro_m_056a_0357.txt", 0x056a, 0x0357, 16, "Digitizer > Stylus", 8192, true, true, true},
    {"wacom_pth660_v150_056a_0357.txt", 0x056a, 0x0357, 16, "Digitizer > Stylus", 8192, true, true, true},
    {"wacom_pth860_v145_056a_0358.txt", 0x056a, 0x0358, 16, "Digitizer > Stylus", 8192, true, true, true},
    {"wacom_pth860_v150_056a_0358.txt", 0x056a, 0x0358, 16, "Digitizer > Stylus", 8192, true, true, true},
    {"xppen_artist24_28bd_093a.txt", 0x28bd, 0x093a, 7, "Pen > Stylus", 8192, true, false, true},
    {"xppen_artist_pro16_gen2_28bd_095b.txt", 0x28bd, 0x095b, 7, "Pen > Stylus", 16384, true, false, true},
};

const Tablet& tablet(const char* file) {
  const auto it = std::find_if(std::begin(kTablets), std::end(kTablets),
                               [&](const Tablet& t) { return std::string(t.file) == file; });
  REQUIRE(it != std::end(kTablets));
  return *it;
}

// Pen (0x0D:0x02) application, report 1: In Range, Tip Switch, 6 bits padding, Tip Pressure (8 bits); report 2:
// X, Y (16 bits, 0..20000), both in one Stylus physical collection.
const std::vector<std::uint8_t> kSplitPen = {0x05, 0x0d, 0x09, 0x02, 0xa1, 0x01, 0x09, 0x20, 0xa1, 0x00, 0x85, 0x01,
                                             0x09, 0x32, 0x09, 0x42, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x02,
                                             0x81, 0x02, 0x95, 0x06, 0x81, 0x03, 0x09, 0x30, 0x26, 0xff, 0x00, 0x75,
                                             0x08, 0x95, 0x01, 0x81, 0x02, 0x85, 0x02, 0x05, 0x01, 0x09, 0x30, 0x09,
                                             0x31, 0x26, 0x20, 0x4e, 0x75, 0x10, 0x95, 0x02, 0x81, 0x02, 0xc0, 0xc0};

}  // namespace

#define TABLET_CASE(file)                                                                                             \
  TEST_CASE("hid_pen: " file ": found as the kernel maps it, and a stroke through it comes back", "[devices][hid]") { \
    checkTablet(tablet(file));                                                                                        \
  }

TABLET_CASE("3dconnexion_spacenavigator_046d_c626.txt")
TABLET_CASE("atmel_03eb_8409.txt")
TABLET_CASE("atmel_03eb_840b.txt")
TABLET_CASE("egalax_0eef_7224.txt")
TABLET_CASE("egalax_0eef_72fa.txt")
TABLET_CASE("egalax_0eef_7336.txt")
TABLET_CASE("egalax_0eef_7337.txt")
TABLET_CASE("egalax_0eef_73f4.txt")
TABLET_CASE("elan_04f3_2a49.txt")
TABLET_CASE("goodix_27c6_0e00.txt")
TABLET_CASE("goodix_gxtp_27c6_0113.txt")
TABLET_CASE("huion_kamvas_pro_19_256c_006b.txt")
TABLET_CASE("irtouch_6615_0070.txt")
TABLET_CASE("nexio_1870_0100.txt")
TABLET_CASE("nexio_1870_010d.txt")
TABLET_CASE("ntrig_1b96_0c01.txt")
TABLET_CASE("ntrig_1b96_0c03.txt")
TABLET_CASE("ntrig_1b96_0f00.txt")
TABLET_CASE("ntrig_1b96_0f04.txt")
TABLET_CASE("smart_0b8c_0092.txt")
TABLET_CASE("wacom_dth2452_touch_056a_0383.txt")
TABLET_CASE("wacom_opaque_ctl_tablet_056a_9999.txt")
TABLET_CASE("wacom_opaque_tablet_056a_9999.txt")
TABLET_CASE("wacom_pth460_v105_056a_0392.txt")
TABLET_CASE("wacom_pth660_intuos_pro_m_056a_0357.txt")
TABLET_CASE("wacom_pth660_v150_056a_0357.txt")
TABLET_CASE("wacom_pth860_v145_056a_0358.txt")
TABLET_CASE("wacom_pth860_v150_056a_0358.txt")
TABLET_CASE("xppen_artist24_28bd_093a.txt")
TABLET_CASE("xppen_artist_pro16_gen2_28bd_095b.txt")

TEST_CASE("hid_pen: every descriptor shipped in scenarios/hid/descriptors has a case above", "[devices][hid]") {
  std::set<std::string> shipped, cased;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(INCISE_SCENARIOS_DIR) + "/hid/descriptors"))
    if (entry.path().extension() == ".txt") shipped.insert(entry.path().filename().string());
  for (const Tablet& t : kTablets) cased.insert(t.file);
  CHECK(shipped == cased);
  CHECK(shipped.size() == 30);
}

TEST_CASE("hid_pen: devices/README.md's table of tablets says what the pen profile reads from each", "[devices][hid]") {
  std::ifstream in(std::string(INCISE_DEVICES_DIR) + "/README.md");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  for (const Tablet& t : kTablets) {
    INFO(t.file);
    const std::string start = std::string("| `") + t.file + "` |";
    const auto row =
        std::find_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.rfind(start, 0) == 0; });
    REQUIRE(row != lines.end());
    std::vector<std::string> cells;
    std::stringstream cut(row->substr(1));
    for (std::string cell; std::getline(cut, cell, '|');) {
      const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
      cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
    }
    REQUIRE(cells.size() == 11);
    const HidDescriptor descriptor = parseHidDescriptor(loadShippedDescriptor(t.file));  // the pen points into it
    const auto search = findHidPen(descriptor);
    if (!search.pen) {
      CHECK(cells[4].rfind("no pen: ", 0) == 0);
      CHECK(cells[10] == "no");
      continue;
    }
    const HidPenSummary s = summarizeHidPen(*search.pen);
    CHECK(std::vector<std::string>(cells.begin() + 4, cells.end()) ==
          std::vector<std::string>{s.xy, s.pressure, s.tilt, s.twist, s.buttons, s.in_range, "yes"});
  }
}

TEST_CASE("hid_pen: a pen spread over two reports is read from both, its last values held", "[devices][hid]") {
  const HidDescriptor d = parseBytes(kSplitPen);
  const HidPenSearch search = findHidPen(d);
  REQUIRE(search.pen.has_value());
  CHECK(search.reason ==
        "pen: input reports 1, 2 (Pen > Stylus, collection at descriptor byte 8): X, Y, Tip Switch, Tip Pressure, "
        "In Range");
  REQUIRE(search.pen->layouts().size() == 2);
  HidMapping mapping = tabletOverArea();
  mapping.pen.dead_band = 0.0;
  const auto profile = makeHidProfile(d, {}, mapping);
  PoseSample pose;
  // The position first: the pen has not said it is in range nor touching: hovering there.
  REQUIRE(profile->update(std::vector<std::uint8_t>{2, 0x10, 0x27, 0x00, 0x00}, 0.0, pose));  // X 10000, Y 0
  CHECK(pose.tip_m.x() == Approx(0.2));
  CHECK(pose.tip_m.z() == Approx(0.05 + mapping.pen.hover_m));
  // In range, tip down, full pressure: the position held from report 2.
  REQUIRE(profile->update(std::vector<std::uint8_t>{1, 0x03, 0xff}, 0.01, pose));
  CHECK(pose.tip_m.x() == Approx(0.2));
  CHECK(pose.tip_m.y() == Approx(0.2));
  CHECK(pose.tip_m.z() == Approx(0.05 - 0.02));
  CHECK(pose.buttons == 1u);
  // Moving: the tip and pressure held from report 1.
  REQUIRE(profile->update(std::vector<std::uint8_t>{2, 0x20, 0x4e, 0x20, 0x4e}, 0.02, pose));  // 20000, 20000
  CHECK(pose.tip_m.x() == Approx(0.3));
  CHECK(pose.tip_m.y() == Approx(0.08));
  CHECK(pose.tip_m.z() == Approx(0.05 - 0.02));
  // Out of range: lifted above the last position.
  REQUIRE(profile->update(std::vector<std::uint8_t>{1, 0x00, 0x00}, 0.03, pose));
  CHECK(pose.tip_m.z() == Approx(0.05 + mapping.pen.lift_m));
  CHECK(pose.buttons == 0u);
  // The generator writes both reports per pose and the replay gives the stroke back.
  HidRecordedDevice device;
  device.descriptor = kSplitPen;
  const auto poses = stroke();
  const HidRecording recording = synthesizeHidRecording(device, mapping, poses);
  CHECK(recording.reports.size() == 2 * (201 + 1));
  const HidRecordingPoses replayed = posesFromHidRecording(recording, 0, mapping);
  CHECK(replayed.same_time == 0);
  // Report 1 comes first in each period, report 2 half a period later: the poses report 2 makes carry the
  // period's position; those report 1 makes, the previous period's.
  double worst_m = 0.0;
  int checked = 0;
  for (const PoseSample& p : replayed.poses) {
    const bool from_report_2 = std::llround(p.time_s * 1e6) % 5000 == 2500;
    if (!from_report_2 || p.buttons != 1u || source(poses, p.time_s).buttons != 1u) continue;
    ++checked;
    worst_m = std::max(worst_m, (p.tip_m.head<2>() - source(poses, p.time_s).tip_m.head<2>()).norm());
  }
  CHECK(checked == 161);
  CHECK(worst_m < 2e-5);
}

TEST_CASE("hid_pen: what is missing, and where the rest is", "[devices][hid]") {
  // A Stylus with In Range, X, Y, and no tip: the message names the tool, its usages' places and the lack.
  std::vector<std::uint8_t> no_tip = kSplitPen;
  no_tip[15] = 0x32;  // Tip Switch -> In Range again (ignored: the first In Range is read)
  no_tip[31] = 0x3d;  // Tip Pressure -> X Tilt
  const HidPenSearch a = findHidPen(parseBytes(no_tip));
  CHECK_FALSE(a.pen.has_value());
  CHECK(a.reason ==
        "no pen: the pen of input reports 1, 2 (Pen > Stylus, collection at descriptor byte 8) has X at report 2 "
        "byte 1, Y at report 2 byte 3, In Range at report 1 byte 1 bit 0, X Tilt at report 1 byte 2 but no Tip "
        "Switch, Touch or Tip Pressure");
  CHECK(chooseHidProfile(parseBytes(no_tip)).reason.rfind("no profile: " + a.reason, 0) == 0);
  // X and Y relative (a mouse's axes in a pen collection): named as relative, with their place.
  std::vector<std::uint8_t> relative = kSplitPen;
  relative[57] = 0x06;  // report 2's Input (Data,Var,Abs) -> (Data,Var,Rel)
  const HidPenSearch b = findHidPen(parseBytes(relative));
  CHECK_FALSE(b.pen.has_value());
  CHECK(b.reason.find("but no an absolute X (X at report 2 byte 1 is relative) and an absolute Y (Y at report 2 "
                      "byte 3 is relative)") != std::string::npos);
}

TEST_CASE("hid_pen: a touch screen is touch, a descriptor of feature reports only has no input", "[devices][hid]") {
  const HidDescriptor dth = parseHidDescriptor(loadShippedDescriptor("wacom_dth2452_touch_056a_0383.txt"));
  const HidPenSearch touch = findHidPen(dth);
  CHECK_FALSE(touch.pen.has_value());
  CHECK(describeHidTools(touch.tools) ==
        "touch (Touch Screen, input report 12); touch (Touch Screen > Finger x5, input report 12); other (Vendor "
        "0xff00:0x0001, input report 19)");
  const HidPenSearch nothing = findHidPen(parseBytes(
      {0x05, 0x01, 0x09, 0x02, 0xa1, 0x01, 0x15, 0x00, 0x25, 0x01, 0x75, 0x08, 0x95, 0x01, 0xb1, 0x02, 0xc0}));
  CHECK(nothing.reason == "no pen: the descriptor has no input fields");
}

TEST_CASE("hid_pen: what the pen reads, in words", "[devices][hid]") {
  const auto summary = [](const char* file) {
    return summarizeHidPen(*findHidPen(parseHidDescriptor(loadShippedDescriptor(file))).pen);
  };
  const HidPenSummary wacom = summary(kWacomDescriptor);
  CHECK(wacom.xy == "X 0..44800, Y 0..29600 (224 x 148 mm)");
  CHECK(wacom.pressure == "8192 levels (16-bit field)");
  CHECK(wacom.tilt == "X/Y -64..63 deg");
  CHECK(wacom.twist == "-180..179 deg");
  CHECK(wacom.buttons == "Barrel Switch, Secondary Barrel Switch, Eraser, Invert");
  CHECK(wacom.in_range == "yes");
  const HidPenSummary huion = summary("huion_kamvas_pro_19_256c_006b.txt");
  CHECK(huion.xy == "X 0..32767, Y 0..32767 (unit in^3: not a length)");
  CHECK(huion.tilt == "X/Y -90..90 (no angle unit: read as degrees)");
  const HidPenSummary nexio = summary("nexio_1870_0100.txt");
  CHECK(nexio.pressure == "none (tip switch only)");
  CHECK(nexio.twist == "none");
  CHECK(nexio.buttons == "none");
}
