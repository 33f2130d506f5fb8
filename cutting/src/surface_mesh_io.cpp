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

// The expected shape of a PLY header line, by its keyword; "" when the line is well formed. An element's
// count may not exceed `max_count` (the file's size: every element takes a byte at least).
std::string plyHeaderLineProblem(const std::vector<std::string>& t, long long max_count) {
  const std::string& k = t[0];
  if (k == "comment" || k == "obj_info") return "";
  if (k == "format")
    return t.size() == 3 && (t[1] == "ascii" || t[1] == "binary_little_endian" || t[1] == "binary_big_endian") &&
                   t[2] == "1.0"
               ? ""
               : "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'";
  if (k == "property")
    return t.size() == 3 || (t.size() == 5 && t[1] == "list") ? ""
                                                              : "expected 'property <type> <name>' or 'property list "
                                                                "<count type> <type> <name>'";
  if (k == "element") {
    long long count = -1;
    const auto [end, ec] = t.size() == 3 ? std::from_chars(t[2].data(), t[2].data() + t[2].size(), count)
                                         : std::from_chars_result{nullptr, std::errc::invalid_argument};
    const bool ok = ec == std::errc() && end == t[2].data() + t[2].size() && count >= 0 && count <= INT32_MAX;
    if (ok && count > max_count) return "more elements than the file's " + std::to_string(max_count) + " bytes hold";
    return ok ? "" : "expected 'element <name> <count>'";
  }
  return "unknown keyword '" + k + "'";
}

// OpenMesh 9.0's PLY reader reads its header word by word and never returns when it meets the end of the
// file before a word "end_header" (found by tests/fuzz/fuzz_surface_mesh: "element v float x" made it read
// "end_header" as an element's count; a header whose end_header has bytes stuck to it, or that has none; a
// format line whose version is not a number).
// So the header is checked line by line before OpenMesh sees the file: "ply", then format, comment,
// obj_info, element and property lines of their documented shapes, then a line "end_header"; then an ASCII
// body (checkPlyAsciiBody). OpenMesh also
// reserves room for the declared counts as they are (8 GB for "element vertex 2000000000"), so a count is
// bounded by the file's size.
// A PLY element as its header declares it: how many, and which of its properties are lists.
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<bool> lists;
};

// True for a word istream's >> reads as a number (in a PLY or OFF body): digits, sign, point and exponent only, and from_chars
// agrees (no "nan", "inf" or hex, which leave OpenMesh's stream failed).
bool streamNumber(const std::string& word, double& value) {
  if (word.find_first_not_of("0123456789+-.eE") != std::string::npos) return false;
  const char* begin = word.data() + (word[0] == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(begin, word.data() + word.size(), value);
  return ec == std::errc() && end == word.data() + word.size();
}

// An ASCII body, word by word as OpenMesh reads it: every value a number, every list's length an integer in
// [0, file size] followed by that many numbers. OpenMesh went on reading from a failed stream otherwise,
// with a list length it never set (an out-of-memory found by tests/fuzz/fuzz_surface_mesh).
void checkPlyAsciiBody(std::istream& in, const std::vector<PlyElement>& elements, const std::filesystem::path& path,
                       long long bytes) {
  std::string word;
  double value = 0.0;
  for (const PlyElement& e : elements)
    for (long long i = 0; i < e.count; ++i)
      for (const bool list : e.lists) {
        const auto where = [&] { return path.string() + ": PLY " + e.name + " " + std::to_string(i) + " (0-based): "; };
        if (!(in >> word) || !streamNumber(word, value))
          fail(where() + (in ? "'" + word + "' is not a number" : std::string("the file ends before it")));
        if (!list) continue;
        if (value < 0 || value > static_cast<double>(bytes) || value != std::floor(value))
          fail(where() + "list length '" + word + "' is not an integer the file can hold");
        for (long long k = static_cast<long long>(value); k > 0; --k)
          if (!(in >> word) || !streamNumber(word, value)) fail(where() + "a list ends early or holds a non-number");
      }
}

void checkPlyHeader(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const auto bytes = static_cast<long long>(std::filesystem::file_size(path));
  std::vector<PlyElement> elements;
  bool ascii = false;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream s(line);
    std::vector<std::string> t;
    for (std::string word; s >> word;) t.push_back(word);
    if (number == 1 || t.empty()) continue;  // "ply" (OpenMesh checks it), empty lines
    if (t[0] == "end_header" && t.size() == 1) {
      if (ascii) checkPlyAsciiBody(in, elements, path, bytes);
      return;
    }
    const std::string problem = plyHeaderLineProblem(t, bytes);
    if (!problem.empty())
      fail(path.string() + ":" + std::to_string(number) + ": PLY header: " + problem + ", got '" + line + "'");
    if (t[0] == "format") ascii = t[1] == "ascii";
    if (t[0] == "element") elements.push_back({t[1], std::stoll(t[2]), {}});
    if (t[0] == "property" && elements.empty())  // OpenMesh crashed on it (SEGV; found by fuzz_surface_mesh)
      fail(path.string() + ":" + std::to_string(number) + ": PLY header: a property before any element");
    if (t[0] == "property") elements.back().lists.push_back(t[1] == "list");
  }
  fail(path.string() + ": PLY header without end_header");
}

