#include "json_output.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "incise/cutting/atomic_file.h"

namespace incise::apps {

void writeJsonAtomically(const nlohmann::json& document, const std::filesystem::path& path) {
  cutting::writeFileAtomically(path, document.dump(2) + "\n");
}

nlohmann::json incisionFiguresJson(const std::vector<cutting::IncisionFigures>& figures) {
  nlohmann::json list = nlohmann::json::array();
  for (const cutting::IncisionFigures& f : figures)
    list.push_back({{"stroke_length_m", f.stroke_length_m}, {"groove_length_m", f.groove_length_m}});
  return list;
}

double totalGroove_m(const std::vector<cutting::IncisionFigures>& figures) {
  double sum_m = 0.0;
  for (const cutting::IncisionFigures& f : figures) sum_m += f.groove_length_m;
  return sum_m;
}

double totalStroke_m(const std::vector<cutting::IncisionFigures>& figures) {
  double sum_m = 0.0;
  for (const cutting::IncisionFigures& f : figures) sum_m += f.stroke_length_m;
  return sum_m;
}

nlohmann::json timingSummary(std::vector<double> values_us) {
  if (values_us.empty()) return {{"count", 0}};
  std::sort(values_us.begin(), values_us.end());
  const auto rank = [&](double q) {
    const size_t r = static_cast<size_t>(std::ceil(q * static_cast<double>(values_us.size())));
    return values_us[std::min(values_us.size() - 1, r == 0 ? 0 : r - 1)];
  };
  return {
      {"count", values_us.size()},
      {"p50_us", rank(0.5)},
      {"p99_us", rank(0.99)},
      {"max_us", values_us.back()},
      {"mean_us", std::accumulate(values_us.begin(), values_us.end(), 0.0) / static_cast<double>(values_us.size())}};
}

}  // namespace incise::apps
