// The tissue's thickness under each vertex of a closed surface: how far inwards, along the vertex's normal,
// the surface's far side is. The surface cutter reads it to keep a wall inside thin tissue instead of
// probing the mesh under every stroke station (a grid query of ~100 us on a 1M-triangle mesh).
// Shapes: one value per vertex index (deleted vertices: +infinity), metres, as float.
// Threads: any; reads the mesh only. Runs its rays on oneTBB's workers (on the calling thread alone in a
// thread-sanitizer build); the values do not depend on how the work is shared (each vertex is computed
// alone). Allocates (a CGAL AABB tree of the faces).
// Cost: O(F log F) for the tree, one ray per vertex: 2 s of one core for 470k vertices (the 940k bunny).
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh {

// A surface as it was given, for segments cast into it: how far along a direction from a point the surface
// is first crossed. The thickness below each vertex is read with it, and the surface cutter probes each
// lattice row with it (a row that reaches the surface's far side sideways, which the thickness straight
// below the vertices does not see). The surface is copied: later changes to the mesh are not seen.
// Threads: const queries from any thread. Allocates at construction only (CGAL's AABB tree of the faces,
// about 145 bytes a face: 136 MB for the 940k-face bunny); a query allocates nothing (but in CGAL's exact fallback for a degenerate box test).
// Cost: O(F log F) to build; a query O(log F + the faces whose boxes the segment meets).
class SurfaceRays {
 public:
  explicit SurfaceRays(const TriMesh& mesh);
  ~SurfaceRays();
  SurfaceRays(SurfaceRays&&) noexcept;
  SurfaceRays& operator=(SurfaceRays&&) noexcept;

  // The distance from from_m along the unit `direction` to the first face the segment of length max_m
  // crosses leaving the solid (through a face's outside: faces counter-clockwise seen from outside; by
  // mesh::segmentTriangle), or +infinity when it leaves through none (or for non-finite input). A start a
  // hair outside the surface (a chord between two points on a concave part) is not taken for the far side.
  double firstCrossing(const Eigen::Vector3d& from_m, const Eigen::Vector3d& direction, double max_m) const noexcept;

 private:
  friend std::vector<float> thicknessBelowVertices(const TriMesh&, const SurfaceRays&, double, double);
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// For each vertex v at p with outward unit normal n (the area-weighted mean of its faces' normals): the
// distance from p to the first face crossed by the ray from p - skin_m * n along -n (skin_m > 0 keeps it
// off the vertex's own faces), when it is at most max_m; +infinity beyond max_m, when the ray meets
// nothing, or for a vertex without a normal (no faces, or faces that cancel). Exact predicates, inexact constructions (CGAL's Epick). Throws std::invalid_argument
// for a negative or non-finite max_m or skin_m.
std::vector<float> thicknessBelowVertices(const TriMesh& mesh, double max_m, double skin_m);
// The same with the mesh's rays already built (`rays` made from `mesh`).
std::vector<float> thicknessBelowVertices(const TriMesh& mesh, const SurfaceRays& rays, double max_m, double skin_m);

}  // namespace incise::mesh
