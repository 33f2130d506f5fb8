#include "incise/sim/stroke_poses.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "incise/incision/stroke_path.h"
#include "incise/mesh/shapes.h"

using namespace incise;
using Catch::Matchers::Contains;
using Eigen::Vector3d;

namespace {

// A slab whose top face is the plane y = 0, facing +y (the strokes' rays go down -y).
mesh::SurfaceMesh slab() {
  return mesh::makeBox(Eigen::AlignedBox3d(Vector3d(-0.05, -0.02, -0.05), Vector3d(0.05, 0.0, 0.05)), 8);
}

sim::StrokeSpec straightStroke() {
  sim::StrokeSpec s;
  s.start_m = Vector3d(-0.03, 0.01, 0.01);
  s.direction = Vector3d::UnitX();
  s.length_m = 0.02;
  s.speed_m_per_s = 0.05;
  s.pause_s = 0.1;
  return s;
}

// The samples strokeAlongPath gives for the spec (the stroke phase's source).
incision::Stroke pathOf(const mesh::SurfaceMesh& tissue, const sim::StrokeSpec& spec, double rate_hz) {
  incision::StrokePathOptions o;
  o.start_m = spec.start_m;
  o.direction = spec.direction;
  o.length_m = spec.length_m;
  o.bend_m = spec.bend_m;
  o.speed_m_per_s = spec.speed_m_per_s;
  o.rate_hz = rate_hz;
  return incision::strokeAlongPath(tissue, o);
}

void requireNear(const Vector3d& got, const Vector3d& want, double tol = 1e-12) {
  INFO("got " << got.transpose() << ", want " << want.transpose());
  REQUIRE((got - want).norm() <= tol);
}

// The blade along -normal (local -z), its edge (local +x) along `travel`.
void requireBlade(const devices::PoseSample& p, const Vector3d& normal, const Vector3d& travel) {
  REQUIRE(p.orientation.norm() == Approx(1.0).epsilon(1e-12));
  requireNear(p.orientation * Vector3d(0, 0, -1), -normal, 1e-9);
  requireNear(p.orientation * Vector3d::UnitX(), travel, 1e-9);
}

}  // namespace

TEST_CASE("stroke_poses: idle above the start, a 30 ms descent, the stroke with the button held, a 30 ms rise",
          "[sim]") {
  const mesh::SurfaceMesh tissue = slab();
  sim::WorldOptions world;
  world.cutter.incision.depth_m = 0.003;
  const double tip_depth = 0.003;  // a stroke without its own depth: the incision's
  const double rate_hz = 1000.0;
  const sim::StrokeSpec spec = straightStroke();
  const incision::Stroke path = pathOf(tissue, spec, rate_hz);
  REQUIRE(path.samples.size() >= 390);  // 2 cm at 0.05 mm a sample

  const std::vector<devices::PoseSample> poses = sim::posesForStrokes(tissue, {spec}, world, rate_hz);
  const std::size_t idle = 101, descent = 31, stroke = path.samples.size(), rise = 31;  // both ends of a move
  REQUIRE(poses.size() == idle + descent + stroke + rise);

  // Times: k / rate_hz from 0, strictly increasing.
  for (std::size_t k = 0; k < poses.size(); ++k) {
    INFO("pose " << k);
    REQUIRE(poses[k].time_s == Approx(static_cast<double>(k) / rate_hz).margin(1e-12));
    if (k > 0) REQUIRE(poses[k].time_s > poses[k - 1].time_s);
    REQUIRE_FALSE(poses[k].pressure);
  }

  const Vector3d start = path.first.point_m;
  requireNear(start, Vector3d(-0.03, 0.0, 0.01));
  const Vector3d above = start + Vector3d(0, 0.005, 0);
  const Vector3d in = start - Vector3d(0, tip_depth, 0);
  std::size_t k = 0;
  // pause_s (100 periods) idle 5 mm above the start, button up.
  for (; k < idle; ++k) {
    INFO("idle pose " << k);
    requireNear(poses[k].tip_m, above);
    REQUIRE(poses[k].buttons == 0);
    requireBlade(poses[k], Vector3d::UnitY(), Vector3d::UnitX());
  }
  // The descent, 30 periods from above to the depth below the surface, the cut button held.
  for (std::size_t j = 0; j < descent; ++j, ++k) {
    INFO("descent pose " << j);
    requireNear(poses[k].tip_m, above + (in - above) * (static_cast<double>(j) / 30.0));
    REQUIRE(poses[k].buttons == 1);
    requireBlade(poses[k], Vector3d::UnitY(), Vector3d::UnitX());
  }
  // The stroke: each of strokeAlongPath's samples with the tip the depth below it, the button held.
  for (std::size_t j = 0; j < stroke; ++j, ++k) {
    INFO("stroke pose " << j);
    const incision::StrokeSample& s = path.samples[j];
    requireNear(poses[k].tip_m, s.point_m - tip_depth * s.normal);
    REQUIRE(poses[k].tip_m.y() == Approx(-tip_depth).margin(1e-12));
    REQUIRE(poses[k].buttons == 1);
    requireBlade(poses[k], Vector3d::UnitY(), Vector3d::UnitX());
  }
  // The rise: 30 periods back to 5 mm above the surface, button up.
  const Vector3d last = path.samples.back().point_m - tip_depth * Vector3d::UnitY();
  for (std::size_t j = 0; j < rise; ++j, ++k) {
    INFO("rise pose " << j);
    requireNear(poses[k].tip_m, last + Vector3d(0, (tip_depth + 0.005) * static_cast<double>(j) / 30.0, 0));
    REQUIRE(poses[k].buttons == 0);
  }
  REQUIRE(poses.back().tip_m.y() == Approx(0.005).margin(1e-12));
}

