// Private to cutting: what the global DFFD's three sources share (global_dffd.cpp: the lattice and the
// projection; global_dffd_split.cpp: the model split; global_dffd_openings.cpp: the openings left open,
// stitched or capped). Soup is the split model while it is being made: vertex positions with their
// provenance (source vertex or edge, side, plane) and triangles, all by index.
// Threads: a Soup belongs to one thread (the split keeps one per thread). Cost: see each function.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

namespace incise::cutting::detail {

struct Soup {
  std::vector<Eigen::Vector3d> x;
  std::vector<int> source;
  std::vector<std::array<int, 2>> edge;
  std::vector<std::int8_t> side;
  std::vector<int> plane;
  std::vector<std::array<int, 3>> faces;
  std::vector<int> remap;     // compaction
  std::vector<int> touching;  // splitAt: faces with a vertex on its plane

  int add(const Eigen::Vector3d& p, int src, std::array<int, 2> e, int on_plane) {
    x.push_back(p);
    source.push_back(src);
    edge.push_back(e);
    side.push_back(0);
    plane.push_back(on_plane);
    return static_cast<int>(x.size()) - 1;
  }
};

// Closes each opening left by separate(): a loop of boundary edges whose vertices all lie on `plane` on
// one side. Its two halves, from its lowest-v vertex to its highest, are given the same v-values (each
// half's edges split where the other half has a vertex) and welded vertex to vertex: once F is stitched
// both halves map onto the same seam, so the weld closes the surface without a flat face. An opening that
// cannot be welded (beyond the box, a half not strictly monotone in v, a face already joining the halves,
// or a weld that would not leave a two-manifold) gets a strip of thin triangles between its halves instead,
// if that leaves a two-manifold; else it stays open. Returns the openings left open.
// Cost O((V + F) log F) plus O(F) per welded vertex.
int zipOpenings(Soup& s, int plane, const Eigen::AlignedBox3d& box);

}  // namespace incise::cutting::detail
