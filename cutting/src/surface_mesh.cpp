#include "incise/cutting/surface_mesh.h"

#include "incise/cutting/atomic_file.h"
#include "incise/cutting/format.h"
#include "union_find.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <nlohmann/json.hpp>

namespace incise::cutting {


namespace {

constexpr const char* kVertexKindProperty = "incise:vertex_kind";
constexpr const char* kFaceKindProperty = "incise:face_kind";
constexpr const char* kObjVertexNote = " (vertex numbers 1-based, as in the file)";

using VertexHandle = TriMesh::VertexHandle;
using FaceHandle = TriMesh::FaceHandle;
using Triangle = std::array<int, 3>;


// A triangle list as read from a file, before any OpenMesh mesh exists. Indices 0-based.
struct RawMesh {
  std::string file;  // the path as given, for messages
  std::vector<Eigen::Vector3d> points;
  std::vector<int> point_lines;  // source line of each point
  std::vector<Triangle> triangles;
  std::vector<int> triangle_lines;  // source line of each triangle

  std::string at(int line) const { return file + ":" + std::to_string(line) + ": "; }
  std::string faceAt(int t) const { return at(triangle_lines[static_cast<size_t>(t)]); }
};

[[noreturn]] void fail(const std::string& message) { throw MeshError(message); }

// ---------------------------------------------------------------------------------------------------------
// OBJ parsing

void splitTokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
}

double parseCoordinate(std::string_view token, const std::string& where) {
  std::string_view digits = token;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const std::string quoted = "'" + std::string(token) + "'";
  if (ec == std::errc::result_out_of_range) fail(where + "coordinate " + quoted + " is out of range");
  if (ec != std::errc() || end != digits.data() + digits.size())
    fail(where + "coordinate " + quoted + " is not a number");
  if (!std::isfinite(value)) fail(where + "coordinate " + quoted + " is not finite");
  return value;
}

// The vertex part of `a`, `a/t`, `a//n` or `a/t/n`, resolved to a 0-based index. Positive indices may
// point past the vertices read so far (checked at the end); negative ones count back from the last.
int parseFaceIndex(std::string_view token, int vertices_so_far, const std::string& where) {
  const std::string_view text = token.substr(0, token.find('/'));
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    fail(where + "face index '" + std::string(token) + "' is not an integer");
  if (value == 0) fail(where + "face index 0 is invalid (OBJ indices start at 1)");
  if (value < 0) {
    const long long resolved = vertices_so_far + value;
    if (resolved < 0)
      fail(where + "face index " + std::to_string(value) + " out of range (" +
           std::to_string(vertices_so_far) + " vertices so far)");
    return static_cast<int>(resolved);
  }
  if (value > std::numeric_limits<int>::max())
    fail(where + "face index " + std::to_string(value) + " out of range");
  return static_cast<int>(value - 1);
}

void parseVertex(const std::vector<std::string_view>& tokens, double scale, int line, RawMesh& raw) {
  const std::string where = raw.at(line);
  if (tokens.size() < 4) fail(where + "expected 3 coordinates, got " + std::to_string(tokens.size() - 1));
  Eigen::Vector3d p;
  for (int a = 0; a < 3; ++a) p[a] = parseCoordinate(tokens[static_cast<size_t>(a + 1)], where);
  p *= scale;
  if (!p.allFinite()) fail(where + "coordinate overflows after scaling by " + formatNumber(scale));
  raw.points.push_back(p);
  raw.point_lines.push_back(line);
}

void parseFace(const std::vector<std::string_view>& tokens, int line, RawMesh& raw) {
  const std::string where = raw.at(line);
  if (tokens.size() < 4)
    fail(where + "a face needs at least 3 vertices, got " + std::to_string(tokens.size() - 1));
  const int so_far = static_cast<int>(raw.points.size());
  const int first = parseFaceIndex(tokens[1], so_far, where);
  int previous = parseFaceIndex(tokens[2], so_far, where);
  for (size_t k = 3; k < tokens.size(); ++k) {  // fan: (first, previous, next)
    const int next = parseFaceIndex(tokens[k], so_far, where);
    raw.triangles.push_back({first, previous, next});
    raw.triangle_lines.push_back(line);
    previous = next;
  }
}

bool ignoredStatement(std::string_view keyword) {
  static constexpr std::array<std::string_view, 8> kIgnored = {"vn", "vt", "vp",     "g",
                                                               "o",  "s",  "usemtl", "mtllib"};
  return std::find(kIgnored.begin(), kIgnored.end(), keyword) != kIgnored.end();
}

void parseObjLine(std::string_view line, double scale, int number, RawMesh& raw,
                  std::vector<std::string_view>& tokens) {
  line = line.substr(0, line.find('#'));
  splitTokens(line, tokens);
  if (tokens.empty() || ignoredStatement(tokens[0])) return;
  if (tokens[0] == "v") return parseVertex(tokens, scale, number, raw);
  if (tokens[0] == "f") return parseFace(tokens, number, raw);
  fail(raw.at(number) + "unsupported OBJ statement '" + std::string(tokens[0]) + "'");
}

void checkIndexRange(const RawMesh& raw) {
  const int n = static_cast<int>(raw.points.size());
  for (size_t t = 0; t < raw.triangles.size(); ++t)
    for (int v : raw.triangles[t])
      if (v >= n)
        fail(raw.faceAt(static_cast<int>(t)) + "face index " + std::to_string(v + 1) + " out of range (" +
             std::to_string(n) + " vertices)");
}

RawMesh readObj(const std::filesystem::path& path, double scale) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  RawMesh raw;
  raw.file = path.string();
  std::string line;
  std::vector<std::string_view> tokens;
  for (int number = 1; std::getline(in, line); ++number) parseObjLine(line, scale, number, raw, tokens);
  if (in.bad()) fail(raw.file + ": read error");
  checkIndexRange(raw);
  return raw;
}

