#include "incise/sim/scenario.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace incise::sim {

namespace {

using nlohmann::json;

// Reads typed values out of a JSON object and names file and key path in every error.
class Reader {
 public:
  Reader(const std::filesystem::path& file, const json& object, std::string path)
      : file_(file), object_(object), path_(std::move(path)) {
    if (!object_.is_object()) fail(path_.empty() ? "the document must be a JSON object" : "must be an object");
  }

  [[noreturn]] void fail(const std::string& message, const std::string& key = "") const {
    const std::string where = key.empty() ? path_ : (path_.empty() ? key : path_ + "." + key);
    throw ScenarioError(file_.string() + ": " + (where.empty() ? "" : where + ": ") + message);
  }

  bool has(const char* key) const { return object_.contains(key); }

  Reader child(const char* key) const {
    if (!has(key)) return Reader(file_, json::object(), join(key));
    return Reader(file_, object_.at(key), join(key));
  }

  double number(const char* key, double fallback, double lo, double hi) const {
    if (!has(key)) return fallback;
    const json& v = object_.at(key);
    if (!v.is_number()) fail("must be a number, got " + v.dump(), key);
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi)) fail(std::to_string(x) + " is outside [" + str(lo) + ", " + str(hi) + "]", key);
    return x;
  }

  int integer(const char* key, int fallback, int lo, int hi) const {
    if (!has(key)) return fallback;
    const json& v = object_.at(key);
    if (!v.is_number_integer()) fail("must be an integer, got " + v.dump(), key);
    const long long x = v.get<long long>();
    if (x < lo || x > hi) fail(std::to_string(x) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", key);
    return static_cast<int>(x);
  }

  std::string text(const char* key, const char* fallback) const {
    if (!has(key)) {
      if (fallback) return fallback;
      fail("is missing", key);
    }
    const json& v = object_.at(key);
    if (!v.is_string()) fail("must be a string, got " + v.dump(), key);
    return v.get<std::string>();
  }

  Eigen::Vector3d vector(const char* key, const Eigen::Vector3d& fallback) const {
    if (!has(key)) return fallback;
    const json& v = object_.at(key);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      fail("must be an array of 3 numbers, got " + v.dump(), key);
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  }

  // A path relative to the scenario file, which must exist.
  std::filesystem::path file(const char* key) const {
    const std::filesystem::path p = file_.parent_path() / text(key, nullptr);
    if (!std::filesystem::exists(p)) fail("file " + p.string() + " does not exist", key);
    return p;
  }

  const json& raw() const { return object_; }
  const std::filesystem::path& filePath() const { return file_; }
  std::string join(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

 private:
  static std::string str(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }

  std::filesystem::path file_;
  json object_;
  std::string path_;
};

json parse(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw ScenarioError(file.string() + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  try {
    return json::parse(s);
  } catch (const json::parse_error& e) {
    // nlohmann gives a byte offset: turn it into line:column.
    const size_t at = std::min<size_t>(e.byte == 0 ? 0 : e.byte - 1, s.size());
    const size_t line = 1 + static_cast<size_t>(std::count(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    const size_t line_start = s.rfind('\n', at == 0 ? 0 : at - 1);
    const size_t column = at - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
    throw ScenarioError(file.string() + ":" + std::to_string(line) + ":" + std::to_string(column) + ": JSON syntax error");
  }
}

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
  if (r.has("keep_surface")) {
    if (!r.raw().at("keep_surface").is_boolean()) r.fail("must be true or false", "keep_surface");
    t.mesh.keep_surface = r.raw().at("keep_surface").get<bool>();
  }
  t.cutter.snap_tolerance_m = r.number("snap_tolerance_m", t.cutter.snap_tolerance_m, 0.0, 1.0);
}

std::vector<StrokeSpec> readStrokes(const Reader& source) {
  if (!source.has("strokes") || !source.raw().at("strokes").is_array() || source.raw().at("strokes").empty())
    source.fail("must be a non-empty array of strokes", "strokes");
  std::vector<StrokeSpec> strokes;
  const json& list = source.raw().at("strokes");
  for (size_t k = 0; k < list.size(); ++k) {
    const Reader s(source.filePath(), list[k], source.join("strokes") + "[" + std::to_string(k) + "]");
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
  const json document = parse(file);
  const Reader root(file, document, "");
  Scenario s;
  s.file = file;
  s.name = root.text("name", file.stem().string().c_str());

  const Reader tissue = root.child("tissue");
  if (!root.has("tissue")) root.fail("is missing", "tissue");
  s.mesh = tissue.file("mesh");
  s.scale = tissue.number("scale", 1.0, 1e-9, 1e9);
  s.subdivide = tissue.integer("subdivide", 0, 0, 5);
  TissueParams& tp = s.world.tissue;
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
  } else {
    source.fail("must be \"trace\" or \"strokes\", got \"" + kind + "\"", "kind");
  }
  return s;
}

cutting::SurfaceMesh loadTissue(const Scenario& scenario) {
  return cutting::subdivided(cutting::loadSurfaceMesh(scenario.mesh, scenario.scale), scenario.subdivide);
}

}  // namespace incise::sim
