// The tissue surface as a solid: a closed solid cut away from it (CGAL's Boolean difference, applied to the
// mesh in place so that the elements outside the cut keep their handles), and the pieces it is made of with
// their volumes. Used by the surface cutter's through-cuts (a blade deeper than the tissue is thick).
//
// Shapes and units: SurfaceMesh in metres; volumes in m^3. Threads: differenceOf reads its tissue only (a
// worker may compute while the tissue's owner reads it), applyDifference writes it. Allocates: differenceOf
// a CGAL copy of both meshes, of the result and of the tissue (not for a real-time hot path);
// applyDifference nothing beyond the mesh's reserved room.
// Paper: none (the DFFD of §4 opens a groove; where the tissue ends under the blade, the blade's swept
// volume is removed instead, as a Boolean difference).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

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

// One connected piece of a closed surface: its faces, and the volume it encloses (the divergence theorem
// over its faces: positive for an outward-oriented closed piece).
struct Piece {
  int faces = 0;
  double volume_m3 = 0.0;
};

// The difference tissue minus solid as changes to the tissue (differenceOf), to be applied to the tissue as
// it was then (applyDifference). Indices are the tissue's OpenMesh indices; the k-th added vertex will be
// vertex `vertices_before` + k, the k-th added face face `faces_before` + k.
struct SolidDifference {
  bool ok = false;
  std::string message;                          // why it failed ("" when ok)
  int vertices_before = 0, faces_before = 0;    // the tissue's n_vertices() and n_faces() it was computed on
  std::vector<int> removed_faces;               // tissue faces deleted (replaced, or inside the solid)
  std::vector<Eigen::Vector3d> added_points_m;  // vertices added, in order
  std::vector<std::array<int, 3>> added_faces;  // faces added (corners by index, added vertices included)
  std::vector<FaceKind> added_kinds;            // their kinds
  // Their corners' texture coordinates, when the tissue has them (else empty): a piece of a tissue face
  // interpolates the face's (barycentric, at the point's projection), a face of the solid's boundary takes
  // the wall's, its corners projected on the face's plane (metres over kWallTextureTile_m).
  std::vector<std::array<Eigen::Vector2d, 3>> added_texcoords;
  // Their materials, when the tissue has them (else empty): a piece of a tissue face its face's, a face of
  // the solid's boundary 0 (it is a Wall face: written with the walls' material).
  std::vector<int> added_materials;
  std::vector<int> touched_vertices;  // corners of removed and added faces, ascending, once each
  std::vector<Piece> pieces;          // the result's pieces (mesh::pieces), largest first
  bool slivers_kept = false;          // the sliver removal made faces cross: not applied
};

// Computes tissue minus the closed solid `solid` (outward oriented) through
// CGAL::Polygon_mesh_processing::corefine_and_compute_difference (exact predicates; the input must not cross
// itself where the solid meets it), and checks that it applies (on a copy of the tissue). Reads `tissue`
// only: it may run on another thread while the owner of the tissue reads it too (never while it writes it).
// Kinds: a face on the solid's boundary is Wall; a piece of a tissue face keeps Wall if the face was a Wall
// face, else it is Split; a new vertex is Wall if all its faces are, else Seam. Needles and caps along the cut
// (edges under a fiftieth of the tissue's mean edge) are collapsed or flipped, unless that makes two faces
// near the cut cross (checked with exact predicates): then the corefined result is kept as it is
// (`slivers_kept`). Failure (CGAL refuses:
// self-intersection, a non-manifold result; OpenMesh refuses a face): `ok` false and why. Cost
// O((V + F) log (V + F)) over both meshes (the copies), plus CGAL's corefinement near the solid.
SolidDifference differenceOf(const SurfaceMesh& tissue, const SurfaceMesh& solid);

// Applies an ok difference to the tissue it was computed on, in place: faces and vertices the difference
// keeps keep their handles; removed faces and the vertices left without faces are deleted (OpenMesh's
// deleted status, no garbage collection: handles stay valid), added vertices and faces appended, normals
// updated around them. Allocates nothing when the mesh has room reserved for the added elements. Refuses
// (`ok` false, the mesh unchanged) a difference computed on a mesh of another size. Cost O(changes).
SubtractResult applyDifference(SurfaceMesh& tissue, const SolidDifference& difference) noexcept;

// differenceOf, then applyDifference. Every vertex and face index added, changed or deleted is appended to
// `changed_vertices` / `changed_faces` when they are given. On failure the mesh is unchanged.
SubtractResult subtractSolid(SurfaceMesh& tissue, const SurfaceMesh& solid,
                             std::vector<int>* changed_vertices = nullptr, std::vector<int>* changed_faces = nullptr);

// The connected pieces (faces joined through shared vertices) of `mesh`'s non-deleted faces, largest volume
// first. Cost O(V + F).
std::vector<Piece> pieces(const TriMesh& mesh);

}  // namespace incise::mesh
