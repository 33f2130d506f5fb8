// A simulated tissue in the world (sim/tissue_physics.h): its scenario keys and their refusals, its steps at
// the fixed rate of simulated time, cuts reaching the model in the frame they are made, the same bytes in
// real time as fast, the skin embedded on its own side of the cut, and a cut in a tensioned pad that gapes.
#include "incise/sim/tissue_physics.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <mutex>
#include <set>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/physics/tissue_model.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/geometry_stream.h"
#include "incise/sim/simulation.h"
#include "incise/tets/tet_cutter.h"
#include "scenario_fixture.h"
#include "shipped_scenario.h"

using namespace incise;
using Catch::Matchers::Contains;

namespace {

// A small pad with tets and a material, and `extra` keys in the tissue object and at the root.
std::string tissuePadScenario(const std::string& tissue_extra, const std::string& root_extra = "") {
  return R"({
    "tissue": {"shape": "pad", "size_m": [0.02, 0.01, 0.02], "grid_m": 0.002, "tets": {"max_volume_m3": 1e-7})" +
         tissue_extra + R"(},
    "pose_source": {"kind": "strokes", "strokes": [{}]})" +
         root_extra + "}";
}

const char* kMaterial = R"(, "material": {"youngs_modulus_Pa": 20000, "poisson_ratio": 0.4, "density_kg_per_m3": 900,
    "damping": {"mass_per_s": 2, "stiffness_s": 0.02}, "prestretch": [1.1, 1, 1.05]},
    "fixed": [{"min_m": [-1, -1, -1], "max_m": [1, -0.0099, 1]}])";

sim::Scenario load(const std::string& name, const std::string& text) {
  return sim::loadScenario(test::scenarioDir().scenario(name, text));
}

std::string materialWith(const std::string& from, const std::string& to) {
  std::string m = kMaterial;
  const std::size_t at = m.find(from);
  REQUIRE(at != std::string::npos);
  return m.replace(at, from.size(), to);
}

// The shipped tensioned pad, replayed frame by frame (fast), prestretch overridden when given.
struct PadRun {
  test::ShippedScenario run;
  sim::ReplayReport report;
  std::int64_t frames = 0;
  double t_first_s = 0.0, t_last_s = 0.0;
};

// The kernel's opening overridden too when opening_m >= 0 (the shipped pad has none: its tension opens it);
// the stroke after a press beside it (test::padPressPoses) when press_first.
PadRun replayPad(const Eigen::Vector3d* prestretch = nullptr, sim::ReplayPace pace = sim::ReplayPace::Fast,
                 std::function<void(std::int64_t)> before_step = {}, double opening_m = -1.0,
                 bool press_first = false) {
  PadRun p;
  p.run = test::loadShipped("pad-tension");
  if (press_first) p.run.poses = test::followedBy(test::padPressPoses({}), p.run.poses);
  if (prestretch || opening_m >= 0.0) {
    sim::Scenario s = p.run.scenario;
    if (prestretch) s.world.physics.material.prestretch = *prestretch;
    if (opening_m >= 0.0) s.world.cutter.incision.opening_m = opening_m;
    p.run.world = std::make_unique<sim::World>(sim::loadTissue(s), s.world);
  }
  sim::ReplayOptions options;
  options.pace = pace;
  options.period_us = p.run.scenario.periodUs();
  options.settle_s = p.run.scenario.settle_s;
  options.physics_before_step = std::move(before_step);
  p.report = sim::replay(*p.run.world, p.run.poses, options);
  p.frames = p.report.frames;
  return p;
}

// What `replay` writes of a simulated tissue, as bytes: the surface as simulated (cut.obj's vertices), the
// tets as simulated (tets.node's nodes), and the model's counters but the timing ones.
struct SimulatedBytes {
  std::vector<double> surface, tets;
  std::int64_t steps = 0, cuts_applied = 0, cg_limited = 0, non_finite = 0, pieces_refused = 0;
  int nodes = 0, elements = 0, max_inverted = 0;
  std::uint64_t hash = 0;
  bool operator==(const SimulatedBytes&) const = default;
};

SimulatedBytes simulatedBytes(const sim::World& world) {
  const sim::TissuePhysics& physics = *world.physics();
  SimulatedBytes b;
  const mesh::SurfaceMesh deformed = physics.deformedSurface(world.tissue());
  for (const auto v : deformed.mesh().vertices())
    for (int a = 0; a < 3; ++a) b.surface.push_back(deformed.mesh().point(v)[a]);
  tets::TetView view = world.tets()->view();
  physics.deform(view, *world.tets());
  for (const Eigen::Vector3d& x : view.mesh.nodes_m) b.tets.insert(b.tets.end(), {x.x(), x.y(), x.z()});
  const sim::PhysicsCounters c = physics.counters();
  b.steps = c.steps, b.cuts_applied = c.cuts_applied, b.cg_limited = c.cg_limited, b.non_finite = c.non_finite;
  b.pieces_refused = c.pieces_refused, b.max_inverted = c.max_inverted;
  b.nodes = physics.model().nodeCount(), b.elements = physics.model().elementCount();
  b.hash = physics.positionsHash();
  return b;
}

// The wound's width at the skin around the cut's middle: the spread across the cut (in x) of the lips' seam
// vertices on top within 4 mm of z = 0, as simulated (`x` the vertices' positions) or at rest. At rest it
// is the kernel's opening; the lips pulled apart by the tissue widen it.
double woundWidthM(const mesh::SurfaceMesh& rest, const mesh::SurfaceMesh& x) {
  const mesh::TriMesh& m = rest.mesh();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto v : m.vertices()) {
    const Eigen::Vector3d r = mesh::toEigen(m.point(v));
    if (rest.kind(v) != mesh::VertexKind::Seam || r.y() < -1e-4 || std::abs(r.z()) > 0.004) continue;
    const double px = mesh::toEigen(x.mesh().point(v)).x();
    lo = std::min(lo, px), hi = std::max(hi, px);
  }
  return hi - lo;
}

