// Numbers and points in messages and text outputs: the shortest text that reads back to the same double
// (std::to_chars: round trip, locale-independent), so the value a message names is exactly the value that
// was refused, and 0.1 reads "0.1". The one formatter of incise (errors, summaries, reports).
// Threads: any. Cost: O(1) per number; allocates the string.
#pragma once

#include <array>
#include <string>

#include <Eigen/Core>

namespace incise::core {

std::string formatNumber(double x);
// "(x, y, z)" and "(x, y)", each coordinate as formatNumber writes it.
std::string formatPoint(const Eigen::Vector3d& p);
std::string formatPoint(const Eigen::Vector2d& p);
// "(i, j, k)": a triple of indices (a control point, a face's or a tet face's vertices).
std::string formatIndices(const std::array<int, 3>& ijk);

}  // namespace incise::core
