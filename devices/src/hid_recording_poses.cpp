#include "incise/devices/hid_recording_poses.h"

#include <stdexcept>
#include <string>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_report.h"

namespace incise::devices {
namespace {

// Where the device's R: line is, for messages: "pen.hid: device 0".
std::string where(const std::filesystem::path& file, int device) {
  return (file.empty() ? std::string("recording") : file.string()) + ": device " + std::to_string(device) + ": ";
}

}  // namespace

HidRecordingPoses posesFromHidRecording(const HidRecording& recording, int device, const HidMapping& mapping,
                                        const std::filesystem::path& file) {
  if (device < 0 || static_cast<std::size_t>(device) >= recording.devices.size())
    throw std::invalid_argument(where(file, device) + "no such device (the recording has " +
                                std::to_string(recording.devices.size()) + ")");
  const HidRecordedDevice& d = recording.devices[static_cast<std::size_t>(device)];
  HidDescriptor descriptor;
  std::unique_ptr<HidProfile> profile;
  try {
    descriptor = parseHidDescriptor(d.descriptor);
    profile = makeHidProfile(descriptor, {d.vid, d.pid}, mapping);
  } catch (const HidDescriptorError& e) {
    throw HidDescriptorError(where(file, device) + e.what(), e.offset());
  } catch (const HidProfileError& e) {
    throw HidProfileError(where(file, device) + e.what());
  }
  const HidReportDecoder decoder(descriptor);
  HidRecordingPoses result;
  result.profile = profile->kind();
  for (const HidRecordedReport& report : recording.reports) {
    if (report.device != device) continue;
    ++result.reports;
    PoseSample pose;
    if (!profile->update(report.bytes, report.time_s(), pose)) {
      const bool bad = decoder.check(report.bytes) != HidDecodeStatus::Ok;
      if (bad && result.first_bad_line == 0) result.first_bad_line = report.line;
      ++(bad ? result.bad_reports : result.ignored_reports);
    } else if (!result.poses.empty() && pose.time_s <= result.poses.back().time_s) {
      ++result.same_time;
    } else {
      result.poses.push_back(pose);
    }
  }
  return result;
}

}  // namespace incise::devices
