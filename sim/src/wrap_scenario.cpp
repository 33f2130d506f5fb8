#include "incise/sim/wrap_scenario.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "incise/cutting/shapes.h"
#include "json_reader.h"

namespace incise::sim {

namespace {

using nlohmann::json;
using Reader = detail::JsonReader;
using cutting::SurfaceMesh;

// A shape ("shape": box, cylinder, sphere, prism with "outline": "face", robot) from its keys.
SurfaceMesh shapeOf(const Reader& k) {
  const std::string shape = k.text("shape", nullptr);
  if (shape == "box")
    return cutting::makeBox(Eigen::AlignedBox3d(k.vector("min_m", Eigen::Vector3d::Constant(-0.01)),
                                                k.vector("max_m", Eigen::Vector3d::Constant(0.01))),
                            k.integer("divisions", 8, 1, 1000));
  if (shape == "cylinder")
    return cutting::makeCylinder(k.vector("base_m", Eigen::Vector3d::Zero()),
                                 k.vector("axis_m", Eigen::Vector3d(0, 0, 0.05)),
                                 k.number("radius_m", 0.005, 1e-6, 10.0), k.integer("segments", 48, 3, 100000),
                                 k.integer("rings", 4, 1, 100000), k.integer("cap_rings", 2, 1, 100000));
  if (shape == "sphere")
    return cutting::makeSphere(k.vector("centre_m", Eigen::Vector3d::Zero()), k.number("radius_m", 0.01, 1e-6, 10.0),
                               k.integer("subdivisions", 3, 0, 8));
  if (shape == "prism") {
    if (k.text("outline", "face") != "face")
      k.fail("must be \"face\" (the silhouette of a face in profile)", "outline");
    return cutting::makePrism(
        cutting::faceSilhouette(k.number("height_m", 0.03, 1e-6, 10.0), k.integer("points", 120, 25, 100000)),
        k.number("z0_m", -0.02, -10.0, 10.0), k.number("z1_m", 0.02, -10.0, 10.0), k.integer("rings", 4, 1, 10000));
  }
  if (shape == "robot")
    return cutting::makeRobot(k.number("height_m", 0.1, 1e-4, 100.0),
                              k.integer("detail", cutting::kRobotDetail30k, 1, 200));
  k.fail("must be box, cylinder, sphere, prism or robot, got \"" + shape + "\"", "shape");
}

// A closed mesh from a scenario entry: a file ("mesh", "scale", "subdivide") or a shape, then scaled per
// axis ("stretch"), rotated about x ("rotate_x_deg": 90 turns a y-up model z-up) and moved ("offset_m").
SurfaceMesh meshOf(const Reader& k) {
  SurfaceMesh mesh;
  if (k.has("mesh")) {
    const std::filesystem::path p = k.file("mesh");
    mesh = cutting::subdivided(cutting::loadSurfaceMesh(p, k.number("scale", 1.0, 1e-9, 1e9)),
                               k.integer("subdivide", 0, 0, 4));
  } else {
    mesh = shapeOf(k);
  }
  const Eigen::Vector3d stretch = k.vector("stretch", Eigen::Vector3d::Ones());
  const Eigen::Vector3d offset = k.vector("offset_m", Eigen::Vector3d::Zero());
  if ((stretch.array() <= 0).any()) k.fail("must be positive", "stretch");
  const double angle = k.number("rotate_x_deg", 0.0, -360.0, 360.0) * M_PI / 180.0;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
  cutting::TriMesh& m = mesh.mesh();
  for (const auto v : m.vertices())
    m.set_point(v, cutting::toOpenMesh(rotation * cutting::toEigen(m.point(v)).cwiseProduct(stretch) + offset));
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
      } catch (const cutting::MeshError& e) {
        throw ScenarioError(file + ": obstacle '" + name + "': " + e.what());
      }
    }
  } catch (const std::invalid_argument& e) {
    throw ScenarioError(file + ": " + e.what());
  } catch (const cutting::MeshError& e) {
    throw ScenarioError(file + ": " + e.what());
  }
}

void readLattice(const Reader& l, cutting::GlobalDffdOptions& o) {
  o.order = l.integer("order", o.order, 2, 8);
  if (l.has("controls")) {
    const Eigen::Vector3d c = l.vector("controls", Eigen::Vector3d::Zero());
    for (int a = 0; a < 3; ++a) o.controls[static_cast<std::size_t>(a)] = static_cast<int>(c[a]);
  }
  o.margin_m = l.number("margin_m", o.margin_m, 0.0, 100.0);
  o.kernel = l.choice("kernel", "bspline", {"bspline", "gaussian"}) == "gaussian"
                 ? cutting::DffdKernel::Gaussian
                 : cutting::DffdKernel::QuadraticBSpline;
  o.kernel_width = l.number("kernel_width", o.kernel_width, 1e-3, 1e4);
  o.clearance_m = l.number("clearance_m", o.clearance_m, 0.0, 1.0);
  o.v_knots = l.boolean("v_knots", o.v_knots == cutting::VKnots::AtObstacleExtremes)
                  ? cutting::VKnots::AtObstacleExtremes
                  : cutting::VKnots::None;
  o.on_fold = l.choice("on_fold", "refuse", {"refuse", "widen"}) == "widen" ? cutting::FoldPolicy::Widen
                                                                            : cutting::FoldPolicy::Refuse;
}

cutting::OpeningTreatment readTreatment(const Reader& root) {
  const std::string t = root.choice("treatment", "open", {"open", "stitched", "capped"});
  return t == "stitched" ? cutting::OpeningTreatment::Stitched
         : t == "capped" ? cutting::OpeningTreatment::Capped
                         : cutting::OpeningTreatment::Open;
}

}  // namespace

WrapScenario loadWrapScenario(const std::filesystem::path& file) {
  const json document = detail::parseJsonFile(file);
  const Reader root(file, document, "");
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
    const bool capped = s.treatment == cutting::OpeningTreatment::Capped;
    cutting::validateModel(s.model, capped ? cutting::ModelClosure::Closed : cutting::ModelClosure::MayBeOpen);
  } catch (const cutting::DffdError& e) {
    root.fail(e.what(), "model");
  }
  s.format = root.choice("format", "obj", {"obj", "ply"}) == "ply" ? WrapFormat::Ply : WrapFormat::Obj;
  s.tolerance_m = root.number("penetration_tolerance_m", s.tolerance_m, 0.0, 1.0);
  return s;
}

const char* treatmentName(cutting::OpeningTreatment treatment) {
  switch (treatment) {
    case cutting::OpeningTreatment::Stitched:
      return "stitched";
    case cutting::OpeningTreatment::Capped:
      return "capped";
    case cutting::OpeningTreatment::Open:
      break;
  }
  return "open";
}

const char* formatName(WrapFormat format) { return format == WrapFormat::Ply ? "ply" : "obj"; }

}  // namespace incise::sim
