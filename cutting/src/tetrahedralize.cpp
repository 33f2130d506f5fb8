#include "incise/cutting/tetrahedralize.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#ifndef TETLIBRARY
#define TETLIBRARY  // TetGen's library interface: failures are thrown as int codes instead of exit()
#endif
#include <tetgen.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace incise::cutting {
namespace {

using Vec = Eigen::Vector3d;

// Sign of det(b - a, c - a, d - a): > 0 when d lies on the side of (a, b, c) its normal points to.
int orient3d(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
  Eigen::Matrix3d m;
  m.col(0) = b - a;
  m.col(1) = c - a;
  m.col(2) = d - a;
  const double det = m.determinant();
  return (det > 0) - (det < 0);
}

int orient2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  return (det > 0) - (det < 0);
}

// Closed segments pq and ab (2D) share a point.
bool segmentsMeet2d(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                    const Eigen::Vector2d& b) {
  const int o1 = orient2d(p, q, a), o2 = orient2d(p, q, b), o3 = orient2d(a, b, p), o4 = orient2d(a, b, q);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  // Touching or collinear: a point of one segment on the other.
  auto onSegment = [](const Eigen::Vector2d& s, const Eigen::Vector2d& t, const Eigen::Vector2d& x) {
    return orient2d(s, t, x) == 0 && x.x() >= std::min(s.x(), t.x()) && x.x() <= std::max(s.x(), t.x()) &&
           x.y() >= std::min(s.y(), t.y()) && x.y() <= std::max(s.y(), t.y());
  };
  return (o1 == 0 && onSegment(p, q, a)) || (o2 == 0 && onSegment(p, q, b)) || (o3 == 0 && onSegment(a, b, p)) ||
         (o4 == 0 && onSegment(a, b, q));
}

bool insideTriangle2d(const Eigen::Vector2d& x, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      const Eigen::Vector2d& c) {
  const int o1 = orient2d(a, b, x), o2 = orient2d(b, c, x), o3 = orient2d(c, a, x);
  return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

// The closed segment pq and the closed triangle abc share a point.
bool segmentMeetsTriangle(const Vec& p, const Vec& q, const Vec& a, const Vec& b, const Vec& c) {
  const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (sp * sq > 0) return false;
  if (sp == 0 && sq == 0) {
    // Coplanar: drop the coordinate along which the triangle's normal is largest.
    const Vec n = (b - a).cross(c - a);
    int drop = 0;
    n.cwiseAbs().maxCoeff(&drop);
    auto flat = [drop](const Vec& x) {
      return Eigen::Vector2d(x[(drop + 1) % 3], x[(drop + 2) % 3]);
    };
    const Eigen::Vector2d p2 = flat(p), q2 = flat(q), a2 = flat(a), b2 = flat(b), c2 = flat(c);
    return insideTriangle2d(p2, a2, b2, c2) || insideTriangle2d(q2, a2, b2, c2) ||
           segmentsMeet2d(p2, q2, a2, b2) || segmentsMeet2d(p2, q2, b2, c2) || segmentsMeet2d(p2, q2, c2, a2);
  }
  const int o1 = orient3d(p, q, a, b), o2 = orient3d(p, q, b, c), o3 = orient3d(p, q, c, a);
  return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

struct Triangle {
  std::array<int, 3> v;
  std::array<Vec, 3> p;
  Eigen::AlignedBox3d box;
};

// Two faces meet other than where their shared vertices force them to. Faces sharing an edge: false.
bool facesIntersect(const Triangle& s, const Triangle& t) {
  int shared = 0, s_shared = -1, t_shared = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (s.v[static_cast<size_t>(i)] == t.v[static_cast<size_t>(j)]) ++shared, s_shared = i, t_shared = j;
  auto edgeMeets = [](const Triangle& x, int i, const Triangle& y) {
    return segmentMeetsTriangle(x.p[static_cast<size_t>(i)], x.p[static_cast<size_t>((i + 1) % 3)], y.p[0],
                                y.p[1], y.p[2]);
  };
  if (shared == 0) {
    for (int i = 0; i < 3; ++i)
      if (edgeMeets(s, i, t) || edgeMeets(t, i, s)) return true;
    return false;
  }
  if (shared == 1) {
    // Edge (k + 1, k + 2) is the one opposite corner k. The faces' common part contains the shared vertex;
    // if it reaches further, its far end lies on an edge opposite the shared vertex or where such an edge
    // crosses the other face, so testing the two opposite edges suffices.
    return edgeMeets(s, (s_shared + 1) % 3, t) || edgeMeets(t, (t_shared + 1) % 3, s);
  }
  return false;
}

std::string number(double x) {
  char s[400];
  const auto r = std::to_chars(s, s + sizeof s, x, std::chars_format::fixed);  // shortest round-trip
  return std::string(s, r.ptr);
}

const char* tetgenMeaning(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "a self-intersection of the input surface";
    case 4: return "a very small input feature size";
    case 5: return "two very close input facets";
    case 10: return "an input error";
    default: return "an unknown error";
  }
}

}  // namespace

