#include "incise/devices/hid_transport.h"

#include <charconv>
#include <cstdio>
#include <stdexcept>

namespace incise::devices {
namespace {

std::uint16_t parseHex16(const std::string& text, const std::string& part, const char* what) {
  unsigned value = 0;
  const auto result = std::from_chars(part.data(), part.data() + part.size(), value, 16);
  if (part.empty() || part.size() > 4 || result.ec != std::errc() || result.ptr != part.data() + part.size())
    throw std::invalid_argument("--device '" + text + "': " + what + " '" + part + "' is not 1-4 hex digits");
  return static_cast<std::uint16_t>(value);
}

}  // namespace

bool HidDeviceSelector::matches(const HidDeviceInfo& device) const {
  if (path) return device.path == *path;
  return device.vid == vid && device.pid == pid && (!serial || device.serial == *serial);
}

std::string HidDeviceSelector::describe() const {
  if (path) return *path;
  return formatVidPid(vid, pid) + (serial ? ":" + *serial : "");
}

HidDeviceSelector parseHidDeviceSelector(const std::string& text) {
  HidDeviceSelector selector;
  if (!text.empty() && text.front() == '/') {
    selector.path = text;
    return selector;
  }
  const std::size_t first = text.find(':');
  if (first == std::string::npos)
    throw std::invalid_argument("--device '" + text +
                                "': expected VID:PID, VID:PID:serial (hex) or a /dev/hidraw path");
  const std::size_t second = text.find(':', first + 1);
  selector.vid = parseHex16(text, text.substr(0, first), "vendor id");
  selector.pid = parseHex16(
      text, text.substr(first + 1, second == std::string::npos ? std::string::npos : second - first - 1), "product id");
  if (second != std::string::npos) {
    selector.serial = text.substr(second + 1);
    if (selector.serial->empty())
      throw std::invalid_argument("--device '" + text + "': empty serial after the second ':'");
  }
  return selector;
}

std::string formatVidPid(std::uint16_t vid, std::uint16_t pid) {
  char text[16];
  std::snprintf(text, sizeof text, "%04x:%04x", vid, pid);
  return text;
}

}  // namespace incise::devices
