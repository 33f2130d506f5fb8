// Tests for cutting/mesh/src/shapes.cpp and shapes_prism.cpp: every generated mesh is a closed, outward-oriented
// two-manifold of genus 0 per component with the expected element counts and volume; the face silhouette
// is non-convex and monotone in y; the robot's parts are disjoint; bad arguments are refused with their
// value.
#include "incise/mesh/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "incise/tets/tetrahedralize.h"

namespace incise::mesh {
namespace {

// Sum over faces of dot(a, cross(b, c)) / 6: positive for an outward-oriented closed surface.
double signedVolume(const TriMesh& mesh) {
  double volume = 0;
  for (const auto f : mesh.faces()) {
    std::vector<Eigen::Vector3d> p;
    for (const auto v : mesh.fv_range(f)) p.push_back(toEigen(mesh.point(v)));
    volume += p[0].dot(p[1].cross(p[2])) / 6;
  }
  return volume;
}

// V - E + F of every connected component (vertex-edge graph), in order of each component's lowest vertex.
std::vector<int> componentEulerCharacteristics(const TriMesh& mesh) {
  std::vector<int> parent(mesh.n_vertices());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  std::function<int(int)> root = [&](int v) {
    while (parent[static_cast<size_t>(v)] != v)
      v = parent[static_cast<size_t>(v)] = parent[static_cast<size_t>(parent[static_cast<size_t>(v)])];
    return v;
  };
  for (const auto e : mesh.edges()) {
    const int a = root(mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)).idx());
    const int b = root(mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx());
    parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
  }
  std::map<int, int> chi;
  for (const auto v : mesh.vertices()) ++chi[root(v.idx())];
  for (const auto e : mesh.edges()) --chi[root(mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)).idx())];
  for (const auto f : mesh.faces()) ++chi[root(mesh.fv_range(f).begin()->idx())];
  std::vector<int> out;
  for (const auto& [component, value] : chi) out.push_back(value);
  return out;
}

// The faces of every connected component (faces sharing a vertex are connected), in order of each
// component's lowest face.
std::vector<std::vector<int>> componentFaces(const TriMesh& mesh) {
  std::vector<int> component(mesh.n_faces(), -1);
  std::vector<std::vector<int>> out;
  for (const auto seed : mesh.faces()) {
    if (component[static_cast<size_t>(seed.idx())] != -1) continue;
    out.emplace_back();
    std::vector<TriMesh::FaceHandle> stack{seed};
    component[static_cast<size_t>(seed.idx())] = static_cast<int>(out.size()) - 1;
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      out.back().push_back(f.idx());
      for (const auto v : mesh.fv_range(f)) {
        for (const auto g : mesh.vf_range(v)) {
          if (component[static_cast<size_t>(g.idx())] != -1) continue;
          component[static_cast<size_t>(g.idx())] = component[static_cast<size_t>(f.idx())];
          stack.push_back(g);
        }
      }
    }
  }
  return out;
}

// Closed two-manifold, every component a sphere (Euler characteristic 2), outward (positive volume).
void requireClosedOutward(const SurfaceMesh& surface, int components = 1) {
  const ManifoldReport report = checkManifold(surface.mesh());
  INFO(report.first_problem);
  REQUIRE(report.closed_two_manifold);
  REQUIRE(report.degenerate_faces == 0);
  REQUIRE(report.components == components);
  const std::vector<int> chi = componentEulerCharacteristics(surface.mesh());
  REQUIRE(chi == std::vector<int>(static_cast<size_t>(components), 2));
  REQUIRE(signedVolume(surface.mesh()) > 0);
}

