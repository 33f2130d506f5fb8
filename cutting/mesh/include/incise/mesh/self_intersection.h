// Self-intersection of a triangle mesh: whether two of its faces cross other than along what they share.
// CGAL's Polygon Mesh Processing (exact predicates), compiled in the mesh module's CGAL object library.
// Threads: any; calls on distinct or const meshes may run concurrently. Allocates (a CGAL copy of the mesh).
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh {

// The lexicographically smallest pair of face indices (lower first) of faces that intersect other than
// along what they share, by CGAL's Polygon Mesh Processing self_intersections (exact predicates; faces
// sharing an edge or a vertex are tested too). Deleted faces are skipped. Throws MeshError when the mesh
// cannot be represented as a CGAL::Surface_mesh (not a two-manifold). Cost O(F log F + pairs of
// overlapping boxes).
std::optional<std::pair<int, int>> findSelfIntersection(const TriMesh& mesh);

// Every such pair (lower index first), in ascending order: where a cut surface crosses itself, for checks
// and reports. Same test and cost as findSelfIntersection.
std::vector<std::pair<int, int>> findSelfIntersections(const TriMesh& mesh);

}  // namespace incise::mesh
