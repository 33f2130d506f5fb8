// Profiles: chosen by usages, pens mapped onto the tissue as PenMapping documents, 6-DOF velocity control
// integrated over the reports' times, and the pen mapping's inverse (the generator's) undoing it.
#include <catch2/catch.hpp>

#include <cmath>

#include "hid_fixture.h"
#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"

using namespace incise::devices;
using namespace incise::test;

namespace {

constexpr std::uint32_t kX = hidUsage(0x01, 0x30), kY = hidUsage(0x01, 0x31);
constexpr std::uint32_t kTip = hidUsage(0x0D, 0x42), kInRange = hidUsage(0x0D, 0x32);
constexpr std::uint32_t kPressure = hidUsage(0x0D, 0x30), kBarrel = hidUsage(0x0D, 0x44);
constexpr std::uint32_t kTiltX = hidUsage(0x0D, 0x3D), kTiltY = hidUsage(0x0D, 0x3E);

PenMapping testMapping() {
  PenMapping m;
  m.origin_m = {0.1, 0.2, 0.05};
  m.x_edge_m = {0.2, 0.0, 0.0};
  m.y_edge_m = {0.0, -0.1, 0.0};
  m.max_depth_m = 0.02;
  m.dead_band = 0.0;
  return m;
}

// A shipped pen's profile with a mapping, and a report of its pen layout to fill and send.
class ShippedPen {
 public:
  ShippedPen(const char* file, std::uint8_t report_id, const PenMapping& mapping)
      : d_(parseHidDescriptor(loadShippedDescriptor(file))),
        encoder_(d_),
        layout_(*d_.find(HidReportType::Input, report_id)),
        raw(encoder_.blank(layout_)) {
    HidMapping m;
    m.pen = mapping;
    profile_ = makeHidProfile(d_, {}, m);
  }
  ShippedPen(const ShippedPen&) = delete;
  ShippedPen& operator=(const ShippedPen&) = delete;

  void set(std::uint32_t usage, std::int64_t logical) { REQUIRE(encoder_.setLogical(raw, layout_, usage, logical)); }
  PoseSample send(double time_s) {
    PoseSample pose;
    REQUIRE(profile_->update(raw, time_s, pose));
    return pose;
  }
  HidProfile& profile() { return *profile_; }

 private:
  HidDescriptor d_;
  HidReportEncoder encoder_;
  const HidReportLayout& layout_;

 public:
  std::vector<std::uint8_t> raw;

 private:
  std::unique_ptr<HidProfile> profile_;
};

}  // namespace

TEST_CASE("hid_profile: chosen by the usages the descriptor declares", "[devices][hid]") {
  const auto choose = [](const char* name) {
    return chooseHidProfile(parseHidDescriptor(loadShippedDescriptor(name))).kind;
  };
  CHECK(choose(kWacomDescriptor) == HidProfileKind::Pen);
  CHECK(choose(kXpPenDescriptor) == HidProfileKind::Pen);
  CHECK(choose(kSpaceNavigatorDescriptor) == HidProfileKind::SixDof);
  // A plain mouse: X, Y, buttons, no digitizer, no six axes.
  const HidDescriptor mouse =
      parseBytes({0x05, 0x01, 0x09, 0x02, 0xa1, 0x01, 0x05, 0x09, 0x19, 0x01, 0x29, 0x03, 0x15, 0x00, 0x25,
                  0x01, 0x75, 0x01, 0x95, 0x03, 0x81, 0x02, 0x95, 0x05, 0x81, 0x03, 0x05, 0x01, 0x09, 0x30,
                  0x09, 0x31, 0x15, 0x81, 0x25, 0x7f, 0x75, 0x08, 0x95, 0x02, 0x81, 0x06, 0xc0});
  const HidProfileChoice none = chooseHidProfile(mouse);
  CHECK(none.kind == HidProfileKind::None);
  CHECK(none.reason.find("no Stylus, Pen, Digitizer or Light Pen collection; its input is mouse (Mouse") !=
        std::string::npos);
  CHECK_THROWS_AS(makeHidProfile(mouse, {}, {}), HidProfileError);
}

