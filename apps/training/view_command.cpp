// `incise view [SCENARIO] [--speed X] [--out DIR] [--size WxH] [--camera AZ,EL[,DIST]]`: replays the
// scenario in real time with the viewer attached — the sim thread at its rate (1 kHz, times --speed), the
// window on the main thread at display rate, reading the snapshots and the geometry stream and never
// making the sim wait. R restarts the run on a fresh tissue, Space pauses it. Closing the window stops the
// run cleanly; what `replay` writes (cut.obj, report.json, the summary line) is written for the frames run.
// The sim thread is pinned to the last CPU (spinning the last 200 us before each deadline, as `incise bench`),
// the window and Mesa's llvmpipe threads to the others. No display: a message naming `incise render` and
// `xvfb-run`, exit 2.

#include <atomic>
#include <cstdio>
#include <thread>

#include "data_dir.h"
#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/geometry_stream.h"
#include "incise/sim/simulation.h"
#include "incise/sim/triple_buffer.h"
#include "incise/viewer/gl_context.h"
#include "incise/viewer/viewer_window.h"
#include "picture_output.h"
#include "replay_outputs.h"
#include "scenario_run.h"
#include "tissue_images.h"
#include "training_commands.h"

namespace incise::apps::training {

namespace {

struct ViewArgs {
  std::string scenario = shippedFile("bunny-straight.json");
  double speed = 1.0;
  std::string out = "out/view";
  std::string size = "1280x800";
  std::string camera;
  bool until_end = false;
};

std::string sourceDescription(const sim::Scenario& s) {
  switch (s.source) {
    case sim::Scenario::Source::Trace:
      return "trace " + s.trace.filename().string();
    case sim::Scenario::Source::HidRecording:
      return "hid recording " + s.hid.path.filename().string();
    default:
      return "generated strokes (" + std::to_string(s.strokes.size()) + ")";
  }
}

// One run: the replay on its own thread (which runs the sim thread, the feeder and the snapshot reader),
// the window on this one until the replay ends and the user closes or restarts.
struct Run {
  LoadedScenario loaded;
  sim::GeometryStream stream;
  sim::TripleBuffer<sim::Snapshot> snapshots;  // written by replay's reader thread, read by the window
  std::unique_ptr<sim::FrameTimesQueue> times = std::make_unique<sim::FrameTimesQueue>();
  std::atomic<bool> stop{false}, paused{false}, ended{false};
  sim::ReplayOptions options;
  sim::ReplayReport report;
  std::thread thread;

