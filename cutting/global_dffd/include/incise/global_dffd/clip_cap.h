// Clipping a closed tissue surface by an axis-aligned plane and capping the cut, so that the kept part is
// closed again: the "capped" treatment of a model split at a discontinuity plane u = u_i (paper §3.2, first
// method: the model is clipped by the plane and the cuts are capped), through CGAL's Polygon Mesh Processing
// clip; CGAL stays out of this header.
//
// Shapes: a SurfaceMesh in, a SurfaceMesh out (triangles only, deleted elements of the input skipped; a
// clipped result has none, with normals computed). Each face of a clipped result keeps what the face it is
// a piece of had (CGAL's corefinement visitor follows it): its kind, its material and its texture
// coordinates, interpolated at its corners (exact for a planar map); a cap face is a Wall face, mapped on
// its plane (mesh::planarTexCoords) and, on a mesh with materials, written with the walls' material.
// Vertices are all Original.
// Units: as the mesh (metres in incise); `value` in the same units. Threads: any thread; calls on distinct
// or const meshes may run concurrently. Allocates: not for the sim thread.
// Failure: std::invalid_argument for axis outside 0..2 or a non-finite value (checked first); MeshError
// for an input that is not a closed two-manifold (with checkManifold's first problem), when CGAL finds a
// self-intersection among the triangles the plane crosses, reports failure (clip returns false: the result
// would not be manifold) or throws, or when the result cannot be rebuilt as an OpenMesh triangle mesh.
// Self-intersections away from the plane are not looked for (CGAL requires none; they pass through).
#pragma once

#include "incise/mesh/surface_mesh.h"

namespace incise::global_dffd {

// Which half-space to keep: Below is x[axis] <= value, Above is x[axis] >= value.
enum class KeepSide { Below, Above };

// The part of the closed two-manifold `mesh` on the `keep` side of the plane x[axis] = value (axis 0, 1,
// 2 for x, y, z), closed by a cap in the plane and consistently oriented (outward normals, like the input).
// Cap vertices lie exactly in the plane: after clipping, every vertex within 1e-12 * max(|value|, size)
// of it (size: the largest extent of the input's bounding box) gets x[axis] = value, so callers may test
// `p[axis] == value`. (CGAL leaves nearly all of them an ulp or so off: it builds its clipper box with
// inexact constructions. The size term keeps the snap working for a plane near 0.)
// A plane that misses the mesh (or only touches it) on the kept side gives an empty SurfaceMesh (no
// vertices, no faces); one that misses or touches it on the other side gives a copy of the input (same
// handles, kinds and deleted elements). The input is not modified.
// Cost: O((V + F) log(V + F)): the manifold check, the conversions and CGAL's corefinement with a box cut
// by the plane; about 6 ms for the bunny (3,674 triangles) and 65-80 ms for it Loop-subdivided twice
// (58,784), half of it in CGAL's clip (Release, one core).
// Through CGAL::Polygon_mesh_processing::clip with clip_volume(true), on a CGAL::Surface_mesh with the
// Exact_predicates_inexact_constructions_kernel.
mesh::SurfaceMesh clipAndCap(const mesh::SurfaceMesh& mesh, int axis, double value, KeepSide keep);

}  // namespace incise::global_dffd
