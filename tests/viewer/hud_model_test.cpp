// The HUD's numbers (viewer/src/hud_model.cpp) from snapshots, without a window.
#include "incise/viewer/hud_model.h"

#include <catch2/catch.hpp>

using incise::sim::Snapshot;
using incise::viewer::HudModel;

namespace {

// Frame f took f % 100 + 1 us (cut: half of it, haptic 1 us); every 250th missed its deadline; frame 500
// made a cut visible 2 frames after its pose.
incise::sim::FrameTimes timesOf(std::int64_t f) {
  incise::sim::FrameTimes t;
  t.frame = f;
  t.frame_us = static_cast<float>(f % 100 + 1);
  t.haptic_us = 1.0f;
  t.cut_us = t.frame_us / 2;
  t.deadline_missed = f % 250 == 0;
  t.pose_to_visible_frames = f == 500 ? 2 : -1;
  return t;
}

Snapshot snapshotAt(std::int64_t frame) {
  Snapshot s;
  s.frame = frame;
  s.t_s = 0.001 * static_cast<double>(frame);
  s.deadline_misses = frame / 250 + 1;
  s.haptic.force_N = Eigen::Vector3d(3.0, 4.0, 0.0);
  s.incisions = 2;
  return s;
}

// Frames [from, to) as the HUD gets them.
void feed(HudModel& hud, std::int64_t from, std::int64_t to) {
  for (std::int64_t f = from; f < to; ++f) hud.add(timesOf(f));
  hud.add(snapshotAt(to - 1));
}

}  // namespace

TEST_CASE("hud_model: percentiles over the window's frames, budget used, force", "[viewer]") {
  HudModel hud(1000.0, 300.0, 1.0);  // a window of 1000 frames
  feed(hud, 0, 1990);
  const auto h = hud.figures();
  CHECK(h.frames == 1000);  // frames 990..1989
  CHECK(h.frames_unseen == 0);
  CHECK(h.frame_us.p50 == 50.0);
  CHECK(h.frame_us.p99 == 99.0);
  CHECK(h.frame_us.max == 100.0);
  CHECK(h.cut_us.p99 == 49.5);
  CHECK(h.period_used == Approx(0.099));
  CHECK(h.cut_budget_used == Approx(49.5 / 300.0));
  CHECK(h.force_N == Approx(5.0));
  CHECK(h.incisions == 2);
  CHECK(h.window_misses == 4);  // frames 1000, 1250, 1500, 1750
  CHECK(h.deadline_misses == snapshotAt(1989).deadline_misses);
  CHECK(h.pose_to_visible_frames_max == -1);  // frame 500 has left the window
  HudModel wide(1000.0, 300.0, 5.0);
  feed(wide, 0, 1990);
  CHECK(wide.figures().pose_to_visible_frames_max == 2);
}

TEST_CASE("hud_model: frames the queue dropped are counted, not invented", "[viewer]") {
  HudModel hud(1000.0, 300.0, 5.0);
  feed(hud, 0, 100);
  feed(hud, 744, 1000);  // frames 100..743 never came
  const auto h = hud.figures();
  CHECK(h.frames_unseen == 644);
  CHECK(h.frames == 100 + 256);
  CHECK(h.pose_to_visible_frames_max == -1);
  feed(hud, 0, 1);  // a restart: the window starts over
  CHECK(hud.figures().frames == 1);
  CHECK(hud.figures().frames_unseen == 0);
}

TEST_CASE("hud_model: the plot's buckets hold their largest frame time, oldest first", "[viewer]") {
  HudModel hud(1000.0, 300.0, 1.0);
  feed(hud, 0, 1100);
  const std::vector<float> plot = hud.plot(10);  // 100 frames a bucket
  REQUIRE(plot.size() == 10);
  for (const float v : plot) CHECK(v == 100.0f);  // every bucket of 100 frames holds one f % 100 == 99
  HudModel young(1000.0, 300.0, 1.0);
  feed(young, 0, 150);  // a short window ends at the right edge: the first buckets are empty
  const std::vector<float> part = young.plot(10);
  CHECK(part[0] == 0.0f);
  CHECK(part[9] == 100.0f);
}

TEST_CASE("hud_model: latency on screen in milliseconds and display frames", "[viewer]") {
  HudModel hud(1000.0, 300.0, 5.0);
  hud.add(snapshotAt(10));
  const std::int64_t ms = 1'000'000;
  for (int i = 0; i < 31; ++i) hud.displayed(1000 * ms + i * 33 * ms, 1000 * ms + i * 33 * ms + 40 * ms);
  const auto h = hud.figures();
  CHECK(h.screen_latency_ms_p50 == Approx(40.0));
  CHECK(h.display_fps == Approx(1000.0 / 33.0));
  CHECK(h.screen_latency_display_frames_max == Approx(40.0 / 33.0));
}