TEST_CASE("stroke_poses: strokes follow each other on one timeline, at any rate", "[sim]") {
  const mesh::SurfaceMesh tissue = slab();
  const sim::WorldOptions world;
  sim::StrokeSpec a = straightStroke();
  sim::StrokeSpec b = straightStroke();
  b.start_m = Vector3d(0.01, 0.01, -0.02);
  b.direction = Vector3d(0, 0, 1);  // along +z
  b.length_m = 0.01;
  b.pause_s = 0.05;
  const double rate_hz = 500.0;
  const std::vector<devices::PoseSample> poses = sim::posesForStrokes(tissue, {a, b}, world, rate_hz);
  const std::size_t first = 51 + 16 + pathOf(tissue, a, rate_hz).samples.size() + 16;
  const std::size_t second = 26 + 16 + pathOf(tissue, b, rate_hz).samples.size() + 16;
  REQUIRE(poses.size() == first + second);
  for (std::size_t k = 1; k < poses.size(); ++k) {
    INFO("pose " << k);
    REQUIRE(poses[k].time_s - poses[k - 1].time_s == Approx(1.0 / rate_hz).epsilon(1e-9));
  }
  // The second stroke starts idle 5 mm above its own start, its blade's edge along +z.
  requireNear(poses[first].tip_m, Vector3d(0.01, 0.005, -0.02));
  REQUIRE(poses[first].buttons == 0);
  requireBlade(poses[first], Vector3d::UnitY(), Vector3d::UnitZ());
  REQUIRE(poses[first - 1].buttons == 0);  // the first stroke ended lifted
  REQUIRE(poses.back().tip_m.y() == Approx(0.005).margin(1e-12));
}

