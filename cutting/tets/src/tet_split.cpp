#include "tet_split.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace incise::tets::detail {
namespace {

// Where a convex piece is coned from: FromVertex, one of its own vertices whose faces are fans from it (a
// Steiner point only if none is); SteinerPoint, always a point inside it (when a vertex apex made a flat tet).
enum class Apex : std::uint8_t { FromVertex, SteinerPoint };

// Faces opposite node f, counter-clockwise seen from outside (as tet_mesh.cpp).
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
constexpr int kCutFace = 4;
constexpr int kMaxLocal = 12;  // 4 nodes, 6 edge points, 2 Steiner points

int edgeIndex(int a, int b) {
  for (int e = 0; e < 6; ++e)
    if ((kTetEdges[e][0] == a && kTetEdges[e][1] == b) || (kTetEdges[e][0] == b && kTetEdges[e][1] == a)) return e;
  return -1;
}

struct Tri {
  std::array<int, 3> v;  // local vertex indices
  int face;              // 0..3: the tet face it lies on; kCutFace: the cut
};

// The tet's vertices in local numbering: 0..3 nodes, 4 + e the point on edge e, 10 and 11 Steiner points.
struct Local {
  std::array<int, kMaxLocal> id{};
  std::array<Eigen::Vector3d, kMaxLocal> x;
  std::array<int, kMaxLocal> sign{};
  std::array<bool, kMaxLocal> present{};
  int steiner = 10;
};

Local localVertices(const SplitInput& in) {
  Local l;
  for (int i = 0; i < 4; ++i) {
    l.id[i] = in.nodes[i].id, l.x[i] = in.nodes[i].x_m, l.sign[i] = in.nodes[i].sign, l.present[i] = true;
  }
  for (int e = 0; e < 6; ++e) {
    const SplitVertex& p = in.edge_points[e];
    l.present[4 + e] = p.id >= 0;
    l.id[4 + e] = p.id, l.x[4 + e] = p.x_m, l.sign[4 + e] = 0;
  }
  return l;
}

bool onFace(int p, int face, const Local& l) {
  if (face == kCutFace) return l.sign[p] == 0;
  if (p < 4) return p != face;
  if (p >= 10) return false;
  const int e = p - 4;
  return kTetEdges[e][0] != face && kTetEdges[e][1] != face;
}

// The face's polygon (corners and edge points, counter-clockwise from outside) cut into triangles by the
// face-local rule of the header.
int triangulateFace(int face, const Local& l, Tri* out) {
  int poly[6], n = 0, corner_at[6];
  for (int k = 0; k < 3; ++k) {
    const int a = kFace[face][k], b = kFace[face][(k + 1) % 3];
    corner_at[n] = 1, poly[n++] = a;
    const int p = 4 + edgeIndex(a, b);
    if (l.present[p]) corner_at[n] = 0, poly[n++] = p;
  }
  const auto at = [&](int i) { return poly[((i % n) + n) % n]; };
  if (n == 3) {
    out[0] = {{poly[0], poly[1], poly[2]}, face};
    return 1;
  }
  if (n == 4) {
    int i = 0;
    while (corner_at[i]) ++i;
    out[0] = {{at(i), at(i + 1), at(i + 2)}, face};
    out[1] = {{at(i), at(i + 2), at(i + 3)}, face};
    return 2;
  }
  // n == 5: two points x = at(i), y = at(i + 2) around the corner at(i + 1); the quad y, q, r, x remains.
  int i = 0;
  while (corner_at[i] || corner_at[(i + 2) % 5]) ++i;
  const int x = at(i), c = at(i + 1), y = at(i + 2), q = at(i + 3), r = at(i + 4);
  out[0] = {{x, c, y}, face};
  const double d_yr = (l.x[y] - l.x[r]).norm(), d_qx = (l.x[q] - l.x[x]).norm();
  const bool via_yr = d_yr != d_qx ? d_yr < d_qx : std::min(l.id[y], l.id[r]) < std::min(l.id[q], l.id[x]);
  if (via_yr) {
    out[1] = {{y, q, r}, face};
    out[2] = {{y, r, x}, face};
  } else {
    out[1] = {{y, q, x}, face};
    out[2] = {{q, r, x}, face};
  }
  return 3;
}

// The cut polygon (edge points and zero nodes), in cyclic order, as one or two triangles.
int triangulateCut(const Local& l, Tri* out) {
  int poly[4], n = 0;
  Eigen::Vector3d plus = Eigen::Vector3d::Zero(), minus = Eigen::Vector3d::Zero();
  int n_plus = 0, n_minus = 0;
  for (int i = 0; i < 10; ++i) {
    if (!l.present[i]) continue;
    if (l.sign[i] == 0 && n < 4) poly[n++] = i;
    if (l.sign[i] > 0) plus += l.x[i], ++n_plus;
    if (l.sign[i] < 0) minus += l.x[i], ++n_minus;
  }
  if (n < 3) return 0;
  if (n == 3) {
    out[0] = {{poly[0], poly[1], poly[2]}, kCutFace};
    return 1;
  }
  // Four points: order them by angle about the axis from the - nodes to the + nodes.
  const Eigen::Vector3d axis = (plus / n_plus - minus / n_minus).normalized();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) centre += l.x[poly[k]] / 4.0;
  const Eigen::Vector3d e1 = (l.x[poly[0]] - centre - axis.dot(l.x[poly[0]] - centre) * axis).normalized();
  const Eigen::Vector3d e2 = axis.cross(e1);
  double angle[4];
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d d = l.x[poly[k]] - centre;
    angle[k] = std::atan2(d.dot(e2), d.dot(e1));
  }
  int order[4] = {0, 1, 2, 3};
  std::sort(order, order + 4, [&](int a, int b) { return angle[a] < angle[b]; });
  const int a = poly[order[0]], b = poly[order[1]], c = poly[order[2]], d = poly[order[3]];
  if ((l.x[a] - l.x[c]).norm() <= (l.x[b] - l.x[d]).norm()) {
    out[0] = {{a, b, c}, kCutFace};
    out[1] = {{a, c, d}, kCutFace};
  } else {
    out[0] = {{a, b, d}, kCutFace};
    out[1] = {{b, c, d}, kCutFace};
  }
  return 2;
}

