#include "incise/sim/fixed_rate_loop.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <stdexcept>
#include <string>
#include <utility>

namespace incise::sim {

namespace {

using Clock = std::chrono::steady_clock;

// A middle SCHED_FIFO priority: above every normal thread, below the kernel's own real-time threads.
constexpr int kFifoPriority = 50;

inline void cpuRelax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

}  // namespace

FixedRateLoop::FixedRateLoop(const FixedRateLoopOptions& options) : options_(options) {
  if (options_.period_us <= 0)
    throw std::invalid_argument("FixedRateLoop: period_us must be > 0, got " + std::to_string(options_.period_us));
  if (options_.spin_us < 0 || options_.spin_us > options_.period_us)
    throw std::invalid_argument("FixedRateLoop: spin_us must be in [0, period_us = " +
                                std::to_string(options_.period_us) + "], got " + std::to_string(options_.spin_us));
  if (options_.max_catch_up_frames < 0)
    throw std::invalid_argument("FixedRateLoop: max_catch_up_frames must be >= 0, got " +
                                std::to_string(options_.max_catch_up_frames));
  // A correctly rounded division: 1000 us gives exactly the double 0.001.
  dt_s_ = static_cast<double>(options_.period_us) / 1e6;
}

FixedRateLoop::~FixedRateLoop() {
  try {
    stop();
  } catch (...) {
    // A destructor cannot report the step's exception; stop() called explicitly would have.
  }
}

void FixedRateLoop::resetCounters() noexcept {
  frames_.store(0, std::memory_order_relaxed);
  overruns_.store(0, std::memory_order_relaxed);
  skipped_deadlines_.store(0, std::memory_order_relaxed);
  max_period_error_us_.store(0.0, std::memory_order_relaxed);
}

void FixedRateLoop::start(StepFunction step) {
  if (!step) throw std::invalid_argument("FixedRateLoop::start: empty step function");
  if (running()) throw std::logic_error("FixedRateLoop::start: the loop is already running");
  stop();  // joins a loop that ended by itself (requestStop from the step, or an exception)

  step_ = std::move(step);
  resetCounters();
  realtime_status_.store(RealtimeStatus::NotRequested, std::memory_order_relaxed);
  realtime_error_.store(0, std::memory_order_relaxed);
  stop_requested_.store(false, std::memory_order_relaxed);
  running_.store(true, std::memory_order_release);

  std::promise<void> ready;
  std::future<void> ready_future = ready.get_future();
  try {
    thread_ = std::thread([this, &ready] {
      // Published for stop() called inside the step: thread_ itself may still be being assigned.
      loop_thread_id_.store(std::this_thread::get_id(), std::memory_order_release);
      if (options_.realtime_priority) {
        sched_param param{};
        param.sched_priority = std::min(kFifoPriority, sched_get_priority_max(SCHED_FIFO));
        const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
        realtime_error_.store(rc, std::memory_order_relaxed);
        realtime_status_.store(rc == 0 ? RealtimeStatus::Granted : RealtimeStatus::Denied, std::memory_order_release);
      }
      if (options_.cpu >= 0) {  // keep the loop on its own core, away from device and viewer threads
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET(options_.cpu, &set);
        pthread_setaffinity_np(pthread_self(), sizeof set, &set);  // best effort: failure leaves it floating
      }
      ready.set_value();  // the last use of `ready`: start() may return from here on
      run();
    });
  } catch (...) {
    running_.store(false, std::memory_order_release);
    throw;
  }
  ready_future.wait();
}

void FixedRateLoop::run() {
  const std::chrono::microseconds period(options_.period_us);
  const std::chrono::microseconds spin(options_.spin_us);
  const std::int64_t max_catch_up = options_.max_catch_up_frames;
  const Clock::time_point t0 = Clock::now();
  std::int64_t k = 0;      // deadline index
  std::int64_t frame = 0;  // frames run
  double max_error_us = 0.0;
  try {
    while (!stop_requested_.load(std::memory_order_acquire)) {
      const Clock::time_point deadline = t0 + k * period;
      if (spin.count() > 0) {
        std::this_thread::sleep_until(deadline - spin);
        while (Clock::now() < deadline) cpuRelax();
      } else {
        std::this_thread::sleep_until(deadline);
      }
      if (stop_requested_.load(std::memory_order_acquire)) break;

      const Clock::time_point begin = Clock::now();
      const double error_us = std::chrono::duration<double, std::micro>(begin - deadline).count();
      step_(frameInfo(frame, error_us, true));
      ++frame;
      frames_.store(frame, std::memory_order_release);
      if (error_us > max_error_us) {
        max_error_us = error_us;
        max_period_error_us_.store(max_error_us, std::memory_order_relaxed);
      }

      // The last deadline index that has passed. Past k: this frame overran. Run at most max_catch_up of the
      // passed deadlines (the latest ones), skip the others, never change dt.
      const std::int64_t last_passed = (Clock::now() - t0) / period;
      std::int64_t next = k + 1;
      if (last_passed >= next) {
        overruns_.fetch_add(1, std::memory_order_relaxed);
        next = std::max(next, last_passed + 1 - max_catch_up);
        skipped_deadlines_.fetch_add(next - (k + 1), std::memory_order_relaxed);
      }
      k = next;
    }
  } catch (...) {
    step_error_ = std::current_exception();
  }
  running_.store(false, std::memory_order_release);
}

void FixedRateLoop::requestStop() noexcept { stop_requested_.store(true, std::memory_order_release); }

void FixedRateLoop::stop() {
  requestStop();
  // From the step: joining would deadlock. Checked first, because the loop thread must not read thread_.
  if (loop_thread_id_.load(std::memory_order_acquire) == std::this_thread::get_id()) return;
  if (!thread_.joinable()) return;
  thread_.join();
  step_ = nullptr;
  if (step_error_) std::rethrow_exception(std::exchange(step_error_, nullptr));
}

std::int64_t FixedRateLoop::runFast(const StepFunction& step, std::int64_t frames) {
  if (!step) throw std::invalid_argument("FixedRateLoop::runFast: empty step function");
  if (frames < 0)
    throw std::invalid_argument("FixedRateLoop::runFast: frames must be >= 0, got " + std::to_string(frames));
  if (running()) throw std::logic_error("FixedRateLoop::runFast: the loop thread is running");
  resetCounters();
  stop_requested_.store(false, std::memory_order_relaxed);
  std::int64_t frame = 0;
  while (frame < frames && !stop_requested_.load(std::memory_order_acquire)) {
    step(frameInfo(frame, 0.0, false));
    ++frame;
    frames_.store(frame, std::memory_order_release);
  }
  return frame;
}

LoopCounters FixedRateLoop::counters() const noexcept {
  return LoopCounters{frames_.load(std::memory_order_acquire), overruns_.load(std::memory_order_relaxed),
                      skipped_deadlines_.load(std::memory_order_relaxed),
                      max_period_error_us_.load(std::memory_order_relaxed)};
}

int lastCpu() noexcept { return std::max(0, static_cast<int>(std::thread::hardware_concurrency()) - 1); }

void keepOffLastCpu() noexcept {
  const int cpus = static_cast<int>(std::thread::hardware_concurrency());
  if (cpus < 2) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c = 0; c < cpus - 1; ++c) CPU_SET(c, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);  // best effort
}

}  // namespace incise::sim
