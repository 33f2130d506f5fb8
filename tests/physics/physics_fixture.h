// Test fixture for incise::physics: a regular tet grid in a box, the nodes on a plane of it, the mean of a
// displacement component over a set of nodes, and the message a refused input throws.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "incise/physics/grid_tets.h"
#include "incise/physics/tissue_model.h"

namespace incise::physics::testing {

struct Grid {
  Eigen::AlignedBox3d box;
  Eigen::Vector3i cells;
  tets::TetMesh mesh;
};

inline Grid grid(const Eigen::Vector3d& min_m, const Eigen::Vector3d& max_m, const Eigen::Vector3i& cells) {
  Grid g{Eigen::AlignedBox3d(min_m, max_m), cells, {}};
  g.mesh = gridTets(g.box, cells);
  return g;
}

// Nodes whose coordinate `axis` is within 1e-9 m of value_m.
inline std::vector<int> nodesAt(const tets::TetMesh& mesh, int axis, double value_m) {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(mesh.nodes_m.size()); ++i)
    if (std::abs(mesh.nodes_m[static_cast<std::size_t>(i)][axis] - value_m) < 1e-9) out.push_back(i);
  return out;
}

// A fixed box around the plane coordinate `axis` = value_m (every node on it, nothing else).
inline Box plane(int axis, double value_m) {
  Box b{Eigen::Vector3d::Constant(-1e9), Eigen::Vector3d::Constant(1e9)};
  b.min_m[axis] = value_m - 1e-9, b.max_m[axis] = value_m + 1e-9;
  return b;
}

// Mean over `nodes` of the displacement's component `axis`.
inline double meanDisplacement(const TissueModel& model, const std::vector<int>& nodes, int axis) {
  double sum = 0.0;
  for (const int n : nodes)
    sum += model.positions_m()[static_cast<std::size_t>(n)][axis] -
           model.restPositions_m()[static_cast<std::size_t>(n)][axis];
  return sum / static_cast<double>(nodes.size());
}

// The message of the std::invalid_argument `f` throws ("" if it does not throw).
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace incise::physics::testing
