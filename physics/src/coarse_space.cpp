#include "coarse_space.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

namespace incise::physics::detail {
namespace {

using Row6 = Eigen::Matrix<double, 3, 6>;

// y += B Z_j = [B | -B [d_j]x]: row r of B [d]x is (b_r x d)^T.
void addTimesModes(Row6& y, const Block& b, const Eigen::Vector3d& d) noexcept {
  for (int r = 0; r < 3; ++r) {
    const Eigen::Vector3d row(b(r, 0), b(r, 1), b(r, 2));
    y.block<1, 3>(r, 0) += row.transpose();
    y.block<1, 3>(r, 3) -= row.cross(d).transpose();
  }
}

// Z_i^T Y = [Y ; [d_i]x Y] (Z_i^T = [I ; [d_i]x]).
Eigen::Matrix<double, 6, 6> modesTimes(const Eigen::Vector3d& d, const Row6& y) noexcept {
  Eigen::Matrix<double, 6, 6> c;
  c.topRows<3>() = y;
  for (int k = 0; k < 6; ++k) c.block<3, 1>(3, k) = d.cross(y.col(k));
  return c;
}

}  // namespace

void CoarseSpace::reserve(std::size_t nodes, int max_aggregates) {
  const auto k = static_cast<Eigen::Index>(6 * std::max(max_aggregates, 0));
  aggregate_.reserve(nodes);
  offset_.reserve(nodes);
  order_.reserve(nodes);
  centre_.reserve(static_cast<std::size_t>(max_aggregates));
  count_.reserve(static_cast<std::size_t>(max_aggregates));
  coarse_.resize(k, k);
  g_.resize(k);
}

void CoarseSpace::split(int first, int count, int parts, std::span<const Eigen::Vector3d> rest_m, int& next) noexcept {
  const auto begin = order_.begin() + first;
  if (parts == 1) {
    for (auto it = begin; it != begin + count; ++it) aggregate_[static_cast<std::size_t>(*it)] = next;
    ++next;
    return;
  }
  Eigen::AlignedBox3d box;
  for (auto it = begin; it != begin + count; ++it) box.extend(rest_m[static_cast<std::size_t>(*it)]);
  Eigen::Index axis = 0;
  box.sizes().maxCoeff(&axis);
  const int left_parts = parts / 2;
  const int left = static_cast<int>(static_cast<long long>(count) * left_parts / parts);
  // Ties broken by node index: the same inputs, the same aggregates.
  std::nth_element(begin, begin + left, begin + count, [&](int p, int q) {
    const double a = rest_m[static_cast<std::size_t>(p)][axis], b = rest_m[static_cast<std::size_t>(q)][axis];
    return a < b || (a == b && p < q);
  });
  split(first, left, left_parts, rest_m, next);
  split(first + left, count - left, parts - left_parts, rest_m, next);
}

void CoarseSpace::partition(std::span<const Eigen::Vector3d> rest_m, std::span<const std::uint8_t> active,
                            int aggregates, int nodes_per_aggregate_min) noexcept {
  order_.clear();
  for (std::size_t i = 0; i < active.size(); ++i)
    if (active[i]) order_.push_back(static_cast<int>(i));
  const int n = static_cast<int>(order_.size());
  const int most = static_cast<int>(coarse_.rows() / 6);
  int k = std::min({aggregates, most, nodes_per_aggregate_min > 0 ? n / nodes_per_aggregate_min : n});
  if (k < 2) k = 0;
  aggregate_.assign(active.size(), -1);
  aggregates_ = 0;
  if (k > 0) split(0, n, k, rest_m, aggregates_);
  ready_ = false;
}

void CoarseSpace::addRow(int i, const Row6& y, int aj, bool diagonal) noexcept {
  const int ai = aggregate_[static_cast<std::size_t>(i)];
  const Eigen::Matrix<double, 6, 6> c = modesTimes(offset_[static_cast<std::size_t>(i)], y);
  if (diagonal)
    coarse_.block<6, 6>(6 * ai, 6 * ai) += c;
  else if (ai > aj)
    coarse_.block<6, 6>(6 * ai, 6 * aj) += c;
  else if (ai < aj)
    coarse_.block<6, 6>(6 * aj, 6 * ai) += c.transpose();
  else
    coarse_.block<6, 6>(6 * ai, 6 * ai) += c + c.transpose();
}

void CoarseSpace::addRows(const BlockMatrix& a, std::span<const std::uint8_t> active) noexcept {
  const int n = std::min(a.rows(), static_cast<int>(aggregate_.size()));  // nodes added since: no aggregate
  // Per row: sum_j A_ij Z_j over its blocks above the diagonal, one sum per aggregate of j (a row meets few).
  constexpr int kRoom = 8;
  std::array<Row6, kRoom> sums;
  std::array<int, kRoom> of{};
  for (int i = 0; i < n; ++i) {
    if (aggregate_[static_cast<std::size_t>(i)] < 0 || !active[static_cast<std::size_t>(i)]) continue;
    Row6 diagonal = Row6::Zero();
    addTimesModes(diagonal, a.diagonal(i), offset_[static_cast<std::size_t>(i)]);
    addRow(i, diagonal, -1, true);
    int used = 0;
    a.forEachUpper(i, [&](int j, const Block& block) {
      const int aj = j < n ? aggregate_[static_cast<std::size_t>(j)] : -1;
      if (aj < 0 || !active[static_cast<std::size_t>(j)]) return;
      int k = 0;
      while (k < used && of[static_cast<std::size_t>(k)] != aj) ++k;
      if (k == used) {  // an aggregate new to this row: a slot of its own (the last one flushed when full)
        if (used == kRoom)
          addRow(i, sums[kRoom - 1], of[kRoom - 1], false), k = kRoom - 1;
        else
          ++used;
        of[static_cast<std::size_t>(k)] = aj;
        sums[static_cast<std::size_t>(k)].setZero();
      }
      addTimesModes(sums[static_cast<std::size_t>(k)], block, offset_[static_cast<std::size_t>(j)]);
    });
    for (int k = 0; k < used; ++k) addRow(i, sums[static_cast<std::size_t>(k)], of[static_cast<std::size_t>(k)], false);
  }
}

bool CoarseSpace::factorise() noexcept {
  const Eigen::Index m = 6 * aggregates_;
  Eigen::Ref<Eigen::MatrixXd> c = coarse_.topLeftCorner(m, m);
  // A mode no node moves (the rotation about the line of an aggregate's collinear nodes) has a zero row;
  // it is decoupled (its right-hand side is zero too).
  const double largest = c.diagonal().cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) return false;
  for (Eigen::Index r = 0; r < m; ++r)
    if (!(c(r, r) > 1e-14 * largest)) c.row(r).setZero(), c.col(r).setZero(), c(r, r) = largest;
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(c);  // in place: the factor in c's lower part
  return llt.info() == Eigen::Success;
}

