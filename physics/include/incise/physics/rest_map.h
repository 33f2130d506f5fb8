// The blade mapped back through the tissue's deformation: the incision is made in the tissue's rest frame,
// so a point the tool holds in the world (deformed) is first taken to the rest point the tissue carried
// there. A RestMap is that inverse linearised around one point: rest = rest_m + world_to_rest (x - world_m),
// exact inside the tet that holds the point (the deformation is affine in a linear tet), a first-order
// extrapolation around it. TissueModel::restMap makes one after a step; sim's simulated tissue carries them
// from the physics thread to the frame.
//
// Units: metres. Threads: a value, copied across. Cost: O(1). No allocation.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace incise::physics {

struct RestMap {
  Eigen::Vector3d world_m = Eigen::Vector3d::Zero();            // the point it was made around, deformed
  Eigen::Vector3d rest_m = Eigen::Vector3d::Zero();             // the same material point at rest
  Eigen::Matrix3d world_to_rest = Eigen::Matrix3d::Identity();  // F^-1 of the tet holding it
  std::int64_t step = 0;  // the physics step it was made after (0: the tissue at rest)
  bool located = false;   // false: no tet within reach of the point: the identity

  Eigen::Vector3d toRest(const Eigen::Vector3d& x_m) const noexcept { return rest_m + world_to_rest * (x_m - world_m); }
  Eigen::Vector3d directionToRest(const Eigen::Vector3d& d) const noexcept { return world_to_rest * d; }
};

}  // namespace incise::physics
