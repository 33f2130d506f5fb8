// The simulated tissue in the world: the physics module's finite-element model (physics/tissue_model.h) on
// the tet cutter's tets, fed the cutter's change journal and stepped at a fixed rate of simulated time.
// World owns it (a tissue with `material`). It steps either on the calling thread (advance() takes the due
// steps itself: World::step, tests, bindings) or, between startThread() and stopThread(), on a physics thread
// of its own (Simulation's replays and live sessions): then advance() only hands each due step over and the
// sim thread never waits for a step.
//
// Stepping: step k (k = 1, 2, ...) is due at t_first + k / rate_hz, t_first the time of the first frame
// advance() saw; advance(t_s) makes every step due at or before t_s, each of 1 / rate_hz. Cuts: collect()
// reads the cutter's journal past what it read before (the journal may be shared with a geometry stream that
// clears it: journalCleared()) into a change buffer; the changes collected before step k became due are
// applied right before step k (physics/cut_changes.h), on whichever thread steps. So step k's inputs are the
// cuts of the frames up to its time, whatever the clock: `replay --fast`, a real-time replay and an inline
// run give the same bytes.
//
// The handoff (threaded): per due step one message {step, change buffer or none, wall time due} into a
// fixed SPSC queue (kQueuedSteps), the change buffer one of kChangeSlots reserved at startThread() and given
// back by the physics thread once applied. Neither end allocates or locks. When the handoff is full the sim
// thread either waits (PhysicsThreadOptions::wait_for_room: fast replays, never in real time) or does not:
// a full queue holds the step back to go with the next one, a missing free buffer leaves the changes to go
// with a later step (counted: PhysicsCounters::deferred; only then can a real-time run differ from a fast
// one). A step is late (PhysicsCounters::late) when it finished more than one physics period of wall time
// (1 / rate_hz x wall_per_simulated_s) after the frame that made it due handed it over (never in a fast
// replay: wall_per_simulated_s 0).
//
// Units: SI (m, s, Hz). Threads: the owner (the sim thread) calls everything but the hook; between
// startThread() and stopThread() the model, its readers (model(), deformedSurface(), deformedPoint(), deform(),
// positionsHash()) and counters() belong to the physics thread: read them after stopThread(); stepsDone()
// and lateSteps() may be read from any thread, latestState() from one reader thread (a triple buffer the
// physics thread publishes the node positions into after every step). Cost: advance() O(changes) + a step per due tick inline (a
// step is O(elements + CG iterations x matrix entries): docs/benchmarks.md), O(1) per due tick threaded.
// Allocation: the model and the change buffers at construction and startThread(); none after, within their
// reserves (growth is counted in PhysicsCounters::reserve_overflows), on either thread. Failure: the
// constructor throws std::invalid_argument (a bad material, a boundary that holds no node: the model's
// message), startThread() std::system_error (no thread); collect() and advance() never throw.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "incise/physics/cut_changes.h"
#include "incise/physics/embedding.h"
#include "incise/physics/material.h"
#include "incise/physics/rest_map.h"
#include "incise/sim/spsc_queue.h"
#include "incise/sim/triple_buffer.h"
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
  // The tool's spring on the skin while it presses without cutting in (World: tissue.stiffness_N_per_m, the
  // haptic force's): the tissue dents under it (TissueModel::setToolPress). 0: the tool never presses.
  double press_stiffness_N_per_m = 0.0;
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
  std::int64_t pressed_steps = 0;      // steps whose start had the tool pressing the skin in (a dent)
  // Threaded only: steps finished more than a physics period of wall time after they became due, and cut
  // changes that reached the model at a later step than theirs because the handoff was full (the only way a
  // real-time run's bytes can differ from a fast one's).
  std::int64_t late = 0;
  std::int64_t deferred = 0;
  // The blade's rest maps (restMapAt): poses mapped with an older step's map than theirs because theirs was
  // not made yet (the physics thread more than kMapLagSteps behind: a real-time run may then differ from a
  // fast one), and maps the frame had not taken before the handoff filled (never with a frame per step).
  std::int64_t stale_maps = 0;
  std::int64_t dropped_maps = 0;
};

