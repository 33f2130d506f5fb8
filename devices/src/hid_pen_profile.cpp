// The pen profile and its inverse (hid_profile.h, "Pen").
#include <algorithm>
#include <cmath>
#include <numbers>

#include "hid_profile_internal.h"
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

// A tilt in degrees: the field's unit when it is an angle, else the value taken as degrees (the HID Usage
// Tables define X/Y Tilt in degrees; the XP-Pen declares no unit).
double degrees(const detail::Binding& b, std::span<const std::uint8_t> payload) {
  const double physical = b.physical(payload);
  const double to_si = hidUnitToSi(b.field->unit);
  const bool angle = (b.field->unit & 0xFu) == 2 || (b.field->unit & 0xFu) == 4;
  return angle && to_si > 0.0 ? physical * to_si / kDegToRad : physical;
}

class PenProfile final : public HidProfile {
 public:
  PenProfile(const HidDescriptor& descriptor, const PenMapping& mapping)
      : descriptor_(descriptor), mapping_(mapping), frame_(mapping) {
    report_ = detail::findPenReport(descriptor);
    const auto bind = [&](std::uint16_t page, std::uint16_t id) {
      return detail::findInput(descriptor, hidUsage(page, id), report_);
    };
    using namespace hid_usages;
    x_ = bind(hid_pages::kGenericDesktop, kX);
    y_ = bind(hid_pages::kGenericDesktop, kY);
    tip_ = bind(hid_pages::kDigitizers, kTipSwitch);
    pressure_ = bind(hid_pages::kDigitizers, kTipPressure);
    in_range_ = bind(hid_pages::kDigitizers, kInRange);
    barrel_ = bind(hid_pages::kDigitizers, kBarrelSwitch);
    barrel2_ = bind(hid_pages::kDigitizers, kSecondaryBarrelSwitch);
    eraser_ = bind(hid_pages::kDigitizers, kEraser);
    invert_ = bind(hid_pages::kDigitizers, kInvert);
    tilt_x_ = bind(hid_pages::kDigitizers, kXTilt);
    tilt_y_ = bind(hid_pages::kDigitizers, kYTilt);
    twist_ = bind(hid_pages::kDigitizers, kTwist);
    reset();
  }

  bool update(std::span<const std::uint8_t> raw, double time_s, PoseSample& pose) noexcept override {
    const auto payload = detail::payloadOf(descriptor_, *report_, raw);
    if (payload.empty()) return false;
    if (in_range_ && in_range_.read(payload) == 0) {
      pose = lifted(time_s);
      return true;
    }
    const double p = pressure_ ? pressure_.fraction(payload) : 0.0;
    const bool tip_down = tip_ ? tip_.read(payload) != 0 : p > mapping_.dead_band;
    const Eigen::Vector3d surface =
        mapping_.origin_m + x_.fraction(payload) * mapping_.x_edge_m + y_.fraction(payload) * mapping_.y_edge_m;
    last_surface_ = surface;
    pose.time_s = time_s;
    pose.tip_m = surface + frame_.up * (tip_down ? -depth(p) : mapping_.hover_m);
    pose.orientation = orientation(payload);
    pose.pressure = pressure_ ? std::optional<double>(p) : std::nullopt;
    pose.buttons = buttons(payload, tip_down, p);
    return true;
  }

  PoseSample lifted(double time_s) const noexcept override {
    PoseSample pose;
    pose.time_s = time_s;
    pose.tip_m = last_surface_ + frame_.up * mapping_.lift_m;
    pose.orientation = frame_.orientation(0.0, 0.0, mapping_.yaw_deg);
    return pose;
  }

  void reset() noexcept override { last_surface_ = mapping_.origin_m + 0.5 * (mapping_.x_edge_m + mapping_.y_edge_m); }
  HidProfileKind kind() const noexcept override { return HidProfileKind::Pen; }

 private:
  double depth(double p) const {
    if (p <= mapping_.dead_band) return 0.0;
    const double t = std::min(1.0, (p - mapping_.dead_band) / (1.0 - mapping_.dead_band));
    return mapping_.max_depth_m * std::pow(t, mapping_.curve);
  }

  Eigen::Quaterniond orientation(std::span<const std::uint8_t> payload) const {
    const bool tilt = mapping_.use_tilt && tilt_x_ && tilt_y_;
    const double twist = mapping_.use_twist && twist_ ? degrees(twist_, payload) : 0.0;
    return frame_.orientation(tilt ? degrees(tilt_x_, payload) : 0.0, tilt ? degrees(tilt_y_, payload) : 0.0,
                              mapping_.yaw_deg + twist);
  }

  std::uint32_t buttons(std::span<const std::uint8_t> payload, bool tip_down, double p) const {
    const bool cutting = mapping_.cut_on == PenMapping::CutOn::TipSwitch ? tip_down : p > mapping_.cut_threshold;
    const auto on = [&](const detail::Binding& b) { return b && b.read(payload) != 0; };
    return (cutting ? 1u : 0u) | (on(barrel_) ? 2u : 0u) | (on(barrel2_) ? 4u : 0u) |
           (on(eraser_) || on(invert_) ? 8u : 0u);
  }

  const HidDescriptor& descriptor_;
  PenMapping mapping_;
  AreaFrame frame_;
  const HidReportLayout* report_ = nullptr;
  detail::Binding x_, y_, tip_, pressure_, in_range_, barrel_, barrel2_, eraser_, invert_, tilt_x_, tilt_y_, twist_;
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