TEST_CASE("stroke_poses: on the bunny the tip is the incision's depth below each sample along its normal", "[sim]") {
  const mesh::SurfaceMesh tissue = mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01);
  sim::WorldOptions world;
  const double tip_depth = world.cutter.incision.depth_m;
  sim::StrokeSpec spec;
  spec.start_m = Vector3d(-0.012, 0.0, 0.015);  // across the back, as in the shipped strokes
  spec.length_m = 0.03;
  spec.pause_s = 0.02;
  const incision::Stroke path = pathOf(tissue, spec, 1000.0);
  const std::vector<devices::PoseSample> poses = sim::posesForStrokes(tissue, {spec}, world, 1000.0);
  REQUIRE(poses.size() == 21 + 31 + path.samples.size() + 31);
  const std::size_t begin = 21 + 31;
  requireNear(poses[0].tip_m, path.first.point_m + 0.005 * path.first.normal);
  requireNear(poses[begin - 1].tip_m, path.first.point_m - tip_depth * path.first.normal);
  for (std::size_t j = 0; j < path.samples.size(); ++j) {
    INFO("stroke pose " << j);
    const incision::StrokeSample& s = path.samples[j];
    const devices::PoseSample& p = poses[begin + j];
    REQUIRE(s.normal.dot(Vector3d::UnitY()) > 0.0);  // the back faces up
    requireNear(p.tip_m, s.point_m - tip_depth * s.normal);
    REQUIRE(p.buttons == 1);
    requireNear(p.orientation * Vector3d::UnitZ(), s.normal, 1e-9);
    // The edge faces the way to the next sample, across the normal.
    REQUIRE(std::abs((p.orientation * Vector3d::UnitX()).dot(s.normal)) < 1e-9);
    if (j + 1 < path.samples.size())
      REQUIRE((p.orientation * Vector3d::UnitX()).dot(path.samples[j + 1].point_m - s.point_m) > 0.0);
  }
}

TEST_CASE("stroke_poses: a bad stroke or rate is refused", "[sim]") {
  const mesh::SurfaceMesh tissue = slab();
  const sim::WorldOptions world;
  sim::StrokeSpec spec = straightStroke();
  spec.length_m = 0.0;
  REQUIRE_THROWS_AS(sim::posesForStrokes(tissue, {spec}, world, 1000.0), std::invalid_argument);
  REQUIRE_THROWS_WITH(sim::posesForStrokes(tissue, {spec}, world, 1000.0), Contains("length_m"));
  spec = straightStroke();
  spec.speed_m_per_s = -1.0;
  REQUIRE_THROWS_WITH(sim::posesForStrokes(tissue, {spec}, world, 1000.0), Contains("speed_m_per_s"));
  spec = straightStroke();
  spec.direction = Vector3d::Zero();
  REQUIRE_THROWS_WITH(sim::posesForStrokes(tissue, {spec}, world, 1000.0), Contains("direction"));
  spec = straightStroke();
  spec.start_m = Vector3d(0.5, 0.01, 0.0);  // beside the tissue
  REQUIRE_THROWS_AS(sim::posesForStrokes(tissue, {spec}, world, 1000.0), std::invalid_argument);
  REQUIRE_THROWS_WITH(sim::posesForStrokes(tissue, {spec}, world, 1000.0),
                      Contains("the first ray misses the surface"));
  // A bad second stroke refuses the whole list.
  REQUIRE_THROWS_AS(sim::posesForStrokes(tissue, {straightStroke(), spec}, world, 1000.0), std::invalid_argument);
  REQUIRE_THROWS_WITH(sim::posesForStrokes(tissue, {straightStroke()}, world, 0.0), Contains("rate_hz"));
  // No strokes, no poses.
  REQUIRE(sim::posesForStrokes(tissue, {}, world, 1000.0).empty());
}

// Regression, once a bug: pause_s is never checked. A negative or NaN pause is taken as a one-period idle (std::max(1, ...)
// in the timeline), where the header promises std::invalid_argument for a bad stroke (loadScenario
// range-checks pause_s to [0, 100], but posesForStrokes is public).
TEST_CASE("stroke_poses: a negative or NaN pause is refused", "[sim]") {
  const mesh::SurfaceMesh tissue = slab();
  const sim::WorldOptions world;
  sim::StrokeSpec spec = straightStroke();
  spec.pause_s = -1.0;
  CHECK_THROWS_AS(sim::posesForStrokes(tissue, {spec}, world, 1000.0), std::invalid_argument);
  spec.pause_s = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(sim::posesForStrokes(tissue, {spec}, world, 1000.0), std::invalid_argument);
}
