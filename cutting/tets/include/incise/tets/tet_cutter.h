// Cuts a tetrahedral tissue (TetMesh, e.g. from tetrahedralize()) with the same local DFFD incisions that
// SurfaceCutter grows on the drawn surface (Schein & Elber, "Discontinuous Free Form Deformations", §3.2
// and §4; Incision in incision.h). The cutter follows an Incision it does not own: after the owner has
// added samples and updated the opening, follow() cuts the tets under the columns that became final and
// moves the nodes; a new incision starts from the mesh the previous one left. The same samples give the same
// mesh (the same bytes from view()) however they are grouped into calls, and whatever the budget.
//
// Units: metres. Threads: one owner (the sim thread). Cost per column: O(tets under `order` columns) plus one
// inversion per new node; per call with no new column: O(columns) + O(nodes under columns whose opening
// changed); nothing is O(mesh) after load. Allocation: none per call within the headroom reserved at load
// (kHeadroomNodes), beyond it amortised growth, counted in stats().reserve_overflows. Failure: the
// constructor throws MeshError for a mesh that is not conforming and std::invalid_argument for bad options;
// follow() never throws: a split that would leave a flat or inverted tet stops the cutter with `failure` set
// in stats() (the mesh stays as the last finished column left it).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "incise/bspline/volume_inversion.h"
#include "incise/core/work_budget.h"
#include "incise/incision/incision.h"
#include "incise/mesh/vertex_grid.h"
#include "incise/tets/tet_cutter_options.h"
#include "incise/tets/tet_mesh.h"

namespace incise::tets {

// A materialised mesh with its per-tet fields (in the mesh's tet order).
struct TetView {
  TetMesh mesh;
  std::vector<int> side;                  // -1 / +1: a piece of a cut tet on that side of the cut; 0: not cut
  std::vector<int> split;                 // 0: an original tet; 1: a piece of a cut tet; 2: part of a conformingly
                                          // subdivided (crack-front) tet
  std::vector<int> node_cut;              // per node: 0 off the cut; 1 on the cut, u < 1/2 side of a duplicated node;
                                          // 2 its copy (u >= 1/2 side); 3 on the cut's front (single, not separated)
  double min_split_dihedral_deg = 180.0;  // over tets with split != 0, at rest
  double min_split_volume_m3 = std::numeric_limits<double>::infinity();  // same
  int inverted_tets = 0;                                                 // tets with non-positive volume in this mesh
};

// One piece of a base tet in the cutter's working mesh (raw(): node indices into its node arrays, which
// keep unused nodes; compact with view()).
struct TetChild {
  std::array<int, 4> nodes;  // positively oriented at rest
  std::int8_t side;          // as TetView::side
  std::uint8_t cut_faces;    // bit i: the face opposite nodes[i] lies on the cut
};

// The tet cutter's change journal, for a reader that follows the working mesh (sim's GeometryStream):
// nodes whose deformed position changed or that are new, base tets whose children changed (each index as
// often as it changed, oldest first; a new incision's rebase reports the base tets it replaced and those it
// appended). Indices are never renumbered: a reader that has followed the journal stays exact.
struct TetChanges {
  std::vector<int> nodes;
  std::vector<int> base_tets;
  void clear() noexcept { nodes.clear(), base_tets.clear(); }
};

class TetCutter {
 public:
  // Load time: checks that `tissue` is conforming (checkConforming) and builds its adjacency and grid.
  explicit TetCutter(TetMesh tissue, const TetCutterOptions& options = {});

  // Load time, optional: sizes what following an incision of these options needs (its lagged lattice, its
  // columns' arrays), so that follow() allocates nothing when the first incision starts (a sim thread's
  // world calls it; without it, the first follow() of an incision allocates them). Throws
  // std::invalid_argument for bad options (Incision::validateOptions).
  void prepare(const incision::IncisionOptions& options);

