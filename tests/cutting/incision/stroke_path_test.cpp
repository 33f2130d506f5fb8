#include "incise/incision/stroke_path.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "incise/mesh/shapes.h"

using namespace incise;
using namespace incise::incision;
using Catch::Matchers::Contains;
using Eigen::Vector3d;

namespace {

// A slab whose top face is the plane y = 0 (the rays go down -y), 10 cm x 10 cm, 2 cm thick.
mesh::SurfaceMesh slab() {
  return mesh::makeBox(Eigen::AlignedBox3d(Vector3d(-0.05, -0.02, -0.05), Vector3d(0.05, 0.0, 0.05)), 8);
}

// Binary-exact steps: 1/16 m/s at 1024 Hz is 2^-14 m per sample; 200 of them make the length.
StrokePathOptions exactOptions() {
  StrokePathOptions o;
  o.start_m = Vector3d(-0.03, 0.01, 0.01);  // 1 cm above the slab
  o.direction = Vector3d::UnitX();
  o.speed_m_per_s = 0.0625;
  o.rate_hz = 1024.0;
  o.length_m = 200.0 * std::ldexp(1.0, -14);
  o.start_time_s = 2.0;
  return o;
}

void requireRefused(StrokePathOptions o, const std::string& what) {
  const mesh::SurfaceMesh mesh = slab();
  INFO(what);
  REQUIRE_THROWS_AS(strokeAlongPath(mesh, o), std::invalid_argument);
  REQUIRE_THROWS_WITH(strokeAlongPath(mesh, o), Contains("strokeAlongPath") && Contains(what));
}

}  // namespace

TEST_CASE("stroke_path: samples at speed x period spacing, on the surface, one period apart", "[cutting]") {
  const mesh::SurfaceMesh mesh = slab();
  const StrokePathOptions o = exactOptions();
  const Stroke stroke = strokeAlongPath(mesh, o);

  const double step_m = o.speed_m_per_s / o.rate_hz;
  REQUIRE(step_m == std::ldexp(1.0, -14));
  REQUIRE(stroke.samples.size() == 200);  // floor(length / step) after the first
  REQUIRE(stroke.blade_direction.isApprox(Vector3d::UnitX(), 1e-15));

  // The first touch: straight below the start, on the top face, facing up, at the start time.
  REQUIRE((stroke.first.point_m - Vector3d(-0.03, 0.0, 0.01)).norm() < 1e-12);
  REQUIRE(stroke.first.normal.isApprox(Vector3d::UnitY(), 1e-12));
  REQUIRE(stroke.first.time_s == 2.0);

  double last_t = stroke.first.time_s;
  Vector3d last_p = stroke.first.point_m;
  for (std::size_t k = 0; k < stroke.samples.size(); ++k) {
    const StrokeSample& s = stroke.samples[k];
    const double i = static_cast<double>(k + 1);
    INFO("sample " << k + 1);
    REQUIRE(std::abs(s.point_m.y()) < 1e-12);  // on the top face
    REQUIRE(s.point_m.x() == Approx(-0.03 + i * step_m).margin(1e-12));
    REQUIRE(s.point_m.z() == Approx(0.01).margin(1e-12));
    REQUIRE(s.normal.isApprox(Vector3d::UnitY(), 1e-12));
    REQUIRE(s.time_s == Approx(2.0 + i / 1024.0).margin(1e-12));
    REQUIRE(s.time_s > last_t);
    REQUIRE((s.point_m - last_p).norm() == Approx(step_m).epsilon(1e-6));
    last_t = s.time_s;
    last_p = s.point_m;
  }
  // The last sample is the path's end.
  REQUIRE(stroke.samples.back().point_m.x() == Approx(-0.03 + o.length_m).margin(1e-12));
}

TEST_CASE("stroke_path: the blade direction is the travel direction across the rays, a bend bulges sideways",
          "[cutting]") {
  const mesh::SurfaceMesh mesh = slab();
  StrokePathOptions o = exactOptions();
  // A direction tilted towards the rays: only its part across them counts, normalised.
  o.direction = Vector3d(3.0, -4.0, 0.0);
  Stroke stroke = strokeAlongPath(mesh, o);
  REQUIRE(stroke.blade_direction.isApprox(Vector3d::UnitX(), 1e-15));
  REQUIRE(stroke.samples.size() == 200);
  REQUIRE(stroke.samples.back().point_m.x() == Approx(-0.03 + o.length_m).margin(1e-12));

  // Along +z: the samples move in z.
  o.direction = Vector3d(0.0, 0.0, 2.0);
  stroke = strokeAlongPath(mesh, o);
  REQUIRE(stroke.blade_direction.isApprox(Vector3d::UnitZ(), 1e-15));
  REQUIRE(stroke.samples.back().point_m.z() == Approx(0.01 + o.length_m).margin(1e-12));
  REQUIRE(stroke.samples.back().point_m.x() == Approx(-0.03).margin(1e-12));

  // A bend: 4 b x (1 - x) along direction x down = +x x -y = -z, b at the middle, 0 at both ends.
  o = exactOptions();
  o.bend_m = 0.002;
  stroke = strokeAlongPath(mesh, o);
  REQUIRE(stroke.samples.size() == 200);
  REQUIRE(stroke.first.point_m.z() == Approx(0.01).margin(1e-12));
  REQUIRE(stroke.samples[99].point_m.z() == Approx(0.01 - 0.002).margin(1e-12));  // sample 100 of 200
  REQUIRE(stroke.samples[49].point_m.z() == Approx(0.01 - 4.0 * 0.002 * 0.25 * 0.75).margin(1e-12));
  REQUIRE(stroke.samples.back().point_m.z() == Approx(0.01).margin(1e-12));
  for (const StrokeSample& s : stroke.samples) REQUIRE(std::abs(s.point_m.y()) < 1e-12);
}

