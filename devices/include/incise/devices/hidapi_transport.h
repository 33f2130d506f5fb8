// The real transport: hidapi 0.13.1's hidraw backend (Debian libhidapi-dev). hidapi cannot return a report
// descriptor (hid_get_report_descriptor came in 0.14), so it is read from
// /sys/class/hidraw/hidrawN/device/report_descriptor, or with the HIDIOCGRDESC ioctl on /dev/hidrawN when
// sysfs is not mounted.
//
// Access: /dev/hidraw* is root-only on a stock system; a udev rule (docs/devices.md, "Permissions") gives the
// user read access. enumerate() lists every HID interface the system has, readable or not; open() says
// "permission denied" for one that is not.
// Threads: as HidTransport (one thread at a time); hid_init in the constructor, hid_exit in the destructor:
// one HidapiTransport per process. Failure: the constructor throws std::runtime_error when hid_init fails.
#pragma once

#include "incise/devices/hid_transport.h"

namespace incise::devices {

class HidapiTransport final : public HidTransport {
 public:
  HidapiTransport();
  ~HidapiTransport() override;
  HidapiTransport(const HidapiTransport&) = delete;
  HidapiTransport& operator=(const HidapiTransport&) = delete;

  std::vector<HidDeviceInfo> enumerate() override;
  std::unique_ptr<HidConnection> open(const HidDeviceInfo& device, std::string& error) override;
  std::vector<std::uint8_t> descriptorOf(const HidDeviceInfo& device, std::string& error) override;
  std::string name() const override;
};

// The report descriptor of a hidraw node ("/dev/hidraw3"): sysfs first, the ioctl second. Throws
// std::runtime_error naming the path and the reason.
std::vector<std::uint8_t> readHidrawDescriptor(const std::string& hidraw_path);

}  // namespace incise::devices