// ---------------------------------------------------------------------------------------------------------
// Triangle-list checks (before building the OpenMesh mesh, which would silently drop non-manifold faces)

std::string vertexPair(int a, int b) {
  return "(" + std::to_string(a + 1) + ", " + std::to_string(b + 1) + ")";
}

void checkDegenerate(const RawMesh& raw) {
  for (size_t t = 0; t < raw.triangles.size(); ++t) {
    const auto [a, b, c] = raw.triangles[t];
    const std::string where = raw.faceAt(static_cast<int>(t)) + "degenerate face " + std::to_string(t) + ": ";
    if (a == b || a == c) fail(where + "vertex " + std::to_string(a + 1) + " repeated" + kObjVertexNote);
    if (b == c) fail(where + "vertex " + std::to_string(b + 1) + " repeated" + kObjVertexNote);
    const auto& p = raw.points;
    const Eigen::Vector3d n = (p[static_cast<size_t>(b)] - p[static_cast<size_t>(a)])
                                  .cross(p[static_cast<size_t>(c)] - p[static_cast<size_t>(a)]);
    if (n.squaredNorm() == 0.0)
      fail(where + "zero area (vertices " + std::to_string(a + 1) + ", " + std::to_string(b + 1) + ", " +
           std::to_string(c + 1) + " are collinear or coincide)" + kObjVertexNote);
  }
}

