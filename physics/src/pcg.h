// Private: preconditioned conjugate gradients on a BlockMatrix, projected onto the active nodes (held and
// unused nodes are out of the system: their unknowns stay zero). Preconditioner: block SSOR,
// M = (D / w + L) (D / w)^-1 (D / w + U) with L = U^T the matrix's lower and upper block triangles and D its
// 3 x 3 diagonal blocks, applied by Eisenstat's trick (CG on (D/w + L)^-1 A (D/w + U)^-1: one forward and one
// backward sweep an iteration, no separate product); or, with w = 0, block Jacobi (M = D). Every sum runs in
// node order: the same inputs give the same bits. Shapes: vectors nodes x 3. Cost per iteration: one pass
// over the stored blocks + O(nodes). No allocation once the scratch has the size. Threads: one owner.
// Reference: S. C. Eisenstat, "Efficient implementation of a class of preconditioned conjugate gradient
// methods", SIAM J. Sci. Stat. Comput. 2(1), 1981.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "block_matrix.h"
#include "coarse_space.h"

namespace incise::physics::detail {

struct PcgScratch {
  std::vector<Eigen::Vector3d> r, z, p, q, t;
  std::vector<Quad> push;
  // Per active node: D_i^-1; with SSOR also D_i / w (the split system's preconditioner) and (1 - 2 / w) D_i
  // (Eisenstat's correction), set once per solve.
  std::vector<Eigen::Matrix3d> inverse_diagonal, scaled_diagonal, correction;
  void reserve(std::size_t nodes);
  void resize(std::size_t nodes);
};

struct PcgResult {
  int iterations = 0;
  double relative_residual = 0.0;  // sqrt(r^T M^-1 r) / scale at the end
  bool converged = false;          // relative_residual <= tolerance
  bool finite = true;
};

// Solves A x = b from the x given (set to zero on inactive nodes first) until
// sqrt(r^T M^-1 r) <= tolerance x scale, scale = max(sqrt(b^T M^-1 b), sqrt(f^T D^-1 f)) with f =
// `floor_vector` (empty: no floor): a residual small next to b, or next to a load (gravity) when b itself is
// small. At most max_iterations. Never throws.
//
// With a `coarse` space that is ready (and SSOR, w > 0) the preconditioner is two-level:
// M2^-1 = M^-1 + Z (Z^T A Z)^-1 Z^T (coarse_space.h), CG runs on A itself (one product and the two sweeps
// an iteration: three passes over the blocks against two) and stops at sqrt(r^T M2^-1 r) <= tolerance x
// the same scale; r^T M2^-1 r >= r^T M^-1 r, so it stops no less converged than SSOR alone would.
PcgResult solvePcg(const BlockMatrix& a, std::span<const std::uint8_t> active, std::span<const Eigen::Vector3d> b,
                   std::span<Eigen::Vector3d> x, double tolerance, int max_iterations, double omega,
                   std::span<const Eigen::Vector3d> floor_vector, PcgScratch& s,
                   CoarseSpace* coarse = nullptr) noexcept;

// sum_i a_i . b_i over the active nodes (in node order).
double dotActive(std::span<const Eigen::Vector3d> a, std::span<const Eigen::Vector3d> b,
                 std::span<const std::uint8_t> active) noexcept;

}  // namespace incise::physics::detail
