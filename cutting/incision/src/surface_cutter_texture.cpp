// The surface cutter's texture coordinates and materials (surface_cutter.h, "Texture coordinates"): the
// corners of the faces that splits, flips, seam duplication and walls make, and the re-attached faces'
// materials. Only on a mesh that has them.
#include <cmath>

#include "incise/incision/surface_cutter.h"
#include "surface_cutter_internal.h"

namespace incise::incision {

using detail::FH;
using detail::VH;

namespace {

void setCorner(mesh::TriMesh& m, OpenMesh::HPropHandleT<OpenMesh::Vec2d> property, mesh::TriMesh::HalfedgeHandle h,
               const Eigen::Vector2d& uv) {
  m.property(property, h) = OpenMesh::Vec2d(uv.x(), uv.y());
}

}  // namespace

SurfaceCutter::SplitCorners SurfaceCutter::splitCorners(mesh::TriMesh::EdgeHandle e) const {
  const mesh::TriMesh& m = mesh_.mesh();
  SplitCorners before;
  const auto h = m.halfedge_handle(e, 0);
  before.a = m.from_vertex_handle(h);
  before.b = m.to_vertex_handle(h);
  if (!textured_) return before;
  for (const int i : {0, 1})
    if (const FH f = m.face_handle(m.halfedge_handle(e, static_cast<unsigned>(i))); f.is_valid())
      before.side[static_cast<std::size_t>(i)] = mesh::faceCorners(mesh_, f);
  return before;
}

void SurfaceCutter::cornersAfterSplit(VH v, double lambda, const SplitCorners& before) {
  if (!textured_) return;
  mesh::TriMesh& m = mesh_.mesh();
  for (auto f = m.vf_iter(v); f.is_valid(); ++f) {
    // The face lies in the side face that holds its corners other than v (the far corner decides).
    const mesh::FaceCorners* side = nullptr;
    for (const auto& candidate : before.side) {
      if (!candidate) continue;
      bool holds = true;
      for (auto c = m.cfv_iter(*f); c.is_valid() && holds; ++c) holds = *c == v || candidate->at(*c).has_value();
      if (holds) side = &*candidate;
    }
    if (side == nullptr) continue;
    const Eigen::Vector2d at_v = (1.0 - lambda) * side->at(before.a).value_or(Eigen::Vector2d::Zero()) +
                                 lambda * side->at(before.b).value_or(Eigen::Vector2d::Zero());
    for (auto h = m.fh_iter(*f); h.is_valid(); ++h) {
      const VH w = m.to_vertex_handle(*h);
      setCorner(m, mesh_.texCoordProperty(), *h, w == v ? at_v : side->at(w).value_or(Eigen::Vector2d::Zero()));
    }
  }
}

bool SurfaceCutter::textureSeamAlong(mesh::TriMesh::HalfedgeHandle ab) const {
  const mesh::TriMesh& m = mesh_.mesh();
  const auto ba = m.opposite_halfedge_handle(ab);
  if (m.is_boundary(ab) || m.is_boundary(ba)) return false;
  if (mesh_.hasMaterials() && m.property(mesh_.materialProperty(), m.face_handle(ab)) !=
                                  m.property(mesh_.materialProperty(), m.face_handle(ba)))
    return true;
  if (!textured_) return false;
  const auto p = mesh_.texCoordProperty();
  // ab's coordinate is b's in ab's face, prev(ab)'s is a's; across the edge the other way round.
  return m.property(p, ab) != m.property(p, m.prev_halfedge_handle(ba)) ||
         m.property(p, m.prev_halfedge_handle(ab)) != m.property(p, ba);
}

void SurfaceCutter::cornersAfterFlip(FH f, FH g, const mesh::FaceCorners& was_f, const mesh::FaceCorners& was_g) {
  if (!textured_) return;
  mesh::TriMesh& m = mesh_.mesh();
  for (const FH face : {f, g})
    for (auto h = m.fh_iter(face); h.is_valid(); ++h) {
      const VH w = m.to_vertex_handle(*h);
      setCorner(m, mesh_.texCoordProperty(), *h, was_f.at(w).value_or(was_g.at(w).value_or(Eigen::Vector2d::Zero())));
    }
}

void SurfaceCutter::keepCorners(FH f, PlusTriangle& t) const {
  if (mesh_.hasMaterials()) t.material = mesh_.mesh().property(mesh_.materialProperty(), f);
  if (!textured_) return;
  const mesh::FaceCorners corners = mesh::faceCorners(mesh_, f);
  for (std::size_t k = 0; k < 3; ++k) t.uv[k] = corners.at(t.v[k]).value_or(Eigen::Vector2d::Zero());
}

void SurfaceCutter::restoreCorners(FH added, const PlusTriangle& t) {
  mesh::TriMesh& m = mesh_.mesh();
  if (mesh_.hasMaterials()) m.property(mesh_.materialProperty(), added) = t.material;
  if (!textured_) return;
  for (auto h = m.fh_iter(added); h.is_valid(); ++h)
    for (std::size_t k = 0; k < 3; ++k)
      if (m.to_vertex_handle(*h) == t.v[k]) setCorner(m, mesh_.texCoordProperty(), *h, t.uv[k]);
}

Eigen::Vector2d SurfaceCutter::wallTexCoord(VH v) const {
  if (!bound(v)) return Eigen::Vector2d::Zero();
  const Eigen::Vector3d& uvw = data(v).uvw;
  const double along_m = (uvw[1] - incision_->startV()) * incision_->options().spacing_m;
  const double span_w = incision_->bottomW() - incision_->surfaceW();
  const double down = span_w != 0.0 ? (uvw[2] - incision_->surfaceW()) / span_w : 0.0;
  const double down_m = down * incision_->options().depth_m;
  return Eigen::Vector2d(along_m, down_m) / mesh::kWallTextureTile_m;
}

void SurfaceCutter::setWallCorners(FH f) {
  if (!textured_) return;
  mesh::TriMesh& m = mesh_.mesh();
  for (auto h = m.fh_iter(f); h.is_valid(); ++h)
    setCorner(m, mesh_.texCoordProperty(), *h, wallTexCoord(m.to_vertex_handle(*h)));
}

}  // namespace incise::incision
