// Tests for cutting/bspline/src/volume_inversion.cpp: Newton point inversion of a B-spline volume.
#include "incise/bspline/volume_inversion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "incise/bspline/fold_over.h"

namespace incise::bspline {
namespace {

const Eigen::AlignedBox3d kUnitBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());

BSplineVolume unitIdentity() { return BSplineVolume::identity(kUnitBox, {4, 4, 4}, {7, 7, 7}); }

Eigen::Vector3d randomIn(std::mt19937& rng, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Eigen::Vector3d x;
  for (int a = 0; a < 3; ++a) x[a] = std::uniform_real_distribution<double>(lo[a], hi[a])(rng);
  return x;
}

// Identity on the unit box with every control moved by up to a tenth of the smallest Greville spacing
// (1/12 for 7 controls of order 4): smooth (C^2) and fold-free.
BSplineVolume perturbedLattice(unsigned seed) {
  BSplineVolume volume = unitIdentity();
  std::mt19937 rng(seed);
  const Eigen::Vector3d amplitude = Eigen::Vector3d::Constant(0.1 / 12.0);
  const auto n = volume.controlCounts();
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        volume.setControl(i, j, k, volume.control(i, j, k) + randomIn(rng, -amplitude, amplitude));
  return volume;
}

// Index of the first copy of t in the u knots.
int firstKnotIndex(const BSplineVolume& volume, double t) {
  const auto& knots = volume.knots(0);
  return static_cast<int>(std::find(knots.begin(), knots.end(), t) - knots.begin());
}

// Identity with `order` knots inserted at u0 = 0.4 and every control of the + side shifted by +delta in x:
// F(u, v, w) = (u, v, w) for u < u0 and (u + delta, v, w) for u >= u0; x in (0.4, 0.4 + delta) is a gap.
BSplineVolume openedCut(double delta) {
  BSplineVolume volume = unitIdentity();
  volume.insertKnot(0, 0.4, 4);
  const int plus = firstKnotIndex(volume, 0.4);  // the first control of the + side
  const auto n = volume.controlCounts();
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = plus; i < n[0]; ++i)
        volume.setControl(i, j, k, volume.control(i, j, k) + Eigen::Vector3d(delta, 0.0, 0.0));
  return volume;
}

