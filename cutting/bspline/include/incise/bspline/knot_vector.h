// Knot vectors and B-spline basis functions (The NURBS Book, 2nd ed., §2.5: A2.1 span search,
// A2.2 basis functions, A2.3 basis derivatives).
//
// A knot vector of a B-spline of order o (degree p = o - 1) with n control points holds n + o
// non-decreasing values; the parameter domain is [knots[p], knots[n]]. Every function here is pure,
// allocation-free where it writes into caller storage, and safe to call from any thread.
#pragma once

#include <span>
#include <string_view>
#include <vector>

namespace incise::bspline {

// Largest order the evaluators support without heap storage (stack arrays of this size).
inline constexpr int kMaxOrder = 16;

// Clamped uniform knots on [lo, hi]: o copies of lo, count - o evenly spaced interior knots, o copies
// of hi. Size count + order. Throws std::invalid_argument unless 2 <= order <= kMaxOrder,
// count >= order and lo < hi (all finite). Cost O(count + order).
std::vector<double> clampedUniformKnots(int order, int count, double lo = 0.0, double hi = 1.0);

// Checks that `knots` is a valid knot vector for `count` control points of `order`: size count + order,
// finite, non-decreasing, no interior multiplicity above `order`, a non-empty domain. `what` names the
// vector in the message ("u knots"). Throws std::invalid_argument naming the offending index and value.
void validateKnots(std::span<const double> knots, int order, int count, std::string_view what);

// Index s of the knot span holding t: knots[s] <= t < knots[s+1], with order-1 <= s <= count-1.
// At an interior knot of any multiplicity this is the span to its right (the + side of a C^-1 knot);
// at the domain's upper end it is the last non-empty span. t outside the domain is clamped to it.
// Cost O(log count). Does not validate.
int findSpan(std::span<const double> knots, int order, int count, double t) noexcept;

// Number of knots equal to t (exact comparison). Cost O(log size).
int knotMultiplicity(std::span<const double> knots, double t) noexcept;

// The `order` non-zero basis functions N_{s-p..s}(t) of span s into out[0..order-1] (A2.2).
// Sums to 1 (partition of unity). Cost O(order^2).
void basisFunctions(std::span<const double> knots, int order, int span, double t, double* out) noexcept;

// Basis functions and their derivatives up to `n_derivs` (A2.3): out is (n_derivs + 1) x order,
// row-major, row d holding the d-th derivatives of N_{s-p..s}. Derivatives above the degree are 0.
// Cost O(order^2 + n_derivs * order^2).
void basisDerivatives(std::span<const double> knots, int order, int span, double t, int n_derivs, double* out) noexcept;

// The Greville abscissa of control point i: the mean of knots[i+1 .. i+order-1]. Control points placed
// at the Greville abscissae reproduce the identity map (linear precision).
double grevilleAbscissa(std::span<const double> knots, int order, int i) noexcept;

}  // namespace incise::bspline
