// Tests for cutting/bspline/src/fold_over.cpp: Theorem 1's control-order test, the sufficient Jacobian test and the
// sampled minimum of det J.
#include "incise/bspline/fold_over.h"

#include <algorithm>
#include <random>
#include <stdexcept>

#include <catch2/catch.hpp>

namespace incise::bspline {
namespace {

const Eigen::AlignedBox3d kUnitBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());

BSplineVolume unitIdentity() { return BSplineVolume::identity(kUnitBox, {4, 4, 4}, {7, 7, 7}); }

// Applies f(i, j, k, P) -> new P to every control.
template <typename F>
void moveAll(BSplineVolume& volume, F&& f) {
  const auto n = volume.controlCounts();
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) volume.setControl(i, j, k, f(i, j, k, volume.control(i, j, k)));
}

// Sets component `axis` of every control of the plane index[axis] == plane to x.
void setPlane(BSplineVolume& volume, int axis, int plane, double x) {
  moveAll(volume, [&](int i, int j, int k, Eigen::Vector3d p) {
    const int ijk[3] = {i, j, k};
    if (ijk[axis] == plane) p[axis] = x;
    return p;
  });
}

// Index of the first copy of t in the knots of `axis`.
int firstKnotIndex(const BSplineVolume& volume, int axis, double t) {
  const auto& knots = volume.knots(axis);
  return static_cast<int>(std::find(knots.begin(), knots.end(), t) - knots.begin());
}

