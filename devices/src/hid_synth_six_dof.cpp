// The 6-DOF half of the generator (hid_synth.h): closed-loop velocity control through the profile itself.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "hid_profile_internal.h"
#include "hid_synth_internal.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_synth.h"
#include "incise/devices/hid_usages.h"

namespace incise::devices::detail {
namespace {

// The logical value whose shaped deflection (hid_profile.h, 6-DOF) is nearest `wanted` in [-1, 1].
std::int64_t deflectionToLogical(const Binding& b, double wanted, double dead_zone) {
  const double full = static_cast<double>(std::max(std::llabs(b.field->logical_min), std::llabs(b.field->logical_max)));
  const double w = std::clamp(wanted, -1.0, 1.0);
  if (w == 0.0) return 0;
  const double raw = std::copysign(dead_zone + std::abs(w) * (1.0 - dead_zone), w);
  const std::int64_t logical =
      std::clamp<std::int64_t>(std::llround(raw * full), b.field->logical_min, b.field->logical_max);
  // Rest rather than the smallest deflection past the dead zone when rest is nearer (no dithering at rest).
  const double d = static_cast<double>(logical) / full;
  const double shaped =
      std::abs(d) <= dead_zone ? 0.0 : std::copysign((std::abs(d) - dead_zone) / (1.0 - dead_zone), d);
  return std::abs(shaped - w) < std::abs(w) ? logical : 0;
}

class SixDofSynth {
 public:
  SixDofSynth(const HidDescriptor& d, HidDeviceId id, const HidMapping& mapping, HidRecording& out)
      : d_(d),
        m_(mapping.six_dof),
        plant_(makeHidProfile(d, id, mapping)),
        out_(out),
        to_device_(m_.device_to_tissue.inverse()) {
    for (int a = 0; a < 6; ++a)
      axes_[a] = findInput(d, hidUsage(hid_pages::kGenericDesktop, static_cast<std::uint16_t>(hid_usages::kX + a)));
    for (int b = 0; b < 32; ++b)
      buttons_[b] = findInput(d, hidUsage(hid_pages::kButton, static_cast<std::uint16_t>(b + 1)));
    const HidQuirk* quirk = findHidQuirk(id);
    const bool relative = m_.axes == SixDofMapping::Axes::Relative ||
                          (m_.axes == SixDofMapping::Axes::Auto && axes_[0].field->isRelative() &&
                           !(quirk != nullptr && quirk->axes_absolute));
    if (relative)
      throw std::invalid_argument(
          "synthesizeHidRecording: the generator writes absolute deflections, but this device's "
          "axes would be read as relative (set six_dof.axes to \"absolute\")");
  }

  // Sends axes [first, first + 3) at time_us: probes with the held values to learn the pose there, then
  // writes the values that reach `target` one period later.
  void axes(int first, std::int64_t time_us, const PoseSample& target, double dt_s) {
    const PoseSample now = feed(*axes_[first].layout, time_us, false);
    Eigen::Vector3d wanted;
    if (first == 0) {
      wanted = to_device_ * (target.tip_m - now.tip_m) / dt_s / m_.max_speed_m_per_s;
    } else {
      const Eigen::AngleAxisd turn(target.orientation * now.orientation.inverse());
      wanted = to_device_ * (turn.axis() * turn.angle()) / dt_s / m_.max_rate_rad_per_s;
    }
    for (int i = 0; i < 3; ++i) held_[first + i] = deflectionToLogical(axes_[first + i], wanted[i], m_.dead_zone);
    feed(*axes_[first].layout, time_us, true);
  }

  void buttons(std::uint32_t mask, std::int64_t time_us) {
    if (!buttons_[0] || mask == buttons_sent_) return;
    buttons_sent_ = mask;
    feed(*buttons_[0].layout, time_us, true);
  }

 private:
  // A report of `layout` holding every axis and button it carries at its held value (a device with one
  // combined report gets all six axes and the buttons each time).
  PoseSample feed(const HidReportLayout& layout, std::int64_t time_us, bool record) {
    auto raw = HidReportEncoder(d_).blank(layout);
    const auto payload = std::span(raw).subspan(d_.uses_report_ids ? 1 : 0);
    for (int a = 0; a < 6; ++a)
      if (axes_[a].layout == &layout) writeHidElement(payload, *axes_[a].field, axes_[a].element, held_[a]);
    for (int b = 0; b < 32; ++b)
      if (buttons_[b] && buttons_[b].layout == &layout)
        writeHidElement(payload, *buttons_[b].field, buttons_[b].element, (buttons_sent_ >> b) & 1u);
    return send(raw, time_us, record);
  }

  // Through the plant, at the time the replay will see (whole microseconds), and into the recording.
  PoseSample send(const std::vector<std::uint8_t>& raw, std::int64_t time_us, bool record) {
    PoseSample pose;
    plant_->update(raw, static_cast<double>(time_us) / 1e6, pose);
    if (record) out_.reports.push_back({0, time_us, raw, 0});
    return pose;
  }

  const HidDescriptor& d_;
  SixDofMapping m_;
  std::unique_ptr<HidProfile> plant_;
  HidRecording& out_;
  Eigen::Matrix3d to_device_;
  std::array<Binding, 6> axes_;
  std::array<Binding, 32> buttons_;     // Button page usages 1..32 (bit n - 1)
  std::array<std::int64_t, 6> held_{};  // the logical value last sent, per axis
  std::uint32_t buttons_sent_ = 0;
};

}  // namespace

void synthesizeSixDof(HidRecording& out, const HidDescriptor& d, HidDeviceId id, const HidMapping& mapping,
                      std::span<const PoseSample> poses, double rate_hz) {
  SixDofSynth synth(d, id, mapping, out);
  const double t0 = poses.front().time_s, dt = 1.0 / rate_hz;
  const auto us = [](double t_s) { return std::llround(t_s * 1e6); };
  std::size_t hint_t = 0, hint_r = 0, hint_b = 0;
  const int ticks = static_cast<int>(std::ceil((poses.back().time_s - t0) * rate_hz));
  for (int k = 0; k <= ticks; ++k) {
    const double t = static_cast<double>(k) * dt;
    synth.axes(0, us(t), interpolatePose(poses, t0 + t + dt, hint_t), dt);
    synth.buttons(interpolatePose(poses, t0 + t + 0.25 * dt, hint_b).buttons, us(t + 0.25 * dt));
    synth.axes(3, us(t + 0.5 * dt), interpolatePose(poses, t0 + t + 1.5 * dt, hint_r), dt);
  }
}

}  // namespace incise::devices::detail
