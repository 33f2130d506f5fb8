#include "incise/bspline/knot_vector.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace incise;
using namespace incise::bspline;
using Catch::Matchers::Contains;

TEST_CASE("knot_vector: clamped uniform knots have order copies at each end and even steps", "[cutting]") {
  const auto knots = clampedUniformKnots(4, 7, 0.0, 2.0);
  REQUIRE(knots == std::vector<double>{0, 0, 0, 0, 0.5, 1.0, 1.5, 2, 2, 2, 2});
  REQUIRE(clampedUniformKnots(2, 2) == std::vector<double>{0, 0, 1, 1});
}

TEST_CASE("knot_vector: span search takes the right-hand span at interior knots", "[cutting]") {
  const std::vector<double> knots{0, 0, 0, 0.3, 0.3, 0.3, 0.5, 1, 1, 1};  // order 3, 7 controls
  REQUIRE(findSpan(knots, 3, 7, 0.0) == 2);
  REQUIRE(findSpan(knots, 3, 7, 0.2999) == 2);
  REQUIRE(findSpan(knots, 3, 7, 0.3) == 5);  // knots[5] = 0.3 <= t < knots[6] = 0.5
  REQUIRE(findSpan(knots, 3, 7, 0.7) == 6);
  REQUIRE(findSpan(knots, 3, 7, 1.0) == 6);  // upper end: last non-empty span
  REQUIRE(knotMultiplicity(knots, 0.3) == 3);
  REQUIRE(knotMultiplicity(knots, 0.4) == 0);
}

TEST_CASE("knot_vector: basis functions are a partition of unity and non-negative", "[cutting]") {
  std::mt19937_64 rng(1);
  for (int order = 2; order <= 7; ++order) {
    std::vector<double> knots = clampedUniformKnots(order, order + 5);
    knots[static_cast<size_t>(order + 1)] = knots[static_cast<size_t>(order)];  // a repeated interior knot
    for (int n = 0; n < 200; ++n) {
      const double t = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
      const int span = findSpan(knots, order, order + 5, t);
      double basis[kMaxOrder];
      basisFunctions(knots, order, span, t, basis);
      double sum = 0.0;
      for (int i = 0; i < order; ++i) {
        REQUIRE(basis[i] >= -1e-15);
        sum += basis[i];
      }
      REQUIRE(sum == Approx(1.0).margin(1e-14));
    }
  }
}

TEST_CASE("knot_vector: basis derivatives match finite differences", "[cutting]") {
  std::mt19937_64 rng(2);
  for (int order = 2; order <= 6; ++order) {
    const int count = order + 4;
    const auto knots = clampedUniformKnots(order, count);
    for (int n = 0; n < 100; ++n) {
      const double t = std::uniform_real_distribution<double>(0.01, 0.99)(rng);
      const int span = findSpan(knots, order, count, t);
      const double h = 1e-6;
      // Stay within one span so that the finite difference sees one polynomial piece.
      if (findSpan(knots, order, count, t - h) != span || findSpan(knots, order, count, t + h) != span) continue;
      double ders[3 * kMaxOrder], plus[kMaxOrder], minus[kMaxOrder], mid[kMaxOrder];
      basisDerivatives(knots, order, span, t, 2, ders);
      basisFunctions(knots, order, span, t + h, plus);
      basisFunctions(knots, order, span, t - h, minus);
      basisFunctions(knots, order, span, t, mid);
      for (int i = 0; i < order; ++i) {
        REQUIRE(ders[i] == Approx(mid[i]).margin(1e-14));
        REQUIRE(ders[order + i] == Approx((plus[i] - minus[i]) / (2 * h)).margin(1e-6));
        if (order >= 3)
          REQUIRE(ders[2 * order + i] == Approx((plus[i] - 2 * mid[i] + minus[i]) / (h * h)).margin(2e-2));
      }
    }
  }
}

TEST_CASE("knot_vector: Greville abscissae of clamped uniform knots reproduce the parameter", "[cutting]") {
  // sum_i greville_i N_i(t) = t (linear precision): the identity lattice rests on this.
  const int order = 4, count = 9;
  const auto knots = clampedUniformKnots(order, count, -1.0, 3.0);
  for (double t = -1.0; t <= 3.0; t += 0.0625) {
    const int span = findSpan(knots, order, count, t);
    double basis[kMaxOrder];
    basisFunctions(knots, order, span, t, basis);
    double x = 0.0;
    for (int i = 0; i < order; ++i) x += basis[i] * grevilleAbscissa(knots, order, span - order + 1 + i);
    REQUIRE(x == Approx(t).margin(1e-14));
  }
}

TEST_CASE("knot_vector: bad knot vectors are refused with the offending value", "[cutting]") {
  REQUIRE_THROWS_WITH(validateKnots(std::vector<double>{0, 0, 0.5, 0.4, 1, 1}, 2, 4, "u knots"),
                      Contains("u knots") && Contains("knot 3 = 0.4") && Contains("decreases"));
  REQUIRE_THROWS_WITH(validateKnots(std::vector<double>{0, 0, 1, 1}, 2, 3, "v knots"),
                      Contains("4 knots, expected count + order = 5"));
  REQUIRE_THROWS_WITH(validateKnots(std::vector<double>{0, 0, 1, 1}, 1, 3, "w knots"), Contains("order 1"));
  REQUIRE_THROWS_WITH(validateKnots(std::vector<double>{0, 0, NAN, 1, 1}, 2, 3, "u knots"), Contains("knot 2 is nan"));
  REQUIRE_THROWS_WITH(validateKnots(std::vector<double>{0, 0, 0.5, 0.5, 0.5, 1, 1}, 2, 5, "u knots"),
                      Contains("multiplicity above order 2"));
  REQUIRE_THROWS_WITH(clampedUniformKnots(3, 2), Contains("count 2 is less than order 3"));
  REQUIRE_THROWS_WITH(clampedUniformKnots(3, 4, 1.0, 1.0), Contains("[1, 1]"));
}
