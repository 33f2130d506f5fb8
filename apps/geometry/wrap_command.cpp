// `incise wrap SCENARIO [--out DIR]`: the global DFFD (paper §3). A model translates along v (y) through
// static obstacles over N frames; at every frame it is split at the discontinuities and mapped through F,
// left open (the lips F leaves together welded: weldClosedLips), stitched or capped. Writes
// DIR/frame_NNNN.obj (or .ply) per frame, DIR/frames.jsonl (one JSON line per frame: vertices, faces,
// boundary loops, worst penetration into an obstacle, min det J, pairs of faces crossing, times)
// and prints a summary; a progress bar on stderr when it is a terminal. The scenario format is in
// docs/scenarios.md ("Wrap scenarios"), read by sim::loadWrapScenario (sim/wrap_scenario.h); this file
// runs the frames and writes the outputs. Exit codes: 2 bad input (the file and key, or the obstacle and
// reason), 1 a frame penetrates an obstacle or a stitched/capped frame is not closed, 0 otherwise.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "geometry_commands.h"
#include "incise/core/atomic_file.h"
#include "incise/core/format.h"
#include "incise/global_dffd/global_dffd.h"
#include "incise/mesh/self_intersection.h"
#include "incise/sim/wrap_scenario.h"
#include "json_output.h"
#include "progress.h"
#include "scenario_run.h"

namespace incise::apps::geometry {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;
using sim::WrapScenario;

[[noreturn]] void fail(const std::string& message) { failWith("wrap", message); }

struct Frame {
  mesh::SurfaceMesh mesh;
  json line;
};

Frame wrapFrame(const WrapScenario& s, const global_dffd::GlobalDffd& base, int f) {
  const Eigen::Vector3d offset = s.translate_m * (double(f) / s.frames);
  mesh::SurfaceMesh moved = s.model;
  mesh::TriMesh& m = moved.mesh();
  for (const auto v : m.vertices()) m.set_point(v, mesh::toOpenMesh(mesh::toEigen(m.point(v)) + offset));
  const auto t0 = Clock::now();
  Frame out;
  double min_det_j = 0.0;
  if (s.treatment == global_dffd::OpeningTreatment::Capped) {
    out.mesh = global_dffd::cappedDeform(moved, base);
    min_det_j = base.minJacobian(1);
  } else {
    const bool stitched = s.treatment == global_dffd::OpeningTreatment::Stitched;
    const global_dffd::DffdSplit split = global_dffd::splitAtDiscontinuities(
        moved, base, stitched ? global_dffd::Openings::Close : global_dffd::Openings::Leave);
    global_dffd::GlobalDffd dffd = base;
    if (stitched)
      for (int i = 0; i < static_cast<int>(dffd.obstacles().size()); ++i)
        dffd.stitch(i, global_dffd::stitchLevel(split, dffd, i));
    if (stitched) {
      out.mesh = global_dffd::deformSplit(split, dffd);
    } else {
      std::vector<Eigen::Vector3d> positions(split.rest_m.size());
      global_dffd::deformSplit(split, dffd, positions);
      out.mesh = global_dffd::weldClosedLips(split, positions);
    }
    min_det_j = dffd.minJacobian(1);
  }
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  std::string deepest;
  const double penetration = global_dffd::worstPenetration(out.mesh.mesh(), s.obstacles, &deepest);
  const mesh::TriMesh& r = out.mesh.mesh();
  out.line = {{"frame", f},
              {"offset_m", {offset.x(), offset.y(), offset.z()}},
              {"vertices", r.n_vertices()},
              {"faces", r.n_faces()},
              {"boundary_loops", global_dffd::boundaryLoops(r)},
              {"worst_penetration_m", penetration},
              {"deepest_obstacle", deepest},
              {"min_det_j", min_det_j},
              {"self_intersections", mesh::findSelfIntersections(r).size()},
              {"split_and_deform_ms", ms}};
  return out;
}

int runWrap(const std::string& scenario, const std::string& out_dir) {
  WrapScenario s;
  try {
    s = sim::loadWrapScenario(scenario);
  } catch (const sim::ScenarioError& e) {
    fail(e.what());
  }
  std::unique_ptr<global_dffd::GlobalDffd> dffd;
  try {
    dffd = std::make_unique<global_dffd::GlobalDffd>(s.obstacles, s.options);
  } catch (const std::exception& e) {
    fail(scenario + ": " + e.what());
  }
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) fail("cannot create output directory " + out_dir + ": " + error.message());
  const std::filesystem::path out(out_dir);
  std::string lines;
  std::string failed;  // the first frame that failed a check, and why
  double worst = 0.0;
  Progress progress("wrap " + s.name, s.frames + 1);
  for (int f = 0; f <= s.frames; ++f) {
    Frame frame;
    try {
      frame = wrapFrame(s, *dffd, f);
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.%s", f, sim::formatName(s.format));
      s.format == sim::WrapFormat::Ply ? mesh::savePly(frame.mesh, out / name) : mesh::saveObj(frame.mesh, out / name);
    } catch (const std::exception& e) {
      fail(scenario + ": frame " + std::to_string(f) + ": " + e.what());
    }
    const double penetration = frame.line["worst_penetration_m"].get<double>();
    worst = std::max(worst, penetration);
    const int loops = frame.line["boundary_loops"].get<int>();
    if (failed.empty() && penetration > s.tolerance_m)
      failed = "frame " + std::to_string(f) + " penetrates obstacle " + frame.line["deepest_obstacle"].dump() + " by " +
               core::formatNumber(penetration) + " m, over penetration_tolerance_m " +
               core::formatNumber(s.tolerance_m);
    if (failed.empty() && s.treatment != global_dffd::OpeningTreatment::Open && loops > 0)
      failed = "frame " + std::to_string(f) + " is not closed: " + std::to_string(loops) + " boundary loop(s) left " +
               sim::treatmentName(s.treatment);
    lines += frame.line.dump() + "\n";
    progress.update(f + 1);
  }
  progress.finish();
  try {
    core::writeFileAtomically(out / "frames.jsonl", lines);
  } catch (const core::FileError& e) {
    fail(e.what());
  }
  std::printf("incise wrap %s (%s): %d frames, %zu obstacles, min det J %.3g, worst penetration %.3g m; wrote %s\n",
              s.name.c_str(), sim::treatmentName(s.treatment), s.frames + 1, s.obstacles.size(), dffd->minJacobian(1),
              worst, out_dir.c_str());
  if (!failed.empty()) std::fprintf(stderr, "incise wrap: check failed: %s\n", failed.c_str());
  return failed.empty() ? 0 : 1;
}

}  // namespace

void addWrapCommand(CLI::App& app) {
  struct Args {
    std::string scenario, out = "out/wrap";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "wrap", "Move a model through obstacles with the global DFFD; write a mesh and a JSON line per frame");
  cmd->add_option("scenario", args->scenario, "wrap scenario (JSON, see scenarios/README.md)")->required();
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->callback([args] { std::exit(runWrap(args->scenario, args->out)); });
}

}  // namespace incise::apps::geometry
