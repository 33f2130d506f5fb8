#include <incise/sim/latency_stats.h>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

using incise::sim::FrameTiming;
using incise::sim::LatencyStats;
using incise::sim::LatencySummary;
using incise::sim::SampleSummary;

namespace {

FrameTiming uniform(double value, bool missed = false) {
  FrameTiming t;
  t.haptic_us = value;
  t.cut_us = value;
  t.frame_us = value;
  t.period_error_us = value;
  t.geometry_us = value;
  t.haptic_cpu_us = value;
  t.deadline_missed = missed;
  return t;
}

// A frame of `value` in every quantity, and a cut that became visible `value` frames after its pose.
void recordUniform(LatencyStats& stats, double value, bool missed = false) {
  stats.record(uniform(value, missed));
  stats.recordPoseToVisible(static_cast<int>(value));
}

}  // namespace

TEST_CASE("latency_stats: nearest-rank percentiles of 1..1000 are 500, 990, 999 and the max 1000", "[sim]") {
  LatencyStats stats(1000);
  for (int i = 1000; i >= 1; --i) recordUniform(stats, i);  // any order: the summary sorts
  const LatencySummary s = stats.summary();
  CHECK(s.frames == 1000);
  CHECK(s.frames_stored == 1000);
  CHECK(s.deadline_misses == 0);
  for (const SampleSummary* q : {&s.haptic_us, &s.cut_us, &s.frame_us, &s.period_error_us, &s.pose_to_visible_frames}) {
    CHECK(q->count == 1000);
    CHECK(q->p50 == 500.0);
    CHECK(q->p99 == 990.0);
    CHECK(q->p999 == 999.0);
    CHECK(q->max == 1000.0);
    CHECK(q->mean == Approx(500.5));
  }
}

TEST_CASE("latency_stats: percentiles of a few samples take the nearest rank, never interpolate", "[sim]") {
  LatencyStats stats(16);
  for (double v : {10.0, 20.0, 30.0}) stats.record(uniform(v));
  const SampleSummary s = stats.summary().frame_us;
  CHECK(s.p50 == 20.0);  // ceil(1.5) = 2nd
  CHECK(s.p99 == 30.0);  // ceil(2.97) = 3rd
  CHECK(s.p999 == 30.0);
  CHECK(s.mean == Approx(20.0));
}

TEST_CASE("latency_stats: deadline misses are counted and pose-to-visible has one sample per cut made visible",
          "[sim]") {
  LatencyStats stats(100);
  for (int i = 0; i < 10; ++i) {
    stats.record(uniform(100.0, /*missed=*/i % 4 == 0));                     // frames 0, 4, 8 miss
    if (i == 2) stats.recordPoseToVisible(1), stats.recordPoseToVisible(3);  // two cuts visible in frame 2
    if (i == 5) stats.recordPoseToVisible(2);
  }
  const LatencySummary s = stats.summary();
  CHECK(s.frames == 10);
  CHECK(s.deadline_misses == 3);
  CHECK(stats.deadlineMisses() == 3);
  CHECK(s.frame_us.count == 10);
  CHECK(s.pose_to_visible_frames.count == 3);  // the cuts, not the frames
  CHECK(s.pose_to_visible_frames.max == 3.0);
  CHECK(s.pose_to_visible_frames.p50 == 2.0);
  CHECK(s.pose_to_visible_frames.mean == Approx(2.0));
}

TEST_CASE("latency_stats: once full it stops storing but keeps counting frames, misses and maxima", "[sim]") {
  LatencyStats stats(10);
  CHECK(stats.capacity() == 10);
  for (int i = 1; i <= 20; ++i) recordUniform(stats, i, /*missed=*/i > 15);
  const LatencySummary s = stats.summary();
  CHECK(s.frames == 20);
  CHECK(s.frames_stored == 10);
  CHECK(s.deadline_misses == 5);  // all after the capacity was reached
  CHECK(s.frame_us.count == 10);  // percentiles and mean: the first 10 frames
  CHECK(s.frame_us.p50 == 5.0);
  CHECK(s.frame_us.p99 == 10.0);
  CHECK(s.frame_us.mean == Approx(5.5));
  CHECK(s.frame_us.max == 20.0);                // max: every frame
  CHECK(s.pose_to_visible_frames.count == 10);  // the same for the pose-to-visible samples
  CHECK(s.pose_to_visible_frames.p99 == 10.0);
  CHECK(s.pose_to_visible_frames.max == 20.0);

  SECTION("clear() starts over with the same capacity") {
    stats.clear();
    recordUniform(stats, 3.0);
    const LatencySummary t = stats.summary();
    CHECK(t.frames == 1);
    CHECK(t.frames_stored == 1);
    CHECK(t.deadline_misses == 0);
    CHECK(t.frame_us.max == 3.0);
    CHECK(t.frame_us.p50 == 3.0);
    CHECK(t.pose_to_visible_frames.count == 1);
    CHECK(t.pose_to_visible_frames.max == 3.0);
  }
}