// How the physics thread runs (TissuePhysics::startThread).
struct PhysicsThreadOptions {
  // The handoff full (the thread behind): advance() waits for room (a fast replay, whose caller may wait)
  // instead of deferring the changes. Never for a run against the clock.
  bool wait_for_room = false;
  // Wall seconds per simulated second (1 / a replay's speed); 0: not against the clock (a fast replay), no
  // step is late.
  double wall_per_simulated_s = 1.0;
  // Test hook: called on the physics thread before step k (e.g. to slow it down). Empty: none.
  std::function<void(std::int64_t step)> before_step;
};

// Where the tool's press holds the skin after a step (TissuePhysics::pressPointAt): the anchored skin point
// as the tissue carries it and the skin's outward normal there, deformed (on: the tool pressed at that step).
struct PressPoint {
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
  std::int64_t step = 0;
  bool on = false;
};

// The model's state after a step, as the physics thread publishes it (TissuePhysics::latestState).
struct PhysicsState {
  std::int64_t step = 0;             // the step it is after (0: none yet)
  std::size_t nodes = 0;             // x_m[0, nodes) are the model's nodes' positions
  std::vector<Eigen::Vector3d> x_m;  // sized once (the model's nodes and the cuts' reserve), never grown
};

// Where a pose's tool presses the skin without cutting in (World: the blade's entry point and the skin's
// outward normal there, in the rest frame, while the tip is below the skin and not cutting): the point the
// physics step's press spring holds (TissueModel::setToolPress).
struct ToolPress {
  bool on = false;
  Eigen::Vector3d rest_point_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rest_normal = Eigen::Vector3d::UnitY();
};

// The tool over its recent poses (World records each pose it accepts): its tip in the world, before mapping,
// and its press. A physics step's rest map is made around, and its press spring pulls towards, the newest
// tip at or before the step's time. A fixed ring of kCapacity poses (the oldest overwritten). Thread: the
// owner's (the sim thread). No allocation.
class ToolTrack {
 public:
  static constexpr std::size_t kCapacity = 256;
  void record(double time_s, const Eigen::Vector3d& tip_m, const ToolPress& press = {}) noexcept;
  // The newest pose at or before t_s; the oldest kept when every one is later; false when none is kept.
  bool tipAt(double t_s, Eigen::Vector3d& tip_m, ToolPress* press = nullptr) const noexcept;

 private:
  std::array<double, kCapacity> time_s_{};
  std::array<Eigen::Vector3d, kCapacity> tip_m_{};
  std::array<ToolPress, kCapacity> press_{};
  std::size_t next_ = 0, size_ = 0;
};

// A threaded step's wall time (us) and whether it was late; one per step, in step order.
struct PhysicsStepTime {
  float us = 0.0f;
  bool late = false;
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
  // Every step due at or before t_s, each after the changes collected before it became due: taken here
  // (inline), or handed to the physics thread (threaded). Returns the steps made due by this call.
  int advance(double t_s) noexcept { return advance(t_s, nullptr); }
  // The same, and after each step a rest map around the tool's tip at the step's time (`track`; none: the
  // identity), for restMapAt().
  int advance(double t_s, const ToolTrack* track) noexcept;

