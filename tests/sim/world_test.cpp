#include "incise/sim/world.h"
#include "incise/incision/surface_cutter.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <tuple>

#include "incise/incision/stroke_path.h"
#include "incise/mesh/mesh_hash.h"
#include "incise/mesh/self_intersection.h"
#include "incise/mesh/shapes.h"
#include "incise/sim/scenario.h"
#include "incise/sim/stroke_poses.h"

using namespace incise;
using Catch::Matchers::Contains;

namespace {

mesh::SurfaceMesh bunny() {
  return mesh::subdivided(mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01), 2);
}

// A pose with the blade pointing down -y (local -z) and its edge along +x, tip at `tip`.
devices::PoseSample poseAt(const Eigen::Vector3d& tip, double t_s, std::uint32_t buttons = 1) {
  devices::PoseSample p;
  p.time_s = t_s;
  p.tip_m = tip;
  Eigen::Matrix3d r;
  r << Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY().cross(Eigen::Vector3d::UnitX()), Eigen::Vector3d::UnitY();
  p.orientation = Eigen::Quaterniond(r);
  p.buttons = buttons;
  return p;
}

// Where a vertical ray at (x, z) meets the bunny's back.
Eigen::Vector3d surfaceAt(const mesh::SurfaceMesh& mesh, double x, double z) {
  incision::StrokePathOptions o;
  o.start_m = Eigen::Vector3d(x, 0.0, z);
  o.length_m = 0.001;
  return incision::strokeAlongPath(mesh, o).first.point_m;
}

// One frame: the haptic part, then the cut phase (which takes the pose and refills the contact proxy).
sim::HapticState frameOf(sim::World& world, const devices::PoseSample& pose) {
  const sim::HapticState h = world.updateTool(std::span(&pose, 1), 0.001);
  world.cut(pose.time_s);
  return h;
}

}  // namespace

TEST_CASE("world: no contact above the surface, a penalty force along the normal below it", "[sim]") {
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh tissue = bunny();
  const Eigen::Vector3d surface = surfaceAt(tissue, 0.005, 0.015);
  sim::World world(tissue, options);

  const auto above = poseAt(surface + Eigen::Vector3d(0, 0.002, 0), 0.0, 0);
  sim::HapticState h = frameOf(world, above);  // the first frame: no proxy yet, so no contact could be found
  REQUIRE(h.proxy_miss);
  REQUIRE_FALSE(h.contact);
  REQUIRE(h.force_N.norm() == 0.0);
  h = frameOf(world, poseAt(above.tip_m, 0.0005, 0));
  REQUIRE_FALSE(h.proxy_miss);
  REQUIRE_FALSE(h.contact);

  // 1 mm in, the button up: contact and a spring force, no cut. Down there in two frames: the proxy's reach
  // (2 mm at 1 kHz) covers the blade's motion between refills, not a 3 mm jump in one frame.
  h = frameOf(world, poseAt(surface + Eigen::Vector3d(0, 0.0005, 0), 0.001, 0));
  REQUIRE_FALSE(h.proxy_miss);
  REQUIRE_FALSE(h.contact);
  auto in = poseAt(surface - Eigen::Vector3d(0, 0.001, 0), 0.0015, 0);
  h = frameOf(world, in);
  REQUIRE(h.contact);
  REQUIRE_FALSE(h.cutting);
  REQUIRE(h.penetration_m == Approx(0.001 * std::abs(h.normal.y())).epsilon(0.05));
  REQUIRE(h.force_N.dot(h.normal) > 0.0);  // pushes the tool out
  // Damping: the tool moved 3 mm into the tissue in 1 ms; the damper resists that, adding to the spring.
  const double inward_speed = -h.normal.dot(Eigen::Vector3d(0, -3.0, 0));
  REQUIRE(h.force_N.norm() ==
          Approx(options.tissue.stiffness_N_per_m * h.penetration_m + options.tissue.damping_N_s_per_m * inward_speed)
              .epsilon(1e-9));
  // Holding still: the spring alone.
  in.time_s = 0.0025;
  h = frameOf(world, in);
  REQUIRE(h.force_N.norm() == Approx(options.tissue.stiffness_N_per_m * h.penetration_m).epsilon(1e-9));

  // Deep in: clamped to the device's limit.
  const auto deep = poseAt(surface - Eigen::Vector3d(0, 0.0025, 0), 0.0035, 0);  // 1.5 mm on: within reach
  sim::WorldOptions stiff = options;
  stiff.tissue.stiffness_N_per_m = 1e5;
  sim::World stiff_world(tissue, stiff);
  frameOf(stiff_world, in);
  h = frameOf(stiff_world, deep);
  REQUIRE(h.force_N.norm() == Approx(stiff.tissue.max_force_N));
  REQUIRE(world.incisions() == 0);
}

