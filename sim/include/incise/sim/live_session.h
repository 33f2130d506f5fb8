// A live run (a trainee's mouse in the viewer, a device): the sim thread at its rate on FixedRateLoop while
// a producer on another thread (the window's, a device's) pushes poses as they happen; snapshots, every
// frame's timings and the geometry stream for a viewer, as in a real-time replay (simulation.h). The poses it
// took replay as a trace to the same cut, byte for byte (the clock and stop(): above LiveSession).
//
// Threads: the owner calls start() and stop(); push() from one producer thread; takeSnapshot() from one
// reader thread; the World belongs to the sim thread between start() and stop(). Cost: push O(1) (a queue
// slot and an amortised append to the copy, on the producer's thread). Failure: the constructor throws
// std::invalid_argument for bad options; start() twice throws std::logic_error; push never throws (false:
// the session is not running or the queue is full: dropped and counted).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "incise/devices/pose_source.h"
#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/simulation.h"

namespace incise::sim {

struct LiveOptions {
  std::int64_t period_us = 1000;
  double settle_s = 0.2;  // simulated time after the last pose that stop() still runs
  bool realtime_priority = false;
  std::int64_t spin_us = 0;
  bool pin_threads = false;            // the loop on the last CPU (keepOffLastCpu() for the others)
  GeometryStream* geometry = nullptr;  // attached before the first frame, flushed at stop()
  FrameTimesQueue* times = nullptr;
  LatencyStats* stats = nullptr;
  std::int64_t flush_timeout_ms = 5000;
};

// The clock is the session's: seconds since start(), frame k at k x period. A producer stamps its poses
// with nowS() (or its own clock started with the session) and pushes them in time order; a pose whose time
// is not after the previous one is dropped by World, as from any device. The session keeps a copy of every
// pose it took, in order (poses(), after stop()): replayed as a trace through a fresh world of the same
// scenario it gives the same cut, byte for byte, because the cut depends on the poses alone, never on the
// frames that handled them (the test does exactly that).
//
// stop() ends the producer's part: frames run on until the cutter has no work left and `settle_s` has
// passed since the last pose (the wound opens), then the loop ends and the geometry stream is flushed.
class LiveSession final : public devices::PoseSink {
 public:
  LiveSession(World& world, const LiveOptions& options, ForceSink* sink = nullptr);
  ~LiveSession() override;  // stop() if still running, its report dropped
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  void start();
  // Seconds since start() on the steady clock (0 before it).
  double nowS() const noexcept;
  // Producer thread: the pose into the simulation's queue and the session's copy.
  bool push(const devices::PoseSample& pose) noexcept override;
  bool takeSnapshot(Snapshot& out) noexcept { return sim_.takeSnapshot(out); }
  bool running() const noexcept { return loop_.running(); }

  // Settles, stops the loop and flushes the geometry stream; the report as replay's (frames, latency,
  // poses taken and dropped, incisions, geometry_flushed). Once; later calls return the same report.
  ReplayReport stop();
  // Every pose taken, in the order pushed (after stop(); during the run only from the producer's thread).
  const std::vector<devices::PoseSample>& poses() const noexcept { return poses_; }

 private:
  void frame(const FrameInfo& info) noexcept;

  World& world_;
  LiveOptions options_;
  Simulation sim_;
  FixedRateLoop loop_;
  std::chrono::steady_clock::time_point start_{};
  std::atomic<bool> started_{false}, stopping_{false};
  std::atomic<double> last_pose_s_{0.0};
  std::atomic<std::int64_t> pushed_{0};
  std::vector<devices::PoseSample> poses_;
  std::int64_t last_frame_ = -1;
  bool stopped_ = false;
  ReplayReport report_;
};

}  // namespace incise::sim
