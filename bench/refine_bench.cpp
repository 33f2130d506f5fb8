// Per-sample cost of local refinement ahead of the cut. Two cases, each cut
// sample by sample (5 cm/s, 1 kHz) with refinement on and against the same stroke on a mesh fine enough
// beforehand (refinement off there):
//  - coarse: a 10 cm icosphere of 4-7 mm edges (642 vertices), a 3.5 cm stroke over its top, refined along
//    the stroke (to the default 1.5 mm, and to 2 mm); against the same sphere Loop-subdivided twice first
//    (16x the faces everywhere, as a user had to before);
//  - bunny: the 235,136-triangle bunny (3 Loop subdivisions, 0.5 mm edges: nothing to refine) and the 5 cm
//    stroke over its back, with refinement on (its checks alone) and off.
// Every configuration runs kRuns times, interleaved, at the simulation's budget (32 inversions a call) and
// unlimited; reported: the median over runs of the per-sample p50 / p99 / max, the refinement's vertices,
// the groove against the stroke, and the ratio of p99s. Target: refined p99 within 10% of the pre-subdivided.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bunny_stroke.h"
#include "cut_timing.h"
#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "incise/measure/machine_info.h"
#include "incise/measure/percentile.h"
#include "incise/mesh/shapes.h"

namespace {

using namespace incise;

using incise::measure::percentile;

constexpr double kTargetRatio = 1.10;
constexpr int kRuns = 5;

struct Config {
  const char* name;
  const mesh::SurfaceMesh* mesh;
  incision::CutterOptions::Refine refine;
  bool bunny;                  // the bunny's back stroke, else the sphere's top stroke
  double refine_edge_m = 0.0;  // CutterOptions::refine_edge_m (0: the default, 1.5 mm)
};

incision::Stroke strokeFor(const Config& c, const mesh::SurfaceMesh& mesh) {
  if (c.bunny) return incise::bench::bunnyBackStroke(mesh);
  incision::StrokePathOptions path;
  path.start_m = Eigen::Vector3d(-0.0175, 0.1, 0.0011);
  path.length_m = 0.035;
  return incision::strokeAlongPath(mesh, path);
}

// One cut: per-sample times (us) and the figures.
struct Run {
  std::vector<double> sample_us;
  incision::IncisionFigures figures;
  int refined_vertices = 0;
  bool closed = false;
};

Run cutOnce(const Config& c, int budget) {
  mesh::SurfaceMesh mesh = *c.mesh;
  const incision::Stroke stroke = strokeFor(c, mesh);
  incision::CutterOptions options;
  options.max_inversions_per_call = budget;
  options.refine = c.refine;
  options.refine_edge_m = c.refine_edge_m;
  incision::SurfaceCutter cutter(mesh, options);
  Run run;
  run.sample_us = incise::bench::timeSamples(cutter, stroke);
  cutter.finish(incision::FinishWork::Later);
  for (int calls = 0; cutter.pending() && calls < 100000; ++calls) cutter.advance(stroke.samples.back().time_s);
  cutter.advance(stroke.samples.back().time_s + 1.0);
  run.figures = cutter.stats().figures.back();
  run.refined_vertices = cutter.stats().refined_vertices;
  run.closed = mesh::checkManifold(mesh.mesh()).closed_two_manifold;
  return run;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

nlohmann::json summarize(const Config& c, int budget, const std::vector<Run>& runs) {
  std::vector<double> p50, p99, max;
  for (const Run& r : runs) {
    p50.push_back(percentile(r.sample_us, 0.50));
    p99.push_back(percentile(r.sample_us, 0.99));
    max.push_back(*std::max_element(r.sample_us.begin(), r.sample_us.end()));
  }
  const Run& r = runs.front();
  return {{"mesh", c.name},
          {"triangles", c.mesh->mesh().n_faces()},
          {"refine", toString(c.refine)},
          {"refine_edge_m",
           c.refine_edge_m > 0.0 ? c.refine_edge_m : incision::refineEdgeLength(incision::CutterOptions{})},
          {"max_inversions_per_call", budget},
          {"runs", runs.size()},
          {"samples", r.sample_us.size()},
          {"p50_us", median(p50)},
          {"p99_us", median(p99)},
          {"p99_us_each_run", p99},
          {"max_us", median(max)},
          {"refined_vertices", r.refined_vertices},
          {"stroke_length_m", r.figures.stroke_length_m},
          {"groove_length_m", r.figures.groove_length_m},
          {"shortfall", toString(r.figures.shortfall)},
          {"closed_two_manifold_after", r.closed}};
}

}  // namespace

int main() {
  const mesh::SurfaceMesh sphere = mesh::makeSphere(Eigen::Vector3d::Zero(), 0.05, 3);
  const mesh::SurfaceMesh sphere_subdivided = mesh::subdivided(sphere, 2);
  const mesh::SurfaceMesh bunny =
      mesh::subdivided(mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01), 3);
  const std::vector<std::pair<Config, Config>> pairs = {
      {{"icosphere r 5 cm, 3 subdivisions (4-7 mm edges)", &sphere, incision::CutterOptions::Refine::Linear, false},
       {"the same, Loop-subdivided twice beforehand", &sphere_subdivided, incision::CutterOptions::Refine::Off, false}},
      // Refined to 2 mm: about the pre-subdivided mesh's own density (its edges are 1-2 mm).
      {{"icosphere r 5 cm, 3 subdivisions, refined to 2 mm", &sphere, incision::CutterOptions::Refine::Linear, false,
        0.002},
       {"the same, Loop-subdivided twice beforehand", &sphere_subdivided, incision::CutterOptions::Refine::Off, false}},
      {{"bunny, 3 Loop subdivisions", &bunny, incision::CutterOptions::Refine::Linear, true},
       {"bunny, 3 Loop subdivisions", &bunny, incision::CutterOptions::Refine::Off, true}},
  };
  nlohmann::json report = {
      {"benchmark", "refine_per_sample"},
      {"stroke", "sphere: 3.5 cm over the top; bunny: 5 cm over the back; 1 kHz, 5 cm/s, spacing 0.5 mm, order 4"},
      {"threads", 1},
      {"machine", incise::measure::machineInfo()},
      {"results", nlohmann::json::array()},
  };
  for (const int budget : {32, 0}) {
    for (const auto& [refined, before] : pairs) {
      std::vector<Run> a, b;
      for (int k = 0; k < kRuns; ++k) {  // interleaved: the VM's slow and fast spells fall on both
        a.push_back(cutOnce(refined, budget));
        b.push_back(cutOnce(before, budget));
      }
      const nlohmann::json ja = summarize(refined, budget, a), jb = summarize(before, budget, b);
      const double ratio = ja["p99_us"].get<double>() / jb["p99_us"].get<double>();
      report["results"].push_back({{"refined", ja},
                                   {"fine_beforehand", jb},
                                   {"p99_ratio_refined_over_fine", ratio},
                                   {"target_ratio", kTargetRatio},
                                   {"meets_target", ratio <= kTargetRatio}});
    }
  }
  std::printf("%s\n", report.dump(2).c_str());
  return 0;
}
