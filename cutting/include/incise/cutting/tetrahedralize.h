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

namespace incise::cutting {

struct TetrahedralizeOptions {
  double radius_edge_ratio = 2.0;  // TetGen -q: bound on circumradius / shortest edge; 0 = no quality
                                   // refinement; otherwise finite and >= 1 (smaller may not terminate)
  double max_volume_m3 = 0;        // TetGen -a: largest tet volume; 0 = no bound; finite, >= 0
  bool keep_surface = true;        // TetGen -Y: no Steiner points on the boundary; the boundary triangles
                                   // are exactly the surface's triangles. TetGen then rejects every
                                   // refinement point that encroaches a boundary triangle, so -q and -a
                                   // hold only where that allows (a unit cube stays 6 tets whatever
                                   // max_volume_m3; the bunny at 0.01 scale goes from 6740 to 35365 tets
                                   // with max_volume_m3 = volume / 20000)
};

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
