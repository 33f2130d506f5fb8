#include "incise/bspline/bspline_volume.h"

#include "bspline_errors.h"

#include "incise/core/format.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "incise/bspline/knot_vector.h"
#include "incise/bspline/tensor_kernel.h"

namespace incise::bspline {

namespace {

using detail::kAxisName;

void checkAxis(int axis, const char* who) {
  if (axis < 0 || axis > 2)
    throw std::out_of_range(std::string(who) + ": axis " + std::to_string(axis) + " is not 0, 1 or 2");
}

// The two axes other than `axis`, in increasing order.
std::array<int, 2> otherAxes(int axis) {
  return axis == 0 ? std::array{1, 2} : axis == 1 ? std::array{0, 2} : std::array{0, 1};
}

// Linear index of the control at position a along `axis` and b, c along the other two axes.
int lineIndex(const std::array<int, 3>& counts, int axis, int a, int b, int c) {
  std::array<int, 3> ijk{};
  const auto others = otherAxes(axis);
  ijk[axis] = a;
  ijk[others[0]] = b;
  ijk[others[1]] = c;
  return ijk[0] + counts[0] * (ijk[1] + counts[1] * ijk[2]);
}

}  // namespace

BSplineVolume::BSplineVolume(std::array<int, 3> orders, std::array<std::vector<double>, 3> knots,
                             std::vector<Eigen::Vector3d> controls) {
  std::array<int, 3> counts{};
  for (int a = 0; a < 3; ++a) {
    const std::string what = std::string("BSplineVolume: ") + kAxisName[a] + " knots";
    if (orders[a] < 2 || orders[a] > kMaxOrder)
      throw std::invalid_argument(what + ": order " + std::to_string(orders[a]) + " is outside [2, " +
                                  std::to_string(kMaxOrder) + "]");
    counts[a] = static_cast<int>(knots[a].size()) - orders[a];
    validateKnots(knots[a], orders[a], counts[a], what);
  }
  const size_t expected = static_cast<size_t>(counts[0]) * counts[1] * counts[2];
  if (controls.size() != expected)
    throw std::invalid_argument("BSplineVolume: " + std::to_string(controls.size()) +
                                " control points, expected n_u * n_v * n_w = " + std::to_string(counts[0]) + " * " +
                                std::to_string(counts[1]) + " * " + std::to_string(counts[2]) + " = " +
                                std::to_string(expected));
  for (size_t index = 0; index < controls.size(); ++index) {
    if (!controls[index].allFinite()) {
      const int i = static_cast<int>(index % counts[0]);
      const int j = static_cast<int>((index / counts[0]) % counts[1]);
      const int k = static_cast<int>(index / (static_cast<size_t>(counts[0]) * counts[1]));
      throw std::invalid_argument("BSplineVolume: control point (" + std::to_string(i) + ", " + std::to_string(j) +
                                  ", " + std::to_string(k) + ") is " + core::formatPoint(controls[index]));
    }
  }
  orders_ = orders;
  counts_ = counts;
  knots_ = std::move(knots);
  controls_ = std::move(controls);
}

BSplineVolume BSplineVolume::identity(const Eigen::AlignedBox3d& box, std::array<int, 3> orders,
                                      std::array<int, 3> counts) {
  if (!box.min().allFinite() || !box.max().allFinite() || !(box.min().array() < box.max().array()).all())
    throw std::invalid_argument("BSplineVolume::identity: box " + core::formatPoint(Eigen::Vector3d(box.min())) +
                                " - " + core::formatPoint(Eigen::Vector3d(box.max())) +
                                " is not finite with min < max on every axis");
  BSplineVolume volume;
  std::array<std::vector<double>, 3> greville;
  for (int a = 0; a < 3; ++a) {
    volume.knots_[a] = clampedUniformKnots(orders[a], counts[a], box.min()[a], box.max()[a]);
    greville[a].resize(static_cast<size_t>(counts[a]));
    for (int i = 0; i < counts[a]; ++i)
      greville[a][static_cast<size_t>(i)] = grevilleAbscissa(volume.knots_[a], orders[a], i);
  }
  volume.orders_ = orders;
  volume.counts_ = counts;
  volume.controls_.resize(static_cast<size_t>(counts[0]) * counts[1] * counts[2]);
  for (int k = 0; k < counts[2]; ++k)
    for (int j = 0; j < counts[1]; ++j)
      for (int i = 0; i < counts[0]; ++i)
        volume.controls_[static_cast<size_t>(volume.controlIndex(i, j, k))] =
            Eigen::Vector3d(greville[0][static_cast<size_t>(i)], greville[1][static_cast<size_t>(j)],
                            greville[2][static_cast<size_t>(k)]);
  return volume;
}

bool BSplineVolume::inDomain(double u, double v, double w) const noexcept {
  const double t[3] = {u, v, w};
  for (int a = 0; a < 3; ++a) {
    const auto d = domain(a);
    if (!(t[a] >= d[0] && t[a] <= d[1])) return false;  // false for NaN too
  }
  return true;
}

void BSplineVolume::checkParameters(double u, double v, double w, const char* who) const {
  const double t[3] = {u, v, w};
  for (int a = 0; a < 3; ++a) {
    const auto d = domain(a);
    if (!(t[a] >= d[0] && t[a] <= d[1]))
      throw std::invalid_argument(std::string(who) + ": " + kAxisName[a] + " = " + core::formatNumber(t[a]) +
                                  " is outside the domain [" + core::formatNumber(d[0]) + ", " +
                                  core::formatNumber(d[1]) + "]");
  }
}

Eigen::Vector3d BSplineVolume::evaluate(double u, double v, double w) const {
  checkParameters(u, v, w, "BSplineVolume::evaluate");
  return evaluateUnchecked(u, v, w);
}

Eigen::Vector3d BSplineVolume::evaluateUnchecked(double u, double v, double w) const noexcept {
  const double t[3] = {u, v, w};
  double basis[3][kMaxOrder];
  int first[3];
  for (int a = 0; a < 3; ++a) {
    const int span = findSpan(knots_[a], orders_[a], counts_[a], t[a]);
    const auto d = domain(a);
    const double clamped = t[a] >= d[0] ? (t[a] <= d[1] ? t[a] : d[1]) : d[0];  // NaN -> d[0]
    basisFunctions(knots_[a], orders_[a], span, clamped, basis[a]);
    first[a] = span - (orders_[a] - 1);
  }
  return detail::tensorSum(controls_.data()->data(), counts_[0], counts_[1], controlIndex(first[0], first[1], first[2]),
                           orders_, basis[0], basis[1], basis[2]);
}

Eigen::Matrix3d BSplineVolume::jacobian(double u, double v, double w) const {
  checkParameters(u, v, w, "BSplineVolume::jacobian");
  const double t[3] = {u, v, w};
  double ders[3][2 * kMaxOrder];  // row 0: values, row 1: first derivatives
  int first[3];
  for (int a = 0; a < 3; ++a) {
    const int span = findSpan(knots_[a], orders_[a], counts_[a], t[a]);
    basisDerivatives(knots_[a], orders_[a], span, t[a], 1, ders[a]);
    first[a] = span - (orders_[a] - 1);
  }
  const int ou = orders_[0], ov = orders_[1], ow = orders_[2];
  Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();
  for (int k = 0; k < ow; ++k) {
    for (int j = 0; j < ov; ++j) {
      for (int i = 0; i < ou; ++i) {
        const Eigen::Vector3d& p =
            controls_[static_cast<size_t>(controlIndex(first[0] + i, first[1] + j, first[2] + k))];
        jac.col(0) += ders[0][ou + i] * ders[1][j] * ders[2][k] * p;
        jac.col(1) += ders[0][i] * ders[1][ov + j] * ders[2][k] * p;
        jac.col(2) += ders[0][i] * ders[1][j] * ders[2][ow + k] * p;
      }
    }
  }
  return jac;
}

void BSplineVolume::insertKnot(int axis, double t, int times) {
  checkAxis(axis, "BSplineVolume::insertKnot");
  const std::string who = std::string("BSplineVolume::insertKnot(") + kAxisName[axis] + "): ";
  const auto d = domain(axis);
  if (!(t > d[0] && t < d[1]))
    throw std::invalid_argument(who + "t = " + core::formatNumber(t) + " is not strictly inside the domain (" +
                                core::formatNumber(d[0]) + ", " + core::formatNumber(d[1]) + ")");
  const int order = orders_[axis];
  const int existing = knotMultiplicity(knots_[axis], t);
  if (times < 1 || existing + times > order)
    throw std::invalid_argument(who + "inserting t = " + core::formatNumber(t) + " " + std::to_string(times) +
                                " times onto multiplicity " + std::to_string(existing) +
                                " would leave it outside [1, order = " + std::to_string(order) + "]");

  // Work on copies: the object changes only once everything succeeded (strong guarantee).
  std::vector<double> knots = knots_[axis];
  std::vector<Eigen::Vector3d> controls = controls_;
  std::array<int, 3> counts = counts_;
  const int p = order - 1;
  const auto [b_axis, c_axis] = otherAxes(axis);
  for (int r = 0; r < times; ++r) {
    const int n = counts[axis];
    const int span = findSpan(knots, order, n, t);
    std::array<int, 3> new_counts = counts;
    new_counts[axis] = n + 1;
    std::vector<Eigen::Vector3d> next(static_cast<size_t>(new_counts[0]) * new_counts[1] * new_counts[2]);
    // Boehm: Q_i = a_i P_i + (1 - a_i) P_{i-1}, a_i = 1 for i <= span - p, 0 for i > span.
    for (int c = 0; c < counts[c_axis]; ++c) {
      for (int b = 0; b < counts[b_axis]; ++b) {
        const auto at = [&](int i) -> const Eigen::Vector3d& {
          return controls[static_cast<size_t>(lineIndex(counts, axis, i, b, c))];
        };
        for (int i = 0; i <= n; ++i) {
          Eigen::Vector3d q;
          if (i <= span - p) {
            q = at(i);
          } else if (i > span) {
            q = at(i - 1);
          } else {
            const double alpha = (t - knots[static_cast<size_t>(i)]) /
                                 (knots[static_cast<size_t>(i + p)] - knots[static_cast<size_t>(i)]);
            q = alpha * at(i) + (1.0 - alpha) * at(i - 1);
          }
          next[static_cast<size_t>(lineIndex(new_counts, axis, i, b, c))] = q;
        }
      }
    }
    knots.insert(knots.begin() + span + 1, t);
    controls.swap(next);
    counts = new_counts;
  }
  knots_[axis].swap(knots);
  controls_.swap(controls);
  counts_ = counts;
}

const std::vector<double>& BSplineVolume::knots(int axis) const {
  checkAxis(axis, "BSplineVolume::knots");
  return knots_[axis];
}

std::array<double, 2> BSplineVolume::domain(int axis) const {
  const auto& k = knots_[static_cast<size_t>(axis)];
  return {k[static_cast<size_t>(orders_[axis] - 1)], k[static_cast<size_t>(counts_[axis])]};
}

Eigen::AlignedBox3d BSplineVolume::parameterBox() const {
  Eigen::Vector3d lo, hi;
  for (int a = 0; a < 3; ++a) {
    const auto d = domain(a);
    lo[a] = d[0];
    hi[a] = d[1];
  }
  return Eigen::AlignedBox3d(lo, hi);
}

void BSplineVolume::checkIndex(int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i >= counts_[0] || j >= counts_[1] || k >= counts_[2])
    throw std::out_of_range("BSplineVolume: control (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                            std::to_string(k) + ") outside the " + std::to_string(counts_[0]) + " x " +
                            std::to_string(counts_[1]) + " x " + std::to_string(counts_[2]) + " lattice");
}

const Eigen::Vector3d& BSplineVolume::control(int i, int j, int k) const {
  checkIndex(i, j, k);
  return controls_[static_cast<size_t>(controlIndex(i, j, k))];
}

void BSplineVolume::fillControls(const Eigen::Vector3d& p) {
  if (!p.allFinite())
    throw std::invalid_argument("BSplineVolume::fillControls: point " + core::formatPoint(p) + " is not finite");
  std::fill(controls_.begin(), controls_.end(), p);
}

void BSplineVolume::setControl(int i, int j, int k, const Eigen::Vector3d& p) {
  checkIndex(i, j, k);
  if (!p.allFinite())
    throw std::invalid_argument("BSplineVolume::setControl(" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                                std::to_string(k) + "): point " + core::formatPoint(p) + " is not finite");
  controls_[static_cast<size_t>(controlIndex(i, j, k))] = p;
}

}  // namespace incise::bspline
