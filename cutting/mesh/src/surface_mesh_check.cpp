// The checks of surface meshes (surface_mesh.h): the loader's checks of a triangle list read from a file
// (surface_mesh_internal.h), checkManifold of an OpenMesh mesh, and the summary built on it.
#include "incise/mesh/self_intersection.h"
#include "incise/mesh/surface_mesh.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "incise/core/union_find.h"
#include "surface_mesh_internal.h"

namespace incise::mesh {

namespace {

using detail::countOf;
using detail::fail;
using detail::RawMesh;
using detail::Triangle;
using VertexHandle = TriMesh::VertexHandle;
using FaceHandle = TriMesh::FaceHandle;

// ---------------------------------------------------------------------------------------------------------
// Triangle-list checks (before building the OpenMesh mesh, which would silently drop non-manifold faces)

std::string vertexPair(const RawMesh& raw, int a, int b) {
  return "(" + raw.vertexName(a) + ", " + raw.vertexName(b) + ")";
}

void checkDegenerate(const RawMesh& raw) {
  for (size_t t = 0; t < raw.triangles.size(); ++t) {
    const auto [a, b, c] = raw.triangles[t];
    const std::string where = raw.faceAt(static_cast<int>(t)) + "degenerate face " + std::to_string(t) + ": ";
    if (a == b || a == c) fail(where + "vertex " + raw.vertexName(a) + " repeated" + raw.vertex_note);
    if (b == c) fail(where + "vertex " + raw.vertexName(b) + " repeated" + raw.vertex_note);
    const auto& p = raw.points;
    const Eigen::Vector3d n = (p[static_cast<size_t>(b)] - p[static_cast<size_t>(a)])
                                  .cross(p[static_cast<size_t>(c)] - p[static_cast<size_t>(a)]);
    if (n.squaredNorm() == 0.0)
      fail(where + "zero area (vertices " + raw.vertexName(a) + ", " + raw.vertexName(b) + ", " + raw.vertexName(c) +
           " are collinear or coincide)" + raw.vertex_note);
  }
}

void checkReferenced(const RawMesh& raw) {
  std::vector<char> used(raw.points.size(), 0);
  for (const Triangle& t : raw.triangles)
    for (int v : t) used[static_cast<size_t>(v)] = 1;
  const auto unused = static_cast<size_t>(std::count(used.begin(), used.end(), 0));
  if (unused == 0) return;
  const auto first = static_cast<size_t>(std::find(used.begin(), used.end(), 0) - used.begin());
  fail(raw.at(raw.point_lines[first]) + "unreferenced vertex " + raw.vertexName(static_cast<int>(first)) +
       " (used by no face); " + std::to_string(unused) + " unreferenced vertices in all" + raw.vertex_note);
}

// One side of an undirected edge lo < hi: the face using it and whether it runs lo -> hi.
struct EdgeUse {
  int lo, hi, face;
  bool forward;
  bool operator<(const EdgeUse& o) const { return std::tie(lo, hi, face) < std::tie(o.lo, o.hi, o.face); }
};

std::vector<EdgeUse> edgeUses(const std::vector<Triangle>& triangles) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][static_cast<size_t>(k)], b = triangles[t][static_cast<size_t>((k + 1) % 3)];
      uses.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t), a < b});
    }
  std::sort(uses.begin(), uses.end());
  return uses;
}

// The first offending edge of each kind (index of its first use) and how many there are.
struct EdgeProblems {
  int non_manifold = 0, open = 0, flipped = 0;
  size_t first_non_manifold = 0, first_open = 0, first_flipped = 0;
  void note(int& count, size_t& first, size_t at) {
    if (count++ == 0) first = at;
  }
};

std::string faceList(const RawMesh& raw, const std::vector<EdgeUse>& uses, size_t begin, size_t end) {
  std::string s;
  for (size_t i = begin; i < end && i < begin + 4; ++i) {
    const int f = uses[i].face;
    s += (i > begin ? ", face " : "face ") + std::to_string(f) + (raw.binary ? " at byte " : " at line ") +
         std::to_string(raw.triangle_lines[static_cast<size_t>(f)]);
  }
  return end - begin > 4 ? s + ", ..." : s;
}

