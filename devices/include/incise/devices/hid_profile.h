// Profiles: how a HID device's reports become scalpel poses. A profile is chosen by the usages a
// descriptor declares (chooseHidProfile), never by a VID/PID table; the quirk table (hidQuirks) only
// corrects descriptors known to lie. Two kinds: a pen (hid_pen.h) whose tablet area PenMapping lays over
// the tissue (position control), and a 6-DOF controller that SixDofMapping turns into velocities. Each
// report updates the usages it carries and the pose is made from the last value of each.
//
// Units: metres, radians, seconds; the times are the callers' (a recording's or the steady clock).
// Threads: a profile is owned by one thread (the device thread, or the replay's). Cost: update O(fields
// bound), no allocation. Failure: construction throws HidProfileError when the descriptor has no usable
// pen or 6-DOF report (chooseHidProfile says why); update never throws: a report of a layout the profile
// does not use returns false.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/pose_sample.h"

namespace incise::devices {

// A pen (hid_pen.h: a Stylus, Pen, Digitizer or Light Pen tool, at any depth of collections, on the
// Digitizers page or Wacom's 0xFF0D, with absolute X and Y and Tip Switch, Touch or Tip Pressure, its usages in
// one input report or several). Optional: In Range, Barrel Switch, Secondary Barrel Switch, Eraser, Invert,
// X/Y Tilt, Twist. A value outside its logical range is dropped when its field has a null state, else
// clamped (hid-input's rule). The mapping (PenMapping) puts the tablet's active area onto a rectangle in tissue
// space:
//   surface point  s = origin_m + fx * x_edge_m + fy * y_edge_m,  fx, fy = X, Y as fractions of their
//                  logical ranges (0 at the minimum, 1 at the maximum; 0.5 before the first report);
//   up             u = normalise(y_edge_m x x_edge_m): with x_edge along the tablet's X (to the right) and
//                  y_edge along its Y (towards the user), u points from the tissue towards the pen;
//   tip            s + u * h, where h = hover_m while the pen is in range with the tip up; -depth while the
//                  tip is down, depth = max_depth_m * ((p - dead_band) / (1 - dead_band))^curve for the
//                  normalised pressure p above the dead band (0 below it), or tip_depth_m for a pen without
//                  Tip Pressure; lift_m when the pen leaves range;
//   orientation    the tool's +z along the pen's axis (from X/Y tilt in degrees: tan(tilt_x) along x_edge,
//                  tan(tilt_y) along y_edge, 1 along u; straight up without tilt), its +x (the blade's edge) at
//                  yaw_deg + twist from x_edge towards y_edge, made perpendicular to the axis; an angle field
//                  without an angle unit is read as degrees (hid_pen.h);
//   buttons        bit 0 cutting (the tip switch is down, or the pressure is above cut_threshold with
//                  cut_on = Pressure and a pen that has pressure), bit 1 barrel, bit 2 secondary barrel, bit 3
//                  eraser or invert; all 0 out of range. pressure = p (nullopt when the pen has none).
struct PenMapping {
  Eigen::Vector3d origin_m{0.0, 0.0, 0.0};    // tissue point under the tablet's (X min, Y min) corner
  Eigen::Vector3d x_edge_m{0.2, 0.0, 0.0};    // to the (X max, Y min) corner
  Eigen::Vector3d y_edge_m{0.0, -0.15, 0.0};  // to the (X min, Y max) corner
  double hover_m = 0.01;                      // tip above the area while in range, tip up
  double lift_m = 0.03;                       // ... out of range, or the device gone
  double dead_band = 0.02;                    // normalised pressure that makes no depth
  double curve = 1.0;                         // exponent of the pressure -> depth curve
  double max_depth_m = 0.01;                  // depth below the area at full pressure
  double tip_depth_m = 0.004;                 // ... while the tip is down, for a pen without Tip Pressure
  enum class CutOn : std::uint8_t { TipSwitch, Pressure } cut_on = CutOn::TipSwitch;
  double cut_threshold = 0.05;  // normalised pressure (CutOn::Pressure)
  double yaw_deg = 0.0;         // the blade's edge at twist 0, from x_edge towards y_edge
  bool use_tilt = true, use_twist = true;
};

// A 6-DOF controller (Generic Desktop X, Y, Z, Rx, Ry, Rz input fields, in one report or several as on the
// SpaceNavigator: translation, rotation and buttons each in its own report). Velocity control (SixDofMapping):
// each axis's deflection d = logical / max(|logical_min|, |logical_max|), dead_zone removed and rescaled
// (d' = sign(d) (|d| - dead_zone) / (1 - dead_zone), 0 inside it), times max_speed_m_per_s or
// max_rate_rad_per_s, turned into tissue axes by device_to_tissue; the tip and orientation integrate the
// velocities held since the previous report (zero-order hold, over the reports' time stamps), the tip is
// clamped to the workspace box; a reconnected device resumes from the last pose with zero velocity.
// `lifted` moves the tip lift_m along `up` with no buttons. Relative axes (a device whose axes really report motion counts) add
// logical * m_per_count (rad_per_count) per report instead. Buttons: Button page usage n -> bit n - 1.
struct SixDofMapping {
  Eigen::Vector3d start_m = Eigen::Vector3d::Zero();  // tip at the first report
  Eigen::Quaterniond start_orientation = Eigen::Quaterniond::Identity();
  Eigen::Matrix3d device_to_tissue = Eigen::Matrix3d::Identity();  // device axes -> tissue axes
  double max_speed_m_per_s = 0.05;                                 // at full deflection
  double max_rate_rad_per_s = 1.0;
  double dead_zone = 0.05;  // fraction of full deflection
  Eigen::Vector3d workspace_min_m{-1.0, -1.0, -1.0}, workspace_max_m{1.0, 1.0, 1.0};
  enum class Axes : std::uint8_t { Auto, Absolute, Relative } axes = Axes::Auto;  // Auto: descriptor + quirks
  double m_per_count = 1e-5, rad_per_count = 1e-4;                                // relative axes
  Eigen::Vector3d up{0.0, 0.0, 1.0};  // tissue direction away from the tissue: where `lifted` moves the tip
  double lift_m = 0.03;
};

struct HidMapping {
  PenMapping pen;
  SixDofMapping six_dof;
};

struct HidDeviceId {
  std::uint16_t vid = 0, pid = 0;
};

enum class HidProfileKind : std::uint8_t { None, Pen, SixDof };
const char* toString(HidProfileKind kind);

// Quirks (hidQuirks): a descriptor that declares its axes Relative although they are absolute deflections —
// 3Dconnexion SpaceNavigator (046d:c626) and SpaceTraveler (046d:c623), fixed for the same reason by
// Linux's hid-lg and by the udev-hid-bpf SpaceNavigator fix. An unlisted device with the same lie is read
// as relative: it still moves, at a speed that depends on its report rate instead of its deflection;
// SixDofMapping::axes = Absolute fixes it from the scenario.
struct HidQuirk {
  HidDeviceId id;
  bool axes_absolute = false;  // axes declared Relative are absolute deflections
  const char* why;
};
std::span<const HidQuirk> hidQuirks();
const HidQuirk* findHidQuirk(HidDeviceId id);

struct HidProfileChoice {
  HidProfileKind kind = HidProfileKind::None;
  std::string reason;  // why this profile, or why none ("no Digitizers application with X, Y and ...")
};
HidProfileChoice chooseHidProfile(const HidDescriptor& descriptor, HidDeviceId id = {});

class HidProfileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class HidProfile {
 public:
  virtual ~HidProfile();
  HidProfile(const HidProfile&) = delete;
  HidProfile& operator=(const HidProfile&) = delete;

