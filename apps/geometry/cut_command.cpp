// `incise cut`: one scalpel stroke across a tissue surface, cut sample by sample as the simulation would,
// then the cut mesh (OBJ and/or PLY, wall faces marked) and a JSON summary in --out.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "data_dir.h"
#include "geometry_commands.h"
#include "incise/incision/stroke_path.h"
#include "incise/incision/surface_cutter.h"
#include "json_output.h"
#include "progress.h"
#include "scenario_run.h"

namespace incise::apps::geometry {

namespace {

enum class MeshFormat : std::uint8_t { Obj, Ply, Both };

// The --format value (CLI11 has checked it is one of the three).
MeshFormat meshFormat(const std::string& name) {
  return name == "ply" ? MeshFormat::Ply : name == "both" ? MeshFormat::Both : MeshFormat::Obj;
}

struct CutArgs {
  std::string mesh = shippedFile("meshes/bunny.obj");
  double scale = 0.01;  // the bunny's file is in centimetres
  int subdivide = 2;
  std::vector<double> start{-0.012, 0.0, 0.015};
  std::vector<double> direction{1.0, 0.0, 0.0};
  double length_m = 0.05;
  double bend_m = 0.0;
  double speed_m_per_s = 0.05;
  std::string out = "out/cut";
  MeshFormat format = MeshFormat::Obj;
  incision::CutterOptions cutter;
};

// The --refine value (CLI11 has checked it is one of the three).
incision::CutterOptions::Refine refineMode(const std::string& name) {
  return name == "off"  ? incision::CutterOptions::Refine::Off
         : name == "pn" ? incision::CutterOptions::Refine::PnTriangles
                        : incision::CutterOptions::Refine::Linear;
}

Eigen::Vector3d vec(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

[[noreturn]] void failWith(const std::string& message) { apps::failWith("cut", message); }

nlohmann::json optionsJson(const CutArgs& a) {
  const incision::IncisionOptions& i = a.cutter.incision;
  return {{"mesh", a.mesh},
          {"scale", a.scale},
          {"subdivide", a.subdivide},
          {"start_m", a.start},
          {"direction", a.direction},
          {"length_m", a.length_m},
          {"bend_m", a.bend_m},
          {"speed_m_per_s", a.speed_m_per_s},
          {"depth_m", i.depth_m},
          {"opening_m", i.opening_m},
          {"alpha_m", i.alpha_m},
          {"beta_m", i.beta_m},
          {"spacing_m", i.spacing_m},
          {"order", i.order},
          {"retraction_time_s", i.retraction_time_s},
          {"wall_rows", a.cutter.wall_rows},
          {"refine", toString(a.cutter.refine)},
          {"refine_edge_m", incision::refineEdgeLength(a.cutter)}};
}

// What the cutter did: counts, what refinement added, and per incision where its groove runs.
nlohmann::json statsJson(const incision::CutStats& stats) {
  return {{"edges_split", stats.edges_split},
          {"seam_vertices_duplicated", stats.vertices_duplicated},
          {"refined_vertices", stats.refined_vertices},
          {"refined_faces", stats.refined_faces},
          {"incision_figures", incisionFiguresJson(stats.figures)}};
}

int runCut(CutArgs& a) {
  mesh::SurfaceMesh mesh;
  try {
    mesh = mesh::subdivided(mesh::loadSurfaceMesh(a.mesh, a.scale), a.subdivide);
  } catch (const std::exception& e) {
    failWith(e.what());
  }
  const int euler_before = mesh::checkManifold(mesh.mesh()).euler_characteristic;
  incision::StrokePathOptions path;
  path.start_m = vec(a.start);
  path.direction = vec(a.direction);
  path.length_m = a.length_m;
  path.bend_m = a.bend_m;
  path.speed_m_per_s = a.speed_m_per_s;
  incision::Stroke stroke;
  std::unique_ptr<incision::SurfaceCutter> cutter;
  try {
    stroke = incision::strokeAlongPath(mesh, path);
    cutter = std::make_unique<incision::SurfaceCutter>(mesh, a.cutter);
  } catch (const std::exception& e) {
    failWith(e.what());
  }
  std::error_code error;
  std::filesystem::create_directories(a.out, error);
  if (error) failWith("cannot create output directory " + a.out + ": " + error.message());

  std::vector<double> sample_us;
  int skipped = 0;
  const auto time = [&](auto&& call) {
    const auto start = std::chrono::steady_clock::now();
    const incision::CutStep step = call();
    sample_us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    if (step.sample != incision::SampleStatus::Accepted) ++skipped;
    return step;
  };
  Progress progress("cut", static_cast<double>(stroke.samples.size()));
  time([&] { return cutter->begin(stroke.first, stroke.blade_direction); });
  for (std::size_t k = 0; k < stroke.samples.size(); ++k) {
    time([&] { return cutter->extend(stroke.samples[k]); });
    progress.update(static_cast<double>(k + 1));
  }
  progress.finish();
  cutter->finish();
  cutter->advance(stroke.samples.empty() ? stroke.first.time_s : stroke.samples.back().time_s);

  const mesh::MeshSummary summary = mesh::summarize(mesh);
  std::string failure = cutFailure(cutter->stats());
  if (failure.empty() && totalGroove_m(cutter->stats().figures) == 0.0) failure = "no groove was opened";
  const std::filesystem::path out(a.out);
  try {
    if (a.format != MeshFormat::Ply) mesh::saveObj(mesh, out / "cut.obj");
    if (a.format != MeshFormat::Obj) mesh::savePly(mesh, out / "cut.ply");
    nlohmann::json report = statsJson(cutter->stats());
    report.update({{"options", optionsJson(a)},
                   {"mesh", nlohmann::json::parse(mesh::toJson(summary))},
                   {"euler_characteristic_before", euler_before},
                   {"samples", stroke.samples.size() + 1},
                   {"samples_not_accepted", skipped},
                   {"per_sample", timingSummary(sample_us)},
                   {"failure", failure}});
    writeJsonAtomically(report, out / "summary.json");
  } catch (const std::exception& e) {
    failWith(e.what());
  }
  const bool ok = summary.closed_two_manifold && summary.euler_characteristic == euler_before && failure.empty();
  std::printf(
      "incise cut: %zu samples, %d edges refined, %d edges split, %d seam vertices opened, a groove of %.1f mm along %.1f mm of "
      "stroke in contact; %d vertices, %d faces (%d wall); "
      "closed two-manifold: %s, Euler characteristic %d -> %d; per sample p99 %.1f us; wrote %s\n",
      stroke.samples.size() + 1, cutter->stats().refined_vertices, cutter->stats().edges_split,
      cutter->stats().vertices_duplicated, 1e3 * totalGroove_m(cutter->stats().figures),
      1e3 * totalStroke_m(cutter->stats().figures), summary.vertices, summary.faces, summary.wall_faces,
      summary.closed_two_manifold ? "yes" : "NO", euler_before, summary.euler_characteristic,
      timingSummary(sample_us)["p99_us"].get<double>(), a.out.c_str());
  if (!failure.empty()) std::fprintf(stderr, "incise cut: the cut failed: %s\n", failure.c_str());
  return ok ? 0 : 1;
}

}  // namespace

void addCutCommand(CLI::App& app) {
  auto args = std::make_shared<CutArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cut", "Cut one scalpel stroke across a tissue surface; write the cut mesh and a JSON summary");
  cmd->add_option("--mesh", args->mesh, "closed triangle mesh (OBJ, PLY, OFF, STL)")->capture_default_str();
  cmd->add_option("--scale", args->scale, "metres per file unit")->capture_default_str();
  cmd->add_option("--subdivide", args->subdivide, "Loop subdivisions before cutting")
      ->capture_default_str()
      ->check(CLI::Range(0, 5));
  cmd->add_option("--start", args->start, "stroke start x y z (m); rays go down -y onto the surface")
      ->expected(3)
      ->capture_default_str();
  cmd->add_option("--direction", args->direction, "stroke direction x y z")->expected(3)->capture_default_str();
  cmd->add_option("--length", args->length_m, "stroke length (m)")->capture_default_str();
  cmd->add_option("--bend", args->bend_m, "sideways bulge at the middle (m)")->capture_default_str();
  cmd->add_option("--speed", args->speed_m_per_s, "blade speed (m/s), sampled at 1 kHz")->capture_default_str();
  cmd->add_option("--depth", args->cutter.incision.depth_m, "blade depth (m)")->capture_default_str();
  cmd->add_option("--opening", args->cutter.incision.opening_m, "wound width when retracted (m)")
      ->capture_default_str();
  cmd->add_option("--alpha", args->cutter.incision.alpha_m, "lattice spacing across the cut (m)")
      ->capture_default_str();
  cmd->add_option("--beta", args->cutter.incision.beta_m, "lattice spacing along the normal (m)")
      ->capture_default_str();
  cmd->add_option("--spacing", args->cutter.incision.spacing_m, "stroke resampling step (m)")->capture_default_str();
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->add_option_function<std::string>(
         "--refine", [args](const std::string& name) { args->cutter.refine = refineMode(name); },
         "local refinement ahead of the cut: linear (midpoints), pn (curved PN triangles) or off")
      ->check(CLI::IsMember({"linear", "pn", "off"}))
      ->default_str("linear");
  cmd->add_option("--refine-edge", args->cutter.refine_edge_m,
                  "longest edge refinement keeps near the cut (m); 0 = a quarter of the lattice's width")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option_function<std::string>(
         "--format", [args](const std::string& name) { args->format = meshFormat(name); }, "obj, ply or both")
      ->check(CLI::IsMember({"obj", "ply", "both"}))
      ->default_str("obj");
  cmd->callback([args] {
    const int code = runCut(*args);
    if (code != 0) std::exit(code);
  });
}

}  // namespace incise::apps::geometry
