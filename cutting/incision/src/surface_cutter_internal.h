// Private to the surface cutter's sources (surface_cutter.cpp: the incision's steps; surface_cutter_walls.cpp:
// the seam's duplication and the walls): the handle aliases and small helpers both use.
#pragma once

#include <utility>

#include "incise/mesh/surface_mesh.h"

namespace incise::incision::detail {

using VH = mesh::TriMesh::VertexHandle;
using FH = mesh::TriMesh::FaceHandle;

// Deletes the triangle f as OpenMesh's PolyConnectivity::delete_face(f, false) does (OpenMesh 9.0,
// src/OpenMesh/Core/Mesh/PolyConnectivity.cc, BSD-3-Clause, RWTH Aachen: the same steps in the same order,
// so the same connectivity), without its two std::vectors: allocation-free for the sim thread. The face's
// vertices stay, even when isolated (they are the seam's, re-attached to the faces that replace it). f must
// be a valid, undeleted triangle. O(1).
inline void deleteFace(mesh::TriMesh& m, FH f) noexcept {
  m.status(f).set_deleted(true);
  mesh::TriMesh::EdgeHandle boundary_edges[3];
  VH corners[3];
  int n_boundary = 0, n_corners = 0;
  for (auto h = m.fh_iter(f); h.is_valid() && n_corners < 3; ++h) {
    m.set_boundary(*h);
    if (m.is_boundary(m.opposite_halfedge_handle(*h))) boundary_edges[n_boundary++] = m.edge_handle(*h);
    corners[n_corners++] = m.to_vertex_handle(*h);
  }
  for (int e = 0; e < n_boundary; ++e) {
    const auto h0 = m.halfedge_handle(boundary_edges[e], 0), h1 = m.halfedge_handle(boundary_edges[e], 1);
    const VH v0 = m.to_vertex_handle(h0), v1 = m.to_vertex_handle(h1);
    const auto next0 = m.next_halfedge_handle(h0), prev0 = m.prev_halfedge_handle(h0);
    const auto next1 = m.next_halfedge_handle(h1), prev1 = m.prev_halfedge_handle(h1);
    m.set_next_halfedge_handle(prev0, next1);
    m.set_next_halfedge_handle(prev1, next0);
    if (m.has_edge_status()) m.status(boundary_edges[e]).set_deleted(true);
    if (m.has_halfedge_status()) {
      m.status(h0).set_deleted(true);
      m.status(h1).set_deleted(true);
    }
    if (m.halfedge_handle(v0) == h1) {
      if (next0 == h1)
        m.set_isolated(v0);
      else
        m.set_halfedge_handle(v0, next0);
    }
    if (m.halfedge_handle(v1) == h0) {
      if (next1 == h0)
        m.set_isolated(v1);
      else
        m.set_halfedge_handle(v1, next1);
    }
  }
  for (int i = 0; i < n_corners; ++i) m.adjust_outgoing_halfedge(corners[i]);
}

}  // namespace incise::incision::detail
