// `incise replay [SCENARIO] [--realtime|--fast] [--out DIR]`: the main job. Replays the scenario's poses
// through the simulation loop (a fixed-rate 1 kHz thread in real time, or the same frames as fast as
// possible), then writes the cut mesh, a JSON report (latency statistics, counts, the geometry's hash) and
// prints a short summary. With a tet tissue (the scenario's tissue.tets), also the cut tets (tets.vtu,
// tets.node/.ele) and their figures in the report. With --png FILE, a picture of the end state too
// (picture_output.h). Outputs are written to temporary files and renamed: nothing half-written.
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "data_dir.h"
#include "incise/incision/surface_cutter.h"
#include "incise/jobs/run_report.h"
#include "incise/sim/simulation.h"
#include "incise/tets/tet_cutter.h"
#include "json_output.h"
#include "picture_output.h"
#include "progress.h"
#include "replay_outputs.h"
#include "run_commands.h"
#include "scenario_run.h"
#include "tissue_images.h"

namespace incise::apps::run {

namespace {

struct ReplayArgs {
  std::string scenario = shippedFile("bunny-straight.json");
  bool realtime = false;
  bool fast = false;
  std::string out = "out/replay";
  std::string png;
};

// The tet tissue's files beside the surface mesh: tets.vtu (ParaView) and TetGen's tets.node/.ele, with
// per-tet fields side (-1 / +1 of the cut, 0 elsewhere) and split (0 original, 1 piece of a cut tet, 2 part
// of a crack-front tet).
// A simulated tissue's tets are written as simulated (tets.*) and at rest (tets_rest.node/.ele).
void writeTets(const tets::TetView& view, const sim::World& world, const std::filesystem::path& out) {
  const std::map<std::string, std::vector<int>> fields = {{"side", view.side}, {"split", view.split}};
  const sim::TissuePhysics* physics = world.physics();
  if (!physics) {
    tets::saveVtu(view.mesh, out / "tets.vtu", fields);
    tets::saveNodeEle(view.mesh, out / "tets", fields);
    return;
  }
  tets::TetView simulated = view;
  physics->deform(simulated, *world.tets());
  tets::saveVtu(simulated.mesh, out / "tets.vtu", fields);
  tets::saveNodeEle(simulated.mesh, out / "tets", fields);
  tets::saveNodeEle(view.mesh, out / "tets_rest", fields);
}

// The surface: as simulated in cut.obj and at rest in cut_rest.obj for a simulated tissue, else cut.obj.
void writeSurface(const sim::World& world, const std::filesystem::path& out) {
  if (const sim::TissuePhysics* physics = world.physics()) {
    mesh::saveObj(physics->deformedSurface(world.tissue()), out / "cut.obj");
    mesh::saveObj(world.tissue(), out / "cut_rest.obj");
    return;
  }
  mesh::saveObj(world.tissue(), out / "cut.obj");
}

// The physics' figures for the summary line ("" without a simulated tissue).
std::string physicsNote(const sim::World& world, const sim::LatencySummary& latency) {
  const sim::TissuePhysics* physics = world.physics();
  if (!physics) return "";
  char text[256];
  std::snprintf(text, sizeof text, "; physics %.0f Hz: %lld steps, step p99 %.0f us, %lld late", physics->rateHz(),
                static_cast<long long>(physics->counters().steps), latency.physics_step_us.p99,
                static_cast<long long>(latency.physics_late));
  return text;
}

int runReplay(const ReplayArgs& a) {
  if (!a.png.empty()) checkPngPath("replay", "--png", a.png), checkPictureContext("replay");
  LoadedScenario run;
  try {
    run = loadScenarioRun(a.scenario);
  } catch (const std::exception& e) {
    failWith("replay", e.what());
  }
  // A bad image stops here, before the run.
  std::optional<viewer::TissueImages> textures = a.png.empty() ? std::nullopt : tissueImages("replay", run);
  std::error_code error;
  std::filesystem::create_directories(a.out, error);
  if (error) failWith("replay", "cannot create output directory " + a.out + ": " + error.message());

  sim::ReplayOptions options = jobs::scenarioReplayOptions(
      run.scenario, a.realtime && !a.fast ? sim::ReplayPace::RealTime : sim::ReplayPace::Fast);
  // A bar for a fast replay (a real-time one takes the trace's own time, shown by nothing else).
  Progress progress("replay " + run.scenario.name,
                    (run.poses.back().time_s - run.poses.front().time_s + options.settle_s) * run.scenario.rate_hz);
  if (options.pace == sim::ReplayPace::Fast && progress.drawing())
    options.observer = [&progress](const sim::Snapshot& s) { progress.update(static_cast<double>(s.frame)); };
  const sim::ReplayReport report = sim::replay(*run.world, run.poses, options);
  progress.finish();
  const int code = writeReplayOutputs("replay", run, options, report, a.out);
  if (!a.png.empty()) writeEndPicture("replay", run, report.frames - 1, a.png, std::move(textures));
  return code;
}

}  // namespace

// The outputs of a run that has ended (replay, view): cut.obj, report.json (and the tets' files), and the
// summary line.
int writeReplayOutputs(const char* command, const LoadedScenario& run, const sim::ReplayOptions& options,
                       const sim::ReplayReport& report, const std::string& out_dir) {
  const auto& stats = run.world->cutter().stats();
  const std::filesystem::path out(out_dir);
  nlohmann::json json;
  bool tets_ok = true;
  std::string tets_note;
  try {
    writeSurface(*run.world, out);
    const tets::TetCutter* tets = run.world->tets();
    const std::optional<tets::TetView> view = tets ? std::optional(tets->view(tets::TetShape::Deformed)) : std::nullopt;
    json = jobs::replayReport(run, options, report, view ? &*view : nullptr);
    if (view) {
      writeTets(*view, *run.world, out);
      tets_ok = json["tets"]["failure"].get<std::string>().empty() && json["tets"]["inverted_tets"].get<int>() == 0;
      tets_note = "; " + std::to_string(json["tets"]["tets"].get<size_t>()) + " tets (" +
                  std::to_string(json["tets"]["tets_cut"].get<int>()) + " cut, " +
                  std::to_string(json["tets"]["inverted_tets"].get<int>()) + " inverted)";
    }
    tets_note += physicsNote(*run.world, report.latency);
    writeJsonAtomically(json, out / "report.json");
  } catch (const std::exception& e) {
    failWith(command, e.what());
  }
  const bool closed = json["mesh"]["closed_two_manifold"].get<bool>();
  const std::string note = json["note"].get<std::string>().empty() ? "" : "; " + json["note"].get<std::string>();
  std::printf(
      "incise %s %s (%s): %lld frames, %lld poses, %d incision(s), %d seam vertices opened, grooves of "
      "%.1f mm along %.1f mm of strokes in contact; "
      "frame p99 %.1f us, haptic p99 %.1f us, pose-to-visible p99 %.0f frames, %lld deadline misses; "
      "closed two-manifold: %s; geometry %s%s%s; wrote %s\n",
      command, run.scenario.name.c_str(), options.pace == sim::ReplayPace::RealTime ? "realtime" : "fast",
      static_cast<long long>(report.frames), static_cast<long long>(report.poses), report.incisions,
      stats.vertices_duplicated, 1e3 * totalGroove_m(stats.figures), 1e3 * totalStroke_m(stats.figures),
      report.latency.frame_us.p99, report.latency.haptic_us.p99, report.latency.pose_to_visible_frames.p99,
      static_cast<long long>(report.latency.deadline_misses), closed ? "yes" : "NO",
      json["geometry_hash"].get<std::string>().c_str(), tets_note.c_str(), note.c_str(), out_dir.c_str());
  const std::string failure = json["cut_failure"].get<std::string>();
  if (!failure.empty()) std::fprintf(stderr, "incise %s: the cut failed: %s\n", command, failure.c_str());
  return closed && failure.empty() && tets_ok ? 0 : 1;
}

void addReplayCommand(CLI::App& app) {
  auto args = std::make_shared<ReplayArgs>();
  CLI::App* cmd = app.add_subcommand(
      "replay", "Replay a scenario's scalpel poses through the 1 kHz simulation; write the cut mesh and a JSON report");
  cmd->add_option("scenario", args->scenario, "scenario file (JSON)")->capture_default_str();
  auto* realtime =
      cmd->add_flag("--realtime", args->realtime, "pace frames at the scenario's rate on a fixed-rate thread");
  auto* fast = cmd->add_flag("--fast", args->fast, "run the same frames as fast as possible (default)");
  realtime->excludes(fast);
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->add_option("--png", args->png, "also a picture of the end state (PNG; the camera frames the incision)");
  cmd->callback([args] {
    const int code = runReplay(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps::run