TEST_CASE("stroke_path: a wave is one sine across the stroke, an S sideways", "[cutting]") {
  const mesh::SurfaceMesh mesh = slab();
  StrokePathOptions o = exactOptions();
  o.wave_m = 0.002;  // towards direction x down = -z: -z at a quarter, +z at three quarters
  const Stroke stroke = strokeAlongPath(mesh, o);
  REQUIRE(stroke.samples.size() == 200);
  CHECK(stroke.first.point_m.z() == Approx(0.01).margin(1e-12));
  CHECK(stroke.samples[49].point_m.z() == Approx(0.01 - 0.002).margin(1e-12));   // x = 1/4
  CHECK(stroke.samples[99].point_m.z() == Approx(0.01).margin(1e-12));           // x = 1/2
  CHECK(stroke.samples[149].point_m.z() == Approx(0.01 + 0.002).margin(1e-12));  // x = 3/4
  CHECK(stroke.samples.back().point_m.z() == Approx(0.01).margin(1e-12));
  o.wave_m = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(strokeAlongPath(mesh, o), Contains("wave_m"));
}

TEST_CASE("stroke_path: the stroke stops where the path leaves the surface", "[cutting]") {
  const mesh::SurfaceMesh mesh = slab();
  StrokePathOptions o = exactOptions();
  o.start_m = Vector3d(0.04, 0.01, 0.003);  // 1 cm from the slab's edge x = 0.05, 2.4 cm to go
  o.length_m = 0.024;
  const Stroke stroke = strokeAlongPath(mesh, o);
  // 0.04 + k 2^-14 <= 0.05 for k <= 163.84.
  REQUIRE(stroke.samples.size() == 163);
  REQUIRE(stroke.samples.back().point_m.x() <= 0.05);
  for (const StrokeSample& s : stroke.samples) REQUIRE(std::abs(s.point_m.y()) < 1e-12);
}

TEST_CASE("stroke_path: bad options and a first ray that misses the tissue are refused", "[cutting]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  StrokePathOptions o = exactOptions();
  o.length_m = -0.25;
  requireRefused(o, "length_m = -0.25");
  o.length_m = 0.0;
  requireRefused(o, "length_m = 0");
  o = exactOptions();
  o.length_m = nan;
  requireRefused(o, "length_m");
  o = exactOptions();
  o.start_m.x() = nan;
  requireRefused(o, "start_m is not finite");
  o = exactOptions();
  o.direction = Vector3d::Zero();
  requireRefused(o, "direction must be finite and non-zero");
  o = exactOptions();
  o.down = Vector3d(0, std::numeric_limits<double>::infinity(), 0);
  requireRefused(o, "down must be finite and non-zero");
  o = exactOptions();
  o.speed_m_per_s = 0.0;
  requireRefused(o, "speed_m_per_s");
  o = exactOptions();
  o.rate_hz = -1000.0;
  requireRefused(o, "rate_hz");
  o = exactOptions();
  o.height_m = 0.0;
  requireRefused(o, "height_m");
  o = exactOptions();
  o.bend_m = nan;
  requireRefused(o, "bend_m");

  // Beside the slab, and too high above it for the ray (it spans start +- height_m).
  o = exactOptions();
  o.start_m = Vector3d(0.2, 0.01, 0.0);
  requireRefused(o, "the first ray misses the surface");
  o = exactOptions();
  o.start_m.y() = 0.2;
  o.height_m = 0.15;
  requireRefused(o, "the first ray misses the surface");
}

// Regression, once a bug (stroke_path.h: "std::invalid_argument for bad options (named, with the value)"): only length_m's
// message carries the value; speed_m_per_s, rate_hz, height_m and bend_m name the option without it
// ("strokeAlongPath: speed_m_per_s must be > 0", "strokeAlongPath: bend_m / height_m").
TEST_CASE("stroke_path: every refused option's message gives its value", "[cutting]") {
  StrokePathOptions o = exactOptions();
  o.speed_m_per_s = -0.5;
  CHECK_THROWS_WITH(strokeAlongPath(slab(), o), Contains("speed_m_per_s") && Contains("-0.5"));
  o = exactOptions();
  o.rate_hz = -250.0;
  CHECK_THROWS_WITH(strokeAlongPath(slab(), o), Contains("rate_hz") && Contains("-250"));
  o = exactOptions();
  o.height_m = -0.125;
  CHECK_THROWS_WITH(strokeAlongPath(slab(), o), Contains("height_m") && Contains("-0.125"));
}

// Regression, once a bug: a direction along the rays (here straight down) passes the "finite and non-zero" check, but its
// part across the rays is zero: normalized() leaves it zero, so the blade direction is (0, 0, 0) and every
// sample lies on the first one. It should be refused like a zero direction.
TEST_CASE("stroke_path: a direction along the rays is refused", "[cutting]") {
  StrokePathOptions o = exactOptions();
  o.direction = -Vector3d::UnitY();
  CHECK_THROWS_AS(strokeAlongPath(slab(), o), std::invalid_argument);
}