double polygonArea(const std::vector<Eigen::Vector2d>& p) {
  double twice = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const auto& a = p[i];
    const auto& b = p[(i + 1) % p.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return twice / 2;
}

// The std::invalid_argument message of `make()`; fails the test when nothing (or something else) is thrown.
template <typename Make>
std::string refusal(Make make) {
  try {
    make();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  FAIL("no std::invalid_argument thrown");
  return {};
}

using Catch::Matchers::Contains;

TEST_CASE("shapes: makeBox is a watertight grid with the box's volume", "[cutting]") {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.5, 0.25, 1.0), Eigen::Vector3d(1.5, 0.75, 4.0));
  for (const int n : {1, 2, 5, 16}) {
    INFO("divisions " << n);
    const SurfaceMesh mesh = makeBox(box, n);
    requireClosedOutward(mesh);
    CHECK(static_cast<int>(mesh.mesh().n_vertices()) == 6 * n * n + 2);
    CHECK(static_cast<int>(mesh.mesh().n_faces()) == 12 * n * n);
    CHECK(signedVolume(mesh.mesh()) == Approx(box.volume()).epsilon(1e-13));
    Eigen::AlignedBox3d bounds;
    for (const auto v : mesh.mesh().vertices()) bounds.extend(toEigen(mesh.mesh().point(v)));
    CHECK((bounds.min() == box.min()));
    CHECK((bounds.max() == box.max()));
  }
}

TEST_CASE("shapes: makeBox with divisions per axis is watertight, its top a grid of its own", "[cutting]") {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.5, 0.25, 1.0), Eigen::Vector3d(1.5, 0.75, 4.0));
  const Eigen::Vector3i n(7, 2, 5);
  const SurfaceMesh mesh = makeBox(box, n);
  requireClosedOutward(mesh);
  const int faces = 4 * (n.x() * n.y() + n.y() * n.z() + n.z() * n.x());
  CHECK(static_cast<int>(mesh.mesh().n_faces()) == faces);
  CHECK(static_cast<int>(mesh.mesh().n_vertices()) == faces / 2 + 2);  // Euler: V - E + F = 2, E = 3F / 2
  CHECK(signedVolume(mesh.mesh()) == Approx(box.volume()).epsilon(1e-13));
  // The same divisions on every axis give makeBox(box, n)'s mesh, vertex for vertex.
  const SurfaceMesh cube = makeBox(box, Eigen::Vector3i::Constant(3)), same = makeBox(box, 3);
  REQUIRE(cube.mesh().n_vertices() == same.mesh().n_vertices());
  for (const auto v : cube.mesh().vertices()) CHECK(cube.mesh().point(v) == same.mesh().point(v));
  CHECK_THROWS_AS(makeBox(box, Eigen::Vector3i(3, 0, 3)), std::invalid_argument);
}

TEST_CASE("shapes: makeSkinPad is a 10 x 10 x 2 cm box, top at y = 0, a 1 mm grid on top", "[cutting]") {
  const SurfaceMesh pad = makeSkinPad(Eigen::Vector3d(0.1, 0.02, 0.1), 0.001);
  requireClosedOutward(pad);
  CHECK(pad.mesh().n_faces() == 44000);
  CHECK(signedVolume(pad.mesh()) == Approx(0.1 * 0.02 * 0.1).epsilon(1e-12));
  int top = 0;
  double longest_top_edge_m = 0.0;
  for (const auto e : pad.mesh().edges()) {
    const auto h = pad.mesh().halfedge_handle(e, 0);
    const Eigen::Vector3d a = toEigen(pad.mesh().point(pad.mesh().from_vertex_handle(h)));
    const Eigen::Vector3d b = toEigen(pad.mesh().point(pad.mesh().to_vertex_handle(h)));
    if (a.y() == 0.0 && b.y() == 0.0) longest_top_edge_m = std::max(longest_top_edge_m, (a - b).norm());
  }
  for (const auto v : pad.mesh().vertices()) top += pad.mesh().point(v)[1] == 0.0 ? 1 : 0;
  CHECK(top == 101 * 101);
  CHECK(longest_top_edge_m == Approx(std::sqrt(2.0) * 0.001).epsilon(1e-9));  // the cells' diagonals
  CHECK_THROWS_AS(makeSkinPad(Eigen::Vector3d(0.1, 0.0, 0.1), 0.001), std::invalid_argument);
  CHECK_THROWS_AS(makeSkinPad(Eigen::Vector3d(0.1, 0.02, 0.1), 0.0), std::invalid_argument);
}

