#include "incise/sim/scenario.h"

#include "incise/cutting/incision.h"
#include "incise/cutting/surface_mesh.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "json_reader.h"
#include "scenario_hid.h"

namespace incise::sim {

namespace {

using nlohmann::json;

using Reader = detail::JsonReader;

void readIncision(const Reader& r, cutting::CutterOptions& c) {
  cutting::IncisionOptions& i = c.incision;
  i.depth_m = r.number("depth_m", i.depth_m, 1e-6, 1.0);
  i.opening_m = r.number("opening_m", i.opening_m, 1e-6, 1.0);
  i.alpha_m = r.number("alpha_m", i.alpha_m, 1e-6, 1.0);
  i.beta_m = r.number("beta_m", i.beta_m, 1e-6, 1.0);
  i.spacing_m = r.number("spacing_m", i.spacing_m, 1e-6, 1.0);
  i.retraction_time_s = r.number("retraction_time_s", i.retraction_time_s, 1e-6, 100.0);
  i.order = r.integer("order", i.order, 2, 8);
  i.across_controls = r.integer("across_controls", i.across_controls, 2, 63);
  i.normal_controls = r.integer("normal_controls", i.normal_controls, 2, 63);
  i.max_columns = r.integer("max_columns", i.max_columns, 16, 1 << 20);
  c.wall_rows = r.integer("wall_rows", c.wall_rows, 1, 64);
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

std::vector<StrokeSpec> readStrokes(const Reader& source) {
  std::vector<StrokeSpec> strokes;
  for (const Reader& s : source.objects("strokes")) {
    StrokeSpec spec;
    spec.start_m = s.vector("start_m", spec.start_m);
    spec.direction = s.vector("direction", spec.direction);
    spec.length_m = s.number("length_m", spec.length_m, 1e-4, 10.0);
    spec.bend_m = s.number("bend_m", spec.bend_m, -10.0, 10.0);
    spec.speed_m_per_s = s.number("speed_m_per_s", spec.speed_m_per_s, 1e-4, 10.0);
    spec.pause_s = s.number("pause_s", spec.pause_s, 0.0, 100.0);
    if (spec.direction.norm() == 0.0) s.fail("must not be zero", "direction");
    strokes.push_back(spec);
  }
  return strokes;
}

}  // namespace

Scenario loadScenario(const std::filesystem::path& file) {
  const json document = detail::parseJsonFile(file);
  const Reader root(file, document, "");
  Scenario s;
  s.file = file;
  s.name = root.text("name", file.stem().string().c_str());

  const Reader tissue = root.child("tissue");
  if (!root.has("tissue")) root.fail("is missing", "tissue");
  s.mesh = tissue.file("mesh");
  s.scale = tissue.number("scale", 1.0, 1e-9, 1e9);
  s.subdivide = tissue.integer("subdivide", 0, 0, 5);
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
    cutting::Incision::validateOptions(s.world.cutter.incision);
  } catch (const std::invalid_argument& e) {
    root.fail(e.what(), "incision");
  }

  s.rate_hz = root.number("rate_hz", s.rate_hz, 10.0, 100000.0);
  s.settle_s = root.number("settle_s", s.settle_s, 0.0, 100.0);
  s.world.cut_budget_us = root.number("cut_budget_us", s.world.cut_budget_us, 1.0, 1e6);
  s.world.us_per_inversion = root.number("us_per_inversion", s.world.us_per_inversion, 0.01, 1000.0);
  if (s.settle_s < s.world.cutter.incision.retraction_time_s)
    root.fail("must be at least incision.retraction_time_s so that the wound settles", "settle_s");

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

cutting::SurfaceMesh loadTissue(const Scenario& scenario) {
  return cutting::subdivided(cutting::loadSurfaceMesh(scenario.mesh, scenario.scale), scenario.subdivide);
}

}  // namespace incise::sim
