#include <incise/sim/fixed_rate_loop.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using incise::sim::FixedRateLoop;
using incise::sim::FixedRateLoopOptions;
using incise::sim::FrameInfo;
using incise::sim::LoopCounters;
using incise::sim::RealtimeStatus;
using Clock = std::chrono::steady_clock;

// Wall-clock tests assert generous bounds: the test machine may be loaded (2 cores, other builds running).

namespace {

// Waits (sleeping) until the loop has ended by itself, at most `timeout`. True when it ended.
bool waitForEnd(const FixedRateLoop& loop, std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
  const auto give_up = Clock::now() + timeout;
  while (loop.running()) {
    if (Clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// What a step saw, preallocated: the step itself must not allocate.
struct Trace {
  explicit Trace(std::size_t frames) : infos(frames), starts(frames) {}
  void note(const FrameInfo& info) {
    const auto i = static_cast<std::size_t>(info.frame);
    if (i < infos.size()) {
      infos[i] = info;
      starts[i] = Clock::now();
    }
  }
  std::vector<FrameInfo> infos;
  std::vector<Clock::time_point> starts;
};

}  // namespace

TEST_CASE("fixed_rate_loop: 200 frames at 1 ms keep a 1 ms mean period and do not drift", "[sim]") {
  constexpr std::int64_t kFrames = 200;
  FixedRateLoop loop({.period_us = 1000});
  Trace trace(kFrames);
  loop.start([&](const FrameInfo& info) {
    trace.note(info);
    if (info.frame == kFrames - 1) loop.requestStop();
  });
  REQUIRE(waitForEnd(loop));
  loop.stop();
  const LoopCounters c = loop.counters();
  REQUIRE(c.frames == kFrames);
  INFO("overruns " << c.overruns << ", skipped deadlines " << c.skipped_deadlines << ", max start error "
                   << c.max_period_error_us << " us");

  // The mean period between deadlines. A stall of the whole machine (a loaded 2-core test box) makes the
  // loop skip deadlines rather than run late ones: those periods are counted, and without a stall
  // (skipped_deadlines = 0) this is plainly the mean time between frames.
  const double elapsed_ms = ms(trace.starts[kFrames - 1] - trace.starts[0]);
  const double mean_period_ms = elapsed_ms / static_cast<double>(kFrames - 1 + c.skipped_deadlines);
  INFO("mean period " << mean_period_ms << " ms");
  CHECK(mean_period_ms == Approx(1.0).epsilon(0.10));

  // No drift: deadlines are absolute, so late frames are not followed by later ones. Frame k runs at deadline
  // k + (skipped so far) at the earliest: starts[k] - starts[0] >= k ms - (frame 0's own small lateness).
  CHECK(elapsed_ms > (kFrames - 1) - 0.5);
  // And at least one of the last 10 frames started within 1 ms of its deadline, by the loop's measurement
  // and by ours (a loop that slept "1 ms after the previous frame" would be ~200 * overhead late by now).
  double best_error_us = 1e9;
  double best_wall_excess_ms = 1e9;
  for (std::int64_t k = kFrames - 10; k < kFrames; ++k) {
    best_error_us = std::min(best_error_us, trace.infos[k].period_error_us);
    const double deadline_ms = static_cast<double>(k + c.skipped_deadlines);  // an upper bound on frame k's deadline
    best_wall_excess_ms = std::min(best_wall_excess_ms, ms(trace.starts[k] - trace.starts[0]) - deadline_ms);
  }
  CHECK(best_error_us < 1000.0);
  CHECK(best_wall_excess_ms < 1.0);
}

TEST_CASE("fixed_rate_loop: every frame gets dt = the period exactly and t = frame * dt", "[sim]") {
  constexpr std::int64_t kFrames = 50;
  FixedRateLoop loop({.period_us = 2000});
  Trace trace(kFrames);
  loop.start([&](const FrameInfo& info) {
    trace.note(info);
    if (info.frame == kFrames - 1) loop.requestStop();
  });
  REQUIRE(waitForEnd(loop));
  loop.stop();
  REQUIRE(loop.counters().frames == kFrames);
  CHECK(loop.dtSeconds() == 0.002);
  for (std::int64_t k = 0; k < kFrames; ++k) {
    INFO("frame " << k);
    CHECK(trace.infos[k].frame == k);
    CHECK(trace.infos[k].dt_s == 0.002);
    CHECK(trace.infos[k].t_s == static_cast<double>(k) * 0.002);
    CHECK(trace.infos[k].period_error_us >= 0.0);
  }
}

TEST_CASE("fixed_rate_loop: a slow frame is an overrun and its missed deadlines are skipped, not stretched", "[sim]") {
  constexpr std::int64_t kFrames = 200;
  FixedRateLoop loop({.period_us = 1000});  // max_catch_up_frames = 0: skip
  Trace trace(kFrames);
  std::atomic<int> slow_frames{0};
  loop.start([&](const FrameInfo& info) {
    trace.note(info);
    if (info.frame % 50 == 25) {  // frames 25, 75, 125, 175
      slow_frames.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
    }
    if (info.frame == kFrames - 1) loop.requestStop();
  });
  REQUIRE(waitForEnd(loop));
  loop.stop();
  const LoopCounters c = loop.counters();
  INFO("overruns " << c.overruns << ", skipped deadlines " << c.skipped_deadlines);
  REQUIRE(c.frames == kFrames);
  REQUIRE(slow_frames.load() == 4);
  CHECK(c.overruns >= 4);
  // Each slow frame ends >= 3 ms after its own deadline: the next three deadlines passed and are skipped.
  CHECK(c.skipped_deadlines >= 4 * 3);
  CHECK(c.max_period_error_us >= 0.0);

  double best_after_slow_us = 1e9;
  for (std::int64_t k = 0; k < kFrames; ++k) {
    CHECK(trace.infos[k].dt_s == 0.001);  // never stretched
    CHECK(trace.infos[k].t_s == static_cast<double>(k) * 0.001);
    if (k % 50 == 26) {
      // The frame after a slow one waits for the next future deadline instead of running at once.
      CHECK(ms(trace.starts[k] - trace.starts[k - 1]) >= 3.0);
      best_after_slow_us = std::min(best_after_slow_us, trace.infos[k].period_error_us);
    }
  }
  // Realigned: started on a deadline, not 2-3 ms after one as a catch-up frame would.
  CHECK(best_after_slow_us < 1000.0);
}

TEST_CASE("fixed_rate_loop: with max_catch_up_frames the missed deadlines run late, back to back", "[sim]") {
  constexpr std::int64_t kFrames = 60;
  FixedRateLoop loop({.period_us = 1000, .max_catch_up_frames = 10});
  Trace trace(kFrames);
  loop.start([&](const FrameInfo& info) {
    trace.note(info);
    if (info.frame == 25) std::this_thread::sleep_for(std::chrono::milliseconds(3));
    if (info.frame == kFrames - 1) loop.requestStop();
  });
  REQUIRE(waitForEnd(loop));
  loop.stop();
  const LoopCounters c = loop.counters();
  INFO("overruns " << c.overruns << ", skipped deadlines " << c.skipped_deadlines);
  REQUIRE(c.frames == kFrames);
  CHECK(c.overruns >= 1);
  // Frame 26 runs for deadline 26 although it already passed >= 2 ms ago: it is late, not skipped.
  CHECK(trace.infos[26].period_error_us >= 1500.0);
  CHECK(trace.infos[26].dt_s == 0.001);
  // Only a stall longer than 10 periods skips anything: the frame after one runs 9-10 periods late (the
  // 10th deadline back). A busy machine may stall the thread that long; without such a frame none is skipped.
  double latest_us = 0.0;
  for (const FrameInfo& info : trace.infos) latest_us = std::max(latest_us, info.period_error_us);
  if (latest_us < 9000.0) CHECK(c.skipped_deadlines == 0);
  if (c.skipped_deadlines > 0) CHECK(latest_us >= 9000.0);
}

TEST_CASE("fixed_rate_loop: runFast calls the step N times with the period's dt and never sleeps", "[sim]") {
  constexpr std::int64_t kFrames = 1000;
  FixedRateLoop loop({.period_us = 1000});
  Trace trace(kFrames);
  std::int64_t calls = 0;
  const auto begin = Clock::now();
  const std::int64_t run = loop.runFast(
      [&](const FrameInfo& info) {
        trace.note(info);
        ++calls;
      },
      kFrames);
  const double elapsed_ms = ms(Clock::now() - begin);
  CHECK(run == kFrames);
  CHECK(calls == kFrames);
  CHECK(loop.counters().frames == kFrames);
  CHECK(loop.counters().overruns == 0);
  CHECK(elapsed_ms < 250.0);  // real time would take 1000 ms
  for (std::int64_t k = 0; k < kFrames; ++k) {
    CHECK(trace.infos[k].frame == k);
    CHECK(trace.infos[k].dt_s == 0.001);
    CHECK(trace.infos[k].t_s == static_cast<double>(k) * 0.001);
    CHECK(trace.infos[k].period_error_us == 0.0);
  }

  SECTION("requestStop from the step ends it early") {
    const std::int64_t early = loop.runFast(
        [&](const FrameInfo& info) {
          if (info.frame == 9) loop.requestStop();
        },
        kFrames);
    CHECK(early == 10);
    CHECK(loop.counters().frames == 10);
  }
}

TEST_CASE("fixed_rate_loop: runFast and start give the step the same frame sequence", "[sim]") {
  constexpr std::int64_t kFrames = 30;
  FixedRateLoop loop({.period_us = 500});
  Trace fast(kFrames);
  Trace real(kFrames);
  loop.runFast([&](const FrameInfo& info) { fast.note(info); }, kFrames);
  loop.start([&](const FrameInfo& info) {
    real.note(info);
    if (info.frame == kFrames - 1) loop.requestStop();
  });
  REQUIRE(waitForEnd(loop));
  loop.stop();
  for (std::int64_t k = 0; k < kFrames; ++k) {
    CHECK(fast.infos[k].frame == real.infos[k].frame);
    CHECK(fast.infos[k].dt_s == real.infos[k].dt_s);
    CHECK(fast.infos[k].t_s == real.infos[k].t_s);
  }
}

TEST_CASE("fixed_rate_loop: stop() is idempotent, restartable, and the destructor stops a running loop", "[sim]") {
  std::atomic<std::int64_t> calls{0};
  {
    FixedRateLoop loop;
    loop.stop();  // never started: nothing to do
    CHECK_FALSE(loop.running());
    loop.start([&](const FrameInfo&) { calls.fetch_add(1); });
    CHECK(loop.running());
    while (loop.counters().frames < 5) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    loop.stop();
    CHECK_FALSE(loop.running());
    const std::int64_t after_stop = calls.load();
    loop.stop();
    loop.stop();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    CHECK(calls.load() == after_stop);  // no frame after stop()
    CHECK(loop.counters().frames == after_stop);

    loop.start([&](const FrameInfo&) { calls.fetch_add(1); });  // again, counters reset
    while (loop.counters().frames < 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    CHECK(loop.running());
    // Destroyed while running.
  }
  CHECK(calls.load() >= 8);
}

TEST_CASE("fixed_rate_loop: stop() called inside the step ends the loop without deadlock", "[sim]") {
  FixedRateLoop loop;
  loop.start([&](const FrameInfo& info) {
    if (info.frame == 3) loop.stop();
  });
  REQUIRE(waitForEnd(loop));
  loop.stop();
  CHECK(loop.counters().frames == 4);
}

TEST_CASE("fixed_rate_loop: bad options and misuse throw", "[sim]") {
  CHECK_THROWS_AS(FixedRateLoop({.period_us = 0}), std::invalid_argument);
  CHECK_THROWS_AS(FixedRateLoop({.period_us = 1000, .spin_us = 1001}), std::invalid_argument);
  CHECK_THROWS_AS(FixedRateLoop({.period_us = 1000, .spin_us = -1}), std::invalid_argument);
  CHECK_THROWS_AS(FixedRateLoop({.max_catch_up_frames = -1}), std::invalid_argument);

  FixedRateLoop loop;
  CHECK_THROWS_AS(loop.start(nullptr), std::invalid_argument);
  CHECK_THROWS_AS(loop.runFast(nullptr, 10), std::invalid_argument);
  CHECK_THROWS_AS(loop.runFast([](const FrameInfo&) {}, -1), std::invalid_argument);
  loop.start([](const FrameInfo&) {});
  CHECK_THROWS_AS(loop.start([](const FrameInfo&) {}), std::logic_error);
  CHECK_THROWS_AS(loop.runFast([](const FrameInfo&) {}, 10), std::logic_error);
  loop.stop();
}

TEST_CASE("fixed_rate_loop: an exception from the step ends the loop and stop() rethrows it", "[sim]") {
  FixedRateLoop loop;
  loop.start([](const FrameInfo& info) {
    if (info.frame == 2) throw std::runtime_error("step failed");
  });
  REQUIRE(waitForEnd(loop));
  CHECK(loop.counters().frames == 2);
  CHECK_THROWS_WITH(loop.stop(), "step failed");
  CHECK_NOTHROW(loop.stop());  // reported once
}

TEST_CASE("fixed_rate_loop: spinning before the deadline keeps the same deadlines", "[sim]") {
  constexpr std::int64_t kFrames = 50;
  FixedRateLoop loop({.period_us = 1000, .spin_us = 50});
  Trace trace(kFrames);
  loop.start([&](const FrameInfo& info) {
    trace.note(info);
    if (info.frame == kFrames - 1) loop.requestStop();
  });
  REQUIRE(waitForEnd(loop));
  loop.stop();
  const LoopCounters c = loop.counters();
  REQUIRE(c.frames == kFrames);
  // Per deadline, as in the 200-frame case: skipped deadlines (a stalled machine) are periods too.
  const double mean_period_ms =
      ms(trace.starts[kFrames - 1] - trace.starts[0]) / static_cast<double>(kFrames - 1 + c.skipped_deadlines);
  CHECK(mean_period_ms == Approx(1.0).epsilon(0.10));
  for (const FrameInfo& info : trace.infos) CHECK(info.period_error_us >= 0.0);  // never early
}

TEST_CASE("fixed_rate_loop: realtime priority is granted or reported as denied, and the loop runs either way",
          "[sim]") {
  FixedRateLoop plain;
  CHECK(plain.realtimeStatus() == RealtimeStatus::NotRequested);

  FixedRateLoop loop({.period_us = 1000, .realtime_priority = true});
  loop.start([](const FrameInfo&) {});
  const RealtimeStatus status = loop.realtimeStatus();  // known once start() returns
  CHECK(status != RealtimeStatus::NotRequested);
  if (status == RealtimeStatus::Denied)
    CHECK(loop.realtimeError() != 0);
  else
    CHECK(loop.realtimeError() == 0);
  while (loop.counters().frames < 5) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  loop.stop();
  CHECK(loop.counters().frames >= 5);
}
