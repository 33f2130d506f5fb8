// TetCutter's rebase (tet_cutter.h): when a new incision starts, the mesh the previous one left (settled)
// becomes the new rest mesh by redoing only what that incision changed, in three resumable phases:
//   Tets   each base tet it split or relabelled (touched_tets_, ascending) is replaced by its pieces: the
//          first keeps the index, the others are appended in order; the node -> tet lists follow;
//   Edges  the replaced and appended tets get their edge numbers (an edge shared with a tet that kept its
//          own takes that one's number; otherwise a new one);
//   Nodes  every node the incision resolved or created: its rest position becomes its deformed one (the
//          node grid follows; a node no tet uses any more leaves it) and its per-incision state is cleared.
// The order of it all depends only on the previous incision, never on the budget: the same mesh however the
// work falls into calls. Cost: O(k log k) for k changed tets (the incidence lists are a few dozen long);
// one budget unit (an inversion's time, about 2 us) per kRebaseTetsPerUnit tets, kRebaseEdgesPerUnit
// tets' edges or kRebaseNodesPerUnit nodes (measured with cold caches on the 292k-tet bunny: about 1, 0.6
// and 0.3 us each). Thread: the cutter's owner (inside follow()).
// Allocation: none within the headroom reserved at load (reserveHeadroom); beyond it counted growth.
#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "incise/tets/tet_cutter.h"
#include "tet_split.h"

