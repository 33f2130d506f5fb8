#include "incise/sim/stroke_poses.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <Eigen/Geometry>

#include "incise/core/format.h"
#include "incise/incision/stroke_path.h"

namespace incise::sim {

namespace {

constexpr double kHoverM = 0.005;
constexpr double kDescentS = 0.03;

// The blade along -normal, its cutting edge (local +x) along the direction of travel.
Eigen::Quaterniond bladeOrientation(const Eigen::Vector3d& normal, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d z = normal.normalized();
  Eigen::Vector3d x = direction - direction.dot(z) * z;
  x = x.norm() > 1e-12 ? x.normalized() : z.unitOrthogonal();
  Eigen::Matrix3d r;
  r << x, z.cross(x), z;
  return Eigen::Quaterniond(r).normalized();
}

// Whether the pose holds the cut button (button 0) down.
enum class Blade : std::uint8_t { Up, Cutting };

class Timeline {
 public:
  explicit Timeline(double rate_hz) : dt_s_(1.0 / rate_hz) {}
  void add(std::vector<devices::PoseSample>& poses, const Eigen::Vector3d& tip, const Eigen::Quaterniond& q,
           Blade blade) {
    devices::PoseSample p;
    p.time_s = dt_s_ * static_cast<double>(count_++);
    p.tip_m = tip;
    p.orientation = q;
    p.buttons = blade == Blade::Cutting ? 1u : 0u;
    poses.push_back(p);
  }
  // Poses from a to b over duration_s (both ends included once).
  void move(std::vector<devices::PoseSample>& poses, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
            const Eigen::Quaterniond& q, double duration_s, Blade blade) {
    const int steps = std::max(1, static_cast<int>(std::lround(duration_s / dt_s_)));
    for (int k = 0; k <= steps; ++k) add(poses, a + (b - a) * (double(k) / steps), q, blade);
  }
  double dt() const { return dt_s_; }
  double now() const { return dt_s_ * static_cast<double>(count_); }

 private:
  double dt_s_;
  std::int64_t count_ = 0;
};

}  // namespace

std::vector<devices::PoseSample> posesForStrokes(const mesh::SurfaceMesh& tissue,
                                                 const std::vector<StrokeSpec>& strokes, const WorldOptions& world,
                                                 double rate_hz) {
  std::vector<devices::PoseSample> poses;
  Timeline timeline(rate_hz);
  for (const StrokeSpec& spec : strokes) {
    // The tip's depth: the stroke's own (constant, or a straight ramp to depth_end_m), else the deepest the
    // incision cuts.
    const double depth0_m = spec.depth_m >= 0.0 ? spec.depth_m : world.cutter.incision.depth_m;
    const double depth1_m = spec.depth_end_m >= 0.0 ? spec.depth_end_m : depth0_m;
    if (!(std::isfinite(spec.pause_s) && spec.pause_s >= 0.0))
      throw std::invalid_argument("posesForStrokes: pause_s = " + core::formatNumber(spec.pause_s) +
                                  " must be finite and >= 0");
    incision::StrokePathOptions path;
    path.start_m = spec.start_m;
    path.direction = spec.direction;
    path.length_m = spec.length_m;
    path.bend_m = spec.bend_m;
    path.wave_m = spec.wave_m;
    path.speed_m_per_s = spec.speed_m_per_s;
    path.rate_hz = rate_hz;
    const incision::Stroke stroke = incision::strokeAlongPath(tissue, path);
    const Eigen::Vector3d n0 = stroke.first.normal;
    const Eigen::Quaterniond q0 = bladeOrientation(n0, stroke.blade_direction);
    const Eigen::Vector3d above = stroke.first.point_m + kHoverM * n0;
    const Eigen::Vector3d in = stroke.first.point_m - depth0_m * n0;
    timeline.move(poses, above, above, q0, spec.pause_s, Blade::Up);
    timeline.move(poses, above, in, q0, kDescentS, Blade::Cutting);
    Eigen::Vector3d tip = in;
    Eigen::Quaterniond q = q0;
    double tip_depth_m = depth0_m;
    for (size_t k = 0; k < stroke.samples.size(); ++k) {
      const double f = stroke.samples.size() > 1 ? double(k) / double(stroke.samples.size() - 1) : 0.0;
      tip_depth_m = depth0_m + f * (depth1_m - depth0_m);
      const incision::StrokeSample& s = stroke.samples[k];
      const Eigen::Vector3d travel = k + 1 < stroke.samples.size()
                                         ? Eigen::Vector3d(stroke.samples[k + 1].point_m - s.point_m)
                                         : stroke.blade_direction;
      q = bladeOrientation(s.normal, travel);
      tip = s.point_m - tip_depth_m * s.normal;
      timeline.add(poses, tip, q, Blade::Cutting);
    }
    const Eigen::Vector3d out = tip + (tip_depth_m + kHoverM) * (q * Eigen::Vector3d::UnitZ());
    timeline.move(poses, tip, out, q, kDescentS, Blade::Up);
  }
  return poses;
}

}  // namespace incise::sim