  void start(double speed) {
    options.pace = sim::ReplayPace::RealTime;
    options.period_us = loaded.scenario.periodUs();
    options.settle_s = loaded.scenario.settle_s;
    options.speed = speed;
    options.pin_threads = true;  // the loop on the last CPU, the feeder and reader elsewhere (as incise bench)
    options.spin_us = 200;
    options.realtime_priority = true;  // SCHED_FIFO when the process may have it
    options.geometry = &stream;
    options.times = times.get();
    options.pause = &paused;
    options.stop_requested = [this] { return stop.load(); };
    options.observer = [this](const sim::Snapshot& s) { snapshots.publish(s); };
    thread = std::thread([this] {
      report = sim::replay(*loaded.world, loaded.poses, options);
      ended.store(true);
    });
  }
  void finish() {
    stop.store(true);
    paused.store(false);
    if (thread.joinable()) thread.join();
  }
};

// Shows one run until the window closes (false) or the user restarts (true).
bool show(viewer::ViewerWindow& window, Run& run, const std::string& name, bool until_end, double speed) {
  const std::vector<Eigen::Vector3d> stroke = strokePoints(run.loaded);
  viewer::ReplaySourceStatus source(sourceDescription(run.loaded.scenario), run.loaded.poses.back().time_s);
  viewer::ViewerFeed feed;
  feed.geometry = &run.stream;
  feed.take_snapshot = [&run](sim::Snapshot& s) {
    if (!run.snapshots.update()) return false;
    s = run.snapshots.read();
    return true;
  };
  feed.times = run.times.get();
  feed.source = &source;
  feed.period_us = static_cast<double>(run.loaded.scenario.periodUs());
  feed.cut_budget_us = run.loaded.scenario.world.cut_budget_us;
  feed.blade_length_m = run.loaded.scenario.world.tool.blade_length_m;
  feed.stroke_points_m = stroke;
  feed.scenario = name;
  feed.textures = tissueImages("view", run.loaded);
  if (sim::TissuePhysics* physics = run.loaded.world->physics())
    feed.physics_state = [physics] { return physics->latestState(); };
  sim::GeometryMirror seeded;  // the tissue as it starts, copied before the run: no sweep on the sim thread
  run.stream.seed(*run.loaded.world, seeded);
  window.follow(feed, std::move(seeded));
  run.start(speed);
  while (true) {
    const viewer::ViewerRequests r = window.frame();
    if (r.pause_toggled) {
      run.paused.store(!run.paused.load());
      source.setPaused(run.paused.load());
    }
    if (r.close || r.restart || (until_end && run.ended.load())) {
      run.finish();
      return r.restart && !r.close && !(until_end && run.ended.load());
    }
  }
}

int runView(const ViewArgs& a) {
  viewer::ViewerWindowOptions window_options;
  try {
    window_options.size = viewer::parseSizeOption(a.size);
    if (!a.camera.empty()) window_options.camera = viewer::parseCameraOption(a.camera);
  } catch (const std::exception& e) {
    failWith("view", e.what());
  }
  if (!(a.speed >= 0.01 && a.speed <= 100.0))
    failWith("view", "--speed " + std::to_string(a.speed) + ": must be in [0.01, 100]");
  std::error_code error;
  std::filesystem::create_directories(a.out, error);
  if (error) failWith("view", "cannot create output directory " + a.out + ": " + error.message());
  window_options.screenshot_dir = a.out;
  sim::keepOffLastCpu();  // before the window: llvmpipe's threads inherit this thread's CPUs (the sim's is the last)
  std::unique_ptr<viewer::ViewerWindow> window;
  try {
    window = std::make_unique<viewer::ViewerWindow>(window_options);
  } catch (const std::exception& e) {
    failWith("view", e.what());
  }
  while (true) {
    auto run = std::make_unique<Run>();
    try {
      run->loaded = loadScenarioRun(a.scenario);
    } catch (const std::exception& e) {
      failWith("view", e.what());
    }
    if (show(*window, *run, run->loaded.scenario.name, a.until_end, a.speed)) continue;
    const viewer::HudFigures h = window->figures();
    std::printf(
        "incise view %s: %lld display frames, %.1f fps; on screen %.1f ms p50, %.1f ms max (%.2f display frames) "
        "from a snapshot's sim frame to the first display frame showing it, over %lld snapshots; sim frame p99 "
        "%.1f us in the last 5 s; %s\n",
        run->loaded.scenario.name.c_str(), static_cast<long long>(window->displayFrames()), h.display_fps,
        h.run_screen_latency_ms_p50, h.run_screen_latency_ms_max, h.run_screen_latency_display_frames_max,
        static_cast<long long>(h.snapshots_shown), h.frame_us.p99, window->glDescription().c_str());
    window.reset();  // the window closes before the outputs are written
    return run::writeReplayOutputs("view", run->loaded, run->options, run->report, a.out);
  }
}

}  // namespace

void addViewCommand(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* cmd = app.add_subcommand(
      "view", "Replay a scenario in real time in a window (GLFW + OpenGL 3.3) with a HUD; write what replay writes");
  cmd->add_option("scenario", args->scenario, "scenario file (JSON)")->capture_default_str();
  cmd->add_option("--speed", args->speed, "wall-clock speed of the replay (the frames are the same)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output directory (cut.obj, report.json, screenshots)")->capture_default_str();
  cmd->add_option("--size", args->size, "window WIDTHxHEIGHT in pixels")->capture_default_str();
  cmd->add_option("--camera", args->camera, "AZ,EL[,DIST] (default: frame the incision)");
  cmd->add_flag("--until-end", args->until_end, "close the window when the replay ends (scripts, benchmarks)");
  cmd->callback([args] {
    const int code = runView(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps::training
