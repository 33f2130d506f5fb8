// The shape generators without CGAL (shapes.h): boxes, cylinders, icospheres, the disjoint union and the
// robot. Prisms and the face silhouette are in shapes_prism.cpp.
#include "incise/mesh/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "incise/core/format.h"
#include "shapes_internal.h"

namespace incise::mesh {
namespace {

using detail::Builder;
using detail::fail;
using detail::requireAtLeast;
using detail::requireFaceBudget;
using detail::requireFinite;
using detail::requirePositive;

// Unit vectors u, v with (u, v, w) right-handed and orthonormal for the unit vector w: u is the projection
// of the coordinate axis least aligned with w (the first one on ties), normalised.
std::pair<Eigen::Vector3d, Eigen::Vector3d> frameAround(const Eigen::Vector3d& w) {
  int least = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::abs(w[a]) < std::abs(w[least])) least = a;
  }
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(least);
  const Eigen::Vector3d u = (e - e.dot(w) * w).normalized();
  return {u, w.cross(u)};
}

}  // namespace

SurfaceMesh makeBox(const Eigen::AlignedBox3d& box, int divisions) {
  requireAtLeast("makeBox", "divisions", divisions, 1);
  const double nd = divisions;
  requireFaceBudget("makeBox", 12 * nd * nd, "divisions = " + std::to_string(divisions));
  return makeBox(box, Eigen::Vector3i::Constant(divisions));
}

namespace {

// makeBox's argument checks (shapes.h); returns its face count, 4 (n_x n_y + n_y n_z + n_z n_x).
double checkBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3i& divisions) {
  constexpr const char* who = "makeBox";
  requireFinite(who, "box min corner", box.min());
  requireFinite(who, "box max corner", box.max());
  for (int a = 0; a < 3; ++a) {
    const double size = box.max()[a] - box.min()[a];
    if (!(size > 0) || !std::isfinite(size)) {
      fail(who, std::string("box size along ") + "xyz"[a] + " = " + core::formatNumber(size) +
                    " is not finite and > 0 (box " + core::formatPoint(Eigen::Vector3d(box.min())) + " - " +
                    core::formatPoint(Eigen::Vector3d(box.max())) + ")");
    }
    requireAtLeast(who, (std::string("divisions along ") + "xyz"[a]).c_str(), divisions[a], 1);
  }
  const Eigen::Array3d n = divisions.cast<double>().array();
  const double faces = 4.0 * (n[0] * n[1] + n[1] * n[2] + n[2] * n[0]);
  requireFaceBudget(who, faces, "divisions = " + core::formatPoint(Eigen::Vector3d(n.matrix())));
  return faces;
}

// The faces of the box (checked by checkBox, which gave `faces`) appended to `out`, in makeBox's vertex and
// face order.
void appendBox(Builder& out, const Eigen::AlignedBox3d& box, const Eigen::Vector3i& divisions, double faces) {
  const long long m = std::max({divisions[0], divisions[1], divisions[2]}) + 1LL;

  // Surface vertices of the lattice, numbered as they are first met.
  std::unordered_map<long long, int> index;
  index.reserve(static_cast<std::size_t>(faces / 2 + 2));
  auto coordinate = [&](int a, int i) {
    // The last grid line is the max corner exactly, not min + n * step.
    const int na = divisions[a];
    return i == na ? box.max()[a] : box.min()[a] + (box.max()[a] - box.min()[a]) * (static_cast<double>(i) / na);
  };
  auto vertex = [&](const std::array<int, 3>& g) {
    const long long key = (g[0] * m + g[1]) * m + g[2];
    const auto [it, added] = index.try_emplace(key, -1);
    if (added) it->second = out.vertex({coordinate(0, g[0]), coordinate(1, g[1]), coordinate(2, g[2])});
    return it->second;
  };
  // Face with normal +/- e_a: its grid runs along b = a + 1 and c = a + 2 (cyclic), e_b x e_c = e_a.
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3;
    const int c = (a + 2) % 3;
    for (const int side : {0, divisions[a]}) {
      for (int j = 0; j < divisions[b]; ++j) {
        for (int k = 0; k < divisions[c]; ++k) {
          std::array<int, 3> g00{}, g10{}, g11{}, g01{};
          g00[a] = g10[a] = g11[a] = g01[a] = side;
          g00[b] = j, g00[c] = k;
          g10[b] = j + 1, g10[c] = k;
          g11[b] = j + 1, g11[c] = k + 1;
          g01[b] = j, g01[c] = k + 1;
          if (side != 0) {
            out.quad(vertex(g00), vertex(g10), vertex(g11), vertex(g01));
          } else {
            out.quad(vertex(g00), vertex(g01), vertex(g11), vertex(g10));
          }
        }
      }
    }
  }
}

}  // namespace

