// The openings the split leaves (§3.2): closed for the stitched treatment (zipOpenings: welded, or a strip
// as the fallback), the stitching level and the count of the boundary loops left open. The capped
// treatment is in global_dffd_caps.cpp.
#include "incise/global_dffd/global_dffd.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <span>
#include <vector>

#include "global_dffd_internal.h"

namespace incise::global_dffd {

namespace detail {
namespace {

using Faces = std::vector<std::array<int, 3>>;
using FaceOf = std::map<std::pair<int, int>, int>;  // directed edge -> face

double vOf(const Soup& s, int id) { return s.x[static_cast<size_t>(id)].y(); }

// Enters face `face`'s three directed edges into face_of.
void record(FaceOf& face_of, const Faces& faces, int face) {
  const auto& g = faces[static_cast<size_t>(face)];
  for (int i = 0; i < 3; ++i) face_of[{g[static_cast<size_t>(i)], g[static_cast<size_t>((i + 1) % 3)]}] = face;
}

// Whether flat faces (a vertex repeated) are refused by the check.
enum class FlatFaces : std::uint8_t { Allowed, Refused };

// The one two-manifold check of the openings: no directed edge of `faces` and `more` together is used
// twice (and, if refused, no face repeats a vertex). O(F log F).
bool twoManifold(std::span<const std::array<int, 3>> faces, std::span<const std::array<int, 3>> more, FlatFaces flat) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto part : {faces, more})
    for (const auto& f : part) {
      if (flat == FlatFaces::Refused && (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])) return false;
      for (int i = 0; i < 3; ++i)
        if (++uses[{f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]}] != 1) return false;
    }
  return true;
}

// The openings on `plane`: closed chains of boundary edges a -> b (no face has b -> a) whose ends both lie
// on the plane on the same side, each from its smallest vertex index on; chains that do not close or have
// fewer than three vertices are skipped.
std::vector<std::vector<int>> openingLoops(const Soup& s, int plane, const FaceOf& face_of) {
  std::map<int, int> next;
  for (const auto& [e, f] : face_of) {
    (void)f;
    const auto [a, b] = e;
    if (face_of.count({b, a})) continue;
    if (s.plane[static_cast<size_t>(a)] != plane || s.plane[static_cast<size_t>(b)] != plane) continue;
    if (s.side[static_cast<size_t>(a)] == 0 || s.side[static_cast<size_t>(a)] != s.side[static_cast<size_t>(b)])
      continue;
    next[a] = b;
  }
  std::map<int, char> used;
  std::vector<std::vector<int>> loops;
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
    loops.push_back(std::move(loop));
  }
  return loops;
}

// An opening's two halves, from its lowest-v vertex to its highest: a forward along the loop (its edges
// a[i] -> a[i+1]), b backward.
struct Halves {
  std::vector<int> a, b;
};

Halves halvesOf(const Soup& s, const std::vector<int>& loop) {
  const int n = static_cast<int>(loop.size());
  int lo = 0, hi = 0;
  for (int i = 1; i < n; ++i) {
    if (vOf(s, loop[static_cast<size_t>(i)]) < vOf(s, loop[static_cast<size_t>(lo)])) lo = i;
    if (vOf(s, loop[static_cast<size_t>(i)]) > vOf(s, loop[static_cast<size_t>(hi)])) hi = i;
  }
  Halves h;
  for (int i = lo;; i = (i + 1) % n) {
    h.a.push_back(loop[static_cast<size_t>(i)]);
    if (i == hi) break;
  }
  for (int i = lo;; i = (i + n - 1) % n) {
    h.b.push_back(loop[static_cast<size_t>(i)]);
    if (i == hi) break;
  }
  return h;
}

bool monotoneInV(const Soup& s, const std::vector<int>& chain) {
  for (size_t i = 1; i < chain.size(); ++i)
    if (!(vOf(s, chain[i]) > vOf(s, chain[i - 1]))) return false;
  return true;
}

// Only an opening inside the box is welded (beyond it F is the identity: nothing maps its halves
// together), with both halves strictly monotone in v, and only when no face already joins its two halves
// (welding would fold it flat).
bool weldable(const Soup& s, const std::vector<int>& loop, const Halves& h, const Eigen::AlignedBox3d& box) {
  if (!monotoneInV(s, h.a) || !monotoneInV(s, h.b)) return false;
  for (const int id : loop)
    if (!box.contains(s.x[static_cast<size_t>(id)])) return false;
  std::map<int, int> half;
  for (size_t i = 1; i + 1 < h.a.size(); ++i) half[h.a[i]] = 1;
  for (size_t i = 1; i + 1 < h.b.size(); ++i) half[h.b[i]] = 2;
  for (const auto& f : s.faces) {
    int mask = 0;
    for (const int id : f)
      if (const auto it = half.find(id); it != half.end()) mask |= it->second;
    if (mask == 3) return false;
  }
  return true;
}