// The wound's wall vertices near the cut's middle (|z| < 9 mm) that face across the cut (|n_x| > 0.5, n their
// area-weighted normal at rest), and those of them that did not move away from the wall they face (a wall
// facing -x is the +x lip's: it moves +x as the wound opens). The groove's floor, where both walls meet (its
// vertices' faces face both ways: n is rounding noise), belongs to neither lip: counted apart.
struct WallSides {
  int walls = 0, wrong = 0, floor = 0;
};
WallSides wallSides(const mesh::SurfaceMesh& rest, const mesh::SurfaceMesh& x) {
  const mesh::TriMesh& m = rest.mesh();
  WallSides out;
  for (const auto v : m.vertices()) {
    const Eigen::Vector3d r = mesh::toEigen(m.point(v));
    if (rest.kind(v) != mesh::VertexKind::Wall || std::abs(r.z()) > 0.009) continue;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    double area_sum = 0.0;
    for (const auto f : m.vf_range(v)) {
      std::array<Eigen::Vector3d, 3> p;
      int i = 0;
      for (const auto w : m.fv_range(f)) p[static_cast<std::size_t>(i++)] = mesh::toEigen(m.point(w));
      n += (p[1] - p[0]).cross(p[2] - p[0]);
      area_sum += (p[1] - p[0]).cross(p[2] - p[0]).norm();
    }
    if (n.norm() <= 1e-9 * area_sum) {
      ++out.floor;
      continue;
    }
    if (!(std::abs(n.x()) > 0.5 * n.norm())) continue;
    ++out.walls;
    if ((mesh::toEigen(x.mesh().point(v)).x() - r.x()) * n.x() >= 0.0) ++out.wrong;
  }
  return out;
}

// The cut's plane across x: the mean rest x of the lips' seam vertices on top.
double cutPlaneX(const mesh::SurfaceMesh& rest) {
  const mesh::TriMesh& m = rest.mesh();
  double sum = 0.0;
  int n = 0;
  for (const auto v : m.vertices()) {
    const Eigen::Vector3d r = mesh::toEigen(m.point(v));
    if (rest.kind(v) == mesh::VertexKind::Seam && r.y() >= -1e-4) sum += r.x(), ++n;
  }
  return n > 0 ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

// The scenario's frames one by one (each pose to the frame of its time, World::step), after_frame(t_s)
// after each.
template <class F>
void stepFrames(test::ShippedScenario& l, F&& after_frame) {
  const double dt_s = static_cast<double>(l.scenario.periodUs()) * 1e-6, t0_s = l.poses.front().time_s;
  std::size_t fed = 0;
  for (std::int64_t k = 0; t0_s + static_cast<double>(k) * dt_s <= l.poses.back().time_s; ++k) {
    const double t_s = t0_s + static_cast<double>(k) * dt_s;
    const std::size_t first = fed;
    while (fed < l.poses.size() && l.poses[fed].time_s <= t_s + 1e-12) ++fed;
    l.world->step(std::span(l.poses.data() + first, fed - first), dt_s, t_s);
    after_frame(t_s);
  }
}

}  // namespace

