// The viewer's benchmark, one JSON document on stdout:
//  - "geometry": the geometry stream's per-frame cost on the sim thread (sim::LatencyStats geometry_us) on
//    the bunny Loop-subdivided 3 times (235,136 triangles) and 4 times (940,544), the straight 5 cm stroke
//    replayed as fast as possible with a GeometryMirror pulling after every frame, the mirror seeded before
//    the run (as incise view does) or asking for its copy at the first frame (a sweep of the whole mesh
//    within the per-frame budget); target p99 <= 20 us on ~1M triangles; and the tet bunny (bunny-tets: the
//    surface and the tets' working mesh through the same budget);
//  - "realtime" (needs a display: run it under xvfb-run, e.g. `taskset -c 0 xvfb-run -a ...` so that Xvfb
//    keeps off the sim's core too): the shipped scenario (the bunny subdivided twice) replayed in real
//    time at 1 kHz without the viewer, then with the viewer attached and drawing (a GLFW window, the
//    geometry stream, the HUD), twice each in this order: the sim's frame p99 with the viewer within 10% of
//    without, pose-to-visible on screen (target <= 2 display frames); then the viewer on the 235k bunny:
//    its frame rate under llvmpipe (aim >= 30 fps) and latency. Deadline misses are split into our own overruns (a frame longer than the period)
//    and late wake-ups (the VM not running the loop on time: the period error);
//  - "skin_embedding": a simulated tissue's surface embedded on the viewer's thread (pad-tension,
//    bunny-tets-soft): its update after every pull, a whole embedding, and a physics step's redraw (skinCost);
//   incise_bench_viewer [--seconds S] [--geometry-only] [--skin-only] [--realtime-only] [--textured]
// `--textured`: every bunny gets a planar texture map after subdivision (bench::mapPlanar), so every face
// the stream sends carries its corners' texture coordinates (two records a face), and the real-time part's
// window draws them with the shipped skin (scenarios/textures/skin.png) and the compiled-in flesh.

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bunny_stroke.h"
#include "incise/devices/trace_csv.h"
#include "incise/measure/machine_info.h"
#include "incise/measure/percentile.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/scenario.h"
#include "incise/sim/simulation.h"
#include "incise/sim/stroke_poses.h"
#include "incise/sim/triple_buffer.h"
#include "incise/tets/tet_cutter.h"
#include "incise/viewer/gl_context.h"
#include "incise/viewer/png_file.h"
#include "incise/viewer/skin_embedding.h"
#include "incise/viewer/surface_model.h"
#include "incise/viewer/viewer_window.h"

using namespace incise;

namespace {

struct Loaded {
  sim::Scenario scenario;
  std::unique_ptr<sim::World> world;
  std::vector<devices::PoseSample> poses;
  std::size_t triangles = 0;
};

// A shipped scenario (default: bunny-straight.json) with its tissue subdivided `subdivide` times (< 0: as
// the scenario says). bunny-straight and bunny-tets replay the same 5 cm stroke.
bool g_textured = false;  // --textured: the geometry part's tissues carry texture coordinates

Loaded load(int subdivide, const char* scenario = "bunny-straight") {
  Loaded l;
  l.scenario = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + scenario + ".json");
  if (subdivide >= 0) l.scenario.subdivide = subdivide;
  mesh::SurfaceMesh tissue = sim::loadTissue(l.scenario);
  if (g_textured) bench::mapPlanar(tissue);
  l.triangles = tissue.mesh().n_faces();
  l.poses = l.scenario.source == sim::Scenario::Source::Strokes
                ? sim::posesForStrokes(tissue, l.scenario.strokes, l.scenario.world, l.scenario.rate_hz)
                : devices::TraceReader::readAll(l.scenario.trace);
  l.world = std::make_unique<sim::World>(std::move(tissue), l.scenario.world);
  return l;
}

nlohmann::json summary(const sim::SampleSummary& s) {
  return {{"p50", s.p50}, {"p99", s.p99}, {"p999", s.p999}, {"max", s.max}, {"count", s.count}};
}

