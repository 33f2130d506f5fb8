// The C API's worlds (incise.h): each a sim::World with what the API keeps beside it (the scenario's poses
// and rates, the update stream, scratch for converted poses), named by an id of index and generation. A
// slot's generation changes when its world is destroyed, so a stale id is refused, never followed.
// Threads: create, find and destroy from any thread (a mutex guards the table; find's pointer is the
// caller's to use while no other thread destroys that world, as incise.h's thread rules require).
// Cost: O(1) each (the mutex, uncontended, ~20 ns). Failure: create throws std::bad_alloc; the rest never throw.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "capi_convert.h"
#include "capi_status.h"
#include "incise/devices/pose_sample.h"
#include "incise/incise.h"
#include "incise/sim/geometry_stream.h"
#include "incise/sim/world.h"

namespace incise::capi {

struct WorldState {
  std::unique_ptr<sim::World> world;
  std::vector<devices::PoseSample> scenario_poses;
  double period_s = 0.001;
  double settle_s = 0.2;
  std::unique_ptr<sim::GeometryStream> stream;  // incise_world_enable_updates
  std::int64_t steps = 0;
  std::vector<devices::PoseSample> poses;  // a step's poses, converted (grows to the largest step's count)
};

incise_world_id addWorld(std::unique_ptr<WorldState> state);
// The world of `id`, or nullptr for an id that names none (never made, destroyed, zero).
WorldState* findWorld(incise_world_id id) noexcept;
// Destroys the world of `id`; false when there is none.
bool removeWorld(incise_world_id id) noexcept;

// A C API function's body on the world of `id` (guarded: exceptions become statuses; a stale id fails with
// INCISE_INVALID_HANDLE before body(WorldState&) runs).
template <typename Body>
incise_status onWorld(const char* function, incise_world_id id, Body&& body) noexcept {
  return guarded(function, InvalidArgument::Parameter, [&]() -> incise_status {
    WorldState* w = findWorld(id);
    if (!w) return noWorld(function, id);
    return body(*w);
  });
}

}  // namespace incise::capi
