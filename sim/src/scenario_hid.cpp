#include "scenario_hid.h"

#include <charconv>

namespace incise::sim::detail {
namespace {

using devices::PenMapping;
using devices::SixDofMapping;

void readPen(const JsonReader& r, PenMapping& m) {
  m.origin_m = r.vector("origin_m", m.origin_m);
  m.x_edge_m = r.vector("x_edge_m", m.x_edge_m);
  m.y_edge_m = r.vector("y_edge_m", m.y_edge_m);
  if (m.x_edge_m.cross(m.y_edge_m).norm() < 1e-12) r.fail("must not be parallel to x_edge_m (or zero)", "y_edge_m");
  m.hover_m = r.number("hover_m", m.hover_m, 0.0, 1.0);
  m.lift_m = r.number("lift_m", m.lift_m, 0.0, 1.0);
  m.dead_band = r.number("dead_band", m.dead_band, 0.0, 0.99);
  m.curve = r.number("curve", m.curve, 0.1, 10.0);
  m.max_depth_m = r.number("max_depth_m", m.max_depth_m, 1e-5, 1.0);
  m.tip_depth_m = r.number("tip_depth_m", m.tip_depth_m, 0.0, 1.0);
  m.cut_on = r.choice("cut_on", "tip_switch", {"tip_switch", "pressure"}) == "pressure" ? PenMapping::CutOn::Pressure
                                                                                        : PenMapping::CutOn::TipSwitch;
  m.cut_threshold = r.number("cut_threshold", m.cut_threshold, 0.0, 1.0);
  m.yaw_deg = r.number("yaw_deg", m.yaw_deg, -360.0, 360.0);
  m.use_tilt = r.boolean("use_tilt", m.use_tilt);
  m.use_twist = r.boolean("use_twist", m.use_twist);
}

void readSixDof(const JsonReader& r, SixDofMapping& m) {
  m.start_m = r.vector("start_m", m.start_m);
  const auto q = r.numbers("start_orientation", 4, {1.0, 0.0, 0.0, 0.0});
  m.start_orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  if (std::abs(m.start_orientation.norm() - 1.0) > 1e-6)
    r.fail("must be a unit quaternion [w, x, y, z]", "start_orientation");
  const auto a = r.numbers("device_to_tissue", 9, {1, 0, 0, 0, 1, 0, 0, 0, 1});
  m.device_to_tissue = Eigen::Matrix3d{{a[0], a[1], a[2]}, {a[3], a[4], a[5]}, {a[6], a[7], a[8]}};
  if (std::abs(m.device_to_tissue.determinant()) < 1e-9)
    r.fail("must be invertible (row-major 3x3)", "device_to_tissue");
  m.max_speed_m_per_s = r.number("max_speed_m_per_s", m.max_speed_m_per_s, 1e-6, 100.0);
  m.max_rate_rad_per_s = r.number("max_rate_rad_per_s", m.max_rate_rad_per_s, 1e-6, 1000.0);
  m.dead_zone = r.number("dead_zone", m.dead_zone, 0.0, 0.99);
  m.workspace_min_m = r.vector("workspace_min_m", m.workspace_min_m);
  m.workspace_max_m = r.vector("workspace_max_m", m.workspace_max_m);
  if ((m.workspace_max_m - m.workspace_min_m).minCoeff() <= 0.0)
    r.fail("must be above workspace_min_m in x, y and z", "workspace_max_m");
  const std::string axes = r.choice("axes", "auto", {"auto", "absolute", "relative"});
  m.axes = axes == "absolute"   ? SixDofMapping::Axes::Absolute
           : axes == "relative" ? SixDofMapping::Axes::Relative
                                : SixDofMapping::Axes::Auto;
  m.m_per_count = r.number("m_per_count", m.m_per_count, 0.0, 1.0);
  m.rad_per_count = r.number("rad_per_count", m.rad_per_count, 0.0, 1.0);
  m.up = r.vector("up", m.up);
  if (m.up.norm() == 0.0) r.fail("must not be zero", "up");
  m.lift_m = r.number("lift_m", m.lift_m, 0.0, 1.0);
}

std::uint16_t hexId(const JsonReader& r, const char* key) {
  const std::string text = r.text(key, nullptr);
  unsigned value = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value, 16);
  if (text.empty() || text.size() > 4 || result.ec != std::errc() || result.ptr != text.data() + text.size())
    r.fail("must be 1-4 hex digits (\"056a\"), got \"" + text + "\"", key);
  return static_cast<std::uint16_t>(value);
}

HidSynthesis readSynthesis(const JsonReader& r) {
  HidSynthesis s;
  s.given = true;
  s.from = r.file("from");
  s.descriptor = r.file("descriptor");
  s.name = r.text("name", "");
  s.vid = hexId(r, "vid");
  s.pid = hexId(r, "pid");
  s.rate_hz = r.number("rate_hz", s.rate_hz, 1.0, 10000.0);
  return s;
}

}  // namespace

HidRecordingSource readHidRecordingSource(const JsonReader& source) {
  HidRecordingSource hid;
  if (source.has("synthesis")) hid.synthesis = readSynthesis(source.child("synthesis"));
  // A synthesised recording may not exist yet: `incise hid synth` makes it.
  hid.path = hid.synthesis.given ? source.outputPath("path") : source.file("path");
  hid.device = source.integer("device", 0, 0, 255);
  if (source.has("pen") && source.has("six_dof")) source.fail("give \"pen\" or \"six_dof\", not both", "pen");
  readPen(source.child("pen"), hid.mapping.pen);
  readSixDof(source.child("six_dof"), hid.mapping.six_dof);
  return hid;
}

}  // namespace incise::sim::detail
