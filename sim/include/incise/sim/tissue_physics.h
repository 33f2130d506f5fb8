// The simulated tissue in the world: the physics module's finite-element model (physics/tissue_model.h) on
// the tet cutter's tets, fed the cutter's change journal and stepped at a fixed rate of simulated time.
// World owns it (a tissue with `material`); the sim thread does everything here, inside the frame.
//
// Stepping: step k (k = 1, 2, ...) is due at t_first + k / rate_hz, t_first the time of the first frame
// advance() saw; advance(t_s) takes every step due at or before t_s, each of 1 / rate_hz. It depends on the
// frames' simulated times only, never on a clock: `replay --fast` and a real-time replay give the same bytes.
// Cuts: collect() reads the cutter's journal past what it read before (the journal may be shared with a
// geometry stream that clears it: journalCleared()), and advance() applies what was collected before its
// steps, in the frame the cut was made (physics/cut_changes.h).
//
// Units: SI (m, s, Hz). Threads: the sim thread. Cost: advance() O(changes) + a step per due tick (a step
// is O(elements + CG iterations x matrix entries): docs/benchmarks.md). Allocation: the model and the
// change buffer at construction; none after, within their reserves (growth is counted in
// PhysicsCounters::reserve_overflows). Failure: the constructor throws std::invalid_argument (a bad
// material, a boundary that holds no node: the model's message); collect() and advance() never throw.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "incise/physics/cut_changes.h"
#include "incise/physics/embedding.h"
#include "incise/physics/material.h"
#include "incise/tets/tet_mesh.h"

// No OpenMesh in sim's public headers: the model (physics/tissue_model.h) and the surface through pointers.
namespace incise::mesh {
class SurfaceMesh;
}
namespace incise::physics {
class TissueModel;
}
namespace incise::tets {
class TetCutter;
struct TetView;
}  // namespace incise::tets

namespace incise::sim {

// A simulated tissue (scenario keys tissue.material, tissue.fixed, gravity_m_per_s2, physics_rate_hz).
struct PhysicsOptions {
  bool enabled = false;
  physics::Material material;
  physics::Boundary boundary{{}, {}, Eigen::Vector3d::Zero()};  // gravity [0, 0, 0] unless the scenario says
  double rate_hz = 100.0;                                       // steps per second of simulated time
};

struct PhysicsCounters {
  std::int64_t steps = 0;
  std::int64_t cg_limited = 0;         // steps taken at CG's iteration cap (StepStatus::IterationLimit)
  std::int64_t non_finite = 0;         // steps whose solve was not finite (velocities zeroed)
  std::int64_t cuts_applied = 0;       // journals applied (frames whose cut changed the tets)
  std::int64_t pieces_refused = 0;     // pieces the model could not take (ChangeStats::pieces_refused)
  std::int64_t reserve_overflows = 0;  // growth past the model's or the change buffer's reserve
  std::int64_t failed_applies = 0;     // applies that ran out of memory (their changes are lost)
  int max_inverted = 0;                // the most inverted elements at the start of a step
};

class TissuePhysics {
 public:
  // `mesh` must be the mesh the tet cutter is built with (same node and tet order).
  TissuePhysics(const tets::TetMesh& mesh, const PhysicsOptions& options);
  ~TissuePhysics();

  // The cutter's journal entries not read yet into the change buffer. Never throws.
  void collect(const tets::TetCutter& cutter) noexcept;
  // The journal was cleared by its owner: read it from its start next time.
  void journalCleared() noexcept { read_nodes_ = read_base_tets_ = 0; }
  // Applies the collected changes, then takes every step due at or before t_s. Returns the steps taken.
  int advance(double t_s) noexcept;

  // The surface's vertices embedded in the tets at rest (the surface's positions are the tets' rest: both
  // are the cut as the incision left it), each on its own side of every cut: the side of the tet holding a
  // point just inside the surface next to the vertex (among its neighbours, behind its normal), so that a
  // lip's vertex follows its own lip's tets. Vertices outside every tet take the nearest within 1 mm (weights
  // extrapolated); farther ones are left where they are (nodes -1). O(V x tets near a point); allocates: for
  // outputs and checks, not the sim thread.
  std::vector<physics::Embedded> embedSurface(const mesh::SurfaceMesh& surface) const;
  // The surface as simulated: a copy with every embedded vertex at its deformed position.
  mesh::SurfaceMesh deformedSurface(const mesh::SurfaceMesh& surface) const;
  // A tet cutter's view (TetCutter::view: used nodes in index order) with its nodes at the model's current
  // positions (the same tets). Allocates.
  void deform(tets::TetView& view, const tets::TetCutter& cutter) const;

  // FNV-1a over the bits of every node's current position (determinism checks). O(N).
  std::uint64_t positionsHash() const noexcept;

  double rateHz() const noexcept { return options_.rate_hz; }
  double stepS() const noexcept { return 1.0 / options_.rate_hz; }
  // The model (include incise/physics/tissue_model.h to use it).
  const physics::TissueModel& model() const noexcept { return *model_; }
  physics::TissueModel& model() noexcept { return *model_; }
  const PhysicsCounters& counters() const noexcept { return counters_; }

 private:
  PhysicsOptions options_;
  std::unique_ptr<physics::TissueModel> model_;
  physics::CutChanges changes_;
  std::size_t read_nodes_ = 0, read_base_tets_ = 0;
  bool started_ = false;
  double t_first_s_ = 0.0;
  std::int64_t next_step_ = 1;
  PhysicsCounters counters_;
};

}  // namespace incise::sim
