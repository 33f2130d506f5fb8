// What the viewer tests share: a shipped scenario replayed fast with a GeometryMirror following it through
// the geometry stream, stopped at a time or run to its end.
#pragma once

#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "incise/devices/trace_csv.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/scenario.h"
#include "incise/sim/simulation.h"
#include "incise/sim/stroke_poses.h"

namespace incise::test {

struct FollowedRun {
  sim::Scenario scenario;
  std::unique_ptr<sim::World> world;
  std::vector<devices::PoseSample> poses;
  sim::GeometryStream stream;
  sim::GeometryMirror mirror;
  sim::ReplayReport report;

  // The tips of the poses that cut (what the default camera frames and the pixel tests project).
  std::vector<Eigen::Vector3d> stroke() const {
    std::vector<Eigen::Vector3d> out;
    const int button = scenario.world.tool.cut_button;
    for (const auto& p : poses)
      if (button < 0 || ((p.buttons >> button) & 1u)) out.push_back(p.tip_m);
    return out;
  }
};

// How a run is followed. `each_pull` runs after every pull (the mirror's changes still there), before they
// are cleared; `edit_scenario` changes the scenario before its tissue is loaded, `edit_tissue` the tissue
// loaded; `seed`: the mirror starts as a copy of the tissue (GeometryStream::seed, as the viewer does),
// else it asks for a re-sync and gets the tissue by a sweep within the stream's per-frame budget.
struct FollowOptions {
  double stop_after_s = std::numeric_limits<double>::infinity();
  std::function<void(FollowedRun&)> each_pull;
  std::function<void(sim::Scenario&)> edit_scenario;
  std::function<void(mesh::SurfaceMesh&)> edit_tissue;
  bool seed = false;
};

inline std::unique_ptr<FollowedRun> followRun(const std::string& name, const FollowOptions& f) {
  auto run = std::make_unique<FollowedRun>();
  run->scenario = sim::loadScenario(std::string(INCISE_SCENARIOS_DIR) + "/" + name + ".json");
  if (f.edit_scenario) f.edit_scenario(run->scenario);
  mesh::SurfaceMesh tissue = sim::loadTissue(run->scenario);
  if (f.edit_tissue) f.edit_tissue(tissue);
  run->poses = run->scenario.source == sim::Scenario::Source::Strokes
                   ? sim::posesForStrokes(tissue, run->scenario.strokes, run->scenario.world, run->scenario.rate_hz)
                   : devices::TraceReader::readAll(run->scenario.trace);
  run->world = std::make_unique<sim::World>(std::move(tissue), run->scenario.world);
  if (f.seed) run->stream.seed(*run->world, run->mirror);
  sim::ReplayOptions o;
  o.period_us = run->scenario.periodUs();
  o.settle_s = run->scenario.settle_s;
  o.stop_after_s = f.stop_after_s;
  o.geometry = &run->stream;
  FollowedRun* r = run.get();
  o.geometry_reader = [r, each_pull = f.each_pull] {
    r->mirror.pull(r->stream);
    if (each_pull) each_pull(*r);
    r->mirror.clearChanges();
  };
  run->report = sim::replay(*run->world, run->poses, o);
  return run;
}

inline std::unique_ptr<FollowedRun> followRun(const std::string& name,
                                              double stop_after_s = std::numeric_limits<double>::infinity(),
                                              const std::function<void(FollowedRun&)>& each_pull = {}) {
  FollowOptions f;
  f.stop_after_s = stop_after_s;
  f.each_pull = each_pull;
  return followRun(name, f);
}

// Two materials, "left" on the faces whose centre lies at x < the tissue's middle, "right" on the others.
inline void twoMaterials(mesh::SurfaceMesh& tissue) {
  mesh::TriMesh& m = tissue.mesh();
  double lo = 1e30, hi = -1e30;
  for (const auto v : m.vertices()) lo = std::min(lo, m.point(v)[0]), hi = std::max(hi, m.point(v)[0]);
  const int left = tissue.addMaterial({"left", {}}), right = tissue.addMaterial({"right", {}});
  for (const auto f : m.faces()) {
    double x = 0.0;
    for (const auto v : m.fv_range(f)) x += m.point(v)[0] / 3.0;
    tissue.setMaterial(f, x < 0.5 * (lo + hi) ? left : right);
  }
}

}  // namespace incise::test
