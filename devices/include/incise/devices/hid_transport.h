// The small interface between incise and HID hardware: enumerate devices, open one, read its reports with a
// timeout. HidapiTransport (hidapi_transport.h) is the real one; ReplayTransport (replay_transport.h)
// replays recorded reports and unplugs and replugs on cue, so the live code path runs without hardware.
//
// Threads: a transport and its connections are used from one thread at a time (the device thread);
// enumerate/open are not called concurrently with each other. Failure: enumerate returns what it can
// (an empty list when the system has no HID access); open returns nullptr and fills `error`; read returns
// -1 when the device is gone or broken (a connection never recovers: close it, re-enumerate, reopen).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace incise::devices {

struct HidDeviceInfo {
  std::string path;  // the system's name for this interface (hidraw: /dev/hidrawN); changes on replug
  std::uint16_t vid = 0, pid = 0;
  std::string serial, manufacturer, product;
  std::uint16_t usage_page = 0, usage = 0;  // of the first top-level collection, as the system reports it
  int interface_number = -1;
  std::uint32_t bus = 0;  // 3 USB, 5 Bluetooth (Linux BUS_* numbers); 0 unknown
};

class HidConnection {
 public:
  virtual ~HidConnection() = default;
  // One report into `buffer`, as the device sent it (report ID first when it uses IDs). Returns its length,
  // 0 when none arrived within timeout_ms, -1 when the device is gone or the read failed (see error()).
  virtual int read(std::span<std::uint8_t> buffer, int timeout_ms) noexcept = 0;
  // The report descriptor, read when the connection was opened.
  virtual const std::vector<std::uint8_t>& descriptor() const noexcept = 0;
  virtual std::string error() const = 0;
};

class HidTransport {
 public:
  virtual ~HidTransport() = default;
  virtual std::vector<HidDeviceInfo> enumerate() = 0;
  virtual std::unique_ptr<HidConnection> open(const HidDeviceInfo& device, std::string& error) = 0;
  // The device's report descriptor without opening it for reading (for listings); empty and `error` set
  // when it cannot be read.
  virtual std::vector<std::uint8_t> descriptorOf(const HidDeviceInfo& device, std::string& error) = 0;
  virtual std::string name() const = 0;  // "hidapi (hidraw)", "replay of 'pen.hid'"
};

// Which device to use: "VID:PID" or "VID:PID:serial" in hex (e.g. "056a:0357" or "046d:c626:ABC123"), or
// a path ("/dev/hidraw3"). A device is reopened after a replug by VID, PID and serial, never by path
// (unless the selector is a path).
struct HidDeviceSelector {
  std::uint16_t vid = 0, pid = 0;
  std::optional<std::string> serial;
  std::optional<std::string> path;

  bool matches(const HidDeviceInfo& device) const;
  std::string describe() const;  // as parsed: "056a:0357", "/dev/hidraw3"
};

// Throws std::invalid_argument "--device 'text': what is wrong".
HidDeviceSelector parseHidDeviceSelector(const std::string& text);

// "056a:0357"
std::string formatVidPid(std::uint16_t vid, std::uint16_t pid);

}  // namespace incise::devices
