// Prisms (shapes.h: makePrism, an outline extruded along z, its caps triangulated by CGAL's constrained
// Delaunay triangulation after an exact simplicity check of the outline; both O(n log n) expected) and the
// face silhouette outline they are made from in the scenes. Compiled with CGAL (incise_cutting_cgal).
#include "incise/mesh/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <deque>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/box_intersection_d.h>

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
      fail(who, "outline points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) + " coincide (edge " +
                    std::to_string(i) + " has zero length)");
    }
  }
  std::pair<int, int> worst{n, n};
  auto report = [&](int i, int j) { worst = std::min(worst, std::pair<int, int>(std::min(i, j), std::max(i, j))); };
  // Consecutive edges i - 1 and i meet at point i: they overlap when they are collinear and turn back.
  for (int i = 0; i < n; ++i) {
    const Point2& a = p[static_cast<std::size_t>((i + n - 1) % n)];
    const Point2& b = p[static_cast<std::size_t>(i)];
    const Point2& c = p[static_cast<std::size_t>((i + 1) % n)];
    if (CGAL::orientation(a, b, c) == CGAL::COLLINEAR && CGAL::angle(a, b, c) == CGAL::ACUTE)
      report((i + n - 1) % n, i);
  }
  // Non-consecutive edges: the pairs whose bounding boxes meet (CGAL's box intersection, O(n log n + pairs)),
  // then the exact test on those. A plain x sweep would be O(k^2) on a vertical run of k edges.
  std::vector<Segment2> edges;
  edges.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    edges.emplace_back(p[static_cast<std::size_t>(i)], p[static_cast<std::size_t>((i + 1) % n)]);
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, int>;
  std::vector<Box> boxes;
  boxes.reserve(edges.size());
  for (int i = 0; i < n; ++i) boxes.emplace_back(edges[static_cast<std::size_t>(i)].bbox(), i);
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    const int i = a.info(), j = b.info(), gap = std::abs(i - j);
    if (gap == 1 || gap == n - 1) return;  // consecutive: checked above
    if (CGAL::do_intersect(edges[static_cast<std::size_t>(i)], edges[static_cast<std::size_t>(j)])) report(i, j);
  });
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
  // All points at once: CGAL sorts them spatially first. Inserted one by one in outline order, the points of
  // a finely resampled outline (long runs of collinear points) cost O(n) flips each: 0.8 s for 16,015 points
  // in Release, 85 s under the fuzzers' ASan build (a libFuzzer timeout).
  std::vector<std::pair<Point2, int>> indexed;
  indexed.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) indexed.emplace_back(p[i], static_cast<int>(i));
  Cdt cdt;
  cdt.insert(indexed.begin(), indexed.end());
  std::vector<Cdt::Vertex_handle> handle(p.size());
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    handle[static_cast<std::size_t>(v->info())] = v;
  // requireSimple ruled out repeated points and crossings, so every point is a vertex and the constraints
  // add none; checked anyway (before and after).
  auto requireVertexPerPoint = [&] {
    if (cdt.number_of_vertices() == p.size()) return;
    throw std::logic_error(std::string(who) + ": the cap triangulation has " +
                           std::to_string(cdt.number_of_vertices()) + " vertices for " + std::to_string(p.size()) +
                           " outline points");
  };
  requireVertexPerPoint();
  for (std::size_t i = 0; i < p.size(); ++i) cdt.insert_constraint(handle[i], handle[(i + 1) % p.size()]);
  requireVertexPerPoint();
  markNestingLevels(cdt);
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(p.size() - 2);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 == 1) triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  if (triangles.size() != p.size() - 2) {
    throw std::logic_error(std::string(who) + ": the cap triangulation has " + std::to_string(triangles.size()) +
                           " triangles inside the outline, expected " + std::to_string(p.size() - 2));
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

SurfaceMesh makePrism(const std::vector<Eigen::Vector2d>& outline_m, double z0_m, double z1_m, int rings) {
  constexpr const char* who = "makePrism";
  const int n = static_cast<int>(outline_m.size());
  if (outline_m.size() < 3) fail(who, "outline_m has " + std::to_string(outline_m.size()) + " points, needs >= 3");
  for (int i = 0; i < n; ++i) {
    if (!outline_m[static_cast<std::size_t>(i)].allFinite()) {
      fail(who, "outline point " + std::to_string(i) + " = " +
                    core::formatPoint(outline_m[static_cast<std::size_t>(i)]) + " is not finite");
    }
  }
  if (!std::isfinite(z0_m)) fail(who, "z0_m = " + core::formatNumber(z0_m) + " is not finite");
  if (!std::isfinite(z1_m)) fail(who, "z1_m = " + core::formatNumber(z1_m) + " is not finite");
  if (!(z1_m > z0_m))
    fail(who, "z1_m = " + core::formatNumber(z1_m) + " is not > z0_m = " + core::formatNumber(z0_m) +
                  " (height must be > 0)");
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

}  // namespace incise::mesh
