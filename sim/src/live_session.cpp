#include "incise/sim/live_session.h"

#include <stdexcept>
#include <string>
#include <thread>

#include "incise/incision/surface_cutter.h"

namespace incise::sim {

namespace {

FixedRateLoopOptions loopOptions(const LiveOptions& o) {
  if (o.period_us <= 0 || !(o.settle_s >= 0.0))
    throw std::invalid_argument("LiveSession: period_us = " + std::to_string(o.period_us) +
                                " and settle_s = " + std::to_string(o.settle_s) + " must be > 0 and >= 0");
  FixedRateLoopOptions l;
  l.period_us = o.period_us;
  l.realtime_priority = o.realtime_priority;
  l.spin_us = o.spin_us;
  if (o.pin_threads && std::thread::hardware_concurrency() >= 2) l.cpu = lastCpu();
  return l;
}

}  // namespace

LiveSession::LiveSession(World& world, const LiveOptions& options, ForceSink* sink)
    : world_(world),
      options_(options),
      sim_(world, sink, options.period_us, 0.0, options.stats),
      loop_(loopOptions(options)) {
  poses_.reserve(1 << 16);
  sim_.attachGeometry(options.geometry);
  sim_.attachTimes(options.times);
}

LiveSession::~LiveSession() {
  if (started_.load() && !stopped_) loop_.stop();
  try {
    sim_.finishPhysics();
  } catch (...) {  // the physics thread could not be joined: the world's destructor tries again
  }
}

void LiveSession::start() {
  if (started_.exchange(true)) throw std::logic_error("LiveSession: start() called twice");
  start_ = std::chrono::steady_clock::now();
  sim_.startPhysicsThread({});  // a simulated tissue steps on its own thread; the frame never waits for it
  loop_.start([this](const FrameInfo& info) { frame(info); });
}

double LiveSession::nowS() const noexcept {
  if (!started_.load(std::memory_order_acquire)) return 0.0;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

bool LiveSession::push(const devices::PoseSample& pose) noexcept {
  if (!started_.load(std::memory_order_acquire) || stopping_.load(std::memory_order_acquire)) return false;
  if (!sim_.pushPose(pose)) return false;
  try {
    poses_.push_back(pose);
  } catch (...) {  // out of memory for the copy: the pose still cuts; the copy says what it has
  }
  last_pose_s_.store(pose.time_s, std::memory_order_release);
  pushed_.fetch_add(1, std::memory_order_acq_rel);
  return true;
}

// Sim thread. After stop() was asked: ends once every pushed pose is taken, no cutting work is carried and
// settle_s has passed since the last pose.
void LiveSession::frame(const FrameInfo& info) noexcept {
  sim_.frame(info);
  last_frame_ = info.frame;
  if (!stopping_.load(std::memory_order_acquire)) return;
  const bool all_taken = sim_.posesTaken() + sim_.posesDropped() >= pushed_.load(std::memory_order_acquire);
  if (all_taken && !world_.pending() &&
      sim_.frameTime(info.frame) >= last_pose_s_.load(std::memory_order_acquire) + options_.settle_s)
    loop_.requestStop();
}

ReplayReport LiveSession::stop() {
  if (stopped_ || !started_.load()) return report_;
  stopping_.store(true, std::memory_order_release);
  while (loop_.running()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  loop_.stop();
  stopped_ = true;
  sim_.finishPhysics();
  fillReport(report_, sim_, loop_.counters(), options_.period_us);
  report_.wall_s = nowS();
  if (options_.geometry) {  // the loop has stopped: this thread is the stream's writer now
    report_.geometry_flushed = options_.geometry->flush(world_, std::max<std::int64_t>(last_frame_, 0),
                                                        std::chrono::milliseconds(options_.flush_timeout_ms));
    report_.geometry = options_.geometry->counters();
  }
  return report_;
}

}  // namespace incise::sim
