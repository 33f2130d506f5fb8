#include "incise/viewer/camera.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>

namespace incise::viewer {

namespace {

constexpr double kPi = 3.14159265358979323846;
double radians(double deg) { return deg * kPi / 180.0; }

// Splits "a,b,c" into numbers; false when a field is not a whole finite number.
bool numbers(const std::string& text, char separator, std::vector<double>& out) {
  std::stringstream in(text);
  std::string field;
  while (std::getline(in, field, separator)) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(field, &used);
    } catch (const std::exception&) {
      return false;
    }
    if (used != field.size() || !std::isfinite(x)) return false;
    out.push_back(x);
  }
  return !text.empty() && text.back() != separator;
}

// A unit vector perpendicular to `n`, as close to `hint` as possible.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& n, const Eigen::Vector3d& hint) {
  Eigen::Vector3d u = hint - hint.dot(n) * n;
  if (u.norm() < 1e-6) u = n.unitOrthogonal();
  return u.normalized();
}

}  // namespace

CameraOption parseCameraOption(const std::string& value) {
  std::vector<double> v;
  const std::string usage = "--camera '" + value +
                            "': expected AZ,EL[,DIST] (azimuth and elevation in degrees, distance in metres), "
                            "e.g. --camera 30,20 or --camera 30,20,0.12";
  if (!numbers(value, ',', v) || v.size() < 2 || v.size() > 3) throw std::invalid_argument(usage);
  if (!(std::abs(v[1]) < 90.0))
    throw std::invalid_argument("--camera '" + value + "': the elevation must be strictly between -90 and 90 degrees");
  CameraOption option{v[0], v[1], std::nullopt};
  if (v.size() == 3) {
    if (!(v[2] > 0.0)) throw std::invalid_argument("--camera '" + value + "': the distance must be > 0 metres");
    option.distance_m = v[2];
  }
  return option;
}

ImageSize parseSizeOption(const std::string& value) {
  const std::size_t x = value.find('x');
  std::vector<double> w, h;
  const bool parsed = x != std::string::npos && numbers(value.substr(0, x), ',', w) &&
                      numbers(value.substr(x + 1), ',', h) && w.size() == 1 && h.size() == 1;
  if (!parsed || w[0] != std::floor(w[0]) || h[0] != std::floor(h[0]))
    throw std::invalid_argument("--size '" + value + "': expected WIDTHxHEIGHT in pixels, e.g. --size 1280x800");
  if (w[0] < 16 || w[0] > 8192 || h[0] < 16 || h[0] > 8192)
    throw std::invalid_argument("--size '" + value + "': width and height must be in [16, 8192]");
  return {static_cast<int>(w[0]), static_cast<int>(h[0])};
}

Camera Camera::frameStroke(std::span<const Eigen::Vector3d> points_m, const Eigen::Vector3d& outward,
                           const Eigen::Vector3d& up_hint, double aspect, const Eigen::Vector3d& fallback_m) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : points_m)
    if (p.allFinite()) box.extend(p);
  if (box.isEmpty() || box.diagonal().norm() < 1e-4) {
    const Eigen::Vector3d c = box.isEmpty() ? fallback_m : box.center();
    box = Eigen::AlignedBox3d(c - Eigen::Vector3d::Constant(0.01), c + Eigen::Vector3d::Constant(0.01));
  }
  CameraPose pose;
  pose.target_m = box.center();
  const Eigen::Vector3d n = outward.norm() > 1e-12 ? outward.normalized() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up = perpendicular(n, up_hint);
  // Tilted 25 degrees towards `up`: straight down a groove its walls would be edge-on.
  pose.eye_dir = (std::cos(radians(25.0)) * n + std::sin(radians(25.0)) * up).normalized();
  pose.up = perpendicular(pose.eye_dir, up);
  // Far enough for the box's extent across the view (plus a quarter) to fit both view angles.
  const Eigen::Vector3d right = pose.up.cross(pose.eye_dir).normalized();
  double half_x = 0.0, half_y = 0.0, half_z = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d d = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)) - pose.target_m;
    half_x = std::max(half_x, std::abs(d.dot(right)));
    half_y = std::max(half_y, std::abs(d.dot(pose.up)));
    half_z = std::max(half_z, std::abs(d.dot(pose.eye_dir)));
  }
  const double tan_y = std::tan(radians(0.5 * pose.fov_y_deg)), tan_x = tan_y * std::max(aspect, 1e-3);
  pose.distance_m = 1.25 * std::max(half_x / tan_x, half_y / tan_y) + half_z;
  return Camera(pose);
}

