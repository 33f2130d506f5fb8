#include "incise/sim/wrap_scenario.h"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "incise/core/format.h"
#include "incise/mesh/shapes.h"
#include "incise/sim/scenario_keys.h"
#include "json_reader.h"

namespace incise::sim {

namespace {

using nlohmann::json;
using Reader = detail::JsonReader;
using mesh::SurfaceMesh;

// The most triangles one model or obstacle may have. A wrap scene is a real-time global-DFFD scene: its frame
// target is a few milliseconds on the ~30k-vertex robot (65,088 triangles), so a mesh of more than about
// 200,000 triangles cannot keep up. The shapes' parameters alone allowed far more (a sphere of 8
// subdivisions: 1.3 million, 25 s to build under ASan; a box of 1000 divisions: 12 million), so each count is
// computed from the parameters before anything is built.
constexpr long long kMaxWrapTriangles = 1LL << 18;  // 262,144

// 1234567 -> "1,234,567".
std::string grouped(long long n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && digits[i - 1] != '-' && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// "1 ring", "1,024 segments".
std::string counted(long long n, const char* noun) { return grouped(n) + " " + noun + (n == 1 ? "" : "s"); }

// Refuses at `key` a mesh of `triangles` (described by `what`, "a sphere of 8 subdivisions") over the limit.
void requireTriangles(const Reader& k, const char* key, const std::string& what, long long triangles,
                      const char* kind) {
  if (triangles <= kMaxWrapTriangles) return;
  k.fail(
      what + " has " + grouped(triangles) + " triangles; " + kind + " may have at most " + grouped(kMaxWrapTriangles),
      key);
}

// Of the keys `names` with their `values`, the one with the largest value (the first on ties): where a
// shape's size is refused.
const char* largest(const std::vector<const char*>& names, const std::vector<int>& values) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < values.size(); ++i)
    if (values[i] > values[best]) best = i;
  return names[best];
}

// A box of n divisions: 6 faces of n x n quads, 12 n^2 triangles (mesh/shapes.h, makeBox).
SurfaceMesh boxOf(const Reader& k) {
  const Eigen::AlignedBox3d box(k.vector("min_m", Eigen::Vector3d::Constant(-0.01)),
                                k.vector("max_m", Eigen::Vector3d::Constant(0.01)));
  const int n = k.integer("divisions", 8, 1, 1000);
  requireTriangles(k, "divisions", "a box of " + counted(n, "division"), 12LL * n * n, "a shape");
  return mesh::makeBox(box, n);
}

// A cylinder: 2 segments (rings + 2 cap_rings - 1) triangles (makeCylinder).
SurfaceMesh cylinderOf(const Reader& k) {
  const Eigen::Vector3d base = k.vector("base_m", Eigen::Vector3d::Zero());
  const Eigen::Vector3d axis = k.vector("axis_m", Eigen::Vector3d(0, 0, 0.05));
  const double radius = k.number("radius_m", 0.005, 1e-6, 10.0);
  const int segments = k.integer("segments", 48, 3, 100000);
  const int rings = k.integer("rings", 4, 1, 100000);
  const int cap_rings = k.integer("cap_rings", 2, 1, 100000);
  requireTriangles(k, largest({"segments", "rings", "cap_rings"}, {segments, rings, cap_rings}),
                   "a cylinder of " + counted(segments, "segment") + ", " + counted(rings, "ring") + " and " +
                       counted(cap_rings, "cap ring"),
                   2LL * segments * (rings + 2LL * cap_rings - 1), "a shape");
  return mesh::makeCylinder(base, axis, radius, segments, rings, cap_rings);
}

// An icosphere: 20 * 4^subdivisions triangles (makeSphere).
SurfaceMesh sphereOf(const Reader& k) {
  const Eigen::Vector3d centre = k.vector("centre_m", Eigen::Vector3d::Zero());
  const double radius = k.number("radius_m", 0.01, 1e-6, 10.0);
  const int subdivisions = k.integer("subdivisions", 3, 0, 8);
  requireTriangles(k, "subdivisions", "a sphere of " + counted(subdivisions, "subdivision"), 20LL << (2 * subdivisions),
                   "a shape");
  return mesh::makeSphere(centre, radius, subdivisions);
}

// The face silhouette of n points extruded in `rings` layers: 2 n rings + 2 (n - 2) triangles (makePrism).
SurfaceMesh prismOf(const Reader& k) {
  if (k.text("outline", "face") != "face") k.fail("must be \"face\" (the silhouette of a face in profile)", "outline");
  const double height = k.number("height_m", 0.03, 1e-6, 10.0);
  const int points = k.integer("points", 120, 25, 100000);
  const double z0 = k.number("z0_m", -0.02, -10.0, 10.0), z1 = k.number("z1_m", 0.02, -10.0, 10.0);
  const int rings = k.integer("rings", 4, 1, 10000);
  requireTriangles(k, largest({"points", "rings"}, {points, rings}),
                   "a prism of " + counted(points, "point") + " and " + counted(rings, "ring"),
                   2LL * points * rings + 2LL * (points - 2), "a shape");
  return mesh::makePrism(mesh::faceSilhouette(height, points), z0, z1, rings);
}

// The robot of detail d: 1032 d^2 - 120 d triangles (makeRobot).
SurfaceMesh robotOf(const Reader& k) {
  const double height = k.number("height_m", 0.1, 1e-4, 100.0);
  const int d = k.integer("detail", mesh::kRobotDetail30k, 1, 200);
  requireTriangles(k, "detail", "a robot of detail " + std::to_string(d), 1032LL * d * d - 120LL * d, "a shape");
  return mesh::makeRobot(height, d);
}

// A shape ("shape": box, cylinder, sphere, prism with "outline": "face", robot) from its keys.
SurfaceMesh shapeOf(const Reader& k) {
  const std::string shape = k.text("shape", nullptr);
  if (shape == "box") return boxOf(k);
  if (shape == "cylinder") return cylinderOf(k);
  if (shape == "sphere") return sphereOf(k);
  if (shape == "prism") return prismOf(k);
  if (shape == "robot") return robotOf(k);
  k.fail("must be box, cylinder, sphere, prism or robot, got \"" + shape + "\"", "shape");
}

// A mesh file ("mesh", "scale") Loop-subdivided "subdivide" times: its triangles times 4^subdivide, refused
// over the limit before subdividing.
SurfaceMesh fileMeshOf(const Reader& k) {
  const std::filesystem::path p = k.file("mesh");
  SurfaceMesh mesh = mesh::loadSurfaceMesh(p, k.number("scale", 1.0, 1e-9, 1e9));
  const int subdivide = k.integer("subdivide", 0, 0, 4);
  const auto faces = static_cast<long long>(mesh.mesh().n_faces());
  requireTriangles(
      k, subdivide > 0 ? "subdivide" : "mesh",
      p.filename().string() +
          (subdivide > 0 ? " (" + grouped(faces) + " triangles) subdivided " + counted(subdivide, "time") : ""),
      faces << (2 * subdivide), "a mesh");
  return mesh::subdivided(mesh, subdivide);
}

// A closed mesh from a scenario entry: a file ("mesh", "scale", "subdivide") or a shape, then scaled per
// axis ("stretch"), rotated about x ("rotate_x_deg": 90 turns a y-up model z-up) and moved ("offset_m").
SurfaceMesh meshOf(const Reader& k) {
  SurfaceMesh mesh = k.has("mesh") ? fileMeshOf(k) : shapeOf(k);
  const Eigen::Vector3d stretch = k.vector("stretch", Eigen::Vector3d::Ones());
  const Eigen::Vector3d offset = k.vector("offset_m", Eigen::Vector3d::Zero());
  if ((stretch.array() <= 0).any()) k.fail("must be positive", "stretch");
  const double angle = k.number("rotate_x_deg", 0.0, -360.0, 360.0) * M_PI / 180.0;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
  mesh::TriMesh& m = mesh.mesh();
  for (const auto v : m.vertices())
    m.set_point(v, mesh::toOpenMesh(rotation * mesh::toEigen(m.point(v)).cwiseProduct(stretch) + offset));
  return mesh;
}

// The model and the obstacles; a mesh that cannot be made names the file (and the obstacle).
void readMeshes(const Reader& root, WrapScenario& s) {
  const std::string file = root.filePath().string();
  try {
    if (!root.has("model")) root.fail("must be an object", "model");
    s.model = meshOf(root.child("model"));
    const std::vector<Reader> entries = root.objects("obstacles");
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const std::string name = entries[i].text("name", ("obstacle " + std::to_string(i)).c_str());
      try {
        s.obstacles.push_back({name, meshOf(entries[i])});
      } catch (const mesh::MeshError& e) {
        throw ScenarioError(file + ": obstacle '" + name + "': " + e.what());
      }
    }
  } catch (const std::invalid_argument& e) {
    throw ScenarioError(file + ": " + e.what());
  } catch (const mesh::MeshError& e) {
    throw ScenarioError(file + ": " + e.what());
  }
}

