#include "incise/sim/scenario.h"

#include "incise/core/format.h"
#include "incise/incision/incision.h"
#include "incise/mesh/shapes.h"
#include "incise/mesh/surface_mesh.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "incise/sim/scenario_keys.h"
#include "json_reader.h"
#include "scenario_hid.h"

namespace incise::sim {

namespace {

using nlohmann::json;

using Reader = detail::JsonReader;

void readIncision(const Reader& r, incision::CutterOptions& c) {
  incision::IncisionOptions& i = c.incision;
  i.depth_m = r.number("depth_m", i.depth_m, 1e-6, 1.0);
  i.min_depth_m = r.number("min_depth_m", i.min_depth_m, 1e-6, 1.0);
  i.opening_m = r.number("opening_m", i.opening_m, 0.0, 1.0);
  i.alpha_m = r.number("alpha_m", i.alpha_m, 1e-6, 1.0);
  i.beta_m = r.number("beta_m", i.beta_m, 1e-6, 1.0);
  i.spacing_m = r.number("spacing_m", i.spacing_m, 1e-6, 1.0);
  i.retraction_time_s = r.number("retraction_time_s", i.retraction_time_s, 1e-6, 100.0);
  i.taper_m = r.number("taper_m", i.taper_m, 1e-6, 1.0);
  i.order = r.integer("order", i.order, 2, 8);
  i.across_controls = r.integer("across_controls", i.across_controls, 2, 63);
  i.normal_controls = r.integer("normal_controls", i.normal_controls, 2, 63);
  i.max_columns = r.integer("max_columns", i.max_columns, 16, 1 << 20);
  c.wall_rows = r.integer("wall_rows", c.wall_rows, 1, 64);
  const std::string refine = r.choice("refine", incision::toString(c.refine), {"linear", "pn", "off"});
  c.refine = refine == "off"  ? incision::CutterOptions::Refine::Off
             : refine == "pn" ? incision::CutterOptions::Refine::PnTriangles
                              : incision::CutterOptions::Refine::Linear;
  c.refine_edge_m = r.number("refine_edge_m", c.refine_edge_m, 0.0, 1.0);
  c.reserved_bound_vertices = r.integer("reserve_vertices", c.reserved_bound_vertices, 64, 1 << 24);
}

void readTets(const Reader& r, TetTissueOptions& t) {
  t.enabled = true;
  t.mesh.radius_edge_ratio = r.number("radius_edge_ratio", t.mesh.radius_edge_ratio, 0.0, 100.0);
  if (t.mesh.radius_edge_ratio != 0.0 && t.mesh.radius_edge_ratio < 1.0)
    r.fail("must be 0 (no quality refinement) or >= 1", "radius_edge_ratio");
  t.mesh.max_volume_m3 = r.number("max_volume_m3", t.mesh.max_volume_m3, 0.0, 1.0);
  t.mesh.keep_surface = r.boolean("keep_surface", t.mesh.keep_surface);
  t.cutter.snap_tolerance_m = r.number("snap_tolerance_m", t.cutter.snap_tolerance_m, 0.0, 1.0);
}

// A number that must be > 0 (the key's unit in `unit`).
double positiveNumber(const Reader& r, const char* key, double fallback, const char* unit) {
  const double value = r.number(key, fallback, -1e30, 1e30);
  if (!(value > 0.0)) r.fail("must be > 0 (" + std::string(unit) + "), got " + core::formatNumber(value), key);
  return value;
}

// "tissue.material": the tet tissue's elasticity, density, Rayleigh damping and prestretch.
void readMaterial(const Reader& r, physics::Material& m) {
  m.youngs_modulus_Pa = positiveNumber(r, "youngs_modulus_Pa", m.youngs_modulus_Pa, "Pa");
  m.poisson_ratio = r.number("poisson_ratio", m.poisson_ratio, -1e30, 1e30);
  if (!(m.poisson_ratio >= 0.0 && m.poisson_ratio < 0.5))
    r.fail("= " + core::formatNumber(m.poisson_ratio) + " is outside [0, 0.5)", "poisson_ratio");
  m.density_kg_per_m3 = positiveNumber(r, "density_kg_per_m3", m.density_kg_per_m3, "kg/m^3");
  const Reader damping = r.child("damping");
  m.damping.mass_per_s = damping.number("mass_per_s", m.damping.mass_per_s, 0.0, 1e6);
  m.damping.stiffness_s = damping.number("stiffness_s", m.damping.stiffness_s, 0.0, 1e3);
  m.prestretch = r.vector("prestretch", m.prestretch);
  if (!(m.prestretch.array() > 0.0).all()) r.fail("must be > 0 along every axis", "prestretch");
}

// A simulated tissue: tissue.material (its tets from tissue.tets, or that key's defaults), tissue.fixed (at
// least one box), gravity_m_per_s2 and physics_rate_hz (at most the frame rate). The keys but `material` are
// refused without it.
void readPhysics(const Reader& root, const Reader& tissue, Scenario& s) {
  PhysicsOptions& p = s.world.physics;
  if (!tissue.has("material")) {
    for (const char* key : {"fixed"})
      if (tissue.has(key)) tissue.fail("is only for a simulated tissue (give tissue.material)", key);
    for (const char* key : {"gravity_m_per_s2", "physics_rate_hz"})
      if (root.has(key)) root.fail("is only for a simulated tissue (give tissue.material)", key);
    return;
  }
  p.enabled = true;
  s.world.tets.enabled = true;  // the tets are what is simulated: without tissue.tets, made with its defaults
  readMaterial(tissue.child("material"), p.material);
  if (!tissue.has("fixed"))
    tissue.fail(
        "is missing: a simulated tissue must be held somewhere (give at least one box "
        "{\"min_m\": [x, y, z], \"max_m\": [x, y, z]})",
        "fixed");
  for (const Reader& box : tissue.objects("fixed")) {
    if (!box.has("min_m")) box.fail("is missing ([x, y, z] in metres)", "min_m");
    if (!box.has("max_m")) box.fail("is missing ([x, y, z] in metres)", "max_m");
    const physics::Box b{box.vector("min_m", Eigen::Vector3d::Zero()), box.vector("max_m", Eigen::Vector3d::Zero())};
    if (!(b.min_m.array() <= b.max_m.array()).all()) box.fail("must be >= min_m along every axis", "max_m");
    p.boundary.fixed_boxes.push_back(b);
  }
  p.boundary.gravity_m_per_s2 = root.vector("gravity_m_per_s2", p.boundary.gravity_m_per_s2);
  p.rate_hz = root.number("physics_rate_hz", p.rate_hz, 10.0, s.rate_hz);
}

std::vector<StrokeSpec> readStrokes(const Reader& source) {
  std::vector<StrokeSpec> strokes;
  for (const Reader& s : source.objects("strokes")) {
    StrokeSpec spec;
    spec.start_m = s.vector("start_m", spec.start_m);
    spec.direction = s.vector("direction", spec.direction);
    spec.length_m = s.number("length_m", spec.length_m, 1e-4, 10.0);
    spec.bend_m = s.number("bend_m", spec.bend_m, -10.0, 10.0);
    spec.wave_m = s.number("wave_m", spec.wave_m, -10.0, 10.0);
    spec.speed_m_per_s = s.number("speed_m_per_s", spec.speed_m_per_s, 1e-4, 10.0);
    spec.pause_s = s.number("pause_s", spec.pause_s, 0.0, 100.0);
    spec.depth_m = s.number("depth_m", spec.depth_m, 0.0, 1.0);
    spec.depth_end_m = s.number("depth_end_m", spec.depth_end_m, 0.0, 1.0);
    if (spec.direction.norm() == 0.0) s.fail("must not be zero", "direction");
    strokes.push_back(spec);
  }
  return strokes;
}

// "plan": the polyline (>= 2 points [x, y, z], metres), the target depth and the tolerances (> 0).
PlanSpec readPlan(const Reader& r) {
  PlanSpec plan;
  plan.given = true;
  const json& points = r.has("points_m") ? r.raw()["points_m"] : json();
  if (!points.is_array() || points.size() < 2) r.fail("must be an array of at least 2 points [x, y, z]", "points_m");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const json& p = points[i];
    const std::string key = "points_m[" + std::to_string(i) + "]";
    if (!p.is_array() || p.size() != 3) r.fail("must be a point [x, y, z] in metres", key);
    Eigen::Vector3d point;
    for (int a = 0; a < 3; ++a) {
      if (!p[static_cast<std::size_t>(a)].is_number()) r.fail("must be a point [x, y, z] in metres", key);
      point[a] = p[static_cast<std::size_t>(a)].get<double>();
    }
    if (!point.allFinite()) r.fail("is not finite", key);
    plan.points_m.push_back(point);
  }
  const auto positive = [&r](const char* key, double fallback) {
    const double value = r.number(key, fallback, -1e9, 1.0);
    if (!(value > 0.0)) r.fail("must be > 0 (metres), got " + core::formatNumber(value), key);
    return value;
  };
  plan.depth_m = positive("depth_m", plan.depth_m);
  plan.lateral_tolerance_m = positive("lateral_tolerance_m", plan.lateral_tolerance_m);
  plan.depth_tolerance_m = positive("depth_tolerance_m", plan.depth_tolerance_m);
  return plan;
}

// "tissue": a mesh file, or "shape": "pad" (mesh::makeSkinPad).
void readTissueSource(const Reader& tissue, Scenario& s) {
  if (!tissue.has("shape")) {
    s.mesh = tissue.file("mesh");
    s.scale = tissue.number("scale", 1.0, 1e-9, 1e9);
    s.subdivide = tissue.integer("subdivide", 0, 0, 5);
    return;
  }
  if (tissue.has("mesh")) tissue.fail("give either mesh or shape, not both", "shape");
  tissue.choice("shape", nullptr, {"pad"});
  s.shape.given = true;
  s.shape.size_m = tissue.vector("size_m", s.shape.size_m);
  if (!(s.shape.size_m.array() > 0.0).all()) tissue.fail("must be > 0 along every axis", "size_m");
  s.shape.grid_m = tissue.number("grid_m", s.shape.grid_m, 1e-5, 1.0);
  s.subdivide = tissue.integer("subdivide", 0, 0, 5);
}

// "tissue.texture": how the coordinates are had and which images are drawn.
TextureSpec readTexture(const Reader& texture) {
  TextureSpec spec;
  spec.given = true;
  spec.box_map = texture.has("map") && texture.choice("map", nullptr, {"box"}) == "box";
  spec.tile_m = texture.number("tile_m", spec.tile_m, 1e-5, 10.0);
  if (!spec.box_map && texture.has("tile_m")) texture.fail("needs \"map\": \"box\" (it sizes the made map)", "tile_m");
  if (texture.has("skin")) spec.skin_image = texture.file("skin");
  if (texture.has("wall")) spec.wall_image = texture.file("wall");
  return spec;
}

Scenario readScenario(const Reader& root, const std::filesystem::path& file) {
  Scenario s;
  s.file = file;
  s.name = root.text("name", file.stem().string().c_str());

  const Reader tissue = root.child("tissue");
  if (!root.has("tissue")) root.fail("is missing", "tissue");
  readTissueSource(tissue, s);
  if (tissue.has("texture")) s.texture = readTexture(tissue.child("texture"));
  s.force_threshold_N = tissue.number("force_threshold_N", s.force_threshold_N, 0.0, 1e3);
  TissueOptions& tp = s.world.tissue;
  tp.stiffness_N_per_m = tissue.number("stiffness_N_per_m", tp.stiffness_N_per_m, 0.0, 1e7);
  tp.damping_N_s_per_m = tissue.number("damping_N_s_per_m", tp.damping_N_s_per_m, 0.0, 1e5);
  tp.cutting_resistance_N = tissue.number("cutting_resistance_N", tp.cutting_resistance_N, 0.0, 1e3);
  if (tissue.has("tets")) readTets(tissue.child("tets"), s.world.tets);

  const Reader tool = root.child("tool");
  s.world.tool.blade_length_m = tool.number("blade_length_m", s.world.tool.blade_length_m, 1e-4, 1.0);
  s.world.tool.cut_button = tool.integer("cut_button", s.world.tool.cut_button, -1, 31);
  tp.max_force_N = tool.number("max_force_N", tp.max_force_N, 0.0, 1e3);

  readIncision(root.child("incision"), s.world.cutter);
  try {
    incision::Incision::validateOptions(s.world.cutter.incision);
  } catch (const std::invalid_argument& e) {
    root.fail(e.what(), "incision");
  }
  if (s.world.cutter.incision.depth_m > s.world.tool.blade_length_m)
    root.child("incision")
        .fail("= " + core::formatNumber(s.world.cutter.incision.depth_m) +
                  " m is deeper than the blade is long (tool.blade_length_m = " +
                  core::formatNumber(s.world.tool.blade_length_m) + " m)",
              "depth_m");

  s.rate_hz = root.number("rate_hz", s.rate_hz, 10.0, 100000.0);
  readPhysics(root, tissue, s);
  if (s.world.cutter.incision.opening_m == 0.0 && !s.world.physics.enabled)
    root.child("incision")
        .fail(
            "= 0 leaves the lips touching: only a simulated tissue (tissue.material) opens the wound by its own "
            "tension; give opening_m > 0",
            "opening_m");
  s.settle_s = root.number("settle_s", s.settle_s, 0.0, 100.0);
  s.world.cut_budget_us = root.number("cut_budget_us", s.world.cut_budget_us, 1.0, 1e6);
  s.world.us_per_inversion = root.number("us_per_inversion", s.world.us_per_inversion, 0.01, 1000.0);
  if (s.settle_s < s.world.cutter.incision.retraction_time_s)
    root.fail("must be at least incision.retraction_time_s so that the wound settles", "settle_s");

  if (root.has("plan")) s.plan = readPlan(root.child("plan"));

  if (!root.has("pose_source")) root.fail("is missing", "pose_source");
  const Reader source = root.child("pose_source");
  const std::string kind = source.text("kind", nullptr);
  if (kind == "trace") {
    s.source = Scenario::Source::Trace;
    s.trace = source.file("path");
  } else if (kind == "strokes") {
    s.source = Scenario::Source::Strokes;
    s.strokes = readStrokes(source);
  } else if (kind == "hid-recording") {
    s.source = Scenario::Source::HidRecording;
    s.hid = detail::readHidRecordingSource(source);
  } else {
    source.fail("must be \"trace\", \"strokes\" or \"hid-recording\", got \"" + kind + "\"", "kind");
  }
  return s;
}

}  // namespace

Scenario loadScenario(const std::filesystem::path& file) {
  const json document = detail::parseJsonFile(file);
  return detail::readCheckingKeys(Reader(file, document, ""), replayScenarioKeys(),
                                  [&file](const Reader& root) { return readScenario(root, file); });
}

mesh::SurfaceMesh loadTissue(const Scenario& scenario) {
  mesh::SurfaceMesh tissue =
      scenario.shape.given
          ? mesh::subdivided(mesh::makeSkinPad(scenario.shape.size_m, scenario.shape.grid_m), scenario.subdivide)
          : mesh::subdivided(mesh::loadSurfaceMesh(scenario.mesh, scenario.scale), scenario.subdivide);
  if (scenario.texture.box_map) {
    mesh::boxTexCoords(tissue, scenario.texture.tile_m);
  } else if (scenario.texture.given && !tissue.hasTexCoords()) {
    throw mesh::MeshError(scenario.file.string() + ": tissue.texture: " +
                          (scenario.shape.given ? std::string("a made pad") : scenario.mesh.string()) +
                          " has no texture coordinates (vt); give \"map\": \"box\" to make them");
  }
  return tissue;
}

}  // namespace incise::sim
