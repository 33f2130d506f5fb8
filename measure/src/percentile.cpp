#include "incise/measure/percentile.h"

#include <algorithm>
#include <cmath>

namespace incise::measure {

double nearestRank(const std::vector<double>& sorted, std::size_t num, std::size_t den) noexcept {
  const std::size_t n = sorted.size();
  if (n == 0 || den == 0) return 0.0;
  const std::size_t rank = std::max<std::size_t>(1, (n * num + den - 1) / den);
  return sorted[std::min(rank, n) - 1];
}

double percentile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  constexpr std::size_t kDen = 1'000'000;
  return nearestRank(values, static_cast<std::size_t>(std::llround(std::clamp(q, 0.0, 1.0) * kDen)), kDen);
}

}  // namespace incise::measure