TEST_CASE("world: cutting resistance opposes the blade's motion while it cuts", "[sim]") {
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh tissue = bunny();
  sim::World world(tissue, options);
  const Eigen::Vector3d s0 = surfaceAt(tissue, 0.004, 0.015), s1 = surfaceAt(tissue, 0.0041, 0.015);
  const devices::PoseSample poses[2] = {poseAt(s0 - Eigen::Vector3d(0, 0.002, 0), 0.0),
                                        poseAt(s1 - Eigen::Vector3d(0, 0.002, 0), 0.001)};
  frameOf(world, poses[0]);  // the cut phase begins the incision
  const sim::HapticState h = frameOf(world, poses[1]);
  REQUIRE(h.cutting);
  const Eigen::Vector3d tangential = h.force_N - h.force_N.dot(h.normal) * h.normal;
  REQUIRE(tangential.x() < -0.5 * options.tissue.cutting_resistance_N);  // the blade moves +x
  REQUIRE(world.incisions() == 1);
}

TEST_CASE("world: a stroke of poses cuts the tissue, bad poses are skipped", "[sim]") {
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh tissue = bunny();
  sim::StrokeSpec stroke;
  stroke.start_m = Eigen::Vector3d(-0.012, 0.0, 0.015);
  stroke.length_m = 0.03;
  std::vector<devices::PoseSample> poses = sim::posesForStrokes(tissue, {stroke}, options, 1000.0);
  sim::World world(tissue, options);
  int rejected = 0;
  for (size_t k = 0; k < poses.size(); ++k) {
    sim::HapticState h = world.step(std::span(&poses[k], 1), 0.001, poses[k].time_s).haptic;
    if (k == poses.size() / 2) {  // a NaN pose and one from the past, in the middle of the cut
      devices::PoseSample bad[2] = {poses[k], poses[k - 10]};
      bad[0].tip_m.x() = NAN;
      bad[0].time_s += 1e-4;
      h = world.updateTool(std::span(bad, 2), 0.001);
      rejected += h.poses_rejected;
    }
  }
  for (double t = poses.back().time_s; t < poses.back().time_s + 0.2; t += 0.001) world.cut(t);
  REQUIRE(rejected == 2);
  REQUIRE(world.incisions() == 1);
  REQUIRE(world.cutter().stats().vertices_duplicated > 40);
  REQUIRE_FALSE(world.cutter().pending());
  const mesh::ManifoldReport report = mesh::checkManifold(world.tissue().mesh());
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.euler_characteristic == 2);
}

TEST_CASE("world: bad parameters are refused at construction", "[sim]") {
  const mesh::SurfaceMesh tissue = bunny();
  sim::WorldOptions bad;
  bad.tissue.stiffness_N_per_m = -1.0;
  REQUIRE_THROWS_WITH(sim::World(tissue, bad), Contains("stiffness_N_per_m"));
  bad = sim::WorldOptions{};
  bad.tool.cut_button = 40;
  REQUIRE_THROWS_WITH(sim::World(tissue, bad), Contains("cut_button = 40"));
  bad = sim::WorldOptions{};
  bad.cutter.incision.depth_m = 0.0;
  REQUIRE_THROWS_WITH(sim::World(tissue, bad), Contains("depth_m = 0"));
}

