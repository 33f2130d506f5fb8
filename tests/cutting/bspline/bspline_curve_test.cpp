#include "incise/bspline/bspline_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

using Catch::Contains;
using Eigen::Vector3d;
using incise::bspline::averagingKnots;
using incise::bspline::BSplineCurve;
using incise::bspline::chordLengthParameters;
using incise::bspline::CurveFitOptions;
using incise::bspline::fitCurve;
using incise::bspline::fitCurveAtParameters;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Vector3d randomPoint(std::mt19937& rng) {
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  return {coord(rng), coord(rng), coord(rng)};
}

std::vector<Vector3d> randomPoints(std::mt19937& rng, int count) {
  std::vector<Vector3d> points;
  for (int i = 0; i < count; ++i) points.push_back(randomPoint(rng));
  return points;
}

// de Casteljau on [0, 1]: the reference a clamped Bezier B-spline must reproduce.
Vector3d deCasteljau(std::vector<Vector3d> controls, double s) {
  for (size_t level = 1; level < controls.size(); ++level)
    for (size_t i = 0; i + level < controls.size(); ++i) controls[i] = (1.0 - s) * controls[i] + s * controls[i + 1];
  return controls.front();
}

// A cubic with non-uniform knots, an interior double knot (C^1 there) and domain [-1, 2].
BSplineCurve randomCubic(std::mt19937& rng) {
  std::vector<double> knots = {-1, -1, -1, -1, -0.4, 0.1, 0.1, 0.9, 1.3, 2, 2, 2, 2};
  return BSplineCurve(4, knots, randomPoints(rng, static_cast<int>(knots.size()) - 4));
}

BSplineCurve randomCurve(std::mt19937& rng, int order) {
  const int count = order + 4;
  std::vector<double> knots(static_cast<size_t>(order), 0.0);
  std::uniform_real_distribution<double> gap(0.1, 1.0);
  double knot = 0.0;
  for (int i = 0; i < count - order + 1; ++i) {
    knot += gap(rng);
    knots.push_back(knot);
  }
  knots.insert(knots.end(), static_cast<size_t>(order - 1), knot);
  return BSplineCurve(order, knots, randomPoints(rng, count));
}

double maxDistance(const BSplineCurve& a, const BSplineCurve& b, std::mt19937& rng, int samples) {
  const auto [lo, hi] = a.domain();
  std::uniform_real_distribution<double> param(lo, hi);
  double worst = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double t = param(rng);
    worst = std::max(worst, (a.evaluate(t) - b.evaluate(t)).norm());
  }
  worst = std::max(worst, (a.evaluate(lo) - b.evaluate(lo)).norm());
  return std::max(worst, (a.evaluate(hi) - b.evaluate(hi)).norm());
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Evaluation and derivatives

TEST_CASE("bspline_curve: a clamped curve with order control points is the Bezier curve of de Casteljau", "[cutting]") {
  std::mt19937 rng(11);
  for (int order = 2; order <= 6; ++order) {
    const std::vector<Vector3d> controls = randomPoints(rng, order);
    std::vector<double> knots(static_cast<size_t>(order), 2.0);  // domain [2, 5]
    knots.insert(knots.end(), static_cast<size_t>(order), 5.0);
    const BSplineCurve curve(order, knots, controls);
    for (double s : {0.0, 0.1, 0.25, 0.5, 0.7, 0.999, 1.0}) {
      INFO("order " << order << ", s " << s);
      CHECK((curve.evaluate(2.0 + 3.0 * s) - deCasteljau(controls, s)).norm() < 1e-14);
    }
    // End tangents of a Bezier: p (P_1 - P_0) and p (P_p - P_{p-1}), divided by the domain length 3.
    const double p = order - 1;
    CHECK((curve.derivative(2.0) - p / 3.0 * (controls[1] - controls[0])).norm() < 1e-13);
    CHECK((curve.derivative(5.0) - p / 3.0 * (controls[order - 1] - controls[order - 2])).norm() < 1e-13);
  }
}