void checkReferenced(const RawMesh& raw) {
  std::vector<char> used(raw.points.size(), 0);
  for (const Triangle& t : raw.triangles)
    for (int v : t) used[static_cast<size_t>(v)] = 1;
  const auto unused = static_cast<size_t>(std::count(used.begin(), used.end(), 0));
  if (unused == 0) return;
  const auto first = static_cast<size_t>(std::find(used.begin(), used.end(), 0) - used.begin());
  fail(raw.at(raw.point_lines[first]) + "unreferenced vertex " + std::to_string(first + 1) +
       " (used by no face); " + std::to_string(unused) + " unreferenced vertices in all" + kObjVertexNote);
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
    s += (i > begin ? ", face " : "face ") + std::to_string(f) + " at line " +
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
    fail(raw.faceAt(uses[i].face) + "non-manifold edge " + vertexPair(uses[i].lo, uses[i].hi) +
         " shared by " + std::to_string(j - i) + " faces (" + faceList(raw, uses, i, j) + "); " +
         std::to_string(p.non_manifold) + " such edges in all" + kObjVertexNote);
  }
  if (p.open > 0) {
    const size_t i = p.first_open;
    fail(raw.faceAt(uses[i].face) + "open surface: edge " + vertexPair(uses[i].lo, uses[i].hi) +
         " has 1 face (" + faceList(raw, uses, i, i + 1) + "); " + std::to_string(p.open) +
         " boundary edges in all" + kObjVertexNote);
  }
  if (p.flipped > 0) {
    const size_t i = p.first_flipped;
    fail(raw.faceAt(uses[i].face) + "inconsistent orientation at edge " + vertexPair(uses[i].lo, uses[i].hi) +
         ": " + faceList(raw, uses, i, i + 2) + " run the same way (a face is flipped); " +
         std::to_string(p.flipped) + " such edges in all" + kObjVertexNote);
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
    const auto begin = links.edges.begin() + links.offsets[v],
               end = links.edges.begin() + links.offsets[v + 1];
    const int fans = fanCount(begin, end, seen);
    if (fans != 1)
      fail(raw.at(raw.point_lines[v]) + "non-manifold vertex " + std::to_string(v + 1) + ": its " +
           std::to_string(end - begin) + " faces form " + std::to_string(fans) + " separate fans" +
           kObjVertexNote);
  }
}

void checkTriangles(const RawMesh& raw) {
  if (raw.triangles.empty()) fail(raw.file + ": no faces");
  checkDegenerate(raw);
  checkReferenced(raw);
  checkEdges(raw);
  checkFans(raw);
}

SurfaceMesh buildMesh(const RawMesh& raw) {
  SurfaceMesh surface;
  TriMesh& mesh = surface.mesh();
  mesh.reserve(raw.points.size(), 3 * raw.triangles.size() / 2, raw.triangles.size());
  for (const Eigen::Vector3d& p : raw.points) mesh.add_vertex(toOpenMesh(p));
  for (size_t t = 0; t < raw.triangles.size(); ++t) {
    const auto [a, b, c] = raw.triangles[t];
    const FaceHandle f = mesh.add_face(VertexHandle(a), VertexHandle(b), VertexHandle(c));
    if (!f.is_valid()) fail(raw.faceAt(static_cast<int>(t)) + "OpenMesh rejected face " + std::to_string(t));
  }
  mesh.update_normals();
  return surface;
}

// ---------------------------------------------------------------------------------------------------------
// Other formats, through OpenMesh

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::optional<long long> plyFaceCount(std::istream& in) {
  std::string line;
  while (std::getline(in, line) && line.rfind("end_header", 0) != 0) {
    std::istringstream s(line);
    std::string element, name;
    long long count = -1;
    if (s >> element >> name >> count && element == "element" && name == "face") return count;
  }
  return std::nullopt;
}

// "OFF" (or COFF, NOFF, ...) then "#vertices #faces #edges"; nullopt when comments or binary data intervene.
std::optional<long long> offFaceCount(std::istream& in) {
  std::string word;
  long long vertices = 0, faces = 0;
  if (in >> word && word.find("OFF") != std::string::npos && in >> vertices >> faces) return faces;
  return std::nullopt;
}

// Binary STL when the size matches 84 + 50 * (count at byte 80); ASCII otherwise ("facet" statements).
std::optional<long long> stlFaceCount(std::istream& in, const std::filesystem::path& path) {
  std::array<char, 84> header{};
  in.read(header.data(), header.size());
  std::uint32_t count = 0;
  std::memcpy(&count, header.data() + 80, sizeof count);
  if (in && std::filesystem::file_size(path) == 84 + 50 * static_cast<std::uintmax_t>(count)) return count;
  in.clear();
  in.seekg(0);
  long long facets = 0;
  std::string word;
  while (in >> word) facets += (word == "facet");
  return facets;
}

