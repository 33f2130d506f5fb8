#include "json_output.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "incise/core/atomic_file.h"

namespace incise::apps {

void writeJsonAtomically(const nlohmann::json& document, const std::filesystem::path& path) {
  core::writeFileAtomically(path, document.dump(2) + "\n");
}

nlohmann::json incisionFiguresJson(const std::vector<incision::IncisionFigures>& figures) {
  nlohmann::json list = nlohmann::json::array();
  for (const incision::IncisionFigures& f : figures)
    list.push_back({{"stroke_length_m", f.stroke_length_m},
                    {"groove_length_m", f.groove_length_m},
                    {"groove_start_m", f.groove_start_m},
                    {"groove_end_m", f.groove_end_m},
                    {"lattice_columns", f.columns},
                    {"empty_columns", f.empty_columns},
                    {"seam_vertices", f.seam_vertices},
                    {"refined_vertices", f.refined_vertices},
                    {"refined_faces", f.refined_faces},
                    {"shortfall", incision::toString(f.shortfall)},
                    {"why", incision::describeShortfall(f)}});
  return list;
}

std::string cutFailure(const incision::CutStats& stats) {
  if (!stats.failure.empty()) return stats.failure;
  for (std::size_t i = 0; i < stats.figures.size(); ++i)
    if (stats.figures[i].shortfall != incision::Shortfall::None)
      return "incision " + std::to_string(i + 1) + " of " + std::to_string(stats.figures.size()) + ": " +
             incision::describeShortfall(stats.figures[i]);
  return "";
}

double totalGroove_m(const std::vector<incision::IncisionFigures>& figures) {
  double sum_m = 0.0;
  for (const incision::IncisionFigures& f : figures) sum_m += f.groove_length_m;
  return sum_m;
}

double totalStroke_m(const std::vector<incision::IncisionFigures>& figures) {
  double sum_m = 0.0;
  for (const incision::IncisionFigures& f : figures) sum_m += f.stroke_length_m;
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
