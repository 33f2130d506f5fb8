// The OFF reader (surface_mesh_internal.h): Geomview's text OFF as CGAL, MeshLab, OpenMesh and others write
// it. "[ST][C][N]OFF" (texture coordinates, colours and normals after a vertex's x y z are ignored), the
// counts "#vertices #faces [#edges]" on the keyword's line or the next, one vertex and then one face per
// line ("n i0 ... i(n-1)", 0-based, anything after the indices — a colour — ignored), `#` comments and blank
// lines anywhere. Polygons become fans from their first vertex (right for convex ones). 4OFF, nOFF and
// binary OFF are refused. Errors name file:line.
#include <limits>
#include <string>
#include <vector>

#include "surface_mesh_internal.h"

namespace incise::mesh::detail {

namespace {

using Tokens = std::vector<std::string_view>;

// The keyword's token after its optional ST, C, N prefixes, or a message saying what it is instead.
void checkKeyword(const RawMesh& raw, const TextLines& lines, const Tokens& tokens) {
  std::string_view k = tokens[0];
  const std::string where = raw.at(lines.line());
  for (std::string_view prefix : {"ST", "C", "N"})
    if (k.substr(0, prefix.size()) == prefix && k.size() > 3) k.remove_prefix(prefix.size());
  if (k == "4OFF" || k == "nOFF")
    fail(where + "'" + std::string(tokens[0]) + "' (4D or n-dimensional OFF) is not supported, only 3D");
  if (k != "OFF")
    fail(where + "expected the OFF header ('OFF', 'COFF', 'NOFF', ...), got '" + std::string(tokens[0]) + "'");
  if (tokens.size() > 1 && tokens[1] == "BINARY") fail(where + "binary OFF is not supported, only text OFF");
}

long long parseCount(std::string_view token, const std::string& where, const char* what) {
  const auto value = parseInteger(token);
  if (!value || *value < 0 || *value > std::numeric_limits<int>::max())
    fail(where + "the " + std::string(what) + " count '" + std::string(token) + "' is not a count (0 to 2^31 - 1)");
  return *value;
}

struct OffCounts {
  int vertices = 0, faces = 0;
};

// The counts after the keyword: on its line, or on the next line with tokens.
OffCounts readCounts(const RawMesh& raw, TextLines& lines, Tokens& tokens) {
  tokens.erase(tokens.begin());
  if (!tokens.empty() && tokens[0] == "BINARY") tokens.erase(tokens.begin());
  if (tokens.empty() && !lines.nextTokens(tokens)) fail(raw.file + ": the file ends before the OFF counts");
  const std::string where = raw.at(lines.line());
  if (tokens.size() < 2)
    fail(where + "expected '#vertices #faces #edges' after the OFF header, got " + std::to_string(tokens.size()) +
         " number(s)");
  return {static_cast<int>(parseCount(tokens[0], where, "vertex")),
          static_cast<int>(parseCount(tokens[1], where, "face"))};
}

void readVertices(RawMesh& raw, TextLines& lines, Tokens& tokens, int count, double scale) {
  for (int v = 0; v < count; ++v) {
    if (!lines.nextTokens(tokens))
      fail(raw.file + ": the file ends after " + std::to_string(v) + " of the " + std::to_string(count) +
           " vertices the header declares (line " + std::to_string(lines.line()) + ")");
    const std::string where = raw.at(lines.line());
    if (tokens.size() < 3)
      fail(where + "vertex " + std::to_string(v) + ": expected 3 coordinates, got " + std::to_string(tokens.size()));
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = parseCoordinate(tokens[static_cast<size_t>(a)], where);
    raw.addPoint(p, scale, lines.line());
  }
}

void readFace(RawMesh& raw, const TextLines& lines, const Tokens& tokens, int f, std::vector<int>& polygon) {
  const std::string where = raw.at(lines.line()) + "face " + std::to_string(f);
  const auto n = parseInteger(tokens[0]);
  if (!n || *n < 3) fail(where + ": '" + std::string(tokens[0]) + "' is not a vertex count (at least 3)");
  if (static_cast<long long>(tokens.size()) - 1 < *n)
    fail(where + " declares " + std::to_string(*n) + " vertices but lists " + std::to_string(tokens.size() - 1));
  const long long vertices = static_cast<long long>(raw.points.size());
  polygon.clear();
  for (size_t k = 1; k <= static_cast<size_t>(*n); ++k) {
    const auto index = parseInteger(tokens[k]);
    if (!index) fail(where + ": index '" + std::string(tokens[k]) + "' is not an integer");
    if (*index < 0 || *index >= vertices)
      fail(where + " has index " + std::to_string(*index) + " but there are " + std::to_string(vertices) + " vertices");
    polygon.push_back(static_cast<int>(*index));
  }
  raw.addPolygon(polygon, lines.line());
}

}  // namespace

RawMesh readOff(const std::filesystem::path& path, double scale) {
  const std::string text = readWholeFile(path);
  RawMesh raw = zeroBasedMesh(path);
  TextLines lines(text);
  Tokens tokens;
  if (!lines.nextTokens(tokens)) fail(raw.file + ": empty file (expected the OFF header)");
  checkKeyword(raw, lines, tokens);
  const OffCounts counts = readCounts(raw, lines, tokens);
  readVertices(raw, lines, tokens, counts.vertices, scale);
  std::vector<int> polygon;
  for (int f = 0; f < counts.faces; ++f) {
    if (!lines.nextTokens(tokens))
      fail(raw.file + ": the file ends after " + std::to_string(f) + " of the " + std::to_string(counts.faces) +
           " faces the header declares (line " + std::to_string(lines.line()) + ")");
    readFace(raw, lines, tokens, f, polygon);
  }
  return raw;
}

}  // namespace incise::mesh::detail
