// HID report descriptors (Device Class Definition for HID 1.11, section 6.2.2): the parser that turns a
// descriptor's bytes into the reports a device sends, field by field. hidapi 0.13.1 cannot fetch a
// descriptor; HidapiTransport reads it from /sys/class/hidraw/hidrawN/device/report_descriptor, and a
// hid-recorder file carries it on its `R:` line.
//
// Cost: O(descriptor bytes + fields); a few kB of heap. Threads: a parsed HidDescriptor is an immutable
// value, share it freely. Failure: parseHidDescriptor throws HidDescriptorError, naming the byte offset
// of the item and what is wrong (the cases are listed above parseHidDescriptor).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace incise::devices {

enum class HidReportType : std::uint8_t { Input, Output, Feature };
const char* toString(HidReportType type);

// The data bits of an Input/Output/Feature item (6.2.2.5).
namespace hid_flags {
inline constexpr std::uint32_t kConstant = 1u << 0;  // else data
inline constexpr std::uint32_t kVariable = 1u << 1;  // else array
inline constexpr std::uint32_t kRelative = 1u << 2;  // else absolute
inline constexpr std::uint32_t kWrap = 1u << 3;
inline constexpr std::uint32_t kNonLinear = 1u << 4;
inline constexpr std::uint32_t kNoPreferred = 1u << 5;
inline constexpr std::uint32_t kNullState = 1u << 6;
inline constexpr std::uint32_t kVolatile = 1u << 7;
inline constexpr std::uint32_t kBufferedBytes = 1u << 8;
}  // namespace hid_flags

// Usages are 32-bit extended usages: page << 16 | id. A variable field of count N has N usages (the
// declared ones in order, a usage minimum/maximum range expanded, the last one repeated when fewer are
// declared); an array field keeps its usage list and reports indices into it (6.2.2.5).
inline constexpr std::uint32_t hidUsage(std::uint16_t page, std::uint16_t id) {
  return static_cast<std::uint32_t>(page) << 16 | id;
}
inline constexpr std::uint16_t hidUsagePage(std::uint32_t usage) { return static_cast<std::uint16_t>(usage >> 16); }
inline constexpr std::uint16_t hidUsageId(std::uint32_t usage) { return static_cast<std::uint16_t>(usage & 0xffff); }

// One main item's worth of report data: `count` elements of `bit_size` bits starting at `bit_offset`.
struct HidField {
  HidReportType type = HidReportType::Input;
  std::uint8_t report_id = 0;    // 0 when the descriptor declares no report IDs
  std::uint32_t bit_offset = 0;  // from the first bit after the report ID byte
  std::uint32_t bit_size = 0;    // 1..256; elements over 32 bits are read as their low 32 (hid_report.h)
  std::uint32_t count = 0;       // elements
  std::uint32_t flags = 0;       // hid_flags
  // Ranges as declared (64-bit: a 4-byte unsigned maximum such as 0xffffffff fits).
  std::int64_t logical_min = 0, logical_max = 0;
  std::int64_t physical_min = 0, physical_max = 0;  // equal to the logical range when the items gave 0, 0
  std::uint32_t unit = 0;                           // the Unit item's raw value (system and exponents)
  int unit_exponent = 0;                            // physical values are in units of 10^unit_exponent
  // Variable: one usage per element (size count). Array: the usages the indices select (index
  // logical_min selects usages[0]).
  std::vector<std::uint32_t> usages;
  std::uint32_t application = 0;  // usage of the enclosing application collection (0: none)
  int collection = -1;            // index of the innermost enclosing collection in HidDescriptor::collections

  bool isConstant() const { return (flags & hid_flags::kConstant) != 0; }
  bool isVariable() const { return (flags & hid_flags::kVariable) != 0; }
  bool isRelative() const { return (flags & hid_flags::kRelative) != 0; }
  bool isSigned() const { return logical_min < 0; }
  // The usage of element i of a variable field (0 for a constant field without usages).
  std::uint32_t usageOf(std::uint32_t element) const;
};