// Faces the file declares, when the format says (PLY and OFF headers, STL facets). Polygons may turn into
// more triangles, so only fewer faces than declared means OpenMesh dropped some.
std::optional<long long> declaredFaceCount(const std::filesystem::path& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  if (ext == ".ply") return plyFaceCount(in);
  if (ext == ".off") return offFaceCount(in);
  if (ext == ".stl") return stlFaceCount(in, path);
  return std::nullopt;
}

SurfaceMesh readWithOpenMesh(const std::filesystem::path& path, const std::string& ext, double scale) {
  if (!std::filesystem::exists(path)) fail(path.string() + ": cannot open (no such file)");
  TriMesh mesh;
  OpenMesh::IO::Options options;
  if (!OpenMesh::IO::read_mesh(mesh, path.string(), options))
    fail(path.string() + ": OpenMesh could not read it");
  const auto declared = declaredFaceCount(path, ext);
  if (declared && static_cast<long long>(mesh.n_faces()) < *declared)
    fail(path.string() + ": OpenMesh read " + std::to_string(mesh.n_faces()) + " of the " +
         std::to_string(*declared) + " faces in the file (it drops degenerate and non-manifold faces)");
  for (const VertexHandle v : mesh.vertices()) {
    mesh.point(v) *= scale;
    if (!toEigen(mesh.point(v)).allFinite())
      fail(path.string() + ": vertex " + std::to_string(v.idx()) + " (0-based) has a non-finite position");
  }
  const ManifoldReport report = checkManifold(mesh);
  if (!report.closed_two_manifold)
    fail(path.string() + ": " + report.first_problem + " (0-based indices as read by OpenMesh)");
  mesh.update_normals();
  return SurfaceMesh(std::move(mesh));
}

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
  return "edge " + std::to_string(e.idx()) + " (vertices " +
         std::to_string(mesh.from_vertex_handle(h).idx()) + ", " +
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
      return name() + ": its one-ring reaches " + std::to_string(reached) + " of the " +
             std::to_string(uses) + " faces using it (more than one fan)";
    });
  else if (gaps > 1)
    c.problem(count, [&] { return name() + ": " + std::to_string(gaps) + " boundary gaps in its one-ring"; });
}

int componentCount(const TriMesh& mesh) {
  std::vector<int> storage;
  detail::UnionFind components(storage, mesh.n_vertices());
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    components.unite(mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx());
  }
  int roots = 0;
  for (const VertexHandle v : mesh.vertices()) roots += components.isRoot(v.idx());
  return roots;
}

template <typename Range>
int countOf(const Range& range) {
  return static_cast<int>(std::distance(range.begin(), range.end()));
}

// ---------------------------------------------------------------------------------------------------------
// Saving

// New 0-based indices of non-deleted vertices (-1 for deleted ones), in handle order. Throws for a
// non-finite position before anything is written.
std::vector<int> compactVertices(const TriMesh& mesh, const std::filesystem::path& path) {
  std::vector<int> index(mesh.n_vertices(), -1);
  int next = 0;
  for (const VertexHandle v : mesh.vertices()) {
    if (!toEigen(mesh.point(v)).allFinite())
      fail("cannot save " + path.string() + ": vertex " + std::to_string(v.idx()) +
           " has a non-finite position");
    index[static_cast<size_t>(v.idx())] = next++;
  }
  return index;
}

void writeFaceVertices(AtomicFile& out, const TriMesh& mesh, FaceHandle f, const std::vector<int>& index,
                       int base) {
  for (const VertexHandle v : mesh.fv_range(f)) {
    out << ' ' << index[static_cast<size_t>(v.idx())] + base;
  }
}

// The OBJ groups, in file order: tissue (original and split faces), then wall.
enum class ObjGroup { Tissue, Wall };

