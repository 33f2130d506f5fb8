// The tissue's finite-element model on the (cut) tets: co-rotational linear elasticity on linear tets with
// lumped masses, stepped by linearised implicit (backward) Euler; each step's linear system solved by
// conjugate gradients, block-Jacobi preconditioned and warm-started, on a sparse matrix assembled in place.
// No factorisation is held, so a cut changes the model in O(changed) (apply()). The rotation of each tet
// is the proper rotation closest to its deformation gradient (Mueller et al. 2016, warm-started), which for
// an inverted tet is the rotation of Irving et al. 2004: a crushed or inverted tet pushes back, never explodes.
//
// Shapes: nodes #N x 3 (Eigen::Vector3d), indexed as the tet mesh's (and the tet cutter's) nodes; elements
// are the pieces of base tets. Units: SI (m, s, kg, N, Pa). Threads: one owner (the physics thread); no
// clock, no thread of its own. Cost per step: O(elements + CG iterations x matrix entries); see
// docs/benchmarks.md. Allocation: none in step(), contactModel() and locate(), nor in apply() within the
// reserve (ModelOptions). Failure: the constructor throws std::invalid_argument; nothing else throws except
// std::bad_alloc (apply() past its reserve, solveStatic()); step() reports a bad dt or a non-finite state.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "incise/mesh/vertex_grid.h"
#include "incise/physics/contact_model.h"
#include "incise/physics/cut_changes.h"
#include "incise/physics/embedding.h"
#include "incise/physics/material.h"
#include "incise/physics/rest_map.h"
#include "incise/tets/tet_mesh.h"

namespace incise::physics {

struct ModelOptions {
  double cg_tolerance = 1e-3;  // a step's CG stops at |r| <= tol x max(|b|, h |M g|) (momentum units)
  int max_cg_iterations = 60;  // beyond it the step is taken with what CG has (status IterationLimit)
  // CG's first guess: v + the last step's dv (constant acceleration) while the tissue moves, else v. On
  // the benchmark's swinging beams it saves 15-40% of the iterations and most steps at the cap.
  bool extrapolate_velocity = true;
  // CG's preconditioner: block SSOR with this relaxation in (0, 2) (1: symmetric Gauss-Seidel), or 0 for
  // block Jacobi. 1.3-1.5 converge in about 25% fewer iterations than 1 on the benchmark's grids.
  double ssor_relaxation = 1.4;
  // CG's coarse level (a two-level preconditioner with SSOR): six rigid-body modes on each of up to
  // coarse_aggregates aggregates of the free nodes (0: SSOR alone), each of at least
  // coarse_nodes_per_aggregate nodes (fewer aggregates on a small tissue; none below two), its matrix built
  // from the step's own, in the steps where CG needs many iterations and the coarse level cuts them (a
  // settled tissue, or one whose iterations it does not cut, runs SSOR alone). On the benchmark's swinging
  // grids CG's p99 iterations fall 2-2.5x.
  int coarse_aggregates = 16;
  int coarse_nodes_per_aggregate = 64;
  double rotation_tolerance = 1e-6;  // per-tet rotation: stop when the correction is below this (radians)
  int max_rotation_iterations = 8;   // per tet per step (warm-started: 1 or 2 in smooth motion)
  int reserve_nodes = 20000;         // nodes cuts may add before apply() allocates (the tet cutter's headroom)
  int reserve_elements = 100000;     // pieces cuts may add (pieces of a base tet: up to 16)
};

enum class StepStatus : std::uint8_t {
  Converged,       // CG met its tolerance
  IterationLimit,  // taken with CG's last iterate (max_cg_iterations)
  BadTimeStep,     // dt not finite or <= 0: nothing done
  NonFinite,       // the solve gave a non-finite velocity: positions kept, velocities zeroed
};
const char* toString(StepStatus status) noexcept;

struct StepStats {
  StepStatus status = StepStatus::Converged;
  int cg_iterations = 0;
  double relative_residual = 0.0;  // |r| / max(|b|, h |M g|) at the end
  int inverted_elements = 0;       // det F <= 0 at the start of the step
  bool coarse_level = false;       // CG used its coarse level (ModelOptions::coarse_aggregates)
};

struct ChangeStats {
  int nodes_added = 0, nodes_moved = 0;
  int elements_removed = 0, elements_added = 0;
  int pieces_refused = 0;    // a node index never given a rest position, or not positive at rest (skipped)
  int elements_updated = 0;  // rest shapes recomputed because a node moved
};

struct StaticOptions {
  double force_tolerance = 1e-8;  // stop when |residual force| <= tol x |external + gravity force|
  int max_newton_iterations = 300;
  double cg_tolerance = 1e-10;  // relative, per Newton step
  int max_cg_iterations = 100000;
  double rotation_tolerance = 1e-13;  // per tet (instead of ModelOptions' during the solve)
  int max_rotation_iterations = 50;
};

struct StaticResult {
  bool converged = false;
  int newton_iterations = 0;
  int cg_iterations = 0;  // over all Newton iterations
  double relative_force_residual = 0.0;
};

class TissueModel {
 public:
  // Load time: one element per tet of `mesh` (base tet t = mesh.tets[t], with `sides[t]` if given),
  // positions at rest, velocities zero. Throws std::invalid_argument for a bad material or boundary
  // (validate), a tet with a node out of range or not positive at rest (its index), `sides` of the wrong
  // size, or no node held (a free tissue has no rest).
  TissueModel(const tets::TetMesh& mesh, const Material& material, const Boundary& boundary,
              const ModelOptions& options = {}, std::span<const int> sides = {});

  // One implicit step of dt_s. Cut changes given to apply() are already in. Never throws.
  StepStats step(double dt_s) noexcept;
  std::int64_t steps() const noexcept;

