// The surface mesh itself (surface_mesh.h): vertex and face kinds, checked element access, Loop
// subdivision. Loading and saving are in surface_mesh_io.cpp, the checks and the summary in
// surface_mesh_check.cpp.
#include "incise/mesh/surface_mesh.h"

#include <algorithm>
#include <string>
#include <utility>

#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include "incise/core/format.h"

namespace incise::mesh {

namespace {

constexpr const char* kVertexKindProperty = "incise:vertex_kind";
constexpr const char* kFaceKindProperty = "incise:face_kind";

using VertexHandle = TriMesh::VertexHandle;
using FaceHandle = TriMesh::FaceHandle;

}  // namespace

const char* toString(VertexKind kind) noexcept {
  switch (kind) {
    case VertexKind::Original:
      return "original";
    case VertexKind::Seam:
      return "seam";
    case VertexKind::Wall:
      return "wall";
  }
  return "unknown";
}

const char* toString(FaceKind kind) noexcept {
  switch (kind) {
    case FaceKind::Original:
      return "original";
    case FaceKind::Split:
      return "split";
    case FaceKind::Wall:
      return "wall";
  }
  return "unknown";
}

SurfaceMesh::SurfaceMesh() { attachKinds(); }

SurfaceMesh::SurfaceMesh(TriMesh mesh) : mesh_(std::move(mesh)) { attachKinds(); }

void SurfaceMesh::attachKinds() {
  if (!mesh_.get_property_handle(vertex_kind_, kVertexKindProperty))
    mesh_.add_property(vertex_kind_, kVertexKindProperty);
  if (!mesh_.get_property_handle(face_kind_, kFaceKindProperty)) mesh_.add_property(face_kind_, kFaceKindProperty);
}

namespace {
template <typename Handle>
void checkHandle(Handle h, size_t count, const char* what) {
  if (!h.is_valid() || static_cast<size_t>(h.idx()) >= count)
    throw std::out_of_range(std::string("SurfaceMesh: invalid ") + what + " handle " + std::to_string(h.idx()) + " (" +
                            std::to_string(count) + " " + what + "s)");
}
}  // namespace

VertexKind SurfaceMesh::kind(TriMesh::VertexHandle v) const {
  checkHandle(v, mesh_.n_vertices(), "vertex");
  return mesh_.property(vertex_kind_, v);
}

void SurfaceMesh::setKind(TriMesh::VertexHandle v, VertexKind kind) {
  checkHandle(v, mesh_.n_vertices(), "vertex");
  mesh_.property(vertex_kind_, v) = kind;
}

FaceKind SurfaceMesh::kind(TriMesh::FaceHandle f) const {
  checkHandle(f, mesh_.n_faces(), "face");
  return mesh_.property(face_kind_, f);
}

void SurfaceMesh::setKind(TriMesh::FaceHandle f, FaceKind kind) {
  checkHandle(f, mesh_.n_faces(), "face");
  mesh_.property(face_kind_, f) = kind;
}

TriMesh::VertexHandle SurfaceMesh::addVertex(const Eigen::Vector3d& p, VertexKind kind) {
  if (!p.allFinite())
    throw std::invalid_argument("SurfaceMesh::addVertex: non-finite point (" + core::formatNumber(p.x()) + ", " +
                                core::formatNumber(p.y()) + ", " + core::formatNumber(p.z()) + ")");
  const VertexHandle v = mesh_.add_vertex(toOpenMesh(p));
  mesh_.property(vertex_kind_, v) = kind;
  return v;
}

TriMesh::FaceHandle SurfaceMesh::addFace(TriMesh::VertexHandle v0, TriMesh::VertexHandle v1, TriMesh::VertexHandle v2,
                                         FaceKind kind) {
  for (const VertexHandle v : {v0, v1, v2}) checkHandle(v, mesh_.n_vertices(), "vertex");
  const FaceHandle f = (v0 == v1 || v0 == v2 || v1 == v2) ? FaceHandle() : mesh_.add_face(v0, v1, v2);
  if (!f.is_valid())
    throw MeshError("SurfaceMesh::addFace: OpenMesh refused face (" + std::to_string(v0.idx()) + ", " +
                    std::to_string(v1.idx()) + ", " + std::to_string(v2.idx()) +
                    "): repeated vertex, or it would make an edge or vertex non-manifold");
  mesh_.property(face_kind_, f) = kind;
  return f;
}

TriMesh subdivideLoop(const TriMesh& mesh, int iterations) {
  if (iterations < 0)
    throw std::invalid_argument("subdivideLoop: iterations must be >= 0, got " + std::to_string(iterations));
  TriMesh result = mesh;
  result.garbage_collection();
  if (iterations == 0) return result;
  size_t max_valence = 0;
  for (const VertexHandle v : result.vertices()) max_valence = std::max<size_t>(max_valence, result.valence(v));
  OpenMesh::Subdivider::Uniform::LoopT<TriMesh, double> loop;
  loop.init_weights(std::max<size_t>(max_valence + 1, 50));
  loop.attach(result);
  loop(static_cast<size_t>(iterations));
  loop.detach();
  result.update_normals();
  return result;
}

SurfaceMesh subdivided(const SurfaceMesh& surface, int iterations) {
  SurfaceMesh result(subdivideLoop(surface.mesh(), iterations));
  for (const VertexHandle v : result.mesh().vertices()) result.setKind(v, VertexKind::Original);
  for (const FaceHandle f : result.mesh().faces()) result.setKind(f, FaceKind::Original);
  return result;
}

void deleteTriangle(TriMesh& m, TriMesh::FaceHandle f) noexcept {
  m.status(f).set_deleted(true);
  TriMesh::EdgeHandle boundary_edges[3];
  TriMesh::VertexHandle corners[3];
  int n_boundary = 0, n_corners = 0;
  for (auto h = m.fh_iter(f); h.is_valid() && n_corners < 3; ++h) {
    m.set_boundary(*h);
    if (m.is_boundary(m.opposite_halfedge_handle(*h))) boundary_edges[n_boundary++] = m.edge_handle(*h);
    corners[n_corners++] = m.to_vertex_handle(*h);
  }
  for (int e = 0; e < n_boundary; ++e) {
    const auto h0 = m.halfedge_handle(boundary_edges[e], 0), h1 = m.halfedge_handle(boundary_edges[e], 1);
    const TriMesh::VertexHandle v0 = m.to_vertex_handle(h0), v1 = m.to_vertex_handle(h1);
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

}  // namespace incise::mesh