// The whole word as a decimal integer (from_chars reads "6-1" as 6; istream's >> would go on with "-1").
bool wholeInteger(const std::string& word, long long& value) {
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  return ec == std::errc() && end == word.data() + word.size();
}

// The non-empty, non-comment lines of an OFF file, split into words.
std::vector<std::vector<std::string>> offLines(std::istream& in) {
  std::vector<std::vector<std::string>> lines;
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line.substr(0, line.find('#')));
    std::vector<std::string> words;
    for (std::string word; s >> word;) words.push_back(word);
    if (!words.empty()) lines.push_back(std::move(words));
  }
  return lines;
}

// OpenMesh 9.0's ASCII OFF reader reads a face's vertex count as unsigned and then that many indices: a
// count of -1 had it read 4294967295 numbers from a failed stream (found by tests/fuzz/fuzz_surface_mesh),
// and it reserves room for the vertex and face counts of the header as they are. So an ASCII OFF file is
// checked first: "<#vertices> <#faces> <#edges>" on the line after the keyword line, counts that the file's
// size can hold (a vertex takes 6 bytes at least, a face 8), then after the vertex lines each face line
// "k i1 .. ik ..." with 3 <= k <= its words - 1, every count and index a whole integer, every vertex line 3
// numbers first ("6-1 0" as counts had OpenMesh take -1 faces). Binary OFF is refused.
void checkOff(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const auto lines = offLines(in);
  if (lines.empty() || lines[0][0].find("OFF") == std::string::npos) return;  // OpenMesh refuses it
  // Binary OFF: OpenMesh reserves its binary counts as they are (2 GB for a fuzzed header; found by
  // tests/fuzz/fuzz_surface_mesh). Nothing incise reads is binary OFF, so it is refused rather than checked.
  // OpenMesh takes "BINARY" anywhere on the first line ("OFF\bBINARYfa6" too).
  if (std::any_of(lines[0].begin(), lines[0].end(), [](const std::string& w) { return w.find("BINARY") != w.npos; }))
    fail(path.string() + ": binary OFF is not supported (ASCII OFF, PLY, STL or OBJ are)");
  // OpenMesh takes the counts from the line after the keyword line, whatever follows the keyword.
  const std::vector<std::string> header = lines.size() > 1 ? lines[1] : std::vector<std::string>();
  long long counts[3] = {-1, -1, -1};
  for (std::size_t i = 0; i < 3 && i < header.size(); ++i)
    if (!wholeInteger(header[i], counts[i])) counts[0] = -1;
  const auto bytes = static_cast<long long>(std::filesystem::file_size(path));
  if (counts[0] < 0 || counts[1] < 0 || counts[2] < 0 || counts[0] > bytes / 6 || counts[1] > bytes / 8)
    fail(path.string() + ": OFF header: expected '<#vertices> <#faces> <#edges>' that the file's " +
         std::to_string(bytes) + " bytes can hold");
  const std::size_t first_face = 2 + static_cast<std::size_t>(counts[0]);
  // Fewer lines than declared: OpenMesh read the missing faces' sizes from a failed stream (out of memory).
  if (lines.size() < first_face + static_cast<std::size_t>(counts[1]))
    fail(path.string() + ": OFF: the header declares " + std::to_string(counts[0]) + " vertices and " +
         std::to_string(counts[1]) + " faces, the file has " + std::to_string(lines.size() - 2) + " lines for them");
  double x = 0.0;
  for (std::size_t l = 2; l < first_face; ++l)
    if (lines[l].size() < 3 || !streamNumber(lines[l][0], x) || !streamNumber(lines[l][1], x) ||
        !streamNumber(lines[l][2], x))
      fail(path.string() + ": OFF vertex " + std::to_string(l - 2) + " (0-based): expected 3 numbers");
  for (std::size_t l = first_face; l < first_face + static_cast<std::size_t>(counts[1]); ++l) {
    long long k = -1, index = 0;
    bool ok = wholeInteger(lines[l][0], k) && k >= 3 && k < static_cast<long long>(lines[l].size());
    for (long long j = 1; ok && j <= k; ++j)
      ok = wholeInteger(lines[l][static_cast<std::size_t>(j)], index) && index >= 0;
    if (!ok)
      fail(path.string() + ": OFF face " + std::to_string(l - first_face) + " (0-based): its vertex count '" +
           lines[l][0] + "' is not 3 or more with that many indices after it");
  }
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
  if (ext == ".off") checkOff(path);
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
