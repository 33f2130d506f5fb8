#include "incise/bspline/bspline_volume.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "test_volumes.h"

using namespace incise;
using namespace incise::bspline;
using Catch::Matchers::Contains;
using incise::bspline::testing::randomParameter;
using incise::bspline::testing::randomVolume;

namespace {

// tests/data/bspline_case1.md — "Computed independently by IRIT 11 (TrivTVEval, TrivTVRefineAtParams),
// verb-nurbs 3.0.3, the scijs `nurbs` package and octave-nurbs 1.4.3; all four agree to the 15 digits
// printed."
BSplineVolume case1() {
  const std::vector<double> knots{0, 0, 0, 0.5, 1, 1, 1};
  std::vector<Eigen::Vector3d> controls(64);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i)
        controls[static_cast<size_t>(i + 4 * (j + 4 * k))] =
            Eigen::Vector3d(i / 3.0 + 0.05 * ((7 * i + 3 * j + k) % 5), j / 3.0 + 0.03 * ((i + 5 * j + 2 * k) % 3),
                            k / 3.0 - 0.02 * ((2 * i + j + 3 * k) % 4));
  return BSplineVolume({3, 3, 3}, {knots, knots, knots}, std::move(controls));
}

void requireNear(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tolerance) {
  INFO("got " << a.transpose() << ", expected " << b.transpose());
  REQUIRE((a - b).cwiseAbs().maxCoeff() <= tolerance);
}

}  // namespace

TEST_CASE("bspline_volume: case 1 evaluations match IRIT, verb, scijs nurbs and octave-nurbs", "[cutting]") {
  const BSplineVolume volume = case1();
  requireNear(volume.evaluate(0.1, 0.2, 0.3), {0.234002666666667, 0.273439200000000, 0.311459200000000}, 1e-14);
  requireNear(volume.evaluate(0.5, 0.5, 0.5), {0.606250000000000, 0.533750000000000, 0.470000000000000}, 1e-14);
  requireNear(volume.evaluate(0.77, 0.33, 0.9), {0.817248237000000, 0.400187170520000, 0.841655835925333}, 1e-14);
  REQUIRE(volume.jacobian(0.4, 0.6, 0.2).determinant() == Approx(0.610200678462478).epsilon(1e-13));
}

TEST_CASE("bspline_volume: case 1 o-fold insertion gives the reference control row and the + side", "[cutting]") {
  BSplineVolume volume = case1();
  volume.insertKnot(0, 0.3, 3);
  REQUIRE(volume.knots(0) == std::vector<double>{0, 0, 0, 0.3, 0.3, 0.3, 0.5, 1, 1, 1});
  REQUIRE(volume.controlCounts() == std::array<int, 3>{7, 4, 4});
  const Eigen::Vector3d row[7] = {{0.000000000000000, 0.333333333333333, 0.606666666666667},
                                  {0.260000000000000, 0.351333333333333, 0.630666666666667},
                                  {0.442000000000000, 0.363933333333333, 0.633066666666667},
                                  {0.442000000000000, 0.363933333333333, 0.633066666666667},
                                  {0.563333333333333, 0.372333333333333, 0.634666666666667},
                                  {0.866666666666667, 0.393333333333333, 0.606666666666667},
                                  {1.050000000000000, 0.333333333333333, 0.646666666666667}};
  for (int i = 0; i < 7; ++i) requireNear(volume.control(i, 1, 2), row[i], 1e-14);
  requireNear(volume.evaluate(0.1, 0.2, 0.3), {0.234002666666667, 0.273439200000000, 0.311459200000000}, 1e-14);
  requireNear(volume.evaluate(0.5, 0.5, 0.5), {0.606250000000000, 0.533750000000000, 0.470000000000000}, 1e-14);
  requireNear(volume.evaluate(0.77, 0.33, 0.9), {0.817248237000000, 0.400187170520000, 0.841655835925333}, 1e-14);
  requireNear(volume.evaluate(0.3 - 1e-12, 0.4, 0.6), {0.434671999999006, 0.456828906666644, 0.542375253333334}, 1e-14);
  requireNear(volume.evaluate(0.3, 0.4, 0.6), {0.434672, 0.456828906666667, 0.542375253333333}, 1e-14);

  // The + side really is taken at the knot: move the + plane and F(0.3, ...) follows it, F(0.3 - eps) not.
  const Eigen::Vector3d before_left = volume.evaluate(0.3 - 1e-9, 0.4, 0.6);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j) volume.setControl(3, j, k, volume.control(3, j, k) + Eigen::Vector3d(0.1, 0, 0));
  REQUIRE(volume.evaluate(0.3, 0.4, 0.6).x() == Approx(0.434672 + 0.1).margin(1e-14));
  requireNear(volume.evaluate(0.3 - 1e-9, 0.4, 0.6), before_left, 0.0);
}

