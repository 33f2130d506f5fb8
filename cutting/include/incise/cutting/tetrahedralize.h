// Tetrahedralises a closed tissue surface with TetGen 1.5 (H. Si, "TetGen, a Delaunay-based quality
// tetrahedral mesh generator", ACM TOMS 41(2), 2015): a constrained Delaunay tetrahedralisation of the
// surface as a piecewise linear complex, refined for quality. TetGen is a private dependency: its headers
// do not appear here.
//
// Threads: not the sim thread (seconds for large meshes; allocates). One call at a time: TetGen's exact
// predicates keep file-static state (set up again on every call), so concurrent calls are not known safe.
// findSelfIntersection on distinct or const meshes may run concurrently.
// Failure: MeshError for a surface that is not a closed two-manifold (checkManifold's first problem), that
// intersects itself (naming the two face indices), or that TetGen refuses (the meaning of its code);
// std::invalid_argument for bad options (with the value).
#pragma once

#include <optional>
#include <utility>

#include "incise/cutting/surface_mesh.h"
#include "incise/cutting/tet_mesh.h"
#include "incise/cutting/tetrahedralize_options.h"

namespace incise::cutting {

// Validates `surface` (checkManifold, then findSelfIntersection) and runs TetGen with "pzQ", plus
// "q<ratio>", "a<volume>" and "Y" from the options. Returns the mesh with all tets positively oriented and
// neighbours filled. Nodes: the surface's non-deleted vertices first (in handle order, as TetGen keeps
// them), then Steiner points. Cost: validation O(F log F) for a well-spread surface; TetGen about O(T log T).
TetMesh tetrahedralize(const SurfaceMesh& surface, const TetrahedralizeOptions& options = {});

// The lexicographically smallest pair of face indices (lower first) of faces that intersect other than
// along what they share, by CGAL's Polygon Mesh Processing self_intersections (exact predicates; faces
// sharing an edge or a vertex are tested too). Deleted faces are skipped. Throws MeshError when the mesh
// cannot be represented as a CGAL::Surface_mesh (not a two-manifold). Cost O(F log F + pairs of
// overlapping boxes).
std::optional<std::pair<int, int>> findSelfIntersection(const TriMesh& mesh);

}  // namespace incise::cutting
