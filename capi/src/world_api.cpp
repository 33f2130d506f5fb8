// The C API's worlds: made, destroyed, stepped, described (incise.h).
#include <cmath>
#include <span>

#include "capi_convert.h"
#include "capi_status.h"
#include "incise/jobs/mesh_arrays.h"
#include "incise/jobs/scenario_run.h"
#include "incise/mesh/surface_mesh.h"
#include "world_registry.h"

using incise::capi::fail;
using incise::capi::guarded;
using incise::capi::InvalidArgument;

namespace incise::capi {

namespace {

incise_status created(std::unique_ptr<WorldState> state, incise_world_id* world) {
  *world = addWorld(std::move(state));
  return INCISE_SUCCESS;
}

incise_status worldOver(mesh::SurfaceMesh tissue, const incise_world_def& def, incise_world_id* world) {
  auto state = std::make_unique<WorldState>();
  state->world = std::make_unique<sim::World>(std::move(tissue), worldOptions(def));
  return created(std::move(state), world);
}

void fillResult(const sim::StepResult& r, const sim::World& world, incise_step_result& out) noexcept {
  const sim::HapticState& h = r.haptic;
  for (int a = 0; a < 3; ++a) {
    out.force_N[a] = h.force_N[a];
    out.tip_m[a] = h.tip_m[a];
    out.contact_m[a] = h.contact_m[a];
    out.normal[a] = h.normal[a];
  }
  out.penetration_m = h.penetration_m;
  out.contact = h.contact ? 1 : 0;
  out.cutting = h.cutting ? 1 : 0;
  out.poses_used = h.poses;
  out.poses_rejected = h.poses_rejected;
  out.incisions = world.incisions();
  out.pending = world.pending() ? 1 : 0;
  out.cut_failed = r.cut.failed ? 1 : 0;
  out.reserved = 0;
}

}  // namespace

}  // namespace incise::capi

extern "C" {

INCISE_API incise_status incise_world_create_from_mesh_file(const char* path, const incise_world_def* def,
                                                            incise_world_id* world) {
  return guarded(__func__, InvalidArgument::Parameter, [&]() -> incise_status {
    using namespace incise;
    if (!path) return capi::nullArgument(__func__, "path");
    if (!world) return capi::nullArgument(__func__, "world");
    if (const incise_status s = capi::checkDef(__func__, def); !incise_succeeded(s)) return s;
    return capi::worldOver(mesh::subdivided(mesh::loadSurfaceMesh(path, def->scale), def->subdivide), *def, world);
  });
}

INCISE_API incise_status incise_world_create_from_arrays(const double* xyz_m, uint32_t vertex_count,
                                                         const uint32_t* triangles, uint32_t face_count,
                                                         const incise_world_def* def, incise_world_id* world) {
  return guarded(__func__, InvalidArgument::Parameter, [&]() -> incise_status {
    using namespace incise;
    if (!xyz_m) return capi::nullArgument(__func__, "xyz_m");
    if (!triangles) return capi::nullArgument(__func__, "triangles");
    if (!world) return capi::nullArgument(__func__, "world");
    if (const incise_status s = capi::checkDef(__func__, def); !incise_succeeded(s)) return s;
    const std::vector<std::int64_t> indices(triangles, triangles + 3 * static_cast<std::size_t>(face_count));
    return capi::worldOver(jobs::meshFromArrays(std::span(xyz_m, 3 * static_cast<std::size_t>(vertex_count)), indices),
                           *def, world);
  });
}

INCISE_API incise_status incise_world_create_from_scenario(const char* path, incise_world_id* world) {
  return guarded(__func__, InvalidArgument::Input, [&]() -> incise_status {
    using namespace incise;
    if (!path) return capi::nullArgument(__func__, "path");
    if (!world) return capi::nullArgument(__func__, "world");
    jobs::ScenarioRun run = jobs::loadScenarioRun(path, [](const std::string& text) { capi::warn(text); });
    auto state = std::make_unique<capi::WorldState>();
    state->world = std::move(run.world);
    state->scenario_poses = std::move(run.poses);
    state->period_s = 1e-6 * static_cast<double>(run.scenario.periodUs());
    state->settle_s = run.scenario.settle_s;
    return capi::created(std::move(state), world);
  });
}

INCISE_API incise_status incise_world_destroy(incise_world_id world) {
  return guarded(__func__, InvalidArgument::Parameter, [&]() -> incise_status {
    if (!incise::capi::removeWorld(world)) return incise::capi::noWorld(__func__, world);
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_step(incise_world_id world, const incise_pose* poses, uint32_t pose_count,
                                           double dt_s, double t_s, incise_step_result* result) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    if (pose_count > 0 && !poses) return capi::nullArgument(__func__, "poses");
    if (!(std::isfinite(dt_s) && dt_s > 0.0) || !std::isfinite(t_s))
      return fail(__func__, INCISE_INVALID_PARAMETER,
                  "dt_s = " + std::to_string(dt_s) + ", t_s = " + std::to_string(t_s) +
                      ": dt_s must be finite and > 0, t_s finite");
    w.poses.resize(pose_count);  // allocates only when a step brings more poses than any before
    for (uint32_t i = 0; i < pose_count; ++i) w.poses[i] = capi::toPose(poses[i]);
    const sim::StepResult r = w.world->step(std::span(w.poses.data(), pose_count), dt_s, t_s);
    if (w.stream) w.stream->publish(*w.world, w.steps);
    ++w.steps;
    if (result) capi::fillResult(r, *w.world, *result);
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_get_info(incise_world_id world, incise_world_info* info) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    if (!info) return capi::nullArgument(__func__, "info");
    const mesh::TriMesh& m = w.world->tissue().mesh();
    info->vertex_count = static_cast<uint32_t>(m.n_vertices());
    info->face_count = static_cast<uint32_t>(m.n_faces());
    info->incisions = w.world->incisions();
    info->pending = w.world->pending() ? 1 : 0;
    info->period_s = w.period_s;
    info->settle_s = w.settle_s;
    info->scenario_pose_count = static_cast<uint32_t>(w.scenario_poses.size());
    info->has_tets = w.world->tets() ? 1 : 0;
    return INCISE_SUCCESS;
  });
}

INCISE_API incise_status incise_world_scenario_poses(incise_world_id world, incise_pose* poses, uint32_t capacity,
                                                     uint32_t* count) {
  return incise::capi::onWorld(__func__, world, [&](incise::capi::WorldState& w) -> incise_status {
    using namespace incise;
    incise_status status;
    if (!capi::bufferFits(__func__, poses, capacity, w.scenario_poses.size(), count, &status)) return status;
    for (std::size_t i = 0; i < w.scenario_poses.size(); ++i) poses[i] = capi::fromPose(w.scenario_poses[i]);
    return INCISE_SUCCESS;
  });
}

}  // extern "C"
