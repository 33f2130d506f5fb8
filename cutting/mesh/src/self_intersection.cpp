// findSelfIntersection with CGAL's Polygon Mesh Processing: exact
// predicates, every pair of faces (also faces sharing an edge or a vertex) tested the way CGAL defines a
// self-intersection. Compiled in the CGAL object library.
#include <algorithm>
#include <iterator>
#include <utility>
#include <vector>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include "incise/mesh/cgal_mesh.h"
#include "incise/mesh/self_intersection.h"

namespace incise::mesh {

std::vector<std::pair<int, int>> findSelfIntersections(const TriMesh& mesh) {
  std::vector<int> face_handles;
  const detail::CgalMesh cgal = detail::toCgal(mesh, "findSelfIntersections", &face_handles);
  std::vector<std::pair<detail::CgalMesh::Face_index, detail::CgalMesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(cgal, std::back_inserter(pairs));
  std::vector<std::pair<int, int>> out;
  out.reserve(pairs.size());
  for (const auto& [f, g] : pairs) {
    const int a = face_handles[static_cast<size_t>(f.idx())], b = face_handles[static_cast<size_t>(g.idx())];
    out.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<std::pair<int, int>> findSelfIntersection(const TriMesh& mesh) {
  const std::vector<std::pair<int, int>> pairs = findSelfIntersections(mesh);
  if (pairs.empty()) return std::nullopt;
  return pairs.front();
}

}  // namespace incise::mesh