TEST_CASE("bspline_volume: knot insertion leaves the map unchanged on random volumes", "[cutting]") {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 12; ++trial) {
    const int order = 2 + trial % 4;
    BSplineVolume volume = randomVolume(rng, {order, order + (trial % 2), 3}, {order + 3, order + 4, 5});
    const BSplineVolume original = volume;
    const int axis = trial % 3;
    const auto d = volume.domain(axis);
    // Insert at a random parameter, and once more at an existing interior knot.
    volume.insertKnot(axis, std::uniform_real_distribution<double>(d[0], d[1])(rng), 1 + trial % 2);
    const double existing = volume.knots(axis)[static_cast<size_t>(volume.orders()[axis])];
    if (existing > d[0] && existing < d[1] && knotMultiplicity(volume.knots(axis), existing) < volume.orders()[axis])
      volume.insertKnot(axis, existing);
    for (int n = 0; n < 300; ++n) {
      const Eigen::Vector3d t = randomParameter(rng, original);
      requireNear(volume.evaluate(t), original.evaluate(t), 1e-12);
    }
  }
}

TEST_CASE("bspline_volume: after o insertions the + side moves only F for u >= u0", "[cutting]") {
  std::mt19937_64 rng(4);
  const int order = 4;
  BSplineVolume volume = randomVolume(rng, {order, order, order}, {8, 7, 6});
  const double u0 = 0.4375;
  volume.insertKnot(0, u0, order);
  const BSplineVolume cut = volume;
  // The + side's first control plane is the one just after the last knot of value u0 minus the order.
  const auto& knots = volume.knots(0);
  const int last_u0 = static_cast<int>(std::upper_bound(knots.begin(), knots.end(), u0) - knots.begin()) - 1;
  const int plus_plane = last_u0 - order + 1;
  REQUIRE(volume.control(plus_plane, 2, 3) == volume.control(plus_plane - 1, 2, 3));  // coincident planes
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 7; ++j)
      volume.setControl(plus_plane, j, k, volume.control(plus_plane, j, k) + Eigen::Vector3d(0.3, -0.2, 0.1));
  int changed = 0;
  for (int n = 0; n < 2000; ++n) {
    Eigen::Vector3d t = randomParameter(rng, volume);
    if (n % 10 == 0) t[0] = u0;  // exactly on the knot: the + side
    const bool moved = (volume.evaluate(t) - cut.evaluate(t)).norm() > 0.0;
    if (t[0] < u0) {
      REQUIRE_FALSE(moved);
    } else if (moved) {
      ++changed;
    }
  }
  REQUIRE(changed > 100);
}

TEST_CASE("bspline_volume: the identity lattice maps points to themselves", "[cutting]") {
  std::mt19937_64 rng(5);
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.02, 0.1, 3.0), Eigen::Vector3d(0.05, 0.2, 3.5));
  for (int order = 2; order <= 5; ++order) {
    const BSplineVolume volume = BSplineVolume::identity(box, {order, order, 3}, {order + 3, 9, 4});
    for (int n = 0; n < 300; ++n) {
      const Eigen::Vector3d p = randomParameter(rng, volume);
      requireNear(volume.evaluate(p), p, 1e-14);
      REQUIRE((volume.jacobian(p) - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-12);
    }
    requireNear(volume.evaluate(box.max()), box.max(), 1e-14);
  }
}

