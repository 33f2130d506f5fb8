#include "incise/bspline/fold_over.h"

#include "bspline_errors.h"

#include "incise/core/format.h"

#include <algorithm>
#include <array>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "incise/bspline/knot_vector.h"

namespace incise::bspline {

namespace {

using detail::kAxisName;

using Index3 = std::array<int, 3>;

FoldReport failure(const Index3& ijk, std::string message) {
  return FoldReport{false, ijk[0], ijk[1], ijk[2], std::move(message)};
}

const Eigen::Vector3d& controlAt(const BSplineVolume& volume, const Index3& ijk) {
  return volume.controls()[static_cast<size_t>(volume.controlIndex(ijk[0], ijk[1], ijk[2]))];
}

// Controls i and i+1 straddle a knot of full multiplicity: knots[i+1..i+o] coincide, so N_i and N_{i+1}
// share no support and the derivative factor (o-1) / (knots[i+o] - knots[i+1]) has a zero denominator.
bool straddlesFullKnot(const std::vector<double>& knots, int order, int i) {
  return knots[static_cast<size_t>(i + 1)] == knots[static_cast<size_t>(i + order)];
}

// Span s along `axis` is a non-empty knot cell.
bool nonEmptySpan(const BSplineVolume& volume, int axis, int s) {
  const auto& t = volume.knots(axis);
  return t[static_cast<size_t>(s)] < t[static_cast<size_t>(s + 1)];
}

// One control difference P(from + e_axis) - P(from) of a cell's support.
struct Difference {
  Eigen::Vector3d d;
  Index3 from;
};

// The differences along `axis` inside the support block starting at `first` (orders[a] controls per axis).
// Pairs with a zero knot denominator cannot occur in a non-empty cell's support; they are skipped anyway.
void collectDifferences(const BSplineVolume& volume, int axis, const Index3& first, std::vector<Difference>& out) {
  out.clear();
  const auto& knots = volume.knots(axis);
  const int order = volume.orders()[static_cast<size_t>(axis)];
  Index3 size = volume.orders();
  size[static_cast<size_t>(axis)] -= 1;
  for (int c = 0; c < size[2]; ++c) {
    for (int b = 0; b < size[1]; ++b) {
      for (int a = 0; a < size[0]; ++a) {
        const Index3 from{first[0] + a, first[1] + b, first[2] + c};
        if (straddlesFullKnot(knots, order, from[static_cast<size_t>(axis)])) continue;
        Index3 to = from;
        to[static_cast<size_t>(axis)] += 1;
        out.push_back({controlAt(volume, to) - controlAt(volume, from), from});
      }
    }
  }
}

std::string describeDifference(int axis, const Difference& d) {
  Index3 to = d.from;
  to[static_cast<size_t>(axis)] += 1;
  return std::string(kAxisName[axis]) + ": " + core::formatIndices(to) + " - " + core::formatIndices(d.from);
}

// The first triple of the cell with det(a, b, c) <= 0, as a failure report; ok otherwise.
FoldReport checkCell(const Index3& span, const std::array<std::vector<Difference>, 3>& diffs) {
  for (int a = 0; a < 3; ++a)  // cannot happen in a non-empty cell; an empty set would pass vacuously
    if (diffs[static_cast<size_t>(a)].empty())
      return failure(span, "checkJacobianPositive: knot cell (spans) " + core::formatIndices(span) + " has no " +
                               kAxisName[a] + "-differences");
  for (const Difference& b : diffs[1]) {
    for (const Difference& c : diffs[2]) {
      // det(a, b, c) = a . (b x c): one cross product serves every a.
      const Eigen::Vector3d bc = b.d.cross(c.d);
      for (const Difference& a : diffs[0]) {
        const double det = a.d.dot(bc);
        if (!(det > 0.0))
          return failure(span, "checkJacobianPositive: knot cell (spans) " + core::formatIndices(span) +
                                   ": det of control differences " + describeDifference(0, a) + ", " +
                                   describeDifference(1, b) + ", " + describeDifference(2, c) + " is " +
                                   core::formatNumber(det) + " <= 0: det J not proven positive");
      }
    }
  }
  return FoldReport{true, -1, -1, -1, {}};
}

// J at parameters t inside the cell with the given spans (one-sided at the cell's faces). Cost O(o^3).
Eigen::Matrix3d cellJacobian(const BSplineVolume& volume, const Index3& span, const double t[3]) {
  const Index3 orders = volume.orders();
  double ders[3][2 * kMaxOrder];  // row 0: values, row 1: first derivatives
  for (int a = 0; a < 3; ++a) basisDerivatives(volume.knots(a), orders[a], span[a], t[a], 1, ders[a]);
  Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();
  for (int k = 0; k < orders[2]; ++k) {
    for (int j = 0; j < orders[1]; ++j) {
      for (int i = 0; i < orders[0]; ++i) {
        const Index3 ijk{span[0] - orders[0] + 1 + i, span[1] - orders[1] + 1 + j, span[2] - orders[2] + 1 + k};
        const Eigen::Vector3d& p = controlAt(volume, ijk);
        jac.col(0) += ders[0][orders[0] + i] * ders[1][j] * ders[2][k] * p;
        jac.col(1) += ders[0][i] * ders[1][orders[1] + j] * ders[2][k] * p;
        jac.col(2) += ders[0][i] * ders[1][j] * ders[2][orders[2] + k] * p;
      }
    }
  }
  return jac;
}

// Sample s of n across [lo, hi]: both ends included for n >= 2, the midpoint for n == 1.
double sampleAt(double lo, double hi, int s, int n) {
  return n == 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * static_cast<double>(s) / (n - 1);
}

// Minimum of det J over the n^3 samples of one cell.
double cellMinDeterminant(const BSplineVolume& volume, const Index3& span, int n) {
  std::array<double, 2> range[3];
  for (int a = 0; a < 3; ++a) {
    const auto& t = volume.knots(a);
    range[a] = {t[static_cast<size_t>(span[a])], t[static_cast<size_t>(span[a] + 1)]};
  }
  double result = std::numeric_limits<double>::infinity();
  for (int sk = 0; sk < n; ++sk) {
    for (int sj = 0; sj < n; ++sj) {
      for (int si = 0; si < n; ++si) {
        const double t[3] = {sampleAt(range[0][0], range[0][1], si, n), sampleAt(range[1][0], range[1][1], sj, n),
                             sampleAt(range[2][0], range[2][1], sk, n)};
        result = std::min(result, cellJacobian(volume, span, t).determinant());
      }
    }
  }
  return result;
}

// Calls visit(span) for every non-empty knot cell, in i-fastest order, until it returns false.
template <typename Visit>
void forEachCell(const BSplineVolume& volume, Visit&& visit) {
  const Index3 orders = volume.orders();
  const Index3 counts = volume.controlCounts();
  for (int sw = orders[2] - 1; sw < counts[2]; ++sw) {
    if (!nonEmptySpan(volume, 2, sw)) continue;
    for (int sv = orders[1] - 1; sv < counts[1]; ++sv) {
      if (!nonEmptySpan(volume, 1, sv)) continue;
      for (int su = orders[0] - 1; su < counts[0]; ++su) {
        if (!nonEmptySpan(volume, 0, su)) continue;
        if (!visit(Index3{su, sv, sw})) return;
      }
    }
  }
}

}  // namespace

FoldReport checkAxisOrder(const BSplineVolume& volume, int axis) {
  if (axis < 0 || axis > 2)
    throw std::out_of_range("checkAxisOrder: axis " + std::to_string(axis) + " is not 0, 1 or 2");
  const auto& knots = volume.knots(axis);
  const int order = volume.orders()[static_cast<size_t>(axis)];
  const Index3 counts = volume.controlCounts();
  for (int k = 0; k < counts[2]; ++k) {
    for (int j = 0; j < counts[1]; ++j) {
      for (int i = 0; i < counts[0]; ++i) {
        const Index3 from{i, j, k};
        const int a = from[static_cast<size_t>(axis)];
        if (a + 1 >= counts[static_cast<size_t>(axis)] || straddlesFullKnot(knots, order, a)) continue;
        Index3 to = from;
        to[static_cast<size_t>(axis)] += 1;
        const double lo = controlAt(volume, from)[axis];
        const double hi = controlAt(volume, to)[axis];
        if (!(hi > lo))
          return failure(from, std::string("checkAxisOrder(") + kAxisName[axis] + "): control " +
                                   core::formatIndices(to) + " has component " + std::to_string(axis) + " = " +
                                   core::formatNumber(hi) + ", not above control " + core::formatIndices(from) + " = " +
                                   core::formatNumber(lo) + ": a fold-over (Theorem 1)");
      }
    }
  }
  return FoldReport{true, -1, -1, -1, {}};
}

FoldReport checkJacobianPositive(const BSplineVolume& volume) {
  const Index3 orders = volume.orders();
  // Scratch reused by every cell: the only allocations besides a failure message.
  std::array<std::vector<Difference>, 3> diffs;
  for (int a = 0; a < 3; ++a) {
    Index3 size = orders;
    size[static_cast<size_t>(a)] -= 1;
    diffs[static_cast<size_t>(a)].reserve(static_cast<size_t>(size[0] * size[1] * size[2]));
  }
  FoldReport report{true, -1, -1, -1, {}};
  forEachCell(volume, [&](const Index3& span) {
    const Index3 first{span[0] - orders[0] + 1, span[1] - orders[1] + 1, span[2] - orders[2] + 1};
    for (int a = 0; a < 3; ++a) collectDifferences(volume, a, first, diffs[static_cast<size_t>(a)]);
    report = checkCell(span, diffs);
    return report.ok;
  });
  return report;
}

double minJacobianDeterminant(const BSplineVolume& volume, int samples_per_cell) {
  if (samples_per_cell < 1)
    throw std::invalid_argument("minJacobianDeterminant: samples_per_cell = " + std::to_string(samples_per_cell) +
                                " is less than 1");
  double result = std::numeric_limits<double>::infinity();
  forEachCell(volume, [&](const Index3& span) {
    result = std::min(result, cellMinDeterminant(volume, span, samples_per_cell));
    return true;
  });
  return result;
}

}  // namespace incise::bspline