struct HidCollection {
  std::uint32_t usage = 0;
  std::uint8_t kind = 0;  // 0 physical, 1 application, 2 logical, 3 report, ...
  int parent = -1;
  std::size_t offset = 0;  // byte offset of its Collection item
};

// Report layout: per report type and ID, fields in descriptor order at increasing bit offsets. The offsets
// count from the first data bit after the report ID byte; a report's wire size is its bits rounded up to
// bytes, plus one byte when the descriptor declares report IDs.
struct HidReportLayout {
  HidReportType type = HidReportType::Input;
  std::uint8_t id = 0;
  std::uint32_t bits = 0;  // data bits, without the report ID byte
  std::vector<HidField> fields;

  // Bytes on the wire as hid_read returns them (ID byte included when the device uses IDs).
  std::size_t wireBytes(bool with_id) const { return (bits + 7) / 8 + (with_id ? 1 : 0); }
};

struct HidDescriptor {
  std::vector<std::uint8_t> bytes;  // the descriptor as parsed
  bool uses_report_ids = false;
  std::vector<HidReportLayout> reports;  // in order of first appearance
  std::vector<HidCollection> collections;

  // The layout of one report, or nullptr when the descriptor declares none of that type and ID.
  const HidReportLayout* find(HidReportType type, std::uint8_t id) const;
  // The application collections' usages, in order.
  std::vector<std::uint32_t> applications() const;
};

// A descriptor the parser refuses: what() is "report descriptor byte N (item 0xPP): what is wrong".
class HidDescriptorError : public std::runtime_error {
 public:
  HidDescriptorError(const std::string& message, std::size_t offset) : std::runtime_error(message), offset_(offset) {}
  std::size_t offset() const { return offset_; }  // of the offending item's prefix byte

 private:
  std::size_t offset_;
};

// The descriptor in `bytes`, parsed. What the parser understands (6.2.2.2-6.2.2.8):
//   - short items (1-byte prefix: 4-bit tag, 2-bit type, 2-bit size 0/1/2/4 bytes, little-endian data) and
//     long items (prefix 0xFE, data size, long tag: skipped, no HID 1.11 long item is defined);
//   - main items Input, Output, Feature (their data bits as flags), Collection, End Collection;
//   - global items usage page, logical/physical minimum and maximum, unit exponent, unit, report size,
//     report ID, report count, push, pop;
//   - local items usage, usage minimum/maximum (a 4-byte usage carries its own page in its high 16 bits),
//     designator and string indices (accepted, not kept), delimiter (a set of alternative usages: the first
//     is kept, as Linux's hid-core does);
//   - signed values: logical and physical minima are signed (sign-extended from the item's size); a maximum
//     is signed when its minimum is negative, else unsigned (so `26 ff 00` after a zero minimum is 255).
//     Physical minimum = maximum = 0 means "same as logical" (6.2.2.7).
//   - unit exponent: the 4-bit two's-complement nibble (0x0d = -3); a larger value is taken as a signed
//     byte (some firmware writes 0xfd), as hid-core does.
// Failure: HidDescriptorError for truncated data, a collection without its end or an end without a
// collection, a pop without a push or a push stack over 16 deep, a report size of 0 or over 256 bits (Linux's
// limit), a report ID of 0, a usage range over 65536 usages or with its minimum above its maximum, a main
// item before any report size/count, an item tag HID 1.11 does not define, a report over 4096 bytes, or a
// descriptor that declares report IDs for some fields and not for others.
HidDescriptor parseHidDescriptor(std::span<const std::uint8_t> bytes);

// "05 01 09 08 ...": whitespace-separated two-digit hex bytes, `#` comments to the end of the line (the
// layout of the shipped descriptor files, scenarios/hid/descriptors/). Throws std::invalid_argument
// "line L: what" on anything else.
std::vector<std::uint8_t> parseHexBytes(const std::string& text);
// The same from a file; throws std::runtime_error "path:line: what" (or "path: cannot read").
std::vector<std::uint8_t> loadHexBytes(const std::filesystem::path& path);

}  // namespace incise::devices
