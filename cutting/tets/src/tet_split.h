// Private: the conforming subdivision of one tetrahedron by the cut's level set (tet_cutter.cpp).
//
// Input: the tet's four nodes (positively oriented), each with the sign of phi = u - 1/2 there (-1, 0 on
// the cut, +1), and the points already placed on its edges (local edge e joins kTetEdges[e]). Two modes:
//  - cut: the tet is split along phi = 0 (the plane through its edge points and zero nodes; it is a plane
//    because the points interpolate phi linearly) into a - piece and a + piece, every case: the plane
//    through three edges (a corner), four edges (a quad), a node and two edges, two nodes and an edge, or a
//    face lying on the cut (no split, the face marked);
//  - conforming only (a "transition" tet next to cut ones): the tet stays one piece, its split edges kept.
// Each of the four faces is triangulated by a rule that depends on the face alone (its points and
// positions), so two tets sharing a face always agree: one point -> joined to the opposite corner; two
// points -> the corner triangle between them (its edge is the cut's trace) and the rest split along its
// shorter diagonal (ties by node id). Each piece is a convex polyhedron: it is coned from one of its
// vertices when every face through that vertex is fanned from it, else from a Steiner point at the mean of
// its vertices (`steiner`). Children come out positively oriented, with a bit per face lying on the cut.
//
// Units: metres. Cost: O(1) (at most kMaxChildren children). No allocation. Thread: any.
#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

namespace incise::tets::detail {

inline constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
inline constexpr int kMaxChildren = 16;

struct SplitVertex {
  int id = -1;  // global node id; -1: no point on this edge
  Eigen::Vector3d x_m = Eigen::Vector3d::Zero();
  int sign = 0;  // of phi: -1, 0, +1 (edge points: 0)
};

struct SplitInput {
  std::array<SplitVertex, 4> nodes;
  std::array<SplitVertex, 6> edge_points;  // per local edge
  bool cut = false;
};

struct SubTet {
  std::array<int, 4> nodes;
  std::int8_t side;        // -1 / +1: a piece of a cut tet; 0: a transition tet's part
  std::uint8_t cut_faces;  // bit i: the face opposite nodes[i] lies on the cut
};

// Creates a Steiner node at x_m for a piece on `side` and returns its id.
struct SteinerSink {
  virtual int add(const Eigen::Vector3d& x_m, int side) = 0;

 protected:
  ~SteinerSink() = default;
};

struct SplitResult {
  int count = 0;               // children written to out[0 .. count)
  double min_volume_m3 = 0.0;  // smallest child volume (> 0 unless degenerate)
  bool degenerate = false;     // a child with no volume remained after the Steiner fallback
};

SplitResult splitTet(const SplitInput& input, SteinerSink& steiner, SubTet* out);

}  // namespace incise::tets::detail
