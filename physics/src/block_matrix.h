// Private: a symmetric sparse matrix of 3 x 3 blocks (one block row per node), its upper triangle stored by
// rows: the diagonal blocks apart, and per row its blocks (i, j), j > i, in the order they were acquired, in
// one pool of rows with room to grow. A row that outgrows its room moves to the pool's end (entries keep
// their index within the row, which is what elements hold). An entry counts the elements that use it; one
// no element uses any more stays (zeroed by the next assembly) until an acquire() in its row takes it
// again: the pattern follows cuts in O(changed) and is never rebuilt.
// Blocks are row-major with each row padded to 4 doubles (32-byte aligned): a row's product with the upper
// blocks is gathered lane by lane and summed across lanes once per row, the lower (transposed) blocks are
// pushed to later rows four lanes at a time. AVX builds and others sum in the same order (no fused
// multiply-add): the same bits either way.
//
// Shapes: vectors nodes x 3 (Eigen::Vector3d per node). Cost: multiply, each sweep: one pass over the
// stored blocks; setZero O(pool); acquire O(row). Allocation: none while the reserve lasts (growth beyond it
// is counted). Threads: one owner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace incise::physics::detail {

// A 3 x 3 block, row-major, each row padded to 4 (the 4th lane stays 0).
struct alignas(32) Block {
  double c[12];
  double operator()(int r, int k) const noexcept { return c[4 * r + k]; }
  double& operator()(int r, int k) noexcept { return c[4 * r + k]; }
  Eigen::Matrix3d matrix() const noexcept;
  void setZero() noexcept;
};

// block += m.
void addTo(Block& block, const Eigen::Matrix3d& m) noexcept;

// Four doubles, aligned: the lower sweep's pushed sums.
struct alignas(32) Quad {
  double v[4];
};

class BlockMatrix {
 public:
  void reserve(std::size_t rows, std::size_t entries);
  // Appends a row with room for `room` blocks above the diagonal; returns its index.
  int addRow(int room);
  int rows() const noexcept { return static_cast<int>(diagonal_.size()); }
  // The entry (row, col), row < col: its index within the row, created (or a dead one reused) when absent;
  // one use more.
  int acquire(int row, int col);
  void release(int row, int local) noexcept;  // one use fewer
  // The live entry (row, col), row < col: its index within the row, or -1. O(row).
  int find(int row, int col) const noexcept;

  void setZero() noexcept;
  Block& diagonal(int row) noexcept { return diagonal_[static_cast<std::size_t>(row)]; }
  const Block& diagonal(int row) const noexcept { return diagonal_[static_cast<std::size_t>(row)]; }
  Block& upper(int row, int local) noexcept { return blocks_[static_cast<std::size_t>(first_[row] + local)]; }
  // Hints that a block will be written soon (both its cache lines); no effect on the values.
  void prefetchDiagonal(int row) const noexcept { prefetch(diagonal_[static_cast<std::size_t>(row)]); }
  void prefetchUpper(int row, int local) const noexcept {
    prefetch(blocks_[static_cast<std::size_t>(first_[static_cast<std::size_t>(row)] + local)]);
  }

  // Over the active rows (rows and columns elsewhere absent: x must be zero there, y is written zero there).
  // `push` is scratch of rows() Quads. y = A x:
  void multiply(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y, std::span<const std::uint8_t> active,
                std::span<Quad> push) const noexcept;
  // y = (D / w + U)^-1 x (rows descending); inverse_diagonal holds the active rows' D_i^-1.
  void upperSolve(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y,
                  std::span<const Eigen::Matrix3d> inverse_diagonal, std::span<const std::uint8_t> active,
                  double omega) const noexcept;
  // y = (D / w + L)^-1 x, L = U^T (rows ascending).
  void lowerSolve(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y,
                  std::span<const Eigen::Matrix3d> inverse_diagonal, std::span<const std::uint8_t> active, double omega,
                  std::span<Quad> push) const noexcept;
  // y = (D / w + U) x.
  void upperMultiply(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y,
                     std::span<const std::uint8_t> active, double omega) const noexcept;

  // f(col, block) over row `row`'s stored blocks above the diagonal (a dead one is zero after an assembly).
  template <class F>
  void forEachUpper(int row, F&& f) const noexcept {
    const auto r = static_cast<std::size_t>(row);
    for (int k = 0; k < count_[r]; ++k) {
      const auto e = static_cast<std::size_t>(first_[r] + k);
      if (col_[e] >= 0) f(col_[e], blocks_[e]);
    }
  }

  std::size_t entries() const noexcept;  // the diagonal and the live blocks above it
  int overflows() const noexcept { return overflows_; }

 private:
  static void prefetch(const Block& b) noexcept { __builtin_prefetch(b.c, 1), __builtin_prefetch(b.c + 8, 1); }
  void moveRow(std::size_t row, int room);
  Eigen::Vector3d gather(std::size_t row, const double* x) const noexcept;             // sum_j U_ij x_j
  void pushRow(std::size_t row, const Eigen::Vector3d& y, Quad* push) const noexcept;  // push_j += U_ij^T y

  std::vector<Block> diagonal_;
  std::vector<int> first_, count_, room_;
  std::vector<int> col_, uses_;
  std::vector<Block> blocks_;
  int overflows_ = 0;
};

}  // namespace incise::physics::detail
