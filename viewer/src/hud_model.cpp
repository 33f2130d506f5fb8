#include "incise/viewer/hud_model.h"

#include <algorithm>
#include <cmath>

#include "incise/measure/percentile.h"

namespace incise::viewer {

namespace {

Percentiles percentiles(std::vector<double> values) {
  Percentiles p;
  if (values.empty()) return p;
  std::sort(values.begin(), values.end());
  p.p50 = measure::nearestRank(values, 1, 2), p.p99 = measure::nearestRank(values, 99, 100), p.max = values.back();
  return p;
}

}  // namespace

PoseSourceStatus ReplaySourceStatus::status(const sim::Snapshot& newest) const {
  const char* state = paused_ ? "paused" : newest.t_s <= last_pose_s_ ? "playing" : "finished";
  return {description_, state};
}

HudModel::HudModel(double period_us, double cut_budget_us, double window_s)
    : window_frames_(static_cast<std::size_t>(std::max(1.0, window_s * 1e6 / period_us))),
      period_us_(period_us),
      cut_budget_us_(cut_budget_us) {}

void HudModel::add(const sim::Snapshot& s) { newest_ = s; }

void HudModel::add(const sim::FrameTimes& t) {
  if (t.frame < next_frame_) {  // a new run (restart): start over
    frames_.clear();
    next_frame_ = 0;
    unseen_ = 0;
  }
  unseen_ += t.frame - next_frame_;  // frames the queue dropped
  next_frame_ = t.frame + 1;
  frames_.push_back(t);
  if (frames_.size() > window_frames_) frames_.pop_front();
}

void HudModel::displayed(std::int64_t shown_frame_start_ns, std::int64_t shown_ns) {
  const double window_ns = 1e3 * period_us_ * static_cast<double>(window_frames_);
  display_ns_.push_back(shown_ns);
  while (static_cast<double>(shown_ns - display_ns_.front()) > window_ns) display_ns_.pop_front();
  if (shown_frame_start_ns <= last_shown_frame_start_ns_) return;  // none yet, or shown before
  last_shown_frame_start_ns_ = shown_frame_start_ns;
  const double latency_ms = 1e-6 * static_cast<double>(shown_ns - shown_frame_start_ns);
  shown_.push_back({shown_frame_start_ns, latency_ms});
  run_latency_ms_.push_back(latency_ms);
  while (static_cast<double>(shown_frame_start_ns - shown_.front().frame_start_ns) > window_ns) shown_.pop_front();
}

HudFigures HudModel::figures() const {
  HudFigures h;
  std::vector<double> frame, haptic, cut, geometry;
  for (const sim::FrameTimes& f : frames_) {
    frame.push_back(f.frame_us), haptic.push_back(f.haptic_us), cut.push_back(f.cut_us);
    geometry.push_back(f.geometry_us);
    h.window_misses += f.deadline_missed;
    h.pose_to_visible_frames_max = std::max<int>(h.pose_to_visible_frames_max, f.pose_to_visible_frames);
  }
  h.frames = static_cast<std::int64_t>(frames_.size());
  h.frame_us = percentiles(std::move(frame));
  h.haptic_us = percentiles(std::move(haptic));
  h.cut_us = percentiles(std::move(cut));
  h.geometry_us = percentiles(std::move(geometry));
  h.frames_unseen = unseen_;
  h.deadline_misses = newest_.deadline_misses;
  h.period_used = h.frame_us.p99 / period_us_;
  h.cut_budget_used = h.cut_us.p99 / cut_budget_us_;
  h.force_N = newest_.haptic.force_N.norm();
  h.incisions = newest_.incisions;
  h.physics_steps_due = newest_.physics_steps_due;
  h.physics_steps_done = newest_.physics_steps_done;
  h.physics_late = newest_.physics_late;
  std::vector<double> latency;
  for (const Shown& s : shown_) latency.push_back(s.latency_ms);
  const Percentiles l = percentiles(std::move(latency)), run = percentiles(run_latency_ms_);
  h.screen_latency_ms_p50 = l.p50, h.screen_latency_ms_max = l.max;
  h.run_screen_latency_ms_p50 = run.p50, h.run_screen_latency_ms_max = run.max;
  h.snapshots_shown = static_cast<std::int64_t>(run_latency_ms_.size());
  if (display_ns_.size() >= 2) {
    const double span_s = 1e-9 * static_cast<double>(display_ns_.back() - display_ns_.front());
    h.display_fps = span_s > 0.0 ? static_cast<double>(display_ns_.size() - 1) / span_s : 0.0;
    h.screen_latency_display_frames_max = l.max * 1e-3 * h.display_fps;
    h.run_screen_latency_display_frames_max = run.max * 1e-3 * h.display_fps;
  }
  return h;
}

std::vector<float> HudModel::plot(int points) const {
  std::vector<float> out(static_cast<std::size_t>(std::max(points, 1)), 0.0f);
  if (frames_.empty()) return out;
  const double per = static_cast<double>(window_frames_) / static_cast<double>(out.size());
  const std::size_t offset = window_frames_ - frames_.size();  // a short window ends at the right edge
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const auto b = std::min(out.size() - 1, static_cast<std::size_t>(static_cast<double>(i + offset) / per));
    out[b] = std::max(out[b], frames_[i].frame_us);
  }
  return out;
}

}  // namespace incise::viewer
