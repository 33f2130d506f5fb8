// Names of HID usages and usage pages as the HID Usage Tables (1.3) spell them ("X", "Tip Pressure",
// "X Tilt", "Button 3"), for `incise hid decode` and messages, and the one vendor-page equivalence the
// profiles rely on: Wacom's digitizer page 0xFF0D, whose usage 0xSSUU stands for usage 0xUU of page 0xSS
// (page 0x0D when SS is 0) — the rule of Linux's hid-wacom (wacom_equivalent_usage). So Wacom's 0xFF0D:0x0130
// is Generic Desktop X and 0xFF0D:0x0042 is Digitizers Tip Switch.
//
// Usages are 32-bit extended usages (page << 16 | id, see hid_descriptor.h). Threads: any. Cost: a table
// lookup. Failure: none; an unknown usage is named by its numbers ("Usage 0x0001:0x00c8",
// "Vendor 0xff0d:0x0d03").
#pragma once

#include <cstdint>
#include <string>

namespace incise::devices {

namespace hid_pages {
inline constexpr std::uint16_t kGenericDesktop = 0x01;
inline constexpr std::uint16_t kLed = 0x08;
inline constexpr std::uint16_t kButton = 0x09;
inline constexpr std::uint16_t kDigitizers = 0x0D;
inline constexpr std::uint16_t kWacomDigitizer = 0xFF0D;
}  // namespace hid_pages

// Usage ids the profiles look for.
namespace hid_usages {
inline constexpr std::uint16_t kX = 0x30, kY = 0x31, kZ = 0x32, kRx = 0x33, kRy = 0x34, kRz = 0x35;
inline constexpr std::uint16_t kMultiAxisController = 0x08;
inline constexpr std::uint16_t kDigitizer = 0x01, kPen = 0x02, kLightPen = 0x03, kStylus = 0x20;
inline constexpr std::uint16_t kTipPressure = 0x30, kInRange = 0x32, kInvert = 0x3C, kXTilt = 0x3D, kYTilt = 0x3E;
inline constexpr std::uint16_t kTwist = 0x41, kTipSwitch = 0x42, kBarrelSwitch = 0x44, kEraser = 0x45;
inline constexpr std::uint16_t kSecondaryBarrelSwitch = 0x5A;
}  // namespace hid_usages

// The standard usage a vendor usage stands for (Wacom's 0xFF0D page, see above); any other usage as it is.
std::uint32_t hidEquivalentUsage(std::uint32_t usage);

// "Generic Desktop", "Digitizers", "Button", "Vendor Defined 0xff0d", "Page 0x0042".
std::string hidUsagePageName(std::uint16_t page);
// The usage's name; a vendor usage with a standard equivalent gets the equivalent's name.
std::string hidUsageName(std::uint32_t usage);

}  // namespace incise::devices
