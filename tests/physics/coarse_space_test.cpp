// Tests for CG's coarse level (physics/src/coarse_space.cpp): rigid-body modes per aggregate of nodes, the
// coarse matrix Z^T A Z and the correction Z (Z^T A Z)^-1 Z^T, and CG's two-level preconditioner (pcg.cpp).
#include "coarse_space.h"

#include <random>

#include <catch2/catch.hpp>

#include "block_matrix.h"
#include "pcg.h"

namespace incise::physics::detail {
namespace {

// A symmetric positive definite block matrix over n nodes placed at random in a length x 1 x 1 box, coupling
// each node to those within `reach` with spring-like blocks (k_ij (e e^T + 0.1 I)) plus a small mass term.
struct Springs {
  BlockMatrix a;
  std::vector<Eigen::Vector3d> x_m;
};

Springs springs(int n, std::mt19937& rng, double length = 4.0, double reach = 0.9) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Springs s;
  for (int i = 0; i < n; ++i) s.x_m.emplace_back(length * u(rng), u(rng), u(rng));
  s.a.reserve(static_cast<std::size_t>(n), static_cast<std::size_t>(16 * n));
  for (int i = 0; i < n; ++i) s.a.addRow(8);
  const auto add = [&](int i, int j, const Eigen::Matrix3d& k) {
    addTo(s.a.diagonal(i), k), addTo(s.a.diagonal(j), k);
    addTo(s.a.upper(std::min(i, j), s.a.acquire(std::min(i, j), std::max(i, j))), -k);
  };
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector3d e = s.x_m[static_cast<std::size_t>(j)] - s.x_m[static_cast<std::size_t>(i)];
      if (e.norm() > reach) continue;
      const Eigen::Vector3d unit = e.normalized();
      add(i, j, (unit * unit.transpose() + 0.1 * Eigen::Matrix3d::Identity()) * (1.0 + u(rng)));
    }
  for (int i = 0; i < n; ++i) addTo(s.a.diagonal(i), 1e-3 * Eigen::Matrix3d::Identity());
  return s;
}

TEST_CASE("coarse_space: a rigid motion of the whole is corrected exactly, whatever the aggregates", "[physics]") {
  std::mt19937 rng(5);
  const int n = 120;
  Springs s = springs(n, rng);
  std::vector<std::uint8_t> active(n, 1);
  active[7] = active[40] = 0;  // held: out of the system and of the aggregates
  CoarseSpace coarse;
  coarse.reserve(n, 16);
  coarse.partition(s.x_m, active, 16, 20);
  CHECK(coarse.aggregates() == 5);  // 118 active nodes, at least 20 each
  REQUIRE(coarse.build(s.a, s.x_m, active));
  // u = t + theta x x over the active nodes lies in every aggregate's modes: Z (Z^T A Z)^-1 Z^T A u = u.
  const Eigen::Vector3d t(0.3, -0.2, 0.5), theta(0.1, 0.4, -0.2);
  std::vector<Eigen::Vector3d> u(n, Eigen::Vector3d::Zero()), r(n), z(n, Eigen::Vector3d::Zero());
  for (int i = 0; i < n; ++i)
    if (active[static_cast<std::size_t>(i)])
      u[static_cast<std::size_t>(i)] = t + theta.cross(s.x_m[static_cast<std::size_t>(i)]);
  std::vector<Quad> push(n);
  s.a.multiply(u, r, active, push);
  const double ru = coarse.addCorrection(r, z, active);
  double expected_ru = 0.0;
  for (int i = 0; i < n; ++i) {
    INFO("node " << i);
    CHECK((z[static_cast<std::size_t>(i)] - u[static_cast<std::size_t>(i)]).norm() < 1e-9);
    expected_ru += r[static_cast<std::size_t>(i)].dot(u[static_cast<std::size_t>(i)]);
  }
  CHECK(ru == Approx(expected_ru).epsilon(1e-9));
  // A motion of one node alone is not in the modes: its correction is a smooth part of it, not itself.
  std::vector<Eigen::Vector3d> spike(n, Eigen::Vector3d::Zero()), rs(n), zs(n, Eigen::Vector3d::Zero());
  spike[3] = Eigen::Vector3d(1.0, 0.0, 0.0);
  s.a.multiply(spike, rs, active, push);
  coarse.addCorrection(rs, zs, active);
  CHECK((zs[3] - spike[3]).norm() > 0.5);
}

TEST_CASE("coarse_space: too few nodes for two aggregates leaves no coarse level", "[physics]") {
  std::mt19937 rng(9);
  Springs s = springs(30, rng);
  std::vector<std::uint8_t> active(30, 1);
  CoarseSpace coarse;
  coarse.reserve(30, 16);
  coarse.partition(s.x_m, active, 16, 16);  // 30 nodes: one aggregate of 16 at most
  CHECK(coarse.aggregates() == 0);
  CHECK_FALSE(coarse.build(s.a, s.x_m, active));
  CHECK_FALSE(coarse.ready());
}

TEST_CASE("pcg: the two-level preconditioner solves the system as SSOR alone does, in fewer iterations", "[physics]") {
  std::mt19937 rng(13);
  const int n = 800;
  Springs s = springs(n, rng, 12.0, 0.6);  // a slender beam
  std::vector<std::uint8_t> active(n, 1);
  for (int i = 0; i < n; ++i)  // held at one end (x < 0.3), as a beam clamped there
    if (s.x_m[static_cast<std::size_t>(i)].x() < 0.5) active[static_cast<std::size_t>(i)] = 0;
  std::vector<Eigen::Vector3d> b(n, Eigen::Vector3d(0.0, -1e-3, 0.0));
  CoarseSpace coarse;
  coarse.reserve(n, 16);
  coarse.partition(s.x_m, active, 16, 32);
  REQUIRE(coarse.build(s.a, s.x_m, active));
  PcgScratch scratch;
  scratch.resize(n);
  std::vector<Eigen::Vector3d> x_ssor(n, Eigen::Vector3d::Zero()), x_two(n, Eigen::Vector3d::Zero());
  const PcgResult ssor = solvePcg(s.a, active, b, x_ssor, 1e-10, 2000, 1.4, {}, scratch);
  const PcgResult two = solvePcg(s.a, active, b, x_two, 1e-10, 2000, 1.4, {}, scratch, &coarse);
  INFO("iterations: SSOR " << ssor.iterations << ", two-level " << two.iterations);
  REQUIRE(ssor.converged);
  REQUIRE(two.converged);
  CHECK(two.iterations < 0.6 * ssor.iterations);
  std::vector<Eigen::Vector3d> ax(n);
  std::vector<Quad> push(n);
  s.a.multiply(x_two, ax, active, push);
  double largest = 0.0;
  for (int i = 0; i < n; ++i) largest = std::max(largest, x_ssor[static_cast<std::size_t>(i)].norm());
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    CHECK((active[k] ? (ax[k] - b[k]).norm() : x_two[k].norm()) < 1e-10);
    CHECK((x_two[k] - x_ssor[k]).norm() < 1e-6 * largest);
  }
}

}  // namespace
}  // namespace incise::physics::detail
