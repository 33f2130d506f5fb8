#include "incise/bspline/bspline_curve.h"

#include "bspline_errors.h"

#include "incise/core/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace incise::bspline {

namespace {

using detail::fail;

size_t at(int i) { return static_cast<size_t>(i); }

// One Boehm insertion (Eq. 5.15) of t, strictly inside the domain, into copies the caller owns.
void insertOnce(int order, double t, std::vector<double>& knots, std::vector<Eigen::Vector3d>& controls) {
  const int p = order - 1;
  const int n = static_cast<int>(controls.size());
  const int k = findSpan(knots, order, n, t);
  std::vector<Eigen::Vector3d> refined;
  refined.reserve(controls.size() + 1);
  for (int i = 0; i <= k - p; ++i) refined.push_back(controls[at(i)]);
  for (int i = k - p + 1; i <= k; ++i) {
    // knots[i + p] >= knots[k + 1] > t >= knots[i], so the denominator is positive.
    const double alpha = (t - knots[at(i)]) / (knots[at(i + p)] - knots[at(i)]);
    refined.push_back(alpha * controls[at(i)] + (1.0 - alpha) * controls[at(i - 1)]);
  }
  for (int i = k + 1; i <= n; ++i) refined.push_back(controls[at(i - 1)]);
  knots.insert(knots.begin() + k + 1, t);
  controls.swap(refined);
}

void checkFitShape(size_t point_count, int order, int control_count, const char* who) {
  if (order < 2 || order > kMaxOrder)
    fail(std::string(who) + ": order " + std::to_string(order) + " is outside [2, " + std::to_string(kMaxOrder) + "]");
  if (control_count < order)
    fail(std::string(who) + ": control_count " + std::to_string(control_count) + " is less than order " +
         std::to_string(order));
  if (point_count < static_cast<size_t>(control_count))
    fail(std::string(who) + ": " + std::to_string(point_count) + " points, fewer than control_count " +
         std::to_string(control_count));
}

void checkFinite(std::span<const Eigen::Vector3d> points, const char* who) {
  for (size_t k = 0; k < points.size(); ++k)
    if (!points[k].allFinite())
      fail(std::string(who) + ": point " + std::to_string(k) + " = " + core::formatPoint(points[k]) + " is not finite");
}

void checkParameters(std::span<const double> parameters, const char* who) {
  const std::string name(who);
  if (parameters.empty()) fail(name + ": no parameters");
  if (parameters.front() != 0.0)
    fail(name + ": parameter 0 is " + core::formatNumber(parameters.front()) + ", expected 0");
  for (size_t k = 1; k < parameters.size(); ++k)
    if (!(parameters[k] >= parameters[k - 1]))  // also catches NaN
      fail(name + ": parameter " + std::to_string(k) + " = " + core::formatNumber(parameters[k]) +
           " is not >= parameter " + std::to_string(k - 1) + " = " + core::formatNumber(parameters[k - 1]));
  if (parameters.back() != 1.0)
    fail(name + ": parameter " + std::to_string(parameters.size() - 1) + " is " +
         core::formatNumber(parameters.back()) + ", expected 1");
}

size_t distinctCount(std::span<const double> sorted) {
  size_t count = 0;
  for (size_t k = 0; k < sorted.size(); ++k)
    if (k == 0 || sorted[k] != sorted[k - 1]) ++count;
  return count;
}

// Normal equations (N^T N) P = R of Eqs. 9.63-9.67 for the interior control points P_1..P_{n-1}. A point
// touches `order` basis functions, so N^T N has bandwidth `order` and is kept as its lower band:
// band(r, d) = (N^T N)(r + d, r).
struct NormalEquations {
  Eigen::MatrixXd band;
  Eigen::MatrixX3d rhs;
};

NormalEquations assembleNormalEquations(std::span<const Eigen::Vector3d> points, std::span<const double> parameters,
                                        std::span<const double> knots, int order, int control_count) {
  const int p = order - 1;
  const int n = control_count - 1;
  const int unknowns = n - 1;
  NormalEquations equations{Eigen::MatrixXd::Zero(unknowns, order), Eigen::MatrixX3d::Zero(unknowns, 3)};
  double basis[kMaxOrder];
  for (size_t k = 1; k + 1 < points.size(); ++k) {
    const double t = parameters[k];
    const int span = findSpan(knots, order, control_count, t);
    basisFunctions(knots, order, span, t, basis);
    const int first = span - p;  // control index of basis[0]
    // R_k of Eq. 9.63: the fixed end points moved to the right-hand side.
    Eigen::Vector3d r = points[k];
    if (first == 0) r -= basis[0] * points.front();
    if (span == n) r -= basis[p] * points.back();
    for (int a = 0; a < order; ++a) {
      const int row = first + a - 1;
      if (row < 0 || row >= unknowns) continue;
      equations.rhs.row(row) += basis[a] * r.transpose();
      for (int b = a; b < order && first + b - 1 < unknowns; ++b) equations.band(row, b - a) += basis[a] * basis[b];
    }
  }
  return equations;
}

// Sparse LDL^T in natural order: on a band it fills in only inside the band, O(unknowns * order^2).
// Returns false when the system is (numerically) singular.
bool solveBanded(const NormalEquations& equations, Eigen::MatrixX3d& solution) {
  const auto unknowns = equations.band.rows();
  const auto order = equations.band.cols();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(unknowns * order));
  double largest_diagonal = 0.0;
  for (Eigen::Index row = 0; row < unknowns; ++row) {
    largest_diagonal = std::max(largest_diagonal, equations.band(row, 0));
    for (Eigen::Index d = 0; d < order && row + d < unknowns; ++d)
      entries.emplace_back(static_cast<int>(row + d), static_cast<int>(row), equations.band(row, d));
  }
  Eigen::SparseMatrix<double> normal(unknowns, unknowns);
  normal.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt(normal);
  if (ldlt.info() != Eigen::Success) return false;
  // A pivot this small against the largest diagonal means a condition number beyond 1e12: some basis
  // function is (nearly) unsupported by the parameters and its control point is arbitrary.
  constexpr double kPivotRatio = 1e-12;
  const Eigen::VectorXd& pivots = ldlt.vectorD();
  for (Eigen::Index i = 0; i < pivots.size(); ++i)
    if (!(pivots[i] > kPivotRatio * largest_diagonal)) return false;
  solution = ldlt.solve(equations.rhs);
  return solution.allFinite();
}