TEST_CASE("world: a tet tissue too coarse for the lattice is refused at load, a fine one is not refined", "[sim]") {
  // Local refinement does not bisect tets, so a tet tissue must come fine enough, and its surface
  // is never refined (it must keep matching the tets' boundary).
  sim::WorldOptions options;
  options.tets.enabled = true;
  const mesh::SurfaceMesh coarse = mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01);
  REQUIRE_THROWS_WITH(sim::World(coarse, options),
                      Contains("the tet tissue (tissue.tets) is coarse next to the lattice") &&
                          Contains("3.83 mm on average") && Contains("its tets' median edge") &&
                          Contains("6.00 mm across the cut") && Contains("at most 3.00 mm"));
  // Subdivided once (1.9 mm edges, as scenarios/bunny-tets.json) it loads; a stroke then cuts both, and the
  // surface, whose edges are longer than refinement's 1.5 mm in places, is not refined. Without tets it is.
  options.tets.mesh.max_volume_m3 = 5e-9;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh fine = mesh::subdivided(coarse, 1);
  sim::StrokeSpec stroke;
  stroke.start_m = Eigen::Vector3d(-0.012, 0.0, 0.015);
  stroke.length_m = 0.03;
  const std::vector<devices::PoseSample> poses = sim::posesForStrokes(fine, {stroke}, options, 1000.0);
  for (const bool tets : {true, false}) {
    options.tets.enabled = tets;
    sim::World world(fine, options);
    REQUIRE((world.tets() != nullptr) == tets);
    for (const devices::PoseSample& pose : poses) world.step(std::span(&pose, 1), 0.001, pose.time_s);
    for (double t = poses.back().time_s; t < poses.back().time_s + 0.2; t += 0.001) world.cut(t);
    REQUIRE(world.cutter().stats().vertices_duplicated > 20);
    if (tets) REQUIRE(world.cutter().stats().refined_vertices == 0);
    if (!tets) REQUIRE(world.cutter().stats().refined_vertices > 0);
  }
}

namespace {

// Two strokes over the bunny's back, the second beginning 20 ms after the first lifts off.
std::vector<devices::PoseSample> twoStrokes(const mesh::SurfaceMesh& tissue, const sim::WorldOptions& options) {
  sim::StrokeSpec first, second;
  first.start_m = Eigen::Vector3d(-0.012, 0.0, 0.015);
  first.length_m = 0.025;
  first.speed_m_per_s = 0.25;  // 100 ms: the work of a starved budget trails it
  second.start_m = Eigen::Vector3d(-0.010, 0.0, 0.008);
  second.length_m = 0.02;
  second.pause_s = 0.02;
  return sim::posesForStrokes(tissue, {first, second}, options, 1000.0);
}

struct FramesRun {
  std::uint64_t hash = 0;
  int incisions = 0;
  mesh::SurfaceMesh tissue;  // as the run left it
  sim::WorldCounters counters;
  bool haptic_did_no_cutting = true;  // no updateTool call changed the mesh or the cutter's progress
};

// `deadline_due`: every cut phase is given a deadline that has already passed (a frame whose time is gone),
// so it does one unit of budgeted work.
FramesRun runFrames(const mesh::SurfaceMesh& tissue, const sim::WorldOptions& options,
                    const std::vector<devices::PoseSample>& poses, bool deadline_due = false) {
  sim::World world(tissue, options);
  FramesRun run;
  const auto progress = [&] {
    return std::tuple(world.tissue().mesh().n_vertices(), world.cutter().columnsDone(), world.cutter().columnsFinal(),
                      world.incisions(), world.cutter().stats().edges_split);
  };
  double t_s = poses.front().time_s;
  for (const devices::PoseSample& pose : poses) {
    const auto before = progress();
    world.updateTool(std::span(&pose, 1), 0.001);
    run.haptic_did_no_cutting = run.haptic_did_no_cutting && progress() == before;
    world.cut(t_s = pose.time_s,
              deadline_due ? core::WorkBudget::Clock::now() : core::WorkBudget::Clock::time_point::max());
  }
  // The same frames for every budget, to a time where the wounds' openings have settled and the work is done.
  for (int frame = 0; frame < 3000; ++frame) world.cut(t_s += 0.001);
  REQUIRE_FALSE(world.pending());
  run.hash = mesh::geometryHash(world.tissue());
  run.incisions = world.incisions();
  run.tissue = world.tissue();
  run.counters = world.counters();
  return run;
}

}  // namespace

TEST_CASE("world: a new incision waits for the previous one's work in later frames, the same bytes as at once",
          "[sim]") {
  // Starting an incision never makes the haptic part do the previous one's remaining work; it waits
  // in the cut phase, a frame's budget at a time, and the cut is the one a budget large enough to do it at
  // once gives, byte for byte.
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  // With local refinement (the default): its bisections ahead of the cut retriangulate the skin a later
  // pose's contact meets, which takes the faces the skin had when the incision began (their rest parents),
  // so the cut does not depend on how far that work had got when the pose came.
  const mesh::SurfaceMesh tissue = bunny();
  const std::vector<devices::PoseSample> poses = twoStrokes(tissue, options);
  sim::WorldOptions at_once = options, starved = options;
  at_once.cut_budget_us = 1e9;
  starved.cut_budget_us = 2.0;  // 1 inversion a frame: the first stroke's work trails it by far
  const FramesRun a = runFrames(tissue, at_once, poses), b = runFrames(tissue, starved, poses);
  REQUIRE(a.counters.waits == 0);
  REQUIRE(b.counters.waits == 1);
  REQUIRE(b.counters.waited_frames > 20);
  REQUIRE(b.counters.catch_ups == 0);
  REQUIRE(a.haptic_did_no_cutting);
  REQUIRE(b.haptic_did_no_cutting);
  REQUIRE(a.hash == b.hash);
}

