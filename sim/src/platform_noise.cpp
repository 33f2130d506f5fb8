#include "incise/sim/platform_noise.h"

#include <time.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

namespace incise::sim {

namespace {

using Clock = std::chrono::steady_clock;

std::int64_t threadCpuNs() noexcept {
  timespec ts{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return -1;
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// An empty asm that "changes" x: every step is kept (no folding, no vectorising), x stays in a register.
inline void keepInRegister(double& x) noexcept {
#if defined(__x86_64__)
  asm volatile("" : "+x"(x));
#elif defined(__aarch64__)
  asm volatile("" : "+w"(x));
#else
  asm volatile("" : "+m"(x));
#endif
}

}  // namespace

double fixedWork(int multiply_adds) noexcept {
  double x = 1.0;
  for (int i = 0; i < multiply_adds; ++i) {
    x = x * 0.999999 + 1e-6;  // each step waits for the last: the chain's length sets the time
    keepInRegister(x);
  }
  return x;
}

PlatformNoise measurePlatformNoise(const FixedRateLoopOptions& loop_options, double seconds, double threshold_us,
                                   int multiply_adds) {
  if (!(seconds > 0.0) || multiply_adds < 1)
    throw std::invalid_argument("measurePlatformNoise: seconds must be > 0 and multiply_adds >= 1, got " +
                                std::to_string(seconds) + " and " + std::to_string(multiply_adds));
  const auto frames = static_cast<std::int64_t>(std::ceil(seconds * 1e6 / static_cast<double>(loop_options.period_us)));
  LatencyStats stats(static_cast<std::size_t>(frames));
  FixedRateLoop loop(loop_options);
  loop.start([&](const FrameInfo& info) {
    const std::int64_t cpu_start_ns = threadCpuNs();
    const auto start = Clock::now();
    static_cast<void>(fixedWork(multiply_adds));
    const auto end = Clock::now();
    const std::int64_t cpu_end_ns = threadCpuNs();
    FrameTiming t;
    t.haptic_us = std::chrono::duration<double, std::micro>(end - start).count();
    if (cpu_start_ns >= 0 && cpu_end_ns >= 0) t.haptic_cpu_us = 1e-3 * static_cast<double>(cpu_end_ns - cpu_start_ns);
    t.period_error_us = info.period_error_us;
    stats.record(t);
    if (info.frame + 1 >= frames) loop.requestStop();
  });
  while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  PlatformNoise out;
  out.realtime = loop.realtimeStatus();
  loop.stop();
  const LatencySummary s = stats.summary();
  out.work_us = s.haptic_us;
  out.work_cpu_us = s.haptic_cpu_us;
  out.frames = s.frames;
  out.threshold_us = threshold_us;
  out.frames_over_threshold = stats.framesOver(&FrameTiming::haptic_us, threshold_us);
  return out;
}

}  // namespace incise::sim
