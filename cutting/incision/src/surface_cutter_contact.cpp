// SurfaceCutter's contact queries (surface_cutter.h): the first crossing of a segment with the skin at rest
// for the current incision (intersect), and a bounded copy of that skin around a box (skinNear, for the
// haptic part's contact proxy). Both query the vertex grids with the edge margins the refinement keeps.
#include <algorithm>
#include <cmath>

#include "incise/incision/surface_cutter.h"
#include "incise/mesh/face_walk.h"
#include "surface_cutter_internal.h"

namespace incise::incision {

using detail::FH;
using detail::VH;

void SurfaceCutter::queryRest(const Eigen::AlignedBox3d& box) const {
  // A face near the box has every corner within its longest edge of it. Without refinement: every vertex
  // within the mesh's longest edge. With it (coarse flags kept): every vertex within refine_edge_m (the faces
  // of uncoarse corners), and the coarse vertices within the longest edge (every other face has one).
  const bool flagged = options_.refine != CutterOptions::Refine::Off;
  const auto grown = [&](double margin_m) {
    Eigen::AlignedBox3d out = box;
    out.min().array() -= margin_m;
    out.max().array() += margin_m;
    return out;
  };
  query_.clear();
  grid_.query(grown(flagged ? refine_edge_m_ : longest_edge_m_), query_);
  if (flagged && coarse_vertices_ > 0) coarse_grid_.query(grown(longest_edge_m_), query_);
  const mesh::TriMesh& m = mesh_.mesh();
  if (face_stamp_.size() < m.n_faces()) face_stamp_.resize(m.n_faces() + m.n_faces() / 4, 0);
  if (++face_query_ == 0) {
    std::fill(face_stamp_.begin(), face_stamp_.end(), 0u);
    face_query_ = 1;
  }
}

bool SurfaceCutter::skipForContact(FH f) const {
  std::uint32_t& stamp = face_stamp_[static_cast<size_t>(f.idx())];
  if (stamp == face_query_) return true;  // a face is met from each of its vertices: test it once
  stamp = face_query_;
  return mesh_.kind(f) == mesh::FaceKind::Wall;  // every wound's wall: contact is with the skin
}

std::optional<mesh::SurfacePoint> SurfaceCutter::intersect(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  // Against the surface at rest for the current incision: its own walls left out, every other vertex
  // where it was when the incision began. That surface does not depend on how far the current cut's
  // work has got, so contact (and so the cut) is the same whichever frame handles a pose.
  // A long segment (a whole blade, a thickness probe) is queried piece by piece from `a`, each piece's box
  // about a grid cell: one box around a slanted 30 mm blade would hold the whole skin patch under it. Each
  // piece's faces are tested against the whole segment (the same parameter, so the same bits, as one
  // query); the march stops at the first piece that holds the best crossing so far, which then is the
  // first: a crossing in a piece has its face's corners within the query margin of that piece's box.
  if (!a.allFinite() || !b.allFinite()) return std::nullopt;
  const double length_m = (b - a).norm();
  const int pieces = static_cast<int>(std::clamp(std::ceil(length_m / grid_.cellSize()), 1.0, double(kMaxProbePieces)));
  std::optional<mesh::SurfacePoint> best;
  for (int i = 0; i < pieces; ++i) {
    const double t1 = static_cast<double>(i + 1) / pieces;
    const Eigen::Vector3d p0 = a + (static_cast<double>(i) / pieces) * (b - a);
    const Eigen::Vector3d p1 = i + 1 == pieces ? b : Eigen::Vector3d(a + t1 * (b - a));
    queryRest(Eigen::AlignedBox3d(p0.cwiseMin(p1), p0.cwiseMax(p1)));
    const std::optional<mesh::SurfacePoint> hit = mesh::detail::firstCrossingOfCorners(
        mesh_.mesh(), query_, a, b, [&](FH f) { return contactCorners(f); }, [&](FH f) { return skipForContact(f); });
    if (hit && (!best || hit->distance_m < best->distance_m ||
                (hit->distance_m == best->distance_m && hit->face.idx() < best->face.idx())))
      best = hit;
    if (best && best->distance_m <= t1 * length_m) break;
  }
  return best;
}

void SurfaceCutter::adoptParent(FH f) {
  RestParent& parent = mesh_.mesh().property(rest_parent_, f);
  if (parent.incision == incision_index_) return;
  auto corner = mesh_.mesh().cfv_iter(f);
  for (int& c : parent.corners) c = (corner++)->idx();
  parent.incision = incision_index_;
}

void SurfaceCutter::adoptParents(mesh::TriMesh::EdgeHandle e) {
  for (const int side : {0, 1})
    if (const FH f = mesh_.mesh().face_handle(mesh_.mesh().halfedge_handle(e, side)); f.is_valid()) adoptParent(f);
}

void SurfaceCutter::afterFlip(FH f, FH g) {
  // Both halves of one parent: the flipped pair lies in it still. Else each is its own.
  mesh::TriMesh& m = mesh_.mesh();
  if (m.property(rest_parent_, f).corners == m.property(rest_parent_, g).corners) return;
  for (const FH face : {f, g}) {
    m.property(rest_parent_, face).incision = kNoIncision;
    adoptParent(face);
  }
}

std::array<Eigen::Vector3d, 3> SurfaceCutter::contactCorners(FH f) const {
  const mesh::TriMesh& m = mesh_.mesh();
  std::array<Eigen::Vector3d, 3> p;
  const RestParent& parent = m.property(rest_parent_, f);
  if (parent.incision == incision_index_ && incision_index_ >= 0 &&
      options_.refine != CutterOptions::Refine::PnTriangles) {
    for (int i = 0; i < 3; ++i) p[static_cast<size_t>(i)] = restPosition(VH(parent.corners[static_cast<size_t>(i)]));
    return p;
  }
  auto corner = m.cfv_iter(f);
  for (Eigen::Vector3d& c : p) c = restPosition(*corner++);
  return p;
}

int SurfaceCutter::skinNear(const Eigen::AlignedBox3d& box, std::span<mesh::SkinTriangle> out) const {
  if (!box.min().allFinite() || !box.max().allFinite() || box.isEmpty()) return 0;
  queryRest(box);
  const mesh::TriMesh& m = mesh_.mesh();
  int found = 0;
  for (const int id : query_) {
    const VH v(id);
    if (m.status(v).deleted()) continue;
    for (auto f = m.cvf_iter(v); f.is_valid(); ++f) {
      if (skipForContact(*f)) continue;
      if (static_cast<size_t>(found) < out.size()) {
        mesh::SkinTriangle& t = out[static_cast<size_t>(found)];
        auto corner = m.cfv_iter(*f);
        for (Eigen::Vector3d& c : t.corners_m) c = restPosition(*corner++);
        t.normal = (t.corners_m[1] - t.corners_m[0]).cross(t.corners_m[2] - t.corners_m[0]).normalized();
      }
      ++found;
    }
  }
  return found;
}

}  // namespace incise::incision
