// The machine a benchmark ran on, as JSON: CPU model, logical cores, compiler, build flags, OS, date.
// Every benchmark prints this beside its figures so that numbers are never quoted without their machine.
#pragma once

#include <nlohmann/json.hpp>

namespace incise::bench {

nlohmann::json machineInfo();

}  // namespace incise::bench
