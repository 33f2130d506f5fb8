// Private to the profiles: a usage bound to one element of one field of one input report, found once when
// the profile is built so that update() reads the bits directly (no search per report).
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_pen.h"
#include "incise/devices/hid_profile.h"

namespace incise::devices::detail {

struct Binding {
  const HidReportLayout* layout = nullptr;
  const HidField* field = nullptr;
  std::uint32_t element = 0;

  Binding() = default;
  Binding(const HidReportLayout* l, const HidField* f, std::uint32_t e) : layout(l), field(f), element(e) {}
  explicit Binding(const HidElement& e) : layout(e.layout), field(e.field), element(e.element) {}

  explicit operator bool() const { return field != nullptr; }
  // `payload` starts after the ID byte and holds the whole layout (the caller checked its size).
  std::int64_t read(std::span<const std::uint8_t> payload) const;
  double physical(std::span<const std::uint8_t> payload) const;
  // The value as a fraction of the logical range, clamped to [0, 1].
  double fraction(std::span<const std::uint8_t> payload) const;
  // logical / max(|logical_min|, |logical_max|): a centred axis's deflection in [-1, 1].
  double deflection(std::span<const std::uint8_t> payload) const;
};

// The first data element of a variable input field whose usage (through hidEquivalentUsage) is `usage`,
// in `layout` when given, else in any input report.
Binding findInput(const HidDescriptor& descriptor, std::uint32_t usage, const HidReportLayout* layout = nullptr);

// The payload of `raw` when it is a complete report of `layout`, else an empty span.
std::span<const std::uint8_t> payloadOf(const HidDescriptor& descriptor, const HidReportLayout& layout,
                                        std::span<const std::uint8_t> raw);

// True when the descriptor has all six of X, Y, Z, Rx, Ry, Rz as variable input fields.
bool hasSixAxes(const HidDescriptor& descriptor);

std::unique_ptr<HidProfile> makePenProfile(const HidDescriptor& descriptor, const PenMapping& mapping);
std::unique_ptr<HidProfile> makeSixDofProfile(const HidDescriptor& descriptor, HidDeviceId id,
                                              const SixDofMapping& mapping);

}  // namespace incise::devices::detail
