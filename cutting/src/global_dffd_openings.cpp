// The openings the split leaves (§3.2): closed for the stitched treatment (zipOpenings: welded, or a strip
// as the fallback), the stitching level, the capped treatment (cappedDeform, CGAL) and the count of the
// boundary loops left open.
#include "incise/cutting/global_dffd.h"

#include <algorithm>
#include <map>

#include "global_dffd_internal.h"
#include "incise/cutting/clip_cap.h"

namespace incise::cutting {

namespace detail {

int zipOpenings(Soup& s, int plane, const Eigen::AlignedBox3d& box) {
  std::map<std::pair<int, int>, int> face_of;  // directed edge -> face
  for (size_t f = 0; f < s.faces.size(); ++f)
    for (int i = 0; i < 3; ++i) face_of[{s.faces[f][static_cast<size_t>(i)], s.faces[f][static_cast<size_t>((i + 1) % 3)]}] = static_cast<int>(f);
  std::map<int, int> next;  // boundary: a -> b with no b -> a, both on the plane with the same side
  for (const auto& [e, f] : face_of) {
    (void)f;
    const auto [a, b] = e;
    if (face_of.count({b, a})) continue;
    if (s.plane[static_cast<size_t>(a)] != plane || s.plane[static_cast<size_t>(b)] != plane) continue;
    if (s.side[static_cast<size_t>(a)] == 0 || s.side[static_cast<size_t>(a)] != s.side[static_cast<size_t>(b)]) continue;
    next[a] = b;
  }
  const auto vOf = [&](int id) { return s.x[static_cast<size_t>(id)].y(); };
  std::map<int, char> used;
  int left_open = 0;
  for (const auto& entry : next) {
    const int start = entry.first;
    if (used.count(start)) continue;
    std::vector<int> loop;
    int v = start;
    while (!used.count(v) && next.count(v)) {
      used[v] = 1;
      loop.push_back(v);
      v = next[v];
    }
    if (v != start || loop.size() < 3) continue;
    const int n = static_cast<int>(loop.size());
    int lo = 0, hi = 0;
    for (int i = 1; i < n; ++i) {
      if (vOf(loop[static_cast<size_t>(i)]) < vOf(loop[static_cast<size_t>(lo)])) lo = i;
      if (vOf(loop[static_cast<size_t>(i)]) > vOf(loop[static_cast<size_t>(hi)])) hi = i;
    }
    std::vector<int> a, b;  // a: forward along the loop (its edges a[i] -> a[i+1]); b: backward
    for (int i = lo;; i = (i + 1) % n) {
      a.push_back(loop[static_cast<size_t>(i)]);
      if (i == hi) break;
    }
    for (int i = lo;; i = (i + n - 1) % n) {
      b.push_back(loop[static_cast<size_t>(i)]);
      if (i == hi) break;
    }
    const auto monotone = [&](const std::vector<int>& c) {
      for (size_t i = 1; i < c.size(); ++i)
        if (!(vOf(c[i]) > vOf(c[i - 1]))) return false;
      return true;
    };
    // Only an opening inside the box is stitched (beyond it F is the identity: nothing maps its halves
    // together), and only when no face already joins its two halves (welding would fold it flat).
    bool weldable = monotone(a) && monotone(b);
    for (const int id : loop) weldable = weldable && box.contains(s.x[static_cast<size_t>(id)]);
    if (weldable) {
      std::map<int, int> half;
      for (size_t i = 1; i + 1 < a.size(); ++i) half[a[i]] = 1;
      for (size_t i = 1; i + 1 < b.size(); ++i) half[b[i]] = 2;
      for (const auto& f : s.faces) {
        int mask = 0;
        for (const int id : f)
          if (const auto it = half.find(id); it != half.end()) mask |= it->second;
        if (mask == 3) weldable = false;
      }
    }
    // The fallback: a strip of triangles zipped between the two halves in order of v (each triangle takes
    // two consecutive vertices of one half and one of the other, the loop's edges reversed). Once stitched
    // both halves lie on the seam, so the strip is thin; it is kept only if the result is a two-manifold.
    const auto ladder = [&] {
      std::vector<std::array<int, 3>> strip;
      size_t ia = 0, ib = 0;
      while (ia + 1 < a.size() || ib + 1 < b.size()) {
        const bool advance_a = ib + 1 >= b.size() || (ia + 1 < a.size() && vOf(a[ia + 1]) <= vOf(b[ib + 1]));
        const std::array<int, 3> f = advance_a ? std::array<int, 3>{a[ia + 1], a[ia], b[ib]} : std::array<int, 3>{b[ib], b[ib + 1], a[ia]};
        advance_a ? ++ia : ++ib;
        if (f[0] != f[1] && f[1] != f[2] && f[0] != f[2]) strip.push_back(f);
      }
      std::map<std::pair<int, int>, int> uses;
      bool manifold = true;
      for (const auto* faces : {&s.faces, &strip})
        for (const auto& f : *faces)
          for (int i = 0; i < 3 && manifold; ++i)
            manifold = ++uses[{f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]}] == 1;
      if (!manifold) return false;
      for (const auto& f : strip) {
        s.faces.push_back(f);
        for (int i = 0; i < 3; ++i) face_of[{f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]}] = static_cast<int>(s.faces.size()) - 1;
      }
      return true;
    };
    if (!weldable) {
      if (!ladder()) ++left_open;
      continue;
    }
    // Splits the chain edge p -> q (loop direction) of face f at the given points (ordered from p to q).
    const auto splitEdge = [&](int p, int q, const std::vector<int>& points) {
      const int f = face_of.at({p, q});
      auto t = s.faces[static_cast<size_t>(f)];
      while (t[0] != p) std::rotate(t.begin(), t.begin() + 1, t.end());
      const int r = t[2];
      std::vector<int> chain{p};
      chain.insert(chain.end(), points.begin(), points.end());
      chain.push_back(q);
      const auto record = [&](int face) {
        const auto& g = s.faces[static_cast<size_t>(face)];
        for (int i = 0; i < 3; ++i) face_of[{g[static_cast<size_t>(i)], g[static_cast<size_t>((i + 1) % 3)]}] = face;
      };
      face_of.erase({p, q});
      s.faces[static_cast<size_t>(f)] = {chain[0], chain[1], r};
      record(f);
      for (size_t i = 1; i + 1 < chain.size(); ++i) {
        s.faces.push_back({chain[i], chain[i + 1], r});
        record(static_cast<int>(s.faces.size()) - 1);
      }
    };
    // The merged v-sequence: each half gets a point where the other has a vertex.
    const auto insertInto = [&](const std::vector<int>& chain, const std::vector<int>& other, bool forward) {
      std::vector<int> out{chain[0]};
      size_t k = 1;
      for (size_t i = 1; i < chain.size(); ++i) {
        const int p = chain[i - 1], q = chain[i];
        std::vector<int> points;
        for (; k + 1 < other.size() && vOf(other[k]) < vOf(q); ++k) {
          if (vOf(other[k]) <= vOf(p)) continue;
          const double t = (vOf(other[k]) - vOf(p)) / (vOf(q) - vOf(p));
          Eigen::Vector3d x = s.x[static_cast<size_t>(p)] + t * (s.x[static_cast<size_t>(q)] - s.x[static_cast<size_t>(p)]);
          x.y() = vOf(other[k]);
          const int m = s.add(x, -1, {-1, -1}, plane);
          s.side[static_cast<size_t>(m)] = s.side[static_cast<size_t>(p)];
          points.push_back(m);
        }
        if (vOf(other[k]) == vOf(q) && k + 1 < other.size()) ++k;
        if (!points.empty()) {
          if (forward) {
            splitEdge(p, q, points);
          } else {
            std::vector<int> reversed(points.rbegin(), points.rend());
            splitEdge(q, p, reversed);
          }
        }
        out.insert(out.end(), points.begin(), points.end());
        out.push_back(q);
      }
      return out;
    };
    const std::vector<std::array<int, 3>> before = s.faces;
    const auto face_of_before = face_of;
    const std::vector<int> a2 = insertInto(a, b, true);
    const std::vector<int> b2 = insertInto(b, a, false);
    std::map<int, int> to;
    for (size_t i = 1; i + 1 < a2.size() && a2.size() == b2.size(); ++i) to[b2[i]] = a2[i];
    std::vector<std::array<int, 3>> welded = s.faces;
    for (auto& f : welded)
      for (int& id : f)
        if (const auto it = to.find(id); it != to.end()) id = it->second;
    // The weld must leave a two-manifold: no face folded flat, no directed edge used twice.
    std::map<std::pair<int, int>, int> uses;
    bool manifold = a2.size() == b2.size();
    for (const auto& f : welded) {
      manifold = manifold && f[0] != f[1] && f[1] != f[2] && f[0] != f[2];
      for (int i = 0; i < 3 && manifold; ++i)
        manifold = ++uses[{f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]}] == 1;
    }
    if (!manifold) {  // undo, then the strip
      s.faces = before;
      face_of = face_of_before;
      if (!ladder()) ++left_open;
      continue;
    }
    s.faces = std::move(welded);
  }
  return left_open;
}

}  // namespace detail