TEST_CASE("shapes: makeCylinder is the prism over the inscribed polygon", "[cutting]") {
  const Eigen::Vector3d base(0.1, -0.2, 0.3);
  const double radius = 0.25;
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(0.3, -0.4, 0.2)}) {
    for (const auto [segments, rings, cap_rings] :
         {std::array<int, 3>{3, 1, 1}, std::array<int, 3>{8, 3, 2}, std::array<int, 3>{40, 7, 5}}) {
      INFO("axis " << axis.transpose() << ", segments " << segments << ", rings " << rings << ", cap rings "
                   << cap_rings);
      const SurfaceMesh mesh = makeCylinder(base, axis, radius, segments, rings, cap_rings);
      requireClosedOutward(mesh);
      CHECK(static_cast<int>(mesh.mesh().n_vertices()) == segments * (rings + 1 + 2 * (cap_rings - 1)) + 2);
      CHECK(static_cast<int>(mesh.mesh().n_faces()) == 2 * segments * (rings + 2 * cap_rings - 1));
      const double inscribed =
          segments / 2.0 * radius * radius * std::sin(2 * std::numbers::pi / segments) * axis.norm();
      CHECK(signedVolume(mesh.mesh()) == Approx(inscribed).epsilon(1e-12));
      CHECK(inscribed < std::numbers::pi * radius * radius * axis.norm());
      // Every vertex inside the true cylinder; the side and cap-rim ones on it.
      const Eigen::Vector3d w = axis.normalized();
      int on_surface = 0;
      for (const auto v : mesh.mesh().vertices()) {
        const Eigen::Vector3d d = toEigen(mesh.mesh().point(v)) - base;
        const double along = d.dot(w);
        const double across = (d - along * w).norm();
        REQUIRE(along >= -1e-12);
        REQUIRE(along <= axis.norm() + 1e-12);
        REQUIRE(across <= radius * (1 + 1e-12));
        if (std::abs(across - radius) < 1e-12) ++on_surface;
      }
      CHECK(on_surface == segments * (rings + 1));
    }
  }
  SECTION("along +z the first segment points to +x and the next turns towards +y") {
    const SurfaceMesh mesh = makeCylinder(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), 1.0, 4);
    const auto p0 = toEigen(mesh.mesh().point(mesh.mesh().vertex_handle(0)));
    const auto p1 = toEigen(mesh.mesh().point(mesh.mesh().vertex_handle(1)));
    CHECK((p0 - Eigen::Vector3d(1, 0, 0)).norm() < 1e-15);
    CHECK((p1 - Eigen::Vector3d(0, 1, 0)).norm() < 1e-15);
  }
}

TEST_CASE("shapes: makeSphere is an icosphere between its inscribed ball and the ball", "[cutting]") {
  const Eigen::Vector3d centre(0.5, -1.0, 2.0);
  const double radius = 0.3;
  for (int s = 0; s <= 4; ++s) {
    INFO("subdivisions " << s);
    const SurfaceMesh mesh = makeSphere(centre, radius, s);
    requireClosedOutward(mesh);
    const int four_s = 1 << (2 * s);
    CHECK(static_cast<int>(mesh.mesh().n_vertices()) == 10 * four_s + 2);
    CHECK(static_cast<int>(mesh.mesh().n_faces()) == 20 * four_s);
    for (const auto v : mesh.mesh().vertices()) {
      REQUIRE((toEigen(mesh.mesh().point(v)) - centre).norm() == Approx(radius).epsilon(1e-14));
    }
    // The polyhedron is convex and contains the ball touching its nearest face plane.
    double nearest = radius;
    for (const auto f : mesh.mesh().faces()) {
      std::vector<Eigen::Vector3d> p;
      for (const auto v : mesh.mesh().fv_range(f)) p.push_back(toEigen(mesh.mesh().point(v)) - centre);
      const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
      REQUIRE(normal.dot(p[0]) > 0);  // outward
      nearest = std::min(nearest, normal.dot(p[0]));
    }
    const double volume = signedVolume(mesh.mesh());
    CHECK(volume < 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3));
    CHECK(volume > 4.0 / 3.0 * std::numbers::pi * std::pow(nearest, 3));
  }
  // The regular icosahedron's volume, exactly known.
  const double edge = radius / std::sin(2 * std::numbers::pi / 5);
  CHECK(signedVolume(makeSphere(centre, radius, 0).mesh()) ==
        Approx(5.0 / 12.0 * (3 + std::sqrt(5.0)) * std::pow(edge, 3)).epsilon(1e-12));
}

