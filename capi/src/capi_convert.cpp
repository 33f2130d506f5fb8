#include "capi_convert.h"

#include <cstring>
#include <limits>

#include "incise/incision/surface_cutter_options.h"

namespace incise::capi {

devices::PoseSample toPose(const incise_pose& pose) noexcept {
  devices::PoseSample p;
  p.time_s = pose.time_s;
  p.tip_m = Eigen::Vector3d(pose.tip_m[0], pose.tip_m[1], pose.tip_m[2]);
  const double* q = pose.orientation_wxyz;
  p.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  p.buttons = pose.buttons;
  if (pose.has_pressure) p.pressure = pose.pressure;
  return p;
}

incise_pose fromPose(const devices::PoseSample& p) noexcept {
  incise_pose pose{};
  pose.time_s = p.time_s;
  for (int a = 0; a < 3; ++a) pose.tip_m[a] = p.tip_m[a];
  pose.orientation_wxyz[0] = p.orientation.w();
  pose.orientation_wxyz[1] = p.orientation.x();
  pose.orientation_wxyz[2] = p.orientation.y();
  pose.orientation_wxyz[3] = p.orientation.z();
  pose.buttons = p.buttons;
  pose.has_pressure = p.pressure.has_value() ? 1 : 0;
  pose.pressure = p.pressure.value_or(0.0);
  return pose;
}

incise_status checkDef(const char* function, const incise_world_def* def) {
  if (!def) return nullArgument(function, "def");
  if (def->size != sizeof(incise_world_def) || def->internal_cookie != kWorldDefCookie)
    return fail(function, INCISE_INVALID_PARAMETER,
                "def was not filled by incise_default_world_def() (its size or cookie is wrong: an uninitialised "
                "def, or one from another version of incise.h)");
  if (def->refine > INCISE_REFINE_PN)
    return fail(function, INCISE_INVALID_PARAMETER,
                "def->refine = " + std::to_string(def->refine) + " is not an incise_refine");
  if (def->subdivide < 0 || def->subdivide > 5)
    return fail(function, INCISE_INVALID_PARAMETER,
                "def->subdivide = " + std::to_string(def->subdivide) + " is outside [0, 5]");
  return INCISE_SUCCESS;
}

sim::WorldOptions worldOptions(const incise_world_def& def) {
  sim::WorldOptions o;
  incision::IncisionOptions& i = o.cutter.incision;
  i.depth_m = def.depth_m;
  i.opening_m = def.opening_m;
  i.alpha_m = def.alpha_m;
  i.beta_m = def.beta_m;
  i.spacing_m = def.spacing_m;
  i.retraction_time_s = def.retraction_time_s;
  i.order = def.order;
  o.cutter.wall_rows = def.wall_rows;
  o.cutter.refine = static_cast<incision::CutterOptions::Refine>(def.refine);
  o.cutter.refine_edge_m = def.refine_edge_m;
  o.tool.blade_length_m = def.blade_length_m;
  o.tool.cut_button = def.cut_button;
  o.tissue.stiffness_N_per_m = def.stiffness_N_per_m;
  o.tissue.damping_N_s_per_m = def.damping_N_s_per_m;
  o.tissue.cutting_resistance_N = def.cutting_resistance_N;
  o.tissue.max_force_N = def.max_force_N;
  o.cut_budget_us = def.cut_budget_us;
  return o;
}

incise_status nullArgument(const char* function, const char* name) {
  return fail(function, INCISE_INVALID_PARAMETER, std::string(name) + " is NULL");
}

incise_status noWorld(const char* function, incise_world_id id) {
  return fail(function, INCISE_INVALID_HANDLE,
              "no world has the id {" + std::to_string(id.index) + ", " + std::to_string(id.generation) +
                  "} (destroyed, or never made)");
}

bool bufferFits(const char* function, const void* buffer, std::uint32_t capacity, std::size_t needed,
                std::uint32_t* count, incise_status* status) {
  if (!count) {
    *status = nullArgument(function, "count");
    return false;
  }
  if (needed > std::numeric_limits<std::uint32_t>::max()) {
    *status = fail(function, INCISE_INTERNAL_ERROR, std::to_string(needed) + " elements do not fit a uint32_t count");
    return false;
  }
  *count = static_cast<std::uint32_t>(needed);
  *status = INCISE_SUCCESS;
  if (!buffer) return false;
  if (capacity < needed) {
    *status = fail(function, INCISE_BUFFER_TOO_SMALL,
                   "the buffer holds " + std::to_string(capacity) + " elements, " + std::to_string(needed) +
                       " are needed (written to count)");
    return false;
  }
  return true;
}

incise_status copyText(const char* function, const std::string& text, char* buffer, std::uint32_t capacity,
                       std::uint32_t* length) {
  std::uint32_t needed = 0;
  incise_status status = INCISE_SUCCESS;
  if (!bufferFits(function, buffer, capacity, text.size() + 1, &needed, &status)) {
    if (length) *length = needed;
    return status;
  }
  std::memcpy(buffer, text.c_str(), text.size() + 1);
  if (length) *length = needed;
  return INCISE_SUCCESS;
}

}  // namespace incise::capi