  // One raw report as hid_read returns it, at time_s: true and `pose` filled when the report moved the
  // tool (a report of another layout, too short, or of an undeclared ID: false). Never throws.
  virtual bool update(std::span<const std::uint8_t> raw, double time_s, PoseSample& pose) noexcept = 0;
  // The pose that says "no tool": lifted above the last position, no buttons, no pressure.
  virtual PoseSample lifted(double time_s) const noexcept = 0;
  // Back to the state before the first report (a device reconnected).
  virtual void reset() noexcept = 0;
  virtual HidProfileKind kind() const noexcept = 0;

 protected:
  HidProfile() = default;
};

// The profile chooseHidProfile picks, bound to the descriptor (which must outlive it). Throws
// HidProfileError with chooseHidProfile's reason when there is none.
std::unique_ptr<HidProfile> makeHidProfile(const HidDescriptor& descriptor, HidDeviceId id, const HidMapping& mapping);

// The inverse of the pen mapping, for the generator of recordings: the tablet fractions (fx, fy), the
// pressure (0..1, or nullopt when the pose is not below the area), the X/Y tilt and twist (degrees) that
// make the pose. Poses above the area come out as hovering.
struct PenReading {
  double fx = 0.0, fy = 0.0;
  std::optional<double> pressure;
  double tilt_x_deg = 0.0, tilt_y_deg = 0.0, twist_deg = 0.0;
};
PenReading penReadingFor(const PenMapping& mapping, const PoseSample& pose);

}  // namespace incise::devices
