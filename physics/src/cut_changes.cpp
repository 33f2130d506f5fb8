#include "incise/physics/cut_changes.h"

#include <algorithm>

#include "incise/tets/tet_cutter.h"

namespace incise::physics {
namespace {

// index's entry in `entries` (grown to cover it).
template <class T>
T& entryOf(std::vector<T>& entries, int index) {
  const auto i = static_cast<std::size_t>(index);
  if (entries.size() <= i) entries.resize(i + 1, T{});
  return entries[i];
}

void addNode(const tets::TetCutter& cutter, int node, CutChanges& out) {
  if (node < 0 || node >= cutter.nodeCount()) return;
  int& entry = entryOf(out.node_entry, node);
  const Eigen::Vector3d& x = cutter.nodePosition(node);
  if (entry == 0) {
    out.nodes.push_back({node, x});
    entry = static_cast<int>(out.nodes.size());
  } else {
    out.nodes[static_cast<std::size_t>(entry - 1)].rest_m = x;
  }
}

void addBaseTet(const tets::TetCutter& cutter, int base_tet, CutChanges& out) {
  if (base_tet < 0 || base_tet >= cutter.baseTetCount()) return;
  std::uint32_t& read = entryOf(out.base_read, base_tet);
  if (read == out.collects) return;  // its current pieces are in already
  read = out.collects;
  const std::span<const tets::TetChild> children = cutter.children(base_tet);
  const int first = static_cast<int>(out.pieces.size());
  for (const tets::TetChild& c : children) {
    out.pieces.push_back({c.nodes, c.side});
    for (const int node : c.nodes) addNode(cutter, node, out);
  }
  int& entry = entryOf(out.base_entry, base_tet);
  const BaseTetPieces pieces{base_tet, first, static_cast<int>(children.size())};
  if (entry == 0) {
    out.base_tets.push_back(pieces);
    entry = static_cast<int>(out.base_tets.size());
  } else {
    out.base_tets[static_cast<std::size_t>(entry - 1)] = pieces;  // the older pieces stay unused until clear()
  }
}

}  // namespace

void CutChanges::clear() noexcept {
  for (const NodeRest& n : nodes) node_entry[static_cast<std::size_t>(n.node)] = 0;
  for (const BaseTetPieces& b : base_tets) base_entry[static_cast<std::size_t>(b.base_tet)] = 0;
  nodes.clear(), base_tets.clear(), pieces.clear();
}

void CutChanges::reserve(std::size_t node_count, std::size_t base_tet_count, std::size_t piece_count) {
  nodes.reserve(node_count), base_tets.reserve(base_tet_count), pieces.reserve(piece_count);
  node_entry.reserve(node_count), base_entry.reserve(base_tet_count), base_read.reserve(base_tet_count);
}

void collectCutChanges(const tets::TetCutter& cutter, const tets::TetChanges& journal, CutChanges& out) {
  collectCutChanges(cutter, journal.nodes, journal.base_tets, out);
}

void collectCutChanges(const tets::TetCutter& cutter, std::span<const int> nodes, std::span<const int> base_tets,
                       CutChanges& out) {
  if (++out.collects == 0) {  // wrapped: no base tet counts as read in this call
    std::fill(out.base_read.begin(), out.base_read.end(), 0u);
    out.collects = 1;
  }
  for (const int node : nodes) addNode(cutter, node, out);
  for (const int base_tet : base_tets) addBaseTet(cutter, base_tet, out);
}

}  // namespace incise::physics
