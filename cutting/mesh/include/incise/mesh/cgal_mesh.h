// Private, for the files compiled with CGAL (the incise_cutting_cgal object library): an OpenMesh triangle
// mesh as a CGAL::Surface_mesh with the exact-predicates kernel.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include "incise/mesh/surface_mesh.h"

namespace incise::mesh::detail {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = CgalKernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<CgalPoint>;

// The non-deleted elements of `mesh`, same orientation; CGAL face i is `face_handles[i]` (OpenMesh face
// index) when given. Throws MeshError naming `who` and the face when Surface_mesh refuses a face (the mesh
// is not a two-manifold there). Cost O(V + F).
inline CgalMesh toCgal(const TriMesh& mesh, const char* who, std::vector<int>* face_handles = nullptr) {
  CgalMesh out;
  out.reserve(static_cast<CgalMesh::size_type>(mesh.n_vertices()), static_cast<CgalMesh::size_type>(mesh.n_edges()),
              static_cast<CgalMesh::size_type>(mesh.n_faces()));
  std::vector<CgalMesh::Vertex_index> index(mesh.n_vertices());
  for (const auto v : mesh.vertices()) {  // skips deleted vertices
    const auto& p = mesh.point(v);
    index[static_cast<std::size_t>(v.idx())] = out.add_vertex(CgalPoint(p[0], p[1], p[2]));
  }
  if (face_handles) face_handles->clear();
  for (const auto f : mesh.faces()) {
    std::vector<CgalMesh::Vertex_index> corners;
    for (const auto v : mesh.fv_range(f)) corners.push_back(index[static_cast<std::size_t>(v.idx())]);
    if (out.add_face(corners) == CgalMesh::null_face())
      throw MeshError(std::string(who) + ": CGAL::Surface_mesh refused face " + std::to_string(f.idx()) +
                      " (the mesh is not a two-manifold there)");
    if (face_handles) face_handles->push_back(f.idx());
  }
  return out;
}

}  // namespace incise::mesh::detail
