#include "incise/devices/hid_synth.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "hid_pen_units.h"
#include "hid_profile_internal.h"
#include "hid_synth_internal.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"

namespace incise::devices {
namespace detail {
PoseSample interpolatePose(std::span<const PoseSample> poses, double t_s, std::size_t& hint) {
  while (hint + 1 < poses.size() && poses[hint + 1].time_s <= t_s) ++hint;
  PoseSample p = poses[hint];
  p.time_s = t_s;
  if (hint + 1 < poses.size()) {
    const PoseSample& b = poses[hint + 1];
    const double a = std::clamp((t_s - poses[hint].time_s) / (b.time_s - poses[hint].time_s), 0.0, 1.0);
    p.tip_m = poses[hint].tip_m + a * (b.tip_m - poses[hint].tip_m);
    p.orientation = poses[hint].orientation.slerp(a, b.orientation);
  }
  return p;
}
}  // namespace detail

namespace {

std::int64_t micros(double t_s) { return std::llround(t_s * 1e6); }

// Writes a usage's element through its binding (the field found by equivalent usage, as the profile reads it).
void put(std::span<std::uint8_t> payload, const detail::Binding& b, std::int64_t logical) {
  if (b) writeHidElement(payload, *b.field, b.element, std::clamp(logical, b.field->logical_min, b.field->logical_max));
}

std::int64_t fractionToLogical(const detail::Binding& b, double f) {
  const double span = static_cast<double>(b.field->logical_max - b.field->logical_min);
  return b.field->logical_min + std::llround(std::clamp(f, 0.0, 1.0) * span);
}

// A pen's reports for one pose: one per input report its usages are in, the pose's reading written into each
// (the inverse of the pen profile). Out of range: a pen with In Range sends reports of zeros; one without
// keeps its last X and Y with the tip up (it cannot say it left).
class PenSynth {
 public:
  PenSynth(const HidDescriptor& d, const PenMapping& m) : d_(d), m_(m), pen_(*findHidPen(d).pen) {
    for (std::size_t r = 0; r < kHidPenRoles; ++r) bindings_[r] = detail::Binding(pen_.elements[r]);
  }

  std::vector<std::vector<std::uint8_t>> reports(const PoseSample& pose) {
    last_ = penReadingFor(m_, pose);
    const bool down = last_.pressure.has_value() && (pose.buttons & 1u) != 0;
    return encode(last_, true, down);
  }

  std::vector<std::vector<std::uint8_t>> leaving() const {
    if (at(HidPenRole::InRange)) {
      std::vector<std::vector<std::uint8_t>> out;
      for (const HidReportLayout* layout : pen_.layouts()) out.push_back(HidReportEncoder(d_).blank(*layout));
      return out;
    }
    return encode(last_, false, false);
  }

 private:
  const detail::Binding& at(HidPenRole role) const { return bindings_[static_cast<std::size_t>(role)]; }

  std::vector<std::vector<std::uint8_t>> encode(const PenReading& r, bool in_range, bool down) const {
    std::vector<std::vector<std::uint8_t>> out;
    for (const HidReportLayout* layout : pen_.layouts()) {
      std::vector<std::uint8_t> raw = HidReportEncoder(d_).blank(*layout);
      const auto payload = std::span(raw).subspan(d_.uses_report_ids ? 1 : 0);
      const auto set = [&](HidPenRole role, std::int64_t logical) {
        if (at(role).layout == layout) put(payload, at(role), logical);
      };
      set(HidPenRole::InRange, in_range ? 1 : 0);
      set(HidPenRole::TipSwitch, down ? 1 : 0);
      if (at(HidPenRole::TipPressure))
        set(HidPenRole::TipPressure, down ? fractionToLogical(at(HidPenRole::TipPressure), *r.pressure) : 0);
      if (at(HidPenRole::X)) set(HidPenRole::X, fractionToLogical(at(HidPenRole::X), r.fx));
      if (at(HidPenRole::Y)) set(HidPenRole::Y, fractionToLogical(at(HidPenRole::Y), r.fy));
      if (at(HidPenRole::TiltX))
        set(HidPenRole::TiltX, hidPenLogicalDegrees(*at(HidPenRole::TiltX).field, r.tilt_x_deg));
      if (at(HidPenRole::TiltY))
        set(HidPenRole::TiltY, hidPenLogicalDegrees(*at(HidPenRole::TiltY).field, r.tilt_y_deg));
      if (at(HidPenRole::Twist))
        set(HidPenRole::Twist, hidPenLogicalDegrees(*at(HidPenRole::Twist).field, r.twist_deg));
      out.push_back(std::move(raw));
    }
    return out;
  }

  const HidDescriptor& d_;
  PenMapping m_;
  HidPen pen_;
  std::array<detail::Binding, kHidPenRoles> bindings_{};
  PenReading last_;
};

// The reports of one pose at time t_us, spread evenly over the period when the pen uses several reports
// (a device sends them one after the other; the replay drops poses that share a time).
void pushReports(HidRecording& out, std::int64_t t_us, std::int64_t period_us,
                 std::vector<std::vector<std::uint8_t>> reports) {
  const auto n = static_cast<std::int64_t>(reports.size());
  for (std::int64_t k = 0; k < n; ++k)
    out.reports.push_back({0, t_us + k * period_us / n, std::move(reports[static_cast<std::size_t>(k)]), 0});
}

void synthesizePen(HidRecording& out, const HidDescriptor& d, const HidMapping& mapping,
                   std::span<const PoseSample> poses, double rate_hz) {
  PenSynth synth(d, mapping.pen);
  const double t0 = poses.front().time_s, dt = 1.0 / rate_hz;
  const std::int64_t period_us = micros(dt);
  std::size_t hint = 0;
  std::int64_t k = 0;
  for (double t = t0; t <= poses.back().time_s; t = t0 + static_cast<double>(++k) * dt) {
    const PoseSample p = detail::interpolatePose(poses, t, hint);
    pushReports(out, micros(t - t0), period_us, synth.reports(p));
  }
  pushReports(out, micros(static_cast<double>(k) * dt), period_us, synth.leaving());
}

}  // namespace

HidRecording synthesizeHidRecording(const HidRecordedDevice& device, const HidMapping& mapping,
                                    std::span<const PoseSample> poses, const HidSynthOptions& options) {
  if (poses.size() < 2) throw std::invalid_argument("synthesizeHidRecording: needs at least two poses");
  for (std::size_t i = 1; i < poses.size(); ++i)
    if (!(poses[i].time_s > poses[i - 1].time_s))
      throw std::invalid_argument("synthesizeHidRecording: pose " + std::to_string(i) + " is not after the one before");
  if (!(options.rate_hz >= 1.0 && options.rate_hz <= 10000.0))
    throw std::invalid_argument("synthesizeHidRecording: rate_hz must be in [1, 10000]");
  const HidDescriptor d = parseHidDescriptor(device.descriptor);
  HidRecording out;
  out.devices = {device};
  out.devices[0].index = 0;
  switch (chooseHidProfile(d, {device.vid, device.pid}).kind) {
    case HidProfileKind::Pen:
      synthesizePen(out, d, mapping, poses, options.rate_hz);
      break;
    case HidProfileKind::SixDof:
      detail::synthesizeSixDof(out, d, {device.vid, device.pid}, mapping, poses, options.rate_hz);
      break;
    case HidProfileKind::None:
      throw HidProfileError(chooseHidProfile(d).reason);
  }
  return out;
}

}  // namespace incise::devices