TEST_CASE("bspline_curve: a quadratic at a simple interior knot is the midpoint of its two middle controls",
          "[cutting]") {
  // knots {0,0,0,1,2,2,2}: at t = 1, N_1 = N_2 = 1/2 and N_0 = N_3 = 0 (hand-computed from Cox-de Boor).
  const std::vector<Vector3d> controls = {{0, 0, 0}, {1, 2, 0}, {3, 2, 1}, {4, 0, 0}};
  const BSplineCurve curve(3, {0, 0, 0, 1, 2, 2, 2}, controls);
  CHECK((curve.evaluate(1.0) - Vector3d(2, 2, 0.5)).norm() < 1e-15);
  // At t = 0.5: N_0 = 1/4, N_1 = 5/8, N_2 = 1/8.
  const Vector3d expected = 0.25 * controls[0] + 0.625 * controls[1] + 0.125 * controls[2];
  CHECK((curve.evaluate(0.5) - expected).norm() < 1e-15);
  CHECK(curve.domain() == std::array<double, 2>{0.0, 2.0});
}

TEST_CASE("bspline_curve: derivatives match central finite differences at random parameters", "[cutting]") {
  std::mt19937 rng(12);
  const BSplineCurve cubic = randomCubic(rng);
  const BSplineCurve quintic = randomCurve(rng, 6);
  for (const BSplineCurve* curve : {&cubic, &quintic}) {
    const auto [lo, hi] = curve->domain();
    std::uniform_real_distribution<double> param(lo, hi);
    constexpr double h = 1e-5;
    int checked = 0;
    while (checked < 200) {
      const double t = param(rng);
      bool near_knot = t - h < lo || t + h > hi;
      for (double knot : curve->knots()) near_knot = near_knot || std::abs(t - knot) < 2 * h;
      if (near_knot) continue;  // the difference quotient would straddle a jump in a higher derivative
      ++checked;
      for (int n = 1; n <= curve->degree(); ++n) {
        const Vector3d plus = n == 1 ? curve->evaluate(t + h) : curve->derivative(t + h, n - 1);
        const Vector3d minus = n == 1 ? curve->evaluate(t - h) : curve->derivative(t - h, n - 1);
        const Vector3d difference = (plus - minus) / (2 * h);
        const Vector3d exact = curve->derivative(t, n);
        INFO("degree " << curve->degree() << ", n " << n << ", t " << t);
        REQUIRE((exact - difference).norm() <= 1e-6 * std::max(1.0, exact.norm()));
      }
    }
    CHECK(curve->derivative(0.5 * (lo + hi), curve->order()).norm() == 0.0);
  }
}

// ---------------------------------------------------------------------------------------------------------
// Knot insertion

TEST_CASE("bspline_curve: knot insertion leaves the curve unchanged", "[cutting]") {
  std::mt19937 rng(13);
  for (int order = 2; order <= 5; ++order) {
    for (int times = 1; times <= order; ++times) {
      const BSplineCurve original = randomCurve(rng, order);
      const auto [lo, hi] = original.domain();
      const double random_t = std::uniform_real_distribution<double>(lo, hi)(rng);
      const double existing_t = original.knots()[static_cast<size_t>(order + 1)];  // a simple interior knot
      for (double t : {random_t, existing_t}) {
        const int before = static_cast<int>(std::count(original.knots().begin(), original.knots().end(), t));
        if (before + times > order) continue;
        BSplineCurve refined = original;
        refined.insertKnot(t, times);
        INFO("order " << order << ", times " << times << ", t " << t);
        CHECK(refined.controlCount() == original.controlCount() + times);
        CHECK(std::count(refined.knots().begin(), refined.knots().end(), t) == before + times);
        CHECK(maxDistance(original, refined, rng, 200) < 1e-12);
      }
    }
  }
}