void readLattice(const Reader& l, global_dffd::GlobalDffdOptions& o) {
  o.order = l.integer("order", o.order, 2, 8);
  if (l.has("controls")) {
    // Whole numbers in [order, 4096] (GlobalDffd's bounds), checked before the cast to int: a number beyond
    // int's range made the cast undefined (found by fuzz_wrap_scenario).
    const Eigen::Vector3d c = l.vector("controls", Eigen::Vector3d::Zero());
    for (int a = 0; a < 3; ++a) {
      if (!(c[a] >= o.order && c[a] <= 4096 && c[a] == std::floor(c[a])))
        l.fail(std::string("[").append(std::to_string(a)).append("] = ").append(core::formatNumber(c[a])) +
                   " is not a whole number in [" + std::to_string(o.order) + ", 4096]",
               "controls");
      o.controls[static_cast<std::size_t>(a)] = static_cast<int>(c[a]);
    }
  }
  o.margin_m = l.number("margin_m", o.margin_m, 0.0, 100.0);
  o.kernel = l.choice("kernel", "bspline", {"bspline", "gaussian"}) == "gaussian"
                 ? global_dffd::DffdKernel::Gaussian
                 : global_dffd::DffdKernel::QuadraticBSpline;
  o.kernel_width = l.number("kernel_width", o.kernel_width, 1e-3, 1e4);
  o.clearance_m = l.number("clearance_m", o.clearance_m, 0.0, 1.0);
  o.v_knots = l.boolean("v_knots", o.v_knots == global_dffd::VKnots::AtObstacleExtremes)
                  ? global_dffd::VKnots::AtObstacleExtremes
                  : global_dffd::VKnots::None;
  o.on_fold = l.choice("on_fold", "refuse", {"refuse", "widen"}) == "widen" ? global_dffd::FoldPolicy::Widen
                                                                            : global_dffd::FoldPolicy::Refuse;
}