std::vector<Eigen::Vector3d> solveControls(std::span<const Eigen::Vector3d> points, std::span<const double> parameters,
                                           std::span<const double> knots, int order, int control_count) {
  std::vector<Eigen::Vector3d> controls(at(control_count));
  controls.front() = points.front();
  controls.back() = points.back();
  if (control_count == 2) return controls;  // no interior control points
  Eigen::MatrixX3d interior;
  if (!solveBanded(assembleNormalEquations(points, parameters, knots, order, control_count), interior))
    fail("fitCurve: the parameters do not determine the control points (" + std::to_string(distinctCount(parameters)) +
         " distinct parameters among " + std::to_string(points.size()) + " points for " +
         std::to_string(control_count) + " control points; too many repeated points?)");
  for (Eigen::Index i = 0; i < interior.rows(); ++i) controls[static_cast<size_t>(i + 1)] = interior.row(i);
  return controls;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// BSplineCurve

BSplineCurve::BSplineCurve(int order, std::vector<double> knots, std::vector<Eigen::Vector3d> controls)
    : order_(order), knots_(std::move(knots)), controls_(std::move(controls)) {
  validateKnots(knots_, order_, controlCount(), "BSplineCurve knots");
  for (size_t i = 0; i < controls_.size(); ++i)
    if (!controls_[i].allFinite())
      fail("BSplineCurve: control point " + std::to_string(i) + " = " + core::formatPoint(controls_[i]) +
           " is not finite");
}

std::array<double, 2> BSplineCurve::domain() const noexcept {
  return {knots_[at(order_ - 1)], knots_[controls_.size()]};
}

bool BSplineCurve::inDomain(double t) const noexcept {
  const auto [lo, hi] = domain();
  return t >= lo && t <= hi;  // false for NaN
}

void BSplineCurve::checkParameter(double t, const char* who) const {
  if (inDomain(t)) return;
  const auto [lo, hi] = domain();
  fail(std::string(who) + ": t = " + core::formatNumber(t) + " is outside the domain [" + core::formatNumber(lo) +
       ", " + core::formatNumber(hi) + "]");
}

Eigen::Vector3d BSplineCurve::evaluate(double t) const {
  checkParameter(t, "BSplineCurve::evaluate");
  return evaluateUnchecked(t);
}

Eigen::Vector3d BSplineCurve::evaluateUnchecked(double t) const noexcept {
  const auto [lo, hi] = domain();
  if (!(t >= lo)) t = lo;  // NaN too: the basis recurrence would spread it into every coefficient
  if (t > hi) t = hi;
  const int span = findSpan(knots_, order_, controlCount(), t);
  double basis[kMaxOrder];
  basisFunctions(knots_, order_, span, t, basis);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int j = 0; j < order_; ++j) c += basis[j] * controls_[at(span - degree() + j)];
  return c;
}

Eigen::Vector3d BSplineCurve::derivative(double t, int n) const {
  checkParameter(t, "BSplineCurve::derivative");
  if (n < 1) fail("BSplineCurve::derivative: derivative order n = " + std::to_string(n) + " is below 1");
  if (n > degree()) return Eigen::Vector3d::Zero();
  const int span = findSpan(knots_, order_, controlCount(), t);
  double ders[kMaxOrder * kMaxOrder];  // (n + 1) x order with n <= degree
  basisDerivatives(knots_, order_, span, t, n, ders);
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (int j = 0; j < order_; ++j) d += ders[n * order_ + j] * controls_[at(span - degree() + j)];
  return d;
}

