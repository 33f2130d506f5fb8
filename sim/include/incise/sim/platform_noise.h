// The machine's own noise, measured the way the sim thread runs: a FixedRateLoop with the benchmark's
// options (period, spin, SCHED_FIFO, the same pinned CPU) runs one fixed computation per frame, a dependent
// chain of multiply-adds on registers (no memory traffic, no branch that depends on data, the same
// instructions every frame: about 2 us, the haptic part's usual time), and times it on the wall clock and
// the thread's CPU clock.
// Why: whatever stretches a constant computation is not its work. Interrupts, the kernel and a VM's host
// take the CPU inside a frame without a context switch, and on kernels without CONFIG_IRQ_TIME_ACCOUNTING
// the thread's CPU clock counts that time as the thread's. The benchmark sets the haptic part's maximum
// beside this baseline: frames of ours over the target, against frames of a constant workload over it.
// Units: microseconds; seconds of frames. Thread: measurePlatformNoise() blocks the caller for `seconds`
// (the loop thread does the work). Cost: one clock read pair per frame; allocates its samples up front.
#pragma once

#include <cstdint>

#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/latency_stats.h"

namespace incise::sim {

// About 2 us at 4 cycles a step on a 2.5-3 GHz core.
inline constexpr int kPlatformNoiseMultiplyAdds = 1500;

struct PlatformNoise {
  SampleSummary work_us;      // the fixed computation's wall time per frame
  SampleSummary work_cpu_us;  // ... its thread CPU time (CLOCK_THREAD_CPUTIME_ID)
  std::int64_t frames = 0;
  std::int64_t frames_over_threshold = 0;  // work_us > threshold_us
  double threshold_us = 0.0;
  RealtimeStatus realtime = RealtimeStatus::NotRequested;
};

// The fixed computation, `multiply_adds` dependent steps; returns the chain's value (kept, so it is not
// optimised away). Pure and deterministic; noexcept.
double fixedWork(int multiply_adds) noexcept;

// Runs `seconds` of frames (> 0) of fixedWork(multiply_adds) at `loop`'s period and options. Throws
// std::invalid_argument for seconds <= 0 or multiply_adds < 1.
PlatformNoise measurePlatformNoise(const FixedRateLoopOptions& loop, double seconds, double threshold_us,
                                   int multiply_adds = kPlatformNoiseMultiplyAdds);

}  // namespace incise::sim
