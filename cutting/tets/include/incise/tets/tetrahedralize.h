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

#include "incise/mesh/self_intersection.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/tets/tet_mesh.h"
#include "incise/tets/tetrahedralize_options.h"

namespace incise::tets {

// Validates `surface` (checkManifold, then findSelfIntersection) and runs TetGen with "pzQ", plus
// "q<ratio>", "a<volume>" and "Y" from the options. Returns the mesh with all tets positively oriented and
// neighbours filled. Nodes: the surface's non-deleted vertices first (in handle order, as TetGen keeps
// them), then Steiner points. Cost: validation O(F log F) for a well-spread surface; TetGen about O(T log T).
TetMesh tetrahedralize(const mesh::SurfaceMesh& surface, const TetrahedralizeOptions& options = {});

}  // namespace incise::tets