void BSplineCurve::insertKnot(double t, int times) {
  const auto [lo, hi] = domain();
  if (!(t > lo && t < hi))
    fail("BSplineCurve::insertKnot: t = " + core::formatNumber(t) + " is not strictly inside the domain [" +
         core::formatNumber(lo) + ", " + core::formatNumber(hi) + "]");
  if (times < 1) fail("BSplineCurve::insertKnot: times = " + std::to_string(times) + " is below 1");
  const int multiplicity = knotMultiplicity(knots_, t);
  if (multiplicity + times > order_)
    fail("BSplineCurve::insertKnot: inserting t = " + core::formatNumber(t) + " " + std::to_string(times) +
         " times would raise its multiplicity " + std::to_string(multiplicity) + " above the order " +
         std::to_string(order_));
  // Work on copies and commit with non-throwing swaps: the strong guarantee.
  std::vector<double> knots = knots_;
  std::vector<Eigen::Vector3d> controls = controls_;
  for (int r = 0; r < times; ++r) insertOnce(order_, t, knots, controls);
  knots_.swap(knots);
  controls_.swap(controls);
}

// ---------------------------------------------------------------------------------------------------------
// Fitting (§9.4.1)

std::vector<double> chordLengthParameters(std::span<const Eigen::Vector3d> points) {
  if (points.size() < 2) fail("chordLengthParameters: " + std::to_string(points.size()) + " points, need at least 2");
  checkFinite(points, "chordLengthParameters");
  std::vector<double> parameters(points.size(), 0.0);
  double total = 0.0;
  for (size_t k = 1; k < points.size(); ++k) {
    total += (points[k] - points[k - 1]).norm();
    parameters[k] = total;
  }
  if (!(total > 0.0))
    fail("chordLengthParameters: all " + std::to_string(points.size()) +
         " points coincide with point 0 = " + core::formatPoint(points.front()));
  if (!std::isfinite(total))
    fail("chordLengthParameters: the total chord length overflows (point 0 = " + core::formatPoint(points.front()) +
         ")");
  for (double& t : parameters) t /= total;
  parameters.back() = 1.0;
  return parameters;
}

std::vector<double> averagingKnots(std::span<const double> parameters, int order, int control_count) {
  checkFitShape(parameters.size(), order, control_count, "averagingKnots");
  checkParameters(parameters, "averagingKnots");
  const int p = order - 1;
  const int n = control_count - 1;
  const long long points = static_cast<long long>(parameters.size());  // m + 1
  const long long spans = n - p + 1;
  std::vector<double> knots(at(control_count + order), 0.0);
  std::fill(knots.end() - order, knots.end(), 1.0);
  for (int j = 1; j <= n - p; ++j) {
    // j * d = j (m+1) / (n-p+1) split into integer and fractional parts in exact integer arithmetic.
    const long long scaled = j * points;
    const auto i = static_cast<size_t>(scaled / spans);
    const double alpha = static_cast<double>(scaled % spans) / static_cast<double>(spans);
    knots[at(p + j)] = (1.0 - alpha) * parameters[i - 1] + alpha * parameters[i];
  }
  return knots;
}

CurveFit fitCurve(std::span<const Eigen::Vector3d> points, const CurveFitOptions& options) {
  checkFitShape(points.size(), options.order, options.control_count, "fitCurve");
  const std::vector<double> parameters = chordLengthParameters(points);
  return fitCurveAtParameters(points, parameters, options);
}

CurveFit fitCurveAtParameters(std::span<const Eigen::Vector3d> points, std::span<const double> parameters,
                              const CurveFitOptions& options) {
  const int order = options.order;
  const int count = options.control_count;
  checkFitShape(points.size(), order, count, "fitCurve");
  if (parameters.size() != points.size())
    fail("fitCurve: " + std::to_string(parameters.size()) + " parameters for " + std::to_string(points.size()) +
         " points");
  checkFinite(points, "fitCurve");
  std::vector<double> knots = averagingKnots(parameters, order, count);
  // Runs of equal parameters can stack averaged knots beyond the order.
  validateKnots(knots, order, count, "fitCurve: averaged knots (too many repeated points?)");
  std::vector<Eigen::Vector3d> controls = solveControls(points, parameters, knots, order, count);
  CurveFit fit{BSplineCurve(order, std::move(knots), std::move(controls)),
               std::vector<double>(parameters.begin(), parameters.end()), 0.0, 0.0};
  double sum_squares = 0.0;
  for (size_t k = 0; k < points.size(); ++k) {
    const double error = (fit.curve.evaluateUnchecked(parameters[k]) - points[k]).norm();
    fit.max_error = std::max(fit.max_error, error);
    sum_squares += error * error;
  }
  fit.rms_error = std::sqrt(sum_squares / static_cast<double>(points.size()));
  return fit;
}

}  // namespace incise::bspline