TEST_CASE("tissue physics: a material, its held boxes, gravity and rate are read from the scenario", "[sim]") {
  const sim::Scenario s = load("material", tissuePadScenario(kMaterial, R"(, "gravity_m_per_s2": [0, -9.81, 0],
      "physics_rate_hz": 200)"));
  const sim::PhysicsOptions& p = s.world.physics;
  REQUIRE(p.enabled);
  CHECK(p.material.youngs_modulus_Pa == 20000);
  CHECK(p.material.poisson_ratio == 0.4);
  CHECK(p.material.density_kg_per_m3 == 900);
  CHECK(p.material.damping.mass_per_s == 2);
  CHECK(p.material.damping.stiffness_s == 0.02);
  CHECK(p.material.prestretch == Eigen::Vector3d(1.1, 1, 1.05));
  REQUIRE(p.boundary.fixed_boxes.size() == 1);
  CHECK(p.boundary.fixed_boxes[0].max_m == Eigen::Vector3d(1, -0.0099, 1));
  CHECK(p.boundary.gravity_m_per_s2 == Eigen::Vector3d(0, -9.81, 0));
  CHECK(p.rate_hz == 200);
  const sim::Scenario plain = load("plain", tissuePadScenario(""));
  CHECK_FALSE(plain.world.physics.enabled);
  // Defaults: no gravity, 100 Hz.
  const sim::Scenario defaults = load("defaults", tissuePadScenario(kMaterial));
  CHECK(defaults.world.physics.boundary.gravity_m_per_s2 == Eigen::Vector3d::Zero());
  CHECK(defaults.world.physics.rate_hz == 100);
}

TEST_CASE("tissue physics: out-of-range materials and tissues that cannot be simulated are refused by key", "[sim]") {
  CHECK_THROWS_WITH(load("e0", tissuePadScenario(materialWith("20000", "0"))),
                    Contains("e0.json: tissue.material.youngs_modulus_Pa: must be > 0 (Pa), got 0"));
  CHECK_THROWS_WITH(load("nu", tissuePadScenario(materialWith("0.4", "0.5"))),
                    Contains("tissue.material.poisson_ratio: = 0.5 is outside [0, 0.5)"));
  CHECK_THROWS_WITH(load("nuneg", tissuePadScenario(materialWith("0.4", "-0.1"))),
                    Contains("tissue.material.poisson_ratio: = -0.1 is outside [0, 0.5)"));
  CHECK_THROWS_WITH(load("rho", tissuePadScenario(materialWith("900", "-1"))),
                    Contains("tissue.material.density_kg_per_m3: must be > 0 (kg/m^3), got -1"));
  CHECK_THROWS_WITH(load("stretch", tissuePadScenario(materialWith("[1.1, 1, 1.05]", "[1, 0, 1]"))),
                    Contains("tissue.material.prestretch: must be > 0 along every axis"));
  const std::string unheld = R"(, "material": {"youngs_modulus_Pa": 20000})";
  CHECK_THROWS_WITH(load("unheld", tissuePadScenario(unheld)),
                    Contains("tissue.fixed: is missing: a simulated tissue must be held somewhere"));
  CHECK_THROWS_WITH(load("emptyfixed", tissuePadScenario(unheld + R"(, "fixed": [])")),
                    Contains("tissue.fixed: must be a non-empty array"));
  CHECK_THROWS_WITH(
      load("boxorder", tissuePadScenario(unheld + R"(, "fixed": [{"min_m": [0, 0, 0], "max_m": [1, -1, 1]}])")),
      Contains("tissue.fixed[0].max_m: must be >= min_m along every axis"));
  CHECK_THROWS_WITH(load("nomin", tissuePadScenario(unheld + R"(, "fixed": [{"max_m": [1, 1, 1]}])")),
                    Contains("tissue.fixed[0].min_m: is missing"));
  // The physics' keys without a material.
  CHECK_THROWS_WITH(load("gravityonly", tissuePadScenario("", R"(, "gravity_m_per_s2": [0, -9.81, 0])")),
                    Contains("gravity_m_per_s2: is only for a simulated tissue (give tissue.material)"));
  CHECK_THROWS_WITH(load("rateonly", tissuePadScenario("", R"(, "physics_rate_hz": 100)")),
                    Contains("physics_rate_hz: is only for a simulated tissue"));
  CHECK_THROWS_WITH(load("fixedonly", tissuePadScenario(R"(, "fixed": [{"min_m": [0, 0, 0], "max_m": [1, 1, 1]}])")),
                    Contains("tissue.fixed: is only for a simulated tissue"));
  // No kernel opening: only a simulated tissue's own tension opens the wound.
  CHECK_THROWS_WITH(load("shut", tissuePadScenario("", R"(, "incision": {"opening_m": 0})")),
                    Contains("shut.json: incision.opening_m: = 0 leaves the lips touching: only a simulated tissue"));
  CHECK(load("shutsimulated", tissuePadScenario(kMaterial, R"(, "incision": {"opening_m": 0})"))
            .world.cutter.incision.opening_m == 0.0);
  CHECK_THROWS_WITH(load("negopening", tissuePadScenario(kMaterial, R"(, "incision": {"opening_m": -0.001})")),
                    Contains("incision.opening_m: -0.001 is outside [0, 1]"));
  // At most the frame rate; an unknown key in the material is refused like any other.
  CHECK_THROWS_WITH(load("fastphysics", tissuePadScenario(kMaterial, R"(, "physics_rate_hz": 2000)")),
                    Contains("physics_rate_hz: 2000 is outside [10, 1000]"));
  CHECK_THROWS_WITH(load("typo", tissuePadScenario(materialWith("\"poisson_ratio\"", "\"poisson\""))),
                    Contains("tissue.material.poisson"));
}

TEST_CASE("tissue physics: a material without tissue.tets is simulated on tets made with that key's defaults",
          "[sim]") {
  // The tets are what is simulated: a user who gives a material and no tets gets them made at load, as if
  // "tets": {} were given (TetGen on the surface, quality bound 2, the surface kept).
  const sim::Scenario s = load("notets", R"({"tissue": {"shape": "pad", "size_m": [0.02, 0.01, 0.02], "grid_m": 0.002,
      "material": {}, "fixed": [{"min_m": [-1, -1, -1], "max_m": [1, -0.0099, 1]}]},
      "gravity_m_per_s2": [0, -9.81, 0], "pose_source": {"kind": "strokes", "strokes": [{}]}})");
  REQUIRE(s.world.physics.enabled);
  REQUIRE(s.world.tets.enabled);
  const sim::TetTissueOptions defaults;
  CHECK(s.world.tets.mesh.max_volume_m3 == defaults.mesh.max_volume_m3);
  CHECK(s.world.tets.mesh.radius_edge_ratio == defaults.mesh.radius_edge_ratio);
  CHECK(s.world.tets.mesh.keep_surface == defaults.mesh.keep_surface);
  sim::World world(sim::loadTissue(s), s.world);
  REQUIRE(world.tets() != nullptr);
  CHECK(world.tets()->tetCount() > 100);
  REQUIRE(world.physics() != nullptr);
  const physics::TissueModel& model = world.physics()->model();
  CHECK(model.elementCount() == world.tets()->tetCount());
  // Under gravity, held at its base, the pad sags: its top (y = 0 at rest) comes down.
  world.physics()->advance(0.0);  // the first call sets the physics clock
  CHECK(world.physics()->advance(0.2) == 20);
  double highest_top_m = -1.0;  // now, of the nodes on the top at rest
  int top_nodes = 0;
  for (int n = 0; n < model.nodeCount(); ++n) {
    if (!(model.restPositions_m()[static_cast<std::size_t>(n)].y() > -1e-9)) continue;
    ++top_nodes;
    highest_top_m = std::max(highest_top_m, model.positions_m()[static_cast<std::size_t>(n)].y());
  }
  REQUIRE(top_nodes > 10);
  CHECK(highest_top_m < -1e-6);
  CHECK(world.physics()->counters().non_finite == 0);
}

