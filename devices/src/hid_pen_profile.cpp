// The pen profile and its inverse (hid_profile.h, "Pen").
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "hid_pen_units.h"
#include "hid_profile_internal.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"

namespace incise::devices {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// The mapping's frame: unit vectors along the tablet's X and Y as laid over the tissue, and up.
struct AreaFrame {
  Eigen::Vector3d ex, ey, up;

  explicit AreaFrame(const PenMapping& m)
      : ex(m.x_edge_m.normalized()), ey(m.y_edge_m.normalized()), up(m.y_edge_m.cross(m.x_edge_m).normalized()) {}

  Eigen::Quaterniond orientation(double tilt_x_deg, double tilt_y_deg, double edge_deg) const {
    const Eigen::Vector3d axis =
        (std::tan(tilt_x_deg * kDegToRad) * ex + std::tan(tilt_y_deg * kDegToRad) * ey + up).normalized();
    const double a = edge_deg * kDegToRad;
    const Eigen::Vector3d d0 = std::cos(a) * ex + std::sin(a) * ey;
    const Eigen::Vector3d x = (d0 - d0.dot(axis) * axis).normalized();
    Eigen::Matrix3d r;
    r.col(0) = x;
    r.col(1) = axis.cross(x);
    r.col(2) = axis;
    Eigen::Quaterniond q(r);
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    return q;
  }
};

// The value a field holds after a report, as hid-input keeps it: a value outside the logical range is
// ignored when the field has a null state, else clamped into it (a field declaring min > max: as it is).
bool acceptValue(const HidField& f, std::int64_t& value) {
  if (f.logical_min >= f.logical_max) return true;
  if (value >= f.logical_min && value <= f.logical_max) return true;
  if ((f.flags & hid_flags::kNullState) != 0) return false;
  value = std::clamp(value, f.logical_min, f.logical_max);
  return true;
}

double fractionOf(const HidField& f, std::int64_t logical) {
  const double span = static_cast<double>(f.logical_max - f.logical_min);
  return span > 0.0 ? std::clamp(static_cast<double>(logical - f.logical_min) / span, 0.0, 1.0) : 0.0;
}

// The pen's state: each role's last accepted value, across the reports the pen's usages are spread over.
class PenProfile final : public HidProfile {
 public:
  PenProfile(const HidDescriptor& descriptor, const PenMapping& mapping)
      : descriptor_(descriptor), mapping_(mapping), frame_(mapping) {
    const HidPen pen = *findHidPen(descriptor).pen;
    for (std::size_t r = 0; r < kHidPenRoles; ++r) bindings_[r] = detail::Binding(pen.elements[r]);
    for (const HidReportLayout* layout : pen.layouts()) layouts_[layout_count_++] = layout;
    reset();
  }

  bool update(std::span<const std::uint8_t> raw, double time_s, PoseSample& pose) noexcept override {
    const HidReportLayout* layout = layoutOf(raw);
    if (layout == nullptr) return false;
    const auto payload = detail::payloadOf(descriptor_, *layout, raw);
    if (payload.empty()) return false;
    for (std::size_t r = 0; r < kHidPenRoles; ++r) {
      const detail::Binding& b = bindings_[r];
      if (!b || b.layout != layout) continue;
      std::int64_t value = b.read(payload);
      if (acceptValue(*b.field, value)) values_[r] = value, seen_[r] = true;
    }
    pose = current(time_s);
    return true;
  }

  PoseSample lifted(double time_s) const noexcept override {
    PoseSample pose;
    pose.time_s = time_s;
    pose.tip_m = last_surface_ + frame_.up * mapping_.lift_m;
    pose.orientation = frame_.orientation(0.0, 0.0, mapping_.yaw_deg);
    return pose;
  }

  void reset() noexcept override {
    values_.fill(0);
    seen_.fill(false);
    last_surface_ = mapping_.origin_m + 0.5 * (mapping_.x_edge_m + mapping_.y_edge_m);
  }
  HidProfileKind kind() const noexcept override { return HidProfileKind::Pen; }

 private:
  const detail::Binding& at(HidPenRole role) const { return bindings_[static_cast<std::size_t>(role)]; }
  std::int64_t value(HidPenRole role) const { return values_[static_cast<std::size_t>(role)]; }
  bool seen(HidPenRole role) const { return seen_[static_cast<std::size_t>(role)]; }
  // A role's value as a fraction of its logical range; `unseen` before its first report.
  double fraction(HidPenRole role, double unseen) const {
    return seen(role) ? fractionOf(*at(role).field, value(role)) : unseen;
  }
  bool on(HidPenRole role) const { return at(role) && value(role) != 0; }
  double degrees(HidPenRole role) const { return at(role) ? hidPenDegrees(*at(role).field, value(role)) : 0.0; }

  const HidReportLayout* layoutOf(std::span<const std::uint8_t> raw) const {
    if (raw.empty()) return nullptr;
    if (!descriptor_.uses_report_ids) return layouts_[0];
    for (std::size_t i = 0; i < layout_count_; ++i)
      if (layouts_[i]->id == raw[0]) return layouts_[i];
    return nullptr;
  }

