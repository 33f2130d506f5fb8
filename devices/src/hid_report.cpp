#include "incise/devices/hid_report.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace incise::devices {
namespace {

// Elements wider than this are read as their low 32 bits, as Linux's hid-core reads them.
constexpr std::uint32_t kReadBits = 32;

std::uint64_t mask(std::uint32_t bits) { return bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1; }

// A unit nibble as a signed exponent (-8..7).
int nibble(std::uint32_t unit, int index) {
  const std::uint32_t n = (unit >> (4 * index)) & 0xFu;
  return static_cast<int>(n ^ 8u) - 8;
}

// 10^e without std::pow on the decode path (unit exponents are -8..7; others are rare).
double pow10(int e) {
  static constexpr double kPowers[] = {1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1,
                                       1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7};
  return e >= -8 && e <= 7 ? kPowers[e + 8] : std::pow(10.0, e);
}

void appendTerm(std::string& text, const char* name, int exponent) {
  if (!text.empty() && text.back() != '/') text += '*';
  text += name;
  if (exponent > 1) text += '^' + std::to_string(exponent);
}

}  // namespace

const char* toString(HidDecodeStatus status) {
  switch (status) {
    case HidDecodeStatus::Ok:
      return "ok";
    case HidDecodeStatus::Empty:
      return "empty report";
    case HidDecodeStatus::UnknownReportId:
      return "report ID not declared by the descriptor";
    case HidDecodeStatus::TooShort:
      return "report shorter than its layout";
  }
  return "?";
}

std::int64_t readHidElement(std::span<const std::uint8_t> report, const HidField& field, std::uint32_t element) {
  const std::uint64_t bit = std::uint64_t{field.bit_offset} + std::uint64_t{element} * field.bit_size;
  const std::uint32_t bits = std::min(field.bit_size, kReadBits);
  const std::size_t first = bit / 8, shift = bit % 8;
  const std::size_t last = (bit + bits - 1) / 8;  // at most first + 4: bits <= 32
  std::uint64_t word = 0;
  for (std::size_t i = first; i <= last && i < report.size(); ++i)
    word |= std::uint64_t{report[i]} << (8 * (i - first));
  const std::uint64_t value = (word >> shift) & mask(bits);
  if (!field.isSigned() || bits == 0) return static_cast<std::int64_t>(value);
  const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
  return static_cast<std::int64_t>(value ^ sign) - static_cast<std::int64_t>(sign);
}

void writeHidElement(std::span<std::uint8_t> report, const HidField& field, std::uint32_t element,
                     std::int64_t logical) {
  const std::uint64_t bit = std::uint64_t{field.bit_offset} + std::uint64_t{element} * field.bit_size;
  const auto bits = static_cast<std::uint64_t>(logical);  // two's complement; bits past 64 repeat the sign
  for (std::uint32_t b = 0; b < field.bit_size; ++b) {
    const std::uint64_t at = bit + b;
    if (at / 8 >= report.size()) return;
    const auto m = static_cast<std::uint8_t>(1u << (at % 8));
    if ((b < 64 ? bits >> b : bits >> 63) & 1u)
      report[at / 8] |= m;
    else
      report[at / 8] &= static_cast<std::uint8_t>(~m);
  }
}

double hidPhysical(const HidField& f, std::int64_t logical) {
  const double span = static_cast<double>(f.logical_max - f.logical_min);
  double physical = static_cast<double>(f.physical_min);
  if (span != 0.0)
    physical +=
        static_cast<double>(logical - f.logical_min) * static_cast<double>(f.physical_max - f.physical_min) / span;
  return physical * pow10(f.unit_exponent);
}

std::int64_t hidLogical(const HidField& f, double physical) {
  const double p = physical / pow10(f.unit_exponent);
  const double span = static_cast<double>(f.physical_max - f.physical_min);
  double logical = static_cast<double>(f.logical_min);
  if (span != 0.0)
    logical += (p - static_cast<double>(f.physical_min)) * static_cast<double>(f.logical_max - f.logical_min) / span;
  if (!std::isfinite(logical)) return f.logical_min;
  const double lo = static_cast<double>(std::min(f.logical_min, f.logical_max));
  const double hi = static_cast<double>(std::max(f.logical_min, f.logical_max));
  return static_cast<std::int64_t>(std::llround(std::clamp(logical, lo, hi)));
}

HidReportDecoder::HidReportDecoder(const HidDescriptor& descriptor, HidReportType type) : descriptor_(&descriptor) {
  by_id_.fill(-1);
  for (std::size_t i = 0; i < descriptor.reports.size(); ++i) {
    const HidReportLayout& r = descriptor.reports[i];
    if (r.type != type) continue;
    by_id_[r.id] = static_cast<int>(i);
    std::size_t values = 0;
    for (const auto& f : r.fields)
      if (!f.isConstant()) values += f.count;
    max_values_ = std::max(max_values_, values);
  }
}

const HidReportLayout* HidReportDecoder::layoutOf(std::span<const std::uint8_t> raw) const noexcept {
  if (raw.empty()) return nullptr;
  const int index = by_id_[descriptor_->uses_report_ids ? raw[0] : 0];
  return index < 0 ? nullptr : &descriptor_->reports[static_cast<std::size_t>(index)];
}

