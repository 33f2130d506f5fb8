// `incise train SCENARIO [--input mouse] [--out DIR] [--size WxH] [--camera AZ,EL[,DIST]]`: a live training
// session in the viewer. The scenario's plan is drawn on the tissue (its line, the lateral tolerance band,
// start and end markers); the mouse is the scalpel (viewer/mouse_scalpel.h: the cursor's ray meets the
// tissue, the left button held cuts, the wheel sets the depth; right drag orbits, shift + right or middle
// drag pans, ctrl + wheel zooms); the HUD shows the wheel's depth, the blade's depth in the tissue, the
// lateral error against the plan, the force and the time. The sim thread runs at the scenario's rate
// (sim::LiveSession) while the window pushes a pose for every cursor event.
// The session is recorded as it goes to DIR/trace.csv (kill-safe: written every 20 poses, with the
// scenario's tissue hash in its comments). R restarts on a fresh tissue (the trace starts again). When the
// window closes: DIR/cut.obj and DIR/report.json (as replay writes them), DIR/score.json (the recorded trace
// scored by sim::scoreSession: the line `incise score SCENARIO DIR/trace.csv` prints) and, with gnuplot,
// DIR/score.png. Once the camera is framed it prints where the plan's start and end are in the window
// ("plan start at pixel X Y, end at pixel X Y"), for scripts that drive the mouse.
// --pass-mark KEY>=VALUE / KEY<=VALUE (pass_mark.h, repeatable): the session's score line checked against
// each. Exit 2 for bad options (a bad pass mark among them), a bad scenario or no display; 1 when the cut
// failed a check (as replay's) or the score missed a pass mark; else 0, also for a session that cut nothing
// or had no pose at all (the summary says so; nothing is scored without a pose).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

#include "data_dir.h"
#include "hid_support.h"
#include "incise/devices/hid_pose_source.h"
#include "incise/devices/trace_csv.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/live_session.h"
#include "incise/sim/score.h"
#include "incise/viewer/gl_context.h"
#include "incise/viewer/viewer_window.h"
#include "json_output.h"
#include "pass_mark.h"
#include "replay_outputs.h"
#include "scenario_run.h"
#include "score_plots.h"
#include "tissue_images.h"
#include "training_commands.h"

namespace incise::apps::training {

namespace {

struct TrainArgs {
  std::string scenario;
  std::string input = "mouse";
  std::string transport = "hidapi";
  std::string out = "out/train";
  std::string size = "1280x800";
  std::string camera;
  std::vector<std::string> pass_marks;
  std::vector<PassMark> marks;  // parsed and checked before the window opens
};

// The window's poses into the session, each one also into the trace file (the main thread's; a write error
// ends the recording, reported at the end, not the session).
class RecordingSink final : public devices::PoseSink {
 public:
  RecordingSink(sim::LiveSession& session, devices::TraceWriter& writer) : session_(session), writer_(writer) {}
  bool push(const devices::PoseSample& pose) noexcept override {
    if (!session_.push(pose)) return false;
    if (error_.empty()) try {
        writer_.write(pose);
      } catch (const std::exception& e) {
        error_ = e.what();
      }
    return true;
  }
  const std::string& error() const noexcept { return error_; }

 private:
  sim::LiveSession& session_;
  devices::TraceWriter& writer_;
  std::string error_;
};

// A device's poses on the session's clock (the device thread's: the session's one producer), so that the
// recorded trace replays as the session ran.
class SessionClockSink final : public devices::PoseSink {
 public:
  SessionClockSink(const sim::LiveSession& session, devices::PoseSink& next) : session_(session), next_(next) {}
  bool push(const devices::PoseSample& pose) noexcept override {
    devices::PoseSample stamped = pose;
    stamped.time_s = session_.nowS();
    return next_.push(stamped);
  }

 private:
  const sim::LiveSession& session_;
  devices::PoseSink& next_;
};

// The HUD's source line for a device: its description and state.
class DeviceStatus final : public viewer::PoseSourceMonitor {
 public:
  explicit DeviceStatus(const devices::HidPoseSource& source) : source_(source) {}
  viewer::PoseSourceStatus status(const sim::Snapshot&) const override {
    return {source_.describe(), devices::toString(source_.state())};
  }

