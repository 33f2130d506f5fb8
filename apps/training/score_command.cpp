// `incise score SCENARIO TRACE... [--out report.jsonl] [--plots DIR] [--picture]`: each trace replayed
// through the scenario's simulation (as `replay --fast`) and scored (sim/include/incise/sim/score.h): one
// JSON line per trace on stdout, then a summary line; --out writes the same lines to a file (through a .tmp,
// renamed). --plots DIR: per trace, DIR/<trace stem>.png (gnuplot: lateral and depth error along the plan
// with the tolerance bands, speed and force over time); --picture also DIR/<trace stem>-top.png, the cut
// seen from above through the headless renderer, the plan and its lateral band drawn over it (in 2D, after
// rendering: not part of the 3D scene).
// Every trace is read and checked before any is scored: an empty trace, one recorded on another tissue (its
// "# tissue:" comment against the scenario's tissue hash), a plan that does not project, a bad --pass-mark
// -> a message naming the file or mark, exit 2, nothing written. --pass-mark KEY>=VALUE / KEY<=VALUE
// (pass_mark.h, repeatable): each trace's line is checked against every mark; a trace that misses one is
// named on stderr with the figure, the summary line counts the traces that passed and failed, and the exit
// code is 1. Without marks (or with all met) 0.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "incise/jobs/score_traces.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/plan.h"
#include "incise/sim/score.h"
#include "json_output.h"
#include "pass_mark.h"
#include "picture_output.h"
#include "progress.h"
#include "scenario_run.h"
#include "score_plots.h"
#include "tissue_images.h"
#include "training_commands.h"

