#include "incise/bspline/knot_vector.h"

#include "bspline_errors.h"

#include "incise/core/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace incise::bspline {

namespace {

using detail::fail;

}  // namespace

std::vector<double> clampedUniformKnots(int order, int count, double lo, double hi) {
  if (order < 2 || order > kMaxOrder)
    fail("clampedUniformKnots: order " + std::to_string(order) + " is outside [2, " + std::to_string(kMaxOrder) + "]");
  if (count < order)
    fail("clampedUniformKnots: count " + std::to_string(count) + " is less than order " + std::to_string(order));
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
    fail("clampedUniformKnots: domain [" + core::formatNumber(lo) + ", " + core::formatNumber(hi) +
         "] is not a finite, non-empty interval");
  std::vector<double> knots(static_cast<size_t>(count + order));
  const int interior_spans = count - order + 1;
  for (int i = 0; i < count + order; ++i) {
    const int step = std::clamp(i - (order - 1), 0, interior_spans);
    // lo + (hi - lo) * step / spans, with the end points exact.
    knots[static_cast<size_t>(i)] =
        step == interior_spans ? hi : lo + (hi - lo) * static_cast<double>(step) / interior_spans;
  }
  return knots;
}

void validateKnots(std::span<const double> knots, int order, int count, std::string_view what) {
  const std::string name(what);
  if (order < 2 || order > kMaxOrder)
    fail(name + ": order " + std::to_string(order) + " is outside [2, " + std::to_string(kMaxOrder) + "]");
  if (count < order)
    fail(name + ": " + std::to_string(count) + " control points is fewer than order " + std::to_string(order));
  if (knots.size() != static_cast<size_t>(count + order))
    fail(name + ": " + std::to_string(knots.size()) +
         " knots, expected count + order = " + std::to_string(count + order));
  for (size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) fail(name + ": knot " + std::to_string(i) + " is " + core::formatNumber(knots[i]));
    if (i > 0 && knots[i] < knots[i - 1])
      fail(name + ": knot " + std::to_string(i) + " = " + core::formatNumber(knots[i]) + " decreases from knot " +
           std::to_string(i - 1) + " = " + core::formatNumber(knots[i - 1]));
  }
  const size_t p = static_cast<size_t>(order - 1);
  if (!(knots[p] < knots[static_cast<size_t>(count)]))
    fail(name + ": empty parameter domain [" + core::formatNumber(knots[p]) + ", " +
         core::formatNumber(knots[static_cast<size_t>(count)]) + "]");
  // Multiplicity above the order would make a zero-width gap in the basis.
  for (size_t i = 0; i + static_cast<size_t>(order) < knots.size(); ++i) {
    if (knots[i] == knots[i + static_cast<size_t>(order)])
      fail(name + ": knot " + core::formatNumber(knots[i]) + " at index " + std::to_string(i) +
           " has multiplicity above order " + std::to_string(order));
  }
}

int findSpan(std::span<const double> knots, int order, int count, double t) noexcept {
  const int p = order - 1;
  if (!(t > knots[static_cast<size_t>(p)])) {  // also catches NaN: clamp to the first span
    // First non-empty span from the left.
    int s = p;
    while (s < count - 1 && knots[static_cast<size_t>(s + 1)] <= knots[static_cast<size_t>(p)]) ++s;
    return s;
  }
  if (t >= knots[static_cast<size_t>(count)]) {
    // Last non-empty span: knots[s] < knots[count].
    int s = count - 1;
    while (s > p && knots[static_cast<size_t>(s)] >= knots[static_cast<size_t>(count)]) --s;
    return s;
  }
  const auto first = knots.begin() + p;
  const auto last = knots.begin() + count + 1;
  const int s = static_cast<int>(std::upper_bound(first, last, t) - knots.begin()) - 1;
  return std::clamp(s, p, count - 1);
}

int knotMultiplicity(std::span<const double> knots, double t) noexcept {
  const auto range = std::equal_range(knots.begin(), knots.end(), t);
  return static_cast<int>(range.second - range.first);
}

void basisFunctions(std::span<const double> knots, int order, int span, double t, double* out) noexcept {
  double left[kMaxOrder];
  double right[kMaxOrder];
  out[0] = 1.0;
  for (int j = 1; j < order; ++j) {
    left[j] = t - knots[static_cast<size_t>(span + 1 - j)];
    right[j] = knots[static_cast<size_t>(span + j)] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = out[r] / (right[r + 1] + left[j - r]);
      out[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    out[j] = saved;
  }
}

void basisDerivatives(std::span<const double> knots, int order, int span, double t, int n_derivs,
                      double* out) noexcept {
  const int p = order - 1;
  double ndu[kMaxOrder][kMaxOrder];  // ndu[j][r]: basis values (upper) and knot differences (lower)
  double left[kMaxOrder];
  double right[kMaxOrder];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots[static_cast<size_t>(span + 1 - j)];
    right[j] = knots[static_cast<size_t>(span + j)] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) out[j] = ndu[j][p];
  for (int d = 1; d <= n_derivs; ++d)
    for (int j = 0; j <= p; ++j) out[d * order + j] = 0.0;
  const int top = std::min(n_derivs, p);
  double a[2][kMaxOrder];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0;
    int s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= top; ++k) {
      double d = 0.0;
      const int rk = r - k;
      const int pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      out[k * order + r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= top; ++k) {
    for (int j = 0; j <= p; ++j) out[k * order + j] *= factor;
    factor *= (p - k);
  }
}

double grevilleAbscissa(std::span<const double> knots, int order, int i) noexcept {
  double sum = 0.0;
  for (int k = 1; k < order; ++k) sum += knots[static_cast<size_t>(i + k)];
  return sum / (order - 1);
}

}  // namespace incise::bspline