TEST_CASE("shapes: makePrism extrudes convex and non-convex outlines in either orientation", "[cutting]") {
  const std::vector<Eigen::Vector2d> square = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  // An L with a collinear point and a notch: non-convex.
  const std::vector<Eigen::Vector2d> notched = {{0, 0},     {1, 0}, {3, 0}, {3, 1}, {2, 1},
                                                {1.5, 0.4}, {1, 1}, {1, 3}, {0, 3}};
  // A 7-pointed star: many reflex vertices.
  std::vector<Eigen::Vector2d> star;
  for (int i = 0; i < 14; ++i) {
    const double angle = 2 * std::numbers::pi * i / 14;
    const double r = i % 2 == 0 ? 1.0 : 0.35;
    star.emplace_back(r * std::cos(angle), r * std::sin(angle));
  }
  for (const auto& outline : {square, notched, star, faceSilhouette(0.2, 60)}) {
    for (const bool clockwise : {false, true}) {
      for (const int rings : {1, 3}) {
        std::vector<Eigen::Vector2d> p = outline;
        if (clockwise) std::reverse(p.begin(), p.end());
        INFO(p.size() << " points, clockwise " << clockwise << ", rings " << rings);
        const double z0 = -0.25, z1 = 0.5;
        const SurfaceMesh mesh = makePrism(p, z0, z1, rings);
        requireClosedOutward(mesh);
        const int n = static_cast<int>(p.size());
        CHECK(static_cast<int>(mesh.mesh().n_vertices()) == n * (rings + 1));
        CHECK(static_cast<int>(mesh.mesh().n_faces()) == 2 * n * rings + 2 * (n - 2));
        CHECK(signedVolume(mesh.mesh()) == Approx(std::abs(polygonArea(p)) * (z1 - z0)).epsilon(1e-12));
        for (const auto v : mesh.mesh().vertices()) {
          const double z = mesh.mesh().point(v)[2];
          REQUIRE(z >= z0);
          REQUIRE(z <= z1);
        }
        // The caps are embedded discs: every cap triangle turns the right way in the xy-plane (up for the
        // top, down for the bottom) and their areas add up to the outline's, so none overlaps another or
        // leaves the outline.
        double top_area = 0, bottom_area = 0;
        int top_faces = 0, bottom_faces = 0;
        for (const auto f : mesh.mesh().faces()) {
          std::vector<Eigen::Vector3d> q;
          for (const auto v : mesh.mesh().fv_range(f)) q.push_back(toEigen(mesh.mesh().point(v)));
          const double area_z = (q[1] - q[0]).cross(q[2] - q[0]).z() / 2;
          if (q[0].z() == z1 && q[1].z() == z1 && q[2].z() == z1) {
            REQUIRE(area_z > 0);
            top_area += area_z;
            ++top_faces;
          } else if (q[0].z() == z0 && q[1].z() == z0 && q[2].z() == z0) {
            REQUIRE(area_z < 0);
            bottom_area -= area_z;
            ++bottom_faces;
          }
        }
        CHECK(top_faces == n - 2);
        CHECK(bottom_faces == n - 2);
        CHECK(top_area == Approx(std::abs(polygonArea(p))).epsilon(1e-12));
        CHECK(bottom_area == Approx(std::abs(polygonArea(p))).epsilon(1e-12));
      }
    }
  }
}