TEST_CASE(
    "world: a stroke that turns at a corner goes on as a new incision from it, the same bytes at once and "
    "starved",
    "[sim]") {
  // 8 mm along +x on a pad, then 8 mm at 100 degrees from it, the blade 3 mm in: one lattice cannot follow
  // the corner (Incision::extend ends it there); the world begins the next incision at the pose that found
  // the corner and keeps the poses after it queued until then, so a starved budget cuts the same bytes.
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh pad =
      mesh::makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(-0.03, -0.01, -0.03), Eigen::Vector3d(0.03, 0.0, 0.03)),
                    Eigen::Vector3i(60, 10, 60));
  const double kink = 100.0 * 3.14159265358979 / 180.0;
  const Eigen::Vector3d first(1.0, 0.0, 0.0), second(std::cos(kink), 0.0, std::sin(kink));
  std::vector<devices::PoseSample> poses;
  Eigen::Vector3d tip(-0.008, -0.003, 0.0013);
  for (int k = 0; k < 320; ++k) {
    poses.push_back(poseAt(tip, 0.001 * k));
    tip += 0.00005 * (k < 160 ? first : second);
  }
  sim::WorldOptions at_once = options, starved = options;
  at_once.cut_budget_us = 1e9;
  starved.cut_budget_us = 2.0;
  const FramesRun a = runFrames(pad, at_once, poses), b = runFrames(pad, starved, poses);
  CHECK(a.incisions == 2);
  CHECK(b.incisions == 2);
  CHECK(b.counters.waits >= 1);
  CHECK(mesh::findSelfIntersections(a.tissue.mesh()).empty());
  REQUIRE(a.hash == b.hash);
}

TEST_CASE("world: a cut phase stopped by its deadline carries its work over, the same bytes", "[sim]") {
  // Against the clock (Simulation: cut_budget_us after the haptic part) the budgeted work also stops at a
  // deadline; here every deadline has passed when the cut phase starts, so each does one inversion.
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh tissue = bunny();
  const std::vector<devices::PoseSample> poses = twoStrokes(tissue, options);
  const FramesRun free = runFrames(tissue, options, poses), due = runFrames(tissue, options, poses, true);
  REQUIRE(free.counters.deadline_stops == 0);
  REQUIRE(due.counters.deadline_stops > 100);
  REQUIRE(due.counters.waits == 1);  // the first stroke's work trails it into the second
  REQUIRE(due.hash == free.hash);
}

TEST_CASE("world: the haptic contact from the proxy is the cutter's exact contact", "[sim]") {
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh tissue = bunny();
  const std::vector<devices::PoseSample> poses = twoStrokes(tissue, options);
  sim::World world(tissue, options);
  const double probe_m = std::min(options.tool.blade_length_m, options.cutter.incision.depth_m + 0.002);
  int compared = 0, in_contact = 0;
  for (const devices::PoseSample& pose : poses) {
    const sim::HapticState h = world.updateTool(std::span(&pose, 1), 0.001);
    const Eigen::Vector3d handle = pose.tip_m - probe_m * (pose.orientation * Eigen::Vector3d(0, 0, -1));
    const auto exact = world.cutter().intersect(handle, pose.tip_m);  // the same state the proxy was taken from
    world.cut(pose.time_s);
    if (h.proxy_miss) continue;
    ++compared;
    const bool exact_contact = exact && (exact->point_m - pose.tip_m).dot(exact->normal) > 0.0;
    REQUIRE(h.contact == exact_contact);
    if (!exact_contact) continue;
    ++in_contact;
    REQUIRE((h.contact_m - exact->point_m).norm() < 1e-12);
    REQUIRE((h.normal - exact->normal).norm() < 1e-12);
  }
  // All but the first frame (no proxy yet) and the jump to the second stroke's start (the tool moves 2 cm
  // between two poses: the proxy is refilled there after that frame).
  REQUIRE(compared == static_cast<int>(poses.size()) - 2);
  REQUIRE(world.counters().proxy_misses == 2);
  REQUIRE(in_contact > 500);
  REQUIRE(world.counters().proxy_overflows == 0);
  REQUIRE(world.counters().proxy_refills < static_cast<std::int64_t>(poses.size()) / 4);
}