void writeObjGroup(AtomicFile& out, const SurfaceMesh& surface, const std::vector<int>& index, ObjGroup group) {
  const TriMesh& mesh = surface.mesh();
  const bool wall = group == ObjGroup::Wall;
  bool header = false;
  for (const FaceHandle f : mesh.faces()) {
    if ((surface.kind(f) == FaceKind::Wall) != wall) continue;
    if (!header) out << (wall ? "g wall\n" : "g tissue\n");
    header = true;
    out << 'f';
    writeFaceVertices(out, mesh, f, index, 1);
    out << '\n';
  }
}

void writePoint(AtomicFile& out, const OpenMesh::Vec3d& p) {
  for (int a = 0; a < 3; ++a) {
    if (a > 0) out << ' ';
    out.number17(p[a]);
  }
}

void writePlyHeader(AtomicFile& out, const TriMesh& mesh) {
  out << "ply\nformat ascii 1.0\ncomment incise surface mesh; vertex kind 0 original, 1 seam, 2 wall; "
         "face kind 0 original, 1 split, 2 wall\nelement vertex "
      << countOf(mesh.vertices())
      << "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar kind\nelement face "
      << countOf(mesh.faces()) << "\nproperty list uchar int vertex_indices\nproperty uchar kind\nend_header\n";
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------

const char* toString(VertexKind kind) noexcept {
  switch (kind) {
    case VertexKind::Original:
      return "original";
    case VertexKind::Seam:
      return "seam";
    case VertexKind::Wall:
      return "wall";
  }
  return "unknown";
}

const char* toString(FaceKind kind) noexcept {
  switch (kind) {
    case FaceKind::Original:
      return "original";
    case FaceKind::Split:
      return "split";
    case FaceKind::Wall:
      return "wall";
  }
  return "unknown";
}

SurfaceMesh::SurfaceMesh() { attachKinds(); }

SurfaceMesh::SurfaceMesh(TriMesh mesh) : mesh_(std::move(mesh)) { attachKinds(); }

void SurfaceMesh::attachKinds() {
  if (!mesh_.get_property_handle(vertex_kind_, kVertexKindProperty))
    mesh_.add_property(vertex_kind_, kVertexKindProperty);
  if (!mesh_.get_property_handle(face_kind_, kFaceKindProperty))
    mesh_.add_property(face_kind_, kFaceKindProperty);
}

namespace {
template <typename Handle>
void checkHandle(Handle h, size_t count, const char* what) {
  if (!h.is_valid() || static_cast<size_t>(h.idx()) >= count)
    throw std::out_of_range(std::string("SurfaceMesh: invalid ") + what + " handle " +
                            std::to_string(h.idx()) + " (" + std::to_string(count) + " " + what + "s)");
}
}  // namespace

VertexKind SurfaceMesh::kind(TriMesh::VertexHandle v) const {
  checkHandle(v, mesh_.n_vertices(), "vertex");
  return mesh_.property(vertex_kind_, v);
}

void SurfaceMesh::setKind(TriMesh::VertexHandle v, VertexKind kind) {
  checkHandle(v, mesh_.n_vertices(), "vertex");
  mesh_.property(vertex_kind_, v) = kind;
}

FaceKind SurfaceMesh::kind(TriMesh::FaceHandle f) const {
  checkHandle(f, mesh_.n_faces(), "face");
  return mesh_.property(face_kind_, f);
}

void SurfaceMesh::setKind(TriMesh::FaceHandle f, FaceKind kind) {
  checkHandle(f, mesh_.n_faces(), "face");
  mesh_.property(face_kind_, f) = kind;
}

TriMesh::VertexHandle SurfaceMesh::addVertex(const Eigen::Vector3d& p, VertexKind kind) {
  if (!p.allFinite())
    throw std::invalid_argument("SurfaceMesh::addVertex: non-finite point (" + formatNumber(p.x()) + ", " +
                                formatNumber(p.y()) + ", " + formatNumber(p.z()) + ")");
  const VertexHandle v = mesh_.add_vertex(toOpenMesh(p));
  mesh_.property(vertex_kind_, v) = kind;
  return v;
}

TriMesh::FaceHandle SurfaceMesh::addFace(TriMesh::VertexHandle v0, TriMesh::VertexHandle v1,
                                         TriMesh::VertexHandle v2, FaceKind kind) {
  for (const VertexHandle v : {v0, v1, v2}) checkHandle(v, mesh_.n_vertices(), "vertex");
  const FaceHandle f = (v0 == v1 || v0 == v2 || v1 == v2) ? FaceHandle() : mesh_.add_face(v0, v1, v2);
  if (!f.is_valid())
    throw MeshError("SurfaceMesh::addFace: OpenMesh refused face (" + std::to_string(v0.idx()) + ", " +
                    std::to_string(v1.idx()) + ", " + std::to_string(v2.idx()) +
                    "): repeated vertex, or it would make an edge or vertex non-manifold");
  mesh_.property(face_kind_, f) = kind;
  return f;
}

SurfaceMesh loadSurfaceMesh(const std::filesystem::path& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0)
    throw std::invalid_argument("loadSurfaceMesh: scale must be finite and > 0, got " + formatNumber(scale));
  const std::string ext = lowerExtension(path);
  if (ext == ".ply" || ext == ".off" || ext == ".stl") return readWithOpenMesh(path, ext, scale);
  if (ext != ".obj") fail(path.string() + ": unsupported mesh format '" + ext + "' (obj, ply, off, stl)");
  const RawMesh raw = readObj(path, scale);
  checkTriangles(raw);
  return buildMesh(raw);
}

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

