// The surface cutter's seam duplication and walls (surface_cutter.h, steps 3 and 4; paper §4): an interior
// seam vertex gets a copy for the u >= 1/2 side, a column of wall vertices below the pair down to the
// blade's depth, and strips of wall faces between neighbouring columns, so the cut surface stays a closed
// two-manifold. The incision's other steps are in surface_cutter.cpp.
#include <algorithm>
#include <array>
#include <vector>

#include "incise/cutting/surface_cutter.h"
#include "surface_cutter_internal.h"

namespace incise::cutting {

using detail::FH;
using detail::kKeepIsolatedVertices;
using detail::segmentKey;
using detail::VH;

bool SurfaceCutter::duplicate(VH c) {
  TriMesh& m = mesh_.mesh();
  // The faces around c in counter-clockwise order with their side (from their other vertices).
  struct Around {
    FH face;
    int side;
  };
  std::vector<Around> around;
  for (auto f = m.vf_ccwiter(c); f.is_valid(); ++f) {
    int side = 0;
    for (auto v = m.fv_iter(*f); v.is_valid(); ++v)
      if (*v != c && sideOf(*v) != 0) side = sideOf(*v);
    around.push_back({*f, side});
  }
  const auto minus = std::find_if(around.begin(), around.end(), [](const Around& a) { return a.side == -1; });
  if (minus == around.end() ||
      std::none_of(around.begin(), around.end(), [](const Around& a) { return a.side == 1; })) {
    fail("seam vertex " + std::to_string(c.idx()) + " does not separate two sides");
    return false;
  }
  std::rotate(around.begin(), minus, around.end());  // the + faces now form one run
  struct Triangle {
    VH v[3];
    FaceKind kind;
  };
  std::vector<Triangle> plus;
  for (const Around& a : around) {
    if (a.side != 1) continue;
    Triangle t;
    int i = 0;
    for (auto v = m.fv_ccwiter(a.face); v.is_valid() && i < 3; ++v) t.v[i++] = *v;
    t.kind = mesh_.kind(a.face);
    plus.push_back(t);
  }
  for (const Around& a : around)
    if (a.side == 1) {
      faceChanged(a.face);
      m.delete_face(a.face, kKeepIsolatedVertices);
    }
  VertexData copy = data(c);
  const VH c_plus = addBoundVertex(copy.rest_m, copy.uvw, 1, VertexKind::Seam);
  data(c).side = -1;
  data(c).doubled = true;
  setStencil(c);  // now evaluated on the u < 1/2 side: move it even if no column changes again
  dirty_.push_back(c);
  data(c_plus).seam = false;
  for (Triangle& t : plus) {
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
  }
  WallColumn column;
  column.minus.push_back(c);
  column.plus.push_back(c_plus);
  columns_[c.idx()] = column;
  return true;
}

int SurfaceCutter::sideOf(VH v) const {
  if (bound(v)) return data(v).side == -1 || data(v).side == 1 ? data(v).side : 0;
  if (!allColumnsDone()) return 0;  // it may still be bound by a later column
  // Never bound (beyond the lattice): Eq. (2) read backwards tells its side.
  const Eigen::Vector3d guess = incision_->inversionGuess(toEigen(mesh_.mesh().point(v)), next_column_ - 1);
  return guess[0] < 0.5 ? -1 : 1;
}

bool SurfaceCutter::sidesKnown(VH c) const {
  // A split edge's seam vertex always has a side vertex in each face; a vertex snapped onto the cut may
  // have faces whose only off-seam vertex lies in the next slab, not yet bound.
  const TriMesh& m = mesh_.mesh();
  for (auto f = m.cvf_iter(c); f.is_valid(); ++f) {
    bool known = false;
    for (auto v = m.cfv_iter(*f); v.is_valid() && !known; ++v) known = *v != c && sideOf(*v) != 0;
    if (!known) return false;
  }
  return true;
}

void SurfaceCutter::buildWallColumn(VH c) {
  WallColumn& column = columns_[c.idx()];
  const VertexData d = data(c);
  const int rows = options_.wall_rows;
  const double w0 = d.uvw[2], w1 = incision_->bottomW();
  for (int r = 1; r <= rows; ++r) {
    const Eigen::Vector3d uvw(0.5, d.uvw[1], w0 + (w1 - w0) * r / rows);
    const Eigen::Vector3d rest_m = incision_->rest().evaluateUnchecked(uvw[0], uvw[1], uvw[2]);
    if (r == rows) {
      const VH bottom = addBoundVertex(rest_m, uvw, 2, VertexKind::Wall);
      column.minus.push_back(bottom);
      column.plus.push_back(bottom);
    } else {
      column.minus.push_back(addBoundVertex(rest_m, uvw, -1, VertexKind::Wall));
      column.plus.push_back(addBoundVertex(rest_m, uvw, 1, VertexKind::Wall));
    }
  }
}

void SurfaceCutter::deleteStrip(VH a, VH b) {
  const auto it = strips_.find(segmentKey(a, b));
  if (it == strips_.end()) return;
  for (const FH f : it->second)
    if (!mesh_.mesh().status(f).deleted()) {
      faceChanged(f);
      mesh_.mesh().delete_face(f, kKeepIsolatedVertices);
    }
  strips_.erase(it);
}

bool SurfaceCutter::addStripSide(const std::vector<VH>& a, const std::vector<VH>& b, std::vector<FH>& faces) {
  TriMesh& m = mesh_.mesh();
  // The lip edge a[0]-b[0] has a surface face on one side: the wall uses its free (boundary) direction.
  const auto h = m.find_halfedge(a[0], b[0]);
  if (!h.is_valid())
    return fail("lip edge " + std::to_string(a[0].idx()) + "-" + std::to_string(b[0].idx()) + " is missing"), false;
  const bool forward = m.is_boundary(h);
  if (!forward && !m.is_boundary(m.opposite_halfedge_handle(h)))
    return fail("lip edge " + std::to_string(a[0].idx()) + "-" + std::to_string(b[0].idx()) + " is not open"), false;
  const std::vector<VH>& x = forward ? a : b;
  const std::vector<VH>& y = forward ? b : a;
  for (size_t r = 1; r < x.size(); ++r) {
    const std::array<std::array<VH, 3>, 2> tri = {{{x[r - 1], y[r - 1], y[r]}, {x[r - 1], y[r], x[r]}}};
    for (const auto& t : tri) {
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      const FH f = mesh_.mesh().add_face(t[0], t[1], t[2]);
      if (!f.is_valid()) return fail("could not add a wall face at seam vertex " + std::to_string(a[0].idx())), false;
      mesh_.setKind(f, FaceKind::Wall);
      faceChanged(f);
      faces.push_back(f);
    }
  }
  return true;
}

bool SurfaceCutter::buildStrip(VH a, VH b, CutStep& step) {
  const bool a_doubled = data(a).doubled, b_doubled = data(b).doubled;
  if (!a_doubled && !b_doubled) return true;
  const size_t height = static_cast<size_t>(options_.wall_rows) + 1;
  enum class Side : std::uint8_t { Minus, Plus };
  const auto side = [&](VH v, bool doubled, Side s) {
    if (!doubled) return std::vector<VH>(height, v);
    const WallColumn& c = columns_.at(v.idx());
    return s == Side::Plus ? c.plus : c.minus;
  };
  std::vector<FH> faces;
  if (!addStripSide(side(a, a_doubled, Side::Minus), side(b, b_doubled, Side::Minus), faces)) return false;
  if (!addStripSide(side(a, a_doubled, Side::Plus), side(b, b_doubled, Side::Plus), faces)) return false;
  step.wall_faces += static_cast<int>(faces.size());
  strips_[segmentKey(a, b)] = std::move(faces);
  return true;
}

}  // namespace incise::cutting