  PoseSample current(double time_s) {
    if (at(HidPenRole::InRange) && seen(HidPenRole::InRange) && value(HidPenRole::InRange) == 0) return lifted(time_s);
    const bool has_pressure = static_cast<bool>(at(HidPenRole::TipPressure));
    const double p = has_pressure ? fraction(HidPenRole::TipPressure, 0.0) : 0.0;
    const bool tip_down = at(HidPenRole::TipSwitch) ? on(HidPenRole::TipSwitch) : p > mapping_.dead_band;
    const Eigen::Vector3d surface = mapping_.origin_m + fraction(HidPenRole::X, 0.5) * mapping_.x_edge_m +
                                    fraction(HidPenRole::Y, 0.5) * mapping_.y_edge_m;
    last_surface_ = surface;
    PoseSample pose;
    pose.time_s = time_s;
    const double depth_m = !tip_down ? -mapping_.hover_m : has_pressure ? depth(p) : mapping_.tip_depth_m;
    pose.tip_m = surface - frame_.up * depth_m;
    pose.orientation = orientation();
    pose.pressure = has_pressure ? std::optional<double>(p) : std::nullopt;
    const bool cutting =
        mapping_.cut_on == PenMapping::CutOn::Pressure && has_pressure ? p > mapping_.cut_threshold : tip_down;
    pose.buttons = (cutting ? 1u : 0u) | (on(HidPenRole::Barrel) ? 2u : 0u) |
                   (on(HidPenRole::SecondaryBarrel) ? 4u : 0u) |
                   (on(HidPenRole::Eraser) || on(HidPenRole::Invert) ? 8u : 0u);
    return pose;
  }

  double depth(double p) const {
    if (p <= mapping_.dead_band) return 0.0;
    const double t = std::min(1.0, (p - mapping_.dead_band) / (1.0 - mapping_.dead_band));
    return mapping_.max_depth_m * std::pow(t, mapping_.curve);
  }

  Eigen::Quaterniond orientation() const {
    const bool tilt = mapping_.use_tilt && at(HidPenRole::TiltX) && at(HidPenRole::TiltY);
    const double twist = mapping_.use_twist ? degrees(HidPenRole::Twist) : 0.0;
    return frame_.orientation(tilt ? degrees(HidPenRole::TiltX) : 0.0, tilt ? degrees(HidPenRole::TiltY) : 0.0,
                              mapping_.yaw_deg + twist);
  }

  const HidDescriptor& descriptor_;
  PenMapping mapping_;
  AreaFrame frame_;
  std::array<detail::Binding, kHidPenRoles> bindings_{};
  std::array<const HidReportLayout*, kHidPenRoles> layouts_{};
  std::size_t layout_count_ = 0;
  std::array<std::int64_t, kHidPenRoles> values_{};
  std::array<bool, kHidPenRoles> seen_{};
  Eigen::Vector3d last_surface_ = Eigen::Vector3d::Zero();
};

double wrapDegrees(double deg) {
  double wrapped = std::fmod(deg + 180.0, 360.0);
  if (wrapped < 0.0) wrapped += 360.0;
  return wrapped - 180.0;
}

}  // namespace

namespace detail {
std::unique_ptr<HidProfile> makePenProfile(const HidDescriptor& descriptor, const PenMapping& mapping) {
  return std::make_unique<PenProfile>(descriptor, mapping);
}
}  // namespace detail

PenReading penReadingFor(const PenMapping& m, const PoseSample& pose) {
  const AreaFrame frame(m);
  PenReading reading;
  const Eigen::Vector3d d = pose.tip_m - m.origin_m;
  Eigen::Matrix2d gram;
  gram << m.x_edge_m.squaredNorm(), m.x_edge_m.dot(m.y_edge_m), m.x_edge_m.dot(m.y_edge_m), m.y_edge_m.squaredNorm();
  const Eigen::Vector2d f = gram.ldlt().solve(Eigen::Vector2d(m.x_edge_m.dot(d), m.y_edge_m.dot(d)));
  reading.fx = f.x();
  reading.fy = f.y();
  const double h = d.dot(frame.up);
  if (h < 0.0) {
    const double t = std::pow(std::min(1.0, -h / m.max_depth_m), 1.0 / m.curve);
    reading.pressure = m.dead_band + t * (1.0 - m.dead_band);
  }
  const Eigen::Matrix3d r = pose.orientation.toRotationMatrix();
  const Eigen::Vector3d axis = r.col(2), x = r.col(0);
  reading.tilt_x_deg = std::atan(axis.dot(frame.ex) / axis.dot(frame.up)) / kDegToRad;
  reading.tilt_y_deg = std::atan(axis.dot(frame.ey) / axis.dot(frame.up)) / kDegToRad;
  const Eigen::Vector3d d0 = x - (x.dot(frame.up) / axis.dot(frame.up)) * axis;
  const double edge_deg = std::atan2(d0.dot(frame.ey), d0.dot(frame.ex)) / kDegToRad;
  reading.twist_deg = wrapDegrees(edge_deg - m.yaw_deg);
  return reading;
}

}  // namespace incise::devices
