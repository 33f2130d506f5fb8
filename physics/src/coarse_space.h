// Private: the coarse level of CG's two-level preconditioner. The active nodes are partitioned into
// aggregates (recursive coordinate bisection of their rest positions: halves along the longest axis of the
// box of the aggregate's nodes, split in proportion to the aggregates each half gets) and each aggregate carries
// six rigid-body modes about the nodes' positions when the coarse matrix was built (Z_i = [I | -[d_i]x],
// d_i = x_i - the aggregate's centre: u_i = t + theta x d_i). Where block SSOR smooths the error locally,
// these modes carry the long-wave part a bending beam or a swinging pad needs, so CG takes several times
// fewer iterations there. The preconditioner is additive: M^-1 r = SSOR^-1 r + Z (Z^T A Z)^-1 Z^T r.
// References: Vanek, Mandel & Brezina, "Algebraic multigrid by smoothed aggregation for second and fourth
// order elliptic problems", Computing 56, 1996 (rigid-body modes per aggregate as the coarse space);
// Smith, Bjorstad & Gropp, "Domain Decomposition", 1996 (additive two-level Schwarz).
//
// Shapes: vectors nodes x 3. Units: as the matrix (the coarse matrix is A's in the modes' coordinates).
// Cost: partition O(N log N); build one pass over the stored blocks (about 50 flops a block) and a dense
// Cholesky of 6 K x 6 K (K = 16: about 0.1 ms); apply O(N) + (6 K)^2. Allocation: none within what reserve()
// gave. Threads: one owner (the physics thread, through TissueModel). Every sum in node order: the same
// inputs give the same bits.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "block_matrix.h"

namespace incise::physics::detail {

class CoarseSpace {
 public:
  void reserve(std::size_t nodes, int max_aggregates);

  // Aggregates of the active nodes by their rest positions: `aggregates` of them (fewer when there are not
  // nodes_per_aggregate_min nodes for each; none below two). Nothing is in use until the next build().
  void partition(std::span<const Eigen::Vector3d> rest_m, std::span<const std::uint8_t> active, int aggregates,
                 int nodes_per_aggregate_min) noexcept;
  // The coarse matrix Z^T A Z with the modes about x_m, factorised (over the nodes both partitioned and
  // active; a node added since the partition has no coarse part). Returns ready().
  bool build(const BlockMatrix& a, std::span<const Eigen::Vector3d> x_m, std::span<const std::uint8_t> active) noexcept;
  // A coarse matrix is in use: partitioned into aggregates and positive definite at the last build.
  bool ready() const noexcept { return ready_; }
  int aggregates() const noexcept { return aggregates_; }

  // z += Z (Z^T A Z)^-1 Z^T r over the nodes active now; returns r . (that correction). Only when ready().
  double addCorrection(std::span<const Eigen::Vector3d> r, std::span<Eigen::Vector3d> z,
                       std::span<const std::uint8_t> active) noexcept;

 private:
  void split(int first, int count, int parts, std::span<const Eigen::Vector3d> rest_m, int& next) noexcept;
  void addRows(const BlockMatrix& a, std::span<const std::uint8_t> active) noexcept;
  // Z_i^T y into the coarse matrix's lower triangle, y = sum of A_ij Z_j over row i's blocks (j > i) whose
  // nodes are in aggregate aj (C and C^T: the block (i, j) stands for (j, i) too), or over its diagonal
  // block alone (`diagonal`: C once).
  void addRow(int i, const Eigen::Matrix<double, 3, 6>& y, int aj, bool diagonal) noexcept;
  bool factorise() noexcept;

  std::vector<int> aggregate_;           // per node: its aggregate, or -1
  std::vector<Eigen::Vector3d> offset_;  // per node: d_i = x_i - its aggregate's centre, at build()
  std::vector<int> order_;               // the partition's scratch: active nodes, sorted into aggregates
  std::vector<Eigen::Vector3d> centre_;  // per aggregate
  std::vector<int> count_;               // per aggregate: its nodes
  Eigen::MatrixXd coarse_;               // 6 K x 6 K used of it: Z^T A Z's lower triangle, then its Cholesky factor
  Eigen::VectorXd g_;                    // Z^T r, then the coarse solution
  int aggregates_ = 0;
  bool ready_ = false;
};

}  // namespace incise::physics::detail