double signedVolume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

bool contains(const Tri& t, int p) { return t.v[0] == p || t.v[1] == p || t.v[2] == p; }

// Cones one convex piece (its boundary triangles) into children.
void conePiece(const Tri* tris, int n_tris, int side, Apex apex_choice, Local& l, SteinerSink& steiner, SubTet* out,
               SplitResult& result) {
  int apex = -1;
  for (int p = 0; p < 10 && apex_choice == Apex::FromVertex && apex < 0; ++p) {
    bool in_piece = false, fanned = true;
    for (int t = 0; t < n_tris; ++t) {
      in_piece = in_piece || contains(tris[t], p);
      if (onFace(p, tris[t].face, l) && !contains(tris[t], p)) fanned = false;
    }
    if (in_piece && fanned) apex = p;
  }
  if (apex < 0) {
    bool used[kMaxLocal] = {};
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int count = 0;
    for (int t = 0; t < n_tris; ++t)
      for (int v : tris[t].v)
        if (!used[v]) used[v] = true, mean += l.x[v], ++count;
    apex = l.steiner++;
    l.x[apex] = mean / count;
    l.sign[apex] = side;
    l.present[apex] = true;
    l.id[apex] = steiner.add(l.x[apex], side);
  }
  for (int t = 0; t < n_tris; ++t) {
    if (apex < 10 && onFace(apex, tris[t].face, l)) continue;
    std::array<int, 4> v = {tris[t].v[0], tris[t].v[1], tris[t].v[2], apex};
    double vol = signedVolume(l.x[v[0]], l.x[v[1]], l.x[v[2]], l.x[v[3]]);
    if (vol < 0) std::swap(v[1], v[2]), vol = -vol;
    if (result.count == 0 || vol < result.min_volume_m3) result.min_volume_m3 = vol;
    SubTet& s = out[result.count++];
    s.nodes = {l.id[v[0]], l.id[v[1]], l.id[v[2]], l.id[v[3]]};
    s.side = static_cast<std::int8_t>(side);
    // A face of a cut piece whose three vertices lie on the cut (edge points, zero nodes) lies in the cut
    // plane, so on the piece's boundary: the cut polygon, whichever vertex the piece was coned from.
    s.cut_faces = 0;
    for (int i = 0; i < 4 && side != 0; ++i) {
      bool on_cut = true;
      for (int j = 0; j < 4; ++j) on_cut = on_cut && (j == i || l.sign[v[j]] == 0);
      if (on_cut) s.cut_faces = static_cast<std::uint8_t>(s.cut_faces | (1u << i));
    }
  }
}