TEST_CASE(
    "bspline_curve: order insertions split the curve at two coincident controls and evaluate takes the "
    "right-hand side",
    "[cutting]") {
  std::mt19937 rng(14);
  BSplineCurve curve = randomCubic(rng);
  const double t = 0.5;
  const Vector3d on_curve = curve.evaluate(t);
  curve.insertKnot(t, curve.order());

  const auto& controls = curve.controls();
  int split = -1;
  for (size_t i = 0; i + 1 < controls.size(); ++i) {
    if ((controls[i] - controls[i + 1]).norm() < 1e-12) {
      CHECK(split == -1);  // exactly one coincident pair
      split = static_cast<int>(i);
    }
  }
  REQUIRE(split >= 0);
  CHECK((controls[static_cast<size_t>(split)] - on_curve).norm() < 1e-12);

  // Move the right-hand half away: the curve jumps at t and evaluate(t) must follow the right side.
  std::vector<Vector3d> moved = controls;
  const Vector3d offset(0.0, 0.0, 1.0);
  for (size_t i = static_cast<size_t>(split) + 1; i < moved.size(); ++i) moved[i] += offset;
  const BSplineCurve cut(curve.order(), curve.knots(), moved);
  CHECK((cut.evaluate(t) - (on_curve + offset)).norm() < 1e-12);
  CHECK((cut.evaluate(std::nextafter(t, 1.0)) - (on_curve + offset)).norm() < 1e-9);
  CHECK((cut.evaluate(std::nextafter(t, 0.0)) - on_curve).norm() < 1e-9);
}

// ---------------------------------------------------------------------------------------------------------
// Bad input

TEST_CASE("bspline_curve: construction rejects bad orders, knots and control points naming the value", "[cutting]") {
  const std::vector<Vector3d> four(4, Vector3d::Zero());
  const std::vector<double> knots = {0, 0, 0, 0.5, 1, 1, 1};
  CHECK_NOTHROW(BSplineCurve(3, knots, four));
  REQUIRE_THROWS_AS(BSplineCurve(3, {0, 0, 0, 0.75, 0.25, 1, 1}, four), std::invalid_argument);
  REQUIRE_THROWS_WITH(BSplineCurve(3, {0, 0, 0, 0.75, 0.25, 1, 1}, four), Contains("knot 4 = 0.25"));
  REQUIRE_THROWS_AS(BSplineCurve(3, {0, 0, 0, 1, 1, 1}, four), std::invalid_argument);
  REQUIRE_THROWS_WITH(BSplineCurve(3, {0, 0, 0, 1, 1, 1}, four), Contains("6 knots"));
  REQUIRE_THROWS_AS(BSplineCurve(1, {0, 0.25, 0.5, 0.75, 1}, four), std::invalid_argument);
  REQUIRE_THROWS_WITH(BSplineCurve(1, {0, 0.25, 0.5, 0.75, 1}, four), Contains("order 1"));
  std::vector<Vector3d> nan_control = four;
  nan_control[2].y() = kNaN;
  REQUIRE_THROWS_AS(BSplineCurve(3, knots, nan_control), std::invalid_argument);
  REQUIRE_THROWS_WITH(BSplineCurve(3, knots, nan_control), Contains("control point 2"));
}

