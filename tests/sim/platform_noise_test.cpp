#include <incise/sim/platform_noise.h>

#include <catch2/catch.hpp>
#include <stdexcept>

using incise::sim::FixedRateLoopOptions;
using incise::sim::fixedWork;
using incise::sim::measurePlatformNoise;
using incise::sim::PlatformNoise;

TEST_CASE("platform_noise: the fixed work is the same chain every time, step by step", "[sim]") {
  double x = 1.0;
  for (int i = 0; i < 1000; ++i) x = x * 0.999999 + 1e-6;
  CHECK(fixedWork(1000) == x);  // the same operations in the same order: the same bits
  CHECK(fixedWork(1000) == fixedWork(1000));
  CHECK(fixedWork(1) == 0.999999 + 1e-6);
}

TEST_CASE("platform_noise: a short run times one fixed work per frame, on both clocks", "[sim]") {
  FixedRateLoopOptions loop;
  loop.period_us = 1000;
  const PlatformNoise n = measurePlatformNoise(loop, 0.2, 100.0);
  CHECK(n.frames == 200);
  CHECK(n.work_us.count == 200);
  CHECK(n.work_cpu_us.count == 200);
  CHECK(n.work_us.p50 > 0.0);
  CHECK(n.work_us.max >= n.work_us.p50);
  CHECK(n.threshold_us == 100.0);
  CHECK(n.frames_over_threshold >= 0);
  CHECK(n.frames_over_threshold <= 200);
  CHECK(n.realtime == incise::sim::RealtimeStatus::NotRequested);
}

TEST_CASE("platform_noise: a longer chain takes longer, so the work is really done", "[sim]") {
  FixedRateLoopOptions loop;
  loop.period_us = 1000;
  const PlatformNoise short_chain = measurePlatformNoise(loop, 0.1, 100.0, 100);
  const PlatformNoise long_chain = measurePlatformNoise(loop, 0.1, 100.0, 100'000);  // ~40 us or more
  CHECK(long_chain.work_us.p50 > 5.0 * short_chain.work_us.p50);
}

TEST_CASE("platform_noise: bad arguments throw", "[sim]") {
  const FixedRateLoopOptions loop;
  CHECK_THROWS_AS(measurePlatformNoise(loop, 0.0, 100.0), std::invalid_argument);
  CHECK_THROWS_AS(measurePlatformNoise(loop, 1.0, 100.0, 0), std::invalid_argument);
}