TEST_CASE("shapes: makePrism refuses a self-intersecting outline naming the two edges", "[cutting]") {
  // A bow tie: edge 0 (points 0 - 1) crosses edge 2 (points 2 - 3).
  CHECK_THAT(refusal([] {
               makePrism({{0, 0}, {1, 1}, {1, 0}, {0, 1}}, 0, 1);
             }),
             Contains("outline edges 0 (points 0 - 1) and 2 (points 2 - 3) cross or touch"));
  // Point 4 lies on edge 1 (points 1 - 2): edges 1 and 3, 1 and 4 touch it; the lowest pair is named.
  CHECK_THAT(refusal([] {
               makePrism({{0, 0}, {2, 0}, {2, 2}, {1, 3}, {2, 1}, {0, 2}}, 0, 1);
             }),
             Contains("outline edges 1 (points 1 - 2) and 3 (points 3 - 4)"));
  // Folding back along itself at point 2.
  CHECK_THAT(refusal([] { makePrism({{0, 0}, {2, 0}, {3, 0}, {1, 0}, {1, 1}}, 0, 1); }), Contains("outline edges"));
  // A collinear triangle: edge 2 runs back over edge 0.
  CHECK_THAT(refusal([] {
               makePrism({{0, 0}, {1, 0}, {2, 0}}, 0, 1);
             }),
             Contains("outline edges 0 (points 0 - 1) and 2 (points 2 - 0)"));
  // A point repeated further on (the outline touches itself).
  CHECK_THAT(refusal([] {
               makePrism({{0, 0}, {2, 0}, {1, 1}, {2, 2}, {0, 2}, {1, 1}}, 0, 1);
             }),
             Contains("outline edges 1 (points 1 - 2) and 4 (points 4 - 5)"));
  CHECK_THAT(refusal([] {
               makePrism({{0, 0}, {1, 0}, {1, 0}, {0, 1}}, 0, 1);
             }),
             Contains("outline points 1 and 2 coincide"));
}

TEST_CASE("shapes: faceSilhouette is non-convex, counter-clockwise and monotone in y", "[cutting]") {
  const double height = 0.3;
  // 16,015: the fuzzer's timeout (a cap of that many points took 85 s under ASan, inserted point by point).
  for (const int points : {25, 26, 60, 501, 4000, 16015}) {
    INFO(points << " points");
    const std::vector<Eigen::Vector2d> p = faceSilhouette(height, points);
    REQUIRE(static_cast<int>(p.size()) == points);
    CHECK(polygonArea(p) > 0);
    double ymin = p[0].y(), ymax = p[0].y();
    for (const auto& q : p) {
      ymin = std::min(ymin, q.y());
      ymax = std::max(ymax, q.y());
    }
    CHECK(ymin == -height / 2);
    CHECK(ymax == height / 2);
    // Non-convex: some reflex (clockwise) turn.
    int reflex = 0;
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d a = p[(i + n - 1) % n], b = p[i], c = p[(i + 1) % n];
      const Eigen::Vector2d u = b - a, v = c - b;
      if (u.x() * v.y() - u.y() * v.x() < 0) ++reflex;
    }
    CHECK(reflex >= 2);
    // y strictly up to one top vertex, strictly down to the end, then the horizontal neck cut.
    size_t top = 0;
    while (top + 1 < n && p[top + 1].y() > p[top].y()) ++top;
    CHECK(p[top].y() == ymax);
    size_t end = top;
    while (end + 1 < n && p[end + 1].y() < p[end].y()) ++end;
    CHECK(end == n - 1);
    CHECK(p[0].y() == ymin);
    CHECK(p[n - 1].y() == ymin);
    // Every horizontal line strictly between the extremes meets it exactly twice.
    for (int k = 1; k < 997; ++k) {
      const double c = ymin + (ymax - ymin) * k / 997.0;
      int crossings = 0;
      for (size_t i = 0; i < n; ++i) {
        const double y0 = p[i].y(), y1 = p[(i + 1) % n].y();
        if ((y0 <= c) != (y1 <= c)) ++crossings;
      }
      REQUIRE(crossings == 2);
    }
    // A simple polygon: makePrism accepts it.
    requireClosedOutward(makePrism(p, 0, 0.05));
  }
}