TEST_CASE("hud_model: each snapshot counts once on screen, redraws after the run ended change nothing", "[viewer]") {
  // A 3 s run at 60 display frames a second, each showing a new snapshot whose sim frame began 12 ms (first
  // half) or 20 ms (second half) before; then the window stays open 2 s on the last snapshot, then 5 s more.
  HudModel hud(1000.0, 300.0, 5.0);
  const std::int64_t ms = 1'000'000, display_ns = 1'000'000'000 / 60, start_ns = 1000 * ms;
  std::int64_t at_ns = start_ns, last_start_ns = 0;
  for (int i = 0; i < 180; ++i, at_ns += display_ns)
    hud.displayed(last_start_ns = at_ns - (i < 90 ? 12 : 20) * ms, at_ns);
  const auto ended = hud.figures();
  CHECK(ended.snapshots_shown == 180);
  CHECK(ended.run_screen_latency_ms_p50 == Approx(12.0));
  CHECK(ended.run_screen_latency_ms_max == Approx(20.0));
  CHECK(ended.screen_latency_ms_max == Approx(20.0));
  CHECK(ended.display_fps == Approx(60.0));
  CHECK(ended.run_screen_latency_display_frames_max == Approx(20.0 * 60.0 / 1000.0));
  for (const int seconds : {2, 5}) {
    INFO("the window open " << seconds << " s after the run's last snapshot");
    for (int i = 0; i < 60 * seconds; ++i, at_ns += display_ns) hud.displayed(last_start_ns, at_ns);
    const auto open = hud.figures();
    CHECK(open.snapshots_shown == 180);
    CHECK(open.run_screen_latency_ms_p50 == ended.run_screen_latency_ms_p50);
    CHECK(open.run_screen_latency_ms_max == ended.run_screen_latency_ms_max);
    CHECK(open.screen_latency_ms_p50 == ended.screen_latency_ms_p50);  // the window follows the snapshots
    CHECK(open.screen_latency_ms_max == ended.screen_latency_ms_max);
    CHECK(open.display_fps == Approx(60.0));  // the display still runs
  }
  // No snapshot yet (frame_start_ns 0): display frames only.
  HudModel fresh(1000.0, 300.0, 5.0);
  fresh.displayed(0, start_ns);
  fresh.displayed(0, start_ns + display_ns);
  CHECK(fresh.figures().snapshots_shown == 0);
  CHECK(fresh.figures().display_fps == Approx(60.0));
}

TEST_CASE("hud_model: the screen latency's window follows the snapshots' sim time, the run's covers them all",
          "[viewer]") {
  HudModel hud(1000.0, 300.0, 1.0);  // a 1 s window
  const std::int64_t ms = 1'000'000;
  for (int i = 0; i < 30; ++i) hud.displayed((1000 + 100 * i) * ms, (1000 + 100 * i + (i < 10 ? 50 : 10)) * ms);
  const auto h = hud.figures();
  CHECK(h.snapshots_shown == 30);
  CHECK(h.screen_latency_ms_max == Approx(10.0));  // the last 1 s of snapshots: 10 ms each
  CHECK(h.run_screen_latency_ms_max == Approx(50.0));
  CHECK(h.run_screen_latency_ms_p50 == Approx(10.0));
}

TEST_CASE("hud_model: a replay's source is playing, paused, then finished", "[viewer]") {
  incise::viewer::ReplaySourceStatus source("trace bunny-straight.csv", 1.0);
  CHECK(source.status(snapshotAt(500)).state == "playing");
  CHECK(source.status(snapshotAt(500)).source == "trace bunny-straight.csv");
  source.setPaused(true);
  CHECK(source.status(snapshotAt(500)).state == "paused");
  source.setPaused(false);
  CHECK(source.status(snapshotAt(1500)).state == "finished");
}

TEST_CASE("hud_model: a simulated tissue's physics steps, those behind and late, as the sim published them",
          "[viewer]") {
  HudModel hud(1000.0, 300.0, 1.0);
  feed(hud, 0, 10);
  CHECK(hud.figures().physics_steps_due == 0);  // no simulated tissue: the panel shows no physics row
  Snapshot s = snapshotAt(10);
  s.physics_steps_due = 120, s.physics_steps_done = 117, s.physics_late = 4;
  hud.add(s);
  const auto h = hud.figures();
  CHECK(h.physics_steps_due == 120);
  CHECK(h.physics_steps_done == 117);
  CHECK(h.physics_late == 4);
}