  // The blade's mapping to the rest frame for a pose at t_s (the incision is made at rest): the rest map
  // (physics/rest_map.h) made after step k(t_s) - kMapLagSteps, k(t_s) the last step due at t_s, around the
  // tool's tip at that step; the identity before that step (the tissue at rest). Which map a pose gets
  // depends on its time only, so `replay --fast` and a real-time replay map it alike while the physics keeps
  // within kMapLagSteps of the frames. A map not made yet (the physics thread behind): the newest made is
  // taken and counted (PhysicsCounters::stale_maps). The owner's thread, O(maps made since the last call),
  // no allocation, never throws.
  physics::RestMap restMapAt(double t_s) noexcept;
  // A fast replay's thread (wait_for_room): waits until every map the next frame's poses may want is made
  // (the step kMapLagSteps before the last due), so that restMapAt never takes a stale one and the frame's
  // haptic part never waits. Returns at once otherwise. The owner's thread, after advance().
  void awaitMaps() noexcept;
  static constexpr std::int64_t kMapLagSteps = 4;  // 40 ms at 100 Hz
  // The press point for a pose at t_s (the haptic force of a tool denting the skin): made after the same
  // step as restMapAt(t_s)'s map, blended linearly with the step before by t_s's place in its physics period,
  // so that a force from it has no step at the physics rate. Off unless the newer one pressed; the newer
  // alone when the older did not. Depends on t_s and the steps only. The owner's thread, O(1), no allocation.
  PressPoint pressPointAt(double t_s) noexcept;

  // Starts the physics thread (allocates the change buffers, the queue and the thread). Not running.
  void startThread(PhysicsThreadOptions options);
  // Waits until the physics thread has taken every step handed to it, then ends it: the model is the
  // caller's again and later advance() calls step inline. The caller's thread, never the frame's (it
  // waits). Returns at once when no thread runs.
  void stopThread();
  bool threaded() const noexcept { return worker_ != nullptr; }
  // Threaded: the newest state the physics thread published (after each step), never waiting for it;
  // nullptr before the first. One reader thread (the owner's or another, e.g. a viewer's, from the
  // construction on). Valid until its next call.
  const PhysicsState* latestState() noexcept;
  // Steps made due so far (the owner's thread).
  std::int64_t stepsDue() const noexcept { return next_step_ - 1; }
  // Steps finished so far (either way), and those late: any thread, never blocks.
  std::int64_t stepsDone() const noexcept { return steps_done_.load(std::memory_order_acquire); }
  std::int64_t lateSteps() const noexcept { return late_.load(std::memory_order_relaxed); }
  // Every threaded step's time so far, in step order (read after stopThread(); up to kStoredStepTimes).
  std::span<const PhysicsStepTime> stepTimes() const noexcept { return step_times_; }
  void clearStepTimes() noexcept { step_times_.clear(); }
  static constexpr std::size_t kQueuedSteps = 16384;       // 164 s of simulated time at 100 Hz
  static constexpr std::size_t kChangeSlots = 4;           // change buffers: one filling, three in flight
  static constexpr std::size_t kStoredStepTimes = 262144;  // 44 min at 100 Hz (2 MB)

  // The surface's vertices embedded in the tets at rest (the surface's positions are the tets' rest: both
  // are the cut as the incision left it), each on its own side of every cut, so that a lip's vertex follows
  // its own lip's tets (physics::embedSurfaceVertex, surface_embedding.h, over the model's locator).
  // Vertices outside every tet take the nearest within 1 mm (weights extrapolated); farther ones are left
  // where they are (nodes -1). O(V x tets near a point); allocates: for outputs and checks, not the sim
  // thread.
  std::vector<physics::Embedded> embedSurface(const mesh::SurfaceMesh& surface) const;
  // The surface as simulated: a copy with every embedded vertex at its deformed position.
  mesh::SurfaceMesh deformedSurface(const mesh::SurfaceMesh& surface) const;
  // Where the tissue carries the rest point rest_m now (its tet's deformed position; rest_m itself when no
  // tet is within 1 mm of it at rest). O(tets near the point).
  Eigen::Vector3d deformedPoint(const Eigen::Vector3d& rest_m) const;
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
  // The model's counters and the handoff's (after stopThread() when threaded).
  PhysicsCounters counters() const noexcept;

