// The tissue's thickness under each vertex of a closed surface: how far inwards, along the vertex's normal,
// the surface's far side is. The surface cutter reads it to keep a wall inside thin tissue instead of
// probing the mesh under every stroke station (a grid query of ~100 us on a 1M-triangle mesh).
// Shapes: one value per vertex index (deleted vertices: +infinity), metres, as float.
// Threads: any; reads the mesh only. Runs its rays on oneTBB's workers (on the calling thread alone in a
// thread-sanitizer build); the values do not depend on how the work is shared (each vertex is computed
// alone). Allocates (a CGAL AABB tree of the faces).
// Cost: O(F log F) for the tree, one ray per vertex: 2 s of one core for 470k vertices (the 940k bunny).
#pragma once

#include <vector>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh {

// For each vertex v at p with outward unit normal n (the area-weighted mean of its faces' normals): the
// distance from p to the first face crossed by the ray from p - skin_m * n along -n (skin_m > 0 keeps it
// off the vertex's own faces), when it is at most max_m; +infinity beyond max_m, when the ray meets
// nothing, or for a vertex without a normal (no faces, or faces that cancel). Exact predicates, inexact constructions (CGAL's Epick). Throws std::invalid_argument
// for a negative or non-finite max_m or skin_m.
std::vector<float> thicknessBelowVertices(const TriMesh& mesh, double max_m, double skin_m);

}  // namespace incise::mesh
