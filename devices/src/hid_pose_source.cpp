#include "incise/devices/hid_pose_source.h"

#include <chrono>
#include <stdexcept>

namespace incise::devices {

const char* toString(HidSourceState state) {
  switch (state) {
    case HidSourceState::Searching:
      return "searching";
    case HidSourceState::Connected:
      return "connected";
    case HidSourceState::Unplugged:
      return "unplugged";
    case HidSourceState::Stopped:
      return "stopped";
  }
  return "?";
}

HidPoseSource::HidPoseSource(HidTransport& transport, HidDeviceSelector selector, HidMapping mapping, PoseSink& sink,
                             MessageFn on_message, HidPoseSourceOptions options)
    : transport_(transport),
      selector_(std::move(selector)),
      mapping_(std::move(mapping)),
      sink_(sink),
      on_message_(std::move(on_message)),
      options_(options),
      description_(selector_.describe()) {}

HidPoseSource::~HidPoseSource() { stop(); }

void HidPoseSource::start() {
  if (thread_.joinable()) throw std::logic_error("HidPoseSource::start: already started");
  stop_.store(false);
  thread_ = std::thread([this] { run(); });
}

void HidPoseSource::stop() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(wait_mutex_);
    stop_.store(true, std::memory_order_release);
  }
  wait_.notify_all();
  thread_.join();
}

std::string HidPoseSource::describe() const {
  std::lock_guard lock(describe_mutex_);
  return description_ + " (" + toString(state()) + ")";
}

double HidPoseSource::nowS() noexcept {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void HidPoseSource::run() noexcept {
  while (!stop_.load(std::memory_order_acquire)) {
    if (!connection_) {
      bool connected = false;
      try {
        connected = connect();
      } catch (const std::exception& e) {
        last_failure_.clear();
        setState(state(), std::string("error while connecting: ") + e.what());
      }
      if (!connected) waitReconnect();
      continue;
    }
    const int n = connection_->read(buffer_, options_.read_timeout_ms);
    if (n < 0) {
      disconnect(connection_->error());
    } else if (n > 0) {
      handleReport(std::span<const std::uint8_t>(buffer_.data(), static_cast<std::size_t>(n)), nowS());
    }
  }
  if (connection_) {
    pushPose(profile_->lifted(nowS()));
    connection_.reset();
  }
  setState(HidSourceState::Stopped, "");
}

bool HidPoseSource::connect() {
  std::string why;
  for (const HidDeviceInfo& device : transport_.enumerate())
    if (selector_.matches(device) && tryDevice(device, why)) return true;
  if (why.empty()) why = "no device " + selector_.describe() + " on " + transport_.name();
  if (why != last_failure_) {  // once per reason, not every reconnect period
    last_failure_ = why;
    setState(state(), why);
  }
  return false;
}

bool HidPoseSource::tryDevice(const HidDeviceInfo& device, std::string& why) {
  std::string error;
  auto connection = transport_.open(device, error);
  if (!connection) {
    why = "cannot open " + device.path + ": " + error;
    return false;
  }
  const HidDeviceId id{device.vid, device.pid};
  const bool same_descriptor = profile_ && connection->descriptor() == descriptor_.bytes;
  if (!same_descriptor) {
    try {
      HidDescriptor descriptor = parseHidDescriptor(connection->descriptor());
      profile_.reset();
      descriptor_ = std::move(descriptor);
      decoder_ = std::make_unique<HidReportDecoder>(descriptor_);
      profile_ = makeHidProfile(descriptor_, id, mapping_);
    } catch (const std::exception& e) {
      profile_.reset();
      why = device.path + ": " + e.what();
      return false;
    }
  }
  profile_->reset();
  connection_ = std::move(connection);
  last_failure_.clear();
  connects_.fetch_add(1, std::memory_order_relaxed);
  {
    std::lock_guard lock(describe_mutex_);
    description_ = formatVidPid(device.vid, device.pid) + " '" + device.product + "' at " + device.path + ", " +
                   toString(profile_->kind()) + " profile";
  }
  setState(HidSourceState::Connected, "connected: " + description_);
  return true;
}

void HidPoseSource::disconnect(const std::string& why) {
  pushPose(profile_->lifted(nowS()));
  connection_.reset();
  disconnects_.fetch_add(1, std::memory_order_relaxed);
  setState(HidSourceState::Unplugged, "unplugged: " + description_ + " (" + why + "); the tool is lifted");
}

void HidPoseSource::handleReport(std::span<const std::uint8_t> raw, double time_s) noexcept {
  reports_.fetch_add(1, std::memory_order_relaxed);
  PoseSample pose;
  if (profile_->update(raw, time_s, pose)) {
    pushPose(pose);
    return;
  }
  const bool bad = decoder_->check(raw) != HidDecodeStatus::Ok;
  (bad ? bad_reports_ : ignored_reports_).fetch_add(1, std::memory_order_relaxed);
}

void HidPoseSource::pushPose(const PoseSample& pose) noexcept {
  if (pose.time_s <= last_time_s_) return;
  last_time_s_ = pose.time_s;
  if (sink_.push(pose))
    poses_.fetch_add(1, std::memory_order_relaxed);
  else
    dropped_.fetch_add(1, std::memory_order_relaxed);
}

void HidPoseSource::setState(HidSourceState state, const std::string& message) {
  state_.store(state, std::memory_order_release);
  if (on_message_ && !message.empty()) {
    try {
      on_message_(message);
    } catch (...) {
      // A failing message callback must not take the device thread down.
    }
  }
}

void HidPoseSource::waitReconnect() {
  std::unique_lock lock(wait_mutex_);
  wait_.wait_for(lock, std::chrono::duration<double>(options_.reconnect_period_s),
                 [this] { return stop_.load(std::memory_order_acquire); });
}

}  // namespace incise::devices
