// A transport without hardware: one device whose reports are a recording's, delivered at their recorded
// times (or as fast as they are read), and which unplugs and replugs on cue. The live path —
// HidPoseSource's enumerate / open / read / re-enumerate — runs on it exactly as on hidapi. Used by the
// tests (hot-plug under ThreadSanitizer) and the latency benchmark.
//
// Timing: report k is due at open_time + (time_us[k] - time_us[0]) / speed, shifted by the time spent
// unplugged. After the last report the device stays connected and silent (read times out).
// Cues: before report `before_report` is delivered the device goes away: the open connection's read
// returns -1, enumerate lists nothing and open fails for `unplugged_s`; then the device is back under a new
// path (as a replugged hidraw node is) with the same VID, PID and serial, and delivery resumes with that
// report.
// Threads: the transport and its connections from one thread (the device thread); delivered() and
// unplugged() from any thread. Failure: none beyond HidTransport's (-1 reads while unplugged).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <vector>

#include "incise/devices/hid_recording.h"
#include "incise/devices/hid_transport.h"

namespace incise::devices {

struct ReplayCue {
  std::size_t before_report = 0;
  double unplugged_s = 1.0;
};

struct ReplayTransportOptions {
  HidDeviceInfo device;   // what enumerate lists (its path gets a generation suffix)
  bool real_time = true;  // false: every read returns the next report at once
  double speed = 1.0;     // real time only: 2 = twice as fast as recorded
  std::vector<ReplayCue> cues;
};

class ReplayTransport final : public HidTransport {
 public:
  // `reports` in time order (their `device` field is not looked at).
  ReplayTransport(std::vector<std::uint8_t> descriptor, std::vector<HidRecordedReport> reports,
                  ReplayTransportOptions options);
  // Device `device` of a recording: its descriptor and reports; options.device gets its VID, PID and name
  // when they are left 0 / empty.
  ReplayTransport(const HidRecording& recording, int device, ReplayTransportOptions options);

  std::vector<HidDeviceInfo> enumerate() override;
  std::unique_ptr<HidConnection> open(const HidDeviceInfo& device, std::string& error) override;
  std::vector<std::uint8_t> descriptorOf(const HidDeviceInfo&, std::string&) override { return descriptor_; }
  std::string name() const override { return "replay transport"; }

  std::size_t delivered() const { return delivered_.load(std::memory_order_acquire); }
  std::size_t reportCount() const { return reports_.size(); }
  bool unplugged() const { return unplugged_.load(std::memory_order_acquire); }

 private:
  class Connection;
  using Clock = std::chrono::steady_clock;
  int read(std::span<std::uint8_t> buffer, int timeout_ms, int generation) noexcept;
  int unplug(std::size_t next) noexcept;
  bool pluggedNow();
  Clock::time_point due(std::size_t report) const;

  std::vector<std::uint8_t> descriptor_;
  std::vector<HidRecordedReport> reports_;
  ReplayTransportOptions options_;
  std::size_t next_cue_ = 0;
  int generation_ = 0;  // bumped at each replug: older connections are dead
  Clock::time_point start_{}, replug_at_{};
  Clock::duration shift_{};  // time spent unplugged, added to the due times
  bool started_ = false;
  std::atomic<std::size_t> delivered_{0};
  std::atomic<bool> unplugged_{false};
};

}  // namespace incise::devices
