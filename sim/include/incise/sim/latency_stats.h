// Per-frame latency statistics: the sim thread records one FrameTiming per frame, and one pose-to-visible
// latency per cut that became visible (recordPoseToVisible: each once, in the frame it became visible); the
// benchmark, the CLI and the viewer HUD read the same summary (p50 / p99 / p99.9 / max / mean and deadline
// misses).
//
// Units: microseconds for times (the _us fields), frames for pose_to_visible_frames.
// Storage: a fixed capacity of frames (and as many pose-to-visible samples), reserved in the constructor;
// neither record call allocates. When the capacity is reached they keep counting frames and deadline misses
// and keep the per-quantity maxima and stop storing samples: count, percentiles and mean then describe the
// first `capacity` samples, while `max`, `frames` and `deadline_misses` cover every recorded one
// (`frames_stored` < `frames` says so).
// Threads: not synchronised. One thread records (the sim thread); summary() is called by the same thread or
// after the recording thread has been joined (a FixedRateLoop stopped).
// Cost: record() O(1), noexcept; summary() O(n log n) on sorted copies, allocates (not for the sim thread).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace incise::sim {

// What one sim frame cost.
struct FrameTiming {
  double haptic_us = 0.0;
  double cut_us = 0.0;
  double frame_us = 0.0;
  double period_error_us = 0.0;  // how late the frame started vs its deadline
  double geometry_us = 0.0;      // the geometry stream's publish (0 without a stream)
  // The haptic part's CPU time on the sim thread (CLOCK_THREAD_CPUTIME_ID: it leaves out time the thread was
  // descheduled and the steal a VM reports, but counts interrupts taken inside it when the kernel has no
  // CONFIG_IRQ_TIME_ACCOUNTING). haptic_us is the wall time a device sees. -1 when not read (no clock).
  double haptic_cpu_us = -1.0;
  bool deadline_missed = false;  // period_error_us + frame_us over the period: the next deadline was missed
  bool overrun = false;          // frame_us alone over the period: not a late wake-up
  // An overrun whose sim thread ran for at most the period (its CPU time in the frame, CLOCK_THREAD_CPUTIME_ID,
  // read against the clock only): it was descheduled within the frame (the VM or another process took the
  // CPU), so the wall time over the period was not our cost.
  bool preempted = false;
};

// One quantity. count, p50, p99, p999 (nearest-rank on the stored samples: the smallest sample with at
// least p % of the samples <= it) and mean: stored samples, 0 when count = 0. max: every recorded sample,
// 0 when there was none.
struct SampleSummary {
  std::size_t count = 0;
  double p50 = 0.0;
  double p99 = 0.0;
  double p999 = 0.0;
  double max = 0.0;
  double mean = 0.0;
};

struct LatencySummary {
  SampleSummary haptic_us;
  SampleSummary cut_us;
  SampleSummary frame_us;
  SampleSummary period_error_us;
  SampleSummary pose_to_visible_frames;  // one sample per recordPoseToVisible call
  SampleSummary geometry_us;
  SampleSummary haptic_cpu_us;       // frames with haptic_cpu_us >= 0 only
  std::int64_t frames = 0;           // every record() call
  std::int64_t frames_stored = 0;    // min(frames, capacity)
  std::int64_t deadline_misses = 0;  // every recorded frame with deadline_missed
  // ... of which the frame itself took longer than the period running (our cost), took longer only because
  // the thread was descheduled within it (FrameTiming::preempted), or missed only because it started late
  // (the VM or the scheduler woke the loop late: period_error_us).
  std::int64_t overrun_misses = 0;
  std::int64_t preempted_misses = 0;
  std::int64_t late_wakeup_misses = 0;
  // A simulated tissue's physics (recordPhysicsStep: one sample per step on its own thread, or per frame
  // that stepped it inline): the step's time, the samples, and those late (threaded: finished more than a
  // physics period after they were due; inline: the frame's physics alone took longer than its period).
  SampleSummary physics_step_us;
  std::int64_t physics_frames = 0;
  std::int64_t physics_late = 0;
};

class LatencyStats {
 public:
  static constexpr std::size_t kDefaultCapacity = 120'000;  // two minutes at 1 kHz, ~5 MB

  // Reserves room for `capacity_frames` samples (may throw std::bad_alloc; 0 is allowed: maxima and counts
  // only).
  explicit LatencyStats(std::size_t capacity_frames = kDefaultCapacity);

  // Sim thread. O(1), never allocates; see the header comment for what happens once full.
  void record(const FrameTiming& timing) noexcept;
  // Sim thread: a cut became visible `frames` frames after the frame its pose arrived in (>= 0; simulation.h
  // says which pose). Once per cut, in the frame it became visible. O(1), never allocates.
  void recordPoseToVisible(int frames) noexcept;
  // Sim thread (or its owner after the physics thread ended): the tissue's physics stepped for `us`, late or
  // not (LatencySummary). O(1), never allocates (samples past the capacity are counted, not stored).
  void recordPhysicsStep(double us, bool late) noexcept;

  // Forgets every frame; keeps the reserved capacity. No allocation.
  void clear() noexcept;

  // Percentiles of the stored samples, counters over all frames. Allocates; not for the sim thread.
  LatencySummary summary() const;

  // Stored frames whose `field` (e.g. &FrameTiming::haptic_us) is over `threshold`. O(n); not for the sim
  // thread's frames (it reads every sample).
  std::int64_t framesOver(double FrameTiming::*field, double threshold) const noexcept;

  std::size_t capacity() const noexcept { return capacity_; }
  std::int64_t frames() const noexcept { return frames_; }
  std::int64_t deadlineMisses() const noexcept { return deadline_misses_; }
  std::int64_t overrunMisses() const noexcept { return overrun_misses_; }
  std::int64_t preemptedMisses() const noexcept { return preempted_misses_; }

 private:
  std::size_t capacity_;
  std::vector<FrameTiming> samples_;  // reserved to capacity_, never grown past it
  std::vector<int> pose_to_visible_;  // the same
  std::vector<double> physics_us_;    // the same
  double physics_max_us_ = 0.0;
  std::int64_t physics_frames_ = 0, physics_late_ = 0;
  int pose_to_visible_max_ = 0;
  std::int64_t pose_to_visible_count_ = 0;
  std::int64_t frames_ = 0;
  std::int64_t deadline_misses_ = 0, overrun_misses_ = 0, preempted_misses_ = 0;
  // Running maxima over every frame, in the order haptic, cut, frame, period error, geometry, haptic CPU.
  std::array<double, 6> max_{};
  std::array<std::int64_t, 6> max_count_{};
};

// {"frames", "frames_stored", "deadline_misses", "overrun_misses", "preempted_misses", "late_wakeup_misses",
// then per quantity {"count", "p50", "p99", "p999", "max", "mean"} under "haptic_us", "cut_us", "frame_us",
// "period_error_us", "pose_to_visible_frames", "geometry_us", "haptic_cpu_us"}, keys in that order, and with
// a simulated tissue (physics_frames > 0) "physics_frames", "physics_late" and "physics_step_us" last;
// indented by `indent` spaces (-1: one line).
std::string toJson(const LatencySummary& summary, int indent = 2);

}  // namespace incise::sim