void reportEdgeProblems(const RawMesh& raw, const std::vector<EdgeUse>& uses, const EdgeProblems& p) {
  auto groupEnd = [&](size_t i) {
    size_t j = i;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    return j;
  };
  if (p.non_manifold > 0) {
    const size_t i = p.first_non_manifold, j = groupEnd(i);
    fail(raw.faceAt(uses[i].face) + "non-manifold edge " + vertexPair(raw, uses[i].lo, uses[i].hi) + " shared by " +
         std::to_string(j - i) + " faces (" + faceList(raw, uses, i, j) + "); " + std::to_string(p.non_manifold) +
         " such edges in all" + raw.vertex_note);
  }
  if (p.open > 0) {
    const size_t i = p.first_open;
    fail(raw.faceAt(uses[i].face) + "open surface: edge " + vertexPair(raw, uses[i].lo, uses[i].hi) + " has 1 face (" +
         faceList(raw, uses, i, i + 1) + "); " + std::to_string(p.open) + " boundary edges in all" + raw.vertex_note);
  }
  if (p.flipped > 0) {
    const size_t i = p.first_flipped;
    fail(raw.faceAt(uses[i].face) + "inconsistent orientation at edge " + vertexPair(raw, uses[i].lo, uses[i].hi) +
         ": " + faceList(raw, uses, i, i + 2) + " run the same way (a face is flipped); " + std::to_string(p.flipped) +
         " such edges in all" + raw.vertex_note);
  }
}

void checkEdges(const RawMesh& raw) {
  const std::vector<EdgeUse> uses = edgeUses(raw.triangles);
  EdgeProblems p;
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    if (j - i > 2) p.note(p.non_manifold, p.first_non_manifold, i);
    if (j - i == 1) p.note(p.open, p.first_open, i);
    if (j - i == 2 && uses[i].forward == uses[i + 1].forward) p.note(p.flipped, p.first_flipped, i);
    i = j;
  }
  reportEdgeProblems(raw, uses, p);
}

// Link edges (a -> b) of each vertex v: for a face (v, a, b) in its orientation. CSR by vertex.
struct Links {
  std::vector<int> offsets;
  std::vector<std::pair<int, int>> edges;
};

Links vertexLinks(const RawMesh& raw) {
  Links links;
  links.offsets.assign(raw.points.size() + 1, 0);
  for (const Triangle& t : raw.triangles)
    for (int v : t) ++links.offsets[static_cast<size_t>(v) + 1];
  std::partial_sum(links.offsets.begin(), links.offsets.end(), links.offsets.begin());
  std::vector<int> fill(links.offsets.begin(), links.offsets.end() - 1);
  links.edges.resize(3 * raw.triangles.size());
  for (const Triangle& t : raw.triangles)
    for (int k = 0; k < 3; ++k)
      links.edges[static_cast<size_t>(fill[static_cast<size_t>(t[static_cast<size_t>(k)])]++)] = {
          t[static_cast<size_t>((k + 1) % 3)], t[static_cast<size_t>((k + 2) % 3)]};
  return links;
}

// Number of cycles formed by the link edges in [begin, end), sorted by source. Every source appears once
// as a source and once as a target once the edge checks have passed.
int fanCount(std::vector<std::pair<int, int>>::iterator begin, std::vector<std::pair<int, int>>::iterator end,
             std::vector<char>& seen) {
  std::sort(begin, end);
  seen.assign(static_cast<size_t>(end - begin), 0);
  int fans = 0;
  for (auto start = begin; start != end; ++start) {
    if (seen[static_cast<size_t>(start - begin)]) continue;
    ++fans;
    for (auto at = start; at != end && !seen[static_cast<size_t>(at - begin)];) {
      seen[static_cast<size_t>(at - begin)] = 1;
      at = std::lower_bound(begin, end, std::make_pair(at->second, std::numeric_limits<int>::min()));
    }
  }
  return fans;
}

void checkFans(const RawMesh& raw) {
  Links links = vertexLinks(raw);
  std::vector<char> seen;
  for (size_t v = 0; v < raw.points.size(); ++v) {
    const auto begin = links.edges.begin() + links.offsets[v], end = links.edges.begin() + links.offsets[v + 1];
    const int fans = fanCount(begin, end, seen);
    if (fans != 1)
      fail(raw.at(raw.point_lines[v]) + "non-manifold vertex " + raw.vertexName(static_cast<int>(v)) + ": its " +
           std::to_string(end - begin) + " faces form " + std::to_string(fans) + " separate fans" + raw.vertex_note);
  }
}

}  // namespace

