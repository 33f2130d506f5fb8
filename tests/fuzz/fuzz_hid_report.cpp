// libFuzzer harness: the HID report extractor and encoder (devices/hid_report.h). The input is a
// descriptor and a report: byte 0 and 1 give the descriptor's length n (little-endian, taken modulo what
// is left), the next n bytes are the descriptor, the rest is one raw report as hid_read returns it. A
// descriptor the parser refuses ends the run (that parser has its own harness). The report is decoded as
// Input, Output and Feature (decode never throws: the header says so, and it is noexcept); every field's
// elements are read, mapped to physical values and back, and written with the encoder into a blank report.
// A crash, a hang or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_report.h"

namespace {

using namespace incise::devices;

void decodeAs(const HidDescriptor& descriptor, HidReportType type, std::span<const std::uint8_t> raw) {
  const HidReportDecoder decoder(descriptor, type);
  std::vector<HidValue> values(decoder.maxValues());
  const HidDecoded decoded = decoder.decode(raw, values);
  if (decoded.status != decoder.check(raw) || decoded.values > values.size()) __builtin_trap();
  if (decoded.status == HidDecodeStatus::Ok && decoded.layout != decoder.layoutOf(raw)) __builtin_trap();
  (void)toString(decoded.status);
}

// Every element of every field: read, physical and back, unit names; then each usage set in a blank report.
void encodeAll(const HidDescriptor& descriptor, std::span<const std::uint8_t> payload) {
  const HidReportEncoder encoder(descriptor);
  for (const HidReportLayout& layout : descriptor.reports) {
    if (layout.type != HidReportType::Input) continue;
    std::vector<std::uint8_t> blank = encoder.blank(layout);
    for (const HidField& field : layout.fields) {
      for (std::uint32_t e = 0; e < field.count; ++e) {
        const std::int64_t logical = readHidElement(payload, field, e);
        const double physical = hidPhysical(field, logical);
        (void)hidLogical(field, physical);
        writeHidElement(std::span<std::uint8_t>(blank).subspan(descriptor.uses_report_ids ? 1 : 0), field, e, logical);
      }
      (void)hidUnitName(field.unit);
      (void)hidUnitToSi(field.unit);
      // The first few usages only: setPhysical searches the layout, and a usage range may hold 65536.
      for (std::size_t u = 0; u < field.usages.size() && u < 8; ++u)
        (void)encoder.setPhysical(blank, layout, field.usages[u], 0.5);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t left = size - 2;
  const std::size_t n = (static_cast<std::size_t>(data[0]) | static_cast<std::size_t>(data[1]) << 8) % (left + 1);
  const std::span<const std::uint8_t> raw(data + 2 + n, left - n);
  HidDescriptor descriptor;
  try {
    descriptor = parseHidDescriptor(std::span<const std::uint8_t>(data + 2, n));
  } catch (const HidDescriptorError&) {
    return 0;
  }
  for (const HidReportType type : {HidReportType::Input, HidReportType::Output, HidReportType::Feature})
    decodeAs(descriptor, type, raw);
  encodeAll(descriptor, raw.empty() ? raw : raw.subspan(descriptor.uses_report_ids ? 1 : 0));
  return 0;
}
