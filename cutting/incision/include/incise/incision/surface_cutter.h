// Cuts a tissue surface mesh with local DFFD incisions grown along scalpel strokes (Schein & Elber,
// "Discontinuous Free Form Deformations", §4; the lattice itself is Incision, incision.h). For every lattice
// column that becomes final the mesh under it (and only there) is split along u = 1/2, the seam duplicated,
// walls added down to the blade's depth and the vertices moved by the displacement (extend()). The mesh
// stays a closed two-manifold with its Euler characteristic; new elements carry their kinds (surface_mesh.h:
// Seam vertices, Split faces, Wall vertices and faces); the same samples give the same bytes however they
// are grouped into calls. An incision that falls short says why (IncisionFigures, Shortfall).
//
// Threads: one owner (the sim thread). Cost per column step: O(vertices and faces under `order` columns);
// per extend() with no new column: O(columns still opening). Allocation: none after construction while an
// incision binds at most CutterOptions::reserved_bound_vertices vertices (lattice, kHeadroomVertices of mesh,
// grids, seam chain and walls reserved at load); beyond that, growth counted in stats().reserve_overflows.
// Failure: the constructor throws MeshError for a mesh that is not a closed two-manifold and
// std::invalid_argument for bad options; the incision's calls never throw: bad samples come back as a
// status, and an internal topology failure stops the incision with `failed` set and the message in stats().
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "incise/core/work_budget.h"
#include "incise/incision/incision.h"
#include "incise/incision/surface_cutter_options.h"
#include "incise/mesh/solid.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/mesh/surface_query.h"
#include "incise/mesh/thickness.h"
#include "incise/mesh/vertex_grid.h"

namespace incise::incision {

class SurfaceCutter {
 public:
  // Takes the mesh by reference for the cutter's lifetime. Throws MeshError if it is not a closed
  // two-manifold (checkManifold) and std::invalid_argument for bad options. Cost O(V) (the grid).
  SurfaceCutter(mesh::SurfaceMesh& mesh, const CutterOptions& options);

