// Loading and saving surface meshes (surface_mesh.h): OBJ through incise's own reader and checks, PLY, OFF
// and STL through OpenMesh; OBJ and PLY output.
#include "incise/cutting/surface_mesh.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include <OpenMesh/Core/IO/MeshIO.hh>

#include "incise/cutting/atomic_file.h"
#include "incise/cutting/format.h"
#include "surface_mesh_internal.h"

namespace incise::cutting {

namespace {

using detail::countOf;
using detail::fail;
using detail::RawMesh;
using VertexHandle = TriMesh::VertexHandle;
using FaceHandle = TriMesh::FaceHandle;

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
  const std::string quoted = std::string("'").append(token).append("'");  // not "'" + ...: GCC 12 -Wrestrict, PR 105651
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
      fail(where + "face index " + std::to_string(value) + " out of range (" + std::to_string(vertices_so_far) +
           " vertices so far)");
    return static_cast<int>(resolved);
  }
  if (value > std::numeric_limits<int>::max()) fail(where + "face index " + std::to_string(value) + " out of range");
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
  if (tokens.size() < 4) fail(where + "a face needs at least 3 vertices, got " + std::to_string(tokens.size() - 1));
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
  static constexpr std::array<std::string_view, 8> kIgnored = {"vn", "vt", "vp", "g", "o", "s", "usemtl", "mtllib"};
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

// OpenMesh 9.0's PLY reader loops for ever on an element line whose count is not a number ("element v
// float x": found by tests/fuzz/fuzz_surface_mesh), so the header is checked before it sees the file: every
// "element" line is "element <name> <count>" with a count in [0, 2^31), and "end_header" ends the header.
void checkPlyHeader(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.rfind("end_header", 0) == 0) return;
    if (line.rfind("element", 0) != 0) continue;
    std::istringstream s(line);
    std::string element, name, rest;
    long long count = -1;
    if (!(s >> element >> name >> count) || element != "element" || count < 0 || count > INT32_MAX || s >> rest)
      fail(path.string() + ":" + std::to_string(number) + ": PLY header: expected 'element <name> <count>', got '" +
           line + "'");
  }
  fail(path.string() + ": PLY header without end_header");
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
  if (ext == ".ply") checkPlyHeader(path);
  TriMesh mesh;
  OpenMesh::IO::Options options;
  if (!OpenMesh::IO::read_mesh(mesh, path.string(), options)) fail(path.string() + ": OpenMesh could not read it");
  const auto declared = declaredFaceCount(path, ext);
  if (declared && static_cast<long long>(mesh.n_faces()) < *declared)
    fail(path.string() + ": OpenMesh read " + std::to_string(mesh.n_faces()) + " of the " + std::to_string(*declared) +
         " faces in the file (it drops degenerate and non-manifold faces)");
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
// Saving

// New 0-based indices of non-deleted vertices (-1 for deleted ones), in handle order. Throws for a
// non-finite position before anything is written.
std::vector<int> compactVertices(const TriMesh& mesh, const std::filesystem::path& path) {
  std::vector<int> index(mesh.n_vertices(), -1);
  int next = 0;
  for (const VertexHandle v : mesh.vertices()) {
    if (!toEigen(mesh.point(v)).allFinite())
      fail("cannot save " + path.string() + ": vertex " + std::to_string(v.idx()) + " has a non-finite position");
    index[static_cast<size_t>(v.idx())] = next++;
  }
  return index;
}

void writeFaceVertices(AtomicFile& out, const TriMesh& mesh, FaceHandle f, const std::vector<int>& index, int base) {
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

SurfaceMesh loadSurfaceMesh(const std::filesystem::path& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0)
    throw std::invalid_argument("loadSurfaceMesh: scale must be finite and > 0, got " + formatNumber(scale));
  const std::string ext = lowerExtension(path);
  if (ext == ".ply" || ext == ".off" || ext == ".stl") return readWithOpenMesh(path, ext, scale);
  if (ext != ".obj") fail(path.string() + ": unsupported mesh format '" + ext + "' (obj, ply, off, stl)");
  const RawMesh raw = readObj(path, scale);
  detail::checkTriangles(raw);
  return buildMesh(raw);
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

}  // namespace incise::cutting