 private:
  const devices::HidPoseSource& source_;
};

// The source line of the HUD: the mouse, cutting or not.
class MouseStatus final : public viewer::PoseSourceMonitor {
 public:
  viewer::PoseSourceStatus status(const sim::Snapshot& s) const override {
    return {"mouse", s.haptic.cutting ? "cutting" : s.haptic.contact ? "in contact" : "hovering"};
  }
};

// One session in the window: until it closes (false) or the user restarts (true).
// --input hid[:VID:PID]: the device (any, or the one named) through the scenario's pen or 6-DOF mapping.
struct DeviceInput {
  std::unique_ptr<devices::HidTransport> transport;
  devices::HidDeviceSelector selector;
  devices::HidMapping mapping;
};

struct Session {
  LoadedScenario run;
  sim::GeometryStream stream;
  std::unique_ptr<sim::FrameTimesQueue> times = std::make_unique<sim::FrameTimesQueue>();
  std::unique_ptr<sim::LiveSession> live;
  sim::ReplayReport report;
  std::string record_error;
};

devices::TraceWriterOptions traceOptions(const TrainArgs& a, const LoadedScenario& run) {
  devices::TraceWriterOptions o;
  o.flush_every = 20;
  o.comments = {"generator: incise train " + std::filesystem::path(a.scenario).filename().string(),
                "scenario: " + run.scenario.name, std::string(kTissueComment) + tissueHashText(run.world->tissue()),
                "source: incise train --input " + a.input + (a.input == "mouse" ? "" : " --transport " + a.transport)};
  return o;
}

void printPlanPixels(const viewer::ViewerWindow& window, const sim::Plan& plan) {
  const auto start = window.pixelOf(plan.stations.front().point_m), end = window.pixelOf(plan.stations.back().point_m);
  if (!start || !end) return;
  std::printf("incise train: plan start at pixel %.0f %.0f, end at pixel %.0f %.0f\n", start->x(), start->y(), end->x(),
              end->y());
  std::fflush(stdout);
}

// What the window follows: the session's snapshots, stream and timings, the plan; the mouse as the scalpel
// unless a device cuts.
viewer::ViewerFeed feedFor(Session& s, const viewer::PoseSourceMonitor& status, devices::PoseSink* scalpel) {
  viewer::ViewerFeed feed;
  feed.geometry = &s.stream;
  feed.take_snapshot = [&s](sim::Snapshot& out) { return s.live->takeSnapshot(out); };
  feed.times = s.times.get();
  feed.source = &status;
  feed.period_us = static_cast<double>(s.run.scenario.periodUs());
  feed.cut_budget_us = s.run.scenario.world.cut_budget_us;
  feed.blade_length_m = s.run.scenario.world.tool.blade_length_m;
  feed.scenario = s.run.scenario.name + " (training)";
  feed.plan = s.run.plan ? &*s.run.plan : nullptr;
  feed.textures = tissueImages("train", s.run);
  if (sim::TissuePhysics* physics = s.run.world->physics())
    feed.physics_state = [physics] { return physics->latestState(); };
  feed.scalpel = scalpel;
  feed.clock_s = [&s] { return s.live->nowS(); };
  feed.scalpel_options.cut_button = std::max(0, s.run.scenario.world.tool.cut_button);
  if (s.run.plan) feed.scalpel_options.depth_m = std::min(s.run.plan->depth_m, feed.scalpel_options.max_depth_m);
  return feed;
}

bool runSession(viewer::ViewerWindow& window, Session& s, const TrainArgs& a, DeviceInput* device) {
  devices::TraceWriter writer(std::filesystem::path(a.out) / "trace.csv", traceOptions(a, s.run));
  sim::LiveOptions options;
  options.period_us = s.run.scenario.periodUs();
  options.settle_s = s.run.scenario.settle_s;
  options.geometry = &s.stream;
  options.times = s.times.get();
  options.pin_threads = true;
  options.spin_us = 200;
  options.realtime_priority = true;
  s.live = std::make_unique<sim::LiveSession>(*s.run.world, options);
  RecordingSink sink(*s.live, writer);
  SessionClockSink stamped(*s.live, sink);
  std::unique_ptr<devices::HidPoseSource> source;
  if (device)
    source = std::make_unique<devices::HidPoseSource>(
        *device->transport, device->selector, device->mapping, stamped,
        [](const std::string& m) { std::fprintf(stderr, "incise train: %s\n", m.c_str()); });
  MouseStatus mouse;
  std::optional<DeviceStatus> device_status;
  if (source) device_status.emplace(*source);
  viewer::ViewerFeed feed = feedFor(s, source ? static_cast<const viewer::PoseSourceMonitor&>(*device_status) : mouse,
                                    source ? nullptr : &sink);
  std::vector<Eigen::Vector3d> framed;
  if (s.run.plan)
    for (const sim::PlanStation& p : s.run.plan->stations) framed.push_back(p.point_m);
  feed.stroke_points_m = framed;
  sim::GeometryMirror seeded;
  s.stream.seed(*s.run.world, seeded);
  window.follow(feed, std::move(seeded));
  s.live->start();
  if (source) source->start();
  bool printed = false;
  viewer::ViewerRequests r;
  while (!r.close && !r.restart) {
    r = window.frame();
    if (!printed && s.run.plan && window.pixelOf(s.run.plan->stations.front().point_m))
      printPlanPixels(window, *s.run.plan), printed = true;
  }
  if (source) source->stop();  // its last pose (lifted) is in before the session settles
  s.report = s.live->stop();
  s.record_error = sink.error();
  writer.close();
  return r.restart && !r.close;
}

// What the session leaves in DIR once the window has closed.
int writeTrainOutputs(const TrainArgs& a, Session& s) {
  if (!s.record_error.empty()) failWith("train", "recording " + a.out + "/trace.csv failed: " + s.record_error);
  if (s.live->poses().empty()) {
    std::printf("incise train: the session has no poses (the scalpel never met the tissue): nothing to score\n");
    if (a.marks.empty()) return 0;
    std::fprintf(stderr, "incise train: no score, so the pass marks are missed\n");
    return 1;
  }
  sim::ReplayOptions options;
  options.pace = sim::ReplayPace::RealTime;
  options.period_us = s.run.scenario.periodUs();
  options.settle_s = s.run.scenario.settle_s;
  const int code = run::writeReplayOutputs("train", s.run, options, s.report, a.out);
  const mesh::SurfaceMesh uncut = sim::loadTissue(s.run.scenario);
  const sim::Score score = sim::scoreSession(s.run.scenario, uncut, s.live->poses());
  const std::string line = scoreLine((std::filesystem::path(a.out) / "trace.csv").string(), score);
  const std::filesystem::path json = std::filesystem::path(a.out) / "score.json";
  writeThroughTemporary(json, [&](const std::filesystem::path& tmp) {
    std::ofstream f(tmp);
    f << line << '\n';
    if (!f.flush()) throw std::runtime_error("cannot write " + tmp.string());
  });
  if (gnuplotAvailable()) writeScorePlot(score, std::filesystem::path(a.out) / "score.png");
  std::printf("incise train: wrote %s/trace.csv, cut.obj, report.json, score.json%s\n%s\n", a.out.c_str(),
              gnuplotAvailable() ? ", score.png" : "", line.c_str());
  const std::vector<std::string> missed = missedPassMarks(a.marks, nlohmann::ordered_json::parse(line));
  for (const std::string& m : missed) std::fprintf(stderr, "incise train: %s\n", m.c_str());
  return code != 0 || !missed.empty() ? 1 : 0;
}

// The transport, the selector (any device for plain "hid") and the scenario's mapping; exit 2 when any is bad.
DeviceInput deviceInput(const TrainArgs& a, const LoadedScenario& run) {
  if (run.scenario.source != sim::Scenario::Source::HidRecording)
    failWith("train", "--input " + a.input + ": " + a.scenario +
                          " has no pen or six_dof mapping (its pose_source is not a hid-recording)");
  DeviceInput d;
  try {
    d.transport = hid::makeHidTransport(a.transport);
    if (a.input != "hid") d.selector = devices::parseHidDeviceSelector(a.input.substr(4));
  } catch (const std::exception& e) {
    failWith("train", e.what());
  }
  if (a.input == "hid") {  // the first device there is, followed by its ids across a replug
    const auto found = d.transport->enumerate();
    if (found.empty())
      failWith("train",
               "--input hid: no HID device on " + d.transport->name() + "; plug one in, or name it as hid:VID:PID");
    d.selector.vid = found.front().vid, d.selector.pid = found.front().pid;
    if (!found.front().serial.empty()) d.selector.serial = found.front().serial;
  }
  d.mapping = run.scenario.hid.mapping;
  return d;
}

int runTrain(TrainArgs& a) {
  const bool hid = a.input == "hid" || a.input.rfind("hid:", 0) == 0;
  if (a.input != "mouse" && !hid)
    failWith("train", "--input '" + a.input + "': expected mouse, hid or hid:VID:PID[:serial]");
  viewer::ViewerWindowOptions window_options;
  window_options.title = "incise train";
  try {
    window_options.size = viewer::parseSizeOption(a.size);
    if (!a.camera.empty()) window_options.camera = viewer::parseCameraOption(a.camera);
  } catch (const std::exception& e) {
    failWith("train", e.what());
  }
  std::error_code error;
  std::filesystem::create_directories(a.out, error);
  if (error) failWith("train", "cannot create output directory " + a.out + ": " + error.message());
  window_options.screenshot_dir = a.out;
  auto session = std::make_unique<Session>();
  try {
    session->run = loadScenarioRun(a.scenario);
    a.marks = parsePassMarks(a.pass_marks);
    checkPassMarkKeys(a.marks, session->run.scenario);
  } catch (const std::exception& e) {
    failWith("train", e.what());
  }
  std::optional<DeviceInput> device;
  if (hid) device = deviceInput(a, session->run);
  sim::keepOffLastCpu();
  std::unique_ptr<viewer::ViewerWindow> window;
  try {
    window = std::make_unique<viewer::ViewerWindow>(window_options);
  } catch (const std::exception& e) {
    failWith("train", e.what());
  }
  while (runSession(*window, *session, a, device ? &*device : nullptr)) {  // R: a fresh tissue
    auto fresh = std::make_unique<Session>();
    fresh->run = loadScenarioRun(a.scenario);
    session = std::move(fresh);
  }
  window.reset();
  try {
    return writeTrainOutputs(a, *session);
  } catch (const std::exception& e) {
    failWith("train", e.what());
  }
}

}  // namespace

void addTrainCommand(CLI::App& app) {
  auto args = std::make_shared<TrainArgs>();
  CLI::App* cmd = app.add_subcommand(
      "train",
      "A live training session in the viewer: cut along the scenario's plan with the mouse, recorded and scored");
  cmd->add_option("scenario", args->scenario, "scenario file (JSON), with a plan")->required();
  cmd->add_option("--input", args->input, "the scalpel: mouse, hid or hid:VID:PID[:serial] (a pen or 6-DOF device)")
      ->capture_default_str();
  cmd->add_option("--transport", args->transport, "with --input hid: hidapi, or replay:FILE.hid (a recording)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output directory (trace.csv, cut.obj, report.json, score.json, score.png)")
      ->capture_default_str();
  cmd->add_option("--size", args->size, "window WIDTHxHEIGHT in pixels")->capture_default_str();
  cmd->add_option("--camera", args->camera, "AZ,EL[,DIST] (default: frame the plan)");
  cmd->add_option(
         "--pass-mark", args->pass_marks,
         "KEY>=VALUE or KEY<=VALUE on a figure of the score line (repeatable): exit 1 when the session misses one")
      ->allow_extra_args(false);
  cmd->callback([args] {
    const int code = runTrain(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps::training