TEST_CASE("bspline_curve: evaluation rejects NaN and parameters outside the domain naming the value", "[cutting]") {
  std::mt19937 rng(15);
  const BSplineCurve curve = randomCubic(rng);  // domain [-1, 2]
  REQUIRE_THROWS_AS(curve.evaluate(kNaN), std::invalid_argument);
  REQUIRE_THROWS_WITH(curve.evaluate(kNaN), Contains("nan"));
  REQUIRE_THROWS_WITH(curve.evaluate(2.5), Contains("2.5"));
  REQUIRE_THROWS_WITH(curve.evaluate(-1.25), Contains("-1.25"));
  REQUIRE_THROWS_WITH(curve.derivative(kNaN), Contains("nan"));
  REQUIRE_THROWS_WITH(curve.derivative(3.5), Contains("3.5"));
  REQUIRE_THROWS_AS(curve.derivative(0.5, 0), std::invalid_argument);
  REQUIRE_THROWS_WITH(curve.derivative(0.5, 0), Contains("n = 0"));
  CHECK_FALSE(curve.inDomain(kNaN));
  CHECK((curve.evaluateUnchecked(kNaN) - curve.evaluate(-1.0)).norm() == 0.0);
  CHECK((curve.evaluateUnchecked(7.0) - curve.evaluate(2.0)).norm() == 0.0);
}

TEST_CASE("bspline_curve: a rejected knot insertion names the value and leaves the curve unchanged", "[cutting]") {
  std::mt19937 rng(16);
  BSplineCurve curve = randomCubic(rng);  // 0.1 is a double knot
  const BSplineCurve original = curve;
  auto unchanged = [&] { return curve.knots() == original.knots() && curve.controls() == original.controls(); };

  REQUIRE_THROWS_AS(curve.insertKnot(0.1, 3), std::invalid_argument);
  REQUIRE_THROWS_WITH(curve.insertKnot(0.1, 3), Contains("t = 0.1 ") && Contains("multiplicity 2"));
  CHECK(unchanged());
  curve.insertKnot(0.6, 4);
  REQUIRE_THROWS_WITH(curve.insertKnot(0.6), Contains("t = 0.6 "));
  curve = original;
  REQUIRE_THROWS_WITH(curve.insertKnot(kNaN), Contains("nan"));
  REQUIRE_THROWS_WITH(curve.insertKnot(-1.0), Contains("-1"));  // the domain end is not strictly inside
  REQUIRE_THROWS_WITH(curve.insertKnot(2.5), Contains("2.5"));
  REQUIRE_THROWS_WITH(curve.insertKnot(0.5, 0), Contains("times = 0"));
  CHECK(unchanged());
}

// ---------------------------------------------------------------------------------------------------------
// Fitting

TEST_CASE("bspline_curve: fit: chord-length parameters are cumulative chord length over total length", "[cutting]") {
  const std::vector<Vector3d> points = {{0, 0, 0}, {3, 0, 0}, {3, 4, 0}, {3, 4, 0}, {3, 4, 7}};
  const std::vector<double> parameters = chordLengthParameters(points);
  REQUIRE(parameters.size() == 5);
  CHECK(parameters[0] == 0.0);
  CHECK(parameters[1] == Approx(3.0 / 14.0).epsilon(1e-15));
  CHECK(parameters[2] == Approx(0.5).epsilon(1e-15));
  CHECK(parameters[3] == parameters[2]);  // a consecutive duplicate has chord length 0
  CHECK(parameters[4] == 1.0);
}

TEST_CASE("bspline_curve: fit: averaging knots follow Eq. 9.68 with d = (m+1)/(n-p+1)", "[cutting]") {
  // m + 1 = 7 parameters, p = 2, n + 1 = 5: d = 7/3;
  // j = 1 -> i = 2, alpha = 1/3; j = 2 -> i = 4, alpha = 2/3.
  const std::vector<double> parameters = {0, 0.1, 0.3, 0.4, 0.6, 0.9, 1};
  const std::vector<double> knots = averagingKnots(parameters, 3, 5);
  const std::vector<double> expected = {0, 0, 0, 2.0 / 3.0 * 0.1 + 1.0 / 3.0 * 0.3, 1.0 / 3.0 * 0.4 + 2.0 / 3.0 * 0.6,
                                        1, 1, 1};
  REQUIRE(knots.size() == expected.size());
  for (size_t i = 0; i < knots.size(); ++i) CHECK(knots[i] == Approx(expected[i]).margin(1e-15));
  // Uniform parameters t_k = k/m give u_{p+j} = (j d - 1)/m: m + 1 = 10, p = 3, n + 1 = 6, d = 10/3.
  std::vector<double> uniform;
  for (int k = 0; k <= 9; ++k) uniform.push_back(k / 9.0);
  const std::vector<double> cubic_knots = averagingKnots(uniform, 4, 6);
  REQUIRE(cubic_knots.size() == 10);
  CHECK(cubic_knots[4] == Approx(7.0 / 27.0).margin(1e-15));
  CHECK(cubic_knots[5] == Approx(17.0 / 27.0).margin(1e-15));
}