TEST_CASE("shapes: merge is the disjoint union of closed parts", "[cutting]") {
  std::vector<SurfaceMesh> parts;
  parts.push_back(makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)), 2));
  parts.push_back(makeSphere(Eigen::Vector3d(3, 0, 0), 0.5, 2));
  parts.push_back(makeCylinder(Eigen::Vector3d(0, 3, 0), Eigen::Vector3d(0, 0, 1), 0.5, 12, 2, 2));
  parts[1].setKind(parts[1].mesh().vertex_handle(5), VertexKind::Seam);
  parts[2].setKind(parts[2].mesh().face_handle(7), FaceKind::Wall);
  const SurfaceMesh merged = merge(parts);
  requireClosedOutward(merged, 3);
  size_t vertices = 0, faces = 0;
  double volume = 0;
  for (const auto& part : parts) {
    vertices += part.mesh().n_vertices();
    faces += part.mesh().n_faces();
    volume += signedVolume(part.mesh());
  }
  CHECK(merged.mesh().n_vertices() == vertices);
  CHECK(merged.mesh().n_faces() == faces);
  CHECK(signedVolume(merged.mesh()) == Approx(volume).epsilon(1e-14));
  const size_t offset1 = parts[0].mesh().n_vertices();
  CHECK(merged.mesh().point(merged.mesh().vertex_handle(static_cast<unsigned>(offset1 + 5))) ==
        parts[1].mesh().point(parts[1].mesh().vertex_handle(5)));
  CHECK(merged.kind(merged.mesh().vertex_handle(static_cast<unsigned>(offset1 + 5))) == VertexKind::Seam);
  const size_t face_offset2 = parts[0].mesh().n_faces() + parts[1].mesh().n_faces();
  CHECK(merged.kind(merged.mesh().face_handle(static_cast<unsigned>(face_offset2 + 7))) == FaceKind::Wall);
  CHECK(merge({}).mesh().n_vertices() == 0);
}

