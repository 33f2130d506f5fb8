#include "incise/mesh/surface_query.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "incise/mesh/shapes.h"

using namespace incise;
using namespace incise::mesh;
using Eigen::Vector3d;

namespace {

void requireNear(const Vector3d& got, const Vector3d& want, double tol = 1e-12) {
  INFO("got " << got.transpose() << ", want " << want.transpose());
  REQUIRE((got - want).norm() <= tol);
}

VertexGrid gridOf(const TriMesh& mesh) {
  VertexGrid grid(suggestedCellSize(mesh));
  for (const auto v : mesh.vertices()) grid.insert(v.idx(), toEigen(mesh.point(v)));
  return grid;
}

double longestEdge(const TriMesh& mesh) {
  double longest = 0.0;
  for (const auto e : mesh.edges()) longest = std::max(longest, mesh.calc_edge_length(e));
  return longest;
}

const Vector3d kA(0, 0, 0), kB(1, 0, 0), kC(0, 1, 0);

}  // namespace

TEST_CASE("surface_query: closestPointOnTriangle inside, in each edge region and each vertex region", "[cutting]") {
  // Inside: the foot of the perpendicular, from either side of the plane.
  requireNear(closestPointOnTriangle(Vector3d(0.25, 0.25, 3.0), kA, kB, kC), Vector3d(0.25, 0.25, 0));
  requireNear(closestPointOnTriangle(Vector3d(0.1, 0.6, -2.0), kA, kB, kC), Vector3d(0.1, 0.6, 0));
  // A point in the plane and in the triangle is its own closest point.
  requireNear(closestPointOnTriangle(Vector3d(0.2, 0.3, 0), kA, kB, kC), Vector3d(0.2, 0.3, 0));
  // Vertex regions.
  requireNear(closestPointOnTriangle(Vector3d(-1, -1, 0.5), kA, kB, kC), kA);
  requireNear(closestPointOnTriangle(Vector3d(2, -0.5, 0), kA, kB, kC), kB);
  requireNear(closestPointOnTriangle(Vector3d(1.5, 0.2, -1), kA, kB, kC), kB);  // beyond b, above edge bc's foot
  requireNear(closestPointOnTriangle(Vector3d(-0.5, 2, 1), kA, kB, kC), kC);
  // Edge regions: ab (y < 0), ac (x < 0), bc (x + y > 1).
  requireNear(closestPointOnTriangle(Vector3d(0.5, -1, 2), kA, kB, kC), Vector3d(0.5, 0, 0));
  requireNear(closestPointOnTriangle(Vector3d(-1, 0.5, 0), kA, kB, kC), Vector3d(0, 0.5, 0));
  requireNear(closestPointOnTriangle(Vector3d(1, 1, 5), kA, kB, kC), Vector3d(0.5, 0.5, 0));
  requireNear(closestPointOnTriangle(Vector3d(0.9, 0.5, 0), kA, kB, kC), Vector3d(0.7, 0.3, 0));
}

TEST_CASE("surface_query: closestPointOnTriangle is no farther than any point of a tilted triangle", "[cutting]") {
  const Vector3d a(0.3, -0.2, 0.1), b(1.2, 0.4, -0.3), c(-0.1, 0.9, 0.7);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0), w(0.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const Vector3d p(u(rng), u(rng), u(rng));
    const Vector3d q = closestPointOnTriangle(p, a, b, c);
    // q is in the triangle: barycentric coordinates in [0, 1], in its plane.
    const Vector3d n = (b - a).cross(c - a);
    REQUIRE(std::abs((q - a).dot(n.normalized())) < 1e-12);
    const double area = n.norm();
    const double la = (b - q).cross(c - q).norm() / area, lb = (c - q).cross(a - q).norm() / area,
                 lc = (a - q).cross(b - q).norm() / area;
    REQUIRE(la + lb + lc == Approx(1.0).epsilon(1e-9));
    // No sampled point of the triangle is closer.
    const double d = (p - q).norm();
    for (int s = 0; s < 50; ++s) {
      double x = w(rng), y = w(rng);
      if (x + y > 1.0) x = 1.0 - x, y = 1.0 - y;
      const Vector3d r = a + x * (b - a) + y * (c - a);
      REQUIRE(d <= (p - r).norm() + 1e-12);
    }
  }
}

