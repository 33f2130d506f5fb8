// Tests for the private element kernels (physics/src/element.cpp), the block matrix
// (block_matrix.cpp) and conjugate gradients (pcg.cpp) that the model's step is made of.
#include "element.h"

#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <catch2/catch.hpp>

#include "block_matrix.h"
#include "pcg.h"

namespace incise::physics::detail {
namespace {

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// The proper rotation of F's SVD with the sign of the smallest singular value moved into it (Irving et al.).
Eigen::Matrix3d irvingRotation(const Eigen::Matrix3d& f) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant();
  return svd.matrixU() * d * svd.matrixV().transpose();
}

TEST_CASE("element: the rotation of a rotated stretch is its rotation, inverted or not", "[physics]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> stretch(0.5, 1.5);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d r = randomRotation(rng), q = randomRotation(rng);
    Eigen::Vector3d s(stretch(rng), stretch(rng), stretch(rng));
    if (trial % 2 == 1) s[2] = -0.3 * s[2];  // inverted: a reflection in the deformation
    const Eigen::Matrix3d f = r * q * s.asDiagonal() * q.transpose();
    std::array<double, 4> quaternion{1.0, 0.0, 0.0, 0.0};
    int iterations = 0;
    const Eigen::Matrix3d found = rotation(f, quaternion, 1e-12, 100, iterations);
    INFO("trial " << trial << ", " << iterations << " iterations");
    CHECK(found.determinant() == Approx(1.0).epsilon(1e-12));
    CHECK((found.transpose() * found - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    CHECK((found - irvingRotation(f)).norm() < 1e-8);
    // R^T F is symmetric: the element's strain has no rotation left in it.
    const Eigen::Matrix3d rf = found.transpose() * f;
    CHECK((rf - rf.transpose()).norm() < 1e-8);
  }
}

TEST_CASE("element: warm-started, the rotation of the previous step converges in one or two corrections", "[physics]") {
  std::array<double, 4> q{1.0, 0.0, 0.0, 0.0};
  int iterations = 0;
  Eigen::Matrix3d f = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  rotation(f, q, 1e-9, 100, iterations);
  f = Eigen::AngleAxisd(0.31, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
      Eigen::Vector3d(1.1, 0.95, 1.0).asDiagonal();
  const Eigen::Matrix3d r = rotation(f, q, 1e-6, 100, iterations);
  CHECK(iterations <= 2);
  CHECK((r - irvingRotation(f)).norm() < 1e-5);
}

// The correction rotation() would make next from the rotation r (its Newton step, or its gradient step where
// -Hessian is not safely positive definite): the oracle for when it may stop.
Eigen::Vector3d nextCorrection(const Eigen::Matrix3d& f, const Eigen::Matrix3d& r) {
  const Eigen::Matrix3d a = f * r.transpose();
  const Eigen::Vector3d omega(a(2, 1) - a(1, 2), a(0, 2) - a(2, 0), a(1, 0) - a(0, 1));
  const Eigen::Matrix3d h = a.trace() * Eigen::Matrix3d::Identity() - 0.5 * (a + a.transpose());
  const Eigen::LLT<Eigen::Matrix3d> llt(h);
  if (llt.info() == Eigen::Success && h.determinant() > 1e-6 * std::pow(std::abs(a.trace()), 3))
    return llt.solve(omega);
  return omega / (std::abs(a.trace()) + 1e-9);
}

TEST_CASE("element: the rotation stops only where its next correction would be below the tolerance", "[physics]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> stretch(0.3, 2.0), unit(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  int stopped_at_once = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Matrix3d r = randomRotation(rng), q = randomRotation(rng);
    Eigen::Vector3d s(stretch(rng), stretch(rng), stretch(rng));
    if (trial % 3 == 2) s[2] = -0.2 * s[2];  // inverted
    const Eigen::Matrix3d f = r * q * s.asDiagonal() * q.transpose();
    // Warm-started near the answer, 1e-9 to 1e-1 rad away: from already converged to a few corrections.
    const double angle = std::pow(10.0, -9.0 + 8.0 * unit(rng));
    const Eigen::Quaterniond start =
        Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized())) *
        Eigen::Quaterniond(irvingRotation(f));
    std::array<double, 4> quaternion{start.w(), start.x(), start.y(), start.z()};
    const double tolerance = trial % 2 == 0 ? 1e-6 : 1e-9;
    int iterations = 0;
    const Eigen::Matrix3d found = rotation(f, quaternion, tolerance, 50, iterations);
    INFO("trial " << trial << ", " << iterations << " iterations, started " << angle << " rad away");
    REQUIRE(iterations < 50);
    CHECK(nextCorrection(f, found).norm() < tolerance);
    stopped_at_once += iterations == 0 ? 1 : 0;
  }
  CHECK(stopped_at_once > 200);  // the converged starts took no correction
}