TEST_CASE("bspline_volume: the Jacobian matches central finite differences", "[cutting]") {
  std::mt19937_64 rng(6);
  const BSplineVolume volume = randomVolume(rng, {4, 3, 5}, {7, 6, 8});
  for (int n = 0; n < 200; ++n) {
    const Eigen::Vector3d t = randomParameter(rng, volume);
    const Eigen::Matrix3d jac = volume.jacobian(t);
    for (int a = 0; a < 3; ++a) {
      const double h = 1e-6;
      Eigen::Vector3d lo = t, hi = t;
      lo[a] = std::max(lo[a] - h, 0.0);
      hi[a] = std::min(hi[a] + h, 1.0);
      const Eigen::Vector3d fd = (volume.evaluate(hi) - volume.evaluate(lo)) / (hi[a] - lo[a]);
      // Finite differences across a knot see two pieces; the derivative is continuous there (C^1 at least
      // for order >= 3 except at the double knot), so a loose tolerance still catches a wrong column.
      INFO("axis " << a << " at " << t.transpose());
      REQUIRE((jac.col(a) - fd).norm() <= 1e-4 * (1.0 + fd.norm()));
    }
  }
}

TEST_CASE("bspline_volume: bad input is refused and the volume is left as it was", "[cutting]") {
  BSplineVolume volume = case1();
  const std::vector<double> k{0, 0, 0, 0.5, 1, 1, 1};
  std::vector<Eigen::Vector3d> controls(64, Eigen::Vector3d::Zero());
  REQUIRE_THROWS_WITH(BSplineVolume({3, 3, 3}, {std::vector<double>{0, 0, 0, 0.6, 0.5, 1, 1}, k, k}, controls),
                      Contains("u knots") && Contains("0.5") && Contains("decreases"));
  REQUIRE_THROWS_WITH(BSplineVolume({3, 3, 3}, {k, k, k}, std::vector<Eigen::Vector3d>(63)),
                      Contains("63 control points") && Contains("64"));
  REQUIRE_THROWS_WITH(BSplineVolume({1, 3, 3}, {k, k, k}, controls), Contains("order 1"));
  controls[21] = Eigen::Vector3d(0, NAN, 0);
  REQUIRE_THROWS_WITH(BSplineVolume({3, 3, 3}, {k, k, k}, controls), Contains("(1, 1, 1)") && Contains("nan"));

  REQUIRE_THROWS_WITH(volume.evaluate(NAN, 0.5, 0.5), Contains("u = nan"));
  REQUIRE_THROWS_WITH(volume.evaluate(0.5, 1.25, 0.5), Contains("v = 1.25") && Contains("outside the domain [0, 1]"));
  REQUIRE_THROWS_WITH(volume.jacobian(0.5, 0.5, -0.5), Contains("w = -0.5"));
  REQUIRE_THROWS_WITH(volume.setControl(0, 0, 0, Eigen::Vector3d(INFINITY, 0, 0)), Contains("inf"));
  REQUIRE_THROWS_AS(volume.setControl(4, 0, 0, Eigen::Vector3d::Zero()), std::out_of_range);

  volume.insertKnot(1, 0.25, 2);
  const BSplineVolume inserted = volume;
  REQUIRE_THROWS_WITH(volume.insertKnot(1, 0.25, 2),
                      Contains("0.25") && Contains("multiplicity 2") && Contains("order = 3"));
  REQUIRE_THROWS_WITH(volume.insertKnot(0, 1.0), Contains("t = 1") && Contains("strictly inside"));
  REQUIRE_THROWS_WITH(volume.insertKnot(0, NAN), Contains("t = nan"));
  REQUIRE_THROWS_WITH(volume.insertKnot(0, 0.5, 0), Contains("0 times"));
  REQUIRE_THROWS_AS(volume.insertKnot(3, 0.5), std::out_of_range);
  // Nothing half-modified.
  REQUIRE(volume.knots(1) == inserted.knots(1));
  REQUIRE(volume.controlCounts() == inserted.controlCounts());
  for (size_t i = 0; i < volume.controls().size(); ++i) REQUIRE(volume.controls()[i] == inserted.controls()[i]);

  REQUIRE_THROWS_WITH(BSplineVolume::identity(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 1)),
                                              {3, 3, 3}, {4, 4, 4}),
                      Contains("min < max"));
}