TEST_CASE("tissue physics: a boundary that holds no node is refused when the world is made", "[sim]") {
  sim::Scenario s = load("heldnothing", tissuePadScenario(R"(, "material": {}, "fixed": [{"min_m": [5, 5, 5],
      "max_m": [6, 6, 6]}])"));
  CHECK_THROWS_AS(sim::World(sim::loadTissue(s), s.world), std::invalid_argument);
}

TEST_CASE(
    "tissue physics: steps at its rate of simulated time, cuts reach the model at the next step, the tool in both frames",
    "[sim]") {
  test::ShippedScenario l = test::loadShipped("pad-tension");
  sim::World& world = *l.world;
  REQUIRE(world.physics() != nullptr);
  const std::int64_t period_us = l.scenario.periodUs();
  const double dt_s = static_cast<double>(period_us) * 1e-6, t0_s = l.poses.front().time_s;
  std::size_t fed = 0;
  std::int64_t frames = 0, frames_with_new_nodes = 0, frames_tip_mapped = 0;
  int last_nodes = world.physics()->model().nodeCount();
  const double end_s = l.poses.back().time_s;
  for (std::int64_t k = 0; t0_s + static_cast<double>(k) * dt_s <= end_s; ++k, ++frames) {
    const double t_s = t0_s + static_cast<double>(k) * dt_s;
    std::size_t first = fed;
    while (fed < l.poses.size() && l.poses[fed].time_s <= t_s + 1e-12) ++fed;
    const std::int64_t steps_before = world.physics()->stepsDone();
    const sim::StepResult result = world.step(std::span(l.poses.data() + first, fed - first), dt_s, t_s);
    CHECK(world.physics()->stepsDue() == world.physics()->stepsDone());  // inline: taken in the frame
    // The tool as the device gave it beside its pose in the rest frame (the tip moved by the mapping).
    if (fed > 0) {
      REQUIRE(result.haptic.world_tip_m == l.poses[fed - 1].tip_m);
      REQUIRE(result.haptic.world_orientation.coeffs() == l.poses[fed - 1].orientation.coeffs());
      if ((result.haptic.tip_m - result.haptic.world_tip_m).norm() > 0.0005) ++frames_tip_mapped;
    }
    // A pose at t_s is mapped to the rest frame with the map of kMapLagSteps before the last step due.
    const physics::RestMap map = world.physics()->restMapAt(t_s);
    const std::int64_t lagged = world.physics()->stepsDue() - sim::TissuePhysics::kMapLagSteps;
    REQUIRE(map.step == std::max<std::int64_t>(0, lagged));
    if (world.physics()->stepsDone() == steps_before) continue;
    // Every node of every piece the cutter holds is in the model after a frame that took a step.
    int used_max = -1;
    const tets::TetCutter& tets = *world.tets();
    for (int b = 0; b < tets.baseTetCount(); ++b)
      for (const tets::TetChild& c : tets.children(b))
        used_max = std::max({used_max, c.nodes[0], c.nodes[1], c.nodes[2], c.nodes[3]});
    REQUIRE(used_max < world.physics()->model().nodeCount());
    if (world.physics()->model().nodeCount() != last_nodes) ++frames_with_new_nodes;
    last_nodes = world.physics()->model().nodeCount();
  }
  CHECK(frames_with_new_nodes > 10);  // the cut arrives step by step, not at the end
  CHECK(frames_tip_mapped > 100);     // in the sunken tissue the rest-frame tip is a millimetre off
  // Step k at t0 + k / rate: frames 0 .. frames-1 cover (frames - 1) ms, 10 ms a step.
  const std::int64_t expected = (frames - 1) * period_us / 10000;
  CHECK(world.physics()->counters().steps == expected);
  CHECK(world.physics()->counters().non_finite == 0);
  CHECK(world.physics()->counters().pieces_refused == 0);
  CHECK(world.physics()->counters().reserve_overflows == 0);
  CHECK(world.physics()->counters().cuts_applied > 10);
}

