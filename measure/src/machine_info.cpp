#include "incise/measure/machine_info.h"

#include <sys/utsname.h>

#include <chrono>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>

namespace incise::measure {

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

}  // namespace incise::measure