void saveObj(const SurfaceMesh& surface, const std::filesystem::path& path) {
  const TriMesh& mesh = surface.mesh();
  const std::vector<int> index = compactVertices(mesh, path);
  rethrowFileErrorAs<MeshError>([&] {
    AtomicFile out(path);
    out << "# incise surface mesh: groups tissue (original and split faces) and wall\n";
    for (const VertexHandle v : mesh.vertices()) {
      out << "v ";
      writePoint(out, mesh.point(v));
      out << '\n';
    }
    writeObjGroup(out, surface, index, ObjGroup::Tissue);
    writeObjGroup(out, surface, index, ObjGroup::Wall);
    out.commit();
  });
}

void savePly(const SurfaceMesh& surface, const std::filesystem::path& path) {
  const TriMesh& mesh = surface.mesh();
  const std::vector<int> index = compactVertices(mesh, path);
  rethrowFileErrorAs<MeshError>([&] {
    AtomicFile out(path);
    writePlyHeader(out, mesh);
    for (const VertexHandle v : mesh.vertices()) {
      writePoint(out, mesh.point(v));
      out << ' ' << static_cast<int>(surface.kind(v)) << '\n';
    }
    for (const FaceHandle f : mesh.faces()) {
      out << static_cast<long long>(mesh.valence(f));
      writeFaceVertices(out, mesh, f, index, 0);
      out << ' ' << static_cast<int>(surface.kind(f)) << '\n';
    }
    out.commit();
  });
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
  return j.dump(2);
}

TriMesh subdivideLoop(const TriMesh& mesh, int iterations) {
  if (iterations < 0)
    throw std::invalid_argument("subdivideLoop: iterations must be >= 0, got " + std::to_string(iterations));
  TriMesh result = mesh;
  result.garbage_collection();
  if (iterations == 0) return result;
  size_t max_valence = 0;
  for (const VertexHandle v : result.vertices())
    max_valence = std::max<size_t>(max_valence, result.valence(v));
  OpenMesh::Subdivider::Uniform::LoopT<TriMesh, double> loop;
  loop.init_weights(std::max<size_t>(max_valence + 1, 50));
  loop.attach(result);
  loop(static_cast<size_t>(iterations));
  loop.detach();
  result.update_normals();
  return result;
}

SurfaceMesh subdivided(const SurfaceMesh& surface, int iterations) {
  SurfaceMesh result(subdivideLoop(surface.mesh(), iterations));
  for (const VertexHandle v : result.mesh().vertices()) result.setKind(v, VertexKind::Original);
  for (const FaceHandle f : result.mesh().faces()) result.setKind(f, FaceKind::Original);
  return result;
}

}  // namespace incise::cutting