std::optional<std::pair<int, int>> findSelfIntersection(const TriMesh& mesh) {
  std::vector<Triangle> faces;
  std::vector<int> face_index;
  faces.reserve(mesh.n_faces());
  for (const auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    Triangle t;
    int k = 0;
    for (const auto v : mesh.fv_range(f)) {
      if (k == 3) break;
      t.v[static_cast<size_t>(k)] = v.idx();
      t.p[static_cast<size_t>(k)] = toEigen(mesh.point(v));
      t.box.extend(t.p[static_cast<size_t>(k)]);
      ++k;
    }
    if (k != 3) continue;
    faces.push_back(t);
    face_index.push_back(f.idx());
  }
  std::vector<int> order(faces.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double xa = faces[static_cast<size_t>(a)].box.min().x(), xb = faces[static_cast<size_t>(b)].box.min().x();
    return xa < xb || (xa == xb && a < b);
  });
  std::optional<std::pair<int, int>> first;
  for (size_t i = 0; i < order.size(); ++i) {
    const Triangle& s = faces[static_cast<size_t>(order[i])];
    for (size_t j = i + 1; j < order.size(); ++j) {
      const Triangle& t = faces[static_cast<size_t>(order[j])];
      if (t.box.min().x() > s.box.max().x()) break;
      if (!s.box.intersects(t.box) || !facesIntersect(s, t)) continue;
      const int a = face_index[static_cast<size_t>(order[i])], b = face_index[static_cast<size_t>(order[j])];
      const std::pair<int, int> pair{std::min(a, b), std::max(a, b)};
      if (!first || pair < *first) first = pair;
    }
  }
  return first;
}

TetMesh tetrahedralize(const SurfaceMesh& surface, const TetrahedralizeOptions& options) {
  if (!std::isfinite(options.radius_edge_ratio) ||
      (options.radius_edge_ratio != 0 && options.radius_edge_ratio < 1.0))
    throw std::invalid_argument("tetrahedralize: radius_edge_ratio " + number(options.radius_edge_ratio) +
                                " is not 0 or a finite value >= 1");
  if (!std::isfinite(options.max_volume_m3) || options.max_volume_m3 < 0)
    throw std::invalid_argument("tetrahedralize: max_volume_m3 " + number(options.max_volume_m3) +
                                " is not a finite value >= 0");
  const TriMesh& mesh = surface.mesh();
  const ManifoldReport report = checkManifold(mesh);
  if (!report.closed_two_manifold)
    throw MeshError("tetrahedralize: the surface is not a closed two-manifold: " + report.first_problem);
  // TetGen 1.5 may crash instead of failing on a self-intersecting surface: never hand it one.
  if (const auto pair = findSelfIntersection(mesh))
    throw MeshError("tetrahedralize: the surface intersects itself: face " + std::to_string(pair->first) +
                    " and face " + std::to_string(pair->second));

  tetgenio in, out;  // tetgenio frees its arrays with delete[]
  in.firstnumber = 0;
  std::vector<int> compact(mesh.n_vertices(), -1);
  int vertices = 0;
  for (const auto v : mesh.vertices())
    if (!mesh.status(v).deleted()) compact[static_cast<size_t>(v.idx())] = vertices++;
  in.numberofpoints = vertices;
  in.pointlist = new REAL[3 * static_cast<size_t>(vertices)];
  for (const auto v : mesh.vertices()) {
    const int i = compact[static_cast<size_t>(v.idx())];
    if (i < 0) continue;
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = mesh.point(v)[k];
  }
  int faces = 0;
  for (const auto f : mesh.faces())
    if (!mesh.status(f).deleted()) ++faces;
  in.numberoffacets = faces;
  in.facetlist = new tetgenio::facet[static_cast<size_t>(faces)];
  int next = 0;
  for (const auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    tetgenio::facet& facet = in.facetlist[next++];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::polygon& polygon = facet.polygonlist[0];
    tetgenio::init(&polygon);
    polygon.numberofvertices = 3;
    polygon.vertexlist = new int[3];
    int k = 0;
    for (const auto v : mesh.fv_range(f)) polygon.vertexlist[k++] = compact[static_cast<size_t>(v.idx())];
  }

  // p: the input is a piecewise linear complex; z: 0-based output; Q: quiet. Appended, not "q" + ...:
  // GCC 12 warns falsely on that (-Wrestrict, PR 105651).
  std::string switches = "pzQ";
  if (options.radius_edge_ratio > 0) switches.append("q").append(number(options.radius_edge_ratio));
  if (options.max_volume_m3 > 0) switches.append("a").append(number(options.max_volume_m3));
  if (options.keep_surface) switches += "Y";
  try {
    ::tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    throw MeshError("tetrahedralize: TetGen (switches \"" + switches + "\") failed with code " +
                    std::to_string(code) + ": " + tetgenMeaning(code));
  }
  if (out.numberofcorners != 4)
    throw MeshError("tetrahedralize: TetGen returned " + std::to_string(out.numberofcorners) + "-node tets");

  TetMesh result;
  result.nodes_m.resize(static_cast<size_t>(out.numberofpoints));
  for (int i = 0; i < out.numberofpoints; ++i)
    result.nodes_m[static_cast<size_t>(i)] = {out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]};
  result.tets.resize(static_cast<size_t>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    std::array<int, 4>& tet = result.tets[static_cast<size_t>(t)];
    for (int k = 0; k < 4; ++k) tet[static_cast<size_t>(k)] = out.tetrahedronlist[4 * t + k] - out.firstnumber;
    for (int k = 0; k < 4; ++k)
      if (tet[static_cast<size_t>(k)] < 0 || tet[static_cast<size_t>(k)] >= out.numberofpoints)
        throw MeshError("tetrahedralize: TetGen returned tet " + std::to_string(t) + " with node index " +
                        std::to_string(tet[static_cast<size_t>(k)]) + " out of range");
    // TetGen's own orientation convention is the opposite sign; normalise to det(b-a, c-a, d-a) > 0.
    const Vec& a = result.nodes_m[static_cast<size_t>(tet[0])];
    if (orient3d(a, result.nodes_m[static_cast<size_t>(tet[1])], result.nodes_m[static_cast<size_t>(tet[2])],
                 result.nodes_m[static_cast<size_t>(tet[3])]) < 0)
      std::swap(tet[2], tet[3]);
  }
  buildAdjacency(result);
  return result;
}

}  // namespace incise::cutting