HidDecodeStatus HidReportDecoder::check(std::span<const std::uint8_t> raw) const noexcept {
  if (raw.empty()) return HidDecodeStatus::Empty;
  const HidReportLayout* layout = layoutOf(raw);
  if (layout == nullptr) return HidDecodeStatus::UnknownReportId;
  return raw.size() < layout->wireBytes(descriptor_->uses_report_ids) ? HidDecodeStatus::TooShort : HidDecodeStatus::Ok;
}

HidDecoded HidReportDecoder::decode(std::span<const std::uint8_t> raw, std::span<HidValue> out) const noexcept {
  HidDecoded result;
  result.status = check(raw);
  if (result.status != HidDecodeStatus::Ok) return result;
  result.layout = layoutOf(raw);
  const auto payload = raw.subspan(descriptor_->uses_report_ids ? 1 : 0);
  const auto& fields = result.layout->fields;
  for (std::size_t fi = 0; fi < fields.size(); ++fi) {
    const HidField& f = fields[fi];
    if (f.isConstant()) continue;
    for (std::uint32_t e = 0; e < f.count && result.values < out.size(); ++e) {
      HidValue& v = out[result.values++];
      v.logical = readHidElement(payload, f, e);
      v.in_range = v.logical >= f.logical_min && v.logical <= f.logical_max;
      v.physical = hidPhysical(f, v.logical);
      v.field = static_cast<std::uint16_t>(fi);
      v.element = static_cast<std::uint16_t>(e);
      if (f.isVariable()) {
        v.usage = f.usageOf(e);
      } else {
        const std::int64_t index = v.logical - f.logical_min;
        v.usage = v.in_range && index >= 0 && index < static_cast<std::int64_t>(f.usages.size())
                      ? f.usages[static_cast<std::size_t>(index)]
                      : 0;
      }
    }
  }
  return result;
}

HidReportEncoder::HidReportEncoder(const HidDescriptor& descriptor, HidReportType) : descriptor_(&descriptor) {}

std::vector<std::uint8_t> HidReportEncoder::blank(const HidReportLayout& layout) const {
  std::vector<std::uint8_t> raw(layout.wireBytes(descriptor_->uses_report_ids), 0);
  if (descriptor_->uses_report_ids) raw[0] = layout.id;
  return raw;
}

std::span<std::uint8_t> HidReportEncoder::payload(std::span<std::uint8_t> raw) const {
  return descriptor_->uses_report_ids && !raw.empty() ? raw.subspan(1) : raw;
}

bool HidReportEncoder::setLogical(std::span<std::uint8_t> raw, const HidReportLayout& layout, std::uint32_t usage,
                                  std::int64_t logical) const {
  for (const auto& f : layout.fields) {
    if (f.isConstant()) continue;
    if (f.isVariable()) {
      for (std::uint32_t e = 0; e < f.count; ++e)
        if (f.usageOf(e) == usage) {
          writeHidElement(payload(raw), f, e, logical);
          return true;
        }
    } else {
      const auto it = std::find(f.usages.begin(), f.usages.end(), usage);
      if (it == f.usages.end()) continue;
      writeHidElement(payload(raw), f, 0, f.logical_min + (it - f.usages.begin()));
      return true;
    }
  }
  return false;
}

bool HidReportEncoder::setPhysical(std::span<std::uint8_t> raw, const HidReportLayout& layout, std::uint32_t usage,
                                   double physical) const {
  for (const auto& f : layout.fields) {
    if (f.isConstant() || !f.isVariable()) continue;
    for (std::uint32_t e = 0; e < f.count; ++e)
      if (f.usageOf(e) == usage) {
        writeHidElement(payload(raw), f, e, hidLogical(f, physical));
        return true;
      }
  }
  return false;
}

std::string hidUnitName(std::uint32_t unit) {
  const std::uint32_t system = unit & 0xFu;
  if (system == 0 || system > 4) return system == 0 ? "" : "vendor unit";
  static const char* kNames[5][7] = {
      {},
      {"", "cm", "g", "s", "K", "A", "cd"},
      {"", "rad", "g", "s", "K", "A", "cd"},
      {"", "in", "slug", "s", "degF", "A", "cd"},
      {"", "deg", "slug", "s", "degF", "A", "cd"},
  };
  std::string numerator, denominator;
  for (int i = 1; i <= 6; ++i) {
    const int e = nibble(unit, i);
    if (e > 0) appendTerm(numerator, kNames[system][i], e);
    if (e < 0) appendTerm(denominator, kNames[system][i], -e);
  }
  if (numerator.empty() && denominator.empty()) return "";
  if (denominator.empty()) return numerator;
  return (numerator.empty() ? "1" : numerator) + "/" + denominator;
}

double hidUnitToSi(std::uint32_t unit) {
  if ((unit & ~0xF0u) != (unit & 0xFu)) return 0.0;  // another dimension than length
  if (nibble(unit, 1) != 1) return 0.0;
  switch (unit & 0xFu) {
    case 1:
      return 0.01;
    case 2:
      return 1.0;
    case 3:
      return 0.0254;
    case 4:
      return std::numbers::pi / 180.0;
    default:
      return 0.0;
  }
}

}  // namespace incise::devices