Camera Camera::fromOption(const CameraOption& option, const Camera& framed) {
  CameraPose pose = framed.pose();
  const double az = radians(option.azimuth_deg), el = radians(option.elevation_deg);
  pose.eye_dir = Eigen::Vector3d(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  pose.up = perpendicular(pose.eye_dir, Eigen::Vector3d::UnitY());
  if (option.distance_m) pose.distance_m = *option.distance_m;
  return Camera(pose);
}

Eigen::Matrix4f Camera::view() const {
  const Eigen::Vector3d z = pose_.eye_dir;  // the camera looks along -z
  const Eigen::Vector3d x = pose_.up.cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = x.transpose();
  m.block<1, 3>(1, 0) = y.transpose();
  m.block<1, 3>(2, 0) = z.transpose();
  const Eigen::Vector3d eye = eye_m();
  m(0, 3) = -x.dot(eye), m(1, 3) = -y.dot(eye), m(2, 3) = -z.dot(eye);
  return m.cast<float>();
}

Eigen::Matrix4f Camera::projection(double aspect) const {
  const double near_m = 0.02 * pose_.distance_m, far_m = 20.0 * pose_.distance_m;
  const double f = 1.0 / std::tan(radians(0.5 * pose_.fov_y_deg));
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(2, 2) = (far_m + near_m) / (near_m - far_m);
  p(2, 3) = 2.0 * far_m * near_m / (near_m - far_m);
  p(3, 2) = -1.0;
  return p.cast<float>();
}

std::optional<Eigen::Vector2d> Camera::project(const Eigen::Vector3d& x_m, int width, int height) const {
  const Eigen::Vector4d clip = (projection(double(width) / height) * view()).cast<double>() * x_m.homogeneous();
  if (clip.w() <= 0.0) return std::nullopt;
  const double ndc_x = clip.x() / clip.w(), ndc_y = clip.y() / clip.w();
  return Eigen::Vector2d((ndc_x + 1.0) * 0.5 * width, (1.0 - ndc_y) * 0.5 * height);
}

Eigen::Vector3d Camera::rayThrough(double x_px, double y_px, int width, int height) const {
  const double aspect = double(width) / std::max(height, 1);
  const double f = 1.0 / std::tan(radians(0.5 * pose_.fov_y_deg));
  const double ndc_x = 2.0 * x_px / std::max(width, 1) - 1.0, ndc_y = 1.0 - 2.0 * y_px / std::max(height, 1);
  const Eigen::Vector3d z = pose_.eye_dir, x = pose_.up.cross(z).normalized(), y = z.cross(x);  // as view()
  return (-z + (ndc_x * aspect / f) * x + (ndc_y / f) * y).normalized();
}

void Camera::orbit(double dx_px, double dy_px, int height) {
  // A turntable about the framing's up axis: the horizon stays level.
  const double per_px = kPi / std::max(height, 1);  // a window's height turns the eye half round
  const Eigen::Vector3d axis = home_.up;
  const Eigen::Vector3d right = pose_.up.cross(pose_.eye_dir).normalized();
  Eigen::Vector3d dir = Eigen::AngleAxisd(-dx_px * per_px, axis) * pose_.eye_dir;
  const Eigen::Vector3d turned =
      Eigen::AngleAxisd(dy_px * per_px, Eigen::AngleAxisd(-dx_px * per_px, axis) * right) * dir;
  if (std::abs(turned.normalized().dot(axis)) < 0.995) dir = turned;  // short of the poles
  pose_.eye_dir = dir.normalized();
  pose_.up = perpendicular(pose_.eye_dir, axis);
}

void Camera::pan(double dx_px, double dy_px, int height) {
  const double m_per_px = 2.0 * pose_.distance_m * std::tan(radians(0.5 * pose_.fov_y_deg)) / std::max(height, 1);
  const Eigen::Vector3d right = pose_.up.cross(pose_.eye_dir).normalized();
  pose_.target_m += (-dx_px * right + dy_px * pose_.up) * m_per_px;
}

void Camera::zoom(double steps) { pose_.distance_m = std::clamp(pose_.distance_m * std::pow(0.9, steps), 1e-4, 1e3); }

}  // namespace incise::viewer
