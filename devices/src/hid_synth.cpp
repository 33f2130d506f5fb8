#include "incise/devices/hid_synth.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "hid_profile_internal.h"
#include "hid_synth_internal.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"

namespace incise::devices {
namespace {}  // namespace

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

// Degrees into the field's logical value: the inverse of the pen profile's reading of tilt and twist.
std::int64_t degreesToLogical(const detail::Binding& b, double deg) {
  const double to_si = hidUnitToSi(b.field->unit);
  const bool angle = (b.field->unit & 0xFu) == 2 || (b.field->unit & 0xFu) == 4;
  const double physical = angle && to_si > 0.0 ? deg * (std::numbers::pi / 180.0) / to_si : deg;
  return hidLogical(*b.field, physical);
}

class PenSynth {
 public:
  PenSynth(const HidDescriptor& d, const PenMapping& m) : d_(d), m_(m), report_(detail::findPenReport(d)) {
    using namespace hid_usages;
    const auto bind = [&](std::uint16_t page, std::uint16_t id) {
      return detail::findInput(d, hidUsage(page, id), report_);
    };
    x_ = bind(hid_pages::kGenericDesktop, kX);
    y_ = bind(hid_pages::kGenericDesktop, kY);
    tip_ = bind(hid_pages::kDigitizers, kTipSwitch);
    pressure_ = bind(hid_pages::kDigitizers, kTipPressure);
    in_range_ = bind(hid_pages::kDigitizers, kInRange);
    tilt_x_ = bind(hid_pages::kDigitizers, kXTilt);
    tilt_y_ = bind(hid_pages::kDigitizers, kYTilt);
    twist_ = bind(hid_pages::kDigitizers, kTwist);
  }

  std::vector<std::uint8_t> report(const PoseSample* pose) const {
    std::vector<std::uint8_t> raw = HidReportEncoder(d_).blank(*report_);
    const auto payload = std::span(raw).subspan(d_.uses_report_ids ? 1 : 0);
    if (pose == nullptr) return raw;  // out of range: every bit 0
    const PenReading r = penReadingFor(m_, *pose);
    const bool down = r.pressure.has_value() && (pose->buttons & 1u) != 0;
    put(payload, in_range_, 1);
    put(payload, tip_, down ? 1 : 0);
    if (pressure_) put(payload, pressure_, down ? fractionToLogical(pressure_, *r.pressure) : 0);
    put(payload, x_, x_ ? fractionToLogical(x_, r.fx) : 0);
    put(payload, y_, y_ ? fractionToLogical(y_, r.fy) : 0);
    if (tilt_x_) put(payload, tilt_x_, degreesToLogical(tilt_x_, r.tilt_x_deg));
    if (tilt_y_) put(payload, tilt_y_, degreesToLogical(tilt_y_, r.tilt_y_deg));
    if (twist_) put(payload, twist_, degreesToLogical(twist_, r.twist_deg));
    return raw;
  }

 private:
  const HidDescriptor& d_;
  PenMapping m_;
  const HidReportLayout* report_;
  detail::Binding x_, y_, tip_, pressure_, in_range_, tilt_x_, tilt_y_, twist_;
};

void synthesizePen(HidRecording& out, const HidDescriptor& d, const HidMapping& mapping,
                   std::span<const PoseSample> poses, double rate_hz) {
  const PenSynth synth(d, mapping.pen);
  const double t0 = poses.front().time_s, dt = 1.0 / rate_hz;
  std::size_t hint = 0;
  std::int64_t k = 0;
  for (double t = t0; t <= poses.back().time_s; t = t0 + static_cast<double>(++k) * dt) {
    const PoseSample p = detail::interpolatePose(poses, t, hint);
    out.reports.push_back({0, micros(t - t0), synth.report(&p), 0});
  }
  out.reports.push_back({0, micros(static_cast<double>(k) * dt), synth.report(nullptr), 0});
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