  // Catches up with `incision` (owned by the caller, e.g. SurfaceCutter::incision()): cuts the columns it
  // has made final since the last call, within the budget unless `unlimited`, and moves the nodes whose
  // displacement changed. `incision_number` identifies the incision (SurfaceCutter's stats().incisions):
  // a new number starts a new one from the current mesh. Never throws.
  //
  // Per final lattice column (nodes found through a grid, tets through node -> tet incidence; no pass over
  // the mesh):
  //  1. the nodes under the column are parameterised by inverting F0 (as the surface cutter); the tets around
  //     each node bound (or found beyond the lattice after waiting) are decided once all their nodes are known;
  //     phi = u - 1/2; a node closer to the cut than `snap_tolerance_m` gets phi = 0 (it lies on the cut:
  //     snapping instead of a sliver);
  //  2. a tet whose nodes all have phi and whose cut polygon (phi = 0 through it, linear in the tet) lies
  //     inside the cut (after the stroke's start, above the blade's depth, up to the last station once the
  //     stroke is finished: the surface cutter's test) is cut: a point is placed on each crossing edge (shared
  //     by every tet around that edge) and the tet is split into its - and + pieces (tet_split.h: all the
  //     cases: 1-3 edges, through a node, along a face); the tets around a new point that are not cut are
  //     subdivided conformingly without separating (the crack front);
  //  3. every node on the cut is duplicated when the tets around it fall into separate groups once cut faces
  //     no longer connect them: the u < 1/2 group keeps it, the u >= 1/2 group gets a copy; nodes on the crack
  //     front stay single and move with the mean of both sides;
  //  4. nodes move to rest + D(u, v, w) on their side (Incision::displacementAt, through cached stencils; a
  //     node snapped onto the cut keeps its own u, clamped to the lip on the other side), again whenever the
  //     incision's opening changes (Incision::columnOpening), through a delayed copy of D that keeps the
  //     columns near the tets' front shut: every node is where the incision's state and the columns cut so
  //     far put it after each call, whatever the timing of the calls (tet_cutter_deform.cpp).
  //
  // A new incision (a new `incision_number`) starts from the mesh as the previous one left it
  // (deformed, settled): it becomes the new rest mesh. Only what the previous incision changed is redone (the
  // "rebase", tet_cutter_rebase.cpp): each base tet it split or relabelled is replaced by its pieces (the
  // first piece keeps the base tet's index, the others are appended in base-tet order), their edges and the
  // node -> tet incidence are updated, its nodes' rest positions become their deformed ones (moved in the
  // node grid) and their per-incision state is cleared. O(changed tets + changed nodes), under the call's
  // budget (a few items per inversion's worth), before the new incision's first column. The result is the
  // mesh a new TetCutter built from that settled mesh in that order would hold
  // (tests/cutting/tets/tet_cutter_rebase_test.cpp), except that the tets' lag behind the lattice (about two
  // tet edges) uses the median edge measured at load.
  TetStep follow(const incision::Incision& incision, int incision_number,
                 TetBudget budget = TetBudget::PerCall) noexcept;

  // Work for the followed incision not done yet (budget carried over): the rebase, or final columns not cut.
  bool pending() const noexcept;
  // The current mesh, compacted (unused nodes dropped, nodes in creation order, tets in base-tet order, each
  // base tet's children together; after a rebase the extra pieces come last): deformed or at rest. Allocates, O(N + T): for output and checks, not per frame.
  TetView view(TetShape shape = TetShape::Deformed) const;
  const TetCutStats& stats() const noexcept { return stats_; }
  double snapToleranceM() const noexcept { return snap_m_; }
  double medianEdgeM() const noexcept { return median_edge_m_; }  // of the tets it was built with (at load)
  // Tets in the current mesh (O(1)).
  int tetCount() const noexcept { return tet_count_; }

  // The working mesh as it is, uncompacted (O(1) each; for a reader that follows it through changes()):
  // base tets (0 .. baseTetCount()), each with its children; nodes (0 .. nodeCount(), some unused) at their
  // deformed positions in metres.
  int baseTetCount() const noexcept { return static_cast<int>(base_tets_.size()); }
  std::span<const TetChild> children(int base_tet) const noexcept {
    return {children_.data() + child_first_[static_cast<size_t>(base_tet)],
            child_count_[static_cast<size_t>(base_tet)]};
  }
  int nodeCount() const noexcept { return static_cast<int>(deformed_m_.size()); }
  const Eigen::Vector3d& nodePosition(int node) const noexcept { return deformed_m_[static_cast<size_t>(node)]; }
  // The change journal: off by default; on, follow() appends every change (room for kReservedChanges
  // entries each is reserved when turned on, amortised growth beyond); the reader calls clearChanges()
  // (keeps the capacity). Turning it off clears it. Never throws except std::bad_alloc from recordChanges(true).
  void recordChanges(bool on);
  const TetChanges& changes() const noexcept { return changes_; }
  void clearChanges() noexcept { changes_.clear(); }
  static constexpr size_t kReservedChanges = 1 << 16;
  // The cutter's indexes checked against its base tets (for tests and debugging; O(N log N + T), allocates):
  // the node grid holds exactly the nodes some base tet uses, at their rest positions; each node's tet list
  // is ascending and holds exactly the base tets that use it; every base tet's edges are numbered with
  // their nodes, one number per edge. They hold between follow() calls, except while a rebase is under way.
  // Empty when all hold, else the first problem found.
  std::string checkIndexes() const;