TEST_CASE("surface_query: segmentTriangle gives the crossing's parameter, nullopt for a miss or a parallel segment",
          "[cutting]") {
  // Through the plane z = 0 inside the triangle: t where z = 0, from above or below.
  auto t = segmentTriangle(Vector3d(0.2, 0.3, 1), Vector3d(0.2, 0.3, -1), kA, kB, kC);
  REQUIRE(t);
  REQUIRE(*t == Approx(0.5).epsilon(1e-12));
  t = segmentTriangle(Vector3d(0.2, 0.3, 1), Vector3d(0.2, 0.3, -3), kA, kB, kC);
  REQUIRE(t);
  REQUIRE(*t == Approx(0.25).epsilon(1e-12));
  t = segmentTriangle(Vector3d(0.2, 0.3, -3), Vector3d(0.2, 0.3, 1), kA, kB, kC);
  REQUIRE(t);
  REQUIRE(*t == Approx(0.75).epsilon(1e-12));
  // Slanted: from (0, 0, 1) to (0.5, 0.4, -1) crosses at t = 0.5, at (0.25, 0.2, 0).
  t = segmentTriangle(Vector3d(0, 0, 1), Vector3d(0.5, 0.4, -1), kA, kB, kC);
  REQUIRE(t);
  REQUIRE(*t == Approx(0.5).epsilon(1e-12));

  // The line crosses the plane outside the triangle.
  REQUIRE_FALSE(segmentTriangle(Vector3d(0.8, 0.8, 1), Vector3d(0.8, 0.8, -1), kA, kB, kC));
  REQUIRE_FALSE(segmentTriangle(Vector3d(-0.1, 0.3, 1), Vector3d(-0.1, 0.3, -1), kA, kB, kC));
  // The segment stops short of the plane, or starts past it.
  REQUIRE_FALSE(segmentTriangle(Vector3d(0.2, 0.3, 1), Vector3d(0.2, 0.3, 0.5), kA, kB, kC));
  REQUIRE_FALSE(segmentTriangle(Vector3d(0.2, 0.3, -0.5), Vector3d(0.2, 0.3, -1), kA, kB, kC));
  // Parallel to the plane, above it and in it.
  REQUIRE_FALSE(segmentTriangle(Vector3d(-1, 0.2, 1), Vector3d(2, 0.2, 1), kA, kB, kC));
  REQUIRE_FALSE(segmentTriangle(Vector3d(-1, 0.2, 0), Vector3d(2, 0.2, 0), kA, kB, kC));
  // A degenerate (zero-area) triangle is never hit.
  REQUIRE_FALSE(segmentTriangle(Vector3d(0.5, 0, 1), Vector3d(0.5, 0, -1), kA, kB, Vector3d(2, 0, 0)));
}

TEST_CASE("surface_query: closestSurfacePoint on a box finds the nearest face with its outward normal", "[cutting]") {
  const SurfaceMesh box = makeBox(Eigen::AlignedBox3d(Vector3d::Zero(), Vector3d::Ones()), 4);
  const TriMesh& mesh = box.mesh();
  const VertexGrid grid = gridOf(mesh);

  // Above the top face.
  auto s = closestSurfacePoint(mesh, grid, Vector3d(0.3, 0.4, 1.2), 0.5);
  REQUIRE(s);
  requireNear(s->point_m, Vector3d(0.3, 0.4, 1.0));
  requireNear(s->normal, Vector3d(0, 0, 1));
  REQUIRE(s->distance_m == Approx(0.2).epsilon(1e-12));
  REQUIRE(s->face.is_valid());
  // The face found holds the point.
  Vector3d corners[3];
  int i = 0;
  for (auto v = mesh.cfv_iter(s->face); v.is_valid(); ++v) corners[i++] = toEigen(mesh.point(*v));
  requireNear(closestPointOnTriangle(s->point_m, corners[0], corners[1], corners[2]), s->point_m);

  // Inside, nearest the face x = 0: the normal points out, along -x.
  s = closestSurfacePoint(mesh, grid, Vector3d(0.1, 0.45, 0.55), 0.5);
  REQUIRE(s);
  requireNear(s->point_m, Vector3d(0.0, 0.45, 0.55));
  requireNear(s->normal, Vector3d(-1, 0, 0));
  REQUIRE(s->distance_m == Approx(0.1).epsilon(1e-12));

  // Beyond a corner: the corner itself.
  s = closestSurfacePoint(mesh, grid, Vector3d(1.1, 1.1, 1.1), 0.5);
  REQUIRE(s);
  requireNear(s->point_m, Vector3d(1, 1, 1));
  REQUIRE(s->distance_m == Approx(std::sqrt(0.03)).epsilon(1e-12));

  // Off the surface (no vertex within the radius), a non-finite point, a non-positive radius.
  REQUIRE_FALSE(closestSurfacePoint(mesh, grid, Vector3d(5, 5, 5), 0.5));
  REQUIRE_FALSE(closestSurfacePoint(mesh, grid, Vector3d(std::nan(""), 0.5, 0.5), 0.5));
  REQUIRE_FALSE(closestSurfacePoint(mesh, grid, Vector3d(0.3, 0.4, 1.2), 0.0));
  REQUIRE_FALSE(closestSurfacePoint(mesh, grid, Vector3d(0.3, 0.4, 1.2), -1.0));
}