TEST_CASE("hid_profile: an XP-Pen report becomes the documented pose", "[devices][hid]") {
  const PenMapping mapping = testMapping();
  ShippedPen pen(kXpPenDescriptor, 7, mapping);
  pen.set(kInRange, 1);
  pen.set(kTip, 1);
  pen.set(kBarrel, 1);
  pen.set(kX, 32767);  // the right edge
  pen.set(kY, 0);      // the top edge
  pen.set(kPressure, 16383);
  PoseSample pose = pen.send(1.5);
  CHECK(pose.time_s == 1.5);
  CHECK(pose.tip_m.x() == Approx(0.3));
  CHECK(pose.tip_m.y() == Approx(0.2));
  CHECK(pose.tip_m.z() == Approx(0.05 - 0.02));  // full pressure: max depth below the area
  CHECK(pose.buttons == 0b011u);                 // cutting (tip switch) + barrel
  REQUIRE(pose.pressure.has_value());
  CHECK(*pose.pressure == 1.0);
  CHECK((pose.orientation * Eigen::Vector3d::UnitZ()).z() == Approx(1.0));  // no tilt: straight up

  // Tilt: 30 degrees towards +X leans the tool's +z towards +x.
  pen.set(kTiltX, 30);
  pose = pen.send(1.6);
  const Eigen::Vector3d axis = pose.orientation * Eigen::Vector3d::UnitZ();
  CHECK(std::atan2(axis.x(), axis.z()) == Approx(30.0 * M_PI / 180.0));

  // Tip up: hovering, not cutting. Out of range: lifted, no buttons.
  pen.set(kTip, 0);
  pose = pen.send(1.7);
  CHECK(pose.tip_m.z() == Approx(0.05 + mapping.hover_m));
  CHECK((pose.buttons & 1u) == 0);
  pen.set(kInRange, 0);
  pose = pen.send(1.8);
  CHECK(pose.tip_m.z() == Approx(0.05 + mapping.lift_m));
  CHECK(pose.buttons == 0);
  // A report of another ID, or a short one, moves nothing.
  pen.raw[0] = 3;
  CHECK_FALSE(pen.profile().update(pen.raw, 1.9, pose));
  pen.raw[0] = 7;
  pen.raw.pop_back();
  CHECK_FALSE(pen.profile().update(pen.raw, 1.9, pose));
}

TEST_CASE("hid_profile: the pen mapping's inverse undoes it (Wacom, with twist)", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(kWacomDescriptor));
  HidMapping mapping;
  mapping.pen = testMapping();
  mapping.pen.curve = 1.5;
  mapping.pen.dead_band = 0.05;
  const auto profile = makeHidProfile(d, {0x056a, 0x0357}, mapping);
  const HidReportEncoder encoder(d);
  const HidReportLayout& layout = *d.find(HidReportType::Input, 0x10);
  PoseSample target;
  target.tip_m = {0.17, 0.16, 0.05 - 0.007};
  target.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                                          Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  const PenReading reading = penReadingFor(mapping.pen, target);
  REQUIRE(reading.pressure.has_value());
  auto raw = encoder.blank(layout);
  encoder.setLogical(raw, layout, hidUsage(0xFF0D, 0x32), 1);  // in range, on Wacom's page
  encoder.setLogical(raw, layout, hidUsage(0xFF0D, 0x42), 1);  // tip switch
  const auto& x = *std::find_if(layout.fields.begin(), layout.fields.end(),
                                [](const HidField& f) { return hidEquivalentUsage(f.usageOf(0)) == kX; });
  encoder.setLogical(raw, layout, x.usages[0], std::llround(reading.fx * static_cast<double>(x.logical_max)));
  encoder.setLogical(raw, layout, hidUsage(0xFF0D, 0x0131), std::llround(reading.fy * 29600));
  encoder.setLogical(raw, layout, hidUsage(0xFF0D, 0x30), std::llround(*reading.pressure * 8191));
  encoder.setPhysical(raw, layout, hidUsage(0xFF0D, 0x3D), reading.tilt_x_deg);
  encoder.setPhysical(raw, layout, hidUsage(0xFF0D, 0x3E), reading.tilt_y_deg);
  encoder.setPhysical(raw, layout, hidUsage(0xFF0D, 0x41), reading.twist_deg);
  PoseSample pose;
  REQUIRE(profile->update(raw, 0.0, pose));
  // Within the tablet's resolution: 5 um in x and y, a pressure step in depth, a degree in tilt and 0.2 in twist.
  CHECK((pose.tip_m - target.tip_m).norm() < 2e-5);
  CHECK(pose.orientation.angularDistance(target.orientation) < 0.03);
}

TEST_CASE("hid_profile: a tilt without an angle unit is degrees, whatever physical range it inherited",
          "[devices][hid]") {
  // The Huion Kamvas Pro 19's tilts (-90..90) carry the inch^3 unit and 0..2048 physical range its X and Y
  // declared: read through them, 30 would be about 1.4 "degrees".
  ShippedPen pen("huion_kamvas_pro_19_256c_006b.txt", 10, testMapping());
  pen.set(kInRange, 1);
  pen.set(kTip, 1);
  pen.set(kTiltX, 30);
  pen.set(kTiltY, -45);
  const Eigen::Vector3d axis = pen.send(0.0).orientation * Eigen::Vector3d::UnitZ();
  CHECK(axis.x() / axis.z() == Approx(std::tan(30.0 * M_PI / 180.0)));
  // y_edge is -y: a tilt towards +Y leans the axis towards -y.
  CHECK(-axis.y() / axis.z() == Approx(std::tan(-45.0 * M_PI / 180.0)));
}

