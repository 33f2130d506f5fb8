// The surface cutter's seam duplication and walls (surface_cutter.h, steps 3 and 4; paper §4): an interior
// seam vertex gets a copy for the u >= 1/2 side, a column of wall vertices below the pair down to the
// blade's depth, and strips of wall faces between neighbouring columns, so the cut surface stays a closed
// two-manifold. The incision's other steps are in surface_cutter.cpp.
#include <algorithm>
#include <array>
#include <cstdlib>
#include <vector>

#include "incise/incision/surface_cutter.h"
#include "surface_cutter_internal.h"

namespace incise::incision {

using detail::deleteFace;
using detail::FH;
using detail::VH;

bool SurfaceCutter::duplicate(VH c, VH prev, VH next) {
  mesh::TriMesh& m = mesh_.mesh();
  // The seam edges to its neighbours on the chain part the faces around c in two fans: those from the edge
  // to prev round (counter-clockwise) to the edge to next, and the others. Which fan is the u >= 1/2 side
  // the bound vertices of its faces say (a vertex beyond the lattice, or one guessed near the cut, never
  // decides alone).
  const auto to_prev = m.find_halfedge(c, prev), to_next = m.find_halfedge(c, next);
  if (!to_prev.is_valid() || !to_next.is_valid()) {
    fail("seam vertex " + std::to_string(c.idx()) + " is not joined to its neighbours on the seam");
    return false;
  }
  around_.clear();
  int votes = 0;  // + for the first fan on the u >= 1/2 side
  auto h = to_prev;
  int fan = 0;
  do {
    if (h == to_next) fan = 1;
    const FH f = m.face_handle(h);
    if (f.is_valid()) {
      for (auto v = m.fv_iter(f); v.is_valid(); ++v)
        if (*v != c && bound(*v) && !data(*v).seam && std::abs(data(*v).side) == 1)
          votes += (fan == 0 ? 1 : -1) * data(*v).side;
      pushReserved(around_, Around{f, fan});
    }
    h = m.ccw_rotated_halfedge_handle(h);
  } while (h != to_prev);
  if (votes == 0 || fan == 0) {
    fail("seam vertex " + std::to_string(c.idx()) + " does not separate two sides");
    return false;
  }
  const int plus_fan = votes > 0 ? 0 : 1;
  for (Around& a : around_) a.side = a.side == plus_fan ? 1 : -1;
  plus_.clear();
  for (const Around& a : around_) {
    if (a.side != 1) continue;
    PlusTriangle t;
    int i = 0;
    for (auto v = m.fv_ccwiter(a.face); v.is_valid() && i < 3; ++v) t.v[i++] = *v;
    t.kind = mesh_.kind(a.face);
    t.parent = m.property(rest_parent_, a.face);
    keepCorners(a.face, t);
    pushReserved(plus_, t);
  }
  for (const Around& a : around_)
    if (a.side == 1) {
      faceChanged(a.face);
      deleteFace(m, a.face);
    }
  VertexData copy = data(c);
  const VH c_plus = addBoundVertex(copy.rest_m, copy.uvw, 1, mesh::VertexKind::Seam);
  data(c).side = -1;
  data(c).doubled = true;
  setStencil(c);  // now evaluated on the u < 1/2 side: move it even if no column changes again
  pushReserved(dirty_, c);
  data(c_plus).seam = false;
  for (PlusTriangle& t : plus_) {
    for (VH& v : t.v)
      if (v == c) v = c_plus;
    const FH added = mesh_.mesh().add_face(t.v[0], t.v[1], t.v[2]);
    if (!added.is_valid()) {
      fail("could not re-attach a face to the copy of seam vertex " + std::to_string(c.idx()));
      return false;
    }
    faceChanged(added);
    mesh_.setKind(m.find_halfedge(t.v[0], t.v[1]).is_valid() ? m.face_handle(m.find_halfedge(t.v[0], t.v[1])) : FH(),
                  t.kind);
    m.property(rest_parent_, added) = t.parent;
    restoreCorners(added, t);
  }
  if (wall_columns_used_ == wall_columns_.size()) {
    ++stats_.reserve_overflows;
    wall_columns_.emplace_back();
  }
  data(c).wall_column = static_cast<int>(wall_columns_used_);
  WallColumn& column = wall_columns_[wall_columns_used_++];
  column.minus.assign(1, c);  // within the room reserved for a column, as push_back after clear
  column.plus.assign(1, c_plus);
  return true;
}

int SurfaceCutter::sideOf(VH v) const {
  if (bound(v)) return data(v).side == -1 || data(v).side == 1 ? data(v).side : 0;
  if (!allColumnsDone()) return 0;  // it may still be bound by a later column
  // Never bound (beyond the lattice): Eq. (2) read backwards tells its side.
  const Eigen::Vector3d guess = incision_->inversionGuess(mesh::toEigen(mesh_.mesh().point(v)), next_column_ - 1);
  return guess[0] < 0.5 ? -1 : 1;
}

bool SurfaceCutter::sidesKnown(VH c) const {
  // A split edge's seam vertex always has a side vertex in each face; a vertex snapped onto the cut may
  // have faces whose only off-seam vertex lies in the next slab, not yet bound.
  const mesh::TriMesh& m = mesh_.mesh();
  for (auto f = m.cvf_iter(c); f.is_valid(); ++f) {
    bool known = false;
    for (auto v = m.cfv_iter(*f); v.is_valid() && !known; ++v) known = *v != c && sideOf(*v) != 0;
    if (!known) return false;
  }
  return true;
}

void SurfaceCutter::buildWallColumn(VH c) {
  WallColumn& column = wall_columns_[static_cast<std::size_t>(data(c).wall_column)];
  const VertexData d = data(c);
  const int rows = options_.wall_rows;
  const double w0 = d.uvw[2], w1 = incision_->bottomW();
  for (int r = 1; r <= rows; ++r) {
    const Eigen::Vector3d uvw(0.5, d.uvw[1], w0 + (w1 - w0) * r / rows);
    const Eigen::Vector3d rest_m = incision_->rest().evaluateUnchecked(uvw[0], uvw[1], uvw[2]);
    if (r == rows) {
      const VH bottom = addBoundVertex(rest_m, uvw, 2, mesh::VertexKind::Wall);
      pushReserved(column.minus, bottom);
      pushReserved(column.plus, bottom);
    } else {
      pushReserved(column.minus, addBoundVertex(rest_m, uvw, -1, mesh::VertexKind::Wall));
      pushReserved(column.plus, addBoundVertex(rest_m, uvw, 1, mesh::VertexKind::Wall));
    }
  }
}

void SurfaceCutter::deleteStrip(VH a, VH b) {
  const int s = data(a).strip;
  if (s < 0 || strips_[static_cast<std::size_t>(s)].to != b) return;
  for (const FH f : strips_[static_cast<std::size_t>(s)].faces)
    if (!mesh_.mesh().status(f).deleted()) {
      faceChanged(f);
      deleteFace(mesh_.mesh(), f);
    }
  data(a).strip = -1;
}

bool SurfaceCutter::addStripSide(const std::vector<VH>& a, const std::vector<VH>& b, std::vector<FH>& faces) {
  mesh::TriMesh& m = mesh_.mesh();
  // The lip edge a[0]-b[0] has a surface face on one side: the wall uses its free (boundary) direction.
  const auto h = m.find_halfedge(a[0], b[0]);
  if (!h.is_valid())
    return fail("lip edge " + std::to_string(a[0].idx()) + "-" + std::to_string(b[0].idx()) + " is missing"), false;
  const bool forward = m.is_boundary(h);
  if (!forward && !m.is_boundary(m.opposite_halfedge_handle(h)))
    return fail("lip edge " + std::to_string(a[0].idx()) + "-" + std::to_string(b[0].idx()) + " is not open"), false;
  // Both sides split each quad along the same diagonal, a[r - 1] - b[r], only their orientation differs:
  // where the opening is small the two walls are nearly one surface, and crossing diagonals would cross.
  for (size_t r = 1; r < a.size(); ++r) {
    const std::array<std::array<VH, 3>, 2> tri =
        forward ? std::array<std::array<VH, 3>, 2>{{{a[r - 1], b[r - 1], b[r]}, {a[r - 1], b[r], a[r]}}}
                : std::array<std::array<VH, 3>, 2>{{{a[r - 1], b[r], b[r - 1]}, {a[r - 1], a[r], b[r]}}};
    for (const auto& t : tri) {
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      const FH f = mesh_.mesh().add_face(t[0], t[1], t[2]);
      if (!f.is_valid()) return fail("could not add a wall face at seam vertex " + std::to_string(a[0].idx())), false;
      mesh_.setKind(f, mesh::FaceKind::Wall);
      setWallCorners(f);
      faceChanged(f);
      pushReserved(faces, f);
    }
  }
  return true;
}

bool SurfaceCutter::buildStrip(VH a, VH b, CutStep& step) {
  const bool a_doubled = data(a).doubled, b_doubled = data(b).doubled;
  if (!a_doubled && !b_doubled) return true;
  const size_t height = static_cast<size_t>(options_.wall_rows) + 1;
  enum class Side : std::uint8_t { Minus, Plus };
  const auto side = [&](VH v, bool doubled, Side s, std::vector<VH>& out) -> const std::vector<VH>& {
    if (doubled) {
      const WallColumn& c = wall_columns_[static_cast<std::size_t>(data(v).wall_column)];
      return s == Side::Plus ? c.plus : c.minus;
    }
    out.assign(height, v);  // within the room reserved for a column
    return out;
  };
  strip_faces_.clear();
  for (const Side s : {Side::Minus, Side::Plus})
    if (!addStripSide(side(a, a_doubled, s, side_a_), side(b, b_doubled, s, side_b_), strip_faces_)) return false;
  step.wall_faces += static_cast<int>(strip_faces_.size());
  if (strips_used_ == strips_.size()) {
    ++stats_.reserve_overflows;
    strips_.emplace_back();
  }
  Strip& strip = strips_[strips_used_];
  strip.to = b;
  strip.faces.clear();
  for (const FH f : strip_faces_) pushReserved(strip.faces, f);
  data(a).strip = static_cast<int>(strips_used_++);
  return true;
}

}  // namespace incise::incision
