#include "incise/devices/replay_transport.h"

#include <algorithm>
#include <cstring>
#include <thread>

namespace incise::devices {

class ReplayTransport::Connection final : public HidConnection {
 public:
  Connection(ReplayTransport& transport, int generation) : transport_(transport), generation_(generation) {}
  int read(std::span<std::uint8_t> buffer, int timeout_ms) noexcept override {
    return transport_.read(buffer, timeout_ms, generation_);
  }
  const std::vector<std::uint8_t>& descriptor() const noexcept override { return transport_.descriptor_; }
  std::string error() const override { return "replayed device unplugged"; }

 private:
  ReplayTransport& transport_;
  int generation_;
};

ReplayTransport::ReplayTransport(std::vector<std::uint8_t> descriptor, std::vector<HidRecordedReport> reports,
                                 ReplayTransportOptions options)
    : descriptor_(std::move(descriptor)), reports_(std::move(reports)), options_(std::move(options)) {
  std::sort(options_.cues.begin(), options_.cues.end(),
            [](const ReplayCue& a, const ReplayCue& b) { return a.before_report < b.before_report; });
}

namespace {

std::vector<HidRecordedReport> reportsOf(const HidRecording& recording, int device) {
  std::vector<HidRecordedReport> reports;
  for (const auto& r : recording.reports)
    if (r.device == device) reports.push_back(r);
  return reports;
}

ReplayTransportOptions withDevice(ReplayTransportOptions options, const HidRecordedDevice& device) {
  if (options.device.vid == 0 && options.device.pid == 0) {
    options.device.vid = device.vid;
    options.device.pid = device.pid;
  }
  if (options.device.product.empty()) options.device.product = device.name;
  if (options.device.bus == 0) options.device.bus = device.bus;
  return options;
}

}  // namespace

ReplayTransport::ReplayTransport(const HidRecording& recording, int device, ReplayTransportOptions options)
    : ReplayTransport(recording.devices.at(static_cast<std::size_t>(device)).descriptor, reportsOf(recording, device),
                      withDevice(std::move(options), recording.devices.at(static_cast<std::size_t>(device)))) {}

bool ReplayTransport::pluggedNow() {
  if (!unplugged_.load(std::memory_order_relaxed)) return true;
  if (Clock::now() < replug_at_) return false;
  unplugged_.store(false, std::memory_order_release);
  return true;
}

std::vector<HidDeviceInfo> ReplayTransport::enumerate() {
  if (!pluggedNow()) return {};
  HidDeviceInfo info = options_.device;
  info.path = (info.path.empty() ? std::string("replay:hidraw") : info.path) + std::to_string(generation_);
  return {info};
}

std::unique_ptr<HidConnection> ReplayTransport::open(const HidDeviceInfo& device, std::string& error) {
  if (!pluggedNow() || device.vid != options_.device.vid || device.pid != options_.device.pid) {
    error = device.path + ": no such device";
    return nullptr;
  }
  if (!started_) {
    started_ = true;
    start_ = Clock::now();
  }
  return std::make_unique<Connection>(*this, generation_);
}

ReplayTransport::Clock::time_point ReplayTransport::due(std::size_t report) const {
  const double offset_s =
      static_cast<double>(reports_[report].time_us - reports_.front().time_us) * 1e-6 / options_.speed;
  return start_ + shift_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(offset_s));
}

int ReplayTransport::read(std::span<std::uint8_t> buffer, int timeout_ms, int generation) noexcept {
  if (generation != generation_ || unplugged_.load(std::memory_order_relaxed)) return -1;
  const std::size_t next = delivered_.load(std::memory_order_relaxed);
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  const bool cue = next_cue_ < options_.cues.size() && options_.cues[next_cue_].before_report <= next;
  if (next >= reports_.size() && !cue) {
    std::this_thread::sleep_until(deadline);
    return 0;
  }
  if (options_.real_time && next < reports_.size()) {
    const auto when = due(next);
    if (when > deadline) {
      std::this_thread::sleep_until(deadline);
      return 0;
    }
    std::this_thread::sleep_until(when);
  }
  if (cue) return unplug(next);
  const auto& bytes = reports_[next].bytes;
  const std::size_t n = std::min(bytes.size(), buffer.size());
  std::memcpy(buffer.data(), bytes.data(), n);
  delivered_.store(next + 1, std::memory_order_release);
  return static_cast<int>(n);
}

// The device goes away at report `next`'s time; the reports after it are due again from the replug on.
int ReplayTransport::unplug(std::size_t next) noexcept {
  const auto now = Clock::now();
  replug_at_ = now + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(options_.cues[next_cue_].unplugged_s));
  if (options_.real_time && next < reports_.size()) shift_ += replug_at_ - now;
  ++next_cue_;
  ++generation_;
  unplugged_.store(true, std::memory_order_release);
  return -1;
}

}  // namespace incise::devices