 private:
  enum class NodeState : std::uint8_t { Unknown, Waiting, Bound, Outside, EdgePoint, Copy, Steiner };
  struct Node {
    Eigen::Vector3d uvw = Eigen::Vector3d::Zero();
    NodeState state = NodeState::Unknown;
    std::int8_t sign = 0;    // of phi; 0 on the cut (edge points, snapped nodes)
    std::int8_t side = 0;    // for the displacement: -1, +1, 2 (mean), 0 (does not move)
    bool cut_point = false;  // a vertex of some cut polygon: duplicated by groups
    int retry = 0;           // Waiting: the column at which to try again
    int copy = -1;           // the + side's copy of a cut point
    int origin = -1;         // for a copy: the node it copies; else itself
    int support = -1;        // for an edge point: its base edge
    int stencil = -1;
    std::uint32_t stamp = 0;
    bool touched = false;  // in touched_nodes_
    int cell = -1;         // the cells_ list that holds it: the last lattice column its stencil reaches
  };

  void build(TetMesh mesh);  // load time: the base, its edges, incidence and grid
  void reserveHeadroom();
  // New nodes the cutter's incisions may add, over its life, without reallocation (an incision through the
  // 292k-tet bunny adds about 500), with room for 4 new base tets and 8 children each.
  static constexpr size_t kHeadroomNodes = 20000;
  static constexpr size_t kReservedCellNodes = 256;  // nodes with a stencil per lattice cell, reserved
  void startIncision(int incision_number);
  // The rebase (tet_cutter_rebase.cpp): phases in order, each resumable at rebase_next_.
  enum class Rebase : std::uint8_t { None, Tets, Edges, Nodes };
  // Items per budget unit (one inversion, about 2 us): tets replaced, tets' edges numbered, nodes rebased.
  static constexpr size_t kRebaseTetsPerUnit = 2, kRebaseEdgesPerUnit = 4, kRebaseNodesPerUnit = 8;
  bool rebase(core::WorkBudget& budget);  // true when done
  void rebaseTet(int t);
  void rebaseEdges(int t);
  int findEdge(int t, int a, int b) const;
  void rebaseNode(int n);
  int appendBaseTet();
  std::span<const int> tetsAround(int node) const noexcept {
    return {node_tets_.data() + node_tets_first_[static_cast<size_t>(node)],
            static_cast<size_t>(node_tets_count_[static_cast<size_t>(node)])};
  }
  void addIncidence(int node, int tet);
  void removeIncidence(int node, int tet);
  void touchNode(int node);
  template <class Vector>
  void countGrowth(const Vector& v, size_t extra) noexcept {
    if (v.size() + extra > v.capacity()) ++stats_.reserve_overflows;
  }
  bool processColumn(const incision::Incision& in, int column, core::WorkBudget& budget, TetStep& step);
  enum class Resolve : std::uint8_t { Done, Later, OutOfBudget };
  Resolve resolveNode(const incision::Incision& in, int node, int column, core::WorkBudget& budget, TetStep& step);
  // The node's parameters solved again from the start of its own slab when it was resolved at a later column
  // (the same bits whatever the column); `found` if that does not converge there.
  bspline::InversionResult canonicalInversion(const incision::Incision& in, const Eigen::Vector3d& x, int column,
                                              const bspline::InversionResult& found) const;
  void wait(int node);  // the node waits for a later column (waiting_)
  void retryWaiting();  // the column's candidates gain the nodes still waiting
  bool decideCut(const incision::Incision& in, int tet);
  int edgePoint(int edge);
  Eigen::Vector3d crossingUvw(int a, int b, double& lambda) const;
  bool insideCut(const incision::Incision& in, const Eigen::Vector3d& uvw) const;
  void subdivide(int tet, TetStep& step);
  struct SteinerNodes;
  int steinerNode(int tet, const Eigen::Vector3d& x_m, int side);
  void separate(int node);
  void supportTets(int node, std::vector<int>& out) const;
  int addNode(const Eigen::Vector3d& rest_m, const Eigen::Vector3d& uvw, NodeState state, int side);
  void setSide(int node, int side);  // tet_cutter_deform.cpp
  void copyLagged(const incision::Incision& in);
  void redeform(const incision::Incision& in, TetStep& step);
  void fail(const std::string& message);
  int canonical(int node) const { return nodes_[static_cast<size_t>(node)].origin; }

