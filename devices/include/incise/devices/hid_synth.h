// The generator of the shipped HID recordings: a report stream for a stroke (a time-ordered list of poses,
// e.g. the strokes of scenarios/generate/) made from a real report descriptor — the inverse of the
// extractor and the profile. Replaying the result (hid_recording_poses.h) gives the stroke back up to the
// device's resolution. How each kind of device is driven: above synthesizeHidRecording.
//
// Threads: any. Cost: O(reports * fields). Failure: throws HidDescriptorError / HidProfileError for a
// descriptor that is refused or fits no profile, std::invalid_argument for fewer than two poses, poses not in
// time order or rate_hz outside [1, 10000].
#pragma once

#include <span>

#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/pose_sample.h"

namespace incise::devices {

struct HidSynthOptions {
  double rate_hz = 200.0;  // pen reports, or 6-DOF translation/rotation report pairs, per second
};

// A one-device recording of `device` (its descriptor, name, bus, VID, PID as given) whose reports make `poses`.
// Pen (the descriptor's profile is Pen, hid_pen.h): every 1 / rate_hz s from the first pose's time, the pose
// interpolated there (tip linear, orientation slerp, buttons of the pose before), turned into tablet
// fractions, pressure, tilt and twist by penReadingFor, and encoded: In Range 1; Tip Switch 1 and the
// pressure while button 0 is down and the tip is below the area; hovering otherwise. A pen whose usages are
// spread over several input reports gets one of each per pose, their times spread evenly over the period.
// After the last pose the pen leaves: reports of zeros (out of range), or for a pen without In Range its
// last X and Y with the tip up.
// 6-DOF: velocity control is closed-loop: the generator drives a profile exactly like the one that will
// replay the file and chooses each report's deflections so that the integrated tip and orientation reach the
// next interpolated pose by the next report (clamped to full deflection: a stroke faster than
// max_speed_m_per_s lags). Translation report at t_k, rotation report at t_k + half a period, a button report
// when the buttons change.
// Times are written in whole microseconds from 0.
HidRecording synthesizeHidRecording(const HidRecordedDevice& device, const HidMapping& mapping,
                                    std::span<const PoseSample> poses, const HidSynthOptions& options = {});

}  // namespace incise::devices
