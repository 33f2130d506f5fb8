// Private to cutting: what the global DFFD's three sources share (global_dffd.cpp: the lattice and the
// projection; global_dffd_split.cpp: the model split; global_dffd_openings.cpp: the openings left open,
// stitched or capped; global_dffd_splitter.cpp: the split of a moving model kept from frame to frame). Soup
// is the split model while it is being made: vertex positions with their provenance (source vertex or edge,
// side, plane) and triangles, all by index.
// Threads: a Soup belongs to one thread (the split keeps one per thread). Cost: see each function.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <span>

#include <Eigen/Geometry>

#include "incise/global_dffd/global_dffd.h"

namespace incise::global_dffd::detail {

// One construction of a split vertex's position, in the order the split made it: a vertex put on a plane,
// the crossing point of an edge, or a vertex duplicated on a plane; and each choice of the diagonal that
// splits a crossing face's quadrilateral piece (made from positions, so a replay must make it again).
// Replaying them on new positions of the same model, when every vertex is on the same side of every plane
// and every diagonal is chosen as before, gives the split's new positions.
struct SplitStep {
  enum class Kind : std::uint8_t { Snap, Point, Copy, Diagonal };
  Kind kind = Kind::Snap;
  int a = -1;               // Snap: the vertex put on the plane; Point: the edge's first end; Copy: the vertex copied;
                            // Diagonal: the quadrilateral's first corner (p, b, c, q: see quadDiagonalPC)
  int b = -1;               // Point: the edge's second end; Diagonal: its second corner
  double u_m = 0.0;         // Snap, Point: the plane x = u
  int c = -1, d = -1;       // Diagonal: its third and fourth corners
  bool diagonal_pc = true;  // Diagonal: the choice made (p-c, else b-q)
};

// Whether the quadrilateral p, b, c, q (a crossing face's piece beyond the plane: p on a-b, q on c-a) is
// split along p-c (triangles p b c and p c q) rather than b-q (p b q and b c q): b-q only where it is
// clearly the shorter (by 10%), so that no piece is a needless sliver (a sliver's image through F can flip)
// and a model moving rigidly keeps its choices (the margin is far above rounding's; ties stay p-c).
inline bool quadDiagonalPC(const Eigen::Vector3d& p, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& q) {
  return (b - q).squaredNorm() >= 0.81 * (p - c).squaredNorm();
}

// Where the edge a-b crosses the plane x = u (x exactly u): splitAt's and the replay's one formula.
inline Eigen::Vector3d splitPoint(const Eigen::Vector3d& pa, const Eigen::Vector3d& pb, double u) {
  const double t = (u - pa.x()) / (pb.x() - pa.x());
  Eigen::Vector3d p = pa + t * (pb - pa);
  p.x() = u;
  return p;
}

struct Soup {
  std::vector<Eigen::Vector3d> x;
  std::vector<int> source;
  std::vector<std::array<int, 2>> edge;
  std::vector<std::int8_t> side;
  std::vector<int> plane;
  std::vector<std::array<int, 3>> faces;
  std::vector<std::array<Eigen::Vector2d, 3>> uv;  // per face, its corners' texture coordinates (or none)
  std::vector<int> material;                       // per face, its material (or none)
  std::vector<int> remap;                          // compaction
  std::vector<int> touching;                       // splitAt: faces with a vertex on its plane
  std::vector<SplitStep>* steps = nullptr;         // when set, every position constructed is recorded there

  int add(const Eigen::Vector3d& p, int src, std::array<int, 2> e, int on_plane) {
    x.push_back(p);
    source.push_back(src);
    edge.push_back(e);
    side.push_back(0);
    plane.push_back(on_plane);
    return static_cast<int>(x.size()) - 1;
  }
  // Appends triangle t with its corners' texture coordinates and material (each ignored when the soup
  // carries none).
  void addFace(const std::array<int, 3>& t, const std::array<Eigen::Vector2d, 3>& corners_uv, int face_material) {
    faces.push_back(t);
    if (!uv.empty()) uv.push_back(corners_uv);
    if (!material.empty()) material.push_back(face_material);
  }
};

// The texture coordinate at point x on the segment from xa (coordinate ua) to xb (ub): x projected on it.
inline Eigen::Vector2d uvAlong(const Eigen::Vector3d& xa, const Eigen::Vector3d& xb, const Eigen::Vector2d& ua,
                               const Eigen::Vector2d& ub, const Eigen::Vector3d& x) {
  const Eigen::Vector3d d = xb - xa;
  const double length2 = d.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((x - xa).dot(d) / length2, 0.0, 1.0) : 0.0;
  return ua + t * (ub - ua);
}

// Closes each opening left by separate(): a loop of boundary edges whose vertices all lie on `plane` on
// one side. Its two halves, from its lowest-v vertex to its highest, are given the same v-values (each
// half's edges split where the other half has a vertex) and welded vertex to vertex: once F is stitched
// both halves map onto the same seam, so the weld closes the surface without a flat face. An opening that
// cannot be welded (beyond the box, a half not strictly monotone in v, a face already joining the halves,
// or a weld that would not leave a two-manifold) gets a strip of thin triangles between its halves instead,
// if that leaves a two-manifold; else it stays open. Returns the openings left open.
// Cost O((V + F) log F) plus O(F) per welded vertex.
int zipOpenings(Soup& s, int plane, const Eigen::AlignedBox3d& box);

// The soup of a model given by positions and triangles (a triangle's vertex out of range: DffdError). O(V + F).
void soupOf(std::span<const Eigen::Vector3d> positions, std::span<const std::array<int, 3>> faces, Soup& s);

// The split (splitAtDiscontinuities) of soup `s` into `split`: with Openings::Leave, s's buffers and split's
// are swapped (both keep their capacity). Cost: see splitAtDiscontinuities.
void splitSoup(Soup& s, const GlobalDffd& dffd, Openings openings, DffdSplit& split);

// Per vertex of the split: its twin across the plane (a side -1 vertex's side +1 copy and back: the same
// plane, source vertex and source edge), or -1. O(V log V).
std::vector<int> twinsOf(const DffdSplit& split);

// A mesh of the vertices x and triangles `faces` (vertex k is x[k], face f is faces[f]); DffdError
// (NotTwoManifold) naming the first face that cannot be added. O(V + F).
mesh::SurfaceMesh meshOf(const std::vector<Eigen::Vector3d>& x, const std::vector<std::array<int, 3>>& faces);

// How close to a plane splitAt puts a vertex on it (a split there would make a sliver), for `box`.
inline double snapDistance(const Eigen::AlignedBox3d& box) { return 1e-9 * box.sizes().maxCoeff(); }

}  // namespace incise::global_dffd::detail
