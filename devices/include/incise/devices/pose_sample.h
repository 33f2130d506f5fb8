// One reading of the tool: when, where the tip is, how the tool is turned, which buttons are down and,
// when the device has a sensor for it, how hard the user presses. The scalpel's direction of travel is
// not part of a sample: the simulation derives it from successive tips.
//
// Units and frames: time_s in seconds on the device's clock (any origin; a trace starts wherever the
// recording started); tip_m in metres in the device's frame (right-handed); orientation maps tool-frame
// vectors into the device's frame and is unit length when it comes from a source; buttons is a bit mask,
// bit i set = button i pressed (bit 0 the primary button); pressure normalised to [0, 1] (0 = none,
// 1 = the device's maximum), std::nullopt when the device has no pressure sensor.
// Threads: a plain value; copy it across threads. Failure: none (no checks here; sources and the trace
// writer validate).
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace incise::devices {

struct PoseSample {
  double time_s = 0.0;
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::uint32_t buttons = 0;
  std::optional<double> pressure;  // normalised 0..1; nullopt = no pressure sensor
};

// Exact comparison of every field, no tolerance (q and -q are different samples; NaN is never equal;
// 0.0 equals -0.0). Cost O(1).
inline bool operator==(const PoseSample& a, const PoseSample& b) {
  return a.time_s == b.time_s && a.tip_m.cwiseEqual(b.tip_m).all() &&
         a.orientation.coeffs().cwiseEqual(b.orientation.coeffs()).all() && a.buttons == b.buttons &&
         a.pressure == b.pressure;
}

}  // namespace incise::devices
