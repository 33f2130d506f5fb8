// Calibrating a pen mapping from presses: presses found in poses (their median position, their pressures),
// the two corners laid onto the target rectangle in either order without flipping it, the dead band and curve
// from the pressure press, the refusals; and the whole path on the shipped calibration recording
// (scenarios/hid/calibrate/pen-wacom.hid, three presses synthesised through a Wacom PTH-660) played by the
// replay transport into a live HidPoseSource.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>
#include <vector>

#include "hid_fixture.h"
#include "incise/devices/hid_pen_calibration.h"
#include "incise/devices/hid_pose_source.h"
#include "incise/devices/replay_transport.h"

using namespace incise::devices;
using namespace incise::test;

namespace {

// A pose of a pen at tablet fractions (fx, fy), the tip down or up, with a pressure or none.
PoseSample at(const PenMapping& m, double t_s, double fx, double fy, bool down, std::optional<double> pressure) {
  PoseSample p;
  p.time_s = t_s;
  p.tip_m = m.origin_m + fx * m.x_edge_m + fy * m.y_edge_m;
  p.buttons = down ? 1u : 0u;
  p.pressure = pressure;
  return p;
}

// Feeds a press: `count` poses down at (fx, fy) with the given pressures (cycled), then one up.
std::vector<PenPress> press(PenPressDetector& detector, const PenMapping& m, double& t_s, double fx, double fy,
                            const std::vector<double>& pressures) {
  std::vector<PenPress> done;
  for (std::size_t k = 0; k < std::max<std::size_t>(pressures.size(), 5); ++k)
    if (detector.add(at(m, t_s += 0.005, fx, fy, true,
                        pressures.empty() ? std::nullopt : std::optional(pressures[k % pressures.size()]))))
      done.push_back(detector.press());
  if (detector.add(at(m, t_s += 0.005, fx, fy, false, std::nullopt))) done.push_back(detector.press());
  return done;
}

Eigen::Vector3d up(const PenMapping& m) { return m.y_edge_m.cross(m.x_edge_m).normalized(); }

class PressSink final : public PoseSink {
 public:
  explicit PressSink(const PenMapping& m) : detector_(m) {}
  bool push(const PoseSample& sample) noexcept override {
    std::lock_guard lock(mutex_);
    if (detector_.add(sample)) presses_.push_back(detector_.press());
    return true;
  }
  std::vector<PenPress> presses() const {
    std::lock_guard lock(mutex_);
    return presses_;
  }

 private:
  mutable std::mutex mutex_;
  PenPressDetector detector_;
  std::vector<PenPress> presses_;
};

}  // namespace

TEST_CASE("hid_pen_calibration: a press is the tip down, at its median place, with its pressures", "[devices][hid]") {
  const PenMapping m = tabletOverArea().pen;
  PenPressDetector detector(m);
  double t = 0.0;
  CHECK_FALSE(detector.add(at(m, t, 0.5, 0.5, false, 0.0)));  // hovering: nothing
  // Landing at (0.41, 0.52), sliding to (0.4, 0.5) and staying: the median is where it stayed.
  CHECK_FALSE(detector.add(at(m, t += 0.005, 0.41, 0.52, true, 0.1)));
  for (int k = 0; k < 6; ++k) CHECK_FALSE(detector.add(at(m, t += 0.005, 0.4, 0.5, true, 0.3)));
  REQUIRE(detector.add(at(m, t += 0.005, 0.4, 0.5, false, std::nullopt)));
  const PenPress& p = detector.press();
  CHECK(p.fx == Approx(0.4));
  CHECK(p.fy == Approx(0.5));
  CHECK(p.pressures == std::vector<double>{0.1, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3});
  CHECK(p.start_s == Approx(0.005));
  CHECK(p.end_s == Approx(0.035));
}