namespace incise::tets {

void TetCutter::touchNode(int n) {
  Node& d = nodes_[static_cast<size_t>(n)];
  if (d.touched || static_cast<size_t>(n) >= nodes_at_start_) return;  // new nodes are rebased by their range
  d.touched = true;
  countGrowth(touched_nodes_, 1);
  touched_nodes_.push_back(n);
}

void TetCutter::addIncidence(int n, int t) {
  const size_t node = static_cast<size_t>(n);
  int& first = node_tets_first_[node];
  int& count = node_tets_count_[node];
  int& cap = node_tets_cap_[node];
  if (count == cap) {  // full: the list moves to the pool's end with twice the room
    const int room = std::max(16, 2 * cap);
    countGrowth(node_tets_, static_cast<size_t>(room));
    const int moved = static_cast<int>(node_tets_.size());
    node_tets_.resize(node_tets_.size() + static_cast<size_t>(room), -1);
    std::copy_n(node_tets_.begin() + first, count, node_tets_.begin() + moved);
    first = moved, cap = room;
  }
  const auto begin = node_tets_.begin() + first, end = begin + count;
  const auto at = std::upper_bound(begin, end, t);
  std::copy_backward(at, end, end + 1);
  *at = t;
  ++count;
}

void TetCutter::removeIncidence(int n, int t) {
  const size_t node = static_cast<size_t>(n);
  const auto begin = node_tets_.begin() + node_tets_first_[node], end = begin + node_tets_count_[node];
  const auto at = std::lower_bound(begin, end, t);
  if (at == end || *at != t) return;  // a node listed twice in one tet cannot happen (checkConforming)
  std::copy(at + 1, end, at);
  --node_tets_count_[node];
}

int TetCutter::appendBaseTet() {
  const int id = static_cast<int>(base_tets_.size());
  countGrowth(base_tets_, 1);
  base_tets_.push_back({});
  tet_edges_.push_back({});
  tet_state_.push_back(0);
  tet_touched_.push_back(1);
  decided_.push_back(0);
  child_first_.push_back(0);
  child_count_.push_back(0);
  steiner_.push_back({-1, -1, -1});
  return id;
}

// Base tet t (touched by the previous incision) becomes its pieces: t the first, the others appended.
void TetCutter::rebaseTet(int t) {
  const int first = child_first_[static_cast<size_t>(t)], count = child_count_[static_cast<size_t>(t)];
  const std::array<int, 4> old = base_tets_[static_cast<size_t>(t)];
  const auto holds = [](const std::array<int, 4>& nodes, int n) {
    return std::find(nodes.begin(), nodes.end(), n) != nodes.end();
  };
  for (const int n : old)  // t stays in the lists of the nodes its first piece keeps
    if (count == 0 || !holds(children_[static_cast<size_t>(first)].nodes, n)) removeIncidence(n, t);
  for (int c = 0; c < count; ++c) {
    const int id = c == 0 ? t : appendBaseTet();
    Child& piece = children_[static_cast<size_t>(first + c)];
    piece.side = 0, piece.cut_faces = 0;
    base_tets_[static_cast<size_t>(id)] = piece.nodes;
    child_first_[static_cast<size_t>(id)] = first + c;  // each piece is its own only child, where it was
    child_count_[static_cast<size_t>(id)] = 1;
    tet_state_[static_cast<size_t>(id)] = 0;
    steiner_[static_cast<size_t>(id)] = {-1, -1, -1};
    for (const int n : piece.nodes)
      if (c > 0 || !holds(old, n)) addIncidence(n, id);
    if (record_changes_) changes_.base_tets.push_back(id);
  }
  ++stats_.rebased_tets;
}

// The number of edge (a, b) in a tet around it whose edges are numbered (not being rebased); -1 if none.
// The tets around both nodes, by merging their sorted lists (a few dozen each).
int TetCutter::findEdge(int t, int a, int b) const {
  const std::span<const int> around_a = tetsAround(a), around_b = tetsAround(b);
  auto i = around_a.begin(), j = around_b.begin();
  while (i != around_a.end() && j != around_b.end()) {
    if (*i < *j) {
      ++i;
    } else if (*j < *i) {
      ++j;
    } else {
      const int s = *i;
      ++i, ++j;
      if (s == t || tet_touched_[static_cast<size_t>(s)]) continue;
      const auto& nodes = base_tets_[static_cast<size_t>(s)];
      for (int e = 0; e < 6; ++e) {
        const int x = nodes[detail::kTetEdges[e][0]], y = nodes[detail::kTetEdges[e][1]];
        if ((x == a && y == b) || (x == b && y == a)) return tet_edges_[static_cast<size_t>(s)][static_cast<size_t>(e)];
      }
    }
  }
  return -1;
}

void TetCutter::rebaseEdges(int t) {
  if (!tet_touched_[static_cast<size_t>(t)]) return;
  tet_touched_[static_cast<size_t>(t)] = 0;
  if (child_count_[static_cast<size_t>(t)] == 0) return;  // no piece left (a split never does this): no tet
  const auto& nodes = base_tets_[static_cast<size_t>(t)];
  for (int e = 0; e < 6; ++e) {
    const int a = nodes[detail::kTetEdges[e][0]], b = nodes[detail::kTetEdges[e][1]];
    int edge = findEdge(t, a, b);
    if (edge < 0) {
      countGrowth(edges_, 1);
      edge = static_cast<int>(edges_.size());
      edges_.push_back({std::min(a, b), std::max(a, b)});
      edge_point_.push_back(-1);
    }
    tet_edges_[static_cast<size_t>(t)][static_cast<size_t>(e)] = edge;
  }
}

void TetCutter::rebaseNode(int n) {
  const size_t i = static_cast<size_t>(n);
  const bool used = node_tets_count_[i] > 0;
  if (in_grid_[i] && !used)
    node_grid_.remove(n, rest_m_[i]);
  else if (in_grid_[i] && rest_m_[i] != deformed_m_[i])
    node_grid_.move(n, rest_m_[i], deformed_m_[i]);
  else if (!in_grid_[i] && used)
    node_grid_.insert(n, deformed_m_[i]);
  in_grid_[i] = used ? 1 : 0;
  rest_m_[i] = deformed_m_[i];
  nodes_[i] = Node{};
  nodes_[i].origin = n;
}

bool TetCutter::rebase(core::WorkBudget& budget) {
  const size_t touched = touched_tets_.size();
  if (rebase_phase_ == Rebase::Tets) {
    for (; rebase_next_ < touched; ++rebase_next_) {
      if (!budget.takeEvery(rebase_next_, kRebaseTetsPerUnit)) return false;
      rebaseTet(touched_tets_[rebase_next_]);
    }
    rebase_phase_ = Rebase::Edges, rebase_next_ = 0;
  }
  if (rebase_phase_ == Rebase::Edges) {  // the replaced tets, then the appended ones
    const size_t appended = base_tets_.size() - static_cast<size_t>(bases_at_start_);
    for (; rebase_next_ < touched + appended; ++rebase_next_) {
      if (!budget.takeEvery(rebase_next_, kRebaseEdgesPerUnit)) return false;
      rebaseEdges(rebase_next_ < touched ? touched_tets_[rebase_next_]
                                         : bases_at_start_ + static_cast<int>(rebase_next_ - touched));
    }
    rebase_phase_ = Rebase::Nodes, rebase_next_ = 0;
  }
  const size_t fresh = nodes_.size() - nodes_at_start_, old = touched_nodes_.size();
  for (; rebase_next_ < old + fresh; ++rebase_next_) {
    if (!budget.takeEvery(rebase_next_, kRebaseNodesPerUnit)) return false;
    rebaseNode(rebase_next_ < old ? touched_nodes_[rebase_next_]
                                  : static_cast<int>(nodes_at_start_ + (rebase_next_ - old)));
  }
  touched_tets_.clear();
  touched_nodes_.clear();
  nodes_at_start_ = nodes_.size();
  rebase_phase_ = Rebase::None, rebase_next_ = 0;
  return true;
}

std::string TetCutter::checkIndexes() const {
  const auto at = [](const char* what, size_t i) { return std::string(what) + " " + std::to_string(i); };
  std::vector<std::vector<int>> around(nodes_.size());
  std::map<std::pair<int, int>, int> edge_of;
  for (size_t t = 0; t < base_tets_.size(); ++t) {
    if (child_count_[t] == 0) continue;
    const auto& nodes = base_tets_[t];
    for (const int n : nodes) around[static_cast<size_t>(n)].push_back(static_cast<int>(t));
    for (int e = 0; e < 6; ++e) {
      const int a = std::min(nodes[detail::kTetEdges[e][0]], nodes[detail::kTetEdges[e][1]]);
      const int b = std::max(nodes[detail::kTetEdges[e][0]], nodes[detail::kTetEdges[e][1]]);
      const int edge = tet_edges_[t][static_cast<size_t>(e)];
      if (edges_[static_cast<size_t>(edge)] != std::array<int, 2>{a, b}) return at("wrong edge nodes: base tet", t);
      if (edge_of.emplace(std::make_pair(a, b), edge).first->second != edge)
        return at("two numbers for one edge: base tet", t);
    }
  }
  size_t used = 0;
  std::vector<int> found;
  for (size_t n = 0; n < nodes_.size(); ++n) {
    const std::span<const int> listed = tetsAround(static_cast<int>(n));
    if (!std::equal(listed.begin(), listed.end(), around[n].begin(), around[n].end()))
      return at("wrong tet list: node", n);
    if (around[n].empty()) continue;
    ++used;
    found.clear();
    node_grid_.query(Eigen::AlignedBox3d(rest_m_[n], rest_m_[n]), found);
    if (std::find(found.begin(), found.end(), static_cast<int>(n)) == found.end())
      return at("not in the grid at its rest position: node", n);
  }
  if (node_grid_.size() != used) return at("grid entries for unused nodes:", node_grid_.size() - used);
  return {};
}

}  // namespace incise::tets
