#include "json_output.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>
#include <system_error>

namespace incise::apps {

void writeJsonAtomically(const nlohmann::json& document, const std::filesystem::path& path) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << document.dump(2) << '\n';
    out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw std::runtime_error("cannot write " + path.string());
    }
  }
  std::error_code error;
  std::filesystem::rename(tmp, path, error);
  if (error) {
    std::filesystem::remove(tmp, error);
    throw std::runtime_error("cannot write " + path.string());
  }
}

nlohmann::json timingSummary(std::vector<double> values_us) {
  if (values_us.empty()) return {{"count", 0}};
  std::sort(values_us.begin(), values_us.end());
  const auto rank = [&](double q) {
    const size_t r = static_cast<size_t>(std::ceil(q * static_cast<double>(values_us.size())));
    return values_us[std::min(values_us.size() - 1, r == 0 ? 0 : r - 1)];
  };
  return {{"count", values_us.size()},
          {"p50_us", rank(0.5)},
          {"p99_us", rank(0.99)},
          {"max_us", values_us.back()},
          {"mean_us", std::accumulate(values_us.begin(), values_us.end(), 0.0) / static_cast<double>(values_us.size())}};
}

}  // namespace incise::apps
