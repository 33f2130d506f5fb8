// A live HID pose source: a device thread that finds the device (HidDeviceSelector), reads its reports
// with a timeout, turns them into poses through the profile its descriptor calls for (hid_profile.h),
// stamps them with the steady clock at arrival and pushes them into a PoseSink (the simulation's queue).
// It survives unplugging and replugging (hot-plug) and allocates nothing per report: above HidPoseSource.
//
// Threads: construct, start, stop and destroy from one thread; the counters, state() and describe()
// from any thread; the message callback and the sink run on the device thread. stop() returns within
// about read_timeout_ms. Failure: start() throws std::logic_error when already started; nothing on the
// device thread throws out of it (transport, descriptor and profile errors become messages and a retry).
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_profile.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_transport.h"
#include "incise/devices/pose_source.h"

namespace incise::devices {

enum class HidSourceState : std::uint8_t { Searching, Connected, Unplugged, Stopped };
const char* toString(HidSourceState state);

struct HidPoseSourceOptions {
  int read_timeout_ms = 5;          // bounds how long stop() waits for the device thread
  double reconnect_period_s = 0.5;  // between enumerations while no device is open
};

// Hot-plug. When a read fails (the device went away, mid-stroke or not) the source pushes the profile's
// lifted pose at once — no buttons, tip lifted: the simulation sees no contact, no force and no cutting,
// and an incision in progress finishes as when the user lifts the pen — reports "unplugged", and
// re-enumerates every reconnect_period_s. It reopens the first device matching the selector by VID, PID
// and serial (not by the hidraw path, which changes on replug), and resumes: a pen at once (its reports
// are absolute), a 6-DOF device from its last pose with zero velocity. Each change of state is reported
// once through the message callback; nothing is logged per report.
//
// Per report (the device thread's hot path): one read into a fixed buffer, the profile's update, one
// push: no allocation, no lock, no logging. A report that is empty, has an undeclared ID or is shorter than
// its layout is counted (badReports) and skipped; one of a layout the profile does not use (a tablet's pad
// or touch report) is counted as ignored; a pose not after the previous one in time is not pushed.
class HidPoseSource {
 public:
  using MessageFn = std::function<void(const std::string&)>;

  // `transport` and `sink` must outlive the source. `on_message` may be empty.
  HidPoseSource(HidTransport& transport, HidDeviceSelector selector, HidMapping mapping, PoseSink& sink,
                MessageFn on_message = {}, HidPoseSourceOptions options = {});
  ~HidPoseSource();  // stop()
  HidPoseSource(const HidPoseSource&) = delete;
  HidPoseSource& operator=(const HidPoseSource&) = delete;

  void start();
  // Ends the device thread: a connected device's lifted pose is pushed last, the connection closed.
  void stop();

  HidSourceState state() const { return state_.load(std::memory_order_acquire); }
  // "056a:0357 'Wacom Intuos Pro M' at /dev/hidraw3, pen profile (connected)".
  std::string describe() const;

  std::int64_t reports() const { return reports_.load(std::memory_order_relaxed); }
  std::int64_t poses() const { return poses_.load(std::memory_order_relaxed); }
  std::int64_t badReports() const { return bad_reports_.load(std::memory_order_relaxed); }
  std::int64_t ignoredReports() const { return ignored_reports_.load(std::memory_order_relaxed); }
  std::int64_t posesDropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::int64_t connects() const { return connects_.load(std::memory_order_relaxed); }
  std::int64_t disconnects() const { return disconnects_.load(std::memory_order_relaxed); }

 private:
  void run() noexcept;
  bool connect();
  bool tryDevice(const HidDeviceInfo& device, std::string& why);
  void disconnect(const std::string& why);
  void handleReport(std::span<const std::uint8_t> raw, double time_s) noexcept;
  void pushPose(const PoseSample& pose) noexcept;
  void setState(HidSourceState state, const std::string& message);
  void waitReconnect();
  static double nowS() noexcept;

  HidTransport& transport_;
  HidDeviceSelector selector_;
  HidMapping mapping_;
  PoseSink& sink_;
  MessageFn on_message_;
  HidPoseSourceOptions options_;

  // Device-thread state.
  std::unique_ptr<HidConnection> connection_;
  HidDescriptor descriptor_;
  std::unique_ptr<HidReportDecoder> decoder_;
  std::unique_ptr<HidProfile> profile_;
  std::array<std::uint8_t, 4096> buffer_{};
  double last_time_s_ = -1.0;
  std::string last_failure_;

  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mutex wait_mutex_;
  std::condition_variable wait_;
  std::atomic<HidSourceState> state_{HidSourceState::Searching};
  mutable std::mutex describe_mutex_;
  std::string description_;  // the device and its profile, without the state; written on the device thread
  std::atomic<std::int64_t> reports_{0}, poses_{0}, bad_reports_{0}, ignored_reports_{0}, dropped_{0};
  std::atomic<std::int64_t> connects_{0}, disconnects_{0};
};

}  // namespace incise::devices