bool CoarseSpace::build(const BlockMatrix& a, std::span<const Eigen::Vector3d> x_m,
                        std::span<const std::uint8_t> active) noexcept {
  ready_ = false;
  const int k = aggregates_;
  if (k == 0) return false;
  centre_.assign(static_cast<std::size_t>(k), Eigen::Vector3d::Zero());
  count_.assign(static_cast<std::size_t>(k), 0);
  for (std::size_t i = 0; i < aggregate_.size(); ++i)
    if (const int g = aggregate_[i]; g >= 0)
      centre_[static_cast<std::size_t>(g)] += x_m[i], ++count_[static_cast<std::size_t>(g)];
  for (int g = 0; g < k; ++g) centre_[static_cast<std::size_t>(g)] /= std::max(count_[static_cast<std::size_t>(g)], 1);
  offset_.assign(aggregate_.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < aggregate_.size(); ++i)
    if (const int g = aggregate_[i]; g >= 0) offset_[i] = x_m[i] - centre_[static_cast<std::size_t>(g)];
  coarse_.topLeftCorner(6 * k, 6 * k).setZero();
  addRows(a, active);
  ready_ = factorise();
  return ready_;
}

double CoarseSpace::addCorrection(std::span<const Eigen::Vector3d> r, std::span<Eigen::Vector3d> z,
                                  std::span<const std::uint8_t> active) noexcept {
  const Eigen::Index m = 6 * aggregates_;
  auto g = g_.head(m);
  g.setZero();
  const std::size_t n = std::min(aggregate_.size(), active.size());
  for (std::size_t i = 0; i < n; ++i) {
    const int a = aggregate_[i];
    if (a < 0 || !active[i]) continue;
    g.segment<3>(6 * a) += r[i];
    g.segment<3>(6 * a + 3) += offset_[i].cross(r[i]);
  }
  const auto l = coarse_.topLeftCorner(m, m).triangularView<Eigen::Lower>();
  l.solveInPlace(g);
  l.transpose().solveInPlace(g);
  double rz = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const int a = aggregate_[i];
    if (a < 0 || !active[i]) continue;
    const Eigen::Vector3d u = g.segment<3>(6 * a) + g.segment<3>(6 * a + 3).cross(offset_[i]);
    z[i] += u;
    rz += r[i].dot(u);
  }
  return rz;
}

}  // namespace incise::physics::detail
