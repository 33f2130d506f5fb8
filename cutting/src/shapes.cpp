#include "incise/cutting/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "incise/cutting/format.h"

namespace incise::cutting {
namespace {


[[noreturn]] void fail(const char* who, const std::string& what) {
  throw std::invalid_argument(std::string(who) + ": " + what);
}

void requireAtLeast(const char* who, const char* name, int value, int least) {
  if (value < least)
    fail(who, std::string(name) + " = " + std::to_string(value) + " is < " + std::to_string(least));
}

void requirePositive(const char* who, const char* name, double value) {
  if (!std::isfinite(value) || !(value > 0))
    fail(who, std::string(name) + " = " + formatNumber(value) + " is not finite and > 0");
}

void requireFinite(const char* who, const char* name, const Eigen::Vector3d& p) {
  if (!p.allFinite()) fail(who, std::string(name) + " = " + formatPoint(p) + " is not finite");
}

// `faces` is computed in double so that huge arguments cannot overflow before they are refused.
void requireFaceBudget(const char* who, double faces, const std::string& arguments) {
  if (faces > static_cast<double>(kMaxShapeFaces)) {
    fail(who,
         arguments + " would give " + formatNumber(faces) + " faces, more than " + std::to_string(kMaxShapeFaces));
  }
}

// Collects vertices and triangles straight into a SurfaceMesh (every kind Original).
class Builder {
 public:
  Builder(const char* who, long long vertices, long long faces) : who_(who) {
    mesh_.mesh().reserve(static_cast<std::size_t>(vertices), static_cast<std::size_t>(vertices + faces),
                         static_cast<std::size_t>(faces));
  }
  int vertex(const Eigen::Vector3d& p) { return mesh_.mesh().add_vertex(toOpenMesh(p)).idx(); }
  // Counter-clockwise seen from outside.
  void triangle(int a, int b, int c) {
    auto& m = mesh_.mesh();
    if (!m.add_face(m.vertex_handle(static_cast<unsigned>(a)), m.vertex_handle(static_cast<unsigned>(b)),
                    m.vertex_handle(static_cast<unsigned>(c)))
             .is_valid()) {
      // Construction bug, not bad input: the generators only make manifold connectivity.
      throw std::logic_error(std::string(who_) + ": OpenMesh refused face (" + std::to_string(a) + ", " +
                             std::to_string(b) + ", " + std::to_string(c) + ")");
    }
  }
  // The quad a b c d (counter-clockwise seen from outside) as triangles a b c and a c d.
  void quad(int a, int b, int c, int d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  SurfaceMesh finish() {
    mesh_.mesh().update_normals();
    return std::move(mesh_);
  }

 private:
  const char* who_;
  SurfaceMesh mesh_;
};

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

// ---- makePrism: outline check and constrained Delaunay triangulation of the cap -------------------------

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;
using Segment2 = Kernel::Segment_2;
using CdtVertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;  // outline point index
using CdtFaceInfo = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;      // nesting level, -1 unset
using CdtFaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, CdtFaceInfo>;
using CdtTds = CGAL::Triangulation_data_structure_2<CdtVertexBase, CdtFaceBase>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, CdtTds, CGAL::Exact_predicates_tag>;

std::string edgeName(int i, int n) {
  return std::to_string(i) + " (points " + std::to_string(i) + " - " + std::to_string((i + 1) % n) + ")";
}

// Throws unless the closed polyline `p` is a simple polygon. Consecutive edges share a point and must not
// fold back onto each other; any other pair must not meet at all. The smallest failing pair is reported.
void requireSimple(const char* who, const std::vector<Point2>& p) {
  const int n = static_cast<int>(p.size());
  for (int i = 0; i < n; ++i) {
    if (p[static_cast<std::size_t>(i)] == p[static_cast<std::size_t>((i + 1) % n)]) {
      fail(who, "outline points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                    " coincide (edge " + std::to_string(i) + " has zero length)");
    }
  }
  std::pair<int, int> worst{n, n};
  auto report = [&](int i, int j) {
    worst = std::min(worst, std::pair<int, int>(std::min(i, j), std::max(i, j)));
  };
  // Consecutive edges i - 1 and i meet at point i: they overlap when they are collinear and turn back.
  for (int i = 0; i < n; ++i) {
    const Point2& a = p[static_cast<std::size_t>((i + n - 1) % n)];
    const Point2& b = p[static_cast<std::size_t>(i)];
    const Point2& c = p[static_cast<std::size_t>((i + 1) % n)];
    if (CGAL::orientation(a, b, c) == CGAL::COLLINEAR && CGAL::angle(a, b, c) == CGAL::ACUTE)
      report((i + n - 1) % n, i);
  }
  // Non-consecutive edges: sort and sweep on x, exact intersection test for the overlapping ones.
  std::vector<Segment2> edges;
  edges.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    edges.emplace_back(p[static_cast<std::size_t>(i)], p[static_cast<std::size_t>((i + 1) % n)]);
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  auto xmin = [&](int i) {
    return std::min(edges[static_cast<std::size_t>(i)].source().x(),
                    edges[static_cast<std::size_t>(i)].target().x());
  };
  auto xmax = [&](int i) {
    return std::max(edges[static_cast<std::size_t>(i)].source().x(),
                    edges[static_cast<std::size_t>(i)].target().x());
  };
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return xmin(a) < xmin(b) || (xmin(a) == xmin(b) && a < b); });
  for (std::size_t s = 0; s < order.size(); ++s) {
    const int i = order[s];
    const double end = xmax(i);
    for (std::size_t t = s + 1; t < order.size() && xmin(order[t]) <= end; ++t) {
      const int j = order[t];
      const int gap = std::abs(i - j);
      if (gap == 1 || gap == n - 1) continue;  // consecutive: checked above
      if (CGAL::do_intersect(edges[static_cast<std::size_t>(i)], edges[static_cast<std::size_t>(j)]))
        report(i, j);
    }
  }
  if (worst.first < n) {
    fail(who, "outline edges " + edgeName(worst.first, n) + " and " + edgeName(worst.second, n) +
                  " cross or touch: the outline must be a simple polygon");
  }
}

// Nesting level of every face of `cdt`: 0 for the faces reachable from the infinite face without crossing
// a constraint, one more for each constraint crossed (the "mark domains" flood of CGAL's Triangulation_2
// manual). For a simple polygon the faces inside it have level 1.
void markNestingLevels(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::deque<std::pair<Cdt::Face_handle, int>> seeds{{cdt.infinite_face(), 0}};
  while (!seeds.empty()) {
    const auto [start, level] = seeds.front();
    seeds.pop_front();
    if (start->info() != -1) continue;
    std::deque<Cdt::Face_handle> queue{start};
    start->info() = level;
    while (!queue.empty()) {
      const Cdt::Face_handle f = queue.front();
      queue.pop_front();
      for (int e = 0; e < 3; ++e) {
        const Cdt::Face_handle g = f->neighbor(e);
        if (g->info() != -1) continue;
        if (cdt.is_constrained(Cdt::Edge(f, e))) {
          seeds.emplace_back(g, level + 1);
        } else {
          g->info() = level;
          queue.push_back(g);
        }
      }
    }
  }
}

// The triangles (outline point indices, counter-clockwise in the xy-plane) of the simple polygon `p`.
std::vector<std::array<int, 3>> triangulatePolygon(const char* who, const std::vector<Point2>& p) {
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handle(p.size());
  Cdt::Face_handle hint;
  for (std::size_t i = 0; i < p.size(); ++i) {
    handle[i] = cdt.insert(p[i], hint);
    handle[i]->info() = static_cast<int>(i);
    hint = handle[i]->face();
  }
  for (std::size_t i = 0; i < p.size(); ++i) cdt.insert_constraint(handle[i], handle[(i + 1) % p.size()]);
  // requireSimple ruled out repeated points and crossings, so CGAL adds no vertex; checked anyway.
  if (cdt.number_of_vertices() != p.size()) {
    throw std::logic_error(std::string(who) + ": the cap triangulation has " +
                           std::to_string(cdt.number_of_vertices()) + " vertices for " +
                           std::to_string(p.size()) + " outline points");
  }
  markNestingLevels(cdt);
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(p.size() - 2);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 == 1)
      triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  if (triangles.size() != p.size() - 2) {
    throw std::logic_error(std::string(who) + ": the cap triangulation has " +
                           std::to_string(triangles.size()) + " triangles inside the outline, expected " +
                           std::to_string(p.size() - 2));
  }
  return triangles;
}

// ---- faceSilhouette -------------------------------------------------------------------------------------

// The landmark outline for height 1, as (x, y) with y from 0 (neck cut) to 1 (top), counter-clockwise from
// the neck cut's +x end: up the face (x > 0), over the top, down the back of the head (x < 0). The last
// edge, back to the first point, is the neck cut.
constexpr std::array<std::array<double, 2>, 25> kFaceLandmarks = {{
    {0.10, 0.00},                                 // neck front, at the cut
    {0.12, 0.12},                                 // throat
    {0.18, 0.20},                                 // under the chin
    {0.30, 0.25},                                 // chin, lower edge
    {0.33, 0.30},                                 // chin point
    {0.30, 0.35},                                 // dent under the lower lip
    {0.34, 0.40},                                 // lower lip
    {0.32, 0.44},                                 // mouth
    {0.35, 0.48},                                 // upper lip
    {0.33, 0.53},                                 // under the nose
    {0.45, 0.56},                                 // nose tip
    {0.36, 0.66},                                 // nose bridge
    {0.34, 0.72},                                 // dent between nose and brow
    {0.37, 0.76},                                 // brow
    {0.34, 0.88},                                 // forehead
    {0.22, 0.96},                                 // top front
    {0.00, 1.00},                                 // top
    {-0.18, 0.97},                                // top back
    {-0.30, 0.88},                                // back of the head
    {-0.36, 0.75}, {-0.35, 0.60}, {-0.28, 0.45},  // nape
    {-0.15, 0.30}, {-0.10, 0.15},                 // neck back
    {-0.10, 0.00},                                // neck back, at the cut
}};

}  // namespace

