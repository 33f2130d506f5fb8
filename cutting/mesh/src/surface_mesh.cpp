// The surface mesh itself (surface_mesh.h): vertex and face kinds, checked element access, Loop
// subdivision. Loading and saving are in surface_mesh_io.cpp, the checks and the summary in
// surface_mesh_check.cpp.
#include "incise/mesh/surface_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include "incise/core/format.h"

namespace incise::mesh {

namespace {

constexpr const char* kVertexKindProperty = "incise:vertex_kind";
constexpr const char* kFaceKindProperty = "incise:face_kind";
constexpr const char* kTexCoordProperty = "incise:texcoord";
constexpr const char* kMaterialsProperty = "incise:materials";
constexpr const char* kFaceMaterialProperty = "incise:material";

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
  if (!mesh_.get_property_handle(texcoord_, kTexCoordProperty)) texcoord_.reset();
  if (!mesh_.get_property_handle(materials_, kMaterialsProperty) ||
      !mesh_.get_property_handle(face_material_, kFaceMaterialProperty))
    materials_.reset(), face_material_.reset();
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

const std::vector<Material>& SurfaceMesh::materials() const noexcept {
  static const std::vector<Material> kNone;
  return hasMaterials() ? mesh_.property(materials_) : kNone;
}

int SurfaceMesh::addMaterial(const Material& material) {
  if (!hasMaterials()) {
    mesh_.add_property(materials_, kMaterialsProperty);
    mesh_.add_property(face_material_, kFaceMaterialProperty);
    for (const FaceHandle f : mesh_.all_faces()) mesh_.property(face_material_, f) = 0;
  }
  std::vector<Material>& list = mesh_.property(materials_);
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i].name == material.name) {
      if (list[i].statements.empty()) list[i].statements = material.statements;
      return static_cast<int>(i);
    }
  list.push_back(material);
  return static_cast<int>(list.size()) - 1;
}

int SurfaceMesh::material(TriMesh::FaceHandle f) const {
  checkHandle(f, mesh_.n_faces(), "face");
  return hasMaterials() ? mesh_.property(face_material_, f) : -1;
}

void SurfaceMesh::setMaterial(TriMesh::FaceHandle f, int index) {
  checkHandle(f, mesh_.n_faces(), "face");
  if (!hasMaterials() || index < 0 || index >= static_cast<int>(materials().size()))
    throw std::out_of_range("SurfaceMesh::setMaterial: material " + std::to_string(index) + " of " +
                            std::to_string(materials().size()));
  mesh_.property(face_material_, f) = index;
}

void SurfaceMesh::addTexCoords() {
  if (hasTexCoords()) return;
  mesh_.add_property(texcoord_, kTexCoordProperty);
  for (const auto h : mesh_.all_halfedges()) mesh_.property(texcoord_, h) = OpenMesh::Vec2d(0.0, 0.0);
}

Eigen::Vector2d SurfaceMesh::texCoord(TriMesh::HalfedgeHandle h) const {
  if (!hasTexCoords()) throw std::logic_error("SurfaceMesh::texCoord: the mesh has no texture coordinates");
  checkHandle(h, mesh_.n_halfedges(), "halfedge");
  const OpenMesh::Vec2d& uv = mesh_.property(texcoord_, h);
  return {uv[0], uv[1]};
}

void SurfaceMesh::setTexCoord(TriMesh::HalfedgeHandle h, const Eigen::Vector2d& uv) {
  if (!hasTexCoords()) throw std::logic_error("SurfaceMesh::setTexCoord: the mesh has no texture coordinates");
  checkHandle(h, mesh_.n_halfedges(), "halfedge");
  mesh_.property(texcoord_, h) = OpenMesh::Vec2d(uv.x(), uv.y());
}

std::optional<Eigen::Vector2d> FaceCorners::at(TriMesh::VertexHandle v) const noexcept {
  for (std::size_t i = 0; i < 3; ++i)
    if (vertex[i] == v) return uv[i];
  return std::nullopt;
}

FaceCorners faceCorners(const SurfaceMesh& surface, TriMesh::FaceHandle f) {
  const TriMesh& m = surface.mesh();
  const auto property = surface.texCoordProperty();
  FaceCorners corners;
  auto h = m.halfedge_handle(f);
  for (std::size_t i = 0; i < 3; ++i, h = m.next_halfedge_handle(h)) {
    corners.vertex[i] = m.to_vertex_handle(h);
    const OpenMesh::Vec2d& uv = m.property(property, h);
    corners.uv[i] = {uv[0], uv[1]};
  }
  return corners;
}

Eigen::Vector2d interpolateTexCoord(const std::array<Eigen::Vector3d, 3>& x, const std::array<Eigen::Vector2d, 3>& uv,
                                    const Eigen::Vector3d& p) {
  const Eigen::Vector3d e1 = x[1] - x[0], e2 = x[2] - x[0], d = p - x[0];
  const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2), s = d.dot(e1), t = d.dot(e2);
  const double det = a * c - b * b;
  if (!(std::abs(det) > 0.0)) return uv[0];
  const double l1 = (c * s - b * t) / det, l2 = (a * t - b * s) / det;
  return (1.0 - l1 - l2) * uv[0] + l1 * uv[1] + l2 * uv[2];
}

std::array<Eigen::Vector2d, 3> planarTexCoords(const std::array<Eigen::Vector3d, 3>& x) {
  const Eigen::Vector3d n = (x[1] - x[0]).cross(x[2] - x[0]);
  const Eigen::Vector3d axis = std::abs(n.z()) < 0.9 * n.norm() ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d t1 = n.cross(axis).normalized(), t2 = n.normalized().cross(t1);
  std::array<Eigen::Vector2d, 3> uv;
  for (std::size_t i = 0; i < 3; ++i) uv[i] = Eigen::Vector2d(x[i].dot(t1), x[i].dot(t2)) / kWallTextureTile_m;
  return uv;
}

