#include "machine_info.h"

#include <algorithm>
#include <cmath>

#include <sys/utsname.h>

#include <chrono>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>

namespace incise::bench {

namespace {

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown";
}

std::string utcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return buffer;
}

}  // namespace

nlohmann::json machineInfo() {
  utsname name{};
  uname(&name);
  return {
    {"cpu", cpuModel()}, {"logical_cores", std::thread::hardware_concurrency()},
        {"os", std::string(name.sysname) + " " + name.release}, {"compiler", std::string("g++ ") + __VERSION__},
#if defined(__AVX2__)
        {"simd", "avx2"},
#elif defined(__SSE2__)
        {"simd", "sse2"},
#else
        {"simd", "none"},
#endif
        {"utc", utcNow()},
  };
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::min(values.size() - 1, rank == 0 ? 0 : rank - 1)];
}

}  // namespace incise::bench
