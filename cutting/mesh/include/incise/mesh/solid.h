// The tissue surface as a solid: a closed solid cut away from it (CGAL's Boolean difference, applied to the
// mesh in place so that the elements outside the cut keep their handles), and the pieces it is made of with
// their volumes. Used by the surface cutter's through-cuts (a blade deeper than the tissue is thick).
//
// Shapes and units: SurfaceMesh in metres; volumes in m^3. Threads: any; calls on distinct meshes may run
// concurrently. Allocates: a CGAL copy of both meshes and of the result (not for a real-time hot path).
// Paper: none (the DFFD of §4 opens a groove; where the tissue ends under the blade, the blade's swept
// volume is removed instead, as a Boolean difference).
#pragma once

#include <string>
#include <vector>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh {

// What subtractSolid did. On failure (`ok` false) the mesh is as it was, element for element.
struct SubtractResult {
  bool ok = false;
  std::string message;       // why it failed ("" when ok)
  int faces_removed = 0;     // faces of the tissue deleted (replaced or inside the solid)
  int faces_added = 0;       // faces added: the tissue's faces split along the solid, and the solid's walls
  int vertices_added = 0;    // vertices added (where the surfaces cross, and the solid's corners inside)
  int vertices_removed = 0;  // vertices of the tissue inside the solid (deleted, not garbage-collected)
};

// Removes the closed solid `solid` (outward oriented) from the closed two-manifold `tissue`: afterwards
// `tissue` bounds (tissue minus solid), through CGAL::Polygon_mesh_processing::corefine_and_compute_difference
// (exact predicates; the input must not cross itself where the solid meets it). The result is applied in
// place: faces and vertices the difference keeps unchanged keep their handles; other faces are deleted, new
// vertices and faces appended (OpenMesh's deleted status, no garbage collection: handles stay valid).
// Kinds: a face on the solid's boundary is Wall; a piece of a tissue face keeps Wall if the face was a Wall
// face, else it is Split; a new vertex is Wall if all its faces are, else Seam. Every vertex and face index
// added, changed or deleted is appended to `changed_vertices` / `changed_faces` when they are given.
// Failure (CGAL refuses: self-intersection, a non-manifold result; OpenMesh refuses a face) leaves the mesh
// unchanged and says why. Cost O((V + F) log (V + F)) over both meshes (the copies), plus CGAL's
// corefinement near the solid.
SubtractResult subtractSolid(SurfaceMesh& tissue, const SurfaceMesh& solid,
                             std::vector<int>* changed_vertices = nullptr, std::vector<int>* changed_faces = nullptr);

// One connected piece of a closed surface: its faces, and the volume it encloses (the divergence theorem
// over its faces: positive for an outward-oriented closed piece).
struct Piece {
  int faces = 0;
  double volume_m3 = 0.0;
};

// The connected pieces (faces joined through shared vertices) of `mesh`'s non-deleted faces, largest volume
// first. Cost O(V + F).
std::vector<Piece> pieces(const TriMesh& mesh);

}  // namespace incise::mesh
