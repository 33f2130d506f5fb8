// Private: what the three parts of the surface mesh share (surface_mesh.cpp: the mesh and its kinds;
// surface_mesh_io.cpp: loading and saving; surface_mesh_check.cpp: the closed-two-manifold checks and the
// summary): the triangle list the OBJ reader makes and the loader checks, and small helpers.
// Threads, cost and failure as in surface_mesh.h.
#pragma once

#include <array>
#include <iterator>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "incise/cutting/surface_mesh.h"

namespace incise::cutting::detail {

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

[[noreturn]] inline void fail(const std::string& message) { throw MeshError(message); }

// Throws MeshError for the first problem of a triangle list read from a file, before it becomes an
// OpenMesh mesh (which would silently drop non-manifold faces): no faces, a degenerate face, an
// unreferenced vertex, a non-manifold, open or flipped edge, a non-manifold vertex. O(n log n).
void checkTriangles(const RawMesh& raw);

// The number of elements of an OpenMesh range (which skips deleted elements).
template <typename Range>
int countOf(const Range& range) {
  return static_cast<int>(std::distance(range.begin(), range.end()));
}

}  // namespace incise::cutting::detail