void detail::checkTriangles(const RawMesh& raw) {
  if (raw.triangles.empty()) fail(raw.file + ": no faces");
  checkDegenerate(raw);
  checkReferenced(raw);
  checkEdges(raw);
  checkFans(raw);
}

namespace {

// ---------------------------------------------------------------------------------------------------------
// checkManifold

// Records counts and the first problem message; `message` is a callable, run only for the first problem
// (no string work per element on a clean mesh).
struct Checker {
  const TriMesh& mesh;
  ManifoldReport& report;
  template <typename Message>
  void problem(int& counter, Message&& message) {
    ++counter;
    if (report.first_problem.empty()) report.first_problem = message();
  }
};

std::string faceProblem(FaceHandle f, const std::string& what) {
  return "degenerate face " + std::to_string(f.idx()) + ": " + what;
}

void checkFace(Checker& c, FaceHandle f, std::vector<int>& face_uses) {
  std::array<int, 3> v{-1, -1, -1};
  std::array<Eigen::Vector3d, 3> p;
  int n = 0;
  for (const VertexHandle vh : c.mesh.fv_range(f)) {
    if (n < 3) {
      v[static_cast<size_t>(n)] = vh.idx();
      p[static_cast<size_t>(n)] = toEigen(c.mesh.point(vh));
    }
    ++face_uses[static_cast<size_t>(vh.idx())];
    ++n;
  }
  int& count = c.report.degenerate_faces;
  if (n != 3)
    c.problem(count, [&] { return faceProblem(f, std::to_string(n) + " vertices"); });
  else if (v[0] == v[1] || v[0] == v[2] || v[1] == v[2])
    c.problem(count, [&] { return faceProblem(f, "repeated vertex"); });
  else if ((p[1] - p[0]).cross(p[2] - p[0]).squaredNorm() == 0.0)
    c.problem(count, [&] { return faceProblem(f, "zero area"); });
}

std::string edgeName(const TriMesh& mesh, TriMesh::EdgeHandle e) {
  const auto h = mesh.halfedge_handle(e, 0);
  return "edge " + std::to_string(e.idx()) + " (vertices " + std::to_string(mesh.from_vertex_handle(h).idx()) + ", " +
         std::to_string(mesh.to_vertex_handle(h).idx()) + ")";
}

void checkEdgesOf(Checker& c) {
  const TriMesh& mesh = c.mesh;
  std::vector<std::pair<std::uint64_t, int>> pairs;  // (packed vertex pair, edge)
  pairs.reserve(mesh.n_edges());
  for (const auto e : mesh.edges()) {
    const auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    if (mesh.is_boundary(h0) || mesh.is_boundary(h1))
      c.problem(c.report.boundary_edges, [&] { return "boundary " + edgeName(mesh, e); });
    else if (mesh.face_handle(h0) == mesh.face_handle(h1))
      c.problem(c.report.non_manifold_edges,
                [&] { return "non-manifold " + edgeName(mesh, e) + ": one face on both sides"; });
    const auto a = static_cast<std::uint32_t>(mesh.to_vertex_handle(h0).idx());
    const auto b = static_cast<std::uint32_t>(mesh.to_vertex_handle(h1).idx());
    pairs.emplace_back(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b), e.idx());
  }
  std::sort(pairs.begin(), pairs.end());
  for (size_t i = 1; i < pairs.size(); ++i)
    if (pairs[i].first == pairs[i - 1].first)
      c.problem(c.report.non_manifold_edges, [&] {
        return "non-manifold edge: edges " + std::to_string(pairs[i - 1].second) + " and " +
               std::to_string(pairs[i].second) + " join the same two vertices";
      });
}

