// The surface cutter's seam (surface_cutter.h, step 3; paper §4): the chain of seam vertices walked along
// the cut, carried to the cut's ends, its interior vertices duplicated (their walls: surface_cutter_walls.cpp),
// and the groove's length along it.
#include <algorithm>
#include <cmath>
#include <limits>

#include "incise/incision/surface_cutter.h"
#include "surface_cutter_internal.h"

namespace incise::incision {

using detail::FH;
using detail::VH;

bool SurfaceCutter::opensAt(double v) const noexcept {
  // Within a tenth of a spacing of the cut's ends the opening is below a nanometre (it rises as the cube of
  // the distance): the lips there are one surface, not two.
  constexpr double kClosedV = 0.1;
  return v > incision_->startV() + kClosedV && (!incision_->finished() || v < incision_->lastStationV() - kClosedV);
}

void SurfaceCutter::capSeamEnds(CutStep& step) {
  if (chain_.empty() || seam_capped_) return;
  seam_capped_ = true;
  for (const bool at_tip : {true, false}) {
    const VH end = at_tip ? chain_.back() : chain_.front();
    // Where the cut ends the opening is 0 on both sides: an end there needs no cap.
    if (!opensAt(data(end).uvw[1])) continue;
    const VH cap = crossBeyond(end);
    if (!cap.is_valid()) {
      ++stats_.figures.back().uncapped_ends;
      continue;
    }
    data(cap).chained = true;
    ++step.edges_split;
    if (!(at_tip ? chain_.pushBack(cap) : chain_.pushFront(cap))) ++stats_.reserve_overflows;
  }
}

VH SurfaceCutter::crossBeyond(VH end) {
  mesh::TriMesh& m = mesh_.mesh();
  // The edge opposite `end` in one of its faces whose end points lie on the two sides: where the cut's
  // plane leaves that face. Its crossing lies beyond the cut's end (it was not split), where the opening is
  // 0 on both sides.
  for (auto h = m.voh_iter(end); h.is_valid(); ++h) {
    const auto opposite = m.next_halfedge_handle(*h);
    if (m.is_boundary(*h)) continue;
    const VH a = m.from_vertex_handle(opposite), b = m.to_vertex_handle(opposite);
    if (!bound(a) || !bound(b)) continue;
    if (data(a).seam && !data(a).chained) return a;  // on the cut already (snapped)
    if (data(b).seam && !data(b).chained) return b;
    const int sa = data(a).side, sb = data(b).side;
    if (!((sa == -1 && sb == 1) || (sa == 1 && sb == -1))) continue;
    // No sliver: an end point near the cut goes onto it, as bindVertex() and splitCrossings() do inside it.
    const double lambda = (0.5 - data(a).uvw[0]) / (data(b).uvw[0] - data(a).uvw[0]);
    const double ab_m = (data(b).rest_m - data(a).rest_m).norm();
    if (lambda * ab_m < snapDistance(a) || nearCut(a, data(a).uvw)) return snapOntoCut(a), a;
    if ((1.0 - lambda) * ab_m < snapDistance(b) || nearCut(b, data(b).uvw)) return snapOntoCut(b), b;
    return splitAtCut(m.edge_handle(opposite));
  }
  return VH();
}

namespace {

// A triangle's area over its longest edge squared: 0.433 equilateral, 0 degenerate.
double triangleQuality(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return longest2 > 0.0 ? 0.5 * (b - a).cross(c - a).norm() / longest2 : 0.0;
}

// Below this quality a face with its widest angle at a seam vertex is a sliver worth a flip (an equilateral
// face split a tenth of the way along an edge, the snap's limit, leaves about 0.04).
constexpr double kSliverQuality = 0.1;
constexpr int kMaxFlipsPerSeamVertex = 8;

}  // namespace

bool SurfaceCutter::sideVertex(VH v) const {
  if (!bound(v) || data(v).seam || mesh_.kind(v) != mesh::VertexKind::Original) return false;
  return data(v).side == -1 || data(v).side == 1;
}

void SurfaceCutter::relieveSlivers(std::size_t first_seam) {
  mesh::TriMesh& m = mesh_.mesh();
  for (std::size_t i = first_seam; i < seam_created_.size(); ++i) {
    const VH p = seam_created_[i];
    if (m.status(p).deleted() || !bound(p) || !data(p).seam || data(p).doubled) continue;
    // A flip changes the faces around p: the walk starts over after each, a few times at most.
    for (int flips = 0; flips < kMaxFlipsPerSeamVertex; ++flips) {
      bool flipped = false;
      for (auto h = m.voh_iter(p); h.is_valid() && !flipped; ++h)
        if (!m.is_boundary(*h)) flipped = flipSliver(p, m.next_halfedge_handle(*h));
      if (!flipped) break;
    }
  }
}

bool SurfaceCutter::flipSliver(VH p, mesh::TriMesh::HalfedgeHandle ab) {
  mesh::TriMesh& m = mesh_.mesh();
  const auto ba = m.opposite_halfedge_handle(ab);
  if (m.is_boundary(ab) || m.is_boundary(ba)) return false;
  const FH f = m.face_handle(ab), g = m.face_handle(ba);
  if (mesh_.kind(f) == mesh::FaceKind::Wall || mesh_.kind(g) == mesh::FaceKind::Wall || textureSeamAlong(ab))
    return false;
  const VH a = m.from_vertex_handle(ab), b = m.to_vertex_handle(ab), d = m.to_vertex_handle(m.next_halfedge_handle(ba));
  // d and the off-seam ends of a-b on one side: the new edge p-d ends on the cut and crosses nothing.
  if (!sideVertex(d) || (!sideVertex(a) && !sideVertex(b))) return false;
  for (const VH v : {a, b})
    if (sideVertex(v) ? data(v).side != data(d).side : !(bound(v) && data(v).seam)) return false;
  const Eigen::Vector3d P = restPosition(p), A = restPosition(a), B = restPosition(b), D = restPosition(d);
  const double ab2 = (B - A).squaredNorm();
  const double q_old = triangleQuality(P, A, B);
  if (q_old >= kSliverQuality || ab2 < (A - P).squaredNorm() || ab2 < (B - P).squaredNorm()) return false;
  // Faces p a b and b a d become p a d and p d b, facing the way they did; the worse of the two improves
  // (so flips cannot cycle).
  const Eigen::Vector3d normal = (A - P).cross(B - P) + (A - B).cross(D - B);
  if ((A - P).cross(D - P).dot(normal) <= 0.0 || (D - P).cross(B - P).dot(normal) <= 0.0) return false;
  const double q_new = std::min(triangleQuality(P, A, D), triangleQuality(P, D, B));
  if (q_new <= std::min(q_old, triangleQuality(B, A, D)) || !m.is_flip_ok(m.edge_handle(ab))) return false;
  adoptParent(f);
  adoptParent(g);
  const std::optional<mesh::FaceCorners> was_f = textured_ ? std::optional(mesh::faceCorners(mesh_, f)) : std::nullopt;
  const std::optional<mesh::FaceCorners> was_g = textured_ ? std::optional(mesh::faceCorners(mesh_, g)) : std::nullopt;
  m.flip(m.edge_handle(ab));
  afterFlip(f, g);
  if (textured_) cornersAfterFlip(f, g, *was_f, *was_g);
  for (const FH face : {f, g}) {
    mesh_.setKind(face, mesh::FaceKind::Split);
    faceChanged(face);
  }
  ++stats_.slivers_flipped;
  return true;
}

VH SurfaceCutter::splitAtCut(mesh::TriMesh::EdgeHandle e) {
  mesh::TriMesh& m = mesh_.mesh();
  const auto h = m.halfedge_handle(e, 0);
  const VertexData& da = data(m.from_vertex_handle(h));
  const VertexData& db = data(m.to_vertex_handle(h));
  const double lambda = (0.5 - da.uvw[0]) / (db.uvw[0] - da.uvw[0]);
  Eigen::Vector3d uvw = (1.0 - lambda) * da.uvw + lambda * db.uvw;
  uvw[0] = 0.5;
  const Eigen::Vector3d rest_m = (1.0 - lambda) * da.rest_m + lambda * db.rest_m;
  const bool wall = !m.is_boundary(h) && !m.is_boundary(m.opposite_halfedge_handle(h)) &&
                    mesh_.kind(m.face_handle(h)) == mesh::FaceKind::Wall &&
                    mesh_.kind(m.face_handle(m.opposite_halfedge_handle(h))) == mesh::FaceKind::Wall;
  const VH v = addBoundVertex(rest_m, uvw, 0, mesh::VertexKind::Seam);
  adoptParents(e);
  const SplitCorners before = splitCorners(e);
  m.split_copy(e, v);  // the new faces take their split faces' rest parents (their kinds are set below)
  cornersAfterSplit(v, lambda, before);
  for (auto f = m.vf_iter(v); f.is_valid(); ++f) {  // the two faces split and the two new ones
    mesh_.setKind(*f, wall ? mesh::FaceKind::Wall : mesh::FaceKind::Split);
    faceChanged(*f);
  }
  data(v).seam = true;
  ++stats_.figures.back().seam_vertices;
  ++stats_.edges_split;
  return v;
}

void SurfaceCutter::walkChain() {
  mesh::TriMesh& m = mesh_.mesh();
  if (chain_.empty()) {
    if (seam_created_.empty()) return;
    if (!chain_.pushBack(seam_created_.front())) ++stats_.reserve_overflows;
    data(chain_.front()).chained = true;
  }
  // Extend at the tip (larger v preferred) and at the start (smaller v preferred).
  for (const bool at_tip : {true, false}) {
    while (true) {
      const VH end = at_tip ? chain_.back() : chain_.front();
      VH next;
      for (auto n = m.vv_iter(end); n.is_valid(); ++n) {
        if (!bound(*n) || !data(*n).seam || data(*n).chained) continue;
        if (!next.is_valid() || (at_tip ? data(*n).uvw[1] > data(next).uvw[1] : data(*n).uvw[1] < data(next).uvw[1]))
          next = *n;
      }
      if (!next.is_valid()) break;
      data(next).chained = true;
      if (!(at_tip ? chain_.pushBack(next) : chain_.pushFront(next))) ++stats_.reserve_overflows;
    }
  }
}

void SurfaceCutter::promoteInterior(CutStep& step) {
  for (size_t i = 1; i + 1 < chain_.size() && !failed_; ++i) {
    const VH c = chain_[i];
    if (data(c).doubled || !opensAt(data(c).uvw[1])) continue;  // the lips stay closed at the cut's ends
    if (!allColumnsDone() && !sidesKnown(c)) break;             // its neighbours' sides come with a later column
    const VH prev = chain_[i - 1], next = chain_[i + 1];
    deleteStrip(prev, c);
    deleteStrip(c, next);
    if (!duplicate(c, prev, next)) return;
    buildWallColumn(c);
    ++step.vertices_duplicated;
    ++stats_.vertices_duplicated;
    if (!buildStrip(prev, c, step) || !buildStrip(c, next, step)) return;
  }
}

double SurfaceCutter::grooveLength() const noexcept {
  // The chain within the cut's ends (a cap reaches a little beyond them, where the lips stay shut).
  const double v0 = incision_->startV();
  const double v1 = incision_->finished() ? incision_->lastStationV() : std::numeric_limits<double>::infinity();
  double length_m = 0.0;
  for (size_t i = 1; i < chain_.size(); ++i) {
    const VertexData &a = data(chain_[i - 1]), &b = data(chain_[i]);
    const double lo = std::min(a.uvw[1], b.uvw[1]), hi = std::max(a.uvw[1], b.uvw[1]);
    const double inside = hi > lo ? std::clamp((std::min(hi, v1) - std::max(lo, v0)) / (hi - lo), 0.0, 1.0)
                                  : (lo >= v0 && lo <= v1 ? 1.0 : 0.0);
    length_m += inside * (b.rest_m - a.rest_m).norm();
  }
  return length_m;
}

}  // namespace incise::incision
