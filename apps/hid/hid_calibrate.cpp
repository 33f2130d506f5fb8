// `incise hid calibrate --device SEL [--transport T] [--scenario S] [--timeout SECONDS]`: a pen mapping from
// three presses on a live tablet (hid_pen_calibration.h): at one corner of the part of the tablet to lay
// over the tissue, at the opposite corner, then once as firm as a cut to half of max_depth_m. The area goes
// onto the rectangle the scenario's pen block names (the defaults without --scenario); the result is the whole
// "pen" block, as JSON on stdout, to paste into the scenario's pose_source. Prompts and what was measured go to
// stderr. A pen without pressure needs the two corner presses only.
// Exit: 0 with the block; 2 for bad input (no such device, not a pen: what it lacks and where), and when the
// presses did not come within --timeout (or Ctrl-C) or could not make an area (nothing is printed on stdout).
#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "hid_commands.h"
#include "hid_support.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_pen_calibration.h"
#include "incise/devices/hid_pose_source.h"
#include "incise/sim/pose_queue.h"
#include "scenario_run.h"

namespace incise::apps::hid {
namespace {

using Clock = std::chrono::steady_clock;

// The device the selector names must be there and be a pen: its profile's reason otherwise.
void requirePen(devices::HidTransport& transport, const devices::HidDeviceSelector& selector) {
  for (const devices::HidDeviceInfo& d : transport.enumerate()) {
    if (!selector.matches(d)) continue;
    std::string error;
    const auto bytes = transport.descriptorOf(d, error);
    if (bytes.empty()) failWith("hid calibrate", d.path + ": cannot read the report descriptor: " + error);
    try {
      const devices::HidPenSearch search = devices::findHidPen(devices::parseHidDescriptor(bytes));
      if (!search.pen) failWith("hid calibrate", d.path + " is not a pen: " + search.reason);
    } catch (const devices::HidDescriptorError& e) {
      failWith("hid calibrate", d.path + ": " + e.what());
    }
    return;
  }
  failWith("hid calibrate", "no device " + selector.describe() + " on " + transport.name() + " (see incise hid list)");
}

void prompt(std::size_t press, double max_depth_m) {
  if (press == 0)
    std::fprintf(stderr, "1/3: press the pen down at one corner of the area of the tablet to lay over the tissue\n");
  else if (press == 1)
    std::fprintf(stderr, "2/3: press at the opposite corner\n");
  else
    std::fprintf(stderr, "3/3: press once, as firmly as a cut %g m deep (half of max_depth_m) should be, and hold\n",
                 max_depth_m / 2.0);
}

nlohmann::ordered_json vectorJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Every key of a scenario's pose_source.pen (docs/scenarios.md), in its order.
nlohmann::ordered_json penJson(const devices::PenMapping& m) {
  return {{"pen",
           {{"origin_m", vectorJson(m.origin_m)},
            {"x_edge_m", vectorJson(m.x_edge_m)},
            {"y_edge_m", vectorJson(m.y_edge_m)},
            {"hover_m", m.hover_m},
            {"lift_m", m.lift_m},
            {"dead_band", m.dead_band},
            {"curve", m.curve},
            {"max_depth_m", m.max_depth_m},
            {"tip_depth_m", m.tip_depth_m},
            {"cut_on", m.cut_on == devices::PenMapping::CutOn::Pressure ? "pressure" : "tip_switch"},
            {"cut_threshold", m.cut_threshold},
            {"yaw_deg", m.yaw_deg},
            {"use_tilt", m.use_tilt},
            {"use_twist", m.use_twist}}}};
}

}  // namespace

int runHidCalibrate(const HidCalibrateArgs& a) {
  installStopSignals();
  const LiveDevice live = liveDevice("hid calibrate", a.transport, a.device, a.scenario);
  const devices::PenMapping& target = live.mapping.pen;
  requirePen(*live.transport, live.selector);
  // Poses with the tip down exactly while the tip switch is (or, without one, while any pressure is read).
  devices::HidMapping reading;
  reading.pen = target;
  reading.pen.dead_band = 0.0;
  reading.pen.cut_on = devices::PenMapping::CutOn::TipSwitch;
  sim::PoseQueue<8192> queue;
  devices::HidPoseSource source(*live.transport, live.selector, reading, queue, [](const std::string& m) {
    std::fprintf(stderr, "incise hid calibrate: %s\n", m.c_str());
  });
  devices::PenPressDetector detector(reading.pen);
  std::vector<devices::PenPress> presses;
  std::size_t wanted = 3;
  prompt(0, target.max_depth_m);
  source.start();
  const auto start = Clock::now();
  devices::PoseSample pose;
  while (presses.size() < wanted && !stopRequested() &&
         std::chrono::duration<double>(Clock::now() - start).count() < a.timeout_s) {
    while (presses.size() < wanted && queue.pop(pose)) {
      if (!detector.add(pose)) continue;
      presses.push_back(detector.press());
      const devices::PenPress& p = presses.back();
      std::fprintf(stderr, "  pressed at X %.3f, Y %.3f of the tablet for %.2f s%s\n", p.fx, p.fy, p.end_s - p.start_s,
                   p.pressures.empty() ? " (no pressure)" : "");
      if (presses.size() == 1 && p.pressures.empty()) wanted = 2;  // a pen without pressure
      if (presses.size() < wanted) prompt(presses.size(), target.max_depth_m);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  source.stop();
  if (presses.size() < wanted) {
    std::fprintf(stderr, "incise hid calibrate: %zu of %zu presses from %s in %g s; nothing printed\n", presses.size(),
                 wanted, source.describe().c_str(), a.timeout_s);
    return 2;  // the input did not come
  }
  devices::PenCalibration c;
  try {
    c = devices::calibratePen(target, presses[0], presses[1], wanted == 3 ? &presses[2] : nullptr);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "incise hid calibrate: %s; nothing printed\n", e.what());
    return 2;  // presses that make no rectangle
  }
  std::fprintf(stderr, "area: X %.3f..%.3f, Y %.3f..%.3f of the tablet onto the scenario's rectangle\n", c.x0, c.x1,
               c.y0, c.y1);
  if (c.firm_pressure)
    std::fprintf(stderr, "pressure: dead band %.4f (the lightest reading while down), firm %.4f -> curve %.3f\n",
                 c.mapping.dead_band, *c.firm_pressure, c.mapping.curve);
  std::printf("%s\n", penJson(c.mapping).dump(2).c_str());
  return 0;
}

}  // namespace incise::apps::hid