global_dffd::OpeningTreatment readTreatment(const Reader& root) {
  const std::string t = root.choice("treatment", "open", {"open", "stitched", "capped"});
  return t == "stitched" ? global_dffd::OpeningTreatment::Stitched
         : t == "capped" ? global_dffd::OpeningTreatment::Capped
                         : global_dffd::OpeningTreatment::Open;
}

WrapScenario readWrapScenario(const Reader& root, const std::filesystem::path& file) {
  WrapScenario s;
  s.name = root.text("name", file.stem().string().c_str());
  readMeshes(root, s);
  if (root.has("lattice")) readLattice(root.child("lattice"), s.options);
  s.treatment = readTreatment(root);
  if (root.has("motion")) {
    const Reader m = root.child("motion");
    s.translate_m = m.vector("translate_m", s.translate_m);
    s.frames = m.integer("frames", s.frames, 1, 100000);
  }
  try {
    const bool capped = s.treatment == global_dffd::OpeningTreatment::Capped;
    global_dffd::validateModel(s.model,
                               capped ? global_dffd::ModelClosure::Closed : global_dffd::ModelClosure::MayBeOpen);
  } catch (const global_dffd::DffdError& e) {
    root.fail(e.what(), "model");
  }
  s.format = root.choice("format", "obj", {"obj", "ply"}) == "ply" ? WrapFormat::Ply : WrapFormat::Obj;
  s.tolerance_m = root.number("penetration_tolerance_m", s.tolerance_m, 0.0, 1.0);
  return s;
}

}  // namespace

WrapScenario loadWrapScenario(const std::filesystem::path& file) {
  const json document = detail::parseJsonFile(file);
  return detail::readCheckingKeys(Reader(file, document, ""), wrapScenarioKeys(),
                                  [&file](const Reader& root) { return readWrapScenario(root, file); });
}

const char* treatmentName(global_dffd::OpeningTreatment treatment) {
  switch (treatment) {
    case global_dffd::OpeningTreatment::Stitched:
      return "stitched";
    case global_dffd::OpeningTreatment::Capped:
      return "capped";
    case global_dffd::OpeningTreatment::Open:
      break;
  }
  return "open";
}

const char* formatName(WrapFormat format) { return format == WrapFormat::Ply ? "ply" : "obj"; }

}  // namespace incise::sim
