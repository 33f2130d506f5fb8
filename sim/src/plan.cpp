#include "incise/sim/plan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "incise/core/format.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/mesh/surface_query.h"
#include "incise/mesh/vertex_grid.h"

namespace incise::sim {

namespace {

struct TissueIndex {
  const mesh::TriMesh& mesh;
  mesh::VertexGrid grid;
  double radius_m;  // the query radius: the projection limit plus the longest edge
};

double longestEdge(const mesh::TriMesh& mesh) {
  double longest_m = 0.0;
  for (const auto e : mesh.edges()) longest_m = std::max(longest_m, static_cast<double>(mesh.calc_edge_length(e)));
  return longest_m;
}

std::optional<mesh::SurfacePoint> project(const TissueIndex& index, const Eigen::Vector3d& p) {
  auto hit = mesh::closestSurfacePoint(index.mesh, index.grid, p, index.radius_m);
  if (!hit || hit->distance_m > kPlanMaxProjectionM) return std::nullopt;
  return hit;
}

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& key, const std::string& what) {
  throw ScenarioError(file.string() + ": plan." + key + ": " + what);
}

// Tangents by central differences of the stations' points, across = normal x tangent.
void frame(std::vector<PlanStation>& stations) {
  for (std::size_t i = 0; i < stations.size(); ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, stations.size() - 1);
    Eigen::Vector3d t = stations[b].point_m - stations[a].point_m;
    t -= t.dot(stations[i].normal) * stations[i].normal;
    if (t.norm() > 0.0) stations[i].tangent = t.normalized();
    stations[i].across = stations[i].normal.cross(stations[i].tangent).normalized();
  }
}

}  // namespace

Plan projectPlan(const PlanSpec& spec, const mesh::SurfaceMesh& tissue, double spacing_m,
                 const std::filesystem::path& file) {
  TissueIndex index{tissue.mesh(), mesh::VertexGrid(std::max(2.0 * kPlanMaxProjectionM, 1e-4)), 0.0};
  index.radius_m = kPlanMaxProjectionM + longestEdge(index.mesh);
  for (const auto v : index.mesh.vertices()) index.grid.insert(v.idx(), mesh::toEigen(index.mesh.point(v)));
  Plan plan;
  plan.station_m = spacing_m;
  plan.depth_m = spec.depth_m;
  plan.lateral_tolerance_m = spec.lateral_tolerance_m;
  plan.depth_tolerance_m = spec.depth_tolerance_m;
  std::vector<mesh::SurfacePoint> given;
  for (std::size_t i = 0; i < spec.points_m.size(); ++i) {
    const auto hit = project(index, spec.points_m[i]);
    if (!hit)
      fail(file, "points_m[" + std::to_string(i) + "]",
           core::formatPoint(spec.points_m[i]) + " does not project onto the tissue (no surface within " +
               core::formatNumber(1e3 * kPlanMaxProjectionM) + " mm)");
    given.push_back(*hit);
  }
  for (std::size_t i = 0; i + 1 < given.size(); ++i) {
    const Eigen::Vector3d a = given[i].point_m, b = given[i + 1].point_m;
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing_m)));
    for (int k = i == 0 ? 0 : 1; k <= steps; ++k) {
      const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(k) / steps);
      const auto hit = k == 0 ? given[i] : k == steps ? given[i + 1] : project(index, p);
      if (!hit)
        fail(file, "points_m[" + std::to_string(i) + "]",
             "the plan from here to points_m[" + std::to_string(i + 1) + "] leaves the tissue near " +
                 core::formatPoint(p));
      PlanStation station;
      station.point_m = hit->point_m;
      station.normal = hit->normal;
      if (!plan.stations.empty())
        station.s_m = plan.stations.back().s_m + (station.point_m - plan.stations.back().point_m).norm();
      plan.stations.push_back(station);
    }
  }
  plan.length_m = plan.stations.back().s_m;
  if (!(plan.length_m >= spacing_m))
    fail(file, "points_m",
         "the plan is " + core::formatNumber(1e3 * plan.length_m) +
             " mm long on the tissue, shorter than one lattice spacing (incision.spacing_m = " +
             core::formatNumber(1e3 * spacing_m) + " mm)");
  frame(plan.stations);
  return plan;
}

PlanLocation locate(const Plan& plan, const Eigen::Vector3d& x) {
  PlanLocation best;
  best.distance_m = std::numeric_limits<double>::infinity();
  const std::size_t n = plan.stations.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const PlanStation& a = plan.stations[i];
    const PlanStation& b = plan.stations[i + 1];
    const Eigen::Vector3d ab = b.point_m - a.point_m;
    const double length2 = ab.squaredNorm();
    const double raw = length2 > 0.0 ? (x - a.point_m).dot(ab) / length2 : 0.0;
    const double t = std::clamp(raw, 0.0, 1.0);
    const Eigen::Vector3d closest = a.point_m + t * ab;
    const double distance = (x - closest).norm();
    if (distance >= best.distance_m) continue;
    const PlanStation& near = t < 0.5 ? a : b;
    best.distance_m = distance;
    best.s_m = a.s_m + t * (b.s_m - a.s_m);
    best.lateral_m = (x - closest).dot(near.across);
    best.height_m = (x - closest).dot(near.normal);
    const double length = std::sqrt(length2);
    best.beyond_m = (i == 0 && raw < 0.0) ? -raw * length : (i + 2 == n && raw > 1.0) ? (raw - 1.0) * length : 0.0;
  }
  return best;
}

}  // namespace incise::sim