SurfaceMesh makeBox(const Eigen::AlignedBox3d& box, int divisions) {
  constexpr const char* who = "makeBox";
  requireFinite(who, "box min corner", box.min());
  requireFinite(who, "box max corner", box.max());
  for (int a = 0; a < 3; ++a) {
    const double size = box.max()[a] - box.min()[a];
    if (!(size > 0) || !std::isfinite(size)) {
      fail(who, std::string("box size along ") + "xyz"[a] + " = " + formatNumber(size) +
                    " is not finite and > 0 (box " + formatPoint(Eigen::Vector3d(box.min())) + " - " +
                    formatPoint(Eigen::Vector3d(box.max())) + ")");
    }
  }
  requireAtLeast(who, "divisions", divisions, 1);
  const double nd = divisions;
  requireFaceBudget(who, 12 * nd * nd, "divisions = " + std::to_string(divisions));
  const int n = divisions;
  const long long m = n + 1;

  // Surface vertices of the (n + 1)^3 lattice, numbered as they are first met; -1 inside.
  std::unordered_map<long long, int> index;
  index.reserve(static_cast<std::size_t>(6 * n * n + 2));
  Builder out(who, 6LL * n * n + 2, 12LL * n * n);
  auto coordinate = [&](int a, int i) {
    // The last grid line is the max corner exactly, not min + n * step.
    return i == n ? box.max()[a]
                  : box.min()[a] + (box.max()[a] - box.min()[a]) * (static_cast<double>(i) / n);
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
    for (const int side : {0, n}) {
      for (int j = 0; j < n; ++j) {
        for (int k = 0; k < n; ++k) {
          std::array<int, 3> g00{}, g10{}, g11{}, g01{};
          g00[a] = g10[a] = g11[a] = g01[a] = side;
          g00[b] = j, g00[c] = k;
          g10[b] = j + 1, g10[c] = k;
          g11[b] = j + 1, g11[c] = k + 1;
          g01[b] = j, g01[c] = k + 1;
          if (side == n) {
            out.quad(vertex(g00), vertex(g10), vertex(g11), vertex(g01));
          } else {
            out.quad(vertex(g00), vertex(g01), vertex(g11), vertex(g10));
          }
        }
      }
    }
  }
  return out.finish();
}