SurfaceMesh makeBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3i& divisions) {
  const double faces = checkBox(box, divisions);
  Builder out("makeBox", static_cast<long long>(faces / 2 + 2), static_cast<long long>(faces));
  appendBox(out, box, divisions, faces);
  return out.finish();
}

SurfaceMesh makeSkinPad(const Eigen::Vector3d& size_m, double grid_m) {
  constexpr const char* who = "makeSkinPad";
  requireFinite(who, "size_m", size_m);
  requirePositive(who, "grid_m", grid_m);
  for (int a = 0; a < 3; ++a) requirePositive(who, (std::string("size_m.") + "xyz"[a]).c_str(), size_m[a]);
  const auto cells = [&](double length_m, double cell_m) {
    const double count = std::ceil(length_m / cell_m - 1e-9);
    if (!(count <= 1e6))
      fail(who, "grid_m = " + core::formatNumber(grid_m) + " gives more than 1e6 cells along a side");
    return std::max(1, static_cast<int>(count));
  };
  const Eigen::Vector3i divisions(cells(size_m.x(), grid_m), cells(size_m.y(), 4.0 * grid_m),
                                  cells(size_m.z(), grid_m));
  const Eigen::Vector3d half(0.5 * size_m.x(), 0.0, 0.5 * size_m.z());
  return makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(-half.x(), -size_m.y(), -half.z()), half), divisions);
}

