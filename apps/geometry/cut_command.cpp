// `incise cut`: one scalpel stroke across a tissue surface, cut sample by sample as the simulation would,
// then the cut mesh (OBJ and/or PLY, wall faces marked) and a JSON summary in --out.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "data_dir.h"
#include "geometry_commands.h"
#include "incise/jobs/cut_job.h"
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
  jobs::CutJobOptions job;  // the mesh from `mesh`, the start and direction from `start` and `direction`
  std::string mesh = shippedFile("meshes/bunny.obj");
  std::vector<double> start = list(job.start_m);
  std::vector<double> direction = list(job.direction);
  std::string out = "out/cut";
  MeshFormat format = MeshFormat::Obj;
  static std::vector<double> list(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
};

// The --refine value (CLI11 has checked it is one of the three).
incision::CutterOptions::Refine refineMode(const std::string& name) {
  return name == "off"  ? incision::CutterOptions::Refine::Off
         : name == "pn" ? incision::CutterOptions::Refine::PnTriangles
                        : incision::CutterOptions::Refine::Linear;
}

Eigen::Vector3d vec(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

[[noreturn]] void failCut(const std::string& message) { apps::failWith("cut", message); }

int runCut(CutArgs& a) {
  a.job.mesh = a.mesh;
  a.job.start_m = vec(a.start);
  a.job.direction = vec(a.direction);
  std::unique_ptr<jobs::CutJob> job;
  try {
    job = std::make_unique<jobs::CutJob>(a.job);
  } catch (const std::exception& e) {
    failCut(e.what());
  }
  std::error_code error;
  std::filesystem::create_directories(a.out, error);
  if (error) failCut("cannot create output directory " + a.out + ": " + error.message());

  Progress progress("cut", static_cast<double>(job->samples() - 1));
  job->run([&progress](std::size_t done, std::size_t) { progress.update(static_cast<double>(done)); });
  progress.finish();

  const mesh::SurfaceMesh& mesh = job->mesh();
  const mesh::MeshSummary summary = mesh::summarize(mesh);
  const std::string failure = job->failure();
  const std::filesystem::path out(a.out);
  try {
    if (a.format != MeshFormat::Ply) mesh::saveObj(mesh, out / "cut.obj");
    if (a.format != MeshFormat::Obj) mesh::savePly(mesh, out / "cut.ply");
    writeJsonAtomically(job->summary(summary), out / "summary.json");
  } catch (const std::exception& e) {
    failCut(e.what());
  }
  const incision::CutStats& stats = job->stats();
  std::printf(
      "incise cut: %zu samples, %d edges refined, %d edges split, %d seam vertices opened, a groove of %.1f mm along %.1f mm of "
      "stroke in contact; %d vertices, %d faces (%d wall); "
      "closed two-manifold: %s, Euler characteristic %d -> %d; per sample p99 %.1f us; wrote %s\n",
      job->samples(), stats.refined_vertices, stats.edges_split, stats.vertices_duplicated,
      1e3 * totalGroove_m(stats.figures), 1e3 * totalStroke_m(stats.figures), summary.vertices, summary.faces,
      summary.wall_faces, summary.closed_two_manifold ? "yes" : "NO", job->eulerBefore(), summary.euler_characteristic,
      timingSummary(job->sampleUs())["p99_us"].get<double>(), a.out.c_str());
  for (const incision::IncisionFigures& f : stats.figures) {
    if (f.through != incision::ThroughCut::Made) continue;
    std::printf("incise cut: the blade went through the tissue (%d samples): %d closed piece%s", f.through_samples,
                f.pieces, f.pieces == 1 ? "" : "s");
    for (int i = 0; i < std::min(f.pieces, incision::IncisionFigures::kListedPieces); ++i)
      std::printf("%s%.1f cm^3", i == 0 ? ", volumes " : ", ", 1e6 * f.piece_volumes_m3[static_cast<std::size_t>(i)]);
    std::printf("\n");
  }
  if (!failure.empty()) std::fprintf(stderr, "incise cut: the cut failed: %s\n", failure.c_str());
  return job->ok(summary) ? 0 : 1;
}

}  // namespace

void addCutCommand(CLI::App& app) {
  auto args = std::make_shared<CutArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cut", "Cut one scalpel stroke across a tissue surface; write the cut mesh and a JSON summary");
  cmd->add_option("--mesh", args->mesh, "closed triangle mesh (OBJ, PLY, OFF, STL)")->capture_default_str();
  cmd->add_option("--scale", args->job.scale, "metres per file unit")->capture_default_str();
  cmd->add_option("--subdivide", args->job.subdivide, "Loop subdivisions before cutting")
      ->capture_default_str()
      ->check(CLI::Range(0, 5));
  cmd->add_option("--start", args->start, "stroke start x y z (m); rays go down -y onto the surface")
      ->expected(3)
      ->capture_default_str();
  cmd->add_option("--direction", args->direction, "stroke direction x y z")->expected(3)->capture_default_str();
  cmd->add_option("--length", args->job.length_m, "stroke length (m)")->capture_default_str();
  cmd->add_option("--bend", args->job.bend_m, "sideways bulge at the middle (m)")->capture_default_str();
  cmd->add_option("--speed", args->job.speed_m_per_s, "blade speed (m/s), sampled at 1 kHz")->capture_default_str();
  cmd->add_option("--depth", args->job.cutter.incision.depth_m, "blade depth (m)")->capture_default_str();
  cmd->add_option("--opening", args->job.cutter.incision.opening_m, "wound width when retracted (m)")
      ->capture_default_str();
  cmd->add_option("--alpha", args->job.cutter.incision.alpha_m, "lattice spacing across the cut (m)")
      ->capture_default_str();
  cmd->add_option("--beta", args->job.cutter.incision.beta_m, "lattice spacing along the normal (m)")
      ->capture_default_str();
  cmd->add_option("--spacing", args->job.cutter.incision.spacing_m, "stroke resampling step (m)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->add_option_function<std::string>(
         "--refine", [args](const std::string& name) { args->job.cutter.refine = refineMode(name); },
         "local refinement ahead of the cut: linear (midpoints), pn (curved PN triangles) or off")
      ->check(CLI::IsMember({"linear", "pn", "off"}))
      ->default_str("linear");
  cmd->add_option("--refine-edge", args->job.cutter.refine_edge_m,
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