TEST_CASE("tissue physics: a cut in a tensioned, held pad gapes by itself, untensioned it does not", "[sim][slow]") {
  // The shipped pad's incision has no kernel opening (incision.opening_m 0): at rest its lips touch.
  const PadRun tense = replayPad();
  REQUIRE(tense.run.scenario.world.cutter.incision.opening_m == 0.0);
  const sim::TissuePhysics& physics = *tense.run.world->physics();
  REQUIRE(tense.run.world->incisions() == 1);
  const mesh::SurfaceMesh& rest = tense.run.world->tissue();
  const mesh::SurfaceMesh deformed = physics.deformedSurface(rest);
  const double rest_width_m = woundWidthM(rest, rest), width_m = woundWidthM(rest, deformed);
  const Eigen::Vector3d none(1.0, 1.0, 1.0);
  const PadRun slack = replayPad(&none);
  const mesh::SurfaceMesh& slack_rest = slack.run.world->tissue();
  const double slack_width_m = woundWidthM(slack_rest, slack.run.world->physics()->deformedSurface(slack_rest));
  // The DFFD kernel's opening stays available: untensioned, the tissue holds it.
  const PadRun kernel = replayPad(&none, sim::ReplayPace::Fast, {}, 0.0002);
  const mesh::SurfaceMesh& kernel_rest = kernel.run.world->tissue();
  const double kernel_width_m = woundWidthM(kernel_rest, kernel.run.world->physics()->deformedSurface(kernel_rest));
  INFO("wound " << width_m * 1e3 << " mm wide tensioned, " << slack_width_m * 1e3 << " mm without tension, "
                << rest_width_m * 1e3 << " mm at rest, " << kernel_width_m * 1e3 << " mm with a 0.2 mm kernel");
  // The lips touch at rest (the path at rest wavers by micrometres: the blade is mapped through the tissue
  // opening behind it).
  CHECK(rest_width_m < 5e-5);
  CHECK(width_m > 0.002);       // the lips pulled apart by the tissue alone
  CHECK(slack_width_m < 1e-5);  // without tension nothing opens the wound
  CHECK(kernel_width_m > 0.00018);
  CHECK(kernel_width_m < 0.00025);
  // The groove's floor is a crack's tip: the opened lips concentrate the strain there, and one thin tet below
  // it (1.5e-10 m^3 at rest) ends inverted; co-rotation holds it, nothing blows up.
  CHECK(physics.counters().max_inverted <= 1);
  CHECK(physics.counters().non_finite == 0);
  for (const Eigen::Vector3d& p : physics.model().positions_m()) REQUIRE(p.allFinite());
  // The held boxes (the base, the two side walls) stay where they are, every other node is free to move.
  const auto rest_x = physics.model().restPositions_m();
  const auto x = physics.model().positions_m();
  int held = 0;
  for (std::size_t n = 0; n < rest_x.size(); ++n) {
    const Eigen::Vector3d& r = rest_x[n];
    if (!(r.y() <= -0.0099 || std::abs(r.x()) >= 0.0199)) continue;
    REQUIRE(physics.model().isHeld(static_cast<int>(n)));
    REQUIRE((x[n] - r).norm() == 0.0);
    ++held;
  }
  CHECK(held > 100);

  // The skin follows its own lip: vertices near the cut on top move away from the cut plane, each on its side.
  const double plane_x = cutPlaneX(rest);
  int lip_vertices = 0;
  for (const auto v : rest.mesh().vertices()) {
    const Eigen::Vector3d r = mesh::toEigen(rest.mesh().point(v));
    if (std::abs(r.x() - plane_x) > 0.001 || r.y() < -1e-4 || std::abs(r.z()) > 0.006) continue;
    const Eigen::Vector3d d = mesh::toEigen(deformed.mesh().point(v));
    INFO("vertex " << v.idx() << " at rest x " << r.x() << ", simulated x " << d.x() << ", plane " << plane_x);
    if (rest.kind(v) == mesh::VertexKind::Seam) {  // on the plane at rest: its lip pulls it off by itself
      REQUIRE(std::abs(d.x() - plane_x) > 0.0003);
    } else {
      REQUIRE((d.x() - plane_x) * (r.x() - plane_x) > 0.0);
      REQUIRE(std::abs(d.x() - plane_x) > std::abs(r.x() - plane_x));
    }
    ++lip_vertices;
  }
  CHECK(lip_vertices > 10);
}

// The deepest wall vertex of the groove around the cut's middle (|z| < 8 mm), at rest or as simulated.
double grooveBottomY(const mesh::SurfaceMesh& rest, const mesh::SurfaceMesh& x) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto v : rest.mesh().vertices())
    if (rest.kind(v) == mesh::VertexKind::Wall && std::abs(rest.mesh().point(v)[2]) < 0.008)
      lowest = std::min(lowest, static_cast<double>(x.mesh().point(v)[1]));
  return lowest;
}

TEST_CASE("tissue physics: a cut along the pad's grid line gapes, each lip following its own tets", "[sim]") {
  // x = 0 is a plane of the pad's grid: the tets have faces on the cut, and with no kernel opening each lip's
  // vertices lie on faces of tets on both sides. A lip must follow its own side's tets (an uncut tet beside
  // it), not the tet across the plane: then the lips part as on the shipped stroke.
  test::ShippedScenario l = test::loadShipped("pad-tension");
  REQUIRE(l.scenario.strokes.size() == 1);
  l.scenario.strokes[0].start_m.x() = 0.0;
  l.poses = sim::posesForStrokes(sim::loadTissue(l.scenario), l.scenario.strokes, l.scenario.world, l.scenario.rate_hz);
  sim::ReplayOptions options;
  options.period_us = l.scenario.periodUs();
  options.settle_s = l.scenario.settle_s;
  sim::replay(*l.world, l.poses, options);
  REQUIRE(l.world->incisions() == 1);
  const mesh::SurfaceMesh& rest = l.world->tissue();
  const mesh::SurfaceMesh deformed = l.world->physics()->deformedSurface(rest);
  const double width_m = woundWidthM(rest, deformed);
  INFO("wound " << width_m * 1e3 << " mm wide, " << woundWidthM(rest, rest) * 1e3 << " mm at rest");
  CHECK(woundWidthM(rest, rest) < 5e-5);
  CHECK(width_m > 0.001);
  // Every seam vertex on top near the middle moved off the plane, to its own lip's side (its neighbours').
  int seam = 0;
  for (const auto v : rest.mesh().vertices()) {
    const Eigen::Vector3d r = mesh::toEigen(rest.mesh().point(v));
    if (rest.kind(v) != mesh::VertexKind::Seam || r.y() < -1e-4 || std::abs(r.z()) > 0.006) continue;
    double side = 0.0;  // its lip's side: the mean x of its original neighbours on top
    for (const auto u : rest.mesh().vv_range(v))
      if (rest.kind(u) == mesh::VertexKind::Original) side += rest.mesh().point(u)[0];
    const double moved_x = deformed.mesh().point(v)[0] - r.x();
    INFO("seam vertex " << v.idx() << " at z " << r.z() << " moved " << moved_x * 1e3 << " mm across");
    REQUIRE(side != 0.0);
    REQUIRE(moved_x * side > 0.0);
    REQUIRE(std::abs(moved_x) > 0.0002);
    ++seam;
  }
  CHECK(seam > 4);
}

