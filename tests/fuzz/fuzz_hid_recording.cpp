// libFuzzer harness: the hid-recorder file reader (devices/hid_recording.h). The input is a recording's
// bytes, read whole; HidRecordingError is the documented failure, anything else escaping, a crash, a hang
// or a sanitizer report is a finding. A recording read without error must keep its documented promises
// (at least one device, each with its descriptor; reports point at a device).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "incise/devices/hid_recording.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = incise::fuzz::writeInput(data, size, "recording.hid");
  try {
    const incise::devices::HidRecording recording = incise::devices::readHidRecording(path);
    if (recording.devices.empty()) __builtin_trap();
    for (const auto& device : recording.devices)
      if (device.descriptor.empty() || device.descriptor.size() > incise::devices::kHidMaxDescriptorBytes)
        __builtin_trap();
    for (const auto& report : recording.reports)
      if (report.device < 0 || static_cast<std::size_t>(report.device) >= recording.devices.size() ||
          report.time_us < 0 || report.bytes.empty())
        __builtin_trap();
  } catch (const incise::devices::HidRecordingError&) {
  }
  return 0;
}
