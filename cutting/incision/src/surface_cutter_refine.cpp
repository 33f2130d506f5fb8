// The surface cutter's local refinement ahead of the cut (surface_cutter.h; CutterOptions::refine): before a
// lattice column is cut, the skin faces whose bounding box at rest meets the column's control-point hull and
// whose longest edge is longer than refineEdgeLength() are bisected along their longest-edge propagation path
// (M.-C. Rivara, "New longest-edge algorithms for the refinement and/or improvement of unstructured
// triangulations", Int. J. Numer. Meth. Engng 40, 1997: LEPP-bisection). From a face, the path follows each
// face's longest edge into the face across it while that face's own longest edge is another, longer one; its
// last edge (the longest edge of both its faces, the terminal edge) is halved, which splits both faces along
// their longest edges. Repeated until no face in the hull is coarser than the limit: conforming (every split
// halves an edge and both its faces: no T-junction), and the angles stay bounded below.
//
// Only vertices the current incision has not bound are ever involved (the column's faces are refined before
// its vertices are bound, and earlier columns' faces were refined at their own step), and no wall is split;
// where that rule leaves no edge to split, the face stays as it is (CutStats::refine_refused). The new vertex
// lies on the edge at rest (Linear) or on the edge's PN-triangle cubic (PnTriangles, Vlachos, Peters, Boyd and
// Mitchell, "Curved PN triangles", I3D 2001), and is an Original vertex: the faces are still the skin, only finer.
//
// Which vertices have an edge longer than the limit is kept per vertex (a flag, set at construction, updated
// around every split and, when an incision begins, around the vertices the previous one moved), so a mesh
// fine everywhere costs one comparison a column, and a column elsewhere fine a look at a flag per vertex.
// Threads: the sim thread (the cutter's owner). Cost per column: O(coarse vertices within the longest edge of
// the column's hull) for the query while any vertex is flagged, plus O(valence^2) a split; a split is charged one
// unit of the call's budget, and a column's refinement pauses where the budget ends and resumes in the next
// call in the same order (the mesh does not depend on the budget). Allocation: none once the scratch has
// grown to a column's faces (reserved at construction) and while the mesh has headroom (reserveHeadroom);
// refinement stops for the column rather than grow the mesh's arrays (CutStats::refine_limited).
#include <algorithm>
#include <cmath>

#include "incise/incision/surface_cutter.h"
#include "surface_cutter_internal.h"

