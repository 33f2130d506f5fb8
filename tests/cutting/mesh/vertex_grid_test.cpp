// Tests for cutting/mesh/src/vertex_grid.cpp: box queries against brute force, move/remove, order and
// allocation behaviour, argument checks and the suggested cell size.
#include "incise/mesh/vertex_grid.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

namespace incise::mesh {
namespace {

std::vector<int> bruteForce(const std::vector<Eigen::Vector3d>& points, const Eigen::AlignedBox3d& box) {
  std::vector<int> ids;
  for (size_t i = 0; i < points.size(); ++i)
    if (box.contains(points[i])) ids.push_back(static_cast<int>(i));
  return ids;
}

Eigen::Vector3d randomPoint(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

Eigen::AlignedBox3d randomBox(std::mt19937& rng) {
  const Eigen::Vector3d a = randomPoint(rng, -1.2, 1.2), b = randomPoint(rng, -1.2, 1.2);
  return Eigen::AlignedBox3d(a.cwiseMin(b), a.cwiseMax(b));
}

std::vector<int> query(const VertexGrid& grid, const Eigen::AlignedBox3d& box) {
  std::vector<int> out;
  grid.query(box, out);
  return out;
}

TEST_CASE("vertex_grid: query returns exactly the brute-force set for 1000 random points and 100 random boxes",
          "[cutting]") {
  std::mt19937 rng(12345);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1000; ++i) points.push_back(randomPoint(rng, -1.0, 1.0));
  for (const double cell : {0.05, 0.3, 5.0}) {
    VertexGrid grid(cell);
    for (size_t i = 0; i < points.size(); ++i) grid.insert(static_cast<int>(i), points[i]);
    REQUIRE(grid.size() == 1000);
    int nonempty = 0;
    for (int b = 0; b < 100; ++b) {
      const Eigen::AlignedBox3d box = randomBox(rng);
      const std::vector<int> expected = bruteForce(points, box);
      nonempty += !expected.empty();
      REQUIRE(query(grid, box) == expected);  // both ascending
    }
    REQUIRE(nonempty > 50);
  }
}

TEST_CASE("vertex_grid: a box on a point's exact coordinates and a huge box both find it", "[cutting]") {
  VertexGrid grid(0.1);
  grid.insert(3, {0.2, 0.3, -0.4});
  grid.insert(1, {1e9, -1e9, 0.0});  // beyond the clamped cell range
  REQUIRE(query(grid, Eigen::AlignedBox3d(Eigen::Vector3d(0.2, 0.3, -0.4), Eigen::Vector3d(0.2, 0.3, -0.4))) ==
          std::vector<int>{3});
  const double big = 1e12;
  REQUIRE(query(grid, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-big), Eigen::Vector3d::Constant(big))) ==
          std::vector<int>{1, 3});
  REQUIRE(query(grid, Eigen::AlignedBox3d(Eigen::Vector3d(9e8, -2e9, -1), Eigen::Vector3d(2e9, 0, 1))) ==
          std::vector<int>{1});
  REQUIRE(query(grid, Eigen::AlignedBox3d()).empty());  // empty box
  const double nan = std::nan("");
  REQUIRE(query(grid, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(nan), Eigen::Vector3d::Constant(big))).empty());
}

TEST_CASE("vertex_grid: move() updates membership", "[cutting]") {
  std::mt19937 rng(7);
  std::vector<Eigen::Vector3d> points;
  VertexGrid grid(0.2);
  for (int i = 0; i < 300; ++i) {
    points.push_back(randomPoint(rng, -1.0, 1.0));
    grid.insert(i, points.back());
  }
  for (int round = 0; round < 5; ++round) {
    for (int i = 0; i < 300; i += 2) {  // half the points: a small step (often the same cell) or a jump
      const Eigen::Vector3d to =
          (i % 4 == 0) ? points[static_cast<size_t>(i)] + randomPoint(rng, -0.01, 0.01) : randomPoint(rng, -1.0, 1.0);
      grid.move(i, points[static_cast<size_t>(i)], to);
      points[static_cast<size_t>(i)] = to;
    }
    REQUIRE(grid.size() == 300);
    for (int b = 0; b < 30; ++b) {
      const Eigen::AlignedBox3d box = randomBox(rng);
      REQUIRE(query(grid, box) == bruteForce(points, box));
    }
  }
  const Eigen::Vector3d far(10, 10, 10);
  grid.move(0, points[0], far);
  REQUIRE(query(grid, Eigen::AlignedBox3d(far, far)) == std::vector<int>{0});
  REQUIRE(query(grid, Eigen::AlignedBox3d(points[0], points[0])).empty());
  grid.remove(0, far);
  REQUIRE(grid.size() == 299);
  REQUIRE(query(grid, Eigen::AlignedBox3d(far, far)).empty());
}