bool degenerate(const SplitResult& r, const Local& l) {
  double longest = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < i; ++j) longest = std::max(longest, (l.x[i] - l.x[j]).norm());
  return !(r.min_volume_m3 > 1e-12 * longest * longest * longest);
}

SplitResult split(const SplitInput& in, SteinerSink& steiner, SubTet* out, Apex apex_choice) {
  Local l = localVertices(in);
  SplitResult result;
  Tri faces[12];
  int n_faces = 0;
  for (int f = 0; f < 4; ++f) n_faces += triangulateFace(f, l, faces + n_faces);
  if (!in.cut) {
    conePiece(faces, n_faces, 0, apex_choice, l, steiner, out, result);
    return result;
  }
  Tri cut[2];
  const int n_cut = triangulateCut(l, cut);
  for (const int side : {-1, 1}) {
    Tri piece[14];
    int n = 0;
    for (int t = 0; t < n_faces; ++t) {
      const Tri& tri = faces[t];
      const bool on_side =
          std::all_of(tri.v.begin(), tri.v.end(), [&](int v) { return l.sign[v] == 0 || l.sign[v] == side; }) &&
          std::any_of(tri.v.begin(), tri.v.end(), [&](int v) { return l.sign[v] == side; });
      if (on_side) piece[n++] = tri;
    }
    for (int t = 0; t < n_cut; ++t) piece[n++] = cut[t];
    conePiece(piece, n, side, apex_choice, l, steiner, out, result);
  }
  return result;
}

}  // namespace

SplitResult splitTet(const SplitInput& input, SteinerSink& steiner, SubTet* out) {
  int zeros = 0, nonzero = -1;
  for (int i = 0; i < 4; ++i) input.nodes[i].sign == 0 ? ++zeros : nonzero = i;
  if (input.cut && zeros == 3) {  // a face on the cut: no split, the face is marked
    SplitResult r;
    r.count = 1;
    out[0].nodes = {input.nodes[0].id, input.nodes[1].id, input.nodes[2].id, input.nodes[3].id};
    out[0].side = static_cast<std::int8_t>(input.nodes[nonzero].sign);
    out[0].cut_faces = static_cast<std::uint8_t>(1u << nonzero);
    const auto& x = input.nodes;
    r.min_volume_m3 = signedVolume(x[0].x_m, x[1].x_m, x[2].x_m, x[3].x_m);
    return r;
  }
  SplitResult r = split(input, steiner, out, Apex::FromVertex);
  if (degenerate(r, localVertices(input))) {  // a vertex apex made a flat child: cone from inside instead
    r = split(input, steiner, out, Apex::SteinerPoint);
    r.degenerate = degenerate(r, localVertices(input));
  }
  return r;
}

}  // namespace incise::tets::detail