// Walks v's outgoing halfedges; compares the faces reached with the faces that use v.
void checkVertex(Checker& c, VertexHandle v, int uses) {
  const TriMesh& mesh = c.mesh;
  const auto name = [&] { return "non-manifold vertex " + std::to_string(v.idx()); };
  int& count = c.report.non_manifold_vertices;
  if (uses == 0) return c.problem(count, [&] { return name() + ": isolated (no faces)"; });
  const auto start = mesh.halfedge_handle(v);
  int reached = 0, gaps = 0;
  auto h = start;
  for (size_t guard = 0; h.is_valid() && guard <= mesh.n_halfedges(); ++guard) {
    ++(mesh.is_boundary(h) ? gaps : reached);
    h = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h));
    if (h == start) break;
  }
  if (reached != uses)
    c.problem(count, [&] {
      return name() + ": its one-ring reaches " + std::to_string(reached) + " of the " + std::to_string(uses) +
             " faces using it (more than one fan)";
    });
  else if (gaps > 1)
    c.problem(count, [&] { return name() + ": " + std::to_string(gaps) + " boundary gaps in its one-ring"; });
}

int componentCount(const TriMesh& mesh) {
  std::vector<int> storage;
  core::detail::UnionFind components(storage, mesh.n_vertices());
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    components.unite(mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx());
  }
  int roots = 0;
  for (const VertexHandle v : mesh.vertices()) roots += components.isRoot(v.idx());
  return roots;
}

}  // namespace

ManifoldReport checkManifold(const TriMesh& mesh) {
  ManifoldReport report{};
  Checker c{mesh, report};
  std::vector<int> face_uses(mesh.n_vertices(), 0);
  for (const FaceHandle f : mesh.faces()) checkFace(c, f, face_uses);
  checkEdgesOf(c);
  for (const VertexHandle v : mesh.vertices()) checkVertex(c, v, face_uses[static_cast<size_t>(v.idx())]);
  const int faces = countOf(mesh.faces());
  report.euler_characteristic = countOf(mesh.vertices()) - countOf(mesh.edges()) + faces;
  report.components = componentCount(mesh);
  if (faces == 0 && report.first_problem.empty()) report.first_problem = "empty mesh (no faces)";
  report.closed_two_manifold = report.first_problem.empty();
  return report;
}

MeshSummary summarize(const SurfaceMesh& surface) {
  const TriMesh& mesh = surface.mesh();
  MeshSummary s{};
  for (const VertexHandle v : mesh.vertices()) {
    ++s.vertices;
    s.seam_vertices += surface.kind(v) == VertexKind::Seam;
    s.wall_vertices += surface.kind(v) == VertexKind::Wall;
  }
  for (const FaceHandle f : mesh.faces()) {
    ++s.faces;
    s.split_faces += surface.kind(f) == FaceKind::Split;
    s.wall_faces += surface.kind(f) == FaceKind::Wall;
  }
  const ManifoldReport report = checkManifold(mesh);
  s.boundary_edges = report.boundary_edges;
  s.euler_characteristic = report.euler_characteristic;
  s.closed_two_manifold = report.closed_two_manifold;
  s.self_intersections = report.closed_two_manifold ? static_cast<int>(findSelfIntersections(mesh).size()) : -1;
  return s;
}

std::string toJson(const MeshSummary& s) {
  nlohmann::ordered_json j;
  j["vertices"] = s.vertices;
  j["faces"] = s.faces;
  j["wall_faces"] = s.wall_faces;
  j["split_faces"] = s.split_faces;
  j["seam_vertices"] = s.seam_vertices;
  j["wall_vertices"] = s.wall_vertices;
  j["boundary_edges"] = s.boundary_edges;
  j["euler_characteristic"] = s.euler_characteristic;
  j["closed_two_manifold"] = s.closed_two_manifold;
  j["self_intersections"] = s.self_intersections;
  return j.dump(2);
}

EdgeLengths edgeLengths(const TriMesh& mesh) {
  EdgeLengths lengths;
  double sum_m = 0.0;
  int count = 0;
  for (const auto e : mesh.edges()) {
    if (mesh.status(e).deleted()) continue;
    const double l_m = mesh.calc_edge_length(e);
    sum_m += l_m;
    lengths.longest_m = std::max(lengths.longest_m, l_m);
    ++count;
  }
  lengths.mean_m = count ? sum_m / count : 0.0;
  return lengths;
}

}  // namespace incise::mesh
