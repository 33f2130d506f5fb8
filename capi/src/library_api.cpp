// The C API's calls that take no world: the version, the def's defaults, names, and scoring (incise.h).
#include <cmath>
#include <functional>

#include "capi_convert.h"
#include "capi_status.h"
#include "incise/jobs/score_traces.h"
#include "incise/sim/world.h"

static_assert(INCISE_VERSION_MAJOR == INCISE_PROJECT_VERSION_MAJOR &&
                  INCISE_VERSION_MINOR == INCISE_PROJECT_VERSION_MINOR &&
                  INCISE_VERSION_PATCH == INCISE_PROJECT_VERSION_PATCH,
              "incise.h's version macros differ from the project's version (CMakeLists.txt)");

using incise::capi::fail;
using incise::capi::guarded;
using incise::capi::InvalidArgument;

namespace incise::capi {

namespace {

void fillScore(const sim::Score& s, incise_score& out) noexcept {
  out = incise_score{};
  out.frames = s.frames;
  out.poses = s.poses;
  out.strokes = s.strokes_count;
  out.incisions = s.incisions;
  out.time_s = s.time_s;
  out.path_length_in_contact_m = s.path_length_in_contact_m;
  out.economy = s.economy;
  out.idle_time_s = s.idle_time_s;
  out.peak_force_N = s.peak_force_N;
  out.time_above_force_threshold_s = s.time_above_force_threshold_s;
  out.groove_length_m = s.groove_length_m;
  out.session_path_length_m = s.session.path_length_m;
  out.session_sparc = s.session.sparc;
  out.has_plan = s.has_plan ? 1 : 0;
  const double none = s.has_plan ? 0.0 : std::nan("");
  const auto plan = [&](double x) { return s.has_plan ? x : none; };
  out.lateral_mean_abs_m = plan(s.plan.lateral_mean_abs_m);
  out.share_within_lateral_tolerance = plan(s.plan.share_within_lateral_tolerance);
  out.share_uncut = plan(s.plan.share_uncut);
  out.depth_mean_abs_error_m = plan(s.plan.depth_mean_abs_error_m);
  out.share_within_depth_tolerance = plan(s.plan.share_within_depth_tolerance);
}

// Scores the poses `read` gives on the scenario, into the caller's outputs (incise_score_trace's rules).
incise_status scoreInto(const char* function, const char* scenario_path, const std::string& name,
                        const std::function<std::vector<devices::PoseSample>(const jobs::ScoringScenario&)>& read,
                        incise_score* score, char* json, uint32_t json_capacity, uint32_t* json_length) {
  if (!scenario_path) return nullArgument(function, "scenario_path");
  const jobs::ScoringScenario scoring = jobs::loadScoringScenario(scenario_path);
  const std::vector<devices::PoseSample> poses = read(scoring);
  const sim::Score s = sim::scoreSession(scoring.scenario, scoring.tissue, poses);
  if (score) fillScore(s, *score);
  if (!json && !json_length) return INCISE_SUCCESS;
  return copyText(function, jobs::scoreLine(name, s), json, json_capacity, json_length);
}

}  // namespace

}  // namespace incise::capi

extern "C" {

INCISE_API uint32_t incise_version(void) { return INCISE_VERSION; }

INCISE_API const char* incise_version_string(void) { return INCISE_PROJECT_VERSION_STRING; }

INCISE_API incise_world_def incise_default_world_def(void) {
  const incise::sim::WorldOptions o;
  const incise::incision::IncisionOptions& i = o.cutter.incision;
  incise_world_def def{};
  def.size = sizeof(incise_world_def);
  def.internal_cookie = incise::capi::kWorldDefCookie;
  def.scale = 1.0;
  def.subdivide = 0;
  def.refine = static_cast<uint32_t>(o.cutter.refine);
  def.refine_edge_m = o.cutter.refine_edge_m;
  def.depth_m = i.depth_m;
  def.opening_m = i.opening_m;
  def.alpha_m = i.alpha_m;
  def.beta_m = i.beta_m;
  def.spacing_m = i.spacing_m;
  def.retraction_time_s = i.retraction_time_s;
  def.order = i.order;
  def.wall_rows = o.cutter.wall_rows;
  def.blade_length_m = o.tool.blade_length_m;
  def.cut_button = o.tool.cut_button;
  def.stiffness_N_per_m = o.tissue.stiffness_N_per_m;
  def.damping_N_s_per_m = o.tissue.damping_N_s_per_m;
  def.cutting_resistance_N = o.tissue.cutting_resistance_N;
  def.max_force_N = o.tissue.max_force_N;
  def.cut_budget_us = o.cut_budget_us;
  return def;
}

INCISE_API const char* incise_shortfall_name(uint32_t shortfall) {
  if (shortfall > static_cast<uint32_t>(incise::incision::Shortfall::Unexplained)) return "unknown";
  return incise::incision::toString(static_cast<incise::incision::Shortfall>(shortfall));
}

INCISE_API incise_status incise_score_trace(const char* scenario_path, const char* trace_path, incise_score* score,
                                            char* json, uint32_t json_capacity, uint32_t* json_length) {
  return guarded(__func__, InvalidArgument::Input, [&]() -> incise_status {
    if (!trace_path) return incise::capi::nullArgument(__func__, "trace_path");
    return incise::capi::scoreInto(
        __func__, scenario_path, trace_path,
        [&](const incise::jobs::ScoringScenario& scoring) {
          return incise::jobs::readScoreTrace(trace_path, scoring,
                                              [](const std::string& text) { incise::capi::warn(text); });
        },
        score, json, json_capacity, json_length);
  });
}

INCISE_API incise_status incise_score_poses(const char* scenario_path, const incise_pose* poses, uint32_t pose_count,
                                            incise_score* score, char* json, uint32_t json_capacity,
                                            uint32_t* json_length) {
  return guarded(__func__, InvalidArgument::Input, [&]() -> incise_status {
    if (!poses) return incise::capi::nullArgument(__func__, "poses");
    if (pose_count == 0) return fail(__func__, INCISE_INVALID_PARAMETER, "pose_count is 0 (no pose to score)");
    return incise::capi::scoreInto(
        __func__, scenario_path, "poses",
        [&](const incise::jobs::ScoringScenario&) {
          std::vector<incise::devices::PoseSample> samples;
          samples.reserve(pose_count);
          for (uint32_t i = 0; i < pose_count; ++i) samples.push_back(incise::capi::toPose(poses[i]));
          return samples;
        },
        score, json, json_capacity, json_length);
  });
}

}  // extern "C"