TEST_CASE("volume_inversion: the identity lattice inverts every point to itself", "[cutting]") {
  const BSplineVolume volume = unitIdentity();
  std::mt19937 rng(1);
  for (int n = 0; n < 100; ++n) {
    const Eigen::Vector3d p = randomIn(rng, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
    const InversionResult result = invertPoint(volume, p);
    REQUIRE(result.converged);
    REQUIRE((result.uvw - p).norm() < 1e-12);
    REQUIRE(result.residual <= 1e-10);
  }
}

TEST_CASE("volume_inversion: round trip on a deformed lattice", "[cutting]") {
  const BSplineVolume volume = perturbedLattice(7);
  REQUIRE(checkJacobianPositive(volume).ok);  // precondition: the lattice is fold-free, so F is invertible
  std::mt19937 rng(2);
  int worst_iterations = 0;
  for (int n = 0; n < 500; ++n) {
    const Eigen::Vector3d uvw = randomIn(rng, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
    const Eigen::Vector3d p = volume.evaluate(uvw);
    const InversionResult result = invertPoint(volume, p);
    INFO("uvw = " << uvw.transpose() << ", found " << result.uvw.transpose() << ", residual " << result.residual);
    REQUIRE(result.converged);
    REQUIRE((result.uvw - uvw).norm() < 1e-8);
    REQUIRE((volume.evaluate(result.uvw) - p).norm() == Approx(result.residual).margin(1e-15));
    worst_iterations = std::max(worst_iterations, result.iterations);
  }
  CHECK(worst_iterations <= 10);  // Newton from the nearest control's Greville point converges fast
}

TEST_CASE("volume_inversion: a point outside the lattice's range does not converge and does not throw", "[cutting]") {
  const BSplineVolume volume = unitIdentity();
  const Eigen::Vector3d p(1.5, 0.5, -0.25);
  InversionResult result{};
  REQUIRE_NOTHROW(result = invertPoint(volume, p));
  REQUIRE_FALSE(result.converged);
  // The best point is the clamped nearest point of the range.
  REQUIRE((result.uvw - Eigen::Vector3d(1.0, 0.5, 0.0)).norm() < 1e-9);
  REQUIRE(result.residual == Approx(std::hypot(0.5, 0.25)).epsilon(1e-9));
  REQUIRE(volume.parameterBox().contains(result.uvw));
}

TEST_CASE("volume_inversion: across an opened C^-1 cut each side inverts to its own side of u0", "[cutting]") {
  const double u0 = 0.4;
  const double delta = 0.1;
  const BSplineVolume volume = openedCut(delta);
  std::mt19937 rng(3);
  SECTION("points of the - side invert to u < u0") {
    for (int n = 0; n < 200; ++n) {
      Eigen::Vector3d p = randomIn(rng, Eigen::Vector3d::Zero(), Eigen::Vector3d(u0, 1.0, 1.0));
      if (n == 0) p.x() = u0 - 1e-9;  // right against the - plane
      const InversionResult result = invertPoint(volume, p);
      INFO("p = " << p.transpose() << ", found " << result.uvw.transpose());
      REQUIRE(result.converged);
      REQUIRE(result.uvw.x() < u0);
      REQUIRE((result.uvw - p).norm() < 1e-8);
    }
  }
  SECTION("points of the + side invert to u >= u0") {
    for (int n = 0; n < 200; ++n) {
      Eigen::Vector3d p = randomIn(rng, Eigen::Vector3d(u0 + delta, 0.0, 0.0), Eigen::Vector3d(1.0 + delta, 1.0, 1.0));
      if (n == 0) p.x() = u0 + delta;  // exactly on the + plane
      const InversionResult result = invertPoint(volume, p);
      INFO("p = " << p.transpose() << ", found " << result.uvw.transpose());
      REQUIRE(result.converged);
      REQUIRE(result.uvw.x() >= u0);
      REQUIRE((result.uvw - (p - Eigen::Vector3d(delta, 0.0, 0.0))).norm() < 1e-8);
    }
  }
  SECTION("a point in the gap between the planes is not reached") {
    const InversionResult result = invertPoint(volume, Eigen::Vector3d(u0 + 0.5 * delta, 0.5, 0.5));
    REQUIRE_FALSE(result.converged);
    REQUIRE(result.residual >= 0.5 * delta - 1e-9);
  }
}

TEST_CASE("volume_inversion: the start is the Greville point of the nearest control, on its own side of a C^-1 knot",
          "[cutting]") {
  SECTION("identity: the nearest control's Greville point is the control itself") {
    const BSplineVolume volume = unitIdentity();
    const Eigen::Vector3d control = volume.control(2, 3, 5);
    REQUIRE((inversionStart(volume, control + Eigen::Vector3d(0.01, -0.01, 0.01)) - control).norm() < 1e-15);
  }
  SECTION("the last control of the - side starts just left of u0, the first of the + side at u0") {
    const BSplineVolume volume = openedCut(0.1);
    const int plus = firstKnotIndex(volume, 0.4);
    const Eigen::Vector3d minus_start = inversionStart(volume, volume.control(plus - 1, 2, 2));
    const Eigen::Vector3d plus_start = inversionStart(volume, volume.control(plus, 2, 2));
    REQUIRE(minus_start.x() < 0.4);
    REQUIRE(minus_start.x() == Approx(0.4).epsilon(1e-15));
    REQUIRE(plus_start.x() == 0.4);
  }
}

TEST_CASE("volume_inversion: iterations are bounded by max_iterations", "[cutting]") {
  const BSplineVolume volume = perturbedLattice(11);
  const Eigen::Vector3d p = volume.evaluate(0.8, 0.7, 0.9);
  InversionOptions options;
  options.max_iterations = 1;
  const InversionResult one = invertPoint(volume, p, Eigen::Vector3d::Zero(), options);
  REQUIRE(one.iterations <= 1);
  options.max_iterations = 0;
  const InversionResult none = invertPoint(volume, p, Eigen::Vector3d::Zero(), options);
  REQUIRE(none.iterations == 0);
  REQUIRE_FALSE(none.converged);
  REQUIRE(none.uvw == Eigen::Vector3d::Zero());
  // With the default budget the same far start still converges.
  REQUIRE(invertPoint(volume, p, Eigen::Vector3d::Zero()).converged);
}

TEST_CASE("volume_inversion: a non-finite point or start throws std::invalid_argument naming the value", "[cutting]") {
  const BSplineVolume volume = unitIdentity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  REQUIRE_THROWS_AS(invertPoint(volume, Eigen::Vector3d(nan, 0.5, 0.5)), std::invalid_argument);
  REQUIRE_THROWS_WITH(invertPoint(volume, Eigen::Vector3d(nan, 0.5, 0.5)), Catch::Contains("nan"));
  REQUIRE_THROWS_WITH(invertPoint(volume, Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(0.5, inf, 0.5)),
                      Catch::Contains("start") && Catch::Contains("inf"));
  REQUIRE_THROWS_WITH(inversionStart(volume, Eigen::Vector3d(0.5, 0.5, nan)), Catch::Contains("nan"));
}

}  // namespace
}  // namespace incise::bspline
