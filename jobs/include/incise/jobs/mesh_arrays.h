// Tissue meshes to and from flat arrays, for callers that hold meshes as arrays (an engine's vertex and index
// buffers, numpy): a mesh built from positions and triangles with the checks a mesh file gets, and a mesh's
// live elements copied out as arrays.
//
// Shapes: xyz_m holds 3 doubles per vertex (metres); triangles 3 vertex indices per face (0-based,
// counter-clockwise seen from outside). The arrays out hold the live (non-deleted) elements in handle order,
// the faces' vertices re-indexed past deleted vertices: the elements saveObj writes and geometryHash
// (mesh_hash.h) hashes, in the same order within each kind of face.
// Threads: any, on meshes nobody is changing. Cost: O(V + F); meshFromArrays also the manifold check
// (O(V + E log E)). Failure: meshFromArrays throws mesh::MeshError naming the element at fault ("vertex 3:
// coordinate 1 is not finite", "face 7: vertex index 12 is out of range (8 vertices)", "face 2: repeated
// vertex 5", "not a closed two-manifold: ...") and std::invalid_argument for arrays whose sizes are not
// multiples of 3; the copies throw std::invalid_argument when an output's size is not the count asked for.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "incise/mesh/surface_mesh.h"

namespace incise::jobs {

// A closed, consistently oriented triangle mesh from arrays (all kinds Original; normals computed).
mesh::SurfaceMesh meshFromArrays(std::span<const double> xyz_m, std::span<const std::int64_t> triangles);

std::size_t liveVertices(const mesh::TriMesh& mesh) noexcept;
std::size_t liveFaces(const mesh::TriMesh& mesh) noexcept;
// True when no vertex is deleted: the points' storage (OpenMesh's, 3 doubles per vertex, contiguous) is the
// vertex array itself, to be read in place.
bool verticesContiguous(const mesh::TriMesh& mesh) noexcept;

// liveVertices x 3 positions into xyz_m.
void copyVertices(const mesh::SurfaceMesh& mesh, std::span<double> xyz_m);
// liveFaces x 3 vertex indices into triangles and liveFaces kinds (mesh::FaceKind's values) into kinds
// (empty: not wanted).
void copyFaces(const mesh::SurfaceMesh& mesh, std::span<std::int64_t> triangles, std::span<std::uint8_t> kinds);
// liveFaces x 3 corners x (u, v) texture coordinates into uv, the corners in copyFaces' order; the mesh must
// have them (mesh.hasTexCoords()). liveFaces material indices (into mesh.materials(); -1 for a wall, whose
// material is incise's own) into materials; the mesh must have materials. std::invalid_argument for a wrong size or a mesh without them.
void copyTexCoords(const mesh::SurfaceMesh& mesh, std::span<double> uv);
void copyFaceMaterials(const mesh::SurfaceMesh& mesh, std::span<std::int32_t> materials);

}  // namespace incise::jobs
