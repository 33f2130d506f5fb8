// Private to the pen (finder, profile, generator): how a pen's angles and lengths are read. X/Y Tilt and
// Twist are degrees (HID Usage Tables 1.3, 16.3.2): a field with an angle unit (degrees or radians, any
// exponent) is read through its physical range; a field without one (the XP-Pen's and Huion's tilts declare
// none, or carry the inch^3 their X/Y declared) as logical = degrees, the raw value hid-input passes on.
#pragma once

#include <cstdint>

#include "incise/devices/hid_descriptor.h"

namespace incise::devices {

bool isLengthUnit(std::uint32_t unit);  // cm or inch, to the first power (hid_report.h's hidUnitToSi)
bool isAngleUnit(std::uint32_t unit);   // rad or deg, to the first power
// An angle field's value in degrees, and back (rounded, clamped to the logical range).
double hidPenDegrees(const HidField& field, std::int64_t logical);
std::int64_t hidPenLogicalDegrees(const HidField& field, double degrees);

}  // namespace incise::devices
