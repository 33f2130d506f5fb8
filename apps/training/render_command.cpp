// `incise render SCENARIO --out FILE.png [--at S] [--size WxH] [--camera AZ,EL[,DIST]] [--no-tool]
// [--wireframe] [--tets]`: a picture of the scenario's state at S seconds after its first pose (default: the end of
// the replay), without a window — the same frames as `replay --fast` up to S, then the mesh drawn
// off-screen (a hidden window under Xvfb or any display, else EGL on Mesa) and written as PNG through a
// .tmp file. The camera frames the incision unless --camera says otherwise. Exit 2 for bad options, a bad
// scenario, or no display / EGL / OpenGL 3.3.
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "incise/viewer/camera.h"
#include "picture_output.h"
#include "scenario_run.h"
#include "tissue_images.h"
#include "training_commands.h"

namespace incise::apps::training {

namespace {

struct RenderArgs {
  std::string scenario;
  std::string out;
  double at_s = std::numeric_limits<double>::infinity();
  std::string size = "1280x800";
  std::string camera;
  bool no_tool = false;
  bool wireframe = false, tets = false;
};

int runRender(const RenderArgs& a) {
  checkPngPath("render", "--out", a.out);
  PictureArgs picture;
  try {
    picture.size = viewer::parseSizeOption(a.size);
    if (!a.camera.empty()) picture.camera = viewer::parseCameraOption(a.camera);
  } catch (const std::exception& e) {
    failWith("render", e.what());
  }
  if (!(a.at_s >= 0.0)) failWith("render", "--at " + std::to_string(a.at_s) + ": must be >= 0 seconds");
  checkPictureContext("render");
  LoadedScenario run;
  try {
    run = loadScenarioRun(a.scenario);
  } catch (const std::exception& e) {
    failWith("render", e.what());
  }
  if (a.tets && !run.scenario.world.tets.enabled)
    failWith("render", "--tets: " + a.scenario + " has no tet tissue (\"tets\" in its \"tissue\")");
  picture.textures = tissueImages("render", run);  // a bad image stops here, before the run
  sim::ReplayOptions options;
  options.pace = sim::ReplayPace::Fast;
  options.period_us = run.scenario.periodUs();
  options.settle_s = run.scenario.settle_s;
  options.stop_after_s = a.at_s;
  sim::Snapshot last;
  options.observer = [&last](const sim::Snapshot& s) { last = s; };
  const sim::ReplayReport report = sim::replay(*run.world, run.poses, options);
  picture.tool = !a.no_tool;
  picture.wireframe = a.wireframe;
  picture.tets = a.tets;
  picture.last = last;
  std::printf("incise render %s: state at t = %.3f s after the first pose (frame %lld, %d incision(s))\n",
              run.scenario.name.c_str(), last.t_s - run.poses.front().time_s, static_cast<long long>(last.frame),
              report.incisions);
  writePicture("render", run, report.frames - 1, a.out, picture);
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "A PNG picture of a scenario's state at a time, without a window");
  cmd->add_option("scenario", args->scenario, "scenario file (JSON)")->required();
  cmd->add_option("--out", args->out, "the picture (.png)")->required();
  cmd->add_option("--at", args->at_s, "seconds after the first pose (default: the end of the replay)");
  cmd->add_option("--size", args->size, "WIDTHxHEIGHT in pixels")->capture_default_str();
  cmd->add_option("--camera", args->camera,
                  "AZ,EL[,DIST]: azimuth and elevation in degrees, distance in metres (default: frame the incision)");
  cmd->add_flag("--no-tool", args->no_tool, "leave the scalpel, contact point and force out");
  cmd->add_flag("--wireframe", args->wireframe, "draw the triangles' edges");
  cmd->add_flag("--tets", args->tets, "draw the tet mesh's boundary (a scenario with tets) instead of the surface");
  cmd->callback([args] {
    const int code = runRender(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps::training
