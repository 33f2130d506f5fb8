// A hid-recorder recording (hid_recording.h) replayed as poses through the same descriptor parser and
// profile as a live device (hid_profile.h), on the recording's clock: the same file gives the same poses,
// bit for bit, on any machine and at any pace. This is what a scenario's {"kind": "hid-recording"} pose
// source is.
//
// The device's descriptor chooses the profile (chooseHidProfile, with the quirk table for its VID:PID from
// the I: line). Reports go through HidProfile::update in file order with time_s = time_us / 10^6; a report
// that moves the tool yields a pose unless its time is not after the previous pose's (equal times are
// common in recordings: several reports of one read); a report that is empty, has an undeclared ID or is
// shorter than its layout is counted and skipped, as the device thread does.
//
// Threads: any. Cost: O(reports * fields bound). Failure: throws HidDescriptorError (the R: line's
// descriptor is refused: what() is prefixed with the file and line of the R: line), HidProfileError (no
// profile fits: prefixed likewise) or std::invalid_argument (no such device index in the recording).
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_recording.h"
#include "incise/devices/pose_sample.h"

namespace incise::devices {

struct HidRecordingPoses {
  std::vector<PoseSample> poses;
  HidProfileKind profile = HidProfileKind::None;
  std::size_t reports = 0;          // of the device
  std::size_t bad_reports = 0;      // empty, undeclared ID, too short: skipped
  std::size_t ignored_reports = 0;  // a layout the profile does not use (a tablet's pad)
  std::size_t same_time = 0;        // moved the tool at the time of the previous pose: folded into the next
  std::size_t first_bad_line = 0;   // file line of the first bad report, 0 when none
};

HidRecordingPoses posesFromHidRecording(const HidRecording& recording, int device, const HidMapping& mapping,
                                        const std::filesystem::path& file = {});

}  // namespace incise::devices
