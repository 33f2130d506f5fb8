// Tests for cutting/global_dffd/src/clip_cap.cpp: clipping a closed mesh by an axis-aligned plane and capping it (paper
// §3.2, first method). Both halves are closed two-manifolds, lie on their side of the plane, have their cap
// exactly in it and add up to the whole volume; planes that miss the mesh; refused input.
#include "incise/global_dffd/clip_cap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

namespace incise::global_dffd {
namespace {

const char* const kBunny = INCISE_SCENARIOS_DIR "/meshes/bunny.obj";

// Closed, outward-oriented triangle mesh from positions and counter-clockwise (seen from outside) triangles.
mesh::SurfaceMesh buildMesh(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& faces) {
  mesh::SurfaceMesh mesh;
  std::vector<mesh::TriMesh::VertexHandle> v;
  for (const auto& p : points) v.push_back(mesh.addVertex(p));
  for (const auto& f : faces) mesh.addFace(v[f[0]], v[f[1]], v[f[2]]);
  return mesh;
}

// The cube [-1, 1]^3 from 12 triangles (volume 8).
mesh::SurfaceMesh cube() {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0);
  return buildMesh(points, {{0, 2, 3},
                            {0, 3, 1},  // z = -1
                            {4, 5, 7},
                            {4, 7, 6},  // z = +1
                            {0, 1, 5},
                            {0, 5, 4},  // y = -1
                            {2, 6, 7},
                            {2, 7, 3},  // y = +1
                            {0, 4, 6},
                            {0, 6, 2},  // x = -1
                            {1, 3, 7},
                            {1, 7, 5}});  // x = +1
}

// The octahedron |x| + |y| + |z| <= 1 (volume 4/3): its equator lies in the planes x = 0, y = 0, z = 0,
// so clipping there passes through vertices and along edges.
mesh::SurfaceMesh octahedron() {
  return buildMesh({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                   {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
}

// Signed volume: sum over faces of dot(a, cross(b, c)) / 6.
double signedVolume(const mesh::SurfaceMesh& mesh) {
  const mesh::TriMesh& m = mesh.mesh();
  double sum = 0;
  for (const auto f : m.faces()) {
    std::vector<Eigen::Vector3d> p;
    for (const auto v : m.fv_range(f)) p.push_back(mesh::toEigen(m.point(v)));
    sum += p[0].dot(p[1].cross(p[2]));
  }
  return sum / 6;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
};

Range extent(const mesh::SurfaceMesh& mesh, int axis) {
  Range r;
  for (const auto v : mesh.mesh().vertices()) {
    r.lo = std::min(r.lo, mesh.mesh().point(v)[axis]);
    r.hi = std::max(r.hi, mesh.mesh().point(v)[axis]);
  }
  return r;
}

using Key = std::array<double, 3>;

std::set<Key> positions(const mesh::SurfaceMesh& mesh) {
  std::set<Key> out;
  for (const auto v : mesh.mesh().vertices()) {
    const OpenMesh::Vec3d& p = mesh.mesh().point(v);
    out.insert({p[0], p[1], p[2]});
  }
  return out;
}

// Area of the faces lying in the plane x[axis] = value, with the sign of their normal's component along the
// axis.
double capArea(const mesh::SurfaceMesh& mesh, int axis, double value) {
  const mesh::TriMesh& m = mesh.mesh();
  double area = 0;
  for (const auto f : m.faces()) {
    std::vector<Eigen::Vector3d> p;
    for (const auto v : m.fv_range(f)) p.push_back(mesh::toEigen(m.point(v)));
    if (p[0][axis] == value && p[1][axis] == value && p[2][axis] == value) {
      area += (p[1] - p[0]).cross(p[2] - p[0])[axis] / 2;
    }
  }
  return area;
}

// The L-shaped prism: the polygon (0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2) extruded over z in [0, 1]
// (volume 3). The plane y = 1 passes through four of its vertices and contains the top of its right arm.
mesh::SurfaceMesh lPrism() {
  const std::vector<Eigen::Vector2d> polygon{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const int n = static_cast<int>(polygon.size());
  std::vector<Eigen::Vector3d> points;
  for (const double z : {0.0, 1.0}) {
    for (const auto& q : polygon) points.emplace_back(q.x(), q.y(), z);
  }
  std::vector<std::array<int, 3>> faces;
  for (const auto& t : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}, {0, 3, 5}, {3, 4, 5}}) {
    faces.push_back({t[0] + n, t[1] + n, t[2] + n});  // top, seen from +z
    faces.push_back({t[0], t[2], t[1]});              // bottom, seen from -z
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    faces.push_back({i, j, j + n});
    faces.push_back({i, j + n, i + n});
  }
  return buildMesh(points, faces);
}

struct Halves {
  mesh::SurfaceMesh below, above;
};

// Splits `mesh` at x[axis] = value and checks every property both halves must have: closed two-manifolds,
// every vertex on its side, every vertex that is not one of the input's exactly in the plane, volumes adding
// up to the whole and (when the input has no face in the plane) opposite caps of equal area.
// Whether checkSplit compares the caps of the two halves with each other (Skip where they need not match).
enum class Caps : std::uint8_t { Compare, Skip };

Halves checkSplit(const mesh::SurfaceMesh& mesh, int axis, double value, Caps caps = Caps::Compare) {
  const bool compare_caps = caps == Caps::Compare;
  INFO("axis " << axis << ", value " << value);
  Halves h{clipAndCap(mesh, axis, value, KeepSide::Below), clipAndCap(mesh, axis, value, KeepSide::Above)};
  const std::set<Key> input = positions(mesh);
  for (const mesh::SurfaceMesh* part : {&h.below, &h.above}) {
    const mesh::ManifoldReport report = mesh::checkManifold(part->mesh());
    INFO((part == &h.below ? "below" : "above") << ": " << report.first_problem);
    CHECK(report.closed_two_manifold);
    CHECK(report.degenerate_faces == 0);
    for (const auto v : part->mesh().vertices()) {
      const OpenMesh::Vec3d& p = part->mesh().point(v);
      if (part == &h.below) {
        CHECK(p[axis] <= value);
      } else {
        CHECK(p[axis] >= value);
      }
      if (!input.count({p[0], p[1], p[2]})) CHECK(p[axis] == value);
    }
  }
  const double whole = signedVolume(mesh), below = signedVolume(h.below), above = signedVolume(h.above);
  CHECK(below > 0);
  CHECK(above > 0);
  CHECK(std::abs(below + above - whole) <= 1e-9 * whole);
  // The cap closes the below part on its +axis side and the above part on its -axis side.
  if (compare_caps) {
    const double cap_below = capArea(h.below, axis, value), cap_above = capArea(h.above, axis, value);
    CHECK(cap_below > 0);
    CHECK(cap_above == Approx(-cap_below).epsilon(1e-9));
  }
  return h;
}

TEST_CASE("clip_cap: the cube splits into two closed boxes on each axis", "[cutting]") {
  const mesh::SurfaceMesh box = cube();
  REQUIRE(mesh::checkManifold(box.mesh()).closed_two_manifold);
  REQUIRE(signedVolume(box) == Approx(8.0));
  for (int axis = 0; axis < 3; ++axis) {
    const double value = 0.3;
    const Halves h = checkSplit(box, axis, value);
    CHECK(signedVolume(h.below) == Approx(1.3 * 4).epsilon(1e-12));
    CHECK(signedVolume(h.above) == Approx(0.7 * 4).epsilon(1e-12));
    CHECK(capArea(h.below, axis, value) == Approx(4.0).epsilon(1e-12));
    CHECK(extent(h.below, axis).lo == -1.0);
    CHECK(extent(h.below, axis).hi == value);
    CHECK(extent(h.above, axis).lo == value);
    CHECK(extent(h.above, axis).hi == 1.0);
  }
}

TEST_CASE("clip_cap: a plane through vertices and along edges gives two closed pyramids", "[cutting]") {
  const mesh::SurfaceMesh octa = octahedron();
  REQUIRE(mesh::checkManifold(octa.mesh()).closed_two_manifold);
  for (int axis = 0; axis < 3; ++axis) {
    const Halves h = checkSplit(octa, axis, 0.0);
    CHECK(signedVolume(h.below) == Approx(2.0 / 3).epsilon(1e-12));
    CHECK(signedVolume(h.above) == Approx(2.0 / 3).epsilon(1e-12));
    CHECK(capArea(h.below, axis, 0.0) == Approx(2.0).epsilon(1e-12));
  }
}

TEST_CASE("clip_cap: a plane containing a face of a non-convex mesh splits it cleanly", "[cutting]") {
  const mesh::SurfaceMesh l = lPrism();
  REQUIRE(mesh::checkManifold(l.mesh()).closed_two_manifold);
  REQUIRE(signedVolume(l) == Approx(3.0));
  const Halves h = checkSplit(l, 1, 1.0, Caps::Skip);
  CHECK(signedVolume(h.below) == Approx(2.0).epsilon(1e-12));
  CHECK(signedVolume(h.above) == Approx(1.0).epsilon(1e-12));
  // Below: the cap (x in [0, 1]) and the arm's top (x in [1, 2]) face +y. Above: only the cap, facing -y.
  CHECK(capArea(h.below, 1, 1.0) == Approx(2.0).epsilon(1e-12));
  CHECK(capArea(h.above, 1, 1.0) == Approx(-1.0).epsilon(1e-12));
}

TEST_CASE("clip_cap: deleted elements of the input are skipped", "[cutting]") {
  mesh::SurfaceMesh box = cube();
  const auto a = box.addVertex({5, 5, 5}), b = box.addVertex({6, 5, 5}), c = box.addVertex({5, 6, 5});
  box.mesh().delete_face(box.addFace(a, b, c), /*delete_isolated_vertices=*/true);
  REQUIRE(mesh::checkManifold(box.mesh()).closed_two_manifold);
  const Halves h = checkSplit(box, 0, -0.25);
  CHECK(signedVolume(h.below) == Approx(0.75 * 4).epsilon(1e-12));
  for (int axis = 0; axis < 3; ++axis) {
    CHECK(extent(h.below, axis).hi <= 1.0);
    CHECK(extent(h.above, axis).hi == 1.0);
  }
}

TEST_CASE("clip_cap: a mesh intersecting itself at the plane is refused with a MeshError", "[cutting]") {
  // Two interpenetrating cubes in one mesh: each is a closed two-manifold, together they intersect.
  const mesh::SurfaceMesh one = cube();
  mesh::SurfaceMesh two = cube();
  std::vector<mesh::TriMesh::VertexHandle> v;
  for (const auto u : one.mesh().vertices()) {
    v.push_back(two.addVertex(mesh::toEigen(one.mesh().point(u)) + Eigen::Vector3d(0.5, 0.25, 0.125)));
  }
  for (const auto f : one.mesh().faces()) {
    std::vector<int> i;
    for (const auto u : one.mesh().fv_range(f)) i.push_back(u.idx());
    two.addFace(v[i[0]], v[i[1]], v[i[2]]);
  }
  REQUIRE(mesh::checkManifold(two.mesh()).closed_two_manifold);
  CHECK_THROWS_AS(clipAndCap(two, 0, 0.3, KeepSide::Below), mesh::MeshError);
  CHECK_THROWS_WITH(clipAndCap(two, 0, 0.3, KeepSide::Above), Catch::Contains("intersects itself"));
}

TEST_CASE("clip_cap: the bunny splits into two closed halves through its middle on each axis", "[cutting]") {
  const mesh::SurfaceMesh bunny = mesh::loadSurfaceMesh(kBunny, 0.01);
  for (int axis = 0; axis < 3; ++axis) {
    const Range r = extent(bunny, axis);
    // Off-centre values that are not round numbers, so the plane misses the vertices.
    for (const double t : {0.5, 0.137, 0.862}) checkSplit(bunny, axis, r.lo + t * (r.hi - r.lo));
  }
}

TEST_CASE("clip_cap: the twice-subdivided bunny splits into two closed halves", "[cutting]") {
  const mesh::SurfaceMesh fine = mesh::subdivided(mesh::loadSurfaceMesh(kBunny, 0.01), 2);
  const Range r = extent(fine, 1);
  checkSplit(fine, 1, r.lo + 0.41 * (r.hi - r.lo));
}

TEST_CASE("clip_cap: a plane outside the mesh gives an empty mesh or a copy", "[cutting]") {
  const mesh::SurfaceMesh box = cube();
  for (int axis = 0; axis < 3; ++axis) {
    // Beyond the mesh, and touching its face: the side with no volume is empty.
    for (const double value : {2.0, 1.0}) {
      const mesh::SurfaceMesh below = clipAndCap(box, axis, value, KeepSide::Below);
      const mesh::SurfaceMesh above = clipAndCap(box, axis, value, KeepSide::Above);
      CHECK(above.mesh().n_vertices() == 0);
      CHECK(above.mesh().n_faces() == 0);
      REQUIRE(below.mesh().n_vertices() == box.mesh().n_vertices());
      REQUIRE(below.mesh().n_faces() == box.mesh().n_faces());
      for (const auto v : box.mesh().vertices()) CHECK(below.mesh().point(v) == box.mesh().point(v));
      CHECK(signedVolume(below) == signedVolume(box));
    }
    for (const double value : {-2.0, -1.0}) {
      CHECK(clipAndCap(box, axis, value, KeepSide::Below).mesh().n_faces() == 0);
      CHECK(clipAndCap(box, axis, value, KeepSide::Above).mesh().n_faces() == box.mesh().n_faces());
    }
  }
}

TEST_CASE("clip_cap: an open mesh is refused with a MeshError", "[cutting]") {
  mesh::SurfaceMesh open = cube();
  open.mesh().delete_face(*open.mesh().faces_begin(), /*delete_isolated_vertices=*/false);
  REQUIRE_THROWS_AS(clipAndCap(open, 0, 0.3, KeepSide::Below), mesh::MeshError);
  REQUIRE_THROWS_WITH(clipAndCap(open, 0, 0.3, KeepSide::Above),
                      Catch::Contains("not a closed two-manifold") && Catch::Contains("boundary"));
  CHECK_THROWS_AS(clipAndCap(mesh::SurfaceMesh(), 0, 0.0, KeepSide::Below), mesh::MeshError);
}

TEST_CASE("clip_cap: a bad axis or plane value throws invalid_argument", "[cutting]") {
  const mesh::SurfaceMesh box = cube();
  CHECK_THROWS_AS(clipAndCap(box, -1, 0.0, KeepSide::Below), std::invalid_argument);
  CHECK_THROWS_AS(clipAndCap(box, 3, 0.0, KeepSide::Above), std::invalid_argument);
  CHECK_THROWS_AS(clipAndCap(box, 0, std::numeric_limits<double>::quiet_NaN(), KeepSide::Below), std::invalid_argument);
  CHECK_THROWS_AS(clipAndCap(box, 1, std::numeric_limits<double>::infinity(), KeepSide::Above), std::invalid_argument);
}

}  // namespace
}  // namespace incise::global_dffd
