// A B-spline curve C(t) = sum_i P_i N_{i,p}(t) in R^3 (The NURBS Book, 2nd ed.: A3.1 point, A3.2
// derivatives, §5.2 Eq. 5.15 Boehm knot insertion) and its least-squares fit to points (§9.4.1). In
// incise the generator curve G(v) of a scalpel stroke is such a curve, fitted and re-fitted at 1 kHz.
//
// Shapes: order o = degree p + 1 in [2, kMaxOrder]; n >= o control points; n + o knots; the parameter
// domain is [knots[o-1], knots[n]]. Fitted curves are clamped with domain [0, 1].
// Units: parameters are dimensionless; positions in whatever unit the caller uses (metres in incise).
// Threads: const members and the free functions may be called from any number of threads at once;
// insertKnot needs exclusive access.
// Failure: std::invalid_argument with the offending value or index in the message; objects are left as
// they were (strong guarantee).
#pragma once

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "incise/bspline/knot_vector.h"

namespace incise::bspline {

class BSplineCurve {
 public:
  // knots: size controls.size() + order, checked by validateKnots; control points finite. Throws
  // std::invalid_argument naming the bad order, knot (index and value) or control point (index).
  // Cost O(n + o).
  BSplineCurve(int order, std::vector<double> knots, std::vector<Eigen::Vector3d> controls);

  // C(t) (A3.1). At an interior knot of full multiplicity (C^-1) the right-hand (+) side is taken.
  // Throws std::invalid_argument for NaN or t outside the domain. Cost O(log n + o^2).
  Eigen::Vector3d evaluate(double t) const;
  // d^n C / dt^n for n >= 1 (A3.2 through basisDerivatives), the right-hand derivative at knots and the
  // left-hand one at the domain's upper end; zero for n above the degree. Throws like evaluate, and for
  // n < 1. Cost O(log n + n o^2).
  Eigen::Vector3d derivative(double t, int n = 1) const;
  // C(t) without checks for callers that validated t: NaN and values outside the domain are clamped to
  // it. noexcept, no allocation. Cost O(log n + o^2).
  Eigen::Vector3d evaluateUnchecked(double t) const noexcept;
  // True when t is finite and inside the domain.
  bool inDomain(double t) const noexcept;

  // Boehm insertion of t, `times` times: the curve is unchanged, one more control point and knot per
  // insertion. t must lie strictly inside the domain and the resulting multiplicity may reach the order
  // (a C^-1 point: two coincident control points at C(t)). Cost O(times * (n + o)). Strong guarantee.
  void insertKnot(double t, int times = 1);

  int order() const noexcept { return order_; }
  int degree() const noexcept { return order_ - 1; }
  int controlCount() const noexcept { return static_cast<int>(controls_.size()); }
  const std::vector<double>& knots() const noexcept { return knots_; }
  const std::vector<Eigen::Vector3d>& controls() const noexcept { return controls_; }
  // [knots[o-1], knots[n]].
  std::array<double, 2> domain() const noexcept;

 private:
  void checkParameter(double t, const char* who) const;

  int order_;
  std::vector<double> knots_;
  std::vector<Eigen::Vector3d> controls_;
};

struct CurveFitOptions {
  int order = 4;          // o in [2, kMaxOrder]
  int control_count = 8;  // n + 1 in [o, #points]
};

struct CurveFit {
  BSplineCurve curve;              // clamped on [0, 1]; end controls = first and last point (interpolated)
  std::vector<double> parameters;  // t_k of each point, non-decreasing, t_0 = 0, t_m = 1
  double max_error;                // max_k |C(t_k) - Q_k|, in the points' unit
  double rms_error;                // sqrt(mean_k |C(t_k) - Q_k|^2), in the points' unit
};

// Chord-length parameters (Eq. 9.5): t_0 = 0, t_k - t_{k-1} = |Q_k - Q_{k-1}| / total length, t_m = 1.
// Consecutive duplicate points are allowed (equal parameters). Throws std::invalid_argument for fewer than
// two points, a non-finite point (index named) or all points coincident. Cost O(#points).
std::vector<double> chordLengthParameters(std::span<const Eigen::Vector3d> points);

// The clamped knots on [0, 1] of the averaging technique (Eq. 9.68, d = (m+1)/(n-p+1)) for m + 1
// parameters and control_count = n + 1: every knot span holds at least one parameter, which makes the
// normal equations positive definite for distinct parameters. Throws std::invalid_argument for a bad
// order or count, fewer parameters than control points, or parameters that are not non-decreasing from
// 0 to 1 (index named). Cost O(#parameters + control_count + order).
std::vector<double> averagingKnots(std::span<const double> parameters, int order, int control_count);

// Least-squares fit with fixed end points (§9.4.1, Eqs. 9.63-9.67) at chord-length parameters, knots by
// averagingKnots. The normal equations N^T N P = R are banded (bandwidth o) and solved by a sparse LDL^T.
// Cost O(#points * o^2 + control_count * o^2) time (A2.2 basis values and their outer products per point,
// then the band factorisation), O(#points + control_count * o) memory.
// Throws std::invalid_argument for bad options, fewer points than control_count, a non-finite point
// (index named), all points coincident, or points whose parameters do not determine the control points
// (too many repeated points for the number of control points).
CurveFit fitCurve(std::span<const Eigen::Vector3d> points, const CurveFitOptions& options = {});

// fitCurve at caller-chosen parameters (non-decreasing, parameters[0] = 0, parameters.back() = 1, one per
// point), e.g. to re-fit a stroke while keeping its parametrisation. Same cost and failures, plus a size
// mismatch or bad parameters (index named).
CurveFit fitCurveAtParameters(std::span<const Eigen::Vector3d> points, std::span<const double> parameters,
                              const CurveFitOptions& options = {});

}  // namespace incise::bspline
