#include "incise/jobs/score_traces.h"

#include <stdexcept>

#include "incise/devices/trace_csv.h"
#include "incise/sim/plan.h"

namespace incise::jobs {

ScoringScenario loadScoringScenario(const std::filesystem::path& path) {
  ScoringScenario scoring;
  scoring.scenario = sim::loadScenario(path);
  scoring.tissue = sim::loadTissue(scoring.scenario);
  if (scoring.scenario.plan.given)  // bad plans are refused before any trace is read
    sim::projectPlan(scoring.scenario.plan, scoring.tissue, scoring.scenario.world.cutter.incision.spacing_m,
                     scoring.scenario.file);
  scoring.tissue_hash = tissueHashText(scoring.tissue);
  return scoring;
}

std::vector<devices::PoseSample> readScoreTrace(const std::filesystem::path& file, const ScoringScenario& scoring,
                                                const Warn& warn) {
  std::vector<devices::PoseSample> poses;
  devices::TraceReader reader(file);
  while (auto pose = reader.next()) poses.push_back(*pose);
  const std::string recorded = traceTissueHash(reader.comments());
  const std::string& name = scoring.scenario.name;
  if (!recorded.empty() && recorded != scoring.tissue_hash)
    throw std::invalid_argument(file.string() + ": recorded on another tissue (its comment says tissue " + recorded +
                                ", " + name + "'s tissue is " + scoring.tissue_hash + ")");
  if (recorded.empty()) warnWith(warn, file.string() + " carries no tissue hash; scored on " + name + "'s tissue");
  if (poses.empty()) throw std::invalid_argument(file.string() + ": the trace is empty (no pose to score)");
  return poses;
}

std::string scoreLine(const std::string& trace_file, const sim::Score& score) {
  nlohmann::ordered_json line = {{"trace", trace_file}};
  line.update(nlohmann::ordered_json::parse(sim::scoreJson(score)));
  return line.dump();
}

nlohmann::ordered_json scoreSummary(const std::vector<nlohmann::ordered_json>& lines) {
  static const char* keys[] = {"time_s",      "path_length_in_contact_m", "economy", "strokes_count", "idle_time_s",
                               "peak_force_N"};
  static const char* plan_keys[] = {"lateral_mean_abs_m", "share_within_lateral_tolerance", "share_uncut",
                                    "depth_mean_abs_error_m", "share_within_depth_tolerance"};
  nlohmann::ordered_json mean;
  const auto average = [&](const char* key, const char* block) {
    double sum = 0.0;
    int n = 0;
    for (const auto& l : lines) {
      const nlohmann::ordered_json& v = block ? l[block][key] : l[key];
      if (v.is_number()) sum += v.get<double>(), ++n;
    }
    if (n > 0) mean[std::string(block ? std::string(block) + "." : "") + key] = sum / n;
  };
  for (const char* k : keys) average(k, nullptr);
  if (!lines.empty() && lines.front()["plan"].is_object())
    for (const char* k : plan_keys) average(k, "plan");
  return {{"summary", {{"traces", lines.size()}, {"mean", mean}}}};
}

}  // namespace incise::jobs
