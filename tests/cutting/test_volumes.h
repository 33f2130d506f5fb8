// Shared test fixtures for the cutting tests: reproducible random B-spline volumes and parameters.
#pragma once

#include <random>
#include <vector>

#include "incise/bspline/bspline_volume.h"
#include "incise/bspline/knot_vector.h"

namespace incise::bspline::testing {

// A volume with random non-uniform knots (interior knots sorted uniform draws, some repeated) and
// random control points in [-1, 1]^3: nothing about it is special.
inline BSplineVolume randomVolume(std::mt19937_64& rng, std::array<int, 3> orders, std::array<int, 3> counts) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::array<std::vector<double>, 3> knots;
  for (int a = 0; a < 3; ++a) {
    const int interior = counts[a] - orders[a];
    std::vector<double> inner(static_cast<size_t>(interior));
    for (auto& t : inner) t = unit(rng);
    if (interior >= 2) inner[1] = inner[0];  // a double knot: non-trivial multiplicity
    std::sort(inner.begin(), inner.end());
    knots[a].assign(static_cast<size_t>(orders[a]), 0.0);
    knots[a].insert(knots[a].end(), inner.begin(), inner.end());
    knots[a].insert(knots[a].end(), static_cast<size_t>(orders[a]), 1.0);
  }
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  std::vector<Eigen::Vector3d> controls(static_cast<size_t>(counts[0]) * counts[1] * counts[2]);
  for (auto& p : controls) p = Eigen::Vector3d(coord(rng), coord(rng), coord(rng));
  return BSplineVolume(orders, std::move(knots), std::move(controls));
}

inline Eigen::Vector3d randomParameter(std::mt19937_64& rng, const BSplineVolume& volume) {
  Eigen::Vector3d t;
  for (int a = 0; a < 3; ++a) {
    const auto d = volume.domain(a);
    t[a] = std::uniform_real_distribution<double>(d[0], d[1])(rng);
  }
  return t;
}

}  // namespace incise::bspline::testing
