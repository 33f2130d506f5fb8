#include "block_matrix.h"

#include <algorithm>

#include "lanes.h"

namespace incise::physics::detail {
namespace {

// B x for one block (rows dotted with x, lanes summed).
inline Eigen::Vector3d blockProduct(const Block& b, const double* x) noexcept {
  const Lanes xv = Lanes::load3(x);
  return {(Lanes::load(b.c) * xv).sum3(), (Lanes::load(b.c + 4) * xv).sum3(), (Lanes::load(b.c + 8) * xv).sum3()};
}

}  // namespace

Eigen::Matrix3d Block::matrix() const noexcept {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) m(r, k) = c[4 * r + k];
  return m;
}

void Block::setZero() noexcept { std::fill(std::begin(c), std::end(c), 0.0); }

void addTo(Block& block, const Eigen::Matrix3d& m) noexcept {
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) block.c[4 * r + k] += m(r, k);
}

void BlockMatrix::reserve(std::size_t rows, std::size_t entries) {
  diagonal_.reserve(rows), first_.reserve(rows), count_.reserve(rows), room_.reserve(rows);
  col_.reserve(entries), uses_.reserve(entries), blocks_.reserve(entries);
}

int BlockMatrix::addRow(int room) {
  const std::size_t size = static_cast<std::size_t>(std::max(room, 1));
  if (diagonal_.size() == diagonal_.capacity() || col_.size() + size > col_.capacity()) ++overflows_;
  diagonal_.push_back(Block{});
  first_.push_back(static_cast<int>(col_.size()));
  count_.push_back(0);
  room_.push_back(static_cast<int>(size));
  col_.resize(col_.size() + size, -1);
  uses_.resize(col_.size(), 0);
  blocks_.resize(col_.size(), Block{});
  return rows() - 1;
}

void BlockMatrix::moveRow(std::size_t r, int room) {
  const auto from = static_cast<std::ptrdiff_t>(first_[r]), to = static_cast<std::ptrdiff_t>(col_.size());
  if (col_.size() + static_cast<std::size_t>(room) > col_.capacity()) ++overflows_;
  col_.resize(col_.size() + static_cast<std::size_t>(room), -1);
  uses_.resize(col_.size(), 0);
  blocks_.resize(col_.size(), Block{});
  const auto count = static_cast<std::ptrdiff_t>(count_[r]);
  std::copy(col_.begin() + from, col_.begin() + from + count, col_.begin() + to);
  std::copy(uses_.begin() + from, uses_.begin() + from + count, uses_.begin() + to);
  std::copy(blocks_.begin() + from, blocks_.begin() + from + count, blocks_.begin() + to);
  std::fill(uses_.begin() + from, uses_.begin() + from + count, 0);
  first_[r] = static_cast<int>(to);
  room_[r] = room;
}

int BlockMatrix::acquire(int row, int col) {
  const auto r = static_cast<std::size_t>(row);
  const auto first = static_cast<std::size_t>(first_[r]);
  int dead = -1;
  for (int k = 0; k < count_[r]; ++k) {
    const std::size_t e = first + static_cast<std::size_t>(k);
    if (col_[e] == col) return ++uses_[e], k;  // live, or dead with this column: taken again
    if (uses_[e] == 0 && dead < 0) dead = k;
  }
  if (dead < 0) {
    if (count_[r] == room_[r]) moveRow(r, 2 * room_[r]);
    dead = count_[r]++;
  }
  const std::size_t e = static_cast<std::size_t>(first_[r] + dead);
  col_[e] = col, uses_[e] = 1;
  blocks_[e].setZero();
  return dead;
}

int BlockMatrix::find(int row, int col) const noexcept {
  const auto r = static_cast<std::size_t>(row);
  for (int k = 0; k < count_[r]; ++k) {
    const auto e = static_cast<std::size_t>(first_[r] + k);
    if (col_[e] == col && uses_[e] > 0) return k;
  }
  return -1;
}

void BlockMatrix::release(int row, int local) noexcept {
  int& uses = uses_[static_cast<std::size_t>(first_[static_cast<std::size_t>(row)] + local)];
  if (uses > 0) --uses;
}

void BlockMatrix::setZero() noexcept {
  for (Block& b : diagonal_) b.setZero();
  for (Block& b : blocks_) b.setZero();
}

std::size_t BlockMatrix::entries() const noexcept {
  std::size_t n = diagonal_.size();
  for (std::size_t r = 0; r < first_.size(); ++r)
    for (int k = 0; k < count_[r]; ++k) n += uses_[static_cast<std::size_t>(first_[r] + k)] > 0 ? 1 : 0;
  return n;
}