namespace {

// makeCylinder's argument checks (shapes.h).
void checkCylinder(const Eigen::Vector3d& base_centre_m, const Eigen::Vector3d& axis_m, double radius_m, int segments,
                   int rings, int cap_rings) {
  constexpr const char* who = "makeCylinder";
  requireFinite(who, "base_centre_m", base_centre_m);
  requireFinite(who, "axis_m", axis_m);
  if (!(axis_m.norm() > 0) || !std::isfinite(axis_m.norm())) {
    fail(who, "axis_m = " + core::formatPoint(axis_m) + " has length " + core::formatNumber(axis_m.norm()) +
                  ": must be finite and > 0");
  }
  requirePositive(who, "radius_m", radius_m);
  requireAtLeast(who, "segments", segments, 3);
  requireAtLeast(who, "rings", rings, 1);
  requireAtLeast(who, "cap_rings", cap_rings, 1);
  const double s = segments;
  requireFaceBudget(who, 2 * s * (static_cast<double>(rings) + 2.0 * cap_rings - 1),
                    "segments = " + std::to_string(segments) + ", rings = " + std::to_string(rings) +
                        ", cap_rings = " + std::to_string(cap_rings));
}

// The cylinder (checked by checkCylinder) appended to `out`, in makeCylinder's vertex and face order, its
// vertices numbered from out.vertices() on.
void appendCylinder(Builder& out, const Eigen::Vector3d& base_centre_m, const Eigen::Vector3d& axis_m, double radius_m,
                    int segments, int rings, int cap_rings) {
  const Eigen::Vector3d w = axis_m.normalized();
  const auto [u, v] = frameAround(w);
  std::vector<Eigen::Vector3d> direction(static_cast<std::size_t>(segments));
  for (int k = 0; k < segments; ++k) {
    const double angle = 2 * std::numbers::pi * k / segments;
    direction[static_cast<std::size_t>(k)] = std::cos(angle) * u + std::sin(angle) * v;
  }
  const long long S = segments;
  const int base = out.vertices();
  auto centreAt = [&](int ring) {
    return ring == rings ? Eigen::Vector3d(base_centre_m + axis_m)
                         : Eigen::Vector3d(base_centre_m + (static_cast<double>(ring) / rings) * axis_m);
  };
  // Side: ring r, segment k at index r * S + k.
  for (int r = 0; r <= rings; ++r) {
    const Eigen::Vector3d centre = centreAt(r);
    for (int k = 0; k < segments; ++k) out.vertex(centre + radius_m * direction[static_cast<std::size_t>(k)]);
  }
  auto side = [&](int r, int k) { return base + static_cast<int>(r * S + (k % segments)); };
  // Going along k turns from u towards v, so (along k) x (along the axis) points outward.
  for (int r = 0; r < rings; ++r) {
    for (int k = 0; k < segments; ++k) out.quad(side(r, k), side(r, k + 1), side(r + 1, k + 1), side(r + 1, k));
  }
  // Caps: a centre vertex and cap_rings - 1 inner polygons; polygon c = cap_rings is the side's end ring.
  for (const bool top : {false, true}) {
    const Eigen::Vector3d centre = centreAt(top ? rings : 0);
    const int centre_vertex = out.vertex(centre);
    const int first_inner = centre_vertex + 1;
    for (int c = 1; c < cap_rings; ++c) {
      const double r = radius_m * (static_cast<double>(c) / cap_rings);
      for (int k = 0; k < segments; ++k) out.vertex(centre + r * direction[static_cast<std::size_t>(k)]);
    }
    auto at = [&](int c, int k) {
      return c == cap_rings ? side(top ? rings : 0, k) : first_inner + static_cast<int>((c - 1) * S + (k % segments));
    };
    // Seen from +w, k runs counter-clockwise: the top keeps that order, the bottom reverses it.
    for (int k = 0; k < segments; ++k) {
      if (top) {
        out.triangle(centre_vertex, at(1, k), at(1, k + 1));
      } else {
        out.triangle(centre_vertex, at(1, k + 1), at(1, k));
      }
      for (int c = 1; c < cap_rings; ++c) {
        if (top) {
          out.quad(at(c + 1, k), at(c + 1, k + 1), at(c, k + 1), at(c, k));
        } else {
          out.quad(at(c + 1, k + 1), at(c + 1, k), at(c, k), at(c, k + 1));
        }
      }
    }
  }
}

}  // namespace

SurfaceMesh makeCylinder(const Eigen::Vector3d& base_centre_m, const Eigen::Vector3d& axis_m, double radius_m,
                         int segments, int rings, int cap_rings) {
  checkCylinder(base_centre_m, axis_m, radius_m, segments, rings, cap_rings);
  const long long S = segments;
  Builder out("makeCylinder", S * (rings + 1 + 2LL * (cap_rings - 1)) + 2, 2 * S * (rings + 2LL * cap_rings - 1));
  appendCylinder(out, base_centre_m, axis_m, radius_m, segments, rings, cap_rings);
  return out.finish();
}

