#include "incise/mesh/thickness.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "incise/mesh/shapes.h"

using namespace incise;
using namespace incise::mesh;
using Eigen::Vector3d;

TEST_CASE("thickness: every vertex inside a 3 mm slab's top face has the slab under it", "[mesh][thickness]") {
  const SurfaceMesh pad = makeSkinPad(Vector3d(0.04, 0.003, 0.04), 0.002);
  const TriMesh& m = pad.mesh();
  const std::vector<float> thickness = thicknessBelowVertices(m, 0.01, 1e-5);
  REQUIRE(thickness.size() == m.n_vertices());
  int inside = 0;
  for (const auto v : m.vertices()) {
    const Vector3d p = toEigen(m.point(v));
    const bool top_inside = p.y() == 0.0 && std::abs(p.x()) < 0.0195 && std::abs(p.z()) < 0.0195;
    if (!top_inside) continue;
    ++inside;
    INFO("vertex " << v.idx() << " at " << p.transpose());
    REQUIRE(thickness[static_cast<size_t>(v.idx())] == Approx(0.003).margin(1e-7));
  }
  REQUIRE(inside == 19 * 19);
}

TEST_CASE("thickness: a sphere is its diameter thick, beyond max_m there is none", "[mesh][thickness]") {
  const double radius_m = 0.01;
  const SurfaceMesh sphere = makeSphere(Vector3d(0.001, -0.002, 0.003), radius_m, 3);
  const TriMesh& m = sphere.mesh();
  const std::vector<float> deep = thicknessBelowVertices(m, 0.05, 1e-5);
  // Faceted: a vertex's normal points near the centre, the far side is a flat face a little inside the
  // sphere (within 1% of the diameter at 3 subdivisions).
  for (const auto v : m.vertices()) REQUIRE(deep[static_cast<size_t>(v.idx())] == Approx(2.0 * radius_m).epsilon(0.01));
  const std::vector<float> shallow = thicknessBelowVertices(m, 0.015, 1e-5);
  for (const auto v : m.vertices()) REQUIRE(std::isinf(shallow[static_cast<size_t>(v.idx())]));
}

TEST_CASE("thickness: the values do not depend on the worker threads' share", "[mesh][thickness]") {
  const SurfaceMesh sphere = makeSphere(Vector3d::Zero(), 0.02, 4);
  const std::vector<float> a = thicknessBelowVertices(sphere.mesh(), 0.1, 1e-5);
  const std::vector<float> b = thicknessBelowVertices(sphere.mesh(), 0.1, 1e-5);
  REQUIRE(a == b);
}

TEST_CASE("thickness: a negative or non-finite reach is refused", "[mesh][thickness]") {
  const SurfaceMesh box = makeBox(Eigen::AlignedBox3d(Vector3d::Zero(), Vector3d::Ones()));
  REQUIRE_THROWS_AS(thicknessBelowVertices(box.mesh(), -1.0, 0.0), std::invalid_argument);
  REQUIRE_THROWS_AS(thicknessBelowVertices(box.mesh(), std::numeric_limits<double>::infinity(), 0.0),
                    std::invalid_argument);
  REQUIRE_THROWS_AS(thicknessBelowVertices(box.mesh(), 1.0, std::nan("")), std::invalid_argument);
}

TEST_CASE("thickness: a segment finds where it leaves the solid, not where it enters", "[mesh][thickness]") {
  const SurfaceMesh box = makeBox(Eigen::AlignedBox3d(Vector3d::Zero(), Vector3d(0.01, 0.02, 0.03)));
  const SurfaceRays rays(box.mesh());
  const Vector3d x = Vector3d::UnitX();
  // From inside, along +x: the face x = 10 mm, 7 mm away; a segment shorter than that leaves through none.
  REQUIRE(rays.firstCrossing(Vector3d(0.003, 0.01, 0.01), x, 0.02) == Approx(0.007).margin(1e-12));
  REQUIRE(std::isinf(rays.firstCrossing(Vector3d(0.003, 0.01, 0.01), x, 0.006)));
  // From 1 mm outside the face x = 0: it enters there (not counted) and leaves 11 mm on.
  REQUIRE(rays.firstCrossing(Vector3d(-0.001, 0.01, 0.01), x, 0.05) == Approx(0.011).margin(1e-12));
  // Along -y from inside: the face y = 0.
  REQUIRE(rays.firstCrossing(Vector3d(0.005, 0.004, 0.01), -Vector3d::UnitY(), 0.05) == Approx(0.004).margin(1e-12));
  // Missing the box, or bad input: none.
  REQUIRE(std::isinf(rays.firstCrossing(Vector3d(0.005, 0.05, 0.01), x, 0.05)));
  REQUIRE(std::isinf(rays.firstCrossing(Vector3d(std::nan(""), 0.01, 0.01), x, 0.05)));
  REQUIRE(std::isinf(rays.firstCrossing(Vector3d(0.003, 0.01, 0.01), x, -1.0)));
  REQUIRE(std::isinf(rays.firstCrossing(Vector3d(0.003, 0.01, 0.01), x, std::numeric_limits<double>::infinity())));
  // The thickness below each vertex is the same read through prepared rays.
  REQUIRE(thicknessBelowVertices(box.mesh(), rays, 0.05, 1e-5) == thicknessBelowVertices(box.mesh(), 0.05, 1e-5));
}