TEST_CASE("latency_stats: the summary of no frames is all zeros", "[sim]") {
  const LatencySummary s = LatencyStats(0).summary();
  CHECK(s.frames == 0);
  CHECK(s.deadline_misses == 0);
  CHECK(s.frame_us.count == 0);
  CHECK(s.frame_us.p99 == 0.0);
  CHECK(s.frame_us.max == 0.0);
}

TEST_CASE("latency_stats: a miss is an overrun (the frame's own cost) or a late wake-up", "[sim]") {
  // A VM's late wake-ups are told apart from frames that took longer than the period.
  LatencyStats stats(100);
  for (int i = 0; i < 10; ++i) {
    FrameTiming t = uniform(100.0, /*missed=*/i % 2 == 0);  // frames 0, 2, 4, 6, 8 miss
    t.overrun = i % 4 == 0;                                 // 0, 4, 8 of them by their own time
    stats.record(t);
  }
  const LatencySummary s = stats.summary();
  CHECK(s.deadline_misses == 5);
  CHECK(s.overrun_misses == 3);
  CHECK(stats.overrunMisses() == 3);
  CHECK(s.late_wakeup_misses == 2);
  const nlohmann::json j = nlohmann::json::parse(incise::sim::toJson(s));
  CHECK(j.at("overrun_misses") == 3);
  CHECK(j.at("late_wakeup_misses") == 2);
  stats.clear();
  CHECK(stats.summary().overrun_misses == 0);
}

TEST_CASE("latency_stats: an overrun the thread spent descheduled is a preemption, not our cost", "[sim]") {
  LatencyStats stats(100);
  for (int i = 0; i < 6; ++i) {
    FrameTiming t = uniform(100.0, /*missed=*/true);
    t.overrun = i < 4;
    t.preempted = i < 3;  // 3 preempted overruns, 1 of our own, 2 late wake-ups
    stats.record(t);
  }
  const LatencySummary s = stats.summary();
  CHECK(s.deadline_misses == 6);
  CHECK(s.overrun_misses == 1);
  CHECK(s.preempted_misses == 3);
  CHECK(s.late_wakeup_misses == 2);
  CHECK(nlohmann::json::parse(incise::sim::toJson(s)).at("preempted_misses") == 3);
}

TEST_CASE("latency_stats: negative samples keep their own maximum", "[sim]") {
  LatencyStats stats(4);
  stats.record(uniform(-5.0));
  stats.record(uniform(-2.0));
  CHECK(stats.summary().period_error_us.max == -2.0);
}

TEST_CASE("latency_stats: the haptic part's CPU time counts only the frames that read it", "[sim]") {
  LatencyStats stats(8);
  FrameTiming read = uniform(30.0);
  read.haptic_cpu_us = 12.0;
  stats.record(read);
  stats.record(uniform(40.0));  // 40 everywhere, the CPU time too
  FrameTiming unread = uniform(50.0);
  unread.haptic_cpu_us = -1.0;  // a fast replay: no clock read
  stats.record(unread);
  const LatencySummary s = stats.summary();
  CHECK(s.haptic_us.count == 3);
  CHECK(s.haptic_us.max == 50.0);
  CHECK(s.haptic_cpu_us.count == 2);
  CHECK(s.haptic_cpu_us.max == 40.0);
  CHECK(s.haptic_cpu_us.p50 == 12.0);
}

TEST_CASE("latency_stats: framesOver counts the stored frames over a threshold in one field", "[sim]") {
  LatencyStats stats(100);
  for (int i = 1; i <= 100; ++i) {
    FrameTiming t = uniform(i);
    t.cut_us = 101.0 - i;
    stats.record(t);
  }
  CHECK(stats.framesOver(&FrameTiming::haptic_us, 90.0) == 10);  // 91..100
  CHECK(stats.framesOver(&FrameTiming::haptic_us, 100.0) == 0);  // strictly over
  CHECK(stats.framesOver(&FrameTiming::cut_us, 95.0) == 5);      // 96..100, from the other end
  CHECK(stats.framesOver(&FrameTiming::frame_us, 0.0) == 100);
}

TEST_CASE("latency_stats: toJson writes the counters and every quantity's statistics", "[sim]") {
  LatencyStats stats(1000);
  for (int i = 1; i <= 1000; ++i) recordUniform(stats, i, i == 1000);
  const nlohmann::json j = nlohmann::json::parse(incise::sim::toJson(stats.summary()));
  CHECK(j.at("frames") == 1000);
  CHECK(j.at("frames_stored") == 1000);
  CHECK(j.at("deadline_misses") == 1);
  for (const char* name : {"haptic_us", "cut_us", "frame_us", "period_error_us", "pose_to_visible_frames",
                           "geometry_us", "haptic_cpu_us"}) {
    INFO(name);
    const nlohmann::json& q = j.at(name);
    CHECK(q.at("count") == 1000);
    CHECK(q.at("p50").get<double>() == 500.0);
    CHECK(q.at("p99").get<double>() == 990.0);
    CHECK(q.at("p999").get<double>() == 999.0);
    CHECK(q.at("max").get<double>() == 1000.0);
    CHECK(q.at("mean").get<double>() == Approx(500.5));
  }
  CHECK(incise::sim::toJson(stats.summary(), -1).find('\n') == std::string::npos);
}