 private:
  struct Worker;
  struct StepMessage {
    std::int64_t first_step = 0, last_step = 0;  // steps [first, last], the changes before the first
    int slot = -1;                               // the change buffer to apply first; -1: none
    std::int64_t due_ns = 0;                     // steady clock when the first became due
    std::array<double, 3> tip_m{};  // the tool's tip at the last step's time (plain: the queue's copies are noexcept)
    bool has_tip = false;
    std::array<double, 6> press{};  // its press there: rest point, rest normal
    bool has_press = false;
  };
  // The tool at a step's time (ToolTrack::tipAt): its tip in the world and its press.
  struct ToolAt {
    Eigen::Vector3d tip_m;
    ToolPress press;
  };
  // A rest map through the handoff (physics::RestMap's values; plain, so its copies are noexcept).
  struct MapMessage {
    std::array<double, 15> values{};  // world_m, rest_m, world_to_rest (column-major)
    std::array<double, 6> press{};    // the press point: point_m, normal
    std::int64_t step = 0;
    bool located = false, pressed = false;
  };
  void applyChanges(physics::CutChanges& changes) noexcept;  // the stepping thread
  // One step with the tool's press, then its rest map around its tip (nullptr: no tool; the identity). The
  // stepping thread.
  void stepOnce(const ToolAt* tool) noexcept;
  void pressTool(const ToolAt* tool) noexcept;             // the stepping thread: the model's press for the next step
  void publishMap(const Eigen::Vector3d* tip_m) noexcept;  // the stepping thread
  void takeMaps() noexcept;                                // the owner's: the handoff into recent_maps_
  // The step whose map a pose at t_s takes (0: none, the tissue at rest) and t_s's place in its physics
  // period in [0, 1). The owner's thread.
  std::int64_t mapStep(double t_s, double& fraction) const noexcept;
  void handOver(std::int64_t step, std::int64_t due_ns, const ToolAt* tool) noexcept;
  static void packTool(const ToolAt& tool, StepMessage& m) noexcept;
  static ToolAt unpackTool(const StepMessage& m) noexcept;
  bool pushMessage(const StepMessage& m) noexcept;
  void runWorker() noexcept;  // the physics thread's loop

  PhysicsOptions options_;
  std::unique_ptr<physics::TissueModel> model_;
  // The change buffers: slots_[collecting_] is the one collect() fills (only slot 0 until startThread()).
  std::array<physics::CutChanges, kChangeSlots> slots_;
  std::size_t collecting_ = 0;
  std::size_t read_nodes_ = 0, read_base_tets_ = 0;
  bool started_ = false;
  double t_first_s_ = 0.0;
  std::int64_t next_step_ = 1;
  // The stepping thread's counters (the model's), and the owner's (collect() and the handoff).
  PhysicsCounters counters_;
  std::int64_t collect_failed_ = 0, collect_overflows_ = 0, deferred_ = 0;
  std::atomic<std::int64_t> steps_done_{0}, late_{0};
  std::vector<PhysicsStepTime> step_times_;             // the physics thread's; reserved kStoredStepTimes
  std::unique_ptr<TripleBuffer<PhysicsState>> states_;  // the physics thread writes, one reader reads
  std::unique_ptr<Worker> worker_;
  // The rest maps: the stepping thread pushes one per step (its guess the last map's), the owner keeps the
  // last kRecentMaps by step (1.28 s at 100 Hz: a live pose that arrives late still finds its map).
  static constexpr std::size_t kQueuedMaps = 256, kRecentMaps = 128;
  std::unique_ptr<SpscQueue<MapMessage, kQueuedMaps>> maps_;
  Eigen::Vector3d map_guess_m_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::array<physics::RestMap, kRecentMaps> recent_maps_{};
  std::array<PressPoint, kRecentMaps> recent_presses_{};
  // The stepping thread's press: the anchor it located for the last step (pressTool).
  physics::Embedded press_anchor_;
  Eigen::Vector3d press_rest_point_m_ = Eigen::Vector3d::Zero();  // the press's skin point at rest
  Eigen::Vector3d press_normal_ = Eigen::Vector3d::UnitY();       // its direction (the skin's when it began)
  bool press_located_ = false;
  std::int64_t newest_map_ = 0;  // the newest step with a map in recent_maps_ (0: none)
  bool wait_for_maps_ = false;   // a fast replay's thread: awaitMaps waits for the next frame's maps
  std::int64_t stale_maps_ = 0;
  std::atomic<std::int64_t> dropped_maps_{0};
};

}  // namespace incise::sim