TEST_CASE("bspline_curve: fit: a cubic polynomial sampled at given parameters is reproduced everywhere", "[cutting]") {
  std::mt19937 rng(17);
  const std::vector<Vector3d> bezier = randomPoints(rng, 4);
  std::vector<double> parameters = {0.0, 1.0};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 58; ++k) parameters.push_back(unit(rng));
  std::sort(parameters.begin(), parameters.end());
  std::vector<Vector3d> points;
  for (double s : parameters) points.push_back(deCasteljau(bezier, s));

  for (const CurveFitOptions options :
       {CurveFitOptions{4, 4}, CurveFitOptions{4, 7}, CurveFitOptions{4, 12}, CurveFitOptions{5, 9}}) {
    const auto fit = fitCurveAtParameters(points, parameters, options);
    INFO("order " << options.order << ", control_count " << options.control_count);
    CHECK(fit.max_error < 1e-9);
    double worst = 0.0;
    for (int i = 0; i <= 200; ++i) {
      const double s = i / 200.0;
      worst = std::max(worst, (fit.curve.evaluate(s) - deCasteljau(bezier, s)).norm());
    }
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("bspline_curve: fit: a spline sampled at the fit's own knots is recovered control point by control point",
          "[cutting]") {
  std::mt19937 rng(18);
  std::vector<double> parameters = {0.0, 1.0};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 38; ++k) parameters.push_back(unit(rng));
  std::sort(parameters.begin(), parameters.end());
  const CurveFitOptions options{4, 10};
  const BSplineCurve truth(options.order, averagingKnots(parameters, options.order, options.control_count),
                           randomPoints(rng, options.control_count));
  std::vector<Vector3d> points;
  for (double t : parameters) points.push_back(truth.evaluate(t));

  const auto fit = fitCurveAtParameters(points, parameters, options);
  CHECK(fit.curve.knots() == truth.knots());
  REQUIRE(fit.curve.controlCount() == truth.controlCount());
  for (size_t i = 0; i < truth.controls().size(); ++i) {
    INFO("control " << i);
    CHECK((fit.curve.controls()[i] - truth.controls()[i]).norm() < 1e-9);
  }
}

TEST_CASE("bspline_curve: fit: a noisy circle is fitted closely and its end points are interpolated exactly",
          "[cutting]") {
  std::mt19937 rng(19);
  constexpr double radius = 0.05;  // 5 cm, noise 0.05 mm
  constexpr double noise = 5e-5;
  std::uniform_real_distribution<double> jitter(-noise, noise);
  std::vector<Vector3d> points;
  for (int k = 0; k < 300; ++k) {
    const double angle = 1.5 * std::numbers::pi * k / 299.0;
    points.emplace_back(radius * std::cos(angle) + jitter(rng), radius * std::sin(angle) + jitter(rng), jitter(rng));
  }
  const auto fit = fitCurve(points, {4, 12});
  CHECK(fit.parameters.front() == 0.0);
  CHECK(fit.parameters.back() == 1.0);
  CHECK(fit.max_error < 3.0 * noise);
  CHECK(fit.rms_error < fit.max_error);
  CHECK(fit.rms_error > 0.3 * noise);  // least squares cannot follow the noise with 12 control points
  CHECK((fit.curve.evaluate(0.0) - points.front()).norm() < 1e-15);
  CHECK((fit.curve.evaluate(1.0) - points.back()).norm() < 1e-15);
  CHECK(fit.curve.controls().front() == points.front());
  CHECK(fit.curve.controls().back() == points.back());
  // Off the data the fitted curve stays on the circle too (within noise-level error).
  for (int i = 0; i <= 100; ++i) {
    const Vector3d p = fit.curve.evaluate(i / 100.0);
    CHECK(std::abs(std::hypot(p.x(), p.y()) - radius) < 2.0 * noise);
  }
}