TEST_CASE("element: a tet's rest data: volume, gradients and barycentric weights", "[physics]") {
  Element e;
  const std::array<Eigen::Vector3d, 4> x = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0),
                                            Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1)};
  REQUIRE(setRest(e, x, Eigen::Vector3d::Ones()));
  CHECK(e.volume_m3 == Approx(2.0 / 6.0));
  // Sum of the gradients is zero, so each beta_a . sum_b beta_b is 0.
  CHECK(e.dots[0] + e.dots[4] + e.dots[5] + e.dots[6] == Approx(0.0).margin(1e-12));
  const Eigen::Vector4d w = barycentric(e, x[0], Eigen::Vector3d(0.5, 0.25, 0.25), Eigen::Vector3d::Ones());
  CHECK(w.sum() == Approx(1.0));
  CHECK((w[1] * x[1] + w[2] * x[2] + w[3] * x[3]).isApprox(Eigen::Vector3d(0.5, 0.25, 0.25)));
  // Prestretch 2 along x: the natural tet is half as long, half the volume; barycentric weights unchanged.
  Element half;
  REQUIRE(setRest(half, x, Eigen::Vector3d(0.5, 1.0, 1.0)));
  CHECK(half.volume_m3 == Approx(1.0 / 6.0));
  CHECK(barycentric(half, x[0], Eigen::Vector3d(0.5, 0.25, 0.25), Eigen::Vector3d(0.5, 1, 1)).isApprox(w));
  // Flat and inverted tets are refused.
  std::array<Eigen::Vector3d, 4> flat = x;
  flat[3] = Eigen::Vector3d(1, 1, 0);
  CHECK_FALSE(setRest(e, flat, Eigen::Vector3d::Ones()));
  std::swap(flat[1], flat[2]);
  flat[3] = Eigen::Vector3d(0, 0, 1);
  CHECK_FALSE(setRest(e, flat, Eigen::Vector3d::Ones()));
}

TEST_CASE("element: point-triangle distance in each region", "[physics]") {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(pointTriangleDistance(Eigen::Vector3d(0.2, 0.2, 0.5), a, b, c) == Approx(0.5));
  CHECK(pointTriangleDistance(Eigen::Vector3d(-1, -1, 0), a, b, c) == Approx(std::sqrt(2.0)));
  CHECK(pointTriangleDistance(Eigen::Vector3d(0.5, -2, 0), a, b, c) == Approx(2.0));
  CHECK(pointTriangleDistance(Eigen::Vector3d(1, 1, 0), a, b, c) == Approx(std::sqrt(0.5)));
  CHECK(pointTriangleDistance(Eigen::Vector3d(2, 0, 0), a, b, c) == Approx(1.0));
}

// A random symmetric positive definite block matrix over `n` nodes with the pattern of a chain plus skips.
struct Random {
  BlockMatrix a;
  Eigen::MatrixXd dense;
};

Random randomMatrix(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Random m;
  m.a.reserve(static_cast<std::size_t>(n), static_cast<std::size_t>(n));
  m.dense = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int i = 0; i < n; ++i) m.a.addRow(1);  // little room: rows move as they grow
  for (int i = 0; i < n; ++i)
    for (const int j : {i + 1, i + 3, i + 7}) {
      if (j >= n) continue;
      const int local = m.a.acquire(i, j);
      Eigen::Matrix3d b;
      for (int k = 0; k < 9; ++k) b.data()[k] = 0.3 * u(rng);
      addTo(m.a.upper(i, local), b);
      m.dense.block(3 * i, 3 * j, 3, 3) = b;
      m.dense.block(3 * j, 3 * i, 3, 3) = b.transpose();
    }
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity() * 8.0;
    d(0, 1) = d(1, 0) = 0.5;
    addTo(m.a.diagonal(i), d);
    m.dense.block(3 * i, 3 * i, 3, 3) = d;
  }
  return m;
}

