// The clock and the thread of the simulation: calls a step function at a fixed period against absolute
// deadlines, always with the same dt. The step never reads a clock (Box2D-style: the app owns the clock,
// the step takes its dt), so a trace replayed with runFast() (as fast as possible) and with start() (in real
// time) runs the same frames with the same dt and gives the same result. Overruns and skipped deadlines are
// counted (the timing rules: above FixedRateLoop).
//
// Units: period_us and spin_us in microseconds, dt_s and t_s in seconds, period errors in microseconds.
// Threads: start(), stop(), runFast() from one controlling thread; requestStop(), running(), counters() and
// the realtime status from any thread, the step included. The step runs on the loop's own thread (start) or
// on the calling thread (runFast); it is stored once and called by reference: nothing allocates per frame.
// Failure: bad options throw std::invalid_argument (constructor); misuse (start while running, runFast while
// running) throws std::logic_error. The step should not throw (sim-thread rule); if it does, the loop ends
// and stop() rethrows the exception on the controlling thread (the destructor drops it).
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <thread>

namespace incise::sim {

struct FrameInfo {
  std::int64_t frame = 0;        // 0, 1, 2, … frames run so far (skipped deadlines do not count)
  double dt_s = 0.0;             // always exactly period_us / 1e6
  double t_s = 0.0;              // frame * dt_s: simulated time, not wall time
  double period_error_us = 0.0;  // how late this frame started vs its deadline (>= 0; 0 in runFast)
  bool against_clock = false;    // true on the loop thread (start()), false in runFast: frames as fast as possible
};

struct FixedRateLoopOptions {
  std::int64_t period_us = 1000;   // > 0
  std::int64_t spin_us = 0;        // in [0, period_us]: busy-wait this long before each deadline
  int max_catch_up_frames = 0;     // >= 0: how many missed deadlines may still run, late, back to back
  bool realtime_priority = false;  // try SCHED_FIFO for the loop thread; see realtimeStatus()
  int cpu = -1;                    // pin the loop thread to this CPU (best effort); -1: let the OS choose
};

// The calling thread keeps off the last CPU, where a loop with cpu = lastCpu() runs (best effort; nothing
// on a single CPU). Call it before creating threads that should inherit the mask (a window's GL threads).
int lastCpu() noexcept;
void keepOffLastCpu() noexcept;

enum class RealtimeStatus : std::uint8_t {
  NotRequested,  // realtime_priority = false, or the loop has not started
  Granted,       // the loop thread runs SCHED_FIFO
  Denied,        // pthread_setschedparam failed (realtimeError() says why, EPERM without the capability)
};

// Counter values read one by one: each is current, the set is not one consistent instant while running.
struct LoopCounters {
  std::int64_t frames = 0;             // step calls since start() (or during runFast)
  std::int64_t overruns = 0;           // frames that ended after the next deadline
  std::int64_t skipped_deadlines = 0;  // deadlines that ran no frame
  double max_period_error_us = 0.0;    // the largest period_error_us so far
};

// Timing: deadline_k = t0 + k * period on std::chrono::steady_clock, t0 = when the loop thread starts.
// The thread sleeps with std::this_thread::sleep_until (optionally the last spin_us are busy-waited, for
// a tighter start), then calls step(FrameInfo) with dt_s = period. Deadlines are absolute, so lateness
// never accumulates: frame k starts at t0 + k * period plus that one wake-up's error.
// Overruns: a frame that ends after the next deadline is an overrun. dt is never stretched and the missed
// time is not made up beyond a limit: the loop never stays more than max_catch_up_frames deadlines behind.
// With the default 0 the deadlines that passed during the frame are skipped (counted in skipped_deadlines)
// and the loop realigns to the next future deadline; with c > 0 up to c frames run back to back to catch up
// (each starts late; it is an overrun too when it still ends after its next deadline). Skipped deadlines
// run no frame: FrameInfo::frame and t_s count frames actually run, so simulated time falls behind wall
// time by the skipped periods (inputs stamped with wall time then land in later frames than in runFast).
class FixedRateLoop {
 public:
  using StepFunction = std::function<void(const FrameInfo&)>;

  explicit FixedRateLoop(const FixedRateLoopOptions& options = {});
  ~FixedRateLoop();  // stop(), dropping a step exception
  FixedRateLoop(const FixedRateLoop&) = delete;
  FixedRateLoop& operator=(const FixedRateLoop&) = delete;

  // Starts the loop thread and returns once it runs (its priority set or refused); frame 0 starts at once.
  // Resets the counters. Throws std::invalid_argument for an empty step, std::logic_error when already
  // running; a loop that has ended may be started again (start() first rethrows a pending step exception).
  void start(StepFunction step);

  // Asks the loop to end after the current frame (no further frame starts). Any thread, the step included
  // (the way a step ends a replay). Also ends a runFast() early.
  void requestStop() noexcept;

  // requestStop() and join: returns within one period plus one step. Idempotent; a no-op when not started.
  // Called from inside the step it only requests the stop. Rethrows an exception that escaped the step.
  void stop();

  // True from start() until the loop thread has left its loop (stopped, or the step threw).
  bool running() const noexcept { return running_.load(std::memory_order_acquire); }

  // Calls step `frames` times on the calling thread, as fast as possible, with the same FrameInfo sequence
  // as start() would give (frame, dt_s = period, t_s = frame * dt_s, period_error_us = 0). Returns the frames
  // run (fewer when requestStop() was called). Resets and updates the counters (overruns and skips stay 0).
  // Throws std::invalid_argument for frames < 0 or an empty step, std::logic_error while the loop runs.
  std::int64_t runFast(const StepFunction& step, std::int64_t frames);

  LoopCounters counters() const noexcept;
  RealtimeStatus realtimeStatus() const noexcept { return realtime_status_.load(std::memory_order_acquire); }
  // errno value from pthread_setschedparam when Denied, else 0.
  int realtimeError() const noexcept { return realtime_error_.load(std::memory_order_acquire); }

  const FixedRateLoopOptions& options() const noexcept { return options_; }
  double dtSeconds() const noexcept { return dt_s_; }

 private:
  void run();
  void resetCounters() noexcept;
  FrameInfo frameInfo(std::int64_t frame, double period_error_us, bool against_clock) const noexcept {
    return FrameInfo{frame, dt_s_, static_cast<double>(frame) * dt_s_, period_error_us, against_clock};
  }

  FixedRateLoopOptions options_;
  double dt_s_;
  StepFunction step_;
  std::thread thread_;
  std::exception_ptr step_error_;  // written by the loop thread, read after join

  std::atomic<std::thread::id> loop_thread_id_{};
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> running_{false};
  std::atomic<std::int64_t> frames_{0};
  std::atomic<std::int64_t> overruns_{0};
  std::atomic<std::int64_t> skipped_deadlines_{0};
  std::atomic<double> max_period_error_us_{0.0};
  std::atomic<RealtimeStatus> realtime_status_{RealtimeStatus::NotRequested};
  std::atomic<int> realtime_error_{0};
};

}  // namespace incise::sim
