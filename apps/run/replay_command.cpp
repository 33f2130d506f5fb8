// `incise replay [SCENARIO] [--realtime|--fast] [--out DIR]`: the main job. Replays the scenario's poses
// through the simulation loop (a fixed-rate 1 kHz thread in real time, or the same frames as fast as
// possible), then writes the cut mesh, a JSON report (latency statistics, counts, the geometry's hash) and
// prints a short summary. With a tet tissue (the scenario's tissue.tets), also the cut tets (tets.vtu,
// tets.node/.ele) and their figures in the report. With --png FILE, a picture of the end state too
// (picture_output.h). Outputs are written to temporary files and renamed: nothing half-written.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "data_dir.h"
#include "incise/incision/surface_cutter.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/sim/simulation.h"
#include "incise/tets/tet_cutter.h"
#include "json_output.h"
#include "picture_output.h"
#include "progress.h"
#include "replay_outputs.h"
#include "run_commands.h"
#include "scenario_run.h"

namespace incise::apps::run {

namespace {

struct ReplayArgs {
  std::string scenario = shippedFile("bunny-straight.json");
  bool realtime = false;
  bool fast = false;
  std::string out = "out/replay";
  std::string png;
};

std::string hex(std::uint64_t h) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

nlohmann::json summaryJson(const sim::SampleSummary& s) {
  return {{"count", s.count}, {"p50", s.p50}, {"p99", s.p99}, {"p999", s.p999}, {"max", s.max}, {"mean", s.mean}};
}

// The tet tissue's outputs beside the surface mesh: tets.vtu (ParaView) and TetGen's tets.node/.ele, with
// per-tet fields side (-1 / +1 of the cut, 0 elsewhere) and split (0 original, 1 piece of a cut tet, 2 part
// of a crack-front tet), and the report's figures.
nlohmann::json writeTets(const tets::TetCutter& tets, const std::filesystem::path& out) {
  const tets::TetView view = tets.view(tets::TetShape::Deformed);
  const std::map<std::string, std::vector<int>> fields = {{"side", view.side}, {"split", view.split}};
  tets::saveVtu(view.mesh, out / "tets.vtu", fields);
  tets::saveNodeEle(view.mesh, out / "tets", fields);
  const tets::TetCutStats& stats = tets.stats();
  const auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  return {{"tets", view.mesh.tets.size()},
          {"nodes", view.mesh.nodes_m.size()},
          {"volume_m3", tets::volume(view.mesh)},
          {"rest_volume_m3", tets::volume(tets.view(tets::TetShape::Rest).mesh)},
          {"min_dihedral_deg", tets::minDihedralAngleDeg(view.mesh)},
          {"min_split_dihedral_deg", view.min_split_dihedral_deg},
          {"min_split_volume_m3", finite(view.min_split_volume_m3)},
          {"inverted_tets", view.inverted_tets},
          {"tets_cut", stats.tets_cut},
          {"edge_points", stats.edge_points},
          {"duplicated_nodes", stats.duplicated_nodes},
          {"snapped_nodes", stats.snapped_nodes},
          {"steiner_nodes", stats.steiner_nodes},
          {"rebased_tets", stats.rebased_tets},
          {"reserve_overflows", stats.reserve_overflows},
          {"pending", tets.pending()},
          {"failure", stats.failure}};
}

// What went wrong with a replay's cut (cutFailure), and a trace whose blade never touched the tissue.
std::string replayFailure(const incision::CutStats& stats, const sim::ReplayReport& report) {
  if (report.incisions == 0 && report.poses > 0)
    return "no contact: none of the " + std::to_string(report.poses) +
           " poses touched the tissue with the blade (the tip stayed above the surface or the cut button was up)";
  return cutFailure(stats);
}

// The report.json document of a replay (without the tets' block).
nlohmann::json reportJson(const LoadedScenario& run, const sim::ReplayOptions& options, const sim::ReplayReport& report,
                          const mesh::MeshSummary& mesh, std::uint64_t hash) {
  const incision::CutStats& stats = run.world->cutter().stats();
  return {
      {"scenario", run.scenario.name},
      {"mode", options.pace == sim::ReplayPace::RealTime ? "realtime" : "fast"},
      {"period_us", options.period_us},
      {"frames", report.frames},
      {"simulated_s", report.simulated_s},
      {"wall_s", report.wall_s},
      {"poses", report.poses},
      {"poses_dropped", report.poses_dropped},
      {"incisions", report.incisions},
      {"edges_split", stats.edges_split},
      {"seam_vertices_opened", stats.vertices_duplicated},
      {"refined_vertices", stats.refined_vertices},
      {"refined_faces", stats.refined_faces},
      {"reserve_overflows", stats.reserve_overflows},
      {"cut_failure", replayFailure(stats, report)},
      {"incision_figures", incisionFiguresJson(stats.figures)},
      {"geometry_hash", hex(hash)},
      {"mesh", nlohmann::json::parse(mesh::toJson(mesh))},
      {"latency",
       {{"haptic_us", summaryJson(report.latency.haptic_us)},
        {"cut_us", summaryJson(report.latency.cut_us)},
        {"frame_us", summaryJson(report.latency.frame_us)},
        {"period_error_us", summaryJson(report.latency.period_error_us)},
        {"pose_to_visible_frames", summaryJson(report.latency.pose_to_visible_frames)},
        {"deadline_misses", report.latency.deadline_misses}}},
      {"loop",
       {{"overruns", report.loop.overruns},
        {"skipped_deadlines", report.loop.skipped_deadlines},
        {"max_period_error_us", report.loop.max_period_error_us}}},
  };
}

int runReplay(const ReplayArgs& a) {
  if (!a.png.empty()) checkPngPath("replay", "--png", a.png), checkPictureContext("replay");
  LoadedScenario run;
  try {
    run = loadScenarioRun(a.scenario);
  } catch (const std::exception& e) {
    failWith("replay", e.what());
  }
  std::error_code error;
  std::filesystem::create_directories(a.out, error);
  if (error) failWith("replay", "cannot create output directory " + a.out + ": " + error.message());

  sim::ReplayOptions options;
  options.pace = a.realtime && !a.fast ? sim::ReplayPace::RealTime : sim::ReplayPace::Fast;
  options.period_us = run.scenario.periodUs();
  options.settle_s = run.scenario.settle_s;
  // A bar for a fast replay (a real-time one takes the trace's own time, shown by nothing else).
  Progress progress("replay " + run.scenario.name,
                    (run.poses.back().time_s - run.poses.front().time_s + options.settle_s) * run.scenario.rate_hz);
  if (options.pace == sim::ReplayPace::Fast && progress.drawing())
    options.observer = [&progress](const sim::Snapshot& s) { progress.update(static_cast<double>(s.frame)); };
  const sim::ReplayReport report = sim::replay(*run.world, run.poses, options);
  progress.finish();
  const int code = writeReplayOutputs("replay", run, options, report, a.out);
  if (!a.png.empty()) writeEndPicture("replay", run, report.frames - 1, a.png);
  return code;
}

}  // namespace

// The outputs of a run that has ended (replay, view): cut.obj, report.json (and the tets' files), and the
// summary line.
int writeReplayOutputs(const char* command, const LoadedScenario& run, const sim::ReplayOptions& options,
                       const sim::ReplayReport& report, const std::string& out_dir) {
  const mesh::SurfaceMesh& tissue = run.world->tissue();
  const mesh::MeshSummary mesh = mesh::summarize(tissue);
  const std::uint64_t hash = mesh::geometryHash(tissue);
  const auto& stats = run.world->cutter().stats();
  const std::filesystem::path out(out_dir);
  bool tets_ok = true;
  std::string tets_note;
  try {
    mesh::saveObj(tissue, out / "cut.obj");
    nlohmann::json json = reportJson(run, options, report, mesh, hash);
    if (const tets::TetCutter* tets = run.world->tets()) {
      json["tets"] = writeTets(*tets, out);
      tets_ok = json["tets"]["failure"].get<std::string>().empty() && json["tets"]["inverted_tets"].get<int>() == 0;
      tets_note = "; " + std::to_string(json["tets"]["tets"].get<size_t>()) + " tets (" +
                  std::to_string(json["tets"]["tets_cut"].get<int>()) + " cut, " +
                  std::to_string(json["tets"]["inverted_tets"].get<int>()) + " inverted)";
    }
    writeJsonAtomically(json, out / "report.json");
  } catch (const std::exception& e) {
    failWith(command, e.what());
  }
  std::printf(
      "incise %s %s (%s): %lld frames, %lld poses, %d incision(s), %d seam vertices opened, grooves of "
      "%.1f mm along %.1f mm of strokes in contact; "
      "frame p99 %.1f us, haptic p99 %.1f us, pose-to-visible p99 %.0f frames, %lld deadline misses; "
      "closed two-manifold: %s; geometry %s%s; wrote %s\n",
      command, run.scenario.name.c_str(), options.pace == sim::ReplayPace::RealTime ? "realtime" : "fast",
      static_cast<long long>(report.frames), static_cast<long long>(report.poses), report.incisions,
      stats.vertices_duplicated, 1e3 * totalGroove_m(stats.figures), 1e3 * totalStroke_m(stats.figures),
      report.latency.frame_us.p99, report.latency.haptic_us.p99, report.latency.pose_to_visible_frames.p99,
      static_cast<long long>(report.latency.deadline_misses), mesh.closed_two_manifold ? "yes" : "NO",
      hex(hash).c_str(), tets_note.c_str(), out_dir.c_str());
  const std::string failure = replayFailure(stats, report);
  if (!failure.empty()) std::fprintf(stderr, "incise %s: the cut failed: %s\n", command, failure.c_str());
  return mesh.closed_two_manifold && failure.empty() && tets_ok ? 0 : 1;
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
