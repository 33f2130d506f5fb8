#include "incise/devices/hid_usages.h"

#include <algorithm>
#include <cstdio>
#include <iterator>

#include "incise/devices/hid_descriptor.h"

namespace incise::devices {
namespace {

struct Named {
  std::uint16_t id;
  const char* name;
};

// HID Usage Tables 1.3, section 4 (Generic Desktop), in id order.
constexpr Named kGenericDesktop[] = {{0x01, "Pointer"},
                                     {0x02, "Mouse"},
                                     {0x04, "Joystick"},
                                     {0x05, "Gamepad"},
                                     {0x06, "Keyboard"},
                                     {0x07, "Keypad"},
                                     {0x08, "Multi-axis Controller"},
                                     {0x30, "X"},
                                     {0x31, "Y"},
                                     {0x32, "Z"},
                                     {0x33, "Rx"},
                                     {0x34, "Ry"},
                                     {0x35, "Rz"},
                                     {0x36, "Slider"},
                                     {0x37, "Dial"},
                                     {0x38, "Wheel"},
                                     {0x39, "Hat Switch"},
                                     {0x3A, "Counted Buffer"},
                                     {0x3B, "Byte Count"},
                                     {0x3C, "Motion Wakeup"},
                                     {0x3D, "Start"},
                                     {0x3E, "Select"},
                                     {0x40, "Vx"},
                                     {0x41, "Vy"},
                                     {0x42, "Vz"},
                                     {0x43, "Vbrx"},
                                     {0x44, "Vbry"},
                                     {0x45, "Vbrz"},
                                     {0x46, "Vno"},
                                     {0x47, "Feature Notification"},
                                     {0x48, "Resolution Multiplier"}};

// Section 11 (LED), the one the SpaceNavigator declares.
constexpr Named kLed[] = {{0x4B, "Generic Indicator"}};

// Section 16 (Digitizers), in id order.
constexpr Named kDigitizers[] = {{0x01, "Digitizer"},
                                 {0x02, "Pen"},
                                 {0x03, "Light Pen"},
                                 {0x04, "Touch Screen"},
                                 {0x05, "Touch Pad"},
                                 {0x06, "Whiteboard"},
                                 {0x0E, "Device Configuration"},
                                 {0x20, "Stylus"},
                                 {0x21, "Puck"},
                                 {0x22, "Finger"},
                                 {0x23, "Device Settings"},
                                 {0x30, "Tip Pressure"},
                                 {0x31, "Barrel Pressure"},
                                 {0x32, "In Range"},
                                 {0x33, "Touch"},
                                 {0x34, "Untouch"},
                                 {0x35, "Tap"},
                                 {0x36, "Quality"},
                                 {0x37, "Data Valid"},
                                 {0x38, "Transducer Index"},
                                 {0x39, "Tablet Function Keys"},
                                 {0x3A, "Program Change Keys"},
                                 {0x3B, "Battery Strength"},
                                 {0x3C, "Invert"},
                                 {0x3D, "X Tilt"},
                                 {0x3E, "Y Tilt"},
                                 {0x3F, "Azimuth"},
                                 {0x40, "Altitude"},
                                 {0x41, "Twist"},
                                 {0x42, "Tip Switch"},
                                 {0x43, "Secondary Tip Switch"},
                                 {0x44, "Barrel Switch"},
                                 {0x45, "Eraser"},
                                 {0x46, "Tablet Pick"},
                                 {0x47, "Touch Valid"},
                                 {0x48, "Width"},
                                 {0x49, "Height"},
                                 {0x51, "Contact Identifier"},
                                 {0x52, "Device Mode"},
                                 {0x53, "Device Identifier"},
                                 {0x54, "Contact Count"},
                                 {0x55, "Contact Count Maximum"},
                                 {0x56, "Scan Time"},
                                 {0x5A, "Secondary Barrel Switch"},
                                 {0x5B, "Transducer Serial Number"},
                                 {0x5C, "Preferred Color"}};

template <std::size_t N>
const char* lookup(const Named (&table)[N], std::uint16_t id) {
  const auto it = std::lower_bound(std::begin(table), std::end(table), id,
                                   [](const Named& n, std::uint16_t value) { return n.id < value; });
  return it != std::end(table) && it->id == id ? it->name : nullptr;
}

const char* standardName(std::uint32_t usage) {
  const std::uint16_t id = hidUsageId(usage);
  switch (hidUsagePage(usage)) {
    case hid_pages::kGenericDesktop:
      return lookup(kGenericDesktop, id);
    case hid_pages::kLed:
      return lookup(kLed, id);
    case hid_pages::kDigitizers:
      return lookup(kDigitizers, id);
    default:
      return nullptr;
  }
}

std::string numbered(const char* prefix, std::uint32_t usage) {
  char text[48];
  std::snprintf(text, sizeof text, "%s 0x%04x:0x%04x", prefix, hidUsagePage(usage), hidUsageId(usage));
  return text;
}

}  // namespace

std::uint32_t hidEquivalentUsage(std::uint32_t usage) {
  if (hidUsagePage(usage) != hid_pages::kWacomDigitizer) return usage;
  const std::uint16_t id = hidUsageId(usage);
  const auto page = static_cast<std::uint16_t>(id >> 8);
  return hidUsage(page == 0 ? hid_pages::kDigitizers : page, static_cast<std::uint16_t>(id & 0xFF));
}

std::string hidUsagePageName(std::uint16_t page) {
  char text[40];
  switch (page) {
    case hid_pages::kGenericDesktop:
      return "Generic Desktop";
    case 0x06:
      return "Generic Device Controls";
    case 0x07:
      return "Keyboard/Keypad";
    case hid_pages::kLed:
      return "LED";
    case hid_pages::kButton:
      return "Button";
    case 0x0C:
      return "Consumer";
    case hid_pages::kDigitizers:
      return "Digitizers";
    default:
      break;
  }
  std::snprintf(text, sizeof text, page >= 0xFF00 ? "Vendor Defined 0x%04x" : "Page 0x%04x", page);
  return text;
}

std::string hidUsageName(std::uint32_t usage) {
  if (hidUsagePage(usage) == hid_pages::kButton) {
    const std::uint16_t id = hidUsageId(usage);
    return id == 0 ? "No Button Pressed" : "Button " + std::to_string(id);
  }
  if (const char* name = standardName(hidEquivalentUsage(usage))) return name;
  return numbered(hidUsagePage(usage) >= 0xFF00 ? "Vendor" : "Usage", usage);
}

}  // namespace incise::devices
