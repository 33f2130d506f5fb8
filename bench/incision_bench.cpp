// Per-sample cost of growing a local DFFD incision.
// A 5 cm stroke over the bunny's back at 5 cm/s, sampled at 1 kHz (1000 samples), cut sample by sample on
// the bunny Loop-subdivided 3 times (235,136 triangles) and 4 times (940,544 triangles), one thread.
// Reports p50 / p99 / max of the time of SurfaceCutter::extend per sample, and the ratio of the larger
// mesh's p99 to the smaller one's. Targets: p99 <= 300 us; ratio <= 2 (the cost stays local). Also the time
// to make the cutter (cutter_setup_s: its grids, headroom and the thickness under each vertex).
// `--textured`: the bunny gets texture coordinates first (a planar map, subdivided with the mesh), so each
// split, flip and wall face carries them too: run with and without it side by side for their cost.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bunny_stroke.h"
#include "cut_timing.h"
#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "incise/measure/machine_info.h"
#include "incise/measure/percentile.h"

namespace {

using namespace incise;

using incise::measure::percentile;
using Clock = std::chrono::steady_clock;

constexpr double kTargetP99Us = 300.0;
constexpr double kTargetRatio = 2.0;
constexpr int kBudget = 32;

nlohmann::json runMesh(const mesh::SurfaceMesh& base, int subdivisions, int budget) {
  const auto t0 = Clock::now();
  mesh::SurfaceMesh mesh = mesh::subdivided(base, subdivisions);
  const double subdivide_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const incision::Stroke stroke = incise::bench::bunnyBackStroke(mesh);
  incision::CutterOptions options;
  options.max_inversions_per_call = budget;
  const auto setup_start = Clock::now();
  incision::SurfaceCutter cutter(mesh, options);  // grids, headroom, the thickness under each vertex
  const double cutter_setup_s = std::chrono::duration<double>(Clock::now() - setup_start).count();
  const std::vector<double> sample_us = incise::bench::timeSamples(cutter, stroke);
  int trailing_calls = 0;  // calls' worth of carried work still to do when the stroke ends (and after finish)
  while (cutter.pending() && trailing_calls < 1000) cutter.advance(stroke.samples.back().time_s), ++trailing_calls;
  const auto start = Clock::now();
  cutter.finish();
  const double finish_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  // The columns the end of the stroke made final, still under the budget: the cut reaches the last sample.
  while (cutter.pending() && trailing_calls < 100000) cutter.advance(stroke.samples.back().time_s), ++trailing_calls;
  const mesh::ManifoldReport report = mesh::checkManifold(mesh.mesh());
  return {
      {"subdivisions", subdivisions},
      {"max_inversions_per_call", budget},
      {"calls_to_catch_up_after_last_sample", trailing_calls},
      {"triangles", base.mesh().n_faces() * (1u << (2 * subdivisions))},
      {"samples", sample_us.size()},
      {"p50_us", percentile(sample_us, 0.50)},
      {"p99_us", percentile(sample_us, 0.99)},
      {"max_us", *std::max_element(sample_us.begin(), sample_us.end())},
      {"finish_us", finish_us},
      {"target_p99_us", kTargetP99Us},
      {"meets_target", percentile(sample_us, 0.99) <= kTargetP99Us},
      {"edges_split", cutter.stats().edges_split},
      {"seam_vertices_duplicated", cutter.stats().vertices_duplicated},
      {"closed_two_manifold_after", report.closed_two_manifold},
      {"subdivide_s", subdivide_s},
      {"cutter_setup_s", cutter_setup_s},
  };
}

}  // namespace

int main(int argc, char** argv) {
  const bool textured = argc > 1 && std::string(argv[1]) == "--textured";
  if (argc > 2 || (argc == 2 && !textured)) {
    std::fprintf(stderr, "usage: %s [--textured]\n", argv[0]);
    return 2;
  }
  mesh::SurfaceMesh bunny = mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01);
  if (textured) bench::mapPlanar(bunny);
  nlohmann::json report = {
      {"benchmark", "incision_per_sample"},
      {"textured", textured},
      {"stroke", "5 cm over the bunny's back, 1 kHz, 5 cm/s, spacing 0.5 mm, order 4"},
      {"threads", 1},
      {"machine", incise::measure::machineInfo()},
      {"results", nlohmann::json::array()},
  };
  // Unlimited: each call does all final work. Budgeted: at most kBudget inversions per call (about 1 kHz
  // frame's worth), the rest carried to the next call, as the simulation loop runs it.
  for (int budget : {0, kBudget}) {
    nlohmann::json pair = nlohmann::json::array();
    for (int subdivisions : {3, 4}) pair.push_back(runMesh(bunny, subdivisions, budget));
    const double ratio = pair[1]["p99_us"].get<double>() / pair[0]["p99_us"].get<double>();
    report["results"].push_back({{"max_inversions_per_call", budget},
                                 {"meshes", pair},
                                 {"p99_ratio_large_over_small", ratio},
                                 {"target_ratio", kTargetRatio},
                                 {"meets_ratio_target", ratio <= kTargetRatio}});
  }
  std::printf("%s\n", report.dump(2).c_str());
  return 0;
}