TEST_CASE("block_matrix: products and triangular sweeps are the dense matrix's, inactive rows projected out",
          "[physics]") {
  std::mt19937 rng(3);
  const int n = 40;
  Random m = randomMatrix(n, rng);
  CHECK(m.a.overflows() > 0);  // rows moved to the pool's end past its reserve, their entries kept
  std::vector<Eigen::Vector3d> v(n), y(n);
  std::vector<std::uint8_t> active(n, 1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd dense_v(3 * n);
  for (int i = 0; i < n; ++i) v[i] = Eigen::Vector3d(u(rng), u(rng), u(rng)), dense_v.segment<3>(3 * i) = v[i];
  std::vector<Quad> push(n);
  m.a.multiply(v, y, active, push);
  const Eigen::VectorXd expected = m.dense * dense_v;
  for (int i = 0; i < n; ++i) CHECK((y[i] - expected.segment<3>(3 * i)).norm() < 1e-12);
  // The SSOR halves: (D / w + U)^-1 and (D / w + L)^-1, and D / w + U.
  const double omega = 1.3;
  Eigen::MatrixXd upper = Eigen::MatrixXd::Zero(3 * n, 3 * n), lower = upper;
  std::vector<Eigen::Matrix3d> inverse(n);
  for (int i = 0; i < n; ++i) {
    inverse[i] = m.dense.block<3, 3>(3 * i, 3 * i).inverse();
    upper.block<3, 3>(3 * i, 3 * i) = lower.block<3, 3>(3 * i, 3 * i) = m.dense.block<3, 3>(3 * i, 3 * i) / omega;
    for (int j = i + 1; j < n; ++j) {
      upper.block<3, 3>(3 * i, 3 * j) = m.dense.block<3, 3>(3 * i, 3 * j);
      lower.block<3, 3>(3 * j, 3 * i) = m.dense.block<3, 3>(3 * j, 3 * i);
    }
  }
  // Block triangular (each diagonal block full): solved as dense matrices.
  const Eigen::VectorXd up = upper.partialPivLu().solve(dense_v);
  const Eigen::VectorXd low = lower.partialPivLu().solve(dense_v);
  const Eigen::VectorXd upper_product = upper * dense_v;
  std::vector<Eigen::Vector3d> y_low(n), y_product(n);
  m.a.upperSolve(v, y, inverse, active, omega);
  m.a.lowerSolve(v, y_low, inverse, active, omega, push);
  m.a.upperMultiply(v, y_product, active, omega);
  for (int i = 0; i < n; ++i) {
    CHECK((y[i] - up.segment<3>(3 * i)).norm() < 1e-12);
    CHECK((y_low[i] - low.segment<3>(3 * i)).norm() < 1e-12);
    CHECK((y_product[i] - upper_product.segment<3>(3 * i)).norm() < 1e-12);
  }
  // Node 5 inactive (its unknown zero): its row reads zero, the others lose its column.
  active[5] = 0, v[5].setZero(), dense_v.segment<3>(15).setZero();
  m.a.multiply(v, y, active, push);
  const Eigen::VectorXd projected = m.dense * dense_v;
  CHECK(y[5].norm() == 0.0);
  for (int i = 0; i < n; ++i)
    if (i != 5) CHECK((y[i] - projected.segment<3>(3 * i)).norm() < 1e-12);
  // An entry released by all its users is taken again by the next acquire in its row (no growth).
  const std::size_t entries = m.a.entries();
  m.a.release(0, 0);
  CHECK(m.a.entries() == entries - 1);
  CHECK(m.a.acquire(0, 30) == 0);
  CHECK(m.a.entries() == entries);
}

TEST_CASE("pcg: conjugate gradients solve the block system to the tolerance asked", "[physics]") {
  std::mt19937 rng(11);
  const int n = 60;
  Random m = randomMatrix(n, rng);
  std::vector<Eigen::Vector3d> b(n), x(n, Eigen::Vector3d::Zero());
  std::vector<std::uint8_t> active(n, 1);
  active[10] = 0;
  std::normal_distribution<double> g(0.0, 1.0);
  for (auto& v : b) v = Eigen::Vector3d(g(rng), g(rng), g(rng));
  PcgScratch scratch;
  scratch.resize(n);
  for (const double omega : {0.0, 1.0, 1.5}) {  // block Jacobi, symmetric Gauss-Seidel, SSOR
    INFO("omega " << omega);
    std::fill(x.begin(), x.end(), Eigen::Vector3d::Ones());
    const PcgResult r = solvePcg(m.a, active, b, x, 1e-12, 500, omega, {}, scratch);
    CHECK(r.converged);
    CHECK(r.iterations < 60);
    std::vector<Eigen::Vector3d> ax(n);
    std::vector<Quad> push(n);
    m.a.multiply(x, ax, active, push);
    for (int i = 0; i < n; ++i) CHECK((active[i] ? (ax[i] - b[i]).norm() : x[i].norm()) < 1e-9);
    // Warm-started from the solution, it stops at once.
    CHECK(solvePcg(m.a, active, b, x, 1e-8, 500, omega, {}, scratch).iterations == 0);
  }
}

}  // namespace
}  // namespace incise::physics::detail
