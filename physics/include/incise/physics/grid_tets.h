// A box of cells x (1 + cells) nodes split into cubes, each cube into 6 tets around its main diagonal (the
// Kuhn or Freudenthal split: every cube the same way, so neighbouring cubes share their faces' diagonals and
// the mesh is conforming). SOFA's benchmark tissue is such a grid (RegularGridTopology with
// Hexa2TetraTopologicalMapping: 8 x 26 x 8 nodes, 7,350 tets); the analytic tests use it too.
//
// Shapes: node (i, j, k) (0 <= i <= cells.x, ...) is node i + (cells.x + 1) (j + (cells.y + 1) k); the tets
// of cube (i, j, k) are 6 (i + cells.x (j + cells.y k)) .. + 5, positively oriented; neighbours filled.
// Units: metres. Threads: any. Cost O(cells). Failure: std::invalid_argument for a cell count < 1 or an
// empty or non-finite box.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/tets/tet_mesh.h"

namespace incise::physics {

tets::TetMesh gridTets(const Eigen::AlignedBox3d& box, const Eigen::Vector3i& cells);

}  // namespace incise::physics