TEST_CASE("shapes: makeRobot has 7 disjoint closed parts and >= 30000 vertices at kRobotDetail30k", "[cutting]") {
  const double height = 1.8;
  for (const int detail : {1, 2, kRobotDetail30k}) {
    INFO("detail " << detail);
    const SurfaceMesh robot = makeRobot(height, detail);
    requireClosedOutward(robot, 7);
    const long long d = detail;
    CHECK(static_cast<long long>(robot.mesh().n_vertices()) == 516 * d * d - 60 * d + 14);
    CHECK(static_cast<long long>(robot.mesh().n_faces()) == 1032 * d * d - 120 * d);
    // The parts are convex (checked here at low detail: every vertex of a part behind every face plane of
    // it) and their bounding boxes are at least 0.01 * height apart, so no two parts meet.
    const std::vector<std::vector<int>> parts = componentFaces(robot.mesh());
    REQUIRE(parts.size() == 7u);
    std::vector<Eigen::AlignedBox3d> boxes;
    for (const auto& faces : parts) {
      Eigen::AlignedBox3d box;
      std::vector<Eigen::Vector3d> corners;
      for (const int f : faces) {
        for (const auto v : robot.mesh().fv_range(robot.mesh().face_handle(static_cast<unsigned>(f)))) {
          box.extend(toEigen(robot.mesh().point(v)));
          corners.push_back(toEigen(robot.mesh().point(v)));
        }
      }
      boxes.push_back(box);
      if (detail > 2) continue;
      for (const int f : faces) {
        std::vector<Eigen::Vector3d> q;
        for (const auto v : robot.mesh().fv_range(robot.mesh().face_handle(static_cast<unsigned>(f))))
          q.push_back(toEigen(robot.mesh().point(v)));
        const Eigen::Vector3d normal = (q[1] - q[0]).cross(q[2] - q[0]).normalized();
        for (const auto& c : corners) REQUIRE(normal.dot(c - q[0]) <= 1e-12 * height);
      }
    }
    for (size_t a = 0; a < boxes.size(); ++a) {
      for (size_t b = a + 1; b < boxes.size(); ++b) {
        double gap = 0;
        for (int axis = 0; axis < 3; ++axis) {
          gap =
              std::max({gap, boxes[b].min()[axis] - boxes[a].max()[axis], boxes[a].min()[axis] - boxes[b].max()[axis]});
        }
        INFO("parts " << a << " and " << b);
        CHECK(gap >= 0.01 * height * (1 - 1e-9));
      }
    }
    // CGAL's exact self-intersection test agrees: no two faces of the whole robot meet.
    CHECK_FALSE(mesh::findSelfIntersection(robot.mesh()).has_value());
    Eigen::AlignedBox3d bounds;
    for (const auto v : robot.mesh().vertices()) bounds.extend(toEigen(robot.mesh().point(v)));
    CHECK(bounds.min().z() == 0);
    CHECK(bounds.max().z() == height);
    CHECK(bounds.sizes().x() > bounds.sizes().y());  // width along x
    CHECK(std::abs(bounds.center().x()) < 1e-12);
    CHECK(std::abs(bounds.center().y()) < 1e-12);
  }
  CHECK(makeRobot(height, 1).mesh().n_vertices() == 470u);
  CHECK(makeRobot(height, kRobotDetail30k).mesh().n_vertices() >= 30000u);
  CHECK(makeRobot(height, kRobotDetail30k - 1).mesh().n_vertices() < 30000u);
}

// makeRobot builds its parts straight into one mesh; the parts made one by one and merged are the reference:
// the same points (bit for bit), the same faces with the same corners in the same order, the same normals.
TEST_CASE("shapes: makeRobot is the merge of its seven parts, bit for bit", "[cutting]") {
  for (const int detail : {1, 3}) {
    INFO("detail " << detail);
    const double h = 1.7;
    const int d = detail;
    auto upright = [&](double x, double z0, double z1, double radius, int rings) {
      return makeCylinder({x * h, 0, z0 * h}, {0, 0, (z1 - z0) * h}, radius * h, 12 * d, rings, d);
    };
    auto box = [&](double half_x, double half_y, double z0, double z1, int divisions) {
      return makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(-half_x * h, -half_y * h, z0 * h),
                                         Eigen::Vector3d(half_x * h, half_y * h, z1 * h)),
                     divisions);
    };
    const SurfaceMesh reference =
        merge({upright(-0.10, 0.00, 0.45, 0.07, 6 * d), upright(0.10, 0.00, 0.45, 0.07, 6 * d),
               box(0.20, 0.10, 0.46, 0.80, 4 * d), upright(-0.27, 0.42, 0.78, 0.05, 5 * d),
               upright(0.27, 0.42, 0.78, 0.05, 5 * d), upright(0.00, 0.81, 0.85, 0.04, d),
               box(0.09, 0.09, 0.86, 1.00, 2 * d)});
    const SurfaceMesh robot = makeRobot(h, detail);
    const TriMesh& a = robot.mesh();
    const TriMesh& b = reference.mesh();
    REQUIRE(a.n_vertices() == b.n_vertices());
    REQUIRE(a.n_faces() == b.n_faces());
    REQUIRE(a.n_edges() == b.n_edges());
    for (const auto v : a.vertices()) {
      REQUIRE(a.point(v) == b.point(v));
      REQUIRE(a.normal(v) == b.normal(v));
    }
    for (const auto f : a.faces()) {
      std::vector<int> ca, cb;
      for (const auto v : a.fv_range(f)) ca.push_back(v.idx());
      for (const auto v : b.fv_range(b.face_handle(static_cast<unsigned>(f.idx())))) cb.push_back(v.idx());
      REQUIRE(ca == cb);
    }
  }
}