TEST_CASE("vertex_grid: bad arguments throw and leave the grid unchanged", "[cutting]") {
  REQUIRE_THROWS_AS(VertexGrid(0.0), std::invalid_argument);
  REQUIRE_THROWS_AS(VertexGrid(-1.0), std::invalid_argument);
  REQUIRE_THROWS_AS(VertexGrid(std::nan("")), std::invalid_argument);
  VertexGrid grid(1.0);
  grid.insert(4, {0.5, 0.5, 0.5});
  REQUIRE_THROWS_AS(grid.insert(5, {0.0, std::nan(""), 0.0}), std::invalid_argument);
  REQUIRE_THROWS_AS(grid.move(4, {0.4, 0.5, 0.5}, {2, 2, 2}), std::invalid_argument);  // not where it is
  REQUIRE_THROWS_AS(grid.move(5, {0.5, 0.5, 0.5}, {2, 2, 2}), std::invalid_argument);  // no such id there
  REQUIRE_THROWS_AS(grid.move(4, {0.5, 0.5, 0.5}, {2, INFINITY, 2}), std::invalid_argument);
  REQUIRE_THROWS_AS(grid.remove(4, {7, 7, 7}), std::invalid_argument);
  REQUIRE(grid.size() == 1);
  REQUIRE(query(grid, Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones())) == std::vector<int>{4});
  grid.clear();
  REQUIRE(grid.size() == 0);
}

TEST_CASE("vertex_grid: query appends after existing content without reallocating a reserved vector", "[cutting]") {
  VertexGrid grid(0.25);
  for (int i = 0; i < 50; ++i) grid.insert(49 - i, Eigen::Vector3d(0.01 * i, 0.0, 0.0));
  std::vector<int> out{-7};
  out.reserve(100);
  const int* data = out.data();
  grid.query(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(0.195, 1, 1)), out);
  REQUIRE(out.data() == data);
  REQUIRE(out.front() == -7);
  const std::vector<int> appended(out.begin() + 1, out.end());
  REQUIRE(appended.size() == 20);  // x = 0, 0.01, ..., 0.19: ids 49 down to 30
  REQUIRE(std::is_sorted(appended.begin(), appended.end()));
  REQUIRE(appended.front() == 30);
}

TEST_CASE("vertex_grid: suggestedCellSize is twice the mean edge length", "[cutting]") {
  TriMesh mesh;
  const auto a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({3, 0, 0}), c = mesh.add_vertex({0, 4, 0});
  REQUIRE_THROWS_AS(suggestedCellSize(mesh), std::invalid_argument);  // no edges yet
  mesh.add_face(a, b, c);
  REQUIRE(suggestedCellSize(mesh) == Approx(2.0 * (3.0 + 4.0 + 5.0) / 3.0));
  const SurfaceMesh bunny = loadSurfaceMesh(std::filesystem::path(INCISE_SCENARIOS_DIR) / "meshes" / "bunny.obj");
  const double cell = suggestedCellSize(bunny.mesh());
  VertexGrid grid(cell);
  for (const auto v : bunny.mesh().vertices()) grid.insert(v.idx(), toEigen(bunny.mesh().point(v)));
  const Eigen::Vector3d p = toEigen(bunny.mesh().point(TriMesh::VertexHandle(100)));
  std::vector<int> near;
  grid.query(Eigen::AlignedBox3d(p.array() - cell, p.array() + cell), near);
  for (const auto v : bunny.mesh().vv_range(TriMesh::VertexHandle(100)))
    if ((toEigen(bunny.mesh().point(v)) - p).lpNorm<Eigen::Infinity>() <= cell)
      REQUIRE(std::binary_search(near.begin(), near.end(), v.idx()));
  REQUIRE(std::binary_search(near.begin(), near.end(), 100));
}

}  // namespace
}  // namespace incise::mesh
