// A planned incision on the tissue: the scenario's "plan" polyline (PlanSpec, scenario.h)
// projected onto the tissue's surface at load, resampled into stations, and the queries the scoring asks of
// it: where along the plan a point lies and how far beside it.
//
// Shapes: positions in metres, normals and tangents unit. Threads: any; the functions share no state.
// Cost: projectPlan O(stations x vertices near each) after an O(V) grid; locate O(stations).
// Failure: projectPlan throws ScenarioError naming the scenario file and the point: "file: plan.points_m[2]:
// (0.3, 0, 0) does not project onto the tissue (no surface within 5 mm)", the stretch between two points
// leaving the surface, or a plan shorter than one lattice spacing.
#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "incise/sim/scenario.h"

namespace incise::mesh {
class SurfaceMesh;
}

namespace incise::sim {

// A plan point farther than this from the tissue's surface does not project onto it.
inline constexpr double kPlanMaxProjectionM = 0.005;

struct PlanStation {
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();  // on the surface
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // outward
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitX();
  Eigen::Vector3d across = Eigen::Vector3d::UnitZ();  // normal x tangent
  double s_m = 0.0;                                   // arc length from the first station
};

struct Plan {
  std::vector<PlanStation> stations;  // >= 2, s_m increasing, at most station_m apart
  double length_m = 0.0;              // s_m of the last station
  double station_m = 0.0;
  double depth_m = 0.0, lateral_tolerance_m = 0.0, depth_tolerance_m = 0.0;  // from the PlanSpec
};

// The spec projected onto `tissue` (the uncut tissue), stations every spacing_m at most (> 0: the lattice
// spacing). `file` names the scenario in errors.
// Every given point goes to its closest point on the surface (mesh::closestSurfacePoint); the polyline
// between consecutive projected points is resampled every station_m (at most the lattice spacing,
// incision.spacing_m) and each sample projected again, so the plan follows a curved surface. The stations
// carry the arc length s_m from the start (measured along the projected stations), the unit tangent, the
// surface normal and across = normal x tangent (the side a lateral offset is measured along, positive to the
// left of the direction of travel seen from outside).
Plan projectPlan(const PlanSpec& spec, const mesh::SurfaceMesh& tissue, double spacing_m,
                 const std::filesystem::path& file);

// Where a point lies against the plan: its closest point on the stations' polyline at arc length s_m,
// the signed offset along that segment's `across` (lateral_m) and along its normal (height_m, negative
// below the surface), and how far it lies beyond either end along the tangent (beyond_m >= 0; 0 when the
// closest point is inside the plan).
struct PlanLocation {
  double s_m = 0.0;
  double lateral_m = 0.0;
  double height_m = 0.0;
  double beyond_m = 0.0;
  double distance_m = 0.0;  // to the closest point on the polyline
};
PlanLocation locate(const Plan& plan, const Eigen::Vector3d& point_m);

}  // namespace incise::sim