TEST_CASE("bspline_curve: fit: consecutive duplicate points are allowed", "[cutting]") {
  std::vector<Vector3d> points;
  for (int k = 0; k < 20; ++k) {
    const Vector3d p(k * 0.1, std::sin(k * 0.3), 0.0);
    points.push_back(p);
    if (k % 4 == 0) points.push_back(p);  // duplicated, including the first point
  }
  points.push_back(points.back());  // and the last
  const auto fit = fitCurve(points, {3, 12});
  CHECK(fit.parameters[0] == fit.parameters[1]);
  CHECK(fit.parameters[fit.parameters.size() - 2] == 1.0);
  CHECK(fit.curve.controls().front() == points.front());
  CHECK(fit.max_error < 0.03);
}

TEST_CASE("bspline_curve: fit: bad input throws naming the offending value or index", "[cutting]") {
  std::vector<Vector3d> points;
  for (int k = 0; k < 10; ++k) points.emplace_back(k, k * k, 0.0);

  const std::vector<Vector3d> three(points.begin(), points.begin() + 3);
  REQUIRE_THROWS_AS(fitCurve(three), std::invalid_argument);
  REQUIRE_THROWS_WITH(fitCurve(three), Contains("3 points") && Contains("control_count 8"));

  std::vector<Vector3d> with_nan = points;
  with_nan[4].z() = kNaN;
  REQUIRE_THROWS_AS(fitCurve(with_nan), std::invalid_argument);
  REQUIRE_THROWS_WITH(fitCurve(with_nan), Contains("point 4"));

  const std::vector<Vector3d> equal(10, Vector3d(1.0, 2.0, 3.0));
  REQUIRE_THROWS_AS(fitCurve(equal), std::invalid_argument);
  REQUIRE_THROWS_WITH(fitCurve(equal), Contains("coincide") && Contains("point 0"));

  REQUIRE_THROWS_WITH(fitCurve(points, {1, 8}), Contains("order 1"));
  REQUIRE_THROWS_WITH(fitCurve(points, {4, 3}), Contains("control_count 3"));

  std::vector<double> parameters = chordLengthParameters(points);
  REQUIRE_THROWS_WITH(fitCurveAtParameters(points, std::span(parameters).first(9)), Contains("9 parameters"));
  parameters[5] = parameters[3];
  REQUIRE_THROWS_WITH(fitCurveAtParameters(points, parameters), Contains("parameter 5"));
  parameters = chordLengthParameters(points);
  parameters.back() = 0.999;
  REQUIRE_THROWS_WITH(fitCurveAtParameters(points, parameters), Contains("0.999"));

  // Ten points but only two distinct places: eight control points are not determined.
  std::vector<Vector3d> two_places(5, Vector3d::Zero());
  two_places.insert(two_places.end(), 5, Vector3d::UnitX());
  REQUIRE_THROWS_AS(fitCurve(two_places), std::invalid_argument);
  REQUIRE_THROWS_WITH(fitCurve(two_places), Contains("repeated points"));
  // Three distinct places, but only one interior parameter for two interior control points.
  std::vector<Vector3d> three_places(4, Vector3d::Zero());
  three_places.insert(three_places.end(), 3, Vector3d::UnitX());
  three_places.insert(three_places.end(), 3, Vector3d::UnitY());
  REQUIRE_THROWS_WITH(fitCurve(three_places, {3, 4}), Contains("3 distinct parameters"));
}
