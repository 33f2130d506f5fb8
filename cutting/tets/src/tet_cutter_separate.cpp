// TetCutter's step 3 (tet_cutter.h): separating the cut at one node. The child tets around the node are
// grouped (union-find) through their faces that contain it and are not cut faces; when there are two
// groups or more, some with + pieces only, the node is duplicated and those groups move to the copy (the
// u >= 1/2 side). Steps 1 and 2 are in tet_cutter.cpp, step 4 in tet_cutter_deform.cpp.
// Cost: O(k log k) for the k child tets around the node (a few dozen). No allocation within the headroom
// reserved by reserveHeadroom(). Thread: the cutter's owner (inside follow()).
#include "incise/tets/tet_cutter.h"

#include <algorithm>
#include <iterator>
#include <tuple>
#include <vector>

#include "incise/core/union_find.h"

namespace incise::tets {

void TetCutter::supportTets(int x, std::vector<int>& out) const {
  out.clear();
  const Node& d = nodes_[static_cast<size_t>(x)];
  if (d.state == NodeState::EdgePoint) {
    const std::span<const int> lo = tetsAround(edges_[static_cast<size_t>(d.support)][0]),
                               hi = tetsAround(edges_[static_cast<size_t>(d.support)][1]);
    std::set_intersection(lo.begin(), lo.end(), hi.begin(), hi.end(), std::back_inserter(out));
  } else {
    const std::span<const int> around = tetsAround(x);
    out.assign(around.begin(), around.end());
  }
}

void TetCutter::separate(int x) {
  supportTets(x, scratch_);
  // The children around x, and union-find over them through faces that contain x and are not cut faces.
  std::vector<int>& elems = scratch2_;
  elems.clear();
  for (const int t : scratch_)
    for (int c = child_first_[static_cast<size_t>(t)];
         c < child_first_[static_cast<size_t>(t)] + child_count_[static_cast<size_t>(t)]; ++c)
      for (const int n : children_[static_cast<size_t>(c)].nodes)
        if (canonical(n) == x) {
          elems.push_back(c);
          break;
        }
  faces_.clear();
  for (size_t k = 0; k < elems.size(); ++k) {
    const Child& ch = children_[static_cast<size_t>(elems[k])];
    for (int i = 0; i < 4; ++i) {
      if (canonical(ch.nodes[static_cast<size_t>(i)]) == x || (ch.cut_faces >> i & 1u)) continue;
      int other[2], m = 0;
      for (int j = 0; j < 4; ++j)
        if (j != i && canonical(ch.nodes[static_cast<size_t>(j)]) != x)
          other[m++] = canonical(ch.nodes[static_cast<size_t>(j)]);
      faces_.push_back({std::min(other[0], other[1]), std::max(other[0], other[1]), static_cast<int>(k)});
    }
  }
  std::sort(faces_.begin(), faces_.end(),
            [](const auto& p, const auto& q) { return std::tie(p[0], p[1], p[2]) < std::tie(q[0], q[1], q[2]); });
  core::detail::UnionFind joined(parent_, elems.size());  // over the children around x (a few)
  for (size_t i = 1; i < faces_.size(); ++i)
    if (faces_[i][0] == faces_[i - 1][0] && faces_[i][1] == faces_[i - 1][1])
      joined.unite(faces_[i][2], faces_[i - 1][2]);
  // Each group's side: +1 if it holds + pieces only, -1 if - only, 0 if both or none.
  std::vector<std::uint8_t>& seen = group_seen_;
  seen.assign(elems.size(), 0);
  for (size_t k = 0; k < elems.size(); ++k) {
    const int s = children_[static_cast<size_t>(elems[k])].side;
    if (s != 0) seen[static_cast<size_t>(joined.find(static_cast<int>(k)))] |= s > 0 ? 2u : 1u;
  }
  int groups = 0, plus_groups = 0;
  for (size_t k = 0; k < elems.size(); ++k) {
    if (!joined.isRoot(static_cast<int>(k))) continue;
    ++groups;
    if (seen[k] == 2u) ++plus_groups;
  }
  Node& d = nodes_[static_cast<size_t>(x)];
  const bool doubled = groups >= 2 && plus_groups > 0 && plus_groups < groups;
  if (doubled && d.copy < 0) {
    const Eigen::Vector3d rest = rest_m_[static_cast<size_t>(x)], uvw = d.uvw;
    const int copy = addNode(rest, uvw, NodeState::Copy, 1);
    nodes_[static_cast<size_t>(x)].copy = copy;
    nodes_[static_cast<size_t>(copy)].origin = x;
    ++stats_.duplicated_nodes;
  }
  // Below the blade's depth the two sides stay together (the mean of both, as the surface cutter's wall
  // bottom): the tets there are cut apart (the blade's bottom passed through them) but the slit is shut.
  const bool open = doubled && nodes_[static_cast<size_t>(x)].uvw[2] < incision_->bottomW();
  setSide(x, open ? -1 : 2);
  const int copy = nodes_[static_cast<size_t>(x)].copy;
  if (doubled) setSide(copy, open ? 1 : 2);
  for (size_t k = 0; k < elems.size(); ++k) {
    const bool to_copy = doubled && seen[static_cast<size_t>(joined.find(static_cast<int>(k)))] == 2u;
    for (int& n : children_[static_cast<size_t>(elems[k])].nodes)
      if (canonical(n) == x) n = to_copy ? copy : x;
  }
  for (const int t : scratch_) baseTetChanged(t);
}

}  // namespace incise::tets
