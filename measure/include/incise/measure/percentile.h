// Nearest-rank percentiles (no interpolation), the one definition every figure incise reports uses: the
// latency statistics, the viewer's HUD, the benchmarks.
// Threads: any (pure). Cost: nearestRank O(1); percentile O(n log n) (it sorts a copy).
#pragma once

#include <cstddef>
#include <vector>

namespace incise::measure {

// The ceil(n * num / den)-th smallest of `sorted` (ascending, 1-based rank, at least 1), computed in integers
// so that p99.9 of 1000 samples is exactly the 999th and not the 1000th through rounding of 0.999.
// 0 for no values.
double nearestRank(const std::vector<double>& sorted, std::size_t num, std::size_t den) noexcept;

// The q-quantile (0 < q <= 1, to six decimals) of `values` by nearest rank; 0 for no values.
double percentile(std::vector<double> values, double q);

}  // namespace incise::measure
