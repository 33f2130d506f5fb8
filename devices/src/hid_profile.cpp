#include "incise/devices/hid_profile.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "hid_profile_internal.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"

namespace incise::devices {
namespace detail {

std::int64_t Binding::read(std::span<const std::uint8_t> payload) const {
  return readHidElement(payload, *field, element);
}

double Binding::physical(std::span<const std::uint8_t> payload) const { return hidPhysical(*field, read(payload)); }

double Binding::fraction(std::span<const std::uint8_t> payload) const {
  const double span = static_cast<double>(field->logical_max - field->logical_min);
  if (span <= 0.0) return 0.0;
  return std::clamp(static_cast<double>(read(payload) - field->logical_min) / span, 0.0, 1.0);
}

double Binding::deflection(std::span<const std::uint8_t> payload) const {
  const double full = static_cast<double>(std::max(std::llabs(field->logical_min), std::llabs(field->logical_max)));
  return full > 0.0 ? std::clamp(static_cast<double>(read(payload)) / full, -1.0, 1.0) : 0.0;
}

Binding findInput(const HidDescriptor& descriptor, std::uint32_t usage, const HidReportLayout* layout) {
  for (const HidReportLayout& r : descriptor.reports) {
    if (r.type != HidReportType::Input || (layout != nullptr && &r != layout)) continue;
    for (const HidField& f : r.fields) {
      if (f.isConstant() || !f.isVariable()) continue;
      for (std::uint32_t e = 0; e < f.count; ++e)
        if (hidEquivalentUsage(f.usageOf(e)) == usage) return Binding{&r, &f, e};
    }
  }
  return {};
}

std::span<const std::uint8_t> payloadOf(const HidDescriptor& descriptor, const HidReportLayout& layout,
                                        std::span<const std::uint8_t> raw) {
  const bool ids = descriptor.uses_report_ids;
  if (raw.size() < layout.wireBytes(ids) || (ids && raw[0] != layout.id)) return {};
  return raw.subspan(ids ? 1 : 0);
}

bool hasSixAxes(const HidDescriptor& descriptor) {
  for (std::uint16_t id = hid_usages::kX; id <= hid_usages::kRz; ++id)
    if (!findInput(descriptor, hidUsage(hid_pages::kGenericDesktop, id))) return false;
  return true;
}

}  // namespace detail

HidProfile::~HidProfile() = default;

const char* toString(HidProfileKind kind) {
  switch (kind) {
    case HidProfileKind::None:
      return "none";
    case HidProfileKind::Pen:
      return "pen";
    case HidProfileKind::SixDof:
      return "6-dof";
  }
  return "?";
}

std::span<const HidQuirk> hidQuirks() {
  static constexpr std::array<HidQuirk, 2> kQuirks = {{
      {{0x046d, 0xc626}, true, "3Dconnexion SpaceNavigator: axes declared Relative, reported absolute"},
      {{0x046d, 0xc623}, true, "3Dconnexion SpaceTraveler: axes declared Relative, reported absolute"},
  }};
  return kQuirks;
}

const HidQuirk* findHidQuirk(HidDeviceId id) {
  for (const HidQuirk& q : hidQuirks())
    if (q.id.vid == id.vid && q.id.pid == id.pid) return &q;
  return nullptr;
}

HidProfileChoice chooseHidProfile(const HidDescriptor& descriptor, HidDeviceId) {
  HidPenSearch pen = findHidPen(descriptor);
  if (pen.pen) return {HidProfileKind::Pen, std::move(pen.reason)};
  if (detail::hasSixAxes(descriptor))
    return {HidProfileKind::SixDof, "6-dof: input fields X, Y, Z, Rx, Ry, Rz (Generic Desktop)"};
  return {HidProfileKind::None,
          "no profile: " + pen.reason + "; and not all of X, Y, Z, Rx, Ry, Rz as input fields (6-dof)"};
}

std::unique_ptr<HidProfile> makeHidProfile(const HidDescriptor& descriptor, HidDeviceId id, const HidMapping& mapping) {
  const HidProfileChoice choice = chooseHidProfile(descriptor, id);
  switch (choice.kind) {
    case HidProfileKind::Pen:
      return detail::makePenProfile(descriptor, mapping.pen);
    case HidProfileKind::SixDof:
      return detail::makeSixDofProfile(descriptor, id, mapping.six_dof);
    case HidProfileKind::None:
      break;
  }
  throw HidProfileError(choice.reason);
}

}  // namespace incise::devices