double stitchLevel(const DffdSplit& split, const GlobalDffd& dffd, int index) {
  double sum = 0.0;
  int count = 0;
  for (size_t v = 0; v < split.rest_m.size(); ++v)
    if (split.plane[v] == index) sum += split.rest_m[v].z(), ++count;
  return count > 0 ? sum / count : dffd.box().center().z();
}

SurfaceMesh cappedDeform(const SurfaceMesh& model, const GlobalDffd& dffd) {
  // Pieces between consecutive planes: below the first, between each pair, above the last.
  std::vector<SurfaceMesh> pieces;
  SurfaceMesh rest = model;
  for (const DffdObstacle& o : dffd.obstacles()) {
    pieces.push_back(clipAndCap(rest, 0, o.u, KeepSide::Below));
    rest = clipAndCap(rest, 0, o.u, KeepSide::Above);
  }
  pieces.push_back(std::move(rest));
  SurfaceMesh out;
  TriMesh& m = out.mesh();
  for (size_t p = 0; p < pieces.size(); ++p) {
    const TriMesh& piece = pieces[p].mesh();
    std::vector<TriMesh::VertexHandle> handles(piece.n_vertices());
    for (const auto v : piece.vertices()) {
      if (piece.status(v).deleted()) continue;
      const Eigen::Vector3d x = toEigen(piece.point(v));
      int side = 0;  // a cap vertex on the plane below this piece (+ side) or above it (- side)
      if (p > 0 && x.x() == dffd.obstacles()[p - 1].u) side = 1;
      if (p < dffd.obstacles().size() && x.x() == dffd.obstacles()[p].u) side = -1;
      handles[static_cast<size_t>(v.idx())] = m.add_vertex(toOpenMesh(dffd.map(x, side)));
    }
    for (const auto f : piece.faces()) {
      if (piece.status(f).deleted()) continue;
      std::array<TriMesh::VertexHandle, 3> t;
      int i = 0;
      for (auto v = piece.cfv_ccwiter(f); v.is_valid() && i < 3; ++v) t[static_cast<size_t>(i++)] = handles[static_cast<size_t>(v->idx())];
      m.add_face(t[0], t[1], t[2]);
    }
  }
  return out;
}

int boundaryLoops(const TriMesh& mesh) {
  std::vector<char> seen(mesh.n_halfedges(), 0);
  int loops = 0;
  for (const auto h : mesh.halfedges()) {
    if (mesh.status(h).deleted() || !mesh.is_boundary(h) || seen[static_cast<size_t>(h.idx())]) continue;
    ++loops;
    for (auto g = h; !seen[static_cast<size_t>(g.idx())]; g = mesh.next_halfedge_handle(g)) seen[static_cast<size_t>(g.idx())] = 1;
  }
  return loops;
}

}  // namespace incise::cutting