// `seeded`: the reader's copy made before the run (as incise view does); else the reader asks for it at the
// first frame and the sim thread sweeps the whole mesh within its per-frame budget.
nlohmann::json geometryCost(int subdivide, bool seeded, const char* scenario = "bunny-straight") {
  Loaded l = load(subdivide, scenario);
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  if (seeded) stream.seed(*l.world, mirror);
  sim::LatencyStats stats(20000);
  sim::ReplayOptions o;
  o.period_us = l.scenario.periodUs();
  o.settle_s = l.scenario.settle_s;
  o.geometry = &stream;
  o.stats = &stats;
  std::size_t max_records = 0, pulls = 0;
  o.geometry_reader = [&] {
    max_records = std::max(max_records, mirror.pull(stream));
    mirror.clearChanges();
    ++pulls;
  };
  const sim::ReplayReport report = sim::replay(*l.world, l.poses, o);
  const sim::LatencySummary s = stats.summary();
  return {{"scenario", scenario},
          {"triangles", l.triangles},
          {"tets", l.world->tets() ? l.world->tets()->tetCount() : 0},
          {"seeded_before_the_run", seeded},
          {"records_per_frame", sim::GeometryStreamOptions{}.records_per_frame},
          {"frames", s.frames},
          {"geometry_us", summary(s.geometry_us)},
          {"frame_us", summary(s.frame_us)},
          {"records", report.geometry.records},
          {"most_records_read_in_a_frame", max_records},
          {"resets", report.geometry.resets},
          {"stalled_frames", report.geometry.stalled_frames},
          {"regrowths", report.geometry.regrowths},
          {"reader_exact_at_end", mirror.exact()},
          {"reader_tets_exact_at_end", mirror.tets().exact()},
          {"meets_target", s.geometry_us.p99 <= 20.0}};
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

nlohmann::json msSummary(const std::vector<double>& ms) {
  return {{"p50", measure::percentile(ms, 0.5)},
          {"p99", measure::percentile(ms, 0.99)},
          {"max", measure::percentile(ms, 1.0)},
          {"count", ms.size()}};
}

// A simulated tissue's surface embedded on the viewer's side (viewer::SkinEmbedding), its scenario replayed
// fast with a mirror pulling after every frame: update() after every pull (what the cut changed), then at
// the end a whole embedding from scratch, positions() at the last published state and SurfaceModel's
// rebuild with them (what the viewer does at every physics step). Milliseconds on this (the reader's)
// thread; the sim thread does nothing for it. Aim: a physics step's redraw within a 60 Hz display frame.
nlohmann::json skinCost(const char* scenario) {
  Loaded l = load(-1, scenario);
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  stream.seed(*l.world, mirror);
  viewer::SkinEmbedding skin;
  std::vector<double> update_ms;
  sim::ReplayOptions o;
  o.period_us = l.scenario.periodUs();
  o.settle_s = l.scenario.settle_s;
  o.geometry = &stream;
  o.geometry_reader = [&] {
    mirror.pull(stream);
    const auto t0 = std::chrono::steady_clock::now();
    skin.update(mirror);
    update_ms.push_back(msSince(t0));
    mirror.clearChanges();
  };
  sim::replay(*l.world, l.poses, o);
  skin.update(mirror);
  viewer::SkinEmbedding fresh;
  auto t0 = std::chrono::steady_clock::now();
  fresh.update(mirror);
  const double fresh_ms = msSince(t0);
  const sim::PhysicsState* state = l.world->physics() ? l.world->physics()->latestState() : nullptr;
  if (state == nullptr) return {{"scenario", scenario}, {"skipped", "not a simulated tissue"}};
  std::vector<double> positions_ms, redraw_ms, boundary_ms;
  std::vector<std::array<double, 3>> out_m;
  for (int i = 0; i < 20; ++i) {
    t0 = std::chrono::steady_clock::now();
    skin.positions(mirror, *state, out_m);
    positions_ms.push_back(msSince(t0));
    viewer::SurfaceModel model;
    t0 = std::chrono::steady_clock::now();
    model.update(mirror, skin, *state);
    redraw_ms.push_back(msSince(t0));
    viewer::SurfaceModel boundary;  // what the viewer drew before: the tets' boundary as simulated
    t0 = std::chrono::steady_clock::now();
    boundary.update(mirror.tets(), *state);
    boundary_ms.push_back(msSince(t0));
  }
  const double redraw_p50_ms = measure::percentile(redraw_ms, 0.5);
  return {{"scenario", scenario},
          {"vertices", mirror.positions_m().size()},
          {"faces", mirror.faces().size()},
          {"tets", mirror.tets().tetCount()},
          {"embedded", skin.embedded()},
          {"locator_builds", skin.rebuilds()},
          {"update_after_each_pull_ms", msSummary(update_ms)},
          {"whole_embedding_ms", fresh_ms},
          {"positions_ms", msSummary(positions_ms)},
          {"redraw_per_physics_step_ms", msSummary(redraw_ms)},
          {"tets_boundary_redraw_per_physics_step_ms", msSummary(boundary_ms)},
          {"meets_aim_redraw_within_16_7_ms", redraw_p50_ms <= 1000.0 / 60.0}};
}

// The images a textured run is drawn with (--textured).
viewer::TissueImages shippedImages() {
  return {{viewer::readPng(std::string(INCISE_SCENARIOS_DIR) + "/textures/skin.png")}, viewer::fleshImage()};
}

struct RealTimeResult {
  sim::LatencySummary latency;
  std::int64_t replays = 0, overruns = 0, display_frames = 0;
  double fps_sum = 0.0, screen_ms_p50_sum = 0.0, screen_ms_max = 0.0, screen_frames_max = 0.0, wall_s = 0.0;
};

// One replay on a worker thread; the window (if any) draws on this thread until it ends.
void replayOnce(Loaded& l, viewer::ViewerWindow* window, sim::LatencyStats& stats, RealTimeResult& out) {
  sim::GeometryStream stream;
  sim::TripleBuffer<sim::Snapshot> snapshots;
  auto times = std::make_unique<sim::FrameTimesQueue>();
  sim::ReplayOptions o;
  o.pace = sim::ReplayPace::RealTime;
  o.period_us = l.scenario.periodUs();
  o.settle_s = l.scenario.settle_s;
  o.stats = &stats;
  o.spin_us = 200;
  o.pin_threads = true;
  o.realtime_priority = true;  // SCHED_FIFO when the process may have it, as incise bench
  if (window) {
    o.geometry = &stream;
    o.times = times.get();
    o.observer = [&snapshots](const sim::Snapshot& s) { snapshots.publish(s); };
  }
  std::atomic<bool> ended{false};
  sim::ReplayReport report;
  sim::GeometryMirror seeded;
  if (window) stream.seed(*l.world, seeded);  // as incise view does: the tissue copied before the run
  std::thread worker([&] {
    report = sim::replay(*l.world, l.poses, o);
    ended.store(true);
  });
  if (window) {
    viewer::ReplaySourceStatus source("trace " + l.scenario.trace.filename().string(), l.poses.back().time_s);
    viewer::ViewerFeed feed;
    feed.geometry = &stream;
    feed.take_snapshot = [&snapshots](sim::Snapshot& s) {
      if (!snapshots.update()) return false;
      s = snapshots.read();
      return true;
    };
    feed.times = times.get();
    feed.source = &source;
    feed.scenario = "bench";
    if (g_textured) feed.textures = shippedImages();
    window->follow(feed, std::move(seeded));
    const std::int64_t before = window->displayFrames();
    while (!ended.load()) window->frame();
    const viewer::HudFigures h = window->figures();
    out.display_frames += window->displayFrames() - before;
    out.fps_sum += h.display_fps;
    out.screen_ms_p50_sum += h.screen_latency_ms_p50;
    out.screen_ms_max = std::max(out.screen_ms_max, h.screen_latency_ms_max);
    out.screen_frames_max = std::max(out.screen_frames_max, h.screen_latency_display_frames_max);
  }
  worker.join();
  out.overruns += report.loop.overruns;
  out.wall_s += report.wall_s;
  ++out.replays;
}

nlohmann::json realTime(int subdivide, viewer::ViewerWindow* window, double seconds) {
  sim::LatencyStats stats(static_cast<std::size_t>(seconds * 1200.0) + 10000);
  RealTimeResult r;
  std::size_t triangles = 0;
  while (static_cast<double>(stats.frames()) * 1e-3 < seconds) {
    Loaded l = load(subdivide);
    triangles = l.triangles;
    replayOnce(l, window, stats, r);
  }
  const sim::LatencySummary s = stats.summary();
  nlohmann::json j = {{"viewer", window != nullptr},
                      {"triangles", triangles},
                      {"replays", r.replays},
                      {"frames", s.frames},
                      {"frame_us", summary(s.frame_us)},
                      {"haptic_us", summary(s.haptic_us)},
                      {"cut_us", summary(s.cut_us)},
                      {"geometry_us", summary(s.geometry_us)},
                      {"period_error_us", summary(s.period_error_us)},
                      {"deadline_misses", s.deadline_misses},
                      {"loop_overruns", r.overruns},
                      // A frame longer than the period is ours; every other miss is a late wake-up.
                      {"own_overruns_possible", s.frame_us.max > 1000.0}};
  if (window) {
    j["display_frames"] = r.display_frames;
    j["viewer_fps_mean"] = r.fps_sum / static_cast<double>(r.replays);
    j["screen_latency_ms_p50_mean"] = r.screen_ms_p50_sum / static_cast<double>(r.replays);
    j["screen_latency_ms_max"] = r.screen_ms_max;
    j["screen_latency_display_frames_max"] = r.screen_frames_max;
  }
  return j;
}

// The sim's frame p99 without and with the viewer on the shipped scenario (the bunny subdivided twice,
// 58,784 triangles: the loop keeps its period there, so the viewer's effect is not lost in the loop's own
// overruns), twice in this order; then the viewer's frame rate and latency on the 235k bunny.
nlohmann::json realTimePairs(double seconds) {
  sim::keepOffLastCpu();  // the window and llvmpipe's threads inherit this thread's mask
  viewer::ViewerWindowOptions options;
  options.size = {1280, 800};
  options.title = "incise bench";
  viewer::ViewerWindow window(options);
  nlohmann::json runs = nlohmann::json::array();
  for (int pass = 0; pass < 2; ++pass) {
    nlohmann::json without = realTime(2, nullptr, seconds);
    nlohmann::json with = realTime(2, &window, seconds);
    const double a = without["frame_us"]["p99"], b = with["frame_us"]["p99"];
    runs.push_back({{"without_viewer", without},
                    {"with_viewer", with},
                    {"frame_p99_change", b / a - 1.0},
                    {"meets_target_p99_within_10_percent", b <= 1.1 * a},
                    {"meets_target_screen_latency", with["screen_latency_display_frames_max"].get<double>() <= 2.0}});
  }
  nlohmann::json large = realTime(3, &window, seconds);
  large["meets_aim_30_fps"] = large["viewer_fps_mean"].get<double>() >= 30.0;
  large["meets_target_screen_latency"] = large["screen_latency_display_frames_max"].get<double>() <= 2.0;
  return {{"gl", window.glDescription()}, {"runs", runs}, {"viewer_on_235k", large}};
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10.0;
  bool geometry_only = false, skin_only = false, realtime_only = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--geometry-only") == 0) geometry_only = true;
    if (std::strcmp(argv[i], "--skin-only") == 0) skin_only = true;
    if (std::strcmp(argv[i], "--realtime-only") == 0) realtime_only = true;
    if (std::strcmp(argv[i], "--textured") == 0) g_textured = true;
    if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) seconds = std::stod(argv[++i]);
  }
  nlohmann::json report = {{"benchmark", "viewer"},
                           {"targets",
                            {{"geometry_us_p99_on_1M_triangles", 20},
                             {"sim_frame_p99_change_with_viewer", 0.10},
                             {"screen_latency_display_frames", 2},
                             {"viewer_fps_aim_235k_llvmpipe", 30}}},
                           {"machine", measure::machineInfo()},
                           {"textured", g_textured}};
  if (!realtime_only) report["skin_embedding"] = {skinCost("pad-tension"), skinCost("bunny-tets-soft")};
  if (skin_only) {
    std::printf("%s\n", report.dump(2).c_str());
    return 0;
  }
  if (!realtime_only) {
    report["geometry"] = nlohmann::json::array();
    for (const int subdivide : {3, 4})
      for (const bool seeded : {true, false}) report["geometry"].push_back(geometryCost(subdivide, seeded));
    // The tet bunny: the surface and the tet cutter's working mesh through the same budget.
    for (const bool seeded : {true, false}) report["geometry"].push_back(geometryCost(-1, seeded, "bunny-tets"));
  }
  if (!geometry_only) {
    try {
      report["realtime"] = realTimePairs(seconds);
    } catch (const std::exception& e) {
      report["realtime"] = {{"skipped", e.what()}};
    }
  }
  std::printf("%s\n", report.dump(2).c_str());
  return 0;
}