void boxTexCoords(SurfaceMesh& mesh, double tile_m) {
  if (!(tile_m > 0.0) || !std::isfinite(tile_m))
    throw std::invalid_argument("boxTexCoords: the tile must be finite and > 0 metres, got " +
                                core::formatNumber(tile_m));
  mesh.addTexCoords();
  TriMesh& m = mesh.mesh();
  for (const TriMesh::FaceHandle f : m.faces()) {
    std::array<TriMesh::HalfedgeHandle, 3> h;
    std::array<Eigen::Vector3d, 3> x;
    int i = 0;
    for (const TriMesh::HalfedgeHandle he : m.fh_range(f)) h[i] = he, x[i++] = toEigen(m.point(m.to_vertex_handle(he)));
    Eigen::Vector3d::Index axis = 0;
    (x[1] - x[0]).cross(x[2] - x[0]).cwiseAbs().maxCoeff(&axis);
    const int a = axis == 0 ? 2 : 0, b = axis == 1 ? 2 : 1;  // x: (z, y), y: (x, z), z: (x, y)
    for (std::size_t c = 0; c < 3; ++c) mesh.setTexCoord(h[c], Eigen::Vector2d(x[c][a], x[c][b]) / tile_m);
  }
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

namespace {

// The old vertices a new vertex of one Loop round lies between: (v, v) for an old vertex (index below
// old_vertices), the old edge's two ends for an edge vertex (its only neighbours among the old vertices).
std::vector<std::array<int, 2>> loopParents(const TriMesh& fine, int old_vertices) {
  std::vector<std::array<int, 2>> parents(fine.n_vertices(), {-1, -1});
  for (const VertexHandle v : fine.vertices()) {
    if (v.idx() < old_vertices) {
      parents[static_cast<std::size_t>(v.idx())] = {v.idx(), v.idx()};
      continue;
    }
    int found = 0;
    for (const VertexHandle n : fine.vv_range(v))
      if (n.idx() < old_vertices && found < 2) parents[static_cast<std::size_t>(v.idx())][found++] = n.idx();
  }
  return parents;
}

// The old face holding the old vertices of `ends` (two or three distinct ones; with two, the one of the
// faces at that edge whose third corner is `third`, or either when `third` is -1).
FaceHandle oldFaceOf(const TriMesh& coarse, int a, int b, int third) {
  const auto h = coarse.find_halfedge(VertexHandle(a), VertexHandle(b));
  if (!h.is_valid()) return FaceHandle();
  for (const auto side : {h, coarse.opposite_halfedge_handle(h)}) {
    const FaceHandle f = coarse.face_handle(side);
    if (!f.is_valid()) continue;
    if (third < 0) return f;
    for (const VertexHandle v : coarse.fv_range(f))
      if (v.idx() == third) return f;
  }
  return FaceHandle();
}

// One Loop round's texture coordinates and materials: each fine face lies in one coarse face and takes its
// material; its corners take the coarse face's coordinates (old vertices) or the mean of an edge's two
// (edge vertices).
void subdivideCorners(const SurfaceMesh& coarse, SurfaceMesh& fine) {
  const int old_vertices = static_cast<int>(coarse.mesh().n_vertices());
  const std::vector<std::array<int, 2>> parents = loopParents(fine.mesh(), old_vertices);
  TriMesh& m = fine.mesh();
  for (const FaceHandle f : m.faces()) {
    std::vector<int> old;  // the distinct old vertices the face's corners lie between
    for (const VertexHandle v : m.fv_range(f))
      for (const int p : parents[static_cast<std::size_t>(v.idx())])
        if (p >= 0 && std::find(old.begin(), old.end(), p) == old.end()) old.push_back(p);
    const FaceHandle parent =
        old.size() >= 2 ? oldFaceOf(coarse.mesh(), old[0], old[1], old.size() > 2 ? old[2] : -1) : FaceHandle();
    if (!parent.is_valid()) continue;  // not a Loop round of this mesh: left as it is
    if (coarse.hasMaterials()) m.property(fine.materialProperty(), f) = coarse.material(parent);
    if (!coarse.hasTexCoords()) continue;
    const FaceCorners corners = faceCorners(coarse, parent);
    for (const auto h : m.fh_range(f)) {
      const auto& [a, b] = parents[static_cast<std::size_t>(m.to_vertex_handle(h).idx())];
      const Eigen::Vector2d uv = 0.5 * (corners.at(VertexHandle(a)).value_or(Eigen::Vector2d::Zero()) +
                                        corners.at(VertexHandle(b)).value_or(Eigen::Vector2d::Zero()));
      m.property(fine.texCoordProperty(), h) = OpenMesh::Vec2d(uv.x(), uv.y());
    }
  }
}

}  // namespace

SurfaceMesh subdivided(const SurfaceMesh& surface, int iterations) {
  if ((surface.hasTexCoords() || surface.hasMaterials()) && iterations > 0) {
    SurfaceMesh coarse(subdivideLoop(surface.mesh(), 0));  // garbage-collected: indices as the rounds see them
    for (int round = 0; round < iterations; ++round) {
      SurfaceMesh fine(subdivideLoop(coarse.mesh(), 1));
      subdivideCorners(coarse, fine);
      coarse = std::move(fine);
    }
    return subdivided(coarse, 0);
  }
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
