// The tissue under the tool as the haptic loop sees it between two physics steps: a local linearisation
// refreshed at physics rate (TissueModel::contactModel), evaluated at 1 kHz without the solver, as SOFA's
// LCPForceFeedback re-solves its last linearised contact at haptic rate.
//
// stiffness_N_per_m is the tissue's effective stiffness at the contact point over one physics step: the
// inverse of the point's compliance h^2 W^T A^-1 W, where A = (1 + h alpha) M + h (h + beta) K is the step's
// implicit matrix and W spreads a force at the point onto its tet's nodes by the embedding's weights. A force
// f held on the point for the next step moves it by compliance * f; the held nodes are rigid.
//
// Units: metres, N/m, N. Threads: a value, copied across (e.g. through a triple buffer). Cost: O(1).
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace incise::physics {

struct ContactModel {
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();            // the contact point's position at the step
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();            // the surface's deformed outward normal there (unit)
  Eigen::Matrix3d stiffness_N_per_m = Eigen::Matrix3d::Zero();  // symmetric, positive definite when valid
  std::int64_t step = -1;                                       // the physics step it was computed after
  int cg_iterations = 0;                                        // of its three solves
  bool valid = false;  // false: no step taken yet, the point's nodes are all held, or a solve failed

  // The force the tissue pushes a tool tip at tool_m back with (N): stiffness * (point - tool) once the tip
  // is below the surface ((tool - point) . normal < 0), else zero: the tissue sticks to the tip while it is
  // in contact (tangential stiffness included). O(1), no allocation.
  Eigen::Vector3d reactionForce_N(const Eigen::Vector3d& tool_m) const noexcept {
    const Eigen::Vector3d d = point_m - tool_m;
    if (!valid || d.dot(normal) <= 0.0) return Eigen::Vector3d::Zero();
    return stiffness_N_per_m * d;
  }
};

}  // namespace incise::physics