  // The static equilibrium under gravity, the external forces and the held nodes, by Newton iterations with
  // the same element operators (co-rotation updated each iteration; each linear step solved by CG).
  // Velocities are zeroed. The tangent has no stress stiffness (as the step's), so where the stress is large
  // next to the softest mode's stiffness it converges linearly (a bar in 1% tension on 1,920 tets: x 0.89 an
  // iteration). For tests and load time, not the physics loop (it may take seconds on a fine mesh).
  StaticResult solveStatic(const StaticOptions& options = {});

  // State. Spans are valid until the next apply() (which may add nodes).
  int nodeCount() const noexcept;
  std::span<const Eigen::Vector3d> positions_m() const noexcept;
  std::span<const Eigen::Vector3d> velocities_m_per_s() const noexcept;
  std::span<const Eigen::Vector3d> restPositions_m() const noexcept;
  // Copies min(out.size(), nodeCount()) positions into out; returns how many. O(N), no allocation.
  std::size_t copyPositions(std::span<Eigen::Vector3d> out) const noexcept;
  double mass_kg(int node) const noexcept;
  double totalMass_kg() const noexcept;
  double maxDisplacement_m() const noexcept;  // the largest distance of a node from its rest position, O(N)
  bool isHeld(int node) const noexcept;       // by the boundary or holdNode()
  int elementCount() const noexcept;          // live pieces
  int baseTetCount() const noexcept;
  // Positions back to rest, velocities to zero (the held nodes to their targets).
  void resetState() noexcept;

  // The tool. Forces stay until cleared. A held node stays at x_m through steps until released (back to
  // its boundary's rest if the boundary holds it). Node indices out of range are ignored.
  void clearExternalForces() noexcept;
  void addNodeForce(int node, const Eigen::Vector3d& force_N) noexcept;
  void addPointForce(const Embedded& point, const Eigen::Vector3d& force_N) noexcept;  // by its weights
  void holdNode(int node, const Eigen::Vector3d& x_m) noexcept;
  void releaseNode(int node) noexcept;
  void setPosition(int node, const Eigen::Vector3d& x_m) noexcept;  // once (a free node moves on from there)
  // The tool pressing on the skin (a dent, before the blade cuts in): a spring of stiffness_N_per_m along
  // `normal` (the skin's outward unit normal at the point, deformed) between the embedded point `anchor`
  // and the tool's tip tool_m, pushing the point in while the tip is below it ((point - tip) . normal > 0),
  // never pulling. step() and solveStatic() take it implicitly (its stiffness in the matrix: stable however
  // stiff the spring) until cleared or set again. O(1); the step's cost is unchanged.
  void setToolPress(const Embedded& anchor, const Eigen::Vector3d& normal, const Eigen::Vector3d& tool_m,
                    double stiffness_N_per_m) noexcept;
  void clearToolPress() noexcept;
  // The force the press put on the tissue at the last step's start (N, at the anchor; zero: not pushing).
  Eigen::Vector3d toolPressForce_N() const noexcept;

  // A cut: nodes new or moved at rest, base tets replaced by their pieces (new base tets appended). New
  // nodes start where the tissue around them is (their rest position mapped through the tet that held it),
  // velocity zero; a node given a rest inside a fixed box is held. Masses are redistributed (each piece
  // gives a quarter of its mass to each of its nodes), rest shapes of pieces around moved nodes recomputed.
  // O(changed nodes + changed pieces + their neighbourhoods). Call between steps, on the physics thread.
  ChangeStats apply(const CutChanges& changes);

  // The tet (accepted by `filter`) that contains rest_m at rest, with rest_m's barycentric weights in it;
  // if none contains it, the nearest within max_distance_m (weights extrapolated). nullopt if none.
  // O(tets near the point). Thread: the owner's (it uses a scratch list).
  std::optional<Embedded> locate(const Eigen::Vector3d& rest_m, ElementFilter filter = {},
                                 double max_distance_m = 1e-3) const;

  // The rest point the tissue carries at world_m now, as a map linearised there (rest_map.h): Newton on the
  // deformation of the tet holding the guess, at most 4 locates. Guess: where world_m was at rest in the
  // last map near it (a tool followed from step to step: RestMap::toRest of the previous step's map), or
  // world_m itself (the tissue undeformed there). The identity (located false) when no tet is within
  // reach_m of the guess at rest. O(tets near the point), no allocation; never throws. Thread: the owner's.
  RestMap restMap(const Eigen::Vector3d& world_m, const Eigen::Vector3d& guess_rest_m,
                  double reach_m = 0.002) const noexcept;
  RestMap restMap(const Eigen::Vector3d& world_m) const noexcept { return restMap(world_m, world_m); }

  // The contact point's local model after the last step (contact_model.h): its position and deformed
  // normal (rest_normal mapped by its tet), and its effective stiffness over a step from three CG solves
  // with the last step's matrix (warm-started from the previous call's). O(3 CG solves). Never throws.
  ContactModel contactModel(const Embedded& point, const Eigen::Vector3d& rest_normal) noexcept;

  const Material& material() const noexcept;
  const Boundary& boundary() const noexcept;
  const ModelOptions& options() const noexcept;
  int reserveOverflows() const noexcept;       // growth past the reserve (each an allocation in apply())
  std::size_t matrixEntries() const noexcept;  // 3 x 3 blocks in use (upper triangle with the diagonal)

  ~TissueModel();
  TissueModel(TissueModel&&) noexcept;
  TissueModel& operator=(TissueModel&&) noexcept;

  struct State;  // private (src/tissue_model_state.h)

 private:
  std::unique_ptr<State> s_;
};

}  // namespace incise::physics