TEST_CASE("shapes: bad arguments are refused with their value", "[cutting]") {
  const double nan = std::nan("");
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::AlignedBox3d unit(zero, Eigen::Vector3d::Ones());

  CHECK_THAT(refusal([&] { makeBox(unit, 0); }), Contains("makeBox") && Contains("divisions = 0"));
  CHECK_THAT(refusal([&] { makeBox(Eigen::AlignedBox3d(zero, Eigen::Vector3d(1, 0, 1)), 1); }),
             Contains("box size along y = 0"));
  CHECK_THAT(refusal([&] { makeBox(Eigen::AlignedBox3d(zero, Eigen::Vector3d(1, nan, 1)), 1); }),
             Contains("box max corner") && Contains("nan"));
  CHECK_THAT(refusal([&] { makeBox(unit, 100000); }), Contains("divisions = 100000"));

  CHECK_THAT(refusal([&] { makeCylinder(zero, z, -0.5, 8); }), Contains("radius_m = -0.5"));
  CHECK_THAT(refusal([&] { makeCylinder(zero, z, 1, 2); }), Contains("segments = 2"));
  CHECK_THAT(refusal([&] { makeCylinder(zero, z, 1, 8, 0); }), Contains("rings = 0"));
  CHECK_THAT(refusal([&] { makeCylinder(zero, z, 1, 8, 1, 0); }), Contains("cap_rings = 0"));
  CHECK_THAT(refusal([&] { makeCylinder(zero, zero, 1, 8); }), Contains("axis_m = (0, 0, 0)"));
  CHECK_THAT(refusal([&] { makeCylinder(Eigen::Vector3d(0, nan, 0), z, 1, 8); }), Contains("base_centre_m"));
  CHECK_THAT(refusal([&] { makeCylinder(zero, z, std::numeric_limits<double>::infinity(), 8); }),
             Contains("radius_m = inf"));

  CHECK_THAT(refusal([&] { makeSphere(zero, 0, 2); }), Contains("radius_m = 0"));
  CHECK_THAT(refusal([&] { makeSphere(zero, 1, -1); }), Contains("subdivisions = -1"));
  CHECK_THAT(refusal([&] { makeSphere(zero, 1, 11); }), Contains("subdivisions = 11"));
  CHECK_THAT(refusal([&] { makeSphere(Eigen::Vector3d(nan, 0, 0), 1, 1); }), Contains("centre_m = (nan"));

  const std::vector<Eigen::Vector2d> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  CHECK_THAT(refusal([&] { makePrism({{0, 0}, {1, 0}}, 0, 1); }), Contains("2 points"));
  CHECK_THAT(refusal([&] { makePrism(square, 1, 1); }), Contains("z1_m = 1 is not > z0_m = 1"));
  CHECK_THAT(refusal([&] { makePrism(square, 0, nan); }), Contains("z1_m = nan"));
  CHECK_THAT(refusal([&] { makePrism(square, 0, 1, 0); }), Contains("rings = 0"));
  CHECK_THAT(refusal([&] { makePrism({{0, 0}, {1, 0}, {1, nan}}, 0, 1); }), Contains("outline point 2 = (1, nan)"));

  CHECK_THAT(refusal([&] { faceSilhouette(-1, 40); }), Contains("height_m = -1"));
  CHECK_THAT(refusal([&] { faceSilhouette(1, 24); }), Contains("points = 24"));

  CHECK_THAT(refusal([&] { makeRobot(0, 1); }), Contains("height_m = 0"));
  CHECK_THAT(refusal([&] { makeRobot(1, 0); }), Contains("detail = 0"));
  CHECK_THAT(refusal([&] { makeRobot(1, 201); }), Contains("detail = 201"));
}

}  // namespace
}  // namespace incise::mesh