TEST_CASE("hid_pen_calibration: the corners go onto the target's rectangle, in either order, up kept",
          "[devices][hid]") {
  const PenMapping target = tabletOverArea().pen;
  PenPressDetector detector(target);
  double t = 0.0;
  // The opposite corner first, then the near one, then a press ramping from 0.05 to a firm 0.3.
  const auto a = press(detector, target, t, 0.8, 0.7, {0.2});
  const auto b = press(detector, target, t, 0.2, 0.3, {0.2});
  std::vector<double> ramp = {0.05, 0.1, 0.2};
  ramp.insert(ramp.end(), 12, 0.3);
  const auto c = press(detector, target, t, 0.5, 0.5, ramp);
  REQUIRE((a.size() == 1 && b.size() == 1 && c.size() == 1));
  const PenCalibration cal = calibratePen(target, a[0], b[0], &c[0]);
  const PenMapping& m = cal.mapping;
  CHECK((m.origin_m + 0.2 * m.x_edge_m + 0.3 * m.y_edge_m - target.origin_m).norm() < 1e-12);
  CHECK((m.origin_m + 0.8 * m.x_edge_m + 0.7 * m.y_edge_m - (target.origin_m + target.x_edge_m + target.y_edge_m))
            .norm() < 1e-12);
  CHECK((up(m) - up(target)).norm() < 1e-12);
  CHECK(cal.x0 == Approx(0.2));
  CHECK(cal.y1 == Approx(0.7));
  // Pressure: the dead band is the lightest reading, the firm press reaches half of max_depth_m.
  CHECK(m.dead_band == 0.05);
  REQUIRE(cal.firm_pressure.has_value());
  CHECK(*cal.firm_pressure == 0.3);
  CHECK(std::pow((0.3 - 0.05) / (1 - 0.05), m.curve) == Approx(0.5));
  CHECK(m.max_depth_m == target.max_depth_m);  // the rest as the target has it
  CHECK(m.hover_m == target.hover_m);
}

TEST_CASE("hid_pen_calibration: without pressure the dead band and curve stay, bad presses are refused",
          "[devices][hid]") {
  PenMapping target = tabletOverArea().pen;
  target.curve = 1.7;
  PenPressDetector detector(target);
  double t = 0.0;
  const auto a = press(detector, target, t, 0.1, 0.1, {});
  const auto b = press(detector, target, t, 0.9, 0.6, {});
  REQUIRE((a.size() == 1 && b.size() == 1));
  CHECK(a[0].pressures.empty());
  const PenCalibration cal = calibratePen(target, a[0], b[0], nullptr);
  CHECK(cal.mapping.curve == 1.7);
  CHECK(cal.mapping.dead_band == target.dead_band);
  CHECK_FALSE(cal.firm_pressure.has_value());
  // Two presses at nearly the same X: no area.
  const auto near = press(detector, target, t, 0.12, 0.8, {});
  CHECK_THROWS_WITH(calibratePen(target, a[0], near[0], nullptr),
                    "the two corner presses are 2% of the tablet apart in X and 70% in Y: press at opposite corners "
                    "of the area (at least 5% apart in each)");
  // A pressure press that never gets firmer than its lightest reading.
  const auto flat = press(detector, target, t, 0.5, 0.5, {0.2});
  CHECK_THROWS_AS(calibratePen(target, a[0], b[0], &flat[0]), std::invalid_argument);
}

TEST_CASE(
    "hid_pen_calibration: the shipped calibration recording, through the replay transport and the device "
    "thread",
    "[devices][hid][threads]") {
  const HidRecording recording = readHidRecording(std::string(INCISE_SCENARIOS_DIR) + "/hid/calibrate/pen-wacom.hid");
  ReplayTransportOptions options;
  options.real_time = false;
  ReplayTransport transport(recording, 0, options);
  const PenMapping reading = tabletOverArea().pen;
  PressSink sink(reading);
  HidMapping mapping;
  mapping.pen = reading;
  mapping.pen.dead_band = 0.0;
  HidPoseSource source(transport, parseHidDeviceSelector("056a:0357"), mapping, sink);
  source.start();
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (transport.delivered() < transport.reportCount() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  source.stop();
  const auto presses = sink.presses();
  REQUIRE(presses.size() == 3);
  // presses.json presses at pad-pen-wacom's fractions (0.2, 0.3) and (0.8, 0.7), each moving 2 mm (2% of X)
  // along +x, then at the centre moving 3 mm along +y.
  CHECK(presses[0].fx == Approx(0.21).margin(0.005));
  CHECK(presses[0].fy == Approx(0.3).margin(0.001));
  CHECK(presses[1].fx == Approx(0.81).margin(0.005));
  CHECK(presses[1].fy == Approx(0.7).margin(0.001));
  const PenCalibration cal = calibratePen(reading, presses[0], presses[1], &presses[2]);
  CHECK(cal.mapping.dead_band > 0.0);
  CHECK(cal.mapping.dead_band < *cal.firm_pressure);
  CHECK(cal.mapping.curve > 0.1);
  CHECK(cal.mapping.curve < 10.0);
}