TEST_CASE("tissue physics: the pad's wound walls each follow their own lip", "[sim]") {
  // With no kernel opening the two walls coincide at rest; each wall vertex must follow the tets behind it,
  // not those of the wall it touches (or the walls pass through each other as the wound opens).
  const PadRun run = replayPad();
  const mesh::SurfaceMesh& rest = run.run.world->tissue();
  const WallSides sides = wallSides(rest, run.run.world->physics()->deformedSurface(rest));
  INFO(sides.wrong << " of " << sides.walls << " wall vertices moved towards the wall they face; " << sides.floor
                   << " on the groove's floor");
  CHECK(sides.walls > 40);
  CHECK(sides.wrong == 0);
  CHECK(sides.floor > 10);
}

TEST_CASE("tissue physics: the blade is mapped to the rest frame, the groove reaches where the blade did", "[sim]") {
  // The tensioned pad's top sinks about a millimetre as its held sides stretch it (Poisson). The blade, 4 mm
  // below the pad's rest top in the world, is about 3 mm into the sunken tissue: the incision, made at rest,
  // is that deep in the tissue, and the groove as simulated ends where the blade's tip was.
  const PadRun run = replayPad();
  const sim::TissuePhysics& physics = *run.run.world->physics();
  double blade_y = std::numeric_limits<double>::infinity();
  for (const devices::PoseSample& p : run.run.poses) blade_y = std::min(blade_y, p.tip_m.y());
  const mesh::SurfaceMesh& rest = run.run.world->tissue();
  const double rest_bottom_y = grooveBottomY(rest, rest);
  const double bottom_y = grooveBottomY(rest, physics.deformedSurface(rest));
  INFO("blade tip down to y " << blade_y * 1e3 << " mm; groove bottom at rest " << rest_bottom_y * 1e3
                              << " mm, as simulated " << bottom_y * 1e3 << " mm");
  CHECK(rest_bottom_y > blade_y + 0.0005);        // shallower at rest: the tissue had sunk under the blade
  CHECK(std::abs(bottom_y - blade_y) < 0.00015);  // as simulated, where the blade reached
  CHECK(physics.counters().stale_maps == 0);
  CHECK(physics.counters().dropped_maps == 0);
}

TEST_CASE("tissue physics: a tool pressing the pad without cutting dents it and feels the dent, smoothly", "[sim]") {
  // The blade, its cut button up, goes 4 mm below the settled pad's top, holds, and lifts off. The skin
  // under it sinks millimetres (the press spring, tissue.stiffness_N_per_m, pushes the tets' nodes), the
  // force felt is the spring's against the dent (less than against a rigid skin), steady while the press
  // is (no step at the physics rate), nothing is cut, and the skin comes back once the blade is off.
  test::ShippedScenario l = test::loadShipped("pad-tension");
  const test::PadPress press;
  const std::vector<devices::PoseSample> poses = test::padPressPoses(press);
  const double dt_s = 0.001, settle_s = press.settle_s, down_s = press.down_s, hold_s = press.hold_s;
  const double low_m = press.low_y_m;
  const Eigen::Vector3d above(press.x_m, press.above_y_m, press.z_m);
  sim::World& world = *l.world;
  const sim::TissuePhysics& physics = *world.physics();
  const Eigen::Vector3d rest_top(above.x(), 0.0, above.z());
  Eigen::Vector3d settled_m = Eigen::Vector3d::Zero(), pressed_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();
  double largest_change_N = 0.0;
  Eigen::Vector3d last_force_N = Eigen::Vector3d::Zero();
  for (const devices::PoseSample& pose : poses) {
    const Eigen::Vector3d f = world.step(std::span(&pose, 1), dt_s, pose.time_s).haptic.force_N;
    const double t = pose.time_s;
    if (std::abs(t - settle_s) < 1e-9) settled_m = physics.deformedPoint(rest_top);
    if (t > settle_s + down_s + 0.0015 && t <= settle_s + down_s + hold_s)  // the tool held still
      largest_change_N = std::max(largest_change_N, (f - last_force_N).norm());
    if (std::abs(t - (settle_s + down_s + hold_s)) < 1e-9) pressed_m = physics.deformedPoint(rest_top), force_N = f;
    last_force_N = f;
  }
  const Eigen::Vector3d back_m = physics.deformedPoint(rest_top);
  const double depth_m = settled_m.y() - low_m;  // the blade's tip below the settled skin
  const double k_N_per_m = l.scenario.world.tissue.stiffness_N_per_m;
  INFO("skin settled at y " << settled_m.y() * 1e3 << " mm, pressed " << pressed_m.y() * 1e3 << " mm, back "
                            << back_m.y() * 1e3 << " mm; force " << force_N.transpose() << " N (rigid skin: "
                            << k_N_per_m * depth_m << " N); largest frame-to-frame change while held "
                            << largest_change_N * 1e3 << " mN; pressed steps " << physics.counters().pressed_steps);
  CHECK(settled_m.y() - pressed_m.y() > 0.0015);    // the skin gave
  CHECK(force_N.y() > 0.1);                         // pushed back up ...
  CHECK(force_N.y() < 0.8 * k_N_per_m * depth_m);   // ... less than a rigid skin would
  CHECK(largest_change_N < 0.02 * force_N.norm());  // the dent settling, no step at the physics rate
  CHECK(physics.counters().pressed_steps > 100);
  CHECK(world.cutter().stats().incisions == 0);
  CHECK(physics.counters().cuts_applied == 0);
  CHECK((back_m - settled_m).norm() < 5e-5);
  CHECK(last_force_N.isZero());
}

