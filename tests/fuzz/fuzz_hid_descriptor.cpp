// libFuzzer harness: the HID report-descriptor parser (devices/hid_descriptor.h). The input is parsed
// twice: as a descriptor's raw bytes (parseHidDescriptor), and as the hex text of the shipped descriptor
// files (parseHexBytes, whose bytes are parsed as a descriptor in turn). HidDescriptorError and
// parseHexBytes' std::invalid_argument are the documented failures; anything else escaping, a crash, a hang
// or a sanitizer report is a finding. A parsed descriptor is walked (reports, fields, usages) and must keep
// the limits the header promises (fields of 1..256 bits, reports of at most 4096 bytes).
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "fuzz_input.h"
#include "incise/devices/hid_descriptor.h"

namespace {

using namespace incise::devices;

void walk(const HidDescriptor& descriptor) {
  for (const HidReportLayout& report : descriptor.reports) {
    if (report.wireBytes(descriptor.uses_report_ids) > 4097) __builtin_trap();
    if (descriptor.find(report.type, report.id) == nullptr) __builtin_trap();
    for (const HidField& field : report.fields) {
      if (field.bit_size < 1 || field.bit_size > 256) __builtin_trap();
      if (field.isVariable())
        for (std::uint32_t e = 0; e < field.count; ++e) (void)field.usageOf(e);
    }
  }
  (void)descriptor.applications();
}

void parse(std::span<const std::uint8_t> bytes) {
  try {
    walk(parseHidDescriptor(bytes));
  } catch (const HidDescriptorError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  parse(std::span<const std::uint8_t>(data, size));
  try {
    const std::vector<std::uint8_t> bytes = parseHexBytes(incise::fuzz::asText(data, size));
    parse(bytes);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