TEST_CASE("world: a blade that goes through the skin within one frame is caught by the swept test", "[sim]") {
  // A short blade (1 mm long: a 1 mm probe) moved 1.8 mm down in one frame, within the proxy's reach (2 mm
  // at 1 kHz): its whole probe is below the skin, so only the sweep from the last frame's tip finds the
  // crossing.
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  options.tool.blade_length_m = 0.001;
  options.cutter.incision.depth_m = 0.0005;
  const mesh::SurfaceMesh tissue = bunny();
  const Eigen::Vector3d surface = surfaceAt(tissue, 0.005, 0.015);
  sim::World world(tissue, options);
  frameOf(world, poseAt(surface + Eigen::Vector3d(0, 0.0003, 0), 0.0, 0));
  const sim::HapticState hover = frameOf(world, poseAt(surface + Eigen::Vector3d(0, 0.0003, 0), 0.001, 0));
  REQUIRE_FALSE(hover.contact);
  const sim::HapticState h = frameOf(world, poseAt(surface - Eigen::Vector3d(0, 0.0015, 0), 0.002, 0));
  REQUIRE_FALSE(h.proxy_miss);
  REQUIRE(h.swept);
  REQUIRE(h.contact);
  REQUIRE(h.penetration_m == Approx(0.0015 * std::abs(h.normal.y())).epsilon(0.1));
  REQUIRE(h.force_N.dot(h.normal) > 0.0);
  REQUIRE(world.counters().swept_contacts == 1);
}

TEST_CASE("world: frames that start 30 ms late still find the contact: the reach follows the tool's motion", "[sim]") {
  // The blade pressed 1 mm into the bunny's back and drawn along x at 0.1 m/s, its poses 1 ms apart, the
  // frames each taking 30 of them (a busy machine's frames): 3 mm a frame, beyond the 2 mm reach at 1 kHz.
  sim::WorldOptions options;
  options.tool.cut_button = 0;
  const mesh::SurfaceMesh tissue = bunny();
  sim::World world(tissue, options);
  std::vector<devices::PoseSample> poses;
  for (int i = 0; i <= 300; ++i) {
    const double x_m = -0.015 + 1e-4 * i;
    poses.push_back(poseAt(surfaceAt(tissue, x_m, 0.015) - Eigen::Vector3d(0.0, 0.001, 0.0), 0.001 * i, 0));
  }
  frameOf(world, poses.front());
  int frames = 0, in_contact = 0;
  for (std::size_t first = 1; first < poses.size(); first += 30, ++frames) {
    const sim::HapticState h = world.updateTool(std::span(poses).subspan(first, 30), 0.001);
    world.cut(poses[first + 29].time_s);
    if (h.contact && h.force_N.norm() > 0.1) ++in_contact;
  }
  REQUIRE(frames == 10);
  // The first frame finds no proxy yet, the first late frame the tool beyond its region (refilled then,
  // twice as wide as that frame's motion); every later one finds it within.
  REQUIRE(world.counters().proxy_misses == 2);
  REQUIRE(in_contact == 9);
  REQUIRE(world.proxyReachM() == Approx(0.006).epsilon(0.1));
  // A jump faster than a hand (2 cm in 1 ms) does not widen it: 0.5 mm, below the 2 mm the period gives.
  const devices::PoseSample jump = poseAt(poses.back().tip_m + Eigen::Vector3d(0.02, 0.0, 0.0), 0.301, 0);
  world.updateTool(std::span(&jump, 1), 0.001);
  REQUIRE(world.proxyReachM() == Approx(0.002));
}

TEST_CASE("world: the proxy's reach follows the frame period (2 mm at 1 kHz, 1.25 mm at 4 kHz)", "[sim]") {
  sim::World world(bunny(), sim::WorldOptions{});
  REQUIRE(world.proxyReachM() == Approx(0.002));  // before any frame: 1 kHz
  const devices::PoseSample pose = poseAt(Eigen::Vector3d(0.0, 0.05, 0.0), 0.0, 0);
  world.updateTool(std::span(&pose, 1), 0.00025);
  CHECK(world.proxyReachM() == Approx(0.00125));
  world.updateTool(std::span(&pose, 1), 0.01);  // 100 Hz: 11 mm
  CHECK(world.proxyReachM() == Approx(0.011));
  world.updateTool(std::span(&pose, 1), std::numeric_limits<double>::quiet_NaN());  // ignored
  CHECK(world.proxyReachM() == Approx(0.011));
}
