// The capped treatment (paper §3.2, first method): the model split at every discontinuity, its lips welded
// where F leaves the two sides together, and each opening closed by two caps made of the model's section
// at the plane, restricted to where F separates the sides. On a plane u = u_i, F- and F+ differ exactly in
// the knot cells (v, w) in which a control of F's support moved (the region R); on R's boundary and beyond
// it they are both the identity. So the section S (bounded by the split's lips, at rest) is triangulated
// with R's boundary as constraints (CGAL's constrained Delaunay triangulation, with points inside so that
// the caps bend with F), and the triangles of S inside R are mapped through F- (the - side's cap) and F+
// (the + side's). Both caps meet along R's boundary, where their vertices are shared; a lip edge that R's
// boundary crosses is split there (its faces fanned). Where F does not separate the sides there is no
// cap, so no two caps lie face to face. CGAL types stay in this file.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <queue>
#include <set>
#include <string>
#include <vector>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "global_dffd_internal.h"
#include "incise/core/format.h"
#include "incise/global_dffd/global_dffd.h"

namespace incise::global_dffd {

namespace {

struct VertexMark {
  int id = -1;  // the cap point, -1 for a point CGAL made (constraints crossing where none was expected)
};
struct FaceMark {
  int inside = -1;   // 1 in the section, 0 outside, -1 not yet known
  bool cap = false;  // in the section and in R
};
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexMark, Kernel>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceMark, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Vertex = Cdt::Vertex_handle;
using Face = Cdt::Face_handle;

using Edge2 = std::pair<int, int>;  // cap points, smaller first

Edge2 edgeOf(int a, int b) { return a < b ? Edge2{a, b} : Edge2{b, a}; }

[[noreturn]] void fail(int plane, const std::string& why) {
  throw DffdError(DffdErrorKind::NotTwoManifold, "capping the opening at plane " + std::to_string(plane) + ": " + why);
}

// The plane's knot cells in (v, w) = (y, z) and which of them F separates (a control of the support of
// F- or F+ moved).
struct Cells {
  std::vector<double> v, w;  // distinct knots of the domain, increasing
  std::vector<char> moved;   // per cell (j, k), j fastest
  char at(int j, int k) const {
    const int nv = static_cast<int>(v.size()) - 1, nw = static_cast<int>(w.size()) - 1;
    if (j < 0 || k < 0 || j >= nv || k >= nw) return 0;
    return moved[static_cast<size_t>(j + nv * k)];
  }
  // The cell holding (y, z), or -1 in a coordinate outside the domain.
  static int span(const std::vector<double>& knots, double t) {
    if (!(t >= knots.front() && t <= knots.back())) return -1;
    const auto it = std::upper_bound(knots.begin(), knots.end(), t);
    return std::min(static_cast<int>(it - knots.begin()) - 1, static_cast<int>(knots.size()) - 2);
  }
  bool movedAt(const Eigen::Vector2d& p) const { return at(span(v, p.x()), span(w, p.y())); }
};

std::vector<double> distinctKnots(const bspline::BSplineVolume& volume, int axis) {
  const auto domain = volume.domain(axis);
  std::vector<double> out;
  for (const double t : volume.knots(axis))
    if (t >= domain[0] && t <= domain[1] && (out.empty() || t > out.back())) out.push_back(t);
  return out;
}

Cells cellsOf(const GlobalDffd& dffd, double u) {
  Cells c;
  c.v = distinctKnots(dffd.volume(), 1);
  c.w = distinctKnots(dffd.volume(), 2);
  const size_t nv = c.v.size() - 1, nw = c.w.size() - 1;
  c.moved.assign(nv * nw, 0);
  double clamped = 0.0;
  for (size_t k = 0; k < nw; ++k)
    for (size_t j = 0; j < nv; ++j) {
      const Eigen::Vector3d centre(u, 0.5 * (c.v[j] + c.v[j + 1]), 0.5 * (c.w[k] + c.w[k + 1]));
      c.moved[j + nv * k] =
          !dffd.identityCell(dffd.cellOf(centre, -1, clamped)) || !dffd.identityCell(dffd.cellOf(centre, 1, clamped));
    }
  return c;
}

// A piece of R's boundary: the line y = c (axis 0) or z = c (axis 1) from lo to hi along the other axis.
struct Segment {
  int axis = 0;
  double c = 0.0, lo = 0.0, hi = 0.0;
};

std::vector<Segment> boundaryOf(const Cells& cells) {
  std::vector<Segment> out;
  const int nv = static_cast<int>(cells.v.size()) - 1, nw = static_cast<int>(cells.w.size()) - 1;
  for (int k = 0; k < nw; ++k)
    for (int j = 0; j <= nv; ++j)
      if (cells.at(j - 1, k) != cells.at(j, k))
        out.push_back(
            {0, cells.v[static_cast<size_t>(j)], cells.w[static_cast<size_t>(k)], cells.w[static_cast<size_t>(k) + 1]});
  for (int j = 0; j < nv; ++j)
    for (int k = 0; k <= nw; ++k)
      if (cells.at(j, k - 1) != cells.at(j, k))
        out.push_back(
            {1, cells.w[static_cast<size_t>(k)], cells.v[static_cast<size_t>(j)], cells.v[static_cast<size_t>(j) + 1]});
  return out;
}

// One plane's cap: its points at rest on the plane, the - side's lip edges and the triangulation.
struct Cap {
  int plane = 0;
  double u = 0.0;
  std::vector<Eigen::Vector2d> at;  // per cap point: (y, z)
  std::vector<int> lip;             // per cap point: the - side's split vertex, or -1
  std::vector<int> on_edge;         // per cap point on a lip edge's inside: that edge, else -1
  std::vector<double> t;            // its parameter along that edge
  std::map<std::pair<double, double>, int> by_place;
  std::vector<std::array<int, 2>> edges;         // lip edges a -> b (the - side's boundary), split vertices
  std::vector<std::vector<int>> along;           // per lip edge: the cap points on its inside, from a to b
  std::set<Edge2> lip_pieces;                    // the lip edges' pieces between consecutive points
  std::vector<std::pair<int, int>> pieces_of_r;  // R's boundary between consecutive points
  std::vector<char> shared;                      // per cap point: one vertex for both caps (not inside R)
  std::vector<std::array<int, 3>> faces;         // the caps' triangles, counter-clockwise in (y, z)