  // Starts a new incision at `first` (a point on the surface with its outward normal) with the blade moving
  // along `blade_direction`; the previous incision, if any, is finished first, its carried work done
  // (whatever the budget: this call may take as long as that work) and its wound settled at its final
  // opening (a cut begun within retraction_time_s of the last one makes that one snap open). A non-finite sample or a
  // zero normal is refused with a status (no incision starts). Never throws.
  // Several incisions may cut one mesh, crossing or not: a new incision starts from the mesh as the previous
  // ones left it (their wounds stop evolving).
  CutStep begin(const StrokeSample& first, const Eigen::Vector3d& blade_direction) noexcept;
  // The first part of begin(): finishes the current incision, if any, does its carried work whatever the
  // budget and sets its wound to its final, settled opening. A follower of the incision (TetCutter) calls
  // it, then catches up, before begin() replaces the incision. Idempotent. Never throws.
  void settle() noexcept;
  // settle() a call's share at a time: finishes the current incision, does its carried work within the
  // per-call budget (all of it when `unlimited`) and sets its wound to its final opening; true once nothing
  // is carried (then the incision is settled: the same bytes as settle(), whatever the number of calls), and
  // with no incision. A follower (TetCutter) catches up after it returns true, and begin() comes after that.
  // Never throws.
  bool settleStep(bool unlimited = false) noexcept;
  // All begin() needs done before it, a call's share at a time: settleStep(unlimited), then the settled
  // incision's vertices indexed where they now are, as the next incision's rest (the vertex grid, and with
  // refinement the coarse flags around them: O(its bound vertices), 0.2-0.7 us each, one budget unit per
  // kReindexMovesPerUnit grid moves or kReindexCoarsePerUnit vertices' flags). True when begin() has none of
  // it left to do; begin() does what is left at once. The mesh is the same however the work falls into
  // calls. Until begin(), only skinNear() should query the cutter (the grid already holds the vertices where
  // they are; intersect() would still take their previous rest), and the settled incision must not be
  // advanced. A sim thread's World calls it while a new incision waits. Never throws.
  bool prepareBegin(bool unlimited = false) noexcept;
  // Adds stroke samples to the current incision and processes every column they make final (within the
  // per-call budget). A sample off the surface finishes the incision. Never throws.
  //
  // For every lattice column that becomes final (see Incision), the cutter, touching only mesh elements
  // under that column (a VertexGrid query of the column's control-point hull, no pass over the mesh):
  //  1. parameterises the vertices of the slab v in [j, j + 1) by inverting the undeformed lattice F0
  //     (damped Newton, volume_inversion.h);
  //  2. splits each edge whose end points lie on opposite sides of u = 1/2 and whose crossing lies inside
  //     the cut (after the stroke's start, above the blade's depth) at the crossing, in parameter space
  //     (paper §3.2); the new vertex is a seam vertex at u = 1/2 exactly. Degenerate coincidences: a vertex
  //     inside the cut within CutterOptions::snap_fraction of its shortest edge from u = 1/2 (on the plane,
  //     within rounding of it, a stroke along existing edges or through vertices) is snapped: it becomes a
  //     seam vertex where it is, and no edge is split that close to an end point, so no sliver is made;
  //  3. walks the seam (the chain of seam edges, the level set u = 1/2 on the surface) and, for every seam
  //     vertex with a seam neighbour on both sides, duplicates it: faces on the u >= 1/2 side move to the
  //     copy (evaluated at 1/2 + 0), the original keeps the u < 1/2 side (evaluated at 1/2 - epsilon);
  //  4. adds wall geometry for the depth of the cut (§4): below every duplicated seam vertex a column of
  //     `wall_rows` vertices per side down to one shared bottom vertex at the blade's depth, and two walls of
  //     triangles between consecutive columns, meeting at the bottom (the blade's V); at the seam's two ends
  //     the walls close in a fan. The mesh stays a closed two-manifold with its Euler characteristic.
  // Before step 1, where CutterOptions::refine asks for it, the skin faces within the column's control-point hull
  // that are coarser than the lattice are bisected along their longest edges (surface_cutter_refine.cpp), so a
  // coarse model is cut without subdividing all of it; the faces elsewhere stay as they were, bit for bit.
  // Then every vertex whose displacement changed is moved to rest + D(u, v, w) (Incision::displacementAt).
  // Where the blade's tip went past the tissue's far side (its depth >= the thickness there), the groove
  // stops at kFloorOfThickness of the thickness and, once the wound has its final opening (the first call
  // after it settles, or settle()), the blade's path below it is removed through the far side
  // (cutThrough(): a kerf kKerfM wide, CGAL's Boolean difference): the far skin is split too, a piece cut
  // free is a closed piece of its own, and IncisionFigures::through, pieces and piece_volumes_m3 say so.
  // That step is one corefinement of the mesh, O(mesh), not budgeted: made by the call that reaches it, or
  // by the caller's worker thread (setThroughOnWorker) and applied by a later call.
  // When an incision's work is done its IncisionFigures say where the groove runs along the stroke and, if
  // it is much shorter than the stroke, why (Shortfall: no contact, a mesh coarser than the lattice, ...):
  // a cut that did nothing never passes for one that did.
  CutStep extend(const StrokeSample& sample) noexcept;
  CutStep extend(std::span<const StrokeSample> samples) noexcept;
  // Adds a sample without processing: the work waits for the next advance() (a frame's one cutting call).
  // SampleOrigin::OnSurface: the caller found the point on the surface (a contact query), so the cutter
  // does not check again.
  CutStep addSample(const StrokeSample& sample, SampleOrigin origin = SampleOrigin::Unchecked) noexcept;
  // Lets the wound's opening evolve to time t_s without new samples (no-op without an active incision).
  CutStep advance(double t_s) noexcept;
  // The calls that follow (advance, extend, finish, settleStep but not settleStep(true)) stop their budgeted
  // work at `deadline` as well as after max_inversions_per_call units (work_budget.h); time_point::max():
  // none (the default: a replay not against the clock). Where a call stops never changes the mesh.
  void setDeadline(core::WorkBudget::Clock::time_point deadline) noexcept { deadline_ = deadline; }
  // Finishes the current incision: the cut reaches the last station. Never throws. With
  // FinishWork::Later the remaining work waits for advance().
  CutStep finish(FinishWork work = FinishWork::Now) noexcept;

