// Private: what the three parts of the surface mesh share (surface_mesh.cpp: the mesh and its kinds;
// surface_mesh_io.cpp: loading and saving; surface_mesh_check.cpp: the closed-two-manifold checks and the
// summary): the triangle list the OBJ reader makes and the loader checks, and small helpers.
// Threads, cost and failure as in surface_mesh.h.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh::detail {

using Triangle = std::array<int, 3>;

// A triangle list as read from a file, before any OpenMesh mesh exists. Indices 0-based. Where each point
// and triangle came from: its source line in a text file, its byte offset in a binary one (`binary`).
struct RawMesh {
  std::string file;  // the path as given, for messages
  std::vector<Eigen::Vector3d> points;
  std::vector<std::int64_t> point_lines;  // source line (or byte offset) of each point
  std::vector<Triangle> triangles;
  std::vector<std::int64_t> triangle_lines;  // source line (or byte offset) of each triangle
  // Texture coordinates (OBJ `vt`), and per triangle its corners' indices into them (parallel to
  // `triangles`; empty when the file's faces give none).
  std::vector<Eigen::Vector2d> texcoords;
  std::vector<Triangle> triangle_texcoords;
  std::vector<Eigen::Vector2d> corner_texcoords;  // the PLY reader's per-corner ones, until it chooses
  // Materials (OBJ usemtl and its MTL files), and per triangle its index into them (empty: none named).
  std::vector<Material> materials;
  std::vector<int> triangle_materials;
  bool binary = false;
  int index_base = 1;  // how the file numbers vertices (OBJ 1, OFF and PLY 0), for messages
  std::string vertex_note = " (vertex numbers 1-based, as in the file)";

  std::string at(std::int64_t where) const {
    return binary ? file + ": byte " + std::to_string(where) + ": " : file + ":" + std::to_string(where) + ": ";
  }
  std::string faceAt(int t) const { return at(triangle_lines[static_cast<size_t>(t)]); }
  std::string vertexName(int v) const { return std::to_string(v + index_base); }
  // Scales `p`, checks it is finite and appends it, from `where` (a line or byte offset).
  void addPoint(const Eigen::Vector3d& p, double scale, std::int64_t where);
  // Appends the fan (first, previous, next) of a convex polygon given as 0-based indices.
  void addPolygon(const std::vector<int>& polygon, std::int64_t where);
  // The same fan of the polygon's texture coordinate indices (into `texcoords`), after addPolygon.
  void addPolygonTexCoords(const std::vector<int>& polygon_texcoords);
};

[[noreturn]] inline void fail(const std::string& message) { throw MeshError(message); }

// The readers of each format: the file as a triangle list (polygons as fans), 0-based, scaled, every
// position finite; throw MeshError naming the file and the line or byte. Bounded: nothing is reserved
// from a count the file declares before the file is known to hold it. O(bytes).
RawMesh readOff(const std::filesystem::path& path, double scale);
RawMesh readStl(const std::filesystem::path& path, double scale);  // equal positions welded
RawMesh readPly(const std::filesystem::path& path, double scale);

// A triangle list to be read from `path` by a reader whose file numbers vertices from 0.
RawMesh zeroBasedMesh(const std::filesystem::path& path,
                      std::string vertex_note = " (vertex numbers 0-based, as in the file)");

// Shared by the text readers: the whole file (MeshError "cannot open"); a line split at whitespace; a
// coordinate (finite double, "+" allowed; `where` prefixes the message); an integer token.
std::string readWholeFile(const std::filesystem::path& path);
void splitTokens(std::string_view line, std::vector<std::string_view>& tokens);
double parseCoordinate(std::string_view token, const std::string& where);
std::optional<long long> parseInteger(std::string_view token);

// The lines of a text (LF or CRLF), numbered from 1, with `#` comments cut off when asked.
class TextLines {
 public:
  explicit TextLines(std::string_view text) : text_(text) {}
  // The next line with any token left (comments cut off at `#` when `comments`), split into `tokens`;
  // false at the end of the text.
  bool nextTokens(std::vector<std::string_view>& tokens, bool comments = true);
  std::int64_t line() const { return line_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  std::int64_t line_ = 0;
};

// Throws MeshError for the first problem of a triangle list read from a file, before it becomes an
// OpenMesh mesh (which would silently drop non-manifold faces): no faces, a degenerate face, an
// unreferenced vertex, a non-manifold, open or flipped edge, a non-manifold vertex. O(n log n).
void checkTriangles(const RawMesh& raw);

// The number of elements of an OpenMesh range (which skips deleted elements).
template <typename Range>
int countOf(const Range& range) {
  return static_cast<int>(std::distance(range.begin(), range.end()));
}

}  // namespace incise::mesh::detail