  int add(const Eigen::Vector2d& p, int lip_vertex, int edge = -1, double along_t = 0.0) {
    const auto [it, fresh] = by_place.try_emplace({p.x(), p.y()}, static_cast<int>(at.size()));
    if (!fresh) return it->second;
    at.push_back(p);
    lip.push_back(lip_vertex);
    on_edge.push_back(edge);
    t.push_back(along_t);
    return it->second;
  }
  Eigen::Vector3d rest(int point) const {
    return {u, at[static_cast<size_t>(point)].x(), at[static_cast<size_t>(point)].y()};
  }
};

Eigen::Vector2d yz(const Eigen::Vector3d& x) { return {x.y(), x.z()}; }

// The - side's boundary edges on `plane` (a -> b: no face has b -> a), both ends on it.
std::vector<std::array<int, 2>> lipEdges(const DffdSplit& split, int plane) {
  std::set<std::pair<int, int>> directed;
  for (const auto& f : split.faces)
    for (size_t i = 0; i < 3; ++i) directed.insert({f[i], f[(i + 1) % 3]});
  std::vector<std::array<int, 2>> out;
  for (const auto& [a, b] : directed) {
    const auto on = [&](int v) {
      return split.plane[static_cast<size_t>(v)] == plane && split.side[static_cast<size_t>(v)] < 0;
    };
    if (on(a) && on(b) && !directed.count({b, a})) out.push_back({a, b});
  }
  return out;
}

// Where lip edge e crosses R's boundary: points added on it (at their parameter), and each boundary
// segment's points (its ends, the crossings, lip vertices on it) collected for the constraints.
void crossings(Cap& cap, const DffdSplit& split, const std::vector<Segment>& boundary,
               std::vector<std::vector<std::pair<double, int>>>& on_segment) {
  for (size_t e = 0; e < cap.edges.size(); ++e) {
    const auto [a, b] = cap.edges[e];
    const Eigen::Vector2d pa = yz(split.rest_m[static_cast<size_t>(a)]), pb = yz(split.rest_m[static_cast<size_t>(b)]);
    const int ia = cap.add(pa, a), ib = cap.add(pb, b);
    for (size_t s = 0; s < boundary.size(); ++s) {
      const Segment& g = boundary[s];
      const int x = g.axis, y = 1 - g.axis;
      const double da = pa[x] - g.c, db = pb[x] - g.c;
      if (da == 0.0 && pa[y] >= g.lo && pa[y] <= g.hi) on_segment[s].push_back({pa[y], ia});
      if (db == 0.0 && pb[y] >= g.lo && pb[y] <= g.hi) on_segment[s].push_back({pb[y], ib});
      if (!(da * db < 0.0)) continue;
      const double t = da / (da - db);
      Eigen::Vector2d p = pa + t * (pb - pa);
      p[x] = g.c;
      if (!(p[y] >= g.lo && p[y] <= g.hi)) continue;
      const int id = cap.add(p, -1, static_cast<int>(e), t);
      on_segment[s].push_back({p[y], id});
    }
  }
}

// The lip edges' points in order along each edge.
void orderAlong(Cap& cap) {
  cap.along.assign(cap.edges.size(), {});
  for (size_t p = 0; p < cap.at.size(); ++p)
    if (cap.on_edge[p] >= 0) cap.along[static_cast<size_t>(cap.on_edge[p])].push_back(static_cast<int>(p));
  for (auto& list : cap.along)
    std::sort(list.begin(), list.end(),
              [&](int l, int r) { return cap.t[static_cast<size_t>(l)] < cap.t[static_cast<size_t>(r)]; });
}

// Every point of the cap and every constraint (the lip edges' pieces, R's boundary's) in a fresh
// triangulation; `vertex` gets each point's handle.
void triangulate(Cap& cap, const DffdSplit& split, Cdt& cdt, std::vector<Vertex>& vertex) {
  vertex.resize(cap.at.size());
  for (size_t p = 0; p < cap.at.size(); ++p) {
    vertex[p] = cdt.insert(Kernel::Point_2(cap.at[p].x(), cap.at[p].y()));
    vertex[p]->info().id = static_cast<int>(p);
  }
  cap.lip_pieces.clear();
  for (size_t e = 0; e < cap.edges.size(); ++e) {
    std::vector<int> chain{cap.by_place.at({split.rest_m[static_cast<size_t>(cap.edges[e][0])].y(),
                                            split.rest_m[static_cast<size_t>(cap.edges[e][0])].z()})};
    chain.insert(chain.end(), cap.along[e].begin(), cap.along[e].end());
    chain.push_back(cap.by_place.at({split.rest_m[static_cast<size_t>(cap.edges[e][1])].y(),
                                     split.rest_m[static_cast<size_t>(cap.edges[e][1])].z()}));
    for (size_t i = 1; i < chain.size(); ++i) {
      cdt.insert_constraint(vertex[static_cast<size_t>(chain[i - 1])], vertex[static_cast<size_t>(chain[i])]);
      cap.lip_pieces.insert(edgeOf(chain[i - 1], chain[i]));
    }
  }
  for (const auto& [a, b] : cap.pieces_of_r)
    cdt.insert_constraint(vertex[static_cast<size_t>(a)], vertex[static_cast<size_t>(b)]);
}

// R's boundary segments as constraints between consecutive points (their ends added as cap points).
void boundaryPieces(Cap& cap, const std::vector<Segment>& boundary,
                    std::vector<std::vector<std::pair<double, int>>>& on_segment) {
  for (size_t s = 0; s < boundary.size(); ++s) {
    const Segment& g = boundary[s];
    const auto point = [&](double along) {
      Eigen::Vector2d p;
      p[g.axis] = g.c;
      p[1 - g.axis] = along;
      return p;
    };
    auto& list = on_segment[s];
    list.push_back({g.lo, cap.add(point(g.lo), -1)});
    list.push_back({g.hi, cap.add(point(g.hi), -1)});
    std::sort(list.begin(), list.end());
    for (size_t i = 1; i < list.size(); ++i)
      if (list[i].second != list[i - 1].second) cap.pieces_of_r.push_back({list[i - 1].second, list[i].second});
  }
}

bool isLipPiece(const Cap& cap, const Face& f, int i) {
  const int a = f->vertex(Cdt::cw(i))->info().id, b = f->vertex(Cdt::ccw(i))->info().id;
  return cap.lip_pieces.count(edgeOf(a, b)) > 0;
}

// Which faces lie in the section: reached from outside, each lip piece crossed toggles in and out.
void markSection(const Cap& cap, Cdt& cdt) {
  for (const Face f : cdt.all_face_handles()) f->info() = FaceMark{};
  std::queue<Face> queue;
  cdt.infinite_face()->info().inside = 0;
  queue.push(cdt.infinite_face());
  while (!queue.empty()) {
    const Face f = queue.front();
    queue.pop();
    for (int i = 0; i < 3; ++i) {
      const Face g = f->neighbor(i);
      if (g->info().inside >= 0) continue;
      g->info().inside = isLipPiece(cap, f, i) ? 1 - f->info().inside : f->info().inside;
      queue.push(g);
    }
  }
}

// Every triangulation vertex is a cap point (no crossing the constraints did not foresee) and every lip
// piece an edge.
void checkTriangulation(const Cap& cap, const Cdt& cdt, const std::vector<Vertex>& vertex) {
  for (const Vertex v : cdt.finite_vertex_handles())
    if (v->info().id < 0)
      fail(cap.plane, "the section's edges cross each other near (y, z) = (" + core::formatNumber(v->point().x()) +
                          ", " + core::formatNumber(v->point().y()) + ")");
  for (const auto& [a, b] : cap.lip_pieces)
    if (!cdt.is_edge(vertex[static_cast<size_t>(a)], vertex[static_cast<size_t>(b)]))
      fail(cap.plane, "a lip edge at cap point " + std::to_string(a) + " is not in the triangulation");
}

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double length2 = d.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(d) / length2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

// Points inside the section where F separates the sides, about as far apart as the lip's points (at most
// 8 x 8 a cell), none nearer a lip edge than half that: the caps bend with F between them.
std::vector<Eigen::Vector2d> innerPoints(const Cap& cap, const Cells& cells, const DffdSplit& split, Cdt& cdt) {
  double length = 0.0;
  for (const auto& [a, b] : cap.edges)
    length += (split.rest_m[static_cast<size_t>(a)] - split.rest_m[static_cast<size_t>(b)]).norm();
  const double spacing = length / std::max<size_t>(1, cap.edges.size());
  std::vector<Eigen::Vector2d> out;
  if (!(spacing > 0.0)) return out;
  for (size_t k = 0; k + 1 < cells.w.size(); ++k)
    for (size_t j = 0; j + 1 < cells.v.size(); ++j) {
      if (!cells.at(static_cast<int>(j), static_cast<int>(k))) continue;
      const double dv = cells.v[j + 1] - cells.v[j], dw = cells.w[k + 1] - cells.w[k];
      const int nv = std::clamp(static_cast<int>(std::ceil(dv / spacing)), 1, 8);
      const int nw = std::clamp(static_cast<int>(std::ceil(dw / spacing)), 1, 8);
      for (int b = 0; b < nw; ++b)
        for (int a = 0; a < nv; ++a) {
          const Eigen::Vector2d p(cells.v[j] + (a + 0.5) / nv * dv, cells.w[k] + (b + 0.5) / nw * dw);
          const Face f = cdt.locate(Kernel::Point_2(p.x(), p.y()));
          if (cdt.is_infinite(f) || f->info().inside != 1) continue;
          bool clear = true;
          for (size_t e = 0; clear && e < cap.edges.size(); ++e)
            clear = distanceToSegment(p, yz(split.rest_m[static_cast<size_t>(cap.edges[e][0])]),
                                      yz(split.rest_m[static_cast<size_t>(cap.edges[e][1])])) >=
                    0.5 * std::min(dv / nv, dw / nw);
          if (clear) out.push_back(p);
        }
    }
  return out;
}

// Faces of the section inside R are the caps'; a point is shared by both caps unless every face of the
// section around it is a cap face (it lies inside R).
void markCaps(Cap& cap, const Cells& cells, Cdt& cdt) {
  for (const Face f : cdt.finite_face_handles()) {
    if (f->info().inside != 1) continue;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (int i = 0; i < 3; ++i) centre += Eigen::Vector2d(f->vertex(i)->point().x(), f->vertex(i)->point().y()) / 3.0;
    f->info().cap = cells.movedAt(centre);
  }
  cap.shared.assign(cap.at.size(), 1);
  for (const Vertex v : cdt.finite_vertex_handles()) {
    bool all = true, any = false;
    auto f = cdt.incident_faces(v);
    const auto done = f;
    do {
      if (!cdt.is_infinite(f) && f->info().inside == 1) all = all && f->info().cap, any = any || f->info().cap;
    } while (++f != done);
    cap.shared[static_cast<size_t>(v->info().id)] = !(all && any);
  }
}

// The lip edge a lip piece between cap points a and b lies on.
int edgeBetween(const Cap& cap, int a, int b) {
  for (const int p : {a, b})
    if (cap.on_edge[static_cast<size_t>(p)] >= 0) return cap.on_edge[static_cast<size_t>(p)];
  const int la = cap.lip[static_cast<size_t>(a)], lb = cap.lip[static_cast<size_t>(b)];
  for (size_t e = 0; e < cap.edges.size(); ++e)
    if ((cap.edges[e][0] == la && cap.edges[e][1] == lb) || (cap.edges[e][0] == lb && cap.edges[e][1] == la))
      return static_cast<int>(e);
  fail(cap.plane, "no lip edge joins cap points " + std::to_string(a) + " and " + std::to_string(b));
}

// An edge with both ends shared and a cap face on each side (or a cap face and the outside: a lip piece)
// would be used by both caps and, for a lip piece, both sides: such an edge gets its midpoint (a cap point;
// on a lip piece, on its lip edge), which lies inside R. Returns whether any was added (the caller
// triangulates again).
bool splitSharedEdges(Cap& cap, const DffdSplit& split, const Cdt& cdt) {
  std::vector<std::pair<int, int>> inner, lips;
  for (const auto& e : cdt.finite_edges()) {
    const Face f = e.first, g = f->neighbor(e.second);
    const int a = f->vertex(Cdt::cw(e.second))->info().id, b = f->vertex(Cdt::ccw(e.second))->info().id;
    if (!cap.shared[static_cast<size_t>(a)] || !cap.shared[static_cast<size_t>(b)]) continue;
    const bool cf = f->info().cap, cg = !cdt.is_infinite(g) && g->info().cap;
    const bool lip = cap.lip_pieces.count(edgeOf(a, b)) > 0;
    if (lip && (cf || cg)) lips.push_back({a, b});
    if (!lip && cf && cg) inner.push_back({a, b});
  }
  for (const auto& [a, b] : inner) cap.add(0.5 * (cap.at[static_cast<size_t>(a)] + cap.at[static_cast<size_t>(b)]), -1);
  for (const auto& [a, b] : lips) {  // on the lip edge both lie on, halfway between them
    const int e = edgeBetween(cap, a, b);
    const auto along = [&](int p) {
      return cap.on_edge[static_cast<size_t>(p)] == e                                  ? cap.t[static_cast<size_t>(p)]
             : cap.lip[static_cast<size_t>(p)] == cap.edges[static_cast<size_t>(e)][0] ? 0.0
                                                                                       : 1.0;
    };
    const double t = 0.5 * (along(a) + along(b));
    const Eigen::Vector2d pa = yz(split.rest_m[static_cast<size_t>(cap.edges[static_cast<size_t>(e)][0])]);
    const Eigen::Vector2d pb = yz(split.rest_m[static_cast<size_t>(cap.edges[static_cast<size_t>(e)][1])]);
    cap.add(pa + t * (pb - pa), -1, e, t);
  }
  return !inner.empty() || !lips.empty();
}

// One plane's cap: the section's lips, R's boundary and the points inside as a constrained Delaunay
// triangulation, marked until no edge would be used twice by the two caps (a few rounds at most).
Cap capOf(const DffdSplit& split, const GlobalDffd& dffd, int plane) {
  Cap cap;
  cap.plane = plane;
  cap.u = dffd.obstacles()[static_cast<size_t>(plane)].u;
  cap.edges = lipEdges(split, plane);
  if (cap.edges.empty()) return cap;
  const Cells cells = cellsOf(dffd, cap.u);
  const std::vector<Segment> boundary = boundaryOf(cells);
  std::vector<std::vector<std::pair<double, int>>> on_segment(boundary.size());
  crossings(cap, split, boundary, on_segment);
  boundaryPieces(cap, boundary, on_segment);
  for (int round = 0; round < 8; ++round) {
    orderAlong(cap);
    Cdt cdt;
    std::vector<Vertex> vertex;
    triangulate(cap, split, cdt, vertex);
    checkTriangulation(cap, cdt, vertex);
    markSection(cap, cdt);
    if (round == 0) {
      for (const Eigen::Vector2d& p : innerPoints(cap, cells, split, cdt)) {
        const int id = cap.add(p, -1);
        if (static_cast<size_t>(id) + 1 == cap.at.size()) cdt.insert(Kernel::Point_2(p.x(), p.y()))->info().id = id;
      }
      markSection(cap, cdt);
    }
    markCaps(cap, cells, cdt);
    if (splitSharedEdges(cap, split, cdt)) continue;
    for (const Face f : cdt.finite_face_handles())
      if (f->info().cap)
        cap.faces.push_back({f->vertex(0)->info().id, f->vertex(1)->info().id, f->vertex(2)->info().id});
    return cap;
  }
  fail(plane, "edges shared by both caps remain after 8 rounds of splitting");
}

// The capped model as index arrays: the split's vertices (deformed; a lip vertex shared by both caps is
// one vertex) and the caps' new ones, the split's faces (those along a lip edge with points on it fanned)
// and the caps'.
struct Assembly {
  std::vector<Eigen::Vector3d> x;
  std::vector<std::array<int, 3>> faces;
  std::vector<std::array<Eigen::Vector2d, 3>> uv;  // per face, when the split has texture coordinates
  std::vector<int> material;                       // per face, when the split has materials
  std::vector<char> wall;                          // per face: a cap face
  std::vector<int> index;                          // per split vertex: its vertex in x
  void add(const std::array<int, 3>& f, const std::array<Eigen::Vector2d, 3>& corners_uv, int face_material, bool cap) {
    faces.push_back(f);
    uv.push_back(corners_uv);
    material.push_back(face_material);
    wall.push_back(cap);
  }
};

// The split's vertices: a + side vertex whose twin is shared by the caps (or has the same image where no
// cap reaches) is its twin's vertex.
void placeVertices(const DffdSplit& split, const std::vector<int>& twin, std::span<const Eigen::Vector3d> positions,
                   const std::vector<Cap>& caps, Assembly& out) {
  std::vector<char> weld(split.rest_m.size(), 0);
  for (size_t v = 0; v < weld.size(); ++v)
    weld[v] = split.side[v] < 0 && twin[v] >= 0 && positions[v] == positions[static_cast<size_t>(twin[v])];
  for (const Cap& cap : caps)
    for (size_t p = 0; p < cap.at.size(); ++p)
      if (cap.lip[p] >= 0) weld[static_cast<size_t>(cap.lip[p])] = cap.shared[p];
  out.index.assign(split.rest_m.size(), -1);
  for (size_t v = 0; v < weld.size(); ++v) {
    if (split.side[v] > 0 && twin[v] >= 0 && weld[static_cast<size_t>(twin[v])]) continue;
    out.index[v] = static_cast<int>(out.x.size());
    out.x.push_back(positions[v]);
  }
  for (size_t v = 0; v < weld.size(); ++v)
    if (out.index[v] < 0) out.index[v] = out.index[static_cast<size_t>(twin[v])];
}

// Each cap point's vertex on the - and + side: a lip vertex's (or its twin's), else a new one, one for both
// sides where it is shared (at rest: F is the identity there), else F-'s and F+'s images; -1 for a point
// no face uses (R's boundary beyond the section).
std::vector<std::array<int, 2>> capVertices(const Cap& cap, const std::vector<int>& twin, const GlobalDffd& dffd,
                                            Assembly& out) {
  std::vector<char> used(cap.at.size(), 0);  // by a cap face or on a lip edge (its faces fanned)
  for (const auto& f : cap.faces)
    for (const int p : f) used[static_cast<size_t>(p)] = 1;
  for (const auto& chain : cap.along)
    for (const int p : chain) used[static_cast<size_t>(p)] = 1;
  std::vector<std::array<int, 2>> sides(cap.at.size(), {-1, -1});
  for (size_t p = 0; p < cap.at.size(); ++p) {
    if (!used[p]) continue;
    const int v = cap.lip[p];
    if (v >= 0) {
      if (twin[static_cast<size_t>(v)] < 0) fail(cap.plane, "lip vertex " + std::to_string(v) + " has no twin");
      sides[p] = {out.index[static_cast<size_t>(v)], out.index[static_cast<size_t>(twin[static_cast<size_t>(v)])]};
      continue;
    }
    const Eigen::Vector3d x = cap.rest(static_cast<int>(p));
    sides[p][0] = static_cast<int>(out.x.size());
    out.x.push_back(cap.shared[p] ? x : dffd.map(x, -1));
    sides[p][1] = cap.shared[p] ? sides[p][0] : static_cast<int>(out.x.size());
    if (!cap.shared[p]) out.x.push_back(dffd.map(x, 1));
  }
  return sides;
}

// Where a lip edge's points go: per directed edge of the split (the - side's a -> b, the + side's twin
// b -> twin a), its cap, lip edge and side.
struct LipEdgeRef {
  int cap = 0, edge = 0, side = 0;
};
std::map<std::pair<int, int>, LipEdgeRef> lipEdgeRefs(const std::vector<Cap>& caps, const std::vector<int>& twin) {
  std::map<std::pair<int, int>, LipEdgeRef> out;
  for (size_t c = 0; c < caps.size(); ++c)
    for (size_t e = 0; e < caps[c].edges.size(); ++e) {
      if (caps[c].along[e].empty()) continue;
      const auto [a, b] = caps[c].edges[e];
      out[{a, b}] = {static_cast<int>(c), static_cast<int>(e), 0};
      out[{twin[static_cast<size_t>(b)], twin[static_cast<size_t>(a)]}] = {static_cast<int>(c), static_cast<int>(e), 1};
    }
  return out;
}

// The split's faces; one along a lip edge with points on it becomes a fan from its third vertex.
void modelFaces(const DffdSplit& split, const std::vector<int>& twin, const std::vector<Cap>& caps,
                const std::vector<std::vector<std::array<int, 2>>>& sides, Assembly& out) {
  const auto refs = lipEdgeRefs(caps, twin);
  for (size_t f = 0; f < split.faces.size(); ++f) {
    std::array<int, 3> t = split.faces[f];
    std::array<Eigen::Vector2d, 3> uv = split.face_uv.empty() ? std::array<Eigen::Vector2d, 3>{} : split.face_uv[f];
    const int material = split.face_material.empty() ? 0 : split.face_material[f];
    int turn = 0;
    auto ref = refs.end();
    for (; turn < 3 && ref == refs.end(); ++turn) ref = refs.find({t[static_cast<size_t>(turn)], t[(turn + 1) % 3]});
    const auto mapped = [&](const std::array<int, 3>& g) {
      return std::array<int, 3>{out.index[static_cast<size_t>(g[0])], out.index[static_cast<size_t>(g[1])],
                                out.index[static_cast<size_t>(g[2])]};
    };
    if (ref == refs.end()) {
      out.add(mapped(t), uv, material, false);
      continue;
    }
    std::rotate(t.begin(), t.begin() + (turn - 1), t.end());  // t[0] -> t[1] is the lip edge
    std::rotate(uv.begin(), uv.begin() + (turn - 1), uv.end());
    const Cap& cap = caps[static_cast<size_t>(ref->second.cap)];
    std::vector<int> chain = cap.along[static_cast<size_t>(ref->second.edge)];
    if (ref->second.side == 1) std::reverse(chain.begin(), chain.end());
    const Eigen::Vector3d& x0 = split.rest_m[static_cast<size_t>(t[0])];
    const Eigen::Vector3d& x1 = split.rest_m[static_cast<size_t>(t[1])];
    int from = out.index[static_cast<size_t>(t[0])];
    Eigen::Vector2d uv_from = uv[0];
    for (size_t i = 0; i <= chain.size(); ++i) {
      const bool last = i == chain.size();
      const int to = last ? out.index[static_cast<size_t>(t[1])]
                          : sides[static_cast<size_t>(ref->second.cap)][static_cast<size_t>(chain[i])]
                                 [static_cast<size_t>(ref->second.side)];
      const Eigen::Vector2d uv_to = last ? uv[1] : detail::uvAlong(x0, x1, uv[0], uv[1], cap.rest(chain[i]));
      out.add({from, to, out.index[static_cast<size_t>(t[2])]}, {uv_from, uv_to, uv[2]}, material, false);
      from = to;
      uv_from = uv_to;
    }
  }
}

// The caps' faces: the - side's counter-clockwise in (y, z) (its outward normal is +x), the + side's the
// other way round; walls, mapped on their plane at rest.
void capFaces(const std::vector<Cap>& caps, const std::vector<std::vector<std::array<int, 2>>>& sides, Assembly& out) {
  for (size_t c = 0; c < caps.size(); ++c)
    for (const auto& f : caps[c].faces) {
      const auto& s = sides[c];
      const auto at = [&](int i) { return caps[c].rest(f[static_cast<size_t>(i)]); };
      const auto uv = mesh::planarTexCoords({at(0), at(1), at(2)});
      out.add({s[static_cast<size_t>(f[0])][0], s[static_cast<size_t>(f[1])][0], s[static_cast<size_t>(f[2])][0]}, uv,
              0, true);
      out.add({s[static_cast<size_t>(f[0])][1], s[static_cast<size_t>(f[2])][1], s[static_cast<size_t>(f[1])][1]},
              {uv[0], uv[2], uv[1]}, 0, true);
    }
}

mesh::SurfaceMesh meshOf(const DffdSplit& split, const Assembly& a) {
  mesh::SurfaceMesh out = detail::meshOf(a.x, a.faces);
  mesh::TriMesh& m = out.mesh();
  if (!split.face_uv.empty()) out.addTexCoords();
  for (const mesh::Material& material : split.materials) out.addMaterial(material);
  for (const auto f : m.faces()) {
    const auto i = static_cast<size_t>(f.idx());
    if (a.wall[i]) out.setKind(f, mesh::FaceKind::Wall);
    if (!split.face_material.empty()) out.setMaterial(f, a.material[i]);
    if (split.face_uv.empty()) continue;
    for (const auto h : m.fh_range(f)) {
      const int v = m.to_vertex_handle(h).idx();
      out.setTexCoord(h, a.uv[i][v == a.faces[i][0] ? 0 : v == a.faces[i][1] ? 1 : 2]);
    }
  }
  return out;
}

}  // namespace

mesh::SurfaceMesh cappedDeform(const mesh::SurfaceMesh& model, const GlobalDffd& dffd) {
  validateModel(model, ModelClosure::Closed);
  const DffdSplit split = splitAtDiscontinuities(model, dffd, Openings::Leave);
  std::vector<Eigen::Vector3d> positions(split.rest_m.size());
  deformSplit(split, dffd, positions);
  std::vector<Cap> caps;
  for (int i = 0; i < static_cast<int>(dffd.obstacles().size()); ++i) caps.push_back(capOf(split, dffd, i));
  const std::vector<int> twin = detail::twinsOf(split);
  Assembly out;
  placeVertices(split, twin, positions, caps, out);
  std::vector<std::vector<std::array<int, 2>>> sides;
  for (const Cap& cap : caps) sides.push_back(capVertices(cap, twin, dffd, out));
  modelFaces(split, twin, caps, sides, out);
  capFaces(caps, sides, out);
  return meshOf(split, out);
}

}  // namespace incise::global_dffd