SurfaceMesh makeCylinder(const Eigen::Vector3d& base_centre_m, const Eigen::Vector3d& axis_m, double radius_m,
                         int segments, int rings, int cap_rings) {
  constexpr const char* who = "makeCylinder";
  requireFinite(who, "base_centre_m", base_centre_m);
  requireFinite(who, "axis_m", axis_m);
  if (!(axis_m.norm() > 0) || !std::isfinite(axis_m.norm())) {
    fail(who, "axis_m = " + formatPoint(axis_m) + " has length " + formatNumber(axis_m.norm()) + ": must be finite and > 0");
  }
  requirePositive(who, "radius_m", radius_m);
  requireAtLeast(who, "segments", segments, 3);
  requireAtLeast(who, "rings", rings, 1);
  requireAtLeast(who, "cap_rings", cap_rings, 1);
  const double s = segments;
  requireFaceBudget(who, 2 * s * (static_cast<double>(rings) + 2.0 * cap_rings - 1),
                    "segments = " + std::to_string(segments) + ", rings = " + std::to_string(rings) +
                        ", cap_rings = " + std::to_string(cap_rings));

  const Eigen::Vector3d w = axis_m.normalized();
  const auto [u, v] = frameAround(w);
  std::vector<Eigen::Vector3d> direction(static_cast<std::size_t>(segments));
  for (int k = 0; k < segments; ++k) {
    const double angle = 2 * std::numbers::pi * k / segments;
    direction[static_cast<std::size_t>(k)] = std::cos(angle) * u + std::sin(angle) * v;
  }
  const long long S = segments;
  Builder out(who, S * (rings + 1 + 2LL * (cap_rings - 1)) + 2, 2 * S * (rings + 2LL * cap_rings - 1));
  auto centreAt = [&](int ring) {
    return ring == rings ? Eigen::Vector3d(base_centre_m + axis_m)
                         : Eigen::Vector3d(base_centre_m + (static_cast<double>(ring) / rings) * axis_m);
  };
  // Side: ring r, segment k at index r * S + k.
  for (int r = 0; r <= rings; ++r) {
    const Eigen::Vector3d centre = centreAt(r);
    for (int k = 0; k < segments; ++k) out.vertex(centre + radius_m * direction[static_cast<std::size_t>(k)]);
  }
  auto side = [&](int r, int k) { return static_cast<int>(r * S + (k % segments)); };
  // Going along k turns from u towards v, so (along k) x (along the axis) points outward.
  for (int r = 0; r < rings; ++r) {
    for (int k = 0; k < segments; ++k)
      out.quad(side(r, k), side(r, k + 1), side(r + 1, k + 1), side(r + 1, k));
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
      return c == cap_rings ? side(top ? rings : 0, k)
                            : first_inner + static_cast<int>((c - 1) * S + (k % segments));
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
  return out.finish();
}

SurfaceMesh makeSphere(const Eigen::Vector3d& centre_m, double radius_m, int subdivisions) {
  constexpr const char* who = "makeSphere";
  requireFinite(who, "centre_m", centre_m);
  requirePositive(who, "radius_m", radius_m);
  requireAtLeast(who, "subdivisions", subdivisions, 0);
  if (subdivisions > 10) {
    fail(who, "subdivisions = " + std::to_string(subdivisions) +
                  " is > 10 (20 * 4^subdivisions faces, at most " + std::to_string(kMaxShapeFaces) + ")");
  }
  const double t = std::numbers::phi;
  std::vector<Eigen::Vector3d> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                       {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                       {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
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
      const auto key =
          (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
      const auto [it, added] = midpoint.try_emplace(key, static_cast<int>(unit.size()));
      if (added)
        unit.push_back((unit[static_cast<std::size_t>(a)] + unit[static_cast<std::size_t>(b)]).normalized());
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

SurfaceMesh makePrism(const std::vector<Eigen::Vector2d>& outline_m, double z0_m, double z1_m, int rings) {
  constexpr const char* who = "makePrism";
  const int n = static_cast<int>(outline_m.size());
  if (outline_m.size() < 3)
    fail(who, "outline_m has " + std::to_string(outline_m.size()) + " points, needs >= 3");
  for (int i = 0; i < n; ++i) {
    if (!outline_m[static_cast<std::size_t>(i)].allFinite()) {
      fail(who, "outline point " + std::to_string(i) + " = " + formatPoint(outline_m[static_cast<std::size_t>(i)]) +
                    " is not finite");
    }
  }
  if (!std::isfinite(z0_m)) fail(who, "z0_m = " + formatNumber(z0_m) + " is not finite");
  if (!std::isfinite(z1_m)) fail(who, "z1_m = " + formatNumber(z1_m) + " is not finite");
  if (!(z1_m > z0_m))
    fail(who, "z1_m = " + formatNumber(z1_m) + " is not > z0_m = " + formatNumber(z0_m) + " (height must be > 0)");
  requireAtLeast(who, "rings", rings, 1);
  requireFaceBudget(who, 2.0 * n * rings + 2.0 * (n - 2),
                    std::to_string(n) + " outline points and rings = " + std::to_string(rings));

  std::vector<Point2> points;
  points.reserve(outline_m.size());
  for (const auto& p : outline_m) points.emplace_back(p.x(), p.y());
  requireSimple(who, points);
  double twice_area = 0;
  for (int i = 0; i < n; ++i) {
    const auto& p = outline_m[static_cast<std::size_t>(i)];
    const auto& q = outline_m[static_cast<std::size_t>((i + 1) % n)];
    twice_area += p.x() * q.y() - q.x() * p.y();
  }
  if (!(twice_area != 0)) fail(who, "outline_m has zero area");
  // Counter-clockwise from here on; the caps' triangles index this order.
  if (twice_area < 0) std::reverse(points.begin(), points.end());
  const std::vector<std::array<int, 3>> cap = triangulatePolygon(who, points);

  Builder out(who, static_cast<long long>(n) * (rings + 1), 2LL * n * rings + 2LL * (n - 2));
  for (int k = 0; k <= rings; ++k) {
    const double z = k == rings ? z1_m : z0_m + (z1_m - z0_m) * (static_cast<double>(k) / rings);
    for (const auto& p : points) out.vertex({p.x(), p.y(), z});
  }
  auto at = [&](int k, int i) { return k * n + i % n; };
  // Counter-clockwise outline: (along the edge) x (+z) points out of the polygon.
  for (int k = 0; k < rings; ++k) {
    for (int i = 0; i < n; ++i) out.quad(at(k, i), at(k, i + 1), at(k + 1, i + 1), at(k + 1, i));
  }
  for (const auto& [a, b, c] : cap) out.triangle(at(0, a), at(0, c), at(0, b));  // bottom faces -z
  for (const auto& [a, b, c] : cap) out.triangle(at(rings, a), at(rings, b), at(rings, c));
  return out.finish();
}

std::vector<Eigen::Vector2d> faceSilhouette(double height_m, int points) {
  constexpr const char* who = "faceSilhouette";
  requirePositive(who, "height_m", height_m);
  constexpr int landmarks = static_cast<int>(kFaceLandmarks.size());
  requireAtLeast(who, "points", points, landmarks);
  if (points > 1'000'000) fail(who, "points = " + std::to_string(points) + " is > 1000000");

  // Extra points per edge, by length, largest remainder first (lowest edge on ties); none on the neck cut.
  constexpr int edges = landmarks - 1;
  std::array<double, edges> length{};
  double total = 0;
  for (int e = 0; e < edges; ++e) {
    const auto& a = kFaceLandmarks[static_cast<std::size_t>(e)];
    const auto& b = kFaceLandmarks[static_cast<std::size_t>(e + 1)];
    length[static_cast<std::size_t>(e)] = std::hypot(b[0] - a[0], b[1] - a[1]);
    total += length[static_cast<std::size_t>(e)];
  }
  const int extra = points - landmarks;
  std::array<int, edges> count{};
  std::array<double, edges> remainder{};
  int given = 0;
  for (int e = 0; e < edges; ++e) {
    const double share = extra * length[static_cast<std::size_t>(e)] / total;
    count[static_cast<std::size_t>(e)] = static_cast<int>(std::floor(share));
    remainder[static_cast<std::size_t>(e)] = share - count[static_cast<std::size_t>(e)];
    given += count[static_cast<std::size_t>(e)];
  }
  std::array<int, edges> by_remainder{};
  for (int e = 0; e < edges; ++e) by_remainder[static_cast<std::size_t>(e)] = e;
  std::stable_sort(by_remainder.begin(), by_remainder.end(), [&](int a, int b) {
    return remainder[static_cast<std::size_t>(a)] > remainder[static_cast<std::size_t>(b)];
  });
  for (int r = 0; given < extra; ++r, ++given)
    ++count[static_cast<std::size_t>(by_remainder[static_cast<std::size_t>(r % edges)])];

  // Landmark y in [0, 1] maps to [-h/2, h/2]; the neck cut and the top land exactly on the ends.
  auto place = [&](double x, double y) { return Eigen::Vector2d(x * height_m, (y - 0.5) * height_m); };
  std::vector<Eigen::Vector2d> outline;
  outline.reserve(static_cast<std::size_t>(points));
  for (int e = 0; e < landmarks; ++e) {
    const auto& a = kFaceLandmarks[static_cast<std::size_t>(e)];
    outline.push_back(place(a[0], a[1]));
    if (e == edges) break;
    const auto& b = kFaceLandmarks[static_cast<std::size_t>(e + 1)];
    const int k = count[static_cast<std::size_t>(e)];
    for (int j = 1; j <= k; ++j) {
      const double t = static_cast<double>(j) / (k + 1);
      outline.push_back(place(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])));
    }
  }
  return outline;
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
  const int segments = 12 * d;
  auto upright = [&](double x, double z0, double z1, double radius, int rings) {
    return makeCylinder({x * h, 0, z0 * h}, {0, 0, (z1 - z0) * h}, radius * h, segments, rings, d);
  };
  auto box = [&](double half_x, double half_y, double z0, double z1, int divisions) {
    return makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(-half_x * h, -half_y * h, z0 * h),
                                       Eigen::Vector3d(half_x * h, half_y * h, z1 * h)),
                   divisions);
  };
  std::vector<SurfaceMesh> parts;
  parts.push_back(upright(-0.10, 0.00, 0.45, 0.07, 6 * d));  // legs
  parts.push_back(upright(0.10, 0.00, 0.45, 0.07, 6 * d));
  parts.push_back(box(0.20, 0.10, 0.46, 0.80, 4 * d));       // torso
  parts.push_back(upright(-0.27, 0.42, 0.78, 0.05, 5 * d));  // arms
  parts.push_back(upright(0.27, 0.42, 0.78, 0.05, 5 * d));
  parts.push_back(upright(0.00, 0.81, 0.85, 0.04, d));  // neck
  parts.push_back(box(0.09, 0.09, 0.86, 1.00, 2 * d));  // head
  return merge(parts);
}

}  // namespace incise::cutting
