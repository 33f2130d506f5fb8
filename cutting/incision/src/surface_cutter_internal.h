// Private to the surface cutter's sources (surface_cutter.cpp: the incision's steps; surface_cutter_walls.cpp:
// the seam's duplication and the walls): the handle aliases and small helpers both use.
#pragma once

#include <utility>

#include "incise/mesh/surface_mesh.h"

namespace incise::incision::detail {

using VH = mesh::TriMesh::VertexHandle;
using FH = mesh::TriMesh::FaceHandle;

// Deletes the triangle f without allocating (mesh::deleteTriangle).
inline void deleteFace(mesh::TriMesh& m, FH f) noexcept { mesh::deleteTriangle(m, f); }

}  // namespace incise::incision::detail
