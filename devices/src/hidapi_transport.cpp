#include "incise/devices/hidapi_transport.h"

#include <fcntl.h>
#include <linux/hidraw.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <hidapi/hidapi.h>

namespace incise::devices {
namespace {

// hidapi's wide strings (UTF-32 on Linux) as UTF-8.
std::string utf8(const wchar_t* text) {
  std::string out;
  for (; text != nullptr && *text != 0; ++text) {
    const auto c = static_cast<std::uint32_t>(*text);
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (c >> 18));
      out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

// hidapi's bus numbers as Linux's (BUS_USB 3, BUS_BLUETOOTH 5, BUS_I2C 0x18, BUS_SPI 0x1C).
std::uint32_t linuxBus(hid_bus_type bus) {
  switch (bus) {
    case HID_API_BUS_USB:
      return 0x03;
    case HID_API_BUS_BLUETOOTH:
      return 0x05;
    case HID_API_BUS_I2C:
      return 0x18;
    case HID_API_BUS_SPI:
      return 0x1C;
    default:
      return 0;
  }
}

class HidapiConnection final : public HidConnection {
 public:
  HidapiConnection(hid_device* device, std::vector<std::uint8_t> descriptor)
      : device_(device), descriptor_(std::move(descriptor)) {}
  ~HidapiConnection() override { hid_close(device_); }
  HidapiConnection(const HidapiConnection&) = delete;
  HidapiConnection& operator=(const HidapiConnection&) = delete;

  int read(std::span<std::uint8_t> buffer, int timeout_ms) noexcept override {
    return hid_read_timeout(device_, buffer.data(), buffer.size(), timeout_ms);
  }
  const std::vector<std::uint8_t>& descriptor() const noexcept override { return descriptor_; }
  std::string error() const override { return utf8(hid_error(device_)); }

 private:
  hid_device* device_;
  std::vector<std::uint8_t> descriptor_;
};

std::vector<std::uint8_t> descriptorByIoctl(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  int size = 0;
  hidraw_report_descriptor descriptor{};
  const bool ok = ioctl(fd, HIDIOCGRDESCSIZE, &size) == 0 && size > 0 && size <= HID_MAX_DESCRIPTOR_SIZE &&
                  (descriptor.size = static_cast<__u32>(size), ioctl(fd, HIDIOCGRDESC, &descriptor) == 0);
  const int saved = errno;
  ::close(fd);
  if (!ok) throw std::runtime_error(path + ": HIDIOCGRDESC failed: " + std::strerror(saved));
  return {descriptor.value, descriptor.value + size};
}

}  // namespace

std::vector<std::uint8_t> readHidrawDescriptor(const std::string& hidraw_path) {
  const std::string node = hidraw_path.substr(hidraw_path.find_last_of('/') + 1);
  std::ifstream in("/sys/class/hidraw/" + node + "/device/report_descriptor", std::ios::binary);
  if (in) {
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!bytes.empty()) return bytes;
  }
  return descriptorByIoctl(hidraw_path);
}

HidapiTransport::HidapiTransport() {
  if (hid_init() != 0) throw std::runtime_error("hidapi: hid_init failed: " + utf8(hid_error(nullptr)));
}

HidapiTransport::~HidapiTransport() { hid_exit(); }

std::vector<HidDeviceInfo> HidapiTransport::enumerate() {
  std::vector<HidDeviceInfo> devices;
  hid_device_info* list = hid_enumerate(0, 0);
  for (const hid_device_info* d = list; d != nullptr; d = d->next) {
    HidDeviceInfo info;
    info.path = d->path != nullptr ? d->path : "";
    info.vid = d->vendor_id;
    info.pid = d->product_id;
    info.serial = utf8(d->serial_number);
    info.manufacturer = utf8(d->manufacturer_string);
    info.product = utf8(d->product_string);
    info.usage_page = d->usage_page;
    info.usage = d->usage;
    info.interface_number = d->interface_number;
    info.bus = linuxBus(d->bus_type);
    devices.push_back(std::move(info));
  }
  hid_free_enumeration(list);
  return devices;
}

std::unique_ptr<HidConnection> HidapiTransport::open(const HidDeviceInfo& device, std::string& error) {
  std::vector<std::uint8_t> descriptor;
  try {
    descriptor = readHidrawDescriptor(device.path);
  } catch (const std::runtime_error& e) {
    error = e.what();
    return nullptr;
  }
  hid_device* handle = hid_open_path(device.path.c_str());
  if (handle == nullptr) {
    error = device.path + ": " + utf8(hid_error(nullptr));
    return nullptr;
  }
  return std::make_unique<HidapiConnection>(handle, std::move(descriptor));
}

std::vector<std::uint8_t> HidapiTransport::descriptorOf(const HidDeviceInfo& device, std::string& error) {
  try {
    return readHidrawDescriptor(device.path);
  } catch (const std::runtime_error& e) {
    error = e.what();
    return {};
  }
}

std::string HidapiTransport::name() const { return std::string("hidapi ") + hid_version_str() + " (hidraw)"; }

}  // namespace incise::devices
