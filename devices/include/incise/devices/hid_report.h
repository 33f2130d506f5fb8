// Reading and writing report data with a parsed descriptor (hid_descriptor.h): the extractor that turns a
// raw report, exactly as hid_read returns it (the report ID first when the descriptor declares IDs), into
// values by usage — logical, and in physical units — and its inverse, the encoder that builds a report
// from values (the generator of the shipped recordings uses it).
//
// Cost: decode O(bits in the report) with no allocation: about 20-100 ns for a tablet report (see the
// benchmark hid_bench). Threads: a decoder is immutable after construction; decode from any thread.
// Failure: decode never throws; a report that is empty, names an ID the descriptor does not declare, or is
// shorter than its ID's layout returns a status saying which, and no values.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "incise/devices/hid_descriptor.h"

namespace incise::devices {

// Values (HID 1.11 6.2.2.7): a field element's bits are little-endian at its bit offset; a field whose
// logical minimum is negative is two's-complement signed, else unsigned. physical = physical_min +
// (logical - logical_min) * (physical_max - physical_min) / (logical_max - logical_min), in units of
// 10^unit_exponent of the field's unit: HidValue::physical has the exponent applied (Wacom's X: logical
// 0..44800 -> 0..22.4 cm). hidUnitToSi converts length and angle units to metres and radians. A logical
// value outside the logical range (a null state, 6.2.2.5) is passed on as it is; HidValue::in_range says so.
struct HidValue {
  std::uint32_t usage = 0;  // page << 16 | id; for an array element, the usage its index selects (0: none)
  std::int64_t logical = 0;
  double physical = 0.0;      // unit_exponent applied
  std::uint16_t field = 0;    // index into the report layout's fields
  std::uint16_t element = 0;  // element within the field
  bool in_range = true;       // logical_min <= logical <= logical_max
};

enum class HidDecodeStatus : std::uint8_t { Ok, Empty, UnknownReportId, TooShort };
const char* toString(HidDecodeStatus status);

struct HidDecoded {
  HidDecodeStatus status = HidDecodeStatus::Empty;
  const HidReportLayout* layout = nullptr;  // the report's layout when status is Ok
  std::size_t values = 0;                   // entries written to the output span
};

// The bits of one element (zero- or sign-extended as the field says). `report` starts after the ID byte.
// Bits past the end of `report` read as 0. An element wider than 32 bits (a 64-bit transducer serial number)
// gives its low 32 bits, as Linux's hid-core does.
std::int64_t readHidElement(std::span<const std::uint8_t> report, const HidField& field, std::uint32_t element);
// Writes one element, clamped to the bits it has (two's complement, sign-extended over a wider element).
void writeHidElement(std::span<std::uint8_t> report, const HidField& field, std::uint32_t element,
                     std::int64_t logical);
// The linear map logical -> physical of a field (unit exponent applied) and back (rounded to the nearest
// logical value, clamped to the logical range).
double hidPhysical(const HidField& field, std::int64_t logical);
std::int64_t hidLogical(const HidField& field, double physical);

// Decodes reports of one type (Input by default) of one descriptor.
class HidReportDecoder {
 public:
  explicit HidReportDecoder(const HidDescriptor& descriptor, HidReportType type = HidReportType::Input);

  // The data (non-constant) elements of `raw`, in field order, into `out` (at most out.size() entries;
  // maxValues() always suffices). Never throws.
  HidDecoded decode(std::span<const std::uint8_t> raw, std::span<HidValue> out) const noexcept;
  // The layout a raw report would be decoded with (nullptr: empty, unknown ID).
  const HidReportLayout* layoutOf(std::span<const std::uint8_t> raw) const noexcept;
  // What decode would say of `raw`, without decoding: Ok, Empty, UnknownReportId or TooShort.
  HidDecodeStatus check(std::span<const std::uint8_t> raw) const noexcept;
  std::size_t maxValues() const { return max_values_; }
  const HidDescriptor& descriptor() const { return *descriptor_; }

 private:
  const HidDescriptor* descriptor_;
  std::array<int, 256> by_id_;  // report id -> index into descriptor_->reports, -1 none
  std::size_t max_values_ = 0;
};

// Builds raw reports for a descriptor: the inverse of HidReportDecoder.
class HidReportEncoder {
 public:
  explicit HidReportEncoder(const HidDescriptor& descriptor, HidReportType type = HidReportType::Input);

  // A report of `layout`, every bit 0, the ID byte first when the descriptor uses IDs.
  std::vector<std::uint8_t> blank(const HidReportLayout& layout) const;
  // Sets the first element with `usage` in the report (raw, ID byte included); false when the layout has
  // no such usage. Array fields: the first element is set to the index that selects `usage`.
  bool setLogical(std::span<std::uint8_t> raw, const HidReportLayout& layout, std::uint32_t usage,
                  std::int64_t logical) const;
  bool setPhysical(std::span<std::uint8_t> raw, const HidReportLayout& layout, std::uint32_t usage,
                   double physical) const;

 private:
  std::span<std::uint8_t> payload(std::span<std::uint8_t> raw) const;
  const HidDescriptor* descriptor_;
};

// Units (6.2.2.7, table "Unit"): the text of a field's unit, "cm", "deg", "in", "rad", "s", "g",
// "cm/s", ... ("" for none), and the factor from the unit to SI metres or radians (0 when it is neither a
// length nor an angle: then the physical value has no SI conversion here).
std::string hidUnitName(std::uint32_t unit);
double hidUnitToSi(std::uint32_t unit);

}  // namespace incise::devices