TEST_CASE("tissue physics: a physics thread behind maps the blade with its newest map, counted stale", "[sim]") {
  // Frames about a millisecond apart, the physics thread 50 ms a step (its period is 10 ms): it falls behind,
  // and a pose's map (four steps before its time) is not made yet. The newest made stands in, never the
  // identity.
  test::ShippedScenario l = test::loadShipped("pad-tension");
  sim::World& world = *l.world;
  sim::TissuePhysics& physics = *world.physics();
  sim::PhysicsThreadOptions options;
  std::atomic<bool> slow{true};  // slow until the frames end, then the thread catches up at once
  options.before_step = [&slow](std::int64_t) {
    if (slow.load()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  };
  physics.startThread(options);
  std::int64_t stale_seen = 0, newest_seen = 0;
  stepFrames(l, [&](double t_s) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // about real time: the physics at half its rate
    const physics::RestMap map = physics.restMapAt(t_s);
    const std::int64_t want = physics.stepsDue() - sim::TissuePhysics::kMapLagSteps;
    REQUIRE(map.step <= std::max<std::int64_t>(0, want));
    REQUIRE(map.step >= newest_seen);  // never an older map than one already taken (nor the identity)
    newest_seen = map.step;
    if (want > 0 && map.step < want) ++stale_seen;
  });
  slow.store(false);
  physics.stopThread();
  INFO(stale_seen << " frames took an older map; newest map step " << newest_seen);
  CHECK(stale_seen > 100);
  CHECK(newest_seen > 0);
  CHECK(physics.counters().stale_maps >= stale_seen);
  CHECK(physics.counters().dropped_maps == 0);
}

TEST_CASE("tissue physics: a picture's copy of the geometry has the surface and the tets as simulated", "[sim]") {
  const PadRun run = replayPad();
  sim::World& world = *run.run.world;
  sim::GeometryMirror at_rest, simulated;
  sim::copyGeometry(world, run.frames - 1, at_rest);
  sim::copySimulatedGeometry(world, run.frames - 1, simulated);
  const mesh::SurfaceMesh deformed = world.physics()->deformedSurface(world.tissue());
  REQUIRE(simulated.positions_m().size() == at_rest.positions_m().size());
  CHECK(simulated.faces() == at_rest.faces());
  CHECK(simulated.vertexKind() == at_rest.vertexKind());
  int moved = 0;
  for (const auto v : deformed.mesh().vertices()) {
    const auto i = static_cast<std::size_t>(v.idx());
    const auto& p = deformed.mesh().point(v);
    REQUIRE(simulated.positions_m()[i] == std::array<double, 3>{p[0], p[1], p[2]});
    const auto& r = at_rest.positions_m()[i];
    moved += std::hypot(r[0] - p[0], r[1] - p[1], r[2] - p[2]) > 0.0005;
  }
  CHECK(moved > 50);  // the sunken top and the open lips
  // The tets' nodes too (render --tets), the cutter's node n at the model's node n.
  const std::span<const Eigen::Vector3d> x = world.physics()->model().positions_m();
  const auto& nodes = simulated.tets().positions_m();
  REQUIRE(at_rest.tets().positions_m().size() == nodes.size());
  REQUIRE(nodes.size() <= x.size());
  int moved_nodes = 0;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    REQUIRE(nodes[n] == std::array<double, 3>{x[n].x(), x[n].y(), x[n].z()});
    const auto& r = at_rest.tets().positions_m()[n];
    moved_nodes += std::hypot(r[0] - x[n].x(), r[1] - x[n].y(), r[2] - x[n].z()) > 0.0005;
  }
  CHECK(moved_nodes > 50);
  CHECK(simulated.tets().boundary() == at_rest.tets().boundary());
}

TEST_CASE("tissue physics: real time and fast replays give the same simulated tissue", "[sim][slow]") {
  // Both step on the physics thread; the real-time frames only hand the steps over.
  const PadRun fast = replayPad();
  const PadRun realtime = replayPad(nullptr, sim::ReplayPace::RealTime);
  CHECK(fast.frames == realtime.frames);
  const SimulatedBytes a = simulatedBytes(*fast.run.world), b = simulatedBytes(*realtime.run.world);
  CHECK(a.steps > 100);
  CHECK(a.cuts_applied > 10);
  CHECK(a.surface.size() > 1000);
  const sim::PhysicsCounters c = realtime.run.world->physics()->counters();
  if (c.stale_maps == 0) {
    CHECK(a == b);
  } else {  // a loaded machine: the physics more than four steps behind a pose, counted (then bytes may differ)
    WARN(c.stale_maps << " poses mapped with an older step's map: real time and fast not compared");
  }
  CHECK(c.deferred == 0);
  CHECK(fast.run.world->physics()->counters().deferred == 0);
  CHECK_FALSE(realtime.run.world->physics()->threaded());  // ended with the replay: the model is the caller's

  // A press (a dent) before the stroke: the press's steps depend on the poses' times only.
  const PadRun pressed_fast = replayPad(nullptr, sim::ReplayPace::Fast, {}, -1.0, true);
  const PadRun pressed_realtime = replayPad(nullptr, sim::ReplayPace::RealTime, {}, -1.0, true);
  const sim::PhysicsCounters pc = pressed_realtime.run.world->physics()->counters();
  CHECK(pressed_fast.run.world->physics()->counters().pressed_steps > 100);
  CHECK(pc.pressed_steps == pressed_fast.run.world->physics()->counters().pressed_steps);
  if (pc.stale_maps == 0)
    CHECK(simulatedBytes(*pressed_fast.run.world) == simulatedBytes(*pressed_realtime.run.world));
  else
    WARN(pc.stale_maps << " poses mapped with an older step's map: the pressed runs not compared");
}

