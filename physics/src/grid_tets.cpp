#include "incise/physics/grid_tets.h"

#include <array>
#include <stdexcept>
#include <string>
#include <utility>

#include "incise/core/format.h"

namespace incise::physics {

tets::TetMesh gridTets(const Eigen::AlignedBox3d& box, const Eigen::Vector3i& cells) {
  if ((cells.array() < 1).any())
    throw std::invalid_argument("gridTets: cells (" + std::to_string(cells.x()) + ", " + std::to_string(cells.y()) +
                                ", " + std::to_string(cells.z()) + ") must be >= 1 on every axis");
  if (!box.min().allFinite() || !box.max().allFinite() || (box.min().array() >= box.max().array()).any())
    throw std::invalid_argument("gridTets: the box from " + core::formatPoint(box.min()) + " to " +
                                core::formatPoint(box.max()) + " must be finite and not empty");
  const Eigen::Vector3i n = cells + Eigen::Vector3i::Ones();
  const Eigen::Vector3d step = (box.max() - box.min()).cwiseQuotient(cells.cast<double>());
  tets::TetMesh mesh;
  mesh.nodes_m.reserve(static_cast<std::size_t>(n.prod()));
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) mesh.nodes_m.push_back(box.min() + Eigen::Vector3d(i, j, k).cwiseProduct(step));
  const auto node = [&](const Eigen::Vector3i& p) { return p.x() + n.x() * (p.y() + n.y() * p.z()); };
  // The six paths from corner (0,0,0) to (1,1,1) along the axes, one per order of the axes.
  constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  mesh.tets.reserve(6 * static_cast<std::size_t>(cells.prod()));
  for (int k = 0; k < cells.z(); ++k)
    for (int j = 0; j < cells.y(); ++j)
      for (int i = 0; i < cells.x(); ++i)
        for (const auto& order : kOrders) {
          Eigen::Vector3i p(i, j, k);
          std::array<int, 4> tet{};
          tet[0] = node(p);
          for (int s = 0; s < 3; ++s) p[order[s]] += 1, tet[static_cast<std::size_t>(s + 1)] = node(p);
          const auto x = [&](int v) {
            return mesh.nodes_m[static_cast<std::size_t>(tet[static_cast<std::size_t>(v)])];
          };
          Eigen::Matrix3d d;
          d << x(1) - x(0), x(2) - x(0), x(3) - x(0);
          if (d.determinant() < 0.0) std::swap(tet[1], tet[2]);
          mesh.tets.push_back(tet);
        }
  tets::buildAdjacency(mesh);
  return mesh;
}

}  // namespace incise::physics