namespace incise::incision {

using detail::FH;
using detail::VH;
using HH = mesh::TriMesh::HalfedgeHandle;
using EH = mesh::TriMesh::EdgeHandle;

namespace {

// PnTriangles: a face around a vertex more than this off the vertex's normal puts it on a crease (degrees).
constexpr double kCreaseDeg = 30.0;

}  // namespace

double refineEdgeLength(const CutterOptions& options) noexcept {
  if (options.refine_edge_m > 0.0) return options.refine_edge_m;
  const IncisionOptions& i = options.incision;
  return 0.25 * (i.across_controls - 1) * i.alpha_m;
}

const char* toString(CutterOptions::Refine refine) noexcept {
  switch (refine) {
    case CutterOptions::Refine::Off:
      return "off";
    case CutterOptions::Refine::Linear:
      return "linear";
    case CutterOptions::Refine::PnTriangles:
      return "pn";
  }
  return "unknown";
}

HH SurfaceCutter::longestHalfedge(FH f) const {
  // Ties go to the smaller edge index, so "longer" is a strict order and the propagation path cannot cycle.
  const mesh::TriMesh& m = mesh_.mesh();
  HH best;
  double best_m = -1.0;
  for (auto h = m.cfh_iter(f); h.is_valid(); ++h) {
    const double l_m = (restPosition(m.to_vertex_handle(*h)) - restPosition(m.from_vertex_handle(*h))).norm();
    if (l_m > best_m || (l_m == best_m && m.edge_handle(*h).idx() < m.edge_handle(best).idx())) {
      best_m = l_m;
      best = *h;
    }
  }
  return best;
}

bool SurfaceCutter::refinable(FH f, const Eigen::AlignedBox3d& box) const {
  const mesh::TriMesh& m = mesh_.mesh();
  if (m.status(f).deleted() || mesh_.kind(f) == mesh::FaceKind::Wall) return false;
  auto c = m.cfv_iter(f);
  const Eigen::Vector3d a = restPosition(*c), b = restPosition(*++c), d = restPosition(*++c);
  Eigen::AlignedBox3d bounds(a);
  bounds.extend(b).extend(d);
  if (!bounds.intersects(box)) return false;  // the cheaper test first
  const double limit2 = refine_edge_m_ * refine_edge_m_;
  return (b - a).squaredNorm() > limit2 || (d - b).squaredNorm() > limit2 || (a - d).squaredNorm() > limit2;
}

EH SurfaceCutter::terminalEdge(FH f) const {
  const mesh::TriMesh& m = mesh_.mesh();
  HH h = longestHalfedge(f);
  // Each step moves to a strictly longer edge (longestHalfedge's order): the path ends; the bound is a guard.
  for (int step = 0; step < 1024; ++step) {
    const HH across = m.opposite_halfedge_handle(h);
    const FH g = m.face_handle(across);
    if (!g.is_valid() || mesh_.kind(g) == mesh::FaceKind::Wall) break;
    const HH next = longestHalfedge(g);
    if (m.edge_handle(next) == m.edge_handle(h)) break;  // the longest edge of both its faces: terminal
    h = next;
  }
  return m.edge_handle(h);
}

bool SurfaceCutter::splittable(EH e) const {
  const mesh::TriMesh& m = mesh_.mesh();
  for (int side = 0; side < 2; ++side) {
    const FH f = m.face_handle(m.halfedge_handle(e, static_cast<unsigned>(side)));
    if (!f.is_valid() || m.status(f).deleted() || mesh_.kind(f) == mesh::FaceKind::Wall) return false;
    for (auto v = m.cfv_iter(f); v.is_valid(); ++v)
      if (bound(*v)) return false;  // the cut has parameterised it: its faces are the cut's now
  }
  return true;
}

Eigen::Vector3d SurfaceCutter::restNormal(VH v) const {
  // Area-weighted normal of the skin faces around v, at rest.
  const mesh::TriMesh& m = mesh_.mesh();
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (auto f = m.cvf_iter(v); f.is_valid(); ++f) {
    if (mesh_.kind(*f) == mesh::FaceKind::Wall) continue;
    auto c = m.cfv_iter(*f);
    const Eigen::Vector3d a = restPosition(*c), b = restPosition(*++c), d = restPosition(*++c);
    n += (b - a).cross(d - a);
  }
  const double norm = n.norm();
  return norm > 0.0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::Zero();
}

bool SurfaceCutter::onCrease(VH v, const Eigen::Vector3d& normal) const {
  const mesh::TriMesh& m = mesh_.mesh();
  const double cos_crease = std::cos(kCreaseDeg * M_PI / 180.0);
  for (auto f = m.cvf_iter(v); f.is_valid(); ++f) {
    if (mesh_.kind(*f) == mesh::FaceKind::Wall) return true;  // the rim of an earlier wound
    auto c = m.cfv_iter(*f);
    const Eigen::Vector3d a = restPosition(*c), b = restPosition(*++c), d = restPosition(*++c);
    if ((b - a).cross(d - a).normalized().dot(normal) < cos_crease) return true;
  }
  return false;
}

Eigen::Vector3d SurfaceCutter::refinedPoint(HH h) const {
  const mesh::TriMesh& m = mesh_.mesh();
  const VH a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
  const Eigen::Vector3d p0 = restPosition(a), p1 = restPosition(b);
  if (options_.refine != CutterOptions::Refine::PnTriangles) return 0.5 * (p0 + p1);
  const Eigen::Vector3d n0 = restNormal(a), n1 = restNormal(b);
  // An end on a crease or a corner (a face around it more than kCreaseDeg off its normal: a CAD model's box
  // edges) has no tangent plane: PN triangles would bulge the flat faces there, so the edge is halved straight.
  if (onCrease(a, n0) || onCrease(b, n1)) return 0.5 * (p0 + p1);
  // The PN triangle's edge cubic: its inner control points are the edge's thirds projected onto the tangent
  // planes at the ends; its value at 1/2 is (p0 + 3 b1 + 3 b2 + p1) / 8.
  const Eigen::Vector3d b1 = (2.0 * p0 + p1 - (p1 - p0).dot(n0) * n0) / 3.0;
  const Eigen::Vector3d b2 = (2.0 * p1 + p0 - (p0 - p1).dot(n1) * n1) / 3.0;
  return (p0 + 3.0 * b1 + 3.0 * b2 + p1) / 8.0;
}

VH SurfaceCutter::bisect(EH e, CutStep& step) {
  mesh::TriMesh& m = mesh_.mesh();
  const Eigen::Vector3d p = refinedPoint(m.halfedge_handle(e, 0));
  const VH v = mesh_.addVertex(p, mesh::VertexKind::Original);
  adoptParents(e);
  const SplitCorners before = splitCorners(e);
  m.split_copy(e, v);  // the new faces take their split faces' kinds (Original or an earlier cut's Split) and
                       // rest parents
  cornersAfterSplit(v, 0.5, before);
  grid_.insert(v.idx(), p);
  m.property(coarse_, v) = 0;
  updateCoarseAround(v);  // the halved edge's ends, the new vertex and the faces' far corners
  vertexChanged(v);
  for (auto f = m.vf_iter(v); f.is_valid(); ++f) faceChanged(*f);
  IncisionFigures& figures = stats_.figures.back();
  ++figures.refined_vertices;
  figures.refined_faces += 2;
  ++stats_.refined_vertices;
  stats_.refined_faces += 2;
  ++step.edges_refined;
  return v;
}

void SurfaceCutter::initCoarse() {
  mesh::TriMesh& m = mesh_.mesh();
  m.add_property(coarse_, "incise:coarse");
  m.add_property(coarse_at_, "incise:coarse_at");
  m.add_property(coarse_reach_, "incise:coarse_reach");
  coarse_vertices_ = 0;
  for (const auto v : m.vertices()) {
    m.property(coarse_, v) = 0;
    updateCoarse(v);
  }
}

void SurfaceCutter::updateCoarse(VH v, bool current) {
  mesh::TriMesh& m = mesh_.mesh();
  const auto at_rest = [&](VH u) { return current ? mesh::toEigen(m.point(u)) : restPosition(u); };
  double longest_m = 0.0;
  const Eigen::Vector3d p = at_rest(v);
  for (auto n = m.cvv_iter(v); n.is_valid(); ++n) longest_m = std::max(longest_m, (at_rest(*n) - p).norm());
  const std::uint8_t coarse = longest_m > refine_edge_m_;
  m.property(coarse_reach_, v) = longest_m;
  std::uint8_t& flag = m.property(coarse_, v);
  Eigen::Vector3d& at = m.property(coarse_at_, v);
  if (coarse && !flag) {
    at = p;
    coarse_grid_.insert(v.idx(), at);
  } else if (!coarse && flag) {
    coarse_grid_.remove(v.idx(), at);
  } else if (coarse && p != at) {  // moved by an earlier incision
    coarse_grid_.move(v.idx(), at, p);
    at = p;
  }
  coarse_vertices_ += coarse - flag;
  flag = coarse;
}

void SurfaceCutter::updateCoarseAround(VH v, bool current) {
  updateCoarse(v, current);
  for (auto n = mesh_.mesh().cvv_iter(v); n.is_valid(); ++n) updateCoarse(*n, current);
}

bool SurfaceCutter::beginRefine(int column) {
  refine_faces_.clear();
  refine_splits_ = 0;
  if (coarse_vertices_ == 0) return false;  // nothing coarse anywhere: no query at all
  const mesh::TriMesh& m = mesh_.mesh();
  refine_box_ = incision_->columnBox(column);
  // Every face meeting the hull has a vertex within its longest edge of it.
  Eigen::AlignedBox3d reach = refine_box_;
  reach.min().array() -= longest_edge_m_;
  reach.max().array() += longest_edge_m_;
  refine_query_.clear();
  coarse_grid_.query(reach, refine_query_);  // a coarse face has coarse corners
  for (const int id : refine_query_) {
    const VH v(id);
    // Its faces reach no farther from it than its longest edge.
    const double reach_m = m.property(coarse_reach_, v);
    if (refine_box_.squaredExteriorDistance(m.property(coarse_at_, v)) > reach_m * reach_m) continue;
    for (auto f = m.cvf_iter(v); f.is_valid(); ++f)
      if (refinable(*f, refine_box_)) refine_faces_.push_back(f->idx());
  }
  std::sort(refine_faces_.begin(), refine_faces_.end(), std::greater<>());  // the smallest index on top
  refine_faces_.erase(std::unique(refine_faces_.begin(), refine_faces_.end()), refine_faces_.end());
  return !refine_faces_.empty();
}

bool SurfaceCutter::continueRefine(core::WorkBudget& budget, CutStep& step) {
  mesh::TriMesh& m = mesh_.mesh();
  while (!refine_faces_.empty()) {
    if (budget.spent()) return false;  // resume here next call
    const FH f(refine_faces_.back());
    refine_faces_.pop_back();
    if (!refinable(f, refine_box_)) continue;
    if (refine_splits_ >= options_.max_refine_splits_per_column || m.n_vertices() + 1 >= reserved_vertices_) {
      ++stats_.refine_limited;
      refine_faces_.clear();
      break;
    }
    EH e = terminalEdge(f);
    if (!splittable(e)) e = m.edge_handle(longestHalfedge(f));  // bisect f itself, off the path
    if (!splittable(e)) {
      ++stats_.refine_refused;
      continue;
    }
    const VH v = bisect(e, step);
    ++refine_splits_;
    budget.take();
    refine_faces_.push_back(f.idx());  // f (or what is left of it) may still be coarse
    for (auto g = m.vf_iter(v); g.is_valid(); ++g)
      if (*g != f && refinable(*g, refine_box_)) refine_faces_.push_back(g->idx());
  }
  return true;
}

}  // namespace incise::incision