  TetCutterOptions options_;
  double snap_m_ = 0.0;
  const incision::Incision* incision_ = nullptr;  // valid during follow() only
  int incision_number_ = -1;
  int next_column_ = 0;
  bool column_started_ = false;
  size_t next_candidate_ = 0, next_fresh_ = 0;
  int next_fresh_tet_ = -1;
  std::vector<int> fresh_;    // nodes bound during the current column, in order
  std::vector<int> waiting_;  // nodes waiting for a later column, in the order they began to wait
  int last_final_columns_ = 0;
  std::vector<int> candidates_, affected_, cut_points_, scratch_, scratch2_, parent_;
  std::vector<std::array<int, 3>> faces_;  // separate(): (node, node, element) per face through the node
  std::vector<std::uint8_t> group_seen_;
  // The incision's displacement delayed: per column `scale` x the incision's (0 near the tets' front).
  std::optional<bspline::BSplineVolume> lagged_;
  struct LaggedColumn {
    double scale = 1.0, opening = 0.0;  // lagged_ holds scale x the incision's column at this opening
  };
  std::vector<LaggedColumn> lagged_seen_;  // per column
  std::vector<int> lagged_changed_;        // the columns copyLagged() copied again in this call
  int lag_columns_ = 0;
  double median_edge_m_ = 0.0;

  // The rest mesh of the current incision ("base"), its edges and node -> tet incidence.
  std::vector<std::array<int, 4>> base_tets_;
  std::vector<std::array<int, 6>> tet_edges_;
  std::vector<std::array<int, 2>> edges_;  // (lower node, higher node); edges of replaced tets stay, unused
  std::vector<int> edge_point_;
  // Node -> base tets, ascending: node n's are node_tets_[first[n], + count[n]), with room for cap[n]; a
  // list that outgrows its room moves to the pool's end (tetsAround()).
  std::vector<int> node_tets_first_, node_tets_count_, node_tets_cap_, node_tets_;
  std::vector<std::uint8_t> tet_state_;  // 0 untouched, 1 subdivided conformingly, 2 cut
  std::vector<int> decided_;             // the stats_.incisions whose cut decision was made for the tet
  mesh::VertexGrid node_grid_;           // used nodes at rest (in_grid_)
  std::vector<std::uint8_t> in_grid_;
  // What the current incision changed, for the next one's rebase: base tets (flag, list) and nodes that
  // were not new (Node::touched, list); the new ones are those from nodes_at_start_ on.
  std::vector<std::uint8_t> tet_touched_;
  std::vector<int> touched_tets_, touched_nodes_;
  size_t nodes_at_start_ = 0, rebase_next_ = 0;
  int bases_at_start_ = 0;
  Rebase rebase_phase_ = Rebase::None;

  // Every node (base nodes first) and the current children of every base tet.
  std::vector<Eigen::Vector3d> rest_m_, deformed_m_;
  std::vector<Node> nodes_;
  using Child = TetChild;
  std::vector<Child> children_;  // a base tet's children: [child_first_[t], + child_count_[t])
  std::vector<int> child_first_;
  std::vector<std::uint8_t> child_count_;
  std::vector<std::array<int, 3>> steiner_;  // per base tet: Steiner node per piece side (-1, 0, +1)
  int tet_count_ = 0;

  std::vector<std::vector<int>> cells_;  // nodes with a stencil by the last column it reaches (Node::cell)
  std::vector<std::uint8_t> stencil_count_;
  std::vector<int> stencil_first_;
  std::vector<double> stencil_basis_;
  std::vector<int> dirty_;
  std::uint32_t stamp_ = 0;
  TetCutStats stats_;
  bool failed_ = false;
  TetChanges changes_;
  bool record_changes_ = false;
  void nodeChanged(int node) {
    if (record_changes_) changes_.nodes.push_back(node);
  }
  void baseTetChanged(int base_tet) {
    if (!tet_touched_[static_cast<size_t>(base_tet)]) {
      tet_touched_[static_cast<size_t>(base_tet)] = 1;
      touched_tets_.push_back(base_tet);
    }
    if (record_changes_) changes_.base_tets.push_back(base_tet);
  }
};

}  // namespace incise::tets