TEST_CASE("tissue physics: the steps run on the physics thread, the frame does not pay for them", "[sim][slow]") {
  std::mutex m;
  std::set<std::thread::id> stepping;
  const auto caller = std::this_thread::get_id();
  const PadRun fast = replayPad(nullptr, sim::ReplayPace::Fast, [&](std::int64_t) {
    const std::lock_guard<std::mutex> lock(m);  // a test's hook: the physics thread may lock here
    stepping.insert(std::this_thread::get_id());
  });
  REQUIRE(stepping.size() == 1);
  CHECK(*stepping.begin() != caller);  // fast: the frames run on the caller's thread, the steps not
  // Every step made 4 ms longer on the physics thread (a step is 1.4 ms, its period 10 ms): a frame that ran
  // a step, or waited for one, would take 4 ms more. One frame in ten carries a step's poses, so the frames'
  // p99 would be over 4 ms; the frames' p99 is 0.25 ms on an idle machine, 1.4 ms on a loaded one.
  constexpr double kStepStallUs = 4000.0;
  const PadRun realtime = replayPad(nullptr, sim::ReplayPace::RealTime, [](std::int64_t) {
    std::this_thread::sleep_for(std::chrono::microseconds(static_cast<std::int64_t>(kStepStallUs)));
  });
  const sim::LatencySummary& l = realtime.report.latency;
  INFO("frame p99 " << l.frame_us.p99 << " us, physics step p50 " << l.physics_step_us.p50 << " us over "
                    << l.physics_frames << " steps");
  CHECK(l.physics_frames == realtime.run.world->physics()->counters().steps);  // a time per step
  CHECK(l.physics_step_us.p50 > 0.0);
  CHECK(l.frame_us.p99 < kStepStallUs);
}

TEST_CASE("tissue physics: a physics thread slower than its rate is counted late, the tissue is the same",
          "[sim][slow]") {
  const PadRun fast = replayPad();
  // Every eighth step 15 ms late to start (a period is 10 ms): late, and the thread catches up after it.
  // At most two steps wait behind it, so their cuts never run out of the four hand-over buffers (that
  // would defer a cut to a later step: counted, and then the tissue would differ) even on a loaded machine.
  const PadRun slow = replayPad(nullptr, sim::ReplayPace::RealTime, [](std::int64_t k) {
    if (k % 8 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(15));
  });
  const std::int64_t steps = slow.run.world->physics()->counters().steps;
  INFO(slow.report.latency.physics_late << " of " << steps << " steps late");
  CHECK(slow.report.latency.physics_late >= steps / 8);
  CHECK(slow.run.world->physics()->counters().late == slow.report.latency.physics_late);
  CHECK(slow.run.world->physics()->counters().deferred == 0);
  // Late steps change nothing while the blade's maps are made in time (four steps before a pose's time);
  // on a loaded machine a 15 ms stall can leave a pose without its own map, which is counted.
  const std::int64_t stale = slow.run.world->physics()->counters().stale_maps;
  if (stale == 0) {
    CHECK(simulatedBytes(*fast.run.world) == simulatedBytes(*slow.run.world));
  } else {
    WARN(stale << " poses mapped with an older step's map: the tissues not compared");
  }
  CHECK(fast.report.latency.physics_late == 0);  // not against the clock: no step is late
  CHECK(fast.run.world->physics()->counters().late == 0);
}

TEST_CASE("tissue physics: a geometry stream reading the same tet journal changes nothing in the model",
          "[sim][slow]") {
  // The stream clears the tets' journal every frame; the physics reads it first, past where it last read.
  const PadRun alone = replayPad();
  test::ShippedScenario l = test::loadShipped("pad-tension");
  sim::GeometryStream stream;
  sim::ReplayOptions options;
  options.period_us = l.scenario.periodUs();
  options.settle_s = l.scenario.settle_s;
  options.geometry = &stream;
  sim::replay(*l.world, l.poses, options);
  CHECK(l.world->physics()->counters().cuts_applied == alone.run.world->physics()->counters().cuts_applied);
  CHECK(l.world->physics()->model().nodeCount() == alone.run.world->physics()->model().nodeCount());
  CHECK(l.world->physics()->positionsHash() == alone.run.world->physics()->positionsHash());
}

TEST_CASE("tissue physics: the physics thread publishes each step's node positions, read without waiting",
          "[sim][threads]") {
  // A reader thread (as the viewer's) polls the newest state while the frames hand a press and the stroke's
  // steps over to the physics thread; ThreadSanitizer runs it too.
  test::ShippedScenario l = test::loadShipped("pad-tension");
  l.poses = test::followedBy(test::padPressPoses({}), l.poses);
  sim::World& world = *l.world;
  sim::TissuePhysics& physics = *world.physics();
  physics.startThread({});
  REQUIRE(physics.latestState() == nullptr);  // no step yet (read here, before the reader thread takes over)
  std::atomic<bool> done{false};
  std::int64_t last_seen = 0, reads = 0, older = 0, small = 0;
  std::thread reader([&] {
    while (!done.load(std::memory_order_acquire)) {
      if (const sim::PhysicsState* s = physics.latestState()) {
        older += s->step < last_seen;  // never older than what was read before
        small += s->nodes < 1000;
        last_seen = s->step, ++reads;
      }
      std::this_thread::yield();
    }
  });
  stepFrames(l, [](double) {});
  physics.stopThread();
  done.store(true, std::memory_order_release);
  reader.join();
  const sim::PhysicsState* s = physics.latestState();
  REQUIRE(s != nullptr);
  CHECK(reads > 0);
  CHECK(older == 0);
  CHECK(small == 0);
  CHECK(physics.counters().pressed_steps > 50);
  CHECK(s->step == physics.counters().steps);  // the last step's state
  const auto x = physics.model().positions_m();
  REQUIRE(s->nodes == x.size());
  for (std::size_t n = 0; n < x.size(); ++n) REQUIRE(s->x_m[n] == x[n]);
}
