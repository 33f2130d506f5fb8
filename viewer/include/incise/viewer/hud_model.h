// The numbers the viewer's HUD shows, computed from the snapshots it takes (no window needed): live frame,
// haptic, cut and geometry-stream p50 / p99 over the last seconds, deadline misses, the share of the
// frame period and of the cutting budget used, the force, incisions, pose-to-visible latency (in sim
// frames, and on screen in display frames), the pose source and its state, and a frame-time plot.
//
// Every frame's timings come through a sim::FrameTimesQueue (add(const FrameTimes&)); frames the queue
// dropped (a reader away longer than the queue holds) show as gaps in the frame numbers and are counted in
// HudFigures::frames_unseen. The newest snapshot gives the force, incisions, deadline misses and the
// pose's clock time. Latency on screen counts each snapshot once, at the first display frame that shows it
// (redraws of a snapshot already shown, e.g. after a replay ended or while paused, count for nothing).
// Units: microseconds, newtons, seconds, frames. Threads: one (the viewer's). Cost: add() O(1);
// displayed() O(1) amortised (one double kept per snapshot shown, ~8 bytes at display rate); figures()
// O(W log W + S log S) for a window of W frames and S snapshots shown (call it a few times a second).
// Failure: nothing throws but std::bad_alloc.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "incise/sim/simulation.h"

namespace incise::viewer {

// Where the poses come from and how that source is doing, as the HUD shows it.
struct PoseSourceStatus {
  std::string source;  // e.g. "trace traces/bunny-straight.csv", "strokes (2)", "XP-Pen Deco (hidraw3)"
  std::string state;   // e.g. "playing", "finished", "paused"; a live device: "connected", "unplugged"
};

// What the HUD asks of a pose source. A replay's is ReplaySourceStatus; a live device (devices'
// HidPoseSource: describe() and state()) plugs in through its own implementation. Called on the viewer's
// thread once per display frame: must not block.
class PoseSourceMonitor {
 public:
  virtual ~PoseSourceMonitor() = default;
  virtual PoseSourceStatus status(const sim::Snapshot& newest) const = 0;
};

// A recorded source: "playing" until the snapshot's time passes the last pose, then "finished"; "paused"
// while paused() says so.
class ReplaySourceStatus final : public PoseSourceMonitor {
 public:
  ReplaySourceStatus(std::string description, double last_pose_s)
      : description_(std::move(description)), last_pose_s_(last_pose_s) {}
  void setPaused(bool paused) noexcept { paused_ = paused; }
  PoseSourceStatus status(const sim::Snapshot& newest) const override;

 private:
  std::string description_;
  double last_pose_s_;
  bool paused_ = false;
};

struct Percentiles {
  double p50 = 0.0, p99 = 0.0, max = 0.0;
};

struct HudFigures {
  Percentiles frame_us, haptic_us, cut_us, geometry_us;
  std::int64_t frames = 0;           // in the window
  std::int64_t frames_unseen = 0;    // since the start: frames whose timings no snapshot brought
  std::int64_t deadline_misses = 0;  // since the start (the sim's count)
  std::int64_t window_misses = 0;    // in the window
  double period_used = 0.0;          // frame p99 / period
  double cut_budget_used = 0.0;      // cut p99 / cut_budget_us
  double force_N = 0.0;
  int incisions = 0;
  // A simulated tissue (the newest snapshot's; all 0 without one): physics steps due by the sim's time,
  // finished by the physics thread, and finished late (more than a physics period after they were due).
  std::int64_t physics_steps_due = 0, physics_steps_done = 0, physics_late = 0;
  int pose_to_visible_frames_max = -1;  // sim frames, over the window (-1: no cut became visible in it)
  // A snapshot's frame start -> the first display frame showing it, over the snapshots of the window (those
  // whose frame began within the window before the newest one's), and over the whole run; the maxima also
  // in display frames at display_fps.
  double screen_latency_ms_p50 = 0.0, screen_latency_ms_max = 0.0, screen_latency_display_frames_max = 0.0;
  double run_screen_latency_ms_p50 = 0.0, run_screen_latency_ms_max = 0.0, run_screen_latency_display_frames_max = 0.0;
  std::int64_t snapshots_shown = 0;  // over the run, each once
  double display_fps = 0.0;          // display frames over the last window of display time
};

class HudModel {
 public:
  HudModel(double period_us, double cut_budget_us, double window_s = 5.0);

  void add(const sim::Snapshot& snapshot);
  void add(const sim::FrameTimes& times);
  // A display frame finished at `shown_ns` (steady_clock) showing the snapshot whose frame began at
  // `shown_frame_start_ns` (Snapshot::frame_start_ns; 0: none yet). A snapshot not newer than the last one
  // counted adds a display frame only.
  void displayed(std::int64_t shown_frame_start_ns, std::int64_t shown_ns);

  HudFigures figures() const;
  // The window's frame times, `points` buckets oldest first, each the bucket's largest frame_us.
  std::vector<float> plot(int points) const;
  const sim::Snapshot& newest() const noexcept { return newest_; }

 private:
  std::size_t window_frames_;
  double period_us_, cut_budget_us_;
  std::deque<sim::FrameTimes> frames_;
  std::int64_t next_frame_ = 0, unseen_ = 0;
  sim::Snapshot newest_;
  struct Shown {
    std::int64_t frame_start_ns;
    double latency_ms;
  };
  std::deque<Shown> shown_;              // the window's snapshots, oldest first
  std::vector<double> run_latency_ms_;   // every snapshot shown
  std::deque<std::int64_t> display_ns_;  // display frames in the last window of display time
  std::int64_t last_shown_frame_start_ns_ = 0;
};

}  // namespace incise::viewer