TEST_CASE("surface_query: intersectSegment on a box gives the first crossing from the segment's start", "[cutting]") {
  const SurfaceMesh box = makeBox(Eigen::AlignedBox3d(Vector3d::Zero(), Vector3d::Ones()), 4);
  const TriMesh& mesh = box.mesh();
  const VertexGrid grid = gridOf(mesh);
  const double r = longestEdge(mesh);

  // Down through the box: the top face first, 1 m from the start.
  auto s = intersectSegment(mesh, grid, Vector3d(0.3, 0.4, 2.0), Vector3d(0.3, 0.4, -1.0), r);
  REQUIRE(s);
  requireNear(s->point_m, Vector3d(0.3, 0.4, 1.0));
  requireNear(s->normal, Vector3d(0, 0, 1));
  REQUIRE(s->distance_m == Approx(1.0).epsilon(1e-12));
  // Up through it: the bottom face, normal -z.
  s = intersectSegment(mesh, grid, Vector3d(0.3, 0.4, -1.0), Vector3d(0.3, 0.4, 2.0), r);
  REQUIRE(s);
  requireNear(s->point_m, Vector3d(0.3, 0.4, 0.0));
  requireNear(s->normal, Vector3d(0, 0, -1));
  REQUIRE(s->distance_m == Approx(1.0).epsilon(1e-12));
  // From inside out through the face y = 1: the normal still points out of the box (+y).
  s = intersectSegment(mesh, grid, Vector3d(0.6, 0.5, 0.7), Vector3d(0.6, 1.5, 0.7), r);
  REQUIRE(s);
  requireNear(s->point_m, Vector3d(0.6, 1.0, 0.7));
  requireNear(s->normal, Vector3d(0, 1, 0));
  REQUIRE(s->distance_m == Approx(0.5).epsilon(1e-12));

  // Misses: beside the box, wholly inside it, stopping short of it; non-finite ends, negative radius.
  REQUIRE_FALSE(intersectSegment(mesh, grid, Vector3d(2, 2, 2), Vector3d(3, 3, -3), r));
  REQUIRE_FALSE(intersectSegment(mesh, grid, Vector3d(0.2, 0.2, 0.2), Vector3d(0.8, 0.8, 0.8), r));
  REQUIRE_FALSE(intersectSegment(mesh, grid, Vector3d(0.3, 0.4, 2.0), Vector3d(0.3, 0.4, 1.01), r));
  const double inf = std::numeric_limits<double>::infinity();
  REQUIRE_FALSE(intersectSegment(mesh, grid, Vector3d(0.3, 0.4, inf), Vector3d(0.3, 0.4, 0), r));
  REQUIRE_FALSE(intersectSegment(mesh, grid, Vector3d(0.3, 0.4, 2.0), Vector3d(0.3, 0.4, -1.0), -1.0));
}

TEST_CASE("surface_query: on a sphere the hit lies on the surface with the normal pointing out", "[cutting]") {
  const Vector3d centre(0.1, 0.2, 0.3);
  const double radius = 0.05;
  const SurfaceMesh sphere = makeSphere(centre, radius, 3);
  const TriMesh& mesh = sphere.mesh();
  const VertexGrid grid = gridOf(mesh);
  const double r = longestEdge(mesh);
  // Every face plane is at least this far from the centre (the inscribed sphere of the icosphere).
  const double inner = radius * 0.99;

  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (int k = 0; k < 100; ++k) {
    const Vector3d dir = Vector3d(g(rng), g(rng), g(rng)).normalized();
    // From outside towards the centre.
    const auto hit = intersectSegment(mesh, grid, centre + 2.0 * radius * dir, centre, r);
    REQUIRE(hit);
    const double from_centre = (hit->point_m - centre).norm();
    REQUIRE(from_centre <= radius * (1.0 + 1e-12));
    REQUIRE(from_centre >= inner);
    REQUIRE(hit->normal.norm() == Approx(1.0).epsilon(1e-12));
    REQUIRE(hit->normal.dot(hit->point_m - centre) > 0.0);  // outward
    REQUIRE(hit->distance_m == Approx(2.0 * radius - from_centre).epsilon(1e-9));
    // The hit is on its face's plane.
    auto corner = mesh.cfv_iter(hit->face);
    const Vector3d p0 = toEigen(mesh.point(*corner));
    REQUIRE(std::abs((hit->point_m - p0).dot(hit->normal)) < 1e-12);

    // The closest point to a point 1.5 radii out is on the surface, about half a radius away, facing it.
    const Vector3d p = centre + 1.5 * radius * dir;
    const auto near = closestSurfacePoint(mesh, grid, p, radius);
    REQUIRE(near);
    REQUIRE((near->point_m - centre).norm() <= radius * (1.0 + 1e-12));
    REQUIRE((near->point_m - centre).norm() >= inner);
    REQUIRE(near->distance_m == Approx((p - near->point_m).norm()).epsilon(1e-12));
    REQUIRE(near->distance_m >= 0.5 * radius - 1e-12);
    REQUIRE(near->distance_m <= 1.5 * radius - inner);
    REQUIRE(near->normal.dot(p - near->point_m) > 0.0);
  }
  // A segment passing beside the sphere misses.
  REQUIRE_FALSE(intersectSegment(mesh, grid, centre + Vector3d(-0.2, 0.06, 0), centre + Vector3d(0.2, 0.06, 0), r));
}
