// Private to the generator (hid_synth.h): what its pen and 6-DOF halves share.
#pragma once

#include <cstddef>
#include <span>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/pose_sample.h"

namespace incise::devices::detail {

// The pose at time t_s: tip linear and orientation slerp between the samples around it, buttons and
// pressure of the one before (time_s set to t_s). `hint` walks forward with increasing t_s.
PoseSample interpolatePose(std::span<const PoseSample> poses, double t_s, std::size_t& hint);

// The 6-DOF reports for `poses` into out.reports (hid_synth_six_dof.cpp).
void synthesizeSixDof(HidRecording& out, const HidDescriptor& d, HidDeviceId id, const HidMapping& mapping,
                      std::span<const PoseSample> poses, double rate_hz);

}  // namespace incise::devices::detail
