#include "incise/sim/latency_stats.h"

#include <algorithm>
#include <array>

#include <nlohmann/json.hpp>

#include "incise/measure/percentile.h"

namespace incise::sim {

namespace {

constexpr std::size_t kQuantities = 7;

// The value of quantity q in a frame, or false when the frame has none (no new cut visible).
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
      value = static_cast<double>(t.pose_to_visible_frames);
      return t.pose_to_visible_frames >= 0;
    case 5:
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

}  // namespace

LatencyStats::LatencyStats(std::size_t capacity_frames) : capacity_(capacity_frames) { samples_.reserve(capacity_); }

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

void LatencyStats::clear() noexcept {
  samples_.clear();
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
  const std::array<SampleSummary*, kQuantities> targets = {
      &out.haptic_us,   &out.cut_us,       &out.frame_us, &out.period_error_us, &out.pose_to_visible_frames,
      &out.geometry_us, &out.haptic_cpu_us};
  std::vector<double> values;
  values.reserve(samples_.size());
  for (std::size_t q = 0; q < kQuantities; ++q) {
    values.clear();
    double sum = 0.0;
    for (const FrameTiming& t : samples_) {
      double value = 0.0;
      if (!quantity(t, q, value)) continue;
      values.push_back(value);
      sum += value;
    }
    SampleSummary& s = *targets[q];
    s.max = max_[q];
    s.count = values.size();
    if (values.empty()) continue;
    std::sort(values.begin(), values.end());
    s.p50 = measure::nearestRank(values, 1, 2);
    s.p99 = measure::nearestRank(values, 99, 100);
    s.p999 = measure::nearestRank(values, 999, 1000);
    s.mean = sum / static_cast<double>(values.size());
  }
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
  return j.dump(indent);
}

}  // namespace incise::sim
