// Conversions between the C API's structs (incise.h) and incise's C++ types, and the checks every C API
// function makes of its arguments. Threads: any. Cost: O(1) per element. Failure: the checks
// return a failed incise_status with the message recorded (capi_status.h); they build messages, so they run
// inside a guarded body (they may throw std::bad_alloc).
#pragma once

#include <cstdint>
#include <string>

#include "capi_status.h"
#include "incise/devices/pose_sample.h"
#include "incise/incise.h"
#include "incise/sim/world.h"

namespace incise::capi {

// incise_default_world_def() sets it; a def without it was not made by that call.
inline constexpr std::uint32_t kWorldDefCookie = 0x1c15e0d1;

devices::PoseSample toPose(const incise_pose& pose) noexcept;
incise_pose fromPose(const devices::PoseSample& pose) noexcept;

// The def checked (non-NULL, its size and cookie, refine and subdivide in range); INCISE_SUCCESS or a failure.
incise_status checkDef(const char* function, const incise_world_def* def);
// The world's options the def gives (its other checks are the World's, at construction).
sim::WorldOptions worldOptions(const incise_world_def& def);

// "`name` is NULL" as a failure (INCISE_INVALID_PARAMETER).
incise_status nullArgument(const char* function, const char* name);
// The stale-id failure (INCISE_INVALID_HANDLE).
incise_status noWorld(const char* function, incise_world_id id);

// The count rule of every buffer (incise.h): `count` written; a NULL buffer asks for the count alone
// (false: nothing to write, INCISE_SUCCESS in *status); a buffer smaller than `needed` fails (false,
// INCISE_BUFFER_TOO_SMALL in *status); true: write `needed` elements.
bool bufferFits(const char* function, const void* buffer, std::uint32_t capacity, std::size_t needed,
                std::uint32_t* count, incise_status* status);

// `text` NUL-terminated into `buffer` under the same rule, `length` counting the NUL.
incise_status copyText(const char* function, const std::string& text, char* buffer, std::uint32_t capacity,
                       std::uint32_t* length);

}  // namespace incise::capi
