// The machine a benchmark ran on, as JSON: CPU model, logical cores, compiler, build flags, OS, date.
// Every benchmark prints this beside its figures so that numbers are never quoted without their machine.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

namespace incise::bench {

nlohmann::json machineInfo();

// The q-quantile (0 < q <= 1) of `values` by nearest rank (no interpolation); 0 for no values.
double percentile(std::vector<double> values, double q);

}  // namespace incise::bench