// The face beside strip triangle f across its edge along a half (f[0] -> f[1], the loop's edge reversed).
int besideStrip(const FaceOf& face_of, const std::array<int, 3>& f) {
  const auto it = face_of.find({f[1], f[0]});
  return it == face_of.end() ? -1 : it->second;
}

// The corners' texture coordinates of strip triangle f: each vertex's in face `beside`, or, for the one
// from the other half, in any face around it (the strip is thin once stitched). O(F) for that one (rare).
std::array<Eigen::Vector2d, 3> uvBeside(const Soup& s, const std::array<int, 3>& f, int beside) {
  std::array<Eigen::Vector2d, 3> uv{};
  for (size_t i = 0; i < 3; ++i) {
    int face = beside, corner = -1;
    for (int k = 0; beside >= 0 && k < 3; ++k)
      if (s.faces[static_cast<size_t>(beside)][static_cast<size_t>(k)] == f[i]) corner = k;
    for (size_t g = 0; corner < 0 && g < s.faces.size(); ++g)
      for (int k = 0; k < 3; ++k)
        if (s.faces[g][static_cast<size_t>(k)] == f[i]) face = static_cast<int>(g), corner = k;
    if (corner >= 0) uv[i] = s.uv[static_cast<size_t>(face)][static_cast<size_t>(corner)];
  }
  return uv;
}

// The fallback: a strip of triangles zipped between the two halves in order of v (each triangle takes two
// consecutive vertices of one half and one of the other, the loop's edges reversed). Once stitched both
// halves lie on the seam, so the strip is thin; it is added only if the result is a two-manifold (false
// otherwise, nothing changed).
bool zipStrip(Soup& s, FaceOf& face_of, const Halves& h) {
  const std::vector<int>& a = h.a;
  const std::vector<int>& b = h.b;
  Faces strip;
  size_t ia = 0, ib = 0;
  while (ia + 1 < a.size() || ib + 1 < b.size()) {
    const bool advance_a = ib + 1 >= b.size() || (ia + 1 < a.size() && vOf(s, a[ia + 1]) <= vOf(s, b[ib + 1]));
    const std::array<int, 3> f =
        advance_a ? std::array<int, 3>{a[ia + 1], a[ia], b[ib]} : std::array<int, 3>{b[ib], b[ib + 1], a[ia]};
    advance_a ? ++ia : ++ib;
    if (f[0] != f[1] && f[1] != f[2] && f[0] != f[2]) strip.push_back(f);
  }
  if (!twoManifold(s.faces, strip, FlatFaces::Allowed)) return false;
  for (const auto& f : strip) {
    const bool dressed = !s.uv.empty() || !s.material.empty();
    const int beside = dressed ? besideStrip(face_of, f) : -1;
    s.addFace(f, s.uv.empty() ? std::array<Eigen::Vector2d, 3>{} : uvBeside(s, f, beside),
              s.material.empty() || beside < 0 ? 0 : s.material[static_cast<size_t>(beside)]);
    record(face_of, s.faces, static_cast<int>(s.faces.size()) - 1);
  }
  return true;
}

// Splits the chain edge p -> q (loop direction) of its face at `points` (ordered from p to q): the face
// becomes a fan from its third vertex.
void splitChainEdge(Soup& s, FaceOf& face_of, int p, int q, const std::vector<int>& points) {
  const int f = face_of.at({p, q});
  auto t = s.faces[static_cast<size_t>(f)];
  while (t[0] != p) std::rotate(t.begin(), t.begin() + 1, t.end());
  const int r = t[2];
  std::vector<int> chain{p};
  chain.insert(chain.end(), points.begin(), points.end());
  chain.push_back(q);
  face_of.erase({p, q});
  // The points' texture coordinates along p-q in this face (before it changes).
  std::vector<Eigen::Vector2d> uv(chain.size());
  Eigen::Vector2d uv_r = Eigen::Vector2d::Zero();
  if (!s.uv.empty()) {
    const auto& corners = s.uv[static_cast<size_t>(f)];
    const auto& was = s.faces[static_cast<size_t>(f)];
    const auto at = [&](int v) { return corners[v == was[0] ? 0 : v == was[1] ? 1 : 2]; };
    const auto x = [&](int v) -> const Eigen::Vector3d& { return s.x[static_cast<size_t>(v)]; };
    for (size_t i = 0; i < chain.size(); ++i) uv[i] = uvAlong(x(p), x(q), at(p), at(q), x(chain[i]));
    uv_r = at(r);
  }
  const int material = s.material.empty() ? -1 : s.material[static_cast<size_t>(f)];
  s.faces[static_cast<size_t>(f)] = {chain[0], chain[1], r};
  if (!s.uv.empty()) s.uv[static_cast<size_t>(f)] = {uv[0], uv[1], uv_r};
  record(face_of, s.faces, f);
  for (size_t i = 1; i + 1 < chain.size(); ++i) {
    s.addFace({chain[i], chain[i + 1], r}, {uv[i], uv[i + 1], uv_r}, material);
    record(face_of, s.faces, static_cast<int>(s.faces.size()) - 1);
  }
}

