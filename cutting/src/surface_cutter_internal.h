// Private to the surface cutter's sources (surface_cutter.cpp: the incision's steps; surface_cutter_walls.cpp:
// the seam's duplication and the walls): the handle aliases and small helpers both use.
#pragma once

#include <utility>

#include "incise/cutting/surface_mesh.h"

namespace incise::cutting::detail {

using VH = TriMesh::VertexHandle;
using FH = TriMesh::FaceHandle;

// OpenMesh's delete_face(face, delete_isolated_vertices): a deleted face's vertices stay (they are the
// seam's, re-attached to the faces that replace it).
constexpr bool kKeepIsolatedVertices = false;

// The key of the wall strip between seam vertices a and b.
inline std::pair<int, int> segmentKey(VH a, VH b) { return {a.idx(), b.idx()}; }

}  // namespace incise::cutting::detail