namespace incise::apps::training {

namespace {

struct ScoreArgs {
  std::string scenario;
  std::vector<std::string> traces;
  std::string out;
  std::string plots;
  bool picture = false;
  std::vector<std::string> pass_marks;
};

struct ScoredSession {
  std::string file;
  std::vector<devices::PoseSample> poses;
};

// Reads every trace and checks it against the scenario's tissue (exit 2 on the first bad one).
std::vector<ScoredSession> readTraces(const ScoreArgs& a, const jobs::ScoringScenario& scoring) {
  const jobs::Warn warn = [](const std::string& text) {
    std::fprintf(stderr, "incise score: warning: %s\n", text.c_str());
  };
  std::vector<ScoredSession> sessions;
  for (const std::string& file : a.traces) {
    try {
      sessions.push_back({file, jobs::readScoreTrace(file, scoring, warn)});
    } catch (const std::exception& e) {
      failWith("score", e.what());
    }
  }
  return sessions;
}

std::filesystem::path plotPath(const ScoreArgs& a, const std::string& trace, const char* suffix) {
  return std::filesystem::path(a.plots) / (std::filesystem::path(trace).stem().string() + suffix + ".png");
}

void checkOutputs(const ScoreArgs& a) {
  if (a.picture && a.plots.empty()) failWith("score", "--picture needs --plots DIR");
  if (!a.plots.empty()) {
    if (!gnuplotAvailable())
      failWith("score", "--plots needs gnuplot on the PATH (Debian: apt-get install gnuplot-nox)");
    std::error_code error;
    std::filesystem::create_directories(a.plots, error);
    if (error) failWith("score", "cannot create " + a.plots + ": " + error.message());
  }
  if (a.picture) checkPictureContext("score");
}

// The plan's centre line (green) and the edges of its lateral band (yellow), for the picture from above.
std::vector<OverlayLine> planOverlay(const sim::Scenario& scenario, const mesh::SurfaceMesh& tissue) {
  const sim::Plan plan =
      sim::projectPlan(scenario.plan, tissue, scenario.world.cutter.incision.spacing_m, scenario.file);
  OverlayLine centre, left, right;
  left.rgb = right.rgb = {240, 210, 40};
  left.width_px = right.width_px = 1;
  for (const sim::PlanStation& s : plan.stations) {
    centre.points_m.push_back(s.point_m);
    left.points_m.push_back(s.point_m + plan.lateral_tolerance_m * s.across);
    right.points_m.push_back(s.point_m - plan.lateral_tolerance_m * s.across);
  }
  return {left, right, centre};
}

// One trace: scored (the cut left in run.world for the picture), its plots written.
nlohmann::ordered_json scoreOne(const ScoreArgs& a, LoadedScenario& run, const mesh::SurfaceMesh& tissue,
                                ScoredSession& s, const std::optional<viewer::TissueImages>& images) {
  run.world = std::make_unique<sim::World>(tissue, run.scenario.world);
  run.poses = std::move(s.poses);
  const sim::Score score = sim::scoreReplay(run.scenario, tissue, *run.world, run.poses);
  if (!a.plots.empty()) {
    writeScorePlot(score, plotPath(a, s.file, ""));
    if (a.picture) {
      PictureArgs picture;
      picture.camera = viewer::CameraOption{0.0, 89.0, std::nullopt};
      picture.tool = false;
      if (run.scenario.plan.given) picture.overlay = planOverlay(run.scenario, tissue);
      picture.textures = images;
      writePicture("score", run, score.frames - 1, plotPath(a, s.file, "-top").string(), picture);
    }
  }
  return nlohmann::ordered_json::parse(jobs::scoreLine(s.file, score));
}

// The traces that miss a pass mark, each named on stderr with the marks it missed; the summary's count.
int checkPassMarks(const std::vector<PassMark>& marks, const std::vector<ScoredSession>& sessions,
                   const std::vector<nlohmann::ordered_json>& lines, nlohmann::ordered_json& summary) {
  int failed = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::vector<std::string> missed = missedPassMarks(marks, lines[i]);
    for (const std::string& m : missed)
      std::fprintf(stderr, "incise score: %s: %s\n", sessions[i].file.c_str(), m.c_str());
    failed += missed.empty() ? 0 : 1;
  }
  nlohmann::ordered_json texts = nlohmann::ordered_json::array();
  for (const PassMark& m : marks) texts.push_back(m.text);
  summary["summary"]["pass_marks"] = texts;
  summary["summary"]["passed"] = static_cast<int>(lines.size()) - failed;
  summary["summary"]["failed"] = failed;
  return failed;
}

int runScore(const ScoreArgs& a) {
  checkOutputs(a);
  jobs::ScoringScenario scoring;
  std::vector<PassMark> marks;
  try {
    scoring = jobs::loadScoringScenario(a.scenario);
    marks = parsePassMarks(a.pass_marks);
    checkPassMarkKeys(marks, scoring.scenario);
  } catch (const std::exception& e) {
    failWith("score", e.what());
  }
  LoadedScenario run;
  run.scenario = scoring.scenario;
  const mesh::SurfaceMesh& tissue = scoring.tissue;
  std::vector<ScoredSession> sessions = readTraces(a, scoring);
  // A textured tissue's images, read once, before any scoring: a bad one stops here.
  const std::optional<viewer::TissueImages> images =
      a.picture && !a.plots.empty() ? tissueImages("score", run.scenario, tissue) : std::nullopt;
  std::vector<nlohmann::ordered_json> lines;
  Progress progress("score " + run.scenario.name, static_cast<double>(sessions.size()));
  try {
    for (std::size_t i = 0; i < sessions.size(); ++i) {
      lines.push_back(scoreOne(a, run, tissue, sessions[i], images));
      progress.update(static_cast<double>(i + 1));
    }
  } catch (const std::exception& e) {
    failWith("score", e.what());
  }
  progress.finish();
  nlohmann::ordered_json summary = jobs::scoreSummary(lines);
  const int failed = marks.empty() ? 0 : checkPassMarks(marks, sessions, lines, summary);
  std::string all;
  for (const auto& line : lines) all += line.dump() + "\n";
  all += summary.dump() + "\n";
  std::fputs(all.c_str(), stdout);
  if (!a.out.empty()) {
    try {
      writeThroughTemporary(a.out, [&all](const std::filesystem::path& tmp) {
        std::ofstream f(tmp);
        f << all;
        if (!f.flush()) throw std::runtime_error("cannot write " + tmp.string());
      });
    } catch (const std::exception& e) {
      failWith("score", a.out + ": " + e.what());
    }
  }
  return failed > 0 ? 1 : 0;
}

}  // namespace

void addScoreCommand(CLI::App& app) {
  auto args = std::make_shared<ScoreArgs>();
  CLI::App* cmd = app.add_subcommand(
      "score", "Score recorded sessions: each trace replayed through the scenario, its cut measured against the plan");
  cmd->add_option("scenario", args->scenario, "scenario file (JSON), usually one with a plan")->required();
  cmd->add_option("traces", args->traces, "CSV traces to score")->required();
  cmd->add_option("--out", args->out, "also write the JSON lines (one per trace, then the summary) to this file");
  cmd->add_option("--plots", args->plots, "write DIR/<trace>.png (gnuplot) per trace");
  cmd->add_flag("--picture", args->picture, "with --plots: also DIR/<trace>-top.png, the cut seen from above");
  cmd->add_option("--pass-mark", args->pass_marks,
                  "KEY>=VALUE or KEY<=VALUE on a figure of the score line (repeatable): exit 1 when a trace misses one")
      ->allow_extra_args(false);
  cmd->callback([args] {
    const int code = runScore(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps::training