// A half's direction relative to the loop's edges.
enum class Along : std::uint8_t { Loop, Reversed };

// The merged v-sequence: `chain` with a point on its edges (on `plane`, on the chain's side) wherever
// `other` has a vertex, its faces split there.
std::vector<int> matchedChain(Soup& s, FaceOf& face_of, const std::vector<int>& chain, const std::vector<int>& other,
                              int plane, Along along) {
  std::vector<int> out{chain[0]};
  size_t k = 1;
  for (size_t i = 1; i < chain.size(); ++i) {
    const int p = chain[i - 1], q = chain[i];
    std::vector<int> points;
    for (; k + 1 < other.size() && vOf(s, other[k]) < vOf(s, q); ++k) {
      if (vOf(s, other[k]) <= vOf(s, p)) continue;
      const double t = (vOf(s, other[k]) - vOf(s, p)) / (vOf(s, q) - vOf(s, p));
      Eigen::Vector3d x = s.x[static_cast<size_t>(p)] + t * (s.x[static_cast<size_t>(q)] - s.x[static_cast<size_t>(p)]);
      x.y() = vOf(s, other[k]);
      const int m = s.add(x, -1, {-1, -1}, plane);
      s.side[static_cast<size_t>(m)] = s.side[static_cast<size_t>(p)];
      points.push_back(m);
    }
    if (vOf(s, other[k]) == vOf(s, q) && k + 1 < other.size()) ++k;
    if (!points.empty()) {
      if (along == Along::Loop) {
        splitChainEdge(s, face_of, p, q, points);
      } else {
        std::vector<int> reversed(points.rbegin(), points.rend());
        splitChainEdge(s, face_of, q, p, reversed);
      }
    }
    out.insert(out.end(), points.begin(), points.end());
    out.push_back(q);
  }
  return out;
}

// The halves given the same v-values (matchedChain) and welded vertex to vertex. False, with the faces and
// face_of as they were, when the weld would not leave a two-manifold (no face folded flat, no directed
// edge used twice); the points added to s.x then stay, unused.
bool weld(Soup& s, FaceOf& face_of, const Halves& h, int plane) {
  const Faces before = s.faces;
  const auto uv_before = s.uv;
  const auto material_before = s.material;
  const FaceOf face_of_before = face_of;
  const std::vector<int> a2 = matchedChain(s, face_of, h.a, h.b, plane, Along::Loop);
  const std::vector<int> b2 = matchedChain(s, face_of, h.b, h.a, plane, Along::Reversed);
  std::map<int, int> to;
  for (size_t i = 1; i + 1 < a2.size() && a2.size() == b2.size(); ++i) to[b2[i]] = a2[i];
  Faces welded = s.faces;
  for (auto& f : welded)
    for (int& id : f)
      if (const auto it = to.find(id); it != to.end()) id = it->second;
  if (a2.size() != b2.size() || !twoManifold(welded, {}, FlatFaces::Refused)) {
    s.faces = before;
    s.uv = uv_before;
    s.material = material_before;
    face_of = face_of_before;
    return false;
  }
  s.faces = std::move(welded);
  return true;
}

}  // namespace

int zipOpenings(Soup& s, int plane, const Eigen::AlignedBox3d& box) {
  FaceOf face_of;
  for (size_t f = 0; f < s.faces.size(); ++f) record(face_of, s.faces, static_cast<int>(f));
  int left_open = 0;
  for (const std::vector<int>& loop : openingLoops(s, plane, face_of)) {
    const Halves halves = halvesOf(s, loop);
    if (weldable(s, loop, halves, box) && weld(s, face_of, halves, plane)) continue;
    if (!zipStrip(s, face_of, halves)) ++left_open;
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

int boundaryLoops(const mesh::TriMesh& mesh) {
  std::vector<char> seen(mesh.n_halfedges(), 0);
  int loops = 0;
  for (const auto h : mesh.halfedges()) {
    if (mesh.status(h).deleted() || !mesh.is_boundary(h) || seen[static_cast<size_t>(h.idx())]) continue;
    ++loops;
    for (auto g = h; !seen[static_cast<size_t>(g.idx())]; g = mesh.next_halfedge_handle(g))
      seen[static_cast<size_t>(g.idx())] = 1;
  }
  return loops;
}

}  // namespace incise::global_dffd
