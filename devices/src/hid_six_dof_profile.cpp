// The 6-DOF profile (hid_profile.h, "6-DOF"): velocity control of a SpaceMouse-style controller.
#include <algorithm>
#include <array>
#include <cmath>

#include "hid_profile_internal.h"
#include "incise/devices/hid_usages.h"

namespace incise::devices {
namespace {

constexpr int kMaxButtons = 32;

class SixDofProfile final : public HidProfile {
 public:
  SixDofProfile(const HidDescriptor& descriptor, HidDeviceId id, const SixDofMapping& mapping)
      : descriptor_(descriptor), mapping_(mapping) {
    for (int a = 0; a < 6; ++a)
      axes_[a] = detail::findInput(
          descriptor, hidUsage(hid_pages::kGenericDesktop, static_cast<std::uint16_t>(hid_usages::kX + a)));
    for (int b = 0; b < kMaxButtons; ++b)
      buttons_[b] = detail::findInput(descriptor, hidUsage(hid_pages::kButton, static_cast<std::uint16_t>(b + 1)));
    relative_ = mapping.axes == SixDofMapping::Axes::Relative;
    if (mapping.axes == SixDofMapping::Axes::Auto) {
      const HidQuirk* quirk = findHidQuirk(id);
      relative_ = axes_[0].field->isRelative() && !(quirk != nullptr && quirk->axes_absolute);
    }
    tip_m_ = mapping.start_m;
    orientation_ = mapping.start_orientation.normalized();
    reset();
  }

  bool update(std::span<const std::uint8_t> raw, double time_s, PoseSample& pose) noexcept override {
    if (!usesReport(raw)) return false;
    if (!relative_ && has_time_ && time_s > last_time_s_) integrate(time_s - last_time_s_);
    for (int a = 0; a < 6; ++a) readAxis(a, raw);
    for (int b = 0; b < kMaxButtons; ++b) readButton(b, raw);
    if (!has_time_ || time_s > last_time_s_) last_time_s_ = time_s;
    has_time_ = true;
    pose.time_s = time_s;
    pose.tip_m = tip_m_;
    pose.orientation = orientation_;
    pose.buttons = buttons_mask_;
    pose.pressure = std::nullopt;
    return true;
  }

  PoseSample lifted(double time_s) const noexcept override {
    PoseSample pose;
    pose.time_s = time_s;
    pose.tip_m = tip_m_ + mapping_.up.normalized() * mapping_.lift_m;
    pose.orientation = orientation_;
    return pose;
  }

  void reset() noexcept override {
    linear_.setZero();
    angular_.setZero();
    buttons_mask_ = 0;
    has_time_ = false;
  }

  HidProfileKind kind() const noexcept override { return HidProfileKind::SixDof; }

 private:
  double shaped(double d) const {
    const double dz = mapping_.dead_zone;
    if (std::abs(d) <= dz) return 0.0;
    return std::copysign((std::abs(d) - dz) / (1.0 - dz), d);
  }

  bool usesReport(std::span<const std::uint8_t> raw) const {
    for (const auto& b : axes_)
      if (!detail::payloadOf(descriptor_, *b.layout, raw).empty()) return true;
    for (const auto& b : buttons_)
      if (b && !detail::payloadOf(descriptor_, *b.layout, raw).empty()) return true;
    return false;
  }

  bool readAxis(int a, std::span<const std::uint8_t> raw) {
    const detail::Binding& b = axes_[a];
    const auto payload = detail::payloadOf(descriptor_, *b.layout, raw);
    if (payload.empty()) return false;
    Eigen::Vector3d& v = a < 3 ? linear_ : angular_;
    if (relative_) {
      Eigen::Vector3d step = Eigen::Vector3d::Zero();
      step[a % 3] = static_cast<double>(b.read(payload)) * (a < 3 ? mapping_.m_per_count : mapping_.rad_per_count);
      applyStep(a < 3 ? step : Eigen::Vector3d::Zero().eval(), a < 3 ? Eigen::Vector3d::Zero().eval() : step);
    } else {
      v[a % 3] = shaped(b.deflection(payload)) * (a < 3 ? mapping_.max_speed_m_per_s : mapping_.max_rate_rad_per_s);
    }
    return true;
  }

  bool readButton(int b, std::span<const std::uint8_t> raw) {
    if (!buttons_[b]) return false;
    const auto payload = detail::payloadOf(descriptor_, *buttons_[b].layout, raw);
    if (payload.empty()) return false;
    const std::uint32_t bit = 1u << b;
    buttons_mask_ = buttons_[b].read(payload) != 0 ? buttons_mask_ | bit : buttons_mask_ & ~bit;
    return true;
  }

  // Zero-order hold: the velocities of the last reports over dt_s.
  void integrate(double dt_s) { applyStep(linear_ * dt_s, angular_ * dt_s); }

  // A translation and a rotation vector in device axes, turned into tissue axes and applied.
  void applyStep(const Eigen::Vector3d& translation, const Eigen::Vector3d& rotation) {
    tip_m_ += mapping_.device_to_tissue * translation;
    tip_m_ = tip_m_.cwiseMax(mapping_.workspace_min_m).cwiseMin(mapping_.workspace_max_m);
    const Eigen::Vector3d w = mapping_.device_to_tissue * rotation;
    const double angle = w.norm();
    if (angle > 0.0) orientation_ = (Eigen::AngleAxisd(angle, w / angle) * orientation_).normalized();
    if (orientation_.w() < 0.0) orientation_.coeffs() = -orientation_.coeffs();
  }

  const HidDescriptor& descriptor_;
  SixDofMapping mapping_;
  std::array<detail::Binding, 6> axes_;
  std::array<detail::Binding, kMaxButtons> buttons_;
  bool relative_ = false;
  Eigen::Vector3d tip_m_, linear_, angular_;
  Eigen::Quaterniond orientation_;
  std::uint32_t buttons_mask_ = 0;
  double last_time_s_ = 0.0;
  bool has_time_ = false;
};

}  // namespace

namespace detail {
std::unique_ptr<HidProfile> makeSixDofProfile(const HidDescriptor& descriptor, HidDeviceId id,
                                              const SixDofMapping& mapping) {
  return std::make_unique<SixDofProfile>(descriptor, id, mapping);
}
}  // namespace detail

}  // namespace incise::devices
