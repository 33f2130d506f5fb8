#include "incise/core/format.h"

#include <charconv>

namespace incise::core {

std::string formatNumber(double x) {
  char s[64];
  const auto r = std::to_chars(s, s + sizeof s, x);
  return std::string(s, static_cast<std::size_t>(r.ptr - s));
}

namespace {
template <int N>
std::string formatCoordinates(const Eigen::Matrix<double, N, 1>& p) {
  std::string s = "(";
  for (int i = 0; i < N; ++i) {
    if (i > 0) s += ", ";
    s += formatNumber(p[i]);
  }
  return s + ")";
}
}  // namespace

std::string formatIndices(const std::array<int, 3>& ijk) {
  std::string s = "(";
  for (int i = 0; i < 3; ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(ijk[static_cast<std::size_t>(i)]);
  }
  return s + ")";
}

std::string formatPoint(const Eigen::Vector3d& p) { return formatCoordinates<3>(p); }
std::string formatPoint(const Eigen::Vector2d& p) { return formatCoordinates<2>(p); }

}  // namespace incise::core
