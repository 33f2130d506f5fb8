// The HUD's numbers (viewer/src/hud_model.cpp) from snapshots, without a window.
#include "incise/viewer/hud_model.h"

#include <catch2/catch.hpp>

using incise::sim::Snapshot;
using incise::viewer::HudModel;

namespace {

// The snapshot of frame `frame`, its recent timings as the sim fills them: frame f took f % 100 + 1 us
// (cut: half of it), every 250th missed its deadline.
Snapshot snapshotAt(std::int64_t frame) {
  Snapshot s;
  s.frame = frame;
  s.t_s = 0.001 * static_cast<double>(frame);
  s.recent_through = frame - 1;
  for (std::int64_t f = std::max<std::int64_t>(0, frame - Snapshot::kRecentFrames); f < frame; ++f) {
    auto& r = s.recent[static_cast<std::size_t>(f % Snapshot::kRecentFrames)];
    r.frame_us = static_cast<float>(f % 100 + 1);
    r.haptic_us = 1.0f;
    r.cut_us = r.frame_us / 2;
    r.deadline_missed = f % 250 == 0;
    r.pose_to_visible_frames = f == 500 ? 2 : -1;
  }
  s.deadline_misses = (frame - 1) / 250 + 1;
  s.haptic.force_N = Eigen::Vector3d(3.0, 4.0, 0.0);
  s.incisions = 2;
  return s;
}

}  // namespace

TEST_CASE("hud_model: percentiles over every frame the snapshots brought, budget used, force", "[viewer]") {
  HudModel hud(1000.0, 300.0, 1.0);  // a window of 1000 frames
  for (std::int64_t frame = 10; frame <= 2000; frame += 20) hud.add(snapshotAt(frame));
  const auto h = hud.figures();
  CHECK(h.frames == 1000);  // frames 990..1989: the last snapshot (frame 1990) brings up to 1989
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
  CHECK(h.deadline_misses == snapshotAt(1990).deadline_misses);
  CHECK(h.pose_to_visible_frames_max == -1);  // frame 500 has left the window
}

TEST_CASE("hud_model: frames no snapshot brought are counted, not invented", "[viewer]") {
  HudModel hud(1000.0, 300.0, 5.0);
  hud.add(snapshotAt(100));
  hud.add(snapshotAt(1000));  // 1000 - 256 = 744: frames 100..743 went by unseen
  const auto h = hud.figures();
  CHECK(h.frames_unseen == 744 - 100);
  CHECK(h.frames == 100 + Snapshot::kRecentFrames);
  CHECK(h.pose_to_visible_frames_max == -1);
  hud.add(snapshotAt(0));  // a restart: the window starts over
  CHECK(hud.figures().frames == 0);
}

TEST_CASE("hud_model: the plot's buckets hold their largest frame time, oldest first", "[viewer]") {
  HudModel hud(1000.0, 300.0, 1.0);
  for (std::int64_t frame = 100; frame <= 1100; frame += 100) hud.add(snapshotAt(frame));
  const std::vector<float> plot = hud.plot(10);  // 100 frames a bucket
  REQUIRE(plot.size() == 10);
  for (const float v : plot) CHECK(v == 100.0f);  // every bucket of 100 frames holds one f % 100 == 99
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

TEST_CASE("hud_model: a replay's source is playing, paused, then finished", "[viewer]") {
  incise::viewer::ReplaySourceStatus source("trace bunny-straight.csv", 1.0);
  CHECK(source.status(snapshotAt(500)).state == "playing");
  CHECK(source.status(snapshotAt(500)).source == "trace bunny-straight.csv");
  source.setPaused(true);
  CHECK(source.status(snapshotAt(500)).state == "paused");
  source.setPaused(false);
  CHECK(source.status(snapshotAt(1500)).state == "finished");
}