TEST_CASE("hid_profile: a value outside its range is dropped with a null state, else clamped (hid-input's rule)",
          "[devices][hid]") {
  // The Elan's X and Y declare a null state (81 42): 0xffff, above 18460, means "no position": X is kept.
  ShippedPen elan("elan_04f3_2a49.txt", 7, testMapping());
  elan.set(kInRange, 1);
  elan.set(kX, 9230);
  CHECK(elan.send(0.0).tip_m.x() == Approx(0.2));
  elan.set(kX, 0xffff);
  CHECK(elan.send(0.01).tip_m.x() == Approx(0.2));
  // The Huion's X has no null state: 0xffff, above 32767, is clamped to the right edge.
  ShippedPen huion("huion_kamvas_pro_19_256c_006b.txt", 10, testMapping());
  huion.set(kInRange, 1);
  huion.set(kX, 0xffff);
  CHECK(huion.send(0.0).tip_m.x() == Approx(0.3));
}

TEST_CASE("hid_profile: a pen without pressure cuts at tip_depth_m while its tip is down", "[devices][hid]") {
  PenMapping mapping = testMapping();
  mapping.tip_depth_m = 0.006;
  mapping.cut_on = PenMapping::CutOn::Pressure;  // no pressure to compare: the tip switch decides
  ShippedPen pen("nexio_1870_0100.txt", 5, mapping);
  pen.set(kInRange, 1);
  pen.set(kTip, 1);
  PoseSample pose = pen.send(0.0);
  CHECK(pose.tip_m.z() == Approx(0.05 - 0.006));
  CHECK(pose.buttons == 1u);
  CHECK_FALSE(pose.pressure.has_value());
  pen.set(kTip, 0);
  pose = pen.send(0.01);
  CHECK(pose.tip_m.z() == Approx(0.05 + mapping.hover_m));
  CHECK(pose.buttons == 0u);
}

TEST_CASE("hid_profile: SpaceNavigator velocity control over the reports' times", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(kSpaceNavigatorDescriptor));
  HidMapping mapping;
  mapping.six_dof.start_m = {0.0, 0.0, 0.1};
  mapping.six_dof.max_speed_m_per_s = 0.1;
  mapping.six_dof.dead_zone = 0.1;
  mapping.six_dof.workspace_max_m = {0.05, 1.0, 1.0};
  const HidReportEncoder encoder(d);
  const HidReportLayout& translation = *d.find(HidReportType::Input, 1);
  const HidReportLayout& rotation = *d.find(HidReportType::Input, 2);
  const HidReportLayout& buttons = *d.find(HidReportType::Input, 3);

  SECTION("absolute deflections (the quirk table's SpaceNavigator)") {
    const auto profile = makeHidProfile(d, {0x046d, 0xc626}, mapping);
    auto raw = encoder.blank(translation);
    encoder.setLogical(raw, translation, kX, 350);
    encoder.setLogical(raw, translation, hidUsage(0x01, 0x32), 20);  // inside the dead zone
    PoseSample pose;
    REQUIRE(profile->update(raw, 1.0, pose));
    CHECK(pose.tip_m == Eigen::Vector3d(0.0, 0.0, 0.1));  // the first report sets the velocity only
    auto rot = encoder.blank(rotation);
    encoder.setLogical(rot, rotation, hidUsage(0x01, 0x35), -350);
    REQUIRE(profile->update(rot, 1.2, pose));
    CHECK(pose.tip_m.x() == Approx(0.02));  // 0.1 m/s for 0.2 s
    CHECK(pose.tip_m.z() == 0.1);
    REQUIRE(profile->update(rot, 1.7, pose));
    CHECK(pose.tip_m.x() == 0.05);  // clamped to the workspace
    const double angle = 2.0 * std::atan2(pose.orientation.vec().norm(), pose.orientation.w());
    CHECK(angle == Approx(0.5 * mapping.six_dof.max_rate_rad_per_s));
    CHECK(pose.orientation.z() < 0.0);  // about -z
    auto press = encoder.blank(buttons);
    encoder.setLogical(press, buttons, hidUsage(0x09, 2), 1);
    REQUIRE(profile->update(press, 1.8, pose));
    CHECK(pose.buttons == 0b10u);
    const PoseSample lifted = profile->lifted(1.9);
    CHECK(lifted.buttons == 0);
    CHECK(lifted.tip_m.z() == Approx(pose.tip_m.z() + mapping.six_dof.lift_m));
  }
  SECTION("an unlisted device with the same descriptor is read as relative") {
    const auto profile = makeHidProfile(d, {0x1234, 0x5678}, mapping);
    auto raw = encoder.blank(translation);
    encoder.setLogical(raw, translation, kX, 100);
    PoseSample pose;
    REQUIRE(profile->update(raw, 1.0, pose));
    REQUIRE(profile->update(raw, 5.0, pose));
    CHECK(pose.tip_m.x() == Approx(2 * 100 * mapping.six_dof.m_per_count));  // per report, not per second
  }
}
