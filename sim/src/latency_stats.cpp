#include "incise/sim/latency_stats.h"

#include <algorithm>
#include <array>

#include <nlohmann/json.hpp>

#include "incise/measure/percentile.h"

namespace incise::sim {

namespace {

constexpr std::size_t kQuantities = 6;

// The value of quantity q in a frame, or false when the frame has none (no CPU time read).
bool quantity(const FrameTiming& t, std::size_t q, double& value) noexcept {
  switch (q) {
    case 0:
      value = t.haptic_us;
      return true;
    case 1:
      value = t.cut_us;
      return true;
    case 2:
      value = t.frame_us;
      return true;
    case 3:
      value = t.period_error_us;
      return true;
    case 4:
      value = t.geometry_us;
      return true;
    default:
      value = t.haptic_cpu_us;
      return t.haptic_cpu_us >= 0.0;
  }
}

void putSummary(nlohmann::ordered_json& j, const char* name, const SampleSummary& s) {
  j[name] = {{"count", s.count}, {"p50", s.p50}, {"p99", s.p99}, {"p999", s.p999}, {"max", s.max}, {"mean", s.mean}};
}

// count, percentiles and mean of `values` (sorted here); max is the caller's (it covers unstored samples too).
void summarize(std::vector<double>& values, SampleSummary& s) {
  s.count = values.size();
  if (values.empty()) return;
  double sum = 0.0;
  for (const double v : values) sum += v;
  s.mean = sum / static_cast<double>(values.size());
  std::sort(values.begin(), values.end());
  s.p50 = measure::nearestRank(values, 1, 2);
  s.p99 = measure::nearestRank(values, 99, 100);
  s.p999 = measure::nearestRank(values, 999, 1000);
}

}  // namespace

LatencyStats::LatencyStats(std::size_t capacity_frames) : capacity_(capacity_frames) {
  samples_.reserve(capacity_);
  pose_to_visible_.reserve(capacity_);
  physics_us_.reserve(capacity_);
}

void LatencyStats::recordPhysicsStep(double us, bool late) noexcept {
  physics_max_us_ = physics_frames_ == 0 ? us : std::max(physics_max_us_, us);
  ++physics_frames_;
  if (late) ++physics_late_;
  if (physics_us_.size() < capacity_) physics_us_.push_back(us);
}

void LatencyStats::record(const FrameTiming& timing) noexcept {
  ++frames_;
  if (timing.deadline_missed) ++deadline_misses_;
  if (timing.deadline_missed && timing.overrun) ++(timing.preempted ? preempted_misses_ : overrun_misses_);
  for (std::size_t q = 0; q < kQuantities; ++q) {
    double value = 0.0;
    if (!quantity(timing, q, value)) continue;
    if (max_count_[q] == 0 || value > max_[q]) max_[q] = value;
    ++max_count_[q];
  }
  // Below the reserved capacity push_back cannot reallocate.
  if (samples_.size() < capacity_) samples_.push_back(timing);
}

void LatencyStats::recordPoseToVisible(int frames) noexcept {
  pose_to_visible_max_ = pose_to_visible_count_ == 0 ? frames : std::max(pose_to_visible_max_, frames);
  ++pose_to_visible_count_;
  if (pose_to_visible_.size() < capacity_) pose_to_visible_.push_back(frames);
}

void LatencyStats::clear() noexcept {
  samples_.clear();
  pose_to_visible_.clear();
  pose_to_visible_max_ = 0;
  pose_to_visible_count_ = 0;
  physics_us_.clear();
  physics_max_us_ = 0.0;
  physics_frames_ = physics_late_ = 0;
  frames_ = 0;
  deadline_misses_ = overrun_misses_ = preempted_misses_ = 0;
  for (std::size_t q = 0; q < kQuantities; ++q) {
    max_[q] = 0.0;
    max_count_[q] = 0;
  }
}

std::int64_t LatencyStats::framesOver(double FrameTiming::*field, double threshold) const noexcept {
  std::int64_t n = 0;
  for (const FrameTiming& t : samples_) n += t.*field > threshold ? 1 : 0;
  return n;
}

LatencySummary LatencyStats::summary() const {
  LatencySummary out;
  out.frames = frames_;
  out.frames_stored = static_cast<std::int64_t>(samples_.size());
  out.deadline_misses = deadline_misses_;
  out.overrun_misses = overrun_misses_;
  out.preempted_misses = preempted_misses_;
  out.late_wakeup_misses = deadline_misses_ - overrun_misses_ - preempted_misses_;
  const std::array<SampleSummary*, kQuantities> targets = {&out.haptic_us,       &out.cut_us,      &out.frame_us,
                                                           &out.period_error_us, &out.geometry_us, &out.haptic_cpu_us};
  std::vector<double> values;
  values.reserve(std::max(samples_.size(), pose_to_visible_.size()));
  for (std::size_t q = 0; q < kQuantities; ++q) {
    values.clear();
    for (const FrameTiming& t : samples_) {
      double value = 0.0;
      if (quantity(t, q, value)) values.push_back(value);
    }
    summarize(values, *targets[q]);
    targets[q]->max = max_[q];
  }
  values.assign(pose_to_visible_.begin(), pose_to_visible_.end());
  summarize(values, out.pose_to_visible_frames);
  out.pose_to_visible_frames.max = static_cast<double>(pose_to_visible_max_);
  values.assign(physics_us_.begin(), physics_us_.end());
  summarize(values, out.physics_step_us);
  out.physics_step_us.max = physics_max_us_;
  out.physics_frames = physics_frames_;
  out.physics_late = physics_late_;
  return out;
}

std::string toJson(const LatencySummary& summary, int indent) {
  nlohmann::ordered_json j;
  j["frames"] = summary.frames;
  j["frames_stored"] = summary.frames_stored;
  j["deadline_misses"] = summary.deadline_misses;
  j["overrun_misses"] = summary.overrun_misses;
  j["preempted_misses"] = summary.preempted_misses;
  j["late_wakeup_misses"] = summary.late_wakeup_misses;
  putSummary(j, "haptic_us", summary.haptic_us);
  putSummary(j, "cut_us", summary.cut_us);
  putSummary(j, "frame_us", summary.frame_us);
  putSummary(j, "period_error_us", summary.period_error_us);
  putSummary(j, "pose_to_visible_frames", summary.pose_to_visible_frames);
  putSummary(j, "geometry_us", summary.geometry_us);
  putSummary(j, "haptic_cpu_us", summary.haptic_cpu_us);
  if (summary.physics_frames > 0) {
    j["physics_frames"] = summary.physics_frames;
    j["physics_late"] = summary.physics_late;
    putSummary(j, "physics_step_us", summary.physics_step_us);
  }
  return j.dump(indent);
}

}  // namespace incise::sim
