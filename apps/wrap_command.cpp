// `incise wrap SCENARIO [--out DIR]`: the global DFFD (paper §3). A model translates along v (y) through
// static obstacles over N frames; at every frame it is split at the discontinuities and mapped through F,
// left open, stitched or capped. Writes DIR/frame_NNNN.obj (or .ply) per frame, DIR/frames.jsonl (one JSON
// line per frame: vertices, faces, boundary loops, worst penetration into an obstacle, min det J, times)
// and prints a summary; a progress bar on stderr when it is a terminal. The scenario format is in
// scenarios/README.md ("Wrap scenarios"). Exit codes: 2 bad input (the file and key, or the obstacle and
// reason), 1 a frame penetrates an obstacle or a stitched/capped frame is not closed, 0 otherwise.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "incise/cutting/global_dffd.h"
#include "incise/cutting/shapes.h"
#include "json_output.h"
#include "scenario_run.h"

namespace incise::apps {

namespace {

using namespace incise::cutting;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

[[noreturn]] void fail(const std::string& message) { failWith("wrap", message); }

// Typed access to a JSON object that names the file and the key path in every error.
struct Keys {
  std::filesystem::path file;
  const json& object;
  std::string path;

  [[noreturn]] void bad(const std::string& key, const std::string& what) const {
    fail(file.string() + ": " + (path.empty() ? key : path + "." + key) + ": " + what);
  }
  bool has(const char* key) const { return object.contains(key); }
  Keys child(const char* key) const {
    if (!has(key) || !object.at(key).is_object()) bad(key, "must be an object");
    return {file, object.at(key), path.empty() ? key : path + "." + key};
  }
  double number(const char* key, double fallback, double lo, double hi) const {
    if (!has(key)) return fallback;
    if (!object.at(key).is_number()) bad(key, "must be a number, got " + object.at(key).dump());
    const double x = object.at(key).get<double>();
    if (!(x >= lo && x <= hi)) bad(key, object.at(key).dump() + " is outside [" + num(lo) + ", " + num(hi) + "]");
    return x;
  }
  int integer(const char* key, int fallback, int lo, int hi) const {
    if (!has(key)) return fallback;
    if (!object.at(key).is_number_integer()) bad(key, "must be an integer, got " + object.at(key).dump());
    const long long x = object.at(key).get<long long>();
    if (x < lo || x > hi) bad(key, std::to_string(x) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(x);
  }
  std::string text(const char* key, const char* fallback) const {
    if (!has(key)) {
      if (!fallback) bad(key, "is missing");
      return fallback;
    }
    if (!object.at(key).is_string()) bad(key, "must be a string, got " + object.at(key).dump());
    return object.at(key).get<std::string>();
  }
  bool boolean(const char* key, bool fallback) const {
    if (!has(key)) return fallback;
    if (!object.at(key).is_boolean()) bad(key, "must be true or false");
    return object.at(key).get<bool>();
  }
  Eigen::Vector3d vec(const char* key, const Eigen::Vector3d& fallback) const {
    if (!has(key)) return fallback;
    const json& v = object.at(key);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      bad(key, "must be an array of 3 numbers, got " + v.dump());
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  }
  static std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }
};

// A closed mesh from a scenario entry: a file ("mesh", "scale", "subdivide") or a shape ("shape": box,
// cylinder, sphere, prism with "outline": "face", robot), then scaled per axis ("stretch") and moved
// ("offset_m").
SurfaceMesh meshOf(const Keys& k) {
  SurfaceMesh mesh;
  if (k.has("mesh")) {
    const std::filesystem::path p = k.file.parent_path() / k.text("mesh", nullptr);
    if (!std::filesystem::exists(p)) k.bad("mesh", "file " + p.string() + " does not exist");
    mesh = subdivided(loadSurfaceMesh(p, k.number("scale", 1.0, 1e-9, 1e9)), k.integer("subdivide", 0, 0, 4));
  } else {
    const std::string shape = k.text("shape", nullptr);
    if (shape == "box") {
      mesh = makeBox(Eigen::AlignedBox3d(k.vec("min_m", Eigen::Vector3d::Constant(-0.01)), k.vec("max_m", Eigen::Vector3d::Constant(0.01))),
                     k.integer("divisions", 8, 1, 1000));
    } else if (shape == "cylinder") {
      mesh = makeCylinder(k.vec("base_m", Eigen::Vector3d::Zero()), k.vec("axis_m", Eigen::Vector3d(0, 0, 0.05)),
                          k.number("radius_m", 0.005, 1e-6, 10.0), k.integer("segments", 48, 3, 100000), k.integer("rings", 4, 1, 100000),
                          k.integer("cap_rings", 2, 1, 100000));
    } else if (shape == "sphere") {
      mesh = makeSphere(k.vec("centre_m", Eigen::Vector3d::Zero()), k.number("radius_m", 0.01, 1e-6, 10.0), k.integer("subdivisions", 3, 0, 8));
    } else if (shape == "prism") {
      if (k.text("outline", "face") != "face") k.bad("outline", "must be \"face\" (the silhouette of a face in profile)");
      mesh = makePrism(faceSilhouette(k.number("height_m", 0.03, 1e-6, 10.0), k.integer("points", 120, 25, 100000)),
                       k.number("z0_m", -0.02, -10.0, 10.0), k.number("z1_m", 0.02, -10.0, 10.0), k.integer("rings", 4, 1, 10000));
    } else if (shape == "robot") {
      mesh = makeRobot(k.number("height_m", 0.1, 1e-4, 100.0), k.integer("detail", kRobotDetail30k, 1, 200));
    } else {
      k.bad("shape", "must be box, cylinder, sphere, prism or robot, got \"" + shape + "\"");
    }
  }
  const Eigen::Vector3d stretch = k.vec("stretch", Eigen::Vector3d::Ones());
  const Eigen::Vector3d offset = k.vec("offset_m", Eigen::Vector3d::Zero());
  if ((stretch.array() <= 0).any()) k.bad("stretch", "must be positive");
  // Then rotated about x (e.g. 90 turns a y-up model z-up), then moved.
  const double angle = k.number("rotate_x_deg", 0.0, -360.0, 360.0) * M_PI / 180.0;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
  TriMesh& m = mesh.mesh();
  for (const auto v : m.vertices()) m.set_point(v, toOpenMesh(rotation * toEigen(m.point(v)).cwiseProduct(stretch) + offset));
  return mesh;
}

struct WrapScenario {
  std::string name;
  SurfaceMesh model;
  std::vector<Obstacle> obstacles;
  GlobalDffdOptions options;
  std::string treatment = "open";  // open, stitched, capped
  Eigen::Vector3d translate_m{0.0, 0.1, 0.0};
  int frames = 20;
  std::string format = "obj";
  double tolerance_m = 1e-6;
};

WrapScenario loadWrap(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) fail(file.string() + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  json doc;
  try {
    doc = json::parse(text.str());
  } catch (const json::parse_error& e) {
    fail(file.string() + ": JSON syntax error at byte " + std::to_string(e.byte));
  }
  if (!doc.is_object()) fail(file.string() + ": the document must be a JSON object");
  const Keys root{file, doc, ""};
  WrapScenario s;
  s.name = root.text("name", file.stem().string().c_str());
  try {
    s.model = meshOf(root.child("model"));
    if (!root.has("obstacles") || !doc.at("obstacles").is_array() || doc.at("obstacles").empty())
      root.bad("obstacles", "must be a non-empty array");
    for (size_t i = 0; i < doc.at("obstacles").size(); ++i) {
      const json& entry = doc.at("obstacles")[i];
      if (!entry.is_object()) root.bad("obstacles[" + std::to_string(i) + "]", "must be an object");
      const Keys o{file, entry, "obstacles[" + std::to_string(i) + "]"};
      const std::string name = o.text("name", ("obstacle " + std::to_string(i)).c_str());
      try {
        s.obstacles.push_back({name, meshOf(o)});
      } catch (const MeshError& e) {
        fail(file.string() + ": obstacle '" + name + "': " + e.what());
      }
    }
  } catch (const std::invalid_argument& e) {
    fail(file.string() + ": " + e.what());
  } catch (const MeshError& e) {
    fail(file.string() + ": " + e.what());
  }
  if (root.has("lattice")) {
    const Keys l = root.child("lattice");
    GlobalDffdOptions& o = s.options;
    o.order = l.integer("order", o.order, 2, 8);
    if (l.has("controls")) {
      const Eigen::Vector3d c = l.vec("controls", Eigen::Vector3d::Zero());
      for (int a = 0; a < 3; ++a) o.controls[static_cast<size_t>(a)] = static_cast<int>(c[a]);
    }
    o.margin_m = l.number("margin_m", o.margin_m, 0.0, 100.0);
    const std::string kernel = l.text("kernel", "bspline");
    if (kernel != "bspline" && kernel != "gaussian") l.bad("kernel", "must be \"bspline\" or \"gaussian\"");
    o.kernel = kernel == "gaussian" ? DffdKernel::Gaussian : DffdKernel::QuadraticBSpline;
    o.kernel_width = l.number("kernel_width", o.kernel_width, 1e-3, 1e4);
    o.clearance_m = l.number("clearance_m", o.clearance_m, 0.0, 1.0);
    o.v_knots = l.boolean("v_knots", o.v_knots == VKnots::AtObstacleExtremes) ? VKnots::AtObstacleExtremes : VKnots::None;
    const std::string fold = l.text("on_fold", "refuse");
    if (fold != "refuse" && fold != "widen") l.bad("on_fold", "must be \"refuse\" or \"widen\"");
    o.on_fold = fold == "widen" ? FoldPolicy::Widen : FoldPolicy::Refuse;
  }
  s.treatment = root.text("treatment", "open");
  if (s.treatment != "open" && s.treatment != "stitched" && s.treatment != "capped")
    root.bad("treatment", "must be \"open\", \"stitched\" or \"capped\", got \"" + s.treatment + "\"");
  if (root.has("motion")) {
    const Keys m = root.child("motion");
    s.translate_m = m.vec("translate_m", s.translate_m);
    s.frames = m.integer("frames", s.frames, 1, 100000);
  }
  try {
    validateModel(s.model, s.treatment == "capped" ? ModelClosure::Closed : ModelClosure::MayBeOpen);
  } catch (const DffdError& e) {
    root.bad("model", e.what());
  }
  s.format = root.text("format", "obj");
  if (s.format != "obj" && s.format != "ply") root.bad("format", "must be \"obj\" or \"ply\"");
  s.tolerance_m = root.number("penetration_tolerance_m", s.tolerance_m, 0.0, 1.0);
  return s;
}

struct Frame {
  SurfaceMesh mesh;
  json line;
};

Frame wrapFrame(const WrapScenario& s, const GlobalDffd& base, int f) {
  const Eigen::Vector3d offset = s.translate_m * (double(f) / s.frames);
  SurfaceMesh moved = s.model;
  TriMesh& m = moved.mesh();
  for (const auto v : m.vertices()) m.set_point(v, toOpenMesh(toEigen(m.point(v)) + offset));
  const auto t0 = Clock::now();
  Frame out;
  double min_det_j = 0.0;
  if (s.treatment == "capped") {
    out.mesh = cappedDeform(moved, base);
    min_det_j = base.minJacobian(1);
  } else {
    const DffdSplit split = splitAtDiscontinuities(moved, base, s.treatment == "stitched" ? Openings::Close : Openings::Leave);
    GlobalDffd dffd = base;
    if (s.treatment == "stitched")
      for (int i = 0; i < static_cast<int>(dffd.obstacles().size()); ++i) dffd.stitch(i, stitchLevel(split, dffd, i));
    out.mesh = deformSplit(split, dffd);
    min_det_j = dffd.minJacobian(1);
  }
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  std::string deepest;
  const double penetration = worstPenetration(out.mesh.mesh(), s.obstacles, &deepest);
  const TriMesh& r = out.mesh.mesh();
  out.line = {{"frame", f},
              {"offset_m", {offset.x(), offset.y(), offset.z()}},
              {"vertices", r.n_vertices()},
              {"faces", r.n_faces()},
              {"boundary_loops", boundaryLoops(r)},
              {"worst_penetration_m", penetration},
              {"deepest_obstacle", deepest},
              {"min_det_j", min_det_j},
              {"split_and_deform_ms", ms}};
  return out;
}

void progress(int done, int total) {
  if (!isatty(fileno(stderr))) return;
  const int width = 40, filled = width * done / total;
  std::fprintf(stderr, "\r[%s%s] %d/%d", std::string(static_cast<size_t>(filled), '#').c_str(),
               std::string(static_cast<size_t>(width - filled), ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

int runWrap(const std::string& scenario, const std::string& out_dir) {
  const WrapScenario s = loadWrap(scenario);
  std::unique_ptr<GlobalDffd> dffd;
  try {
    dffd = std::make_unique<GlobalDffd>(s.obstacles, s.options);
  } catch (const std::exception& e) {
    fail(scenario + ": " + e.what());
  }
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) fail("cannot create output directory " + out_dir + ": " + error.message());
  const std::filesystem::path out(out_dir);
  std::string lines;
  bool ok = true;
  double worst = 0.0;
  for (int f = 0; f <= s.frames; ++f) {
    Frame frame;
    try {
      frame = wrapFrame(s, *dffd, f);
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.%s", f, s.format.c_str());
      s.format == "ply" ? savePly(frame.mesh, out / name) : saveObj(frame.mesh, out / name);
    } catch (const std::exception& e) {
      fail(scenario + ": frame " + std::to_string(f) + ": " + e.what());
    }
    const double penetration = frame.line["worst_penetration_m"].get<double>();
    worst = std::max(worst, penetration);
    ok = ok && penetration <= s.tolerance_m && (s.treatment == "open" || frame.line["boundary_loops"].get<int>() == 0);
    lines += frame.line.dump() + "\n";
    progress(f + 1, s.frames + 1);
  }
  {
    std::ofstream jsonl(out / "frames.jsonl.tmp", std::ios::binary);
    jsonl << lines;
    if (!jsonl.flush()) fail("cannot write " + (out / "frames.jsonl").string());
  }
  std::filesystem::rename(out / "frames.jsonl.tmp", out / "frames.jsonl", error);
  if (error) fail("cannot write " + (out / "frames.jsonl").string() + ": " + error.message());
  std::printf("incise wrap %s (%s): %d frames, %zu obstacles, min det J %.3g, worst penetration %.3g m; wrote %s\n",
              s.name.c_str(), s.treatment.c_str(), s.frames + 1, s.obstacles.size(), dffd->minJacobian(1), worst,
              out_dir.c_str());
  return ok ? 0 : 1;
}

}  // namespace

void addWrapCommand(CLI::App& app) {
  struct Args {
    std::string scenario, out = "out/wrap";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("wrap", "Move a model through obstacles with the global DFFD; write a mesh and a JSON line per frame");
  cmd->add_option("scenario", args->scenario, "wrap scenario (JSON, see scenarios/README.md)")->required();
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->callback([args] { std::exit(runWrap(args->scenario, args->out)); });
}

}  // namespace incise::apps