Eigen::Vector3d BlockMatrix::gather(std::size_t row, const double* x) const noexcept {
  // Per block row r, the lanes of row_r (.) x_j summed over the blocks, two blocks at a time into two sets of
  // sums (consecutive additions do not wait on each other); lanes added once at the end.
  Lanes a0 = Lanes::zero(), a1 = a0, a2 = a0, b0 = a0, b1 = a0, b2 = a0;
  const std::size_t first = static_cast<std::size_t>(first_[row]);
  const std::size_t end = first + static_cast<std::size_t>(count_[row]);
  std::size_t e = first;
  for (; e + 1 < end; e += 2) {
    const Lanes xa = Lanes::load3(x + 3 * static_cast<std::size_t>(col_[e]));
    const Lanes xb = Lanes::load3(x + 3 * static_cast<std::size_t>(col_[e + 1]));
    const double* ba = blocks_[e].c;
    const double* bb = blocks_[e + 1].c;
    a0 = a0 + Lanes::load(ba) * xa, a1 = a1 + Lanes::load(ba + 4) * xa, a2 = a2 + Lanes::load(ba + 8) * xa;
    b0 = b0 + Lanes::load(bb) * xb, b1 = b1 + Lanes::load(bb + 4) * xb, b2 = b2 + Lanes::load(bb + 8) * xb;
  }
  if (e < end) {
    const Lanes xa = Lanes::load3(x + 3 * static_cast<std::size_t>(col_[e]));
    const double* ba = blocks_[e].c;
    a0 = a0 + Lanes::load(ba) * xa, a1 = a1 + Lanes::load(ba + 4) * xa, a2 = a2 + Lanes::load(ba + 8) * xa;
  }
  return {(a0 + b0).sum3(), (a1 + b1).sum3(), (a2 + b2).sum3()};
}

void BlockMatrix::pushRow(std::size_t row, const Eigen::Vector3d& y, Quad* push) const noexcept {
  const Lanes y0 = Lanes::broadcast(y[0]), y1 = Lanes::broadcast(y[1]), y2 = Lanes::broadcast(y[2]);
  const std::size_t first = static_cast<std::size_t>(first_[row]);
  for (std::size_t e = first, end = first + static_cast<std::size_t>(count_[row]); e < end; ++e) {
    const double* b = blocks_[e].c;
    double* p = push[static_cast<std::size_t>(col_[e])].v;
    (Lanes::load(p) + ((Lanes::load(b) * y0 + Lanes::load(b + 4) * y1) + Lanes::load(b + 8) * y2)).store(p);
  }
}

void BlockMatrix::multiply(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y,
                           std::span<const std::uint8_t> active, std::span<Quad> push) const noexcept {
  const double* xd = x.data()->data();
  for (Quad& q : push) q = Quad{{0.0, 0.0, 0.0, 0.0}};
  for (std::size_t i = 0; i < diagonal_.size(); ++i) {
    if (!active[i]) {
      y[i].setZero();
      continue;
    }
    const double* p = push[i].v;
    y[i] = (blockProduct(diagonal_[i], xd + 3 * i) + gather(i, xd)) + Eigen::Vector3d(p[0], p[1], p[2]);
    pushRow(i, x[i], push.data());
  }
}

void BlockMatrix::upperSolve(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y,
                             std::span<const Eigen::Matrix3d> inverse_diagonal, std::span<const std::uint8_t> active,
                             double omega) const noexcept {
  const double* yd = y.data()->data();
  for (std::size_t i = diagonal_.size(); i-- > 0;)  // y_j, j > i, final (zero where inactive)
    y[i] =
        active[i] ? Eigen::Vector3d(omega * (inverse_diagonal[i] * (x[i] - gather(i, yd)))) : Eigen::Vector3d::Zero();
}

void BlockMatrix::lowerSolve(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y,
                             std::span<const Eigen::Matrix3d> inverse_diagonal, std::span<const std::uint8_t> active,
                             double omega, std::span<Quad> push) const noexcept {
  for (Quad& q : push) q = Quad{{0.0, 0.0, 0.0, 0.0}};
  for (std::size_t i = 0; i < diagonal_.size(); ++i) {
    if (!active[i]) {
      y[i].setZero();
      continue;
    }
    const double* p = push[i].v;  // sum_j<i L_ij y_j, complete: every earlier row has pushed
    y[i] = omega * (inverse_diagonal[i] * (x[i] - Eigen::Vector3d(p[0], p[1], p[2])));
    pushRow(i, y[i], push.data());
  }
}

void BlockMatrix::upperMultiply(std::span<const Eigen::Vector3d> x, std::span<Eigen::Vector3d> y,
                                std::span<const std::uint8_t> active, double omega) const noexcept {
  const double* xd = x.data()->data();
  for (std::size_t i = 0; i < diagonal_.size(); ++i)
    y[i] = active[i] ? Eigen::Vector3d(blockProduct(diagonal_[i], xd + 3 * i) / omega + gather(i, xd))
                     : Eigen::Vector3d::Zero();
}

}  // namespace incise::physics::detail