  bool active() const noexcept { return incision_ != nullptr && !incision_->finished(); }
  // Lattice columns that are final, and how many of them have been cut: the cut is visible up to
  // columnsDone(). Both 0 without an incision.
  int columnsFinal() const noexcept { return incision_ ? incision_->finalColumns() : 0; }
  int columnsDone() const noexcept { return incision_ ? next_column_ : 0; }
  // The first crossing of the segment a -> b with the tissue surface (contact with the tool), through the
  // cutter's vertex grid, against the skin at rest for the current incision: vertices where they were when
  // it began, and every wall face left out — the current incision's and the earlier ones'; each skin face is
  // taken as the face it lies in as the incision began (its rest parent: refinement's bisections and the
  // seam's splits retriangulate within it). That surface does not depend on how far the cut's work has got,
  // so contact is the same, to the bit, whichever frame handles a pose (the earlier incisions' opened lips
  // are part of it; with PN refinement, which moves the skin, the faces themselves are taken). A blade
  // inside an earlier, open groove touches nothing: it is in the wound's air; back in the tissue beyond it, its first contact is the far lip's skin, where a
  // new incision starts (an incision begun on a wall's face, its normal across the stroke, could not chain
  // its seam from the wall onto the skin and cut nothing beyond the lip).
  // Cost O(vertices within one edge of the segment up to the crossing), queried a grid cell at a time from
  // `a`. No allocation once warmed up.
  std::optional<mesh::SurfacePoint> intersect(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
  // The skin faces around `box` as intersect() sees them (at rest for the current incision, walls left out):
  // every face with a corner within the query margin of the box (the longest edge, or refine_edge_m with
  // coarse vertices indexed apart), written to out[0 ..) up to its size. Returns how many there are (more
  // than out.size(): the rest were left out). For a haptic loop's local contact proxy. Cost O(vertices
  // in the grown box + their faces); no allocation once warmed up; 0 for a non-finite or empty box.
  int skinNear(const Eigen::AlignedBox3d& box, std::span<mesh::SkinTriangle> out) const;
  // Work carried to a later call (max_inversions_per_call): columns that are final but not yet cut.
  bool pending() const noexcept {
    return incision_ && !failed_ &&
           (next_column_ < incision_->finalColumns() ||
            through_state_.load(std::memory_order_acquire) != ThroughState::None);
  }
  // The through-cut's Boolean difference on a worker thread the caller runs (off: computed in the call
  // that makes it; not budgeted, O(mesh)). On: when an incision that went through has settled, the cutter
  // marks its through-cut due and waits (pending(), so no new incision begins); the caller hands it over
  // once with postThrough() (true: a job to give its worker) and the worker calls computeThrough() (any
  // thread: reads the tissue, writes the cutter's result only); a later call of the owner (advance,
  // prepareBegin) applies it, allocation-free within the reserved room; an unlimited one (settle(),
  // prepareBegin(true)) computes it itself or waits for the worker. The mesh is the same either way.
  void setThroughOnWorker(bool on) noexcept { through_on_worker_ = on; }
  bool postThrough() noexcept;
  void computeThrough() noexcept;
  const Incision* incision() const noexcept { return incision_.get(); }
  // The change journal (MeshChanges): off by default. On, every later change is appended (amortised
  // growth; room for kReservedChanges entries each is reserved when turned on); the consumer reads
  // changes() and calls clearChanges() (keeps the capacity). Turning it off clears it. Never throws
  // except std::bad_alloc from recordChanges(true).
  void recordChanges(bool on);
  const MeshChanges& changes() const noexcept { return changes_; }
  void clearChanges() noexcept { changes_.clear(); }
  static constexpr size_t kReservedChanges = 1 << 16;
  const CutStats& stats() const noexcept { return stats_; }
  // A cut through the tissue (IncisionFigures::through): the blade's path removed below the groove is a
  // kerf this wide across the cut (m), reaching this many sample spacings beyond the run's first and last
  // through samples (the blade was within a spacing of them: a stroke leaving the tissue across its edge
  // severs it).
  static constexpr double kKerfM = 1e-4;
  static constexpr double kKerfReachSpacings = 2.0;
  const mesh::SurfaceMesh& surface() const noexcept { return mesh_; }
  // Per-vertex data of the current incision: parameters (u, v, w) and rest position, if bound.
  struct Binding {
    Eigen::Vector3d uvw;
    Eigen::Vector3d rest_m;
    int side;  // -1, +1, 0 (on the seam, not duplicated), 2 (bottom of the cut)
  };
  std::optional<Binding> binding(mesh::TriMesh::VertexHandle v) const;

 private:
  struct VertexData {
    Eigen::Vector3d uvw = Eigen::Vector3d::Zero();
    Eigen::Vector3d rest_m = Eigen::Vector3d::Zero();
    int incision = -1;  // the incision this data belongs to; stale otherwise
    std::int8_t side = 0;
    bool seam = false;     // a seam vertex of this incision
    bool chained = false;  // in the chain
    bool doubled = false;  // duplicated (has a + copy and a wall column)
    std::uint32_t stamp = 0;
    int stencil = -1;      // its displacement stencil (Incision::stencil) in the stencil_* arrays
    int wall_column = -1;  // a duplicated seam vertex's column in wall_columns_
    int strip = -1;        // the wall strip from it to its successor in the chain, in strips_
  };
  struct WallColumn {
    std::vector<mesh::TriMesh::VertexHandle> minus, plus;  // [0] the lip, [wall_rows] the shared bottom
  };
  struct Strip {
    mesh::TriMesh::VertexHandle to;  // the chain successor of the vertex whose `strip` this is
    std::vector<mesh::TriMesh::FaceHandle> faces;
  };
  // The seam's chain in stroke order, grown at both ends inside one buffer (room reserved at each end).
  class Chain {
   public:
    void reset(std::size_t room_each_end);
    bool pushBack(mesh::TriMesh::VertexHandle v);  // false: the buffer had to grow (an allocation)
    bool pushFront(mesh::TriMesh::VertexHandle v);
    std::size_t size() const noexcept { return tail_ - head_; }
    bool empty() const noexcept { return tail_ == head_; }
    mesh::TriMesh::VertexHandle operator[](std::size_t i) const noexcept { return buffer_[head_ + i]; }
    mesh::TriMesh::VertexHandle front() const noexcept { return buffer_[head_]; }
    mesh::TriMesh::VertexHandle back() const noexcept { return buffer_[tail_ - 1]; }

   private:
    void recentre(std::size_t capacity);
    std::vector<mesh::TriMesh::VertexHandle> buffer_;
    std::size_t head_ = 0, tail_ = 0;
  };
  struct Crossing {  // splitCrossings(): an edge the cut crosses, by the larger v of its ends
    double key;
    int edge;
  };
  std::vector<Crossing> crossings_;
  // Scratch of duplicate(): the faces around a seam vertex and the copies of its + side's triangles.
  struct Around {
    mesh::TriMesh::FaceHandle face;
    int side;
  };
  // Each face's rest parent: the face of the surface as the current incision began that it lies in (its
  // three corners). Bisections ahead of the cut, the seam's splits and its duplication (faces re-attached
  // to a seam vertex's copy keep theirs) retriangulate the skin within its faces' planes; contact
  // (intersect) is taken with the parents, so it does not depend on how far that work had got when a pose
  // came (the same bits however the frames fall). PN refinement moves the skin off those planes: contact is
  // with the faces themselves there.
  static constexpr int kNoIncision = -2;  // below incision_index_'s -1 (none yet)
  struct RestParent {
    std::array<int, 3> corners{-1, -1, -1};
    int incision = kNoIncision;  // incision_index_ it was set in; another: the face is its own parent
  };
  struct PlusTriangle {
    mesh::TriMesh::VertexHandle v[3];
    mesh::FaceKind kind;
    RestParent parent;
    std::array<Eigen::Vector2d, 3> uv;  // the corners' texture coordinates (with the mesh's), as v
    int material = -1;                  // the face's material (with the mesh's)
  };

  VertexData& data(mesh::TriMesh::VertexHandle v) { return mesh_.mesh().property(vertex_data_, v); }
  const VertexData& data(mesh::TriMesh::VertexHandle v) const { return mesh_.mesh().property(vertex_data_, v); }
  bool bound(mesh::TriMesh::VertexHandle v) const {
    return incision_index_ >= 0 && data(v).incision == incision_index_;
  }

  CutStep process(CutStep step) noexcept;
  CutStep add(std::span<const StrokeSample> samples, SampleOrigin origin = SampleOrigin::Unchecked) noexcept;
  bool processColumn(int column, core::WorkBudget& budget, CutStep& step);  // false: budget spent, resume next call
  void queryColumn(int column, core::WorkBudget& budget);  // the column box's vertices into candidates_, charged
  int redeformMoves() const noexcept;  // about how many vertices redeform() will move (changed_columns_'s cells)
  bool bindVertex(mesh::TriMesh::VertexHandle v, int column, core::WorkBudget& budget);
  void snapOntoCut(mesh::TriMesh::VertexHandle v);            // v becomes a seam vertex at u = 1/2 (it stays in place)
  void snapNearEnd(mesh::TriMesh::EdgeHandle crossing);       // snaps the end point the crossing is within snap of
  bool insideCut(const Eigen::Vector3d& uvw) const noexcept;  // after the start, above the depth, to the end
  double snapDistance(mesh::TriMesh::VertexHandle v) const;   // snap_fraction x its shortest edge (m)
  bool nearCut(mesh::TriMesh::VertexHandle v, const Eigen::Vector3d& uvw) const;  // within snapDistance of u = 1/2
  int sideOf(mesh::TriMesh::VertexHandle v) const;       // a face's side from v: -1, +1, or 0 (on the seam, unknown)
  bool sidesKnown(mesh::TriMesh::VertexHandle c) const;  // every face around seam vertex c has a known side
  bool allColumnsDone() const noexcept {  // finished, and every column cut: no vertex will be bound any more
    return incision_ && incision_->finished() && next_column_ >= incision_->finalColumns();
  }
  void splitCrossings(const std::vector<mesh::TriMesh::VertexHandle>& fresh, CutStep& step);
  // Local refinement ahead of the cut (surface_cutter_refine.cpp): beginRefine collects the column's coarse
  // faces (false: none), continueRefine bisects them within the budget (false: spent, resume next call).
  bool beginRefine(int column);
  bool continueRefine(core::WorkBudget& budget, CutStep& step);
  // Recomputes v's coarse flag (an edge longer than the limit) from its and its neighbours' rest positions, or
  // with `current`, from where they are now (the next incision's rest, before begin() makes it so).
  void updateCoarse(mesh::TriMesh::VertexHandle v, bool current = false);
  void updateCoarseAround(mesh::TriMesh::VertexHandle v, bool current = false);  // v's and its neighbours'
  bool reindexStep(core::WorkBudget& budget);  // prepareBegin()'s second part; true when done
  static constexpr size_t kReindexMovesPerUnit = 8, kReindexCoarsePerUnit = 4;
  size_t reindexed_moves_ = 0, reindexed_coarse_ = 0;  // of all_bound_, by reindexStep
  void initCoarse();
  bool refinable(mesh::TriMesh::FaceHandle f, const Eigen::AlignedBox3d& box) const;
  mesh::TriMesh::HalfedgeHandle longestHalfedge(mesh::TriMesh::FaceHandle f) const;
  mesh::TriMesh::EdgeHandle terminalEdge(mesh::TriMesh::FaceHandle f) const;  // Rivara's LEPP from f
  bool splittable(mesh::TriMesh::EdgeHandle e) const;
  Eigen::Vector3d refinedPoint(mesh::TriMesh::HalfedgeHandle h) const;
  Eigen::Vector3d restNormal(mesh::TriMesh::VertexHandle v) const;
  bool onCrease(mesh::TriMesh::VertexHandle v, const Eigen::Vector3d& normal) const;
  mesh::TriMesh::VertexHandle bisect(mesh::TriMesh::EdgeHandle e, CutStep& step);
  mesh::TriMesh::VertexHandle addBoundVertex(const Eigen::Vector3d& rest_m, const Eigen::Vector3d& uvw, int side,
                                             mesh::VertexKind kind);
  void walkChain();
  // Where the tissue below a sample is thinner than the blade's depth there (its far side within
  // depth / kFloorOfThickness along -normal, at rest), the depth becomes kFloorOfThickness of the
  // thickness: the walls end inside the tissue instead of passing through its far side. Counted in the
  // incision's figures (thickness_limited_samples). True if it changed the sample.
  // Sets last_through_ when the blade's tip reached the far side (its depth >= the thickness there).
  bool limitToThickness(StrokeSample& sample) noexcept;
  // Where the blade went through the tissue (surface_cutter_through.cpp): the accepted samples whose tip
  // passed the far side, at rest, with the blade's depth and the tissue's thickness there.
  struct ThroughSample {
    Eigen::Vector3d point_m, normal;
    double depth_m, thickness_m;
  };
  std::vector<ThroughSample> through_;  // this incision's, in stroke order (reserved at construction)
  ThroughSample last_through_{};        // limitToThickness(): the last sample's, valid when through_last_
  bool through_last_ = false;
  bool through_done_ = false;  // cutThrough() has run for the current incision
  void noteThrough();          // an accepted sample: keeps last_through_ if through_last_
  // Once the incision has settled (its wound at its final opening) and some of its samples went through:
  // the blade's path is removed from the tissue down through its far side (a thin kerf swept along each
  // run of through samples, the runs' kerfs one solid, mesh::differenceOf), so that a piece cut free is a
  // closed piece of its own; the figures get the pieces and their volumes. The groove above stays the
  // DFFD's. Then the grid indexes the new vertices. The difference is computed at once
  // (computeThroughPatch, then applyThrough), or with setThroughOnWorker(true) by the caller's worker:
  // through_state_ goes Due -> Posted (postThrough) -> Running (computeThrough, or throughStep's caller
  // when unlimited) -> Ready -> applied by throughStep on the owner's thread -> None. Nothing else in the
  // cutter runs while it is not None (pending() is true), so the tissue the worker reads does not change.
  void cutThrough();
  void appendKerf(mesh::SurfaceMesh& kerfs, std::size_t first, std::size_t last) const;  // one run's
  void computeThroughPatch() noexcept;        // any thread: reads the mesh and through_, writes through_patch_
  void applyThrough() noexcept;               // the owner's thread: through_patch_ applied, grid and journal
  bool throughStep(bool unlimited) noexcept;  // true when no through-cut waits (applies a Ready one)
  enum class ThroughState : std::uint8_t { None, Due, Posted, Running, Ready };
  bool through_on_worker_ = false;
  bool through_by_worker_ = false;  // the Ready patch came from computeThrough() (set before Ready)
  std::atomic<ThroughState> through_state_{ThroughState::None};
  mesh::SolidDifference through_patch_;  // written by whoever computes, read by applyThrough (acquire)
  // The tissue's thickness below a sample (infinity: no far side within depth_m / kFloorOfThickness): the
  // least thickness_below_m_ of the loaded mesh's vertices within a mean edge of it (within the longest
  // edge when none is that near). One small grid query, or none within a lattice spacing of the last one.
  double thicknessBelow(const StrokeSample& sample) noexcept;
  // Once every column is cut: the seam's first and last vertices are the last crossings inside the cut,
  // where the opening is not yet 0; each end is carried one face further, to where the cut's plane leaves
  // the face beside it (crossBeyond), where the opening is 0 on both sides: the lips close where the seam
  // ends, and no face beyond it is torn.
  void capSeamEnds(CutStep& step);
  // Whether the wound opens at parameter v along the cut (its seam vertices there are duplicated).
  bool opensAt(double v) const noexcept;
  // The seam vertex where the cut's plane leaves a face of `end` (its far edge split there, or an end
  // point of that edge snapped onto the cut); invalid when no face of `end` is crossed.
  mesh::TriMesh::VertexHandle crossBeyond(mesh::TriMesh::VertexHandle end);
  // After a column's splits: the skin faces around the seam vertices it and the column before made, where a
  // seam vertex p lies nearly on the face's far edge a-b (the face a sliver, its widest angle at p: a split
  // or snap next to an edge nearly along the cut leaves one). The opening moves p sideways more than a side
  // vertex of a-b, and p would pass over a-b: the face folds over its neighbour or the wall's top. Edge a-b
  // is flipped to p-d (d the far corner of the face across it, a bound vertex on a-b's side) when the worse
  // of the two new faces is better than the worse of the two old ones and both keep the old orientation, at
  // rest. Topology only: the vertices stay, no edge crosses the cut (p is on it), no allocation.
  // O(faces around those seam vertices).
  void relieveSlivers(std::size_t first_seam);
  bool flipSliver(mesh::TriMesh::VertexHandle p, mesh::TriMesh::HalfedgeHandle far_edge);
  bool sideVertex(mesh::TriMesh::VertexHandle v) const;  // bound, off the seam and the walls, side -1 or +1
  // Splits edge `e`, whose end points lie on the two sides, where it crosses u = 1/2: a new seam vertex.
  mesh::TriMesh::VertexHandle splitAtCut(mesh::TriMesh::EdgeHandle e);
  void promoteInterior(CutStep& step);
  bool duplicate(mesh::TriMesh::VertexHandle c, mesh::TriMesh::VertexHandle prev, mesh::TriMesh::VertexHandle next);
  void buildWallColumn(mesh::TriMesh::VertexHandle c);
  void deleteStrip(mesh::TriMesh::VertexHandle a, mesh::TriMesh::VertexHandle b);
  bool buildStrip(mesh::TriMesh::VertexHandle a, mesh::TriMesh::VertexHandle b, CutStep& step);
  bool addStripSide(const std::vector<mesh::TriMesh::VertexHandle>& a,
                    const std::vector<mesh::TriMesh::VertexHandle>& b, std::vector<mesh::TriMesh::FaceHandle>& faces);
  void redeform(CutStep& step);
  void setStencil(mesh::TriMesh::VertexHandle v);
  void fail(const std::string& message);
  void diagnose() noexcept;  // the incision's work is done: its figures' last fields (surface_cutter_figures.cpp)
  double grooveLength() const noexcept;  // the current chain's arc length at rest (IncisionFigures)
  void reserveHeadroom();
  Eigen::Vector3d restPosition(mesh::TriMesh::VertexHandle v) const;
  static constexpr size_t kHeadroomVertices = 200000;  // new vertices one incision may add without regrowth
  size_t reserved_vertices_ = 0;                       // what reserveHeadroom last reserved room for
  bool onSurface(const Eigen::Vector3d& p) const;
  // Whether a seam or wall vertex (an earlier incision's: the current one's trail its newest sample by
  // about three spacings) lies within 1.5 spacings of p at rest: StrokeSample::in_wound. A grid query
  // into query_ (no allocation once it has grown to a contact query's size).
  bool inWound(const Eigen::Vector3d& p) const;
  // query_: the vertices whose faces may meet the box; a new face stamp for skipForContact.
  void queryRest(const Eigen::AlignedBox3d& box) const;
  bool skipForContact(mesh::TriMesh::FaceHandle f) const;  // seen in this query already, or a wall
  // Rest parents (RestParent above): set, kept through a flip, and the triangle contact is taken with.
  void adoptParent(mesh::TriMesh::FaceHandle f);   // a face its own parent unless set in this incision
  void adoptParents(mesh::TriMesh::EdgeHandle e);  // adoptParent for the faces on both sides of an edge
  void afterFlip(mesh::TriMesh::FaceHandle f, mesh::TriMesh::FaceHandle g);  // parents of a flipped pair
  std::array<Eigen::Vector3d, 3> contactCorners(mesh::TriMesh::FaceHandle f) const;
  OpenMesh::FPropHandleT<RestParent> rest_parent_;
  // Texture coordinates and materials, when the mesh has them (surface_cutter_texture.cpp): every face the
  // cutter makes gets its corners' coordinates and a material. A split point takes, in each face it splits,
  // the interpolation of the edge's ends there (so a texture seam along or across the edge stays one), and
  // the new faces their split faces' materials (OpenMesh's split_copy); a flip keeps each corner's
  // coordinate (an edge with a texture seam or a material boundary along it is not flipped); faces moved to
  // a seam vertex's copy keep theirs; wall faces get the wall's (wallTexCoord; their material is the
  // writer's, by kind). No allocation. O(1) each.
  struct SplitCorners {
    std::array<std::optional<mesh::FaceCorners>, 2> side;  // the faces on edge e's two sides, before
    mesh::TriMesh::VertexHandle a, b;                      // halfedge(e, 0)'s from and to vertex
  };
  SplitCorners splitCorners(mesh::TriMesh::EdgeHandle e) const;
  void cornersAfterSplit(mesh::TriMesh::VertexHandle v, double lambda, const SplitCorners& before);
  // ab's ends' coordinates differ between its two faces, or the faces' materials do.
  bool textureSeamAlong(mesh::TriMesh::HalfedgeHandle ab) const;
  void cornersAfterFlip(mesh::TriMesh::FaceHandle f, mesh::TriMesh::FaceHandle g, const mesh::FaceCorners& was_f,
                        const mesh::FaceCorners& was_g);
  void setWallCorners(mesh::TriMesh::FaceHandle f);
  // f's corners' coordinates into t.uv (as t.v) and its material; back onto t's face re-added.
  void keepCorners(mesh::TriMesh::FaceHandle f, PlusTriangle& t) const;
  void restoreCorners(mesh::TriMesh::FaceHandle added, const PlusTriangle& t);
  // A wall vertex's texture coordinate: (arc length along the stroke from its start, depth below the lip
  // as a fraction of the blade's depth option x that depth), both in metres over mesh::kWallTextureTile_m.
  Eigen::Vector2d wallTexCoord(mesh::TriMesh::VertexHandle v) const;
  bool textured_ = false;  // the mesh has texture coordinates

  mesh::SurfaceMesh& mesh_;
  CutterOptions options_;
  OpenMesh::VPropHandleT<VertexData> vertex_data_;
  mesh::VertexGrid grid_;
  double contact_tolerance_m_ = 0.0;
  double longest_edge_m_ = 0.0;
  double mean_edge_m_ = 0.0;
  bool no_contact_ = false;  // the current incision's first sample was off the surface
  std::unique_ptr<Incision> incision_;
  std::unique_ptr<Incision> spare_;  // made at construction, restarted by begin(): no allocation there
  int incision_index_ = -1;
  int next_column_ = 0;
  bool seam_capped_ = false;     // capSeamEnds() has run for the current incision
  bool column_started_ = false;  // next_column_'s step is under way: candidates_ and fresh_ are live
  // A column's grid query is charged to the budget: one unit per kCandidatesPerUnit vertices found (about
  // 60 ns each on the 940k bunny, memory latency; a unit is a Newton inversion, about 3.5 us).
  static constexpr std::size_t kCandidatesPerUnit = 64;
  // redeform()'s moves are charged too, before the columns' work (kMovesPerUnit vertices a unit, about 55
  // ns each on the 940k bunny), at most half the budget so that binding always goes on.
  static constexpr int kMovesPerUnit = 64;
  // A column's crossings and seam walk: one unit per kFreshPerUnit vertices bound in it.
  static constexpr std::size_t kFreshPerUnit = 16;
  // limitToThickness(): the floor at most this share of the tissue's thickness; the segment starts this far
  // inside the skin (so it does not meet the skin it starts on).
  static constexpr double kFloorOfThickness = 0.8;
  static constexpr double kSkinM = 1e-5;
  // intersect(): a segment longer than a grid cell is queried in at most this many pieces, each about a cell.
  static constexpr int kMaxProbePieces = 64;
  // A sample deeper than this many times incision.depth_m is counted as clamped (a tip held at the clamp
  // measures a hair over it where the contact's normal differs from the stroke's).
  static constexpr double kClampedOver = 1.05;
  bool jumped_ = false;  // the last sample was SkippedJump
  struct ThicknessProbe {
    bool valid = false;
    Eigen::Vector3d at_m = Eigen::Vector3d::Zero();
    double thickness_m = 0.0;
  } thickness_;  // the last thicknessBelow() query
  // The loaded mesh's thickness under each vertex (mesh::thicknessBelowVertices, at construction, up to
  // depth_m / kFloorOfThickness), by vertex index; vertices made later have none.
  std::vector<float> thickness_below_m_;
  // Each station's rows end at kFloorOfThickness of the tissue along them (the loaded mesh's surface, by
  // one segment query on `rays`): a row lagging the surface over a sharp edge does not reach its far side.
  struct RowProbe final : RowLimit {
    std::unique_ptr<mesh::SurfaceRays> rays;
    double rowDepth(const Eigen::Vector3d& point_m, const Eigen::Vector3d& inward,
                    double want_m) const noexcept override;
  } row_probe_;
  int last_query_units_ = 0;  // the last column query's units: the next one waits for as much budget
  size_t next_candidate_ = 0;
  std::vector<mesh::TriMesh::VertexHandle> fresh_;
  double time_s_ = 0.0;
  std::uint32_t stamp_ = 0;
  // Bound vertices by lattice cell floor(v), in the order they were bound: a list per cell through one pool
  // (cell_first_, cell_last_: pool indices or -1; cell_next_: the next in the same cell or -1).
  std::vector<int> cell_first_, cell_last_, cell_next_;
  std::vector<int> cell_count_;  // per cell: the vertices bound in it (deleted ones too)
  std::vector<mesh::TriMesh::VertexHandle> cell_vertex_;
  void addToCell(int cell, mesh::TriMesh::VertexHandle v);
  bool cellEmpty(int cell) const noexcept { return cell_first_[static_cast<std::size_t>(cell)] < 0; }
  std::vector<mesh::TriMesh::VertexHandle> all_bound_;     // every vertex bound to this incision
  std::vector<mesh::TriMesh::VertexHandle> seam_created_;  // seam vertices in order of creation
  // seam_created_'s size when the current and the previous column's steps began (relieveSlivers)
  std::size_t column_seam_begin_ = 0, previous_seam_begin_ = 0;
  Chain chain_;
  std::vector<WallColumn> wall_columns_;  // pool: [0, wall_columns_used_) this incision's
  std::size_t wall_columns_used_ = 0;
  std::vector<Strip> strips_;  // pool: [0, strips_used_) this incision's
  std::size_t strips_used_ = 0;
  std::vector<Around> around_;                          // duplicate()'s scratch
  std::vector<PlusTriangle> plus_;                      // ...
  std::vector<mesh::TriMesh::FaceHandle> strip_faces_;  // buildStrip()'s scratch
  std::vector<mesh::TriMesh::VertexHandle> side_a_, side_b_;
  void reserveIncisionArrays();  // at construction: what one incision uses (reserved_bound_vertices)
  template <typename Vector, typename Value>
  void pushReserved(Vector& v, Value&& value) {  // push_back, counting a growth past the reserve
    if (v.size() == v.capacity()) ++stats_.reserve_overflows;
    v.push_back(std::forward<Value>(value));
  }
  std::vector<mesh::TriMesh::VertexHandle> dirty_;
  // Per bound vertex: 1 or 2 evaluations (count), their corner controls (2 slots) and basis values
  // (2 x stencilSize() slots): re-deforming is then one weighted sum per evaluation.
  std::vector<std::uint8_t> stencil_count_;
  std::vector<int> stencil_first_;
  std::vector<double> stencil_basis_;
  std::vector<int> changed_columns_, candidates_;
  std::vector<int> refine_query_, refine_faces_;  // the column's refinement: scratch, and the faces left to
                                                  // refine (a stack; reserved at construction)
  double refine_edge_m_ = 0.0;                    // refineEdgeLength(options_)
  Eigen::AlignedBox3d refine_box_;                // the column's control-point hull being refined
  bool refining_ = false;                         // next_column_'s refinement is under way
  int refine_splits_ = 0;                         // edges it has bisected
  // Per vertex: it has an edge longer than refine_edge_m_ at rest (stale only upwards: a vertex flagged may
  // have none left, which costs a look; one unflagged has none), and how many are flagged: refinement looks
  // only at the faces of flagged vertices, and not at all while none is.
  OpenMesh::VPropHandleT<std::uint8_t> coarse_;
  int coarse_vertices_ = 0;
  mesh::VertexGrid coarse_grid_;                       // the flagged vertices, at rest
  OpenMesh::VPropHandleT<Eigen::Vector3d> coarse_at_;  // where each is in coarse_grid_
  OpenMesh::VPropHandleT<double> coarse_reach_;        // each vertex's longest edge at rest (m)
  mutable std::vector<int> query_;                     // scratch for intersect(), onSurface(), inWound()
  mutable std::vector<std::uint32_t> face_stamp_;      // intersect(): the query that last tested each face
  mutable std::uint32_t face_query_ = 0;
  CutStats stats_;
  MeshChanges changes_;
  bool record_changes_ = false;
  void vertexChanged(mesh::TriMesh::VertexHandle v) {
    if (record_changes_) changes_.vertices.push_back(v.idx());
  }
  void faceChanged(mesh::TriMesh::FaceHandle f) {
    if (record_changes_) changes_.faces.push_back(f.idx());
  }
  bool failed_ = false;
  core::WorkBudget::Clock::time_point deadline_ = core::WorkBudget::Clock::time_point::max();  // setDeadline()
  bool unlimited_ = false;  // process() ignores the budget (finishing a previous incision's work)
};

}  // namespace incise::incision
