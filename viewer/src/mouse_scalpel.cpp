#include "incise/viewer/mouse_scalpel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace incise::viewer {

namespace {

constexpr std::uint8_t kWallFaceKind = 2;  // mesh::FaceKind::Wall

// Möller and Trumbore, "Fast, minimum storage ray/triangle intersection" (1997): the ray's parameter t
// at its hit of triangle (a, b, c), or a negative value for no hit.
double rayTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-30) return -1.0;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return -1.0;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  return e2.dot(q) * inv;
}

}  // namespace

MouseScalpel::MouseScalpel(const MouseScalpelOptions& options) : options_(options), depth_m_(options.depth_m) {
  const auto bad = [](const char* name, double value) {
    throw std::invalid_argument(std::string("MouseScalpel: ") + name + " = " + std::to_string(value) +
                                " is out of range");
  };
  if (!(options.max_depth_m > 0.0)) bad("max_depth_m", options.max_depth_m);
  if (!(options.depth_m >= 0.0 && options.depth_m <= options.max_depth_m)) bad("depth_m", options.depth_m);
  if (!(options.depth_step_m > 0.0)) bad("depth_step_m", options.depth_step_m);
  if (!(options.hover_m > 0.0)) bad("hover_m", options.hover_m);
  if (!(options.groove_reach_m >= 0.0)) bad("groove_reach_m", options.groove_reach_m);
  if (!(options.start_m >= 0.0)) bad("start_m", options.start_m);
  if (options.cut_button < 0 || options.cut_button > 31) bad("cut_button", options.cut_button);
}

void MouseScalpel::scroll(double notches) noexcept {
  if (!std::isfinite(notches)) return;
  depth_m_ = std::clamp(depth_m_ + notches * options_.depth_step_m, 0.0, options_.max_depth_m);
}

// The nearest front-facing skin face the ray meets; walls are see-through. When a wall is the nearest face
// (or nothing is met) the tangent plane at the last skin hit stands in, within groove_reach_m of it.
std::optional<MouseScalpel::Hit> MouseScalpel::cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                                    const SurfaceModel& tissue) const {
  const std::vector<float>& x = tissue.positions();
  const std::vector<std::uint32_t>& idx = tissue.indices();
  const auto at = [&](std::uint32_t v) { return Eigen::Vector3d(x[3 * v], x[3 * v + 1], x[3 * v + 2]); };
  double skin_t = std::numeric_limits<double>::infinity(), wall_t = skin_t;
  Eigen::Vector3d skin_normal = Eigen::Vector3d::Zero();
  for (std::size_t f = 0; f < tissue.faceCount(); ++f) {
    const std::uint8_t kind = tissue.faceKinds()[f];
    if (kind == sim::kDeletedFace) continue;
    const Eigen::Vector3d a = at(idx[3 * f]), b = at(idx[3 * f + 1]), c = at(idx[3 * f + 2]);
    const double t = rayTriangle(o, d, a, b, c);
    if (!(t > 0.0)) continue;
    if (kind == kWallFaceKind) {
      wall_t = std::min(wall_t, t);
      continue;
    }
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (t < skin_t && n.dot(d) < 0.0) skin_t = t, skin_normal = n.normalized();
  }
  if (std::isfinite(skin_t) && skin_t <= wall_t) return Hit{o + skin_t * d, skin_normal};
  if (has_hit_ && std::abs(d.dot(normal_)) > 1e-9) {  // over a groove: the last skin hit's tangent plane
    const double t = (hit_m_ - o).dot(normal_) / d.dot(normal_);
    const Eigen::Vector3d p = o + t * d;
    if (t > 0.0 && (p - hit_m_).norm() <= options_.groove_reach_m) return Hit{p, normal_};
  }
  if (std::isfinite(skin_t)) return Hit{o + skin_t * d, skin_normal};
  return std::nullopt;
}

// Local z along the normal (the blade, local -z, into the tissue); local x, the cutting edge, along the
// motion over the surface since the last hit (kept while the cursor rests), in the tangent plane.
Eigen::Quaterniond MouseScalpel::orientation(const Eigen::Vector3d& point_m) {
  const Eigen::Vector3d z = normal_;
  Eigen::Vector3d motion = point_m - hit_m_;
  motion -= motion.dot(z) * z;
  Eigen::Vector3d x = motion.norm() > 2e-4 ? Eigen::Vector3d(motion) : Eigen::Vector3d(edge_ - edge_.dot(z) * z);
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  edge_ = x;
  Eigen::Matrix3d r;
  r.col(0) = x;
  r.col(1) = z.cross(x);
  r.col(2) = z;
  return Eigen::Quaterniond(r).normalized();
}

MouseScalpel::Poses MouseScalpel::poses(const Camera& camera, const SurfaceModel& tissue, const MouseReading& m) {
  Poses out;
  const Eigen::Vector3d dir = camera.rayThrough(m.x_px, m.y_px, m.width_px, m.height_px);
  const std::optional<Hit> hit = cast(camera.eye_m(), dir, tissue);
  on_tissue_ = hit.has_value();
  if (!hit && !has_hit_) return out;
  if (!hit || !m.left) {  // hovering above the hit, or lifted off the tissue above the last one
    devices::PoseSample& pose = out.pose[out.count++];
    pose.time_s = m.time_s;
    if (hit) normal_ = hit->normal;
    pose.orientation = orientation(hit ? hit->point_m : hit_m_);
    if (hit) hit_m_ = hit->point_m;
    has_hit_ = true;
    pressed_ = in_ = false;
    pose.tip_m = hit_m_ + options_.hover_m * normal_;
    return out;
  }
  has_hit_ = true;
  if (!pressed_) pressed_ = true, press_m_ = hit->point_m, press_normal_ = hit->normal, press_s_ = m.time_s;
  if (!in_ && (hit->point_m - press_m_).norm() < options_.start_m) return out;  // the way not yet known
  if (!in_) {  // the blade goes in where the button went down, its edge towards the cursor
    in_ = true;
    normal_ = press_normal_;
    hit_m_ = press_m_;
    devices::PoseSample& entry = out.pose[out.count++];
    entry.time_s = press_s_;
    entry.orientation = orientation(hit->point_m);  // the motion from the press point to the cursor
    entry.tip_m = press_m_ - depth_m_ * normal_;
    entry.buttons = 1u << options_.cut_button;
  }
  devices::PoseSample& now = out.pose[out.count++];
  now.time_s = m.time_s;
  normal_ = hit->normal;
  now.orientation = orientation(hit->point_m);
  hit_m_ = hit->point_m;
  now.tip_m = hit_m_ - depth_m_ * normal_;
  now.buttons = 1u << options_.cut_button;
  return out;
}

}  // namespace incise::viewer
