// What a cut changed in the tets, as a value that crosses from the thread that cuts (sim) to the physics
// thread: nodes with their rest positions (new, or moved by the incision), and base tets with the pieces
// that now replace them. collectCutChanges() reads a tets::TetCutter's journal into it (sim thread);
// TissueModel::apply() applies it (physics thread); applyTetCutterJournal (tet_cutter_journal.h) does both.
//
// Indices are the tet cutter's: nodes and base tets are never renumbered, so a model built from the
// cutter's load mesh follows every incision. Shapes: pieces are 4 node indices, positively oriented at rest.
// Units: metres. Threads: a value; one owner at a time. Cost: collect O(journal entries + pieces).
// Allocation: none while within reserve(); beyond it, amortised growth.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace incise::tets {
class TetCutter;
struct TetChanges;
}  // namespace incise::tets

namespace incise::physics {

struct NodeRest {
  int node = -1;
  Eigen::Vector3d rest_m = Eigen::Vector3d::Zero();
};

struct Piece {
  std::array<int, 4> nodes{-1, -1, -1, -1};
  int side = 0;  // -1 / +1: a piece of a cut tet on that side of the cut; 0: not cut
};

struct BaseTetPieces {
  int base_tet = -1;
  int first = 0;  // its pieces are CutChanges::pieces[first, first + count); count 0 removes the base tet
  int count = 0;
};

struct CutChanges {
  std::vector<NodeRest> nodes;  // each node once; every node of every piece listed is here too
  std::vector<BaseTetPieces> base_tets;
  std::vector<Piece> pieces;

  bool empty() const noexcept { return nodes.empty() && base_tets.empty(); }
  void clear() noexcept;  // O(entries); keeps the capacity
  // Room for this many entries, and for node and base-tet indices below these counts.
  void reserve(std::size_t node_count, std::size_t base_tet_count, std::size_t piece_count);

  // For collectCutChanges: per node / base-tet index, 1 + its entry in `nodes` / `base_tets`, 0 if absent;
  // per base tet, the collect call that last read its pieces.
  std::vector<int> node_entry, base_entry;
  std::vector<std::uint32_t> base_read;
  std::uint32_t collects = 0;
};

// Appends the cutter's journal to `out` (out is not cleared: several journals may be collected before the
// physics takes them; a node or base tet already in `out` is updated in place): every node the journal names
// and every node of every changed base tet's current pieces, at the cutter's current positions (its deformed
// positions: its rest + the incision's opening, which become the physics' rest), and each changed base tet's
// current pieces. The journal is not cleared (the caller does: cutter.clearChanges()). Never throws but
// std::bad_alloc beyond the reserve. Thread: the cutter's owner. Cost O(journal + pieces x 4).
void collectCutChanges(const tets::TetCutter& cutter, const tets::TetChanges& journal, CutChanges& out);
// The same for a part of a journal (the entries a reader has not read yet, when the journal is shared with
// another reader who clears it): `nodes` and `base_tets` are journal entries (node and base-tet indices).
void collectCutChanges(const tets::TetCutter& cutter, std::span<const int> nodes, std::span<const int> base_tets,
                       CutChanges& out);

}  // namespace incise::physics