SurfaceMesh makeSphere(const Eigen::Vector3d& centre_m, double radius_m, int subdivisions) {
  constexpr const char* who = "makeSphere";
  requireFinite(who, "centre_m", centre_m);
  requirePositive(who, "radius_m", radius_m);
  requireAtLeast(who, "subdivisions", subdivisions, 0);
  if (subdivisions > 10) {
    fail(who, "subdivisions = " + std::to_string(subdivisions) + " is > 10 (20 * 4^subdivisions faces, at most " +
                  std::to_string(kMaxShapeFaces) + ")");
  }
  const double t = std::numbers::phi;
  std::vector<Eigen::Vector3d> unit = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : unit) p.normalize();
  std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& f : faces) {  // outward: the icosahedron is convex around the origin
    const Eigen::Vector3d& a = unit[static_cast<std::size_t>(f[0])];
    if ((unit[static_cast<std::size_t>(f[1])] - a).cross(unit[static_cast<std::size_t>(f[2])] - a).dot(a) < 0)
      std::swap(f[1], f[2]);
  }
  for (int level = 0; level < subdivisions; ++level) {
    std::unordered_map<std::uint64_t, int> midpoint;
    midpoint.reserve(faces.size() * 3 / 2);
    auto split = [&](int a, int b) {
      const auto key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
      const auto [it, added] = midpoint.try_emplace(key, static_cast<int>(unit.size()));
      if (added) unit.push_back((unit[static_cast<std::size_t>(a)] + unit[static_cast<std::size_t>(b)]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(faces.size() * 4);
    for (const auto& [a, b, c] : faces) {
      const int ab = split(a, b), bc = split(b, c), ca = split(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  Builder out(who, static_cast<long long>(unit.size()), static_cast<long long>(faces.size()));
  for (const auto& p : unit) out.vertex(centre_m + radius_m * p);
  for (const auto& [a, b, c] : faces) out.triangle(a, b, c);
  return out.finish();
}

SurfaceMesh merge(const std::vector<SurfaceMesh>& parts) {
  std::size_t vertices = 0, faces = 0;
  for (const auto& part : parts) {
    vertices += part.mesh().n_vertices();
    faces += part.mesh().n_faces();
  }
  SurfaceMesh out;
  out.mesh().reserve(vertices, vertices + faces, faces);
  for (const auto& part : parts) {
    const TriMesh& m = part.mesh();
    std::vector<TriMesh::VertexHandle> index(m.n_vertices());
    for (const auto v : m.vertices()) {  // skips deleted vertices
      index[static_cast<std::size_t>(v.idx())] = out.addVertex(toEigen(m.point(v)), part.kind(v));
    }
    for (const auto f : m.faces()) {
      std::array<TriMesh::VertexHandle, 3> corner;
      int i = 0;
      for (const auto v : m.fv_range(f))
        corner[static_cast<std::size_t>(i++)] = index[static_cast<std::size_t>(v.idx())];
      out.addFace(corner[0], corner[1], corner[2], part.kind(f));
    }
  }
  out.mesh().update_normals();
  return out;
}

SurfaceMesh makeRobot(double height_m, int detail) {
  constexpr const char* who = "makeRobot";
  requirePositive(who, "height_m", height_m);
  requireAtLeast(who, "detail", detail, 1);
  if (detail > 200) fail(who, "detail = " + std::to_string(detail) + " is > 200");
  const double h = height_m;
  const int d = detail;
  const long long dd = d;
  const int segments = 12 * d;
  // The seven parts straight into one mesh: the same vertices and faces, in the same order, as merge() of the
  // parts made one by one (tests/cutting/mesh/shapes_test.cpp compares them), without building each part's mesh
  // and normals first (a wrap scenario's default robot is 65,088 triangles).
  Builder out(who, 516 * dd * dd - 60 * dd + 14, 1032 * dd * dd - 120 * dd);
  auto upright = [&](double x, double z0, double z1, double radius, int rings) {
    const Eigen::Vector3d base(x * h, 0, z0 * h), axis(0, 0, (z1 - z0) * h);
    checkCylinder(base, axis, radius * h, segments, rings, d);
    appendCylinder(out, base, axis, radius * h, segments, rings, d);
  };
  auto box = [&](double half_x, double half_y, double z0, double z1, int divisions) {
    const Eigen::AlignedBox3d b(Eigen::Vector3d(-half_x * h, -half_y * h, z0 * h),
                                Eigen::Vector3d(half_x * h, half_y * h, z1 * h));
    const Eigen::Vector3i n = Eigen::Vector3i::Constant(divisions);
    appendBox(out, b, n, checkBox(b, n));
  };
  upright(-0.10, 0.00, 0.45, 0.07, 6 * d);  // legs
  upright(0.10, 0.00, 0.45, 0.07, 6 * d);
  box(0.20, 0.10, 0.46, 0.80, 4 * d);       // torso
  upright(-0.27, 0.42, 0.78, 0.05, 5 * d);  // arms
  upright(0.27, 0.42, 0.78, 0.05, 5 * d);
  upright(0.00, 0.81, 0.85, 0.04, d);  // neck
  box(0.09, 0.09, 0.86, 1.00, 2 * d);  // head
  return out.finish();
}

}  // namespace incise::mesh
