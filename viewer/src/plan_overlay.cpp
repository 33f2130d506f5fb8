#include "incise/viewer/plan_overlay.h"

#include <algorithm>

namespace incise::viewer {

namespace {

constexpr double kLift_m = 0.0003;  // above the surface, so that the skin does not hide it

void vertex(std::vector<float>& out, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
            const std::array<float, 3>& c) {
  out.insert(out.end(),
             {float(p.x()), float(p.y()), float(p.z()), float(n.x()), float(n.y()), float(n.z()), c[0], c[1], c[2]});
}

// A ribbon `width_m` wide along the stations, `offset_m` across the plan from its line.
void ribbon(std::vector<float>& out, const sim::Plan& plan, double offset_m, double width_m,
            const std::array<float, 3>& c) {
  for (std::size_t i = 1; i < plan.stations.size(); ++i) {
    const sim::PlanStation &a = plan.stations[i - 1], &b = plan.stations[i];
    const auto side = [&](const sim::PlanStation& s, double d) {
      return Eigen::Vector3d(s.point_m + (offset_m + d) * s.across + kLift_m * s.normal);
    };
    const Eigen::Vector3d a0 = side(a, -0.5 * width_m), a1 = side(a, 0.5 * width_m);
    const Eigen::Vector3d b0 = side(b, -0.5 * width_m), b1 = side(b, 0.5 * width_m);
    for (const Eigen::Vector3d& p : {a0, b0, b1, a0, b1, a1}) vertex(out, p, a.normal, c);
  }
}

// A square marker `size_m` across, centred on the station.
void marker(std::vector<float>& out, const sim::PlanStation& s, double size_m, const std::array<float, 3>& c) {
  const Eigen::Vector3d centre = s.point_m + 1.5 * kLift_m * s.normal;
  const Eigen::Vector3d t = 0.5 * size_m * s.tangent, a = 0.5 * size_m * s.across;
  const Eigen::Vector3d p0 = centre - t - a, p1 = centre + t - a, p2 = centre + t + a, p3 = centre - t + a;
  for (const Eigen::Vector3d& p : {p0, p1, p2, p0, p2, p3}) vertex(out, p, s.normal, c);
}

}  // namespace

std::vector<float> planTriangles(const sim::Plan& plan) {
  std::vector<float> out;
  if (plan.stations.size() < 2) return out;
  const double line_m = std::clamp(0.1 * plan.lateral_tolerance_m, 0.0003, 0.001);
  ribbon(out, plan, 0.0, line_m, kPlanColour);
  ribbon(out, plan, -plan.lateral_tolerance_m, 0.5 * line_m, kBandColour);
  ribbon(out, plan, plan.lateral_tolerance_m, 0.5 * line_m, kBandColour);
  marker(out, plan.stations.front(), 4.0 * line_m, kStartColour);
  marker(out, plan.stations.back(), 4.0 * line_m, kEndColour);
  return out;
}

}  // namespace incise::viewer
