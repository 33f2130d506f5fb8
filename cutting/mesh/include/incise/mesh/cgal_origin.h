// Private, for the files compiled with CGAL: follows every face of a corefinement's result (CGAL's
// difference, or a clip into the input mesh itself) back to the face of the first mesh it is a piece of
// (its OpenMesh index, as toCgal's face_handles give it), or to the second mesh (kFromOther: the solid
// subtracted, the clipper's cap). Faces never split or copied keep the index they were given.
// Threads: one corefinement at a time per visitor. Cost: O(1) per face made.
#pragma once

#include <CGAL/Polygon_mesh_processing/corefinement.h>

#include "incise/mesh/cgal_mesh.h"

namespace incise::mesh::detail {

using CgalFace = CgalMesh::Face_index;
using OriginMap = CgalMesh::Property_map<CgalFace, int>;
inline constexpr int kFromOther = -2;  // a face of the second mesh (the solid, the clipper)
inline constexpr int kOriginUnknown = -1;

// Copied by CGAL's named parameters: the maps are handles onto the meshes' properties. `first` is the mesh
// whose faces carry their origins in `first_origin`; `out` the result (the same mesh for a clip in place).
struct OriginVisitor : CGAL::Polygon_mesh_processing::Corefinement::Default_visitor<CgalMesh> {
  const CgalMesh* first = nullptr;
  const CgalMesh* out = nullptr;
  OriginMap first_origin, out_origin;
  int splitting = kOriginUnknown;  // the origin of the face being split
  void before_subface_creations(CgalFace split, CgalMesh& tm) {
    splitting = &tm == first ? first_origin[split] : kFromOther;
  }
  void after_subface_created(CgalFace made, CgalMesh& tm) {
    if (&tm == first) first_origin[made] = splitting;
  }
  void after_face_copy(CgalFace from, const CgalMesh& source, CgalFace made, CgalMesh& target) {
    if (&target == out) out_origin[made] = &source == first ? first_origin[from] : kFromOther;
  }
};

// Gives every face of `mesh` (as toCgal made it, face i from OpenMesh face face_handles[i]) its origin
// in the property "f:incise_origin", which it returns.
inline OriginMap originsOf(CgalMesh& mesh, const std::vector<int>& face_handles) {
  OriginMap origin = mesh.add_property_map<CgalFace, int>("f:incise_origin", kOriginUnknown).first;
  for (const CgalFace f : mesh.faces()) origin[f] = face_handles[static_cast<std::size_t>(f.idx())];
  return origin;
}

}  // namespace incise::mesh::detail
