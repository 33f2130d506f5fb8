// The score as one JSON line (score.h, scoreJson): keys in a fixed order, units in every key.
#include <cmath>

#include <nlohmann/json.hpp>

#include "incise/sim/score.h"

namespace incise::sim {

namespace {

using Json = nlohmann::ordered_json;

Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json motionJson(const MotionFigures& m) {
  return {{"time_s", number(m.time_s)},
          {"path_length_m", number(m.path_length_m)},
          {"straight_line_m", number(m.straight_line_m)},
          {"economy", number(m.path_length_m > 0.0 ? m.straight_line_m / m.path_length_m : 0.0)},
          {"mean_speed_m_per_s", number(m.mean_speed_m_per_s)},
          {"log_dimensionless_jerk", number(m.log_dimensionless_jerk)},
          {"sparc", number(m.sparc)}};
}

Json planJson(const PlanScore& p) {
  return {{"length_m", number(p.length_m)},
          {"target_depth_m", number(p.target_depth_m)},
          {"lateral_tolerance_m", number(p.lateral_tolerance_m)},
          {"depth_tolerance_m", number(p.depth_tolerance_m)},
          {"lateral_mean_abs_m", number(p.lateral_mean_abs_m)},
          {"lateral_rms_m", number(p.lateral_rms_m)},
          {"lateral_max_m", number(p.lateral_max_m)},
          {"share_within_lateral_tolerance", number(p.share_within_lateral_tolerance)},
          {"share_uncut", number(p.share_uncut)},
          {"length_cut_outside_band_m", number(p.length_cut_outside_band_m)},
          {"depth_mean_abs_error_m", number(p.depth_mean_abs_error_m)},
          {"depth_max_overshoot_m", number(p.depth_max_overshoot_m)},
          {"share_within_depth_tolerance", number(p.share_within_depth_tolerance)},
          {"blade_depth_mean_abs_error_m", number(p.blade_depth_mean_abs_error_m)},
          {"blade_depth_max_overshoot_m", number(p.blade_depth_max_overshoot_m)}};
}

}  // namespace

std::string scoreJson(const Score& s) {
  Json strokes = Json::array();
  for (const StrokeScore& k : s.strokes) {
    Json stroke = {{"start_s", number(k.start_s)}, {"end_s", number(k.end_s)}};
    stroke.update(motionJson(k.motion));
    stroke["path_length_in_contact_m"] = number(k.motion.path_length_m);
    stroke["peak_force_N"] = number(k.peak_force_N);
    strokes.push_back(stroke);
  }
  Json j = {{"scenario", s.scenario},
            {"frames", s.frames},
            {"poses", s.poses},
            {"strokes_count", s.strokes_count},
            {"time_s", number(s.time_s)},
            {"path_length_in_contact_m", number(s.path_length_in_contact_m)},
            {"economy", number(s.economy)},
            {"economy_reference", s.has_plan ? "plan_length" : "straight_line"},
            {"idle_time_s", number(s.idle_time_s)},
            {"peak_force_N", number(s.peak_force_N)},
            {"force_threshold_N", number(s.force_threshold_N)},
            {"time_above_force_threshold_s", number(s.time_above_force_threshold_s)},
            {"impulse_above_force_threshold_N_s", number(s.impulse_above_force_threshold_N_s)},
            {"incisions", s.incisions},
            {"groove_length_m", number(s.groove_length_m)},
            {"plan", s.has_plan ? planJson(s.plan) : Json(nullptr)},
            {"session", motionJson(s.session)},
            {"strokes", strokes}};
  return j.dump();
}

}  // namespace incise::sim
