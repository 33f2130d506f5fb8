// The machine a benchmark ran on, as JSON: CPU model, logical cores, compiler, build flags, OS, date.
// Every benchmark and `incise bench` print this beside their figures, so that numbers are never quoted
// without their machine. Threads: any. Cost: reads /proc/cpuinfo.
#pragma once

#include <nlohmann/json.hpp>

namespace incise::measure {

nlohmann::json machineInfo();

}  // namespace incise::measure