TEST_CASE("fold_over: the identity lattice passes both checks and has det J = 1", "[cutting]") {
  const BSplineVolume volume = unitIdentity();
  for (int axis = 0; axis < 3; ++axis) {
    const FoldReport order = checkAxisOrder(volume, axis);
    REQUIRE(order.ok);
    REQUIRE(order.i == -1);
    REQUIRE(order.j == -1);
    REQUIRE(order.k == -1);
  }
  REQUIRE(checkJacobianPositive(volume).ok);
  REQUIRE(minJacobianDeterminant(volume, 3) == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("fold_over: swapping two interior u-planes is detected by every check", "[cutting]") {
  BSplineVolume volume = unitIdentity();
  const double x3 = volume.control(3, 0, 0).x();
  const double x4 = volume.control(4, 0, 0).x();
  setPlane(volume, 0, 3, x4);
  setPlane(volume, 0, 4, x3);

  const FoldReport order = checkAxisOrder(volume, 0);
  REQUIRE_FALSE(order.ok);
  REQUIRE(order.i == 3);  // the lower control of the first offending pair (3, 0, 0) - (4, 0, 0)
  REQUIRE(order.j == 0);
  REQUIRE(order.k == 0);
  REQUIRE_FALSE(order.message.empty());

  const FoldReport jacobian = checkJacobianPositive(volume);
  REQUIRE_FALSE(jacobian.ok);
  // The first cell (i-fastest) whose support [s - 3, s] holds the pair 3, 4: spans (4, 3, 3).
  REQUIRE(jacobian.i == 4);
  REQUIRE(jacobian.j == 3);
  REQUIRE(jacobian.k == 3);
  REQUIRE_FALSE(jacobian.message.empty());

  REQUIRE(minJacobianDeterminant(volume, 5) <= 0.0);
  // Planes other than u are untouched.
  REQUIRE(checkAxisOrder(volume, 1).ok);
  REQUIRE(checkAxisOrder(volume, 2).ok);
}

TEST_CASE("fold_over: pushing one control point past its neighbour fails both sufficient checks", "[cutting]") {
  BSplineVolume volume = unitIdentity();
  const Eigen::Vector3d next = volume.control(3, 2, 5);
  volume.setControl(2, 2, 5, next + Eigen::Vector3d(0.01, 0.0, 0.0));
  const FoldReport order = checkAxisOrder(volume, 0);
  REQUIRE_FALSE(order.ok);
  REQUIRE((order.i == 2 && order.j == 2 && order.k == 5));
  REQUIRE_FALSE(checkJacobianPositive(volume).ok);
}

TEST_CASE("fold_over: small random moves pass checkJacobianPositive and keep sampled det J > 0", "[cutting]") {
  // Moves up to a tenth of the smallest Greville spacing (1/12): every control difference stays within 20%
  // of its axis direction, so every det(a, b, c) is positive.
  BSplineVolume volume = unitIdentity();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> move(-0.1 / 12.0, 0.1 / 12.0);
  moveAll(volume, [&](int, int, int, const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p + Eigen::Vector3d(move(rng), move(rng), move(rng)));
  });
  const FoldReport jacobian = checkJacobianPositive(volume);
  INFO(jacobian.message);
  REQUIRE(jacobian.ok);
  REQUIRE(minJacobianDeterminant(volume, 4) > 0.0);
  for (int axis = 0; axis < 3; ++axis) REQUIRE(checkAxisOrder(volume, axis).ok);
}

TEST_CASE("fold_over: Theorem 1 - large u-only moves that keep the u-order keep det J > 0", "[cutting]") {
  // Each control moves along u only, to a random strictly increasing sequence per (j, k) row.
  BSplineVolume volume = unitIdentity();
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> gap(0.01, 0.5);
  const auto n = volume.controlCounts();
  for (int k = 0; k < n[2]; ++k) {
    for (int j = 0; j < n[1]; ++j) {
      double x = -0.3;
      for (int i = 0; i < n[0]; ++i) {
        x += gap(rng);
        const Eigen::Vector3d& p = volume.control(i, j, k);
        volume.setControl(i, j, k, Eigen::Vector3d(x, p.y(), p.z()));
      }
    }
  }
  REQUIRE(checkAxisOrder(volume, 0).ok);
  const FoldReport jacobian = checkJacobianPositive(volume);
  INFO(jacobian.message);
  REQUIRE(jacobian.ok);
  REQUIRE(minJacobianDeterminant(volume, 4) > 0.0);
}

TEST_CASE("fold_over: the two planes straddling a full-multiplicity knot may coincide or pass each other",
          "[cutting]") {
  // Inserting order = 4 copies of u0 makes controls plus - 1 (the last of the - side) and plus (the first of
  // the + side) coincide, with plus the index of the first copy of u0 in the knots.
  BSplineVolume volume = unitIdentity();
  volume.insertKnot(0, 0.4, 4);
  const int plus = firstKnotIndex(volume, 0, 0.4);
  REQUIRE(plus == 5);
  for (int j = 0; j < 7; ++j) REQUIRE((volume.control(plus - 1, j, 3) - volume.control(plus, j, 3)).norm() < 1e-15);

  SECTION("coincident planes pass") {
    REQUIRE(checkAxisOrder(volume, 0).ok);
    REQUIRE(checkJacobianPositive(volume).ok);
  }
  SECTION("the + plane moved behind the - plane still passes") {
    setPlane(volume, 0, plus, 0.35);
    REQUIRE(checkAxisOrder(volume, 0).ok);
    const FoldReport jacobian = checkJacobianPositive(volume);
    INFO(jacobian.message);
    REQUIRE(jacobian.ok);
    REQUIRE(minJacobianDeterminant(volume, 4) > 0.0);
  }
  SECTION("the cut opened apart passes") {
    setPlane(volume, 0, plus - 1, 0.37);
    setPlane(volume, 0, plus, 0.43);
    REQUIRE(checkAxisOrder(volume, 0).ok);
    REQUIRE(checkJacobianPositive(volume).ok);
  }
  SECTION("an ordinary plane moved backwards fails") {
    setPlane(volume, 0, 2, volume.control(1, 0, 0).x() - 0.01);
    const FoldReport order = checkAxisOrder(volume, 0);
    REQUIRE_FALSE(order.ok);
    REQUIRE(order.i == 1);
    REQUIRE_FALSE(checkJacobianPositive(volume).ok);
  }
  SECTION("the plane after the + plane moved behind it fails") {
    setPlane(volume, 0, plus + 1, volume.control(plus, 0, 0).x() - 0.01);
    const FoldReport order = checkAxisOrder(volume, 0);
    REQUIRE_FALSE(order.ok);
    REQUIRE(order.i == plus);
    REQUIRE_FALSE(checkJacobianPositive(volume).ok);
  }
  SECTION("the - plane moved behind its predecessor fails") {
    setPlane(volume, 0, plus - 1, volume.control(plus - 2, 0, 0).x() - 0.01);
    const FoldReport order = checkAxisOrder(volume, 0);
    REQUIRE_FALSE(order.ok);
    REQUIRE(order.i == plus - 2);
  }
  SECTION("the rule is per axis: a C^-1 knot along v exempts only the straddling v-planes") {
    BSplineVolume cut_v = unitIdentity();
    cut_v.insertKnot(1, 0.6, 4);
    const int plus_v = firstKnotIndex(cut_v, 1, 0.6);
    setPlane(cut_v, 1, plus_v, 0.55);
    REQUIRE(checkAxisOrder(cut_v, 1).ok);
    REQUIRE(checkJacobianPositive(cut_v).ok);
    // A knot of multiplicity order - 1 (C^0) is not a cut: its neighbours must stay ordered.
    BSplineVolume c0 = unitIdentity();
    c0.insertKnot(1, 0.6, 3);
    const int first = firstKnotIndex(c0, 1, 0.6);
    setPlane(c0, 1, first, c0.control(0, first - 1, 0).y() - 0.01);
    REQUIRE_FALSE(checkAxisOrder(c0, 1).ok);
  }
}

TEST_CASE("fold_over: a fold along v passes the u-order check but not the v-order or Jacobian check", "[cutting]") {
  BSplineVolume volume = unitIdentity();
  const double y2 = volume.control(0, 2, 0).y();
  const double y3 = volume.control(0, 3, 0).y();
  setPlane(volume, 1, 2, y3);
  setPlane(volume, 1, 3, y2);
  REQUIRE(checkAxisOrder(volume, 0).ok);
  const FoldReport order = checkAxisOrder(volume, 1);
  REQUIRE_FALSE(order.ok);
  REQUIRE(order.j == 2);
  REQUIRE_FALSE(checkJacobianPositive(volume).ok);
  REQUIRE(minJacobianDeterminant(volume, 5) <= 0.0);
}

TEST_CASE("fold_over: a bad axis or sample count throws", "[cutting]") {
  const BSplineVolume volume = unitIdentity();
  REQUIRE_THROWS_AS(checkAxisOrder(volume, 3), std::out_of_range);
  REQUIRE_THROWS_AS(checkAxisOrder(volume, -1), std::out_of_range);
  REQUIRE_THROWS_WITH(minJacobianDeterminant(volume, 0), Catch::Contains("0"));
  REQUIRE_THROWS_AS(minJacobianDeterminant(volume, 0), std::invalid_argument);
}

}  // namespace
}  // namespace incise::bspline
