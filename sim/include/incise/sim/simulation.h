// The simulation thread's frame and the replay driver (ARCHITECTURE.md, "Data flow and threads"): poses
// come in through a single-producer single-consumer queue, the world takes a step, the force goes to a
// ForceSink, the results leave through a triple-buffered Snapshot that another thread takes without ever
// blocking the loop, and every frame's timings go to LatencyStats. Frame k's time is t0 + k * period, never
// read from a clock (the frame's steps: above Simulation::frame).
//
// Threads: pushPose from one producer thread (a device or the replay feeder); frame from the sim thread;
// takeSnapshot from one reader thread. Allocation: none per frame (fixed arrays, reserved stats). Failure:
// nothing here throws on the sim thread; a full queue drops the pose and counts it.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "incise/devices/pose_sample.h"
#include "incise/devices/pose_source.h"
#include "incise/sim/fixed_rate_loop.h"
#include "incise/sim/geometry_stream.h"
#include "incise/sim/latency_stats.h"
#include "incise/sim/pose_queue.h"
#include "incise/sim/triple_buffer.h"
#include "incise/sim/world.h"

namespace incise::sim {

// Receives the haptic force every frame, on the sim thread: must not block (a device driver queues it).
class ForceSink {
 public:
  virtual ~ForceSink() = default;
  virtual void apply(const Eigen::Vector3d& force_N, double t_s) noexcept = 0;
};

struct StepProfile {
  double haptic_us = 0.0, cut_us = 0.0;
  double publish_us = 0.0, frame_us = 0.0;  // of the previous frame (a snapshot cannot time its own publish)
  double geometry_us = 0.0;                 // of the previous frame: the geometry stream's publish
  int poses = 0;                            // poses taken this frame
  int queue_backlog = 0;  // poses still queued after draining: a frame takes at most kMaxPosesPerFrame
};

// One frame's timings for a reader that wants every frame (a HUD): Simulation pushes one per frame into a
// FrameTimesQueue when one is attached (a full queue drops it; the reader sees the gap in `frame`).
struct FrameTimes {
  std::int64_t frame = -1;
  float frame_us = 0.0f, haptic_us = 0.0f, cut_us = 0.0f, geometry_us = 0.0f;
  std::int16_t pose_to_visible_frames = -1;  // the largest that became visible this frame (-1: none)
  bool deadline_missed = false;
};
using FrameTimesQueue = SpscQueue<FrameTimes, 8192>;  // 8 s at 1 kHz, 256 KiB

// What a reader sees of a frame: small and fixed-size, copied whole into the triple buffer.
struct Snapshot {
  std::int64_t frame = -1;
  double t_s = 0.0;
  HapticState haptic;
  int incisions = 0;
  int columns_final = 0;  // lattice columns of the current incision that the stroke has fixed
  int columns_done = 0;   // ... and that are cut: the cut is visible up to here
  int edges_split = 0;    // totals over all incisions
  int seam_vertices_opened = 0;
  double groove_depth_m = 0.0;  // the groove's floor where the current incision cuts now (0: none cutting)
  StepProfile profile;
  std::int64_t deadline_misses = 0;  // frames so far that missed their deadline
  std::int64_t frame_start_ns = 0;   // steady_clock time this frame began (a reader's latency on screen)
  // A simulated tissue: steps made due by this frame's time, steps the physics has finished, and those
  // finished late (TissuePhysics::lateSteps); 0 without one.
  std::int64_t physics_steps_due = 0, physics_steps_done = 0, physics_late = 0;
};

// Also a devices::PoseSink: a live source (devices::HidPoseSource) pushes into the pose queue directly.
class Simulation final : public devices::PoseSink {
 public:
  static constexpr std::size_t kQueueCapacity = 4096;
  static constexpr int kMaxPosesPerFrame = 256;

  // `world` and `sink` (may be null) must outlive the simulation. `t0_s` is the time of frame 0. Frame
  // statistics go to `stats` when given (to gather several runs), else to the simulation's own.
  Simulation(World& world, ForceSink* sink, std::int64_t period_us, double t0_s, LatencyStats* stats = nullptr);

  bool pushPose(const devices::PoseSample& pose) noexcept;  // producer thread; false: queue full, dropped
  bool push(const devices::PoseSample& pose) noexcept override { return pushPose(pose); }
  // A frame, in order: 1. drain every queued pose (oldest first) into a fixed array;
  // 2. World::updateTool, the haptic part alone (contact against the world's ContactProxy, force) ->
  // ForceSink (timed: haptic_us); 3. World::cut at the frame's time: the poses' stroke samples and all the
  // cutting work, under the budget (timed: cut_us); 3b. a simulated tissue's World::stepPhysics at the
  // frame's time: with its physics thread running (startPhysicsThread) the due steps are only handed over,
  // inline they are taken here (timed, when it stepped: LatencyStats::recordPhysicsStep); 4. when a
  // GeometryStream is attached, the frame's mesh
  // changes into it (timed: geometry_us; geometry_stream.h), then publish the Snapshot (timed: publish_us);
  // 5. record the frame in LatencyStats (a deadline missed by the frame's own time over the period is an
  // overrun, one missed by starting late a late wake-up). Frame k's time is t0 + k * period: simulated,
  // never read from a clock, so the cut is the same whichever frame saw which pose. Pose-to-visible latency,
  // once per frame whose cut phase made new lattice columns final: from the frame the oldest pose that cut
  // phase handled arrived in (the haptic part took it: a pose that waited in the world's queue counts its
  // wait; frames with no pose count for nothing) to the frame whose snapshot first shows those columns cut.
  void frame(const FrameInfo& info) noexcept;  // sim thread
  bool takeSnapshot(Snapshot& out) noexcept;   // reader thread: true when newer than the last
  // Before the first frame: publish the mesh's changes into `stream` every frame (attach() is done here:
  // allocates). nullptr detaches. The stream must outlive the simulation's frames.
  void attachGeometry(GeometryStream* stream);
  // Before the first frame: a frame takes only the queued poses whose time is at most its own (a later one
  // waits for its frame), so each pose is handled in the frame of its time however early it was pushed.
  // A real-time replay of a simulated tissue feeds poses a few frames early with this on, so that its cuts
  // are made in the same frames as a fast replay's and so reach the same physics steps (a pose handled a
  // frame late can move its cut past a step's time, which changes the tissue's motion). Off by default (a
  // pose is handled when it comes).
  void holdPosesToTheirFrame(bool on) noexcept { hold_ = on; }
  // Before the first frame: a simulated tissue steps on its own thread from now on (TissuePhysics::
  // startThread; allocates); the frame only hands the due steps over. No-op without a simulated tissue.
  void startPhysicsThread(PhysicsThreadOptions options);
  // After the last frame, on the owner's thread: waits for the physics thread to take every step handed to
  // it, ends it, and records its steps' times into the statistics (physics_step_us, physics_late).
  void finishPhysics();
  // Before the first frame: push every frame's timings into `queue` (one reader thread pops them). nullptr
  // detaches. The queue must outlive the simulation's frames.
  void attachTimes(FrameTimesQueue* queue) noexcept { times_ = queue; }
  // The wall-clock period a frame's deadline is measured against (default: the simulated period; a replay
  // at another speed sets its own).
  void setDeadlinePeriodUs(double period_us) noexcept { period_us_ = period_us; }
  double frameTime(std::int64_t frame) const noexcept { return t0_s_ + static_cast<double>(frame) * dt_s_; }

  const LatencyStats& stats() const noexcept { return *stats_; }
  std::int64_t posesDropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
  std::int64_t posesTaken() const noexcept { return taken_.load(std::memory_order_relaxed); }
  const World& world() const noexcept { return world_; }

 private:
  int poseToVisible(std::int64_t frame) noexcept;
  void resetOnNewIncision() noexcept;
  int takePoses(double t_s) noexcept;
  void noteArrivals(int accepted, std::int64_t frame) noexcept;
  void publishSnapshot(std::int64_t frame, double t_s, const HapticState& haptic, int poses, double haptic_us,
                       double cut_us, std::int64_t start_ns) noexcept;  // sim thread
  void notePending(std::int64_t frame) noexcept;
  std::int64_t arrivalFrame(std::int64_t pose, std::int64_t frame) noexcept;

  World& world_;
  ForceSink* sink_;
  double dt_s_;
  double period_us_;
  double t0_s_;
  PoseQueue<kQueueCapacity> queue_;
  std::array<devices::PoseSample, kMaxPosesPerFrame> frame_poses_{};
  TripleBuffer<Snapshot> snapshots_;
  LatencyStats own_stats_{1};
  LatencyStats* stats_;
  std::atomic<std::int64_t> dropped_{0}, taken_{0};
  bool hold_ = false, has_held_ = false;  // holdPosesToTheirFrame; a pose popped before its frame
  devices::PoseSample held_{};
  // Pose-to-visible bookkeeping: columns made final with poses from which frame, in order (a small ring);
  // and per frame that brought poses, how many the world had accepted by its end (a ring holding every
  // frame with a pose the cut phase has not handled, and the newest handled one's: at most the world's
  // queue, kQueuedPoses, plus one; reserved at construction). Poses are counted from 0 in arrival order.
  struct Pending {
    int column;
    std::int64_t frame;
  };
  std::array<Pending, 256> pending_{};
  std::size_t pending_head_ = 0, pending_size_ = 0;
  struct Arrival {
    std::int64_t accepted_through;  // poses accepted in this frame and before it
    std::int64_t frame;
  };
  std::vector<Arrival> arrivals_;
  std::size_t arrivals_head_ = 0, arrivals_size_ = 0;
  std::int64_t accepted_ = 0, handled_ = 0;  // poses the world accepted, and the cut phase handled
  int last_final_ = 0, last_incisions_ = 0;
  double last_publish_us_ = 0.0, last_frame_us_ = 0.0, last_geometry_us_ = 0.0;
  GeometryStream* geometry_ = nullptr;
  FrameTimesQueue* times_ = nullptr;
};

// Fast: the frames run back to back on the caller's thread, as fast as possible (same frames, same dt).
// RealTime: a feeder thread releases the poses at their times and FixedRateLoop paces the frames.
enum class ReplayPace : std::uint8_t { Fast, RealTime };

struct ReplayOptions {
  ReplayPace pace = ReplayPace::Fast;
  std::int64_t period_us = 1000;
  double settle_s = 0.2;  // simulated time after the last pose before the replay ends
  bool realtime_priority = false;
  std::int64_t spin_us = 0;  // busy-wait this long before each deadline (sleep wake-ups are late)
  bool pin_threads = false;  // loop thread on the last CPU, feeder and reader on the others
  // Called on the replay's thread after each frame in fast mode, or from a reader thread about every 2 ms
  // in real time, with the newest snapshot (e.g. a viewer or a recorder). May be empty.
  std::function<void(const Snapshot&)> observer;
  // The mesh's changes for a reader on another thread (attached before the first frame); after the last
  // frame the stream is flushed (up to flush_timeout_ms, waiting for its reader) so that the reader ends
  // with the final mesh exactly. nullptr: none.
  GeometryStream* geometry = nullptr;
  FrameTimesQueue* times = nullptr;  // every frame's timings for a reader on another thread (a HUD)
  std::int64_t flush_timeout_ms = 5000;
  // Fast pace only: the stream's reader on the replay's own thread (e.g. pulls it into a GeometryMirror),
  // called after each frame and while flushing. May be empty (the reader is on another thread).
  std::function<void()> geometry_reader;
  // End the replay once a frame's time reaches this (simulated seconds from the first pose's time), even if
  // poses remain: a picture of the state at that time. Infinity: the whole trace plus settle_s.
  double stop_after_s = std::numeric_limits<double>::infinity();
  // Polled by the replay's thread (real time) or after each frame (fast): true ends the replay early (a
  // viewer's window closed). The outputs are those of the frames run. May be empty.
  std::function<bool()> stop_requested;
  // Real time only. While *pause is true no frame runs (the simulated time stands still) and no pose is
  // released; afterwards every pose comes that much later, so the frames see the same poses. nullptr: none.
  const std::atomic<bool>* pause = nullptr;
  // Test hook: called on the physics thread before each step k of a simulated tissue (e.g. to slow it
  // down: PhysicsThreadOptions::before_step). Empty: none.
  std::function<void(std::int64_t step)> physics_before_step;
  // Real time only: wall-clock speed (the loop's period is period_us / speed, poses come at their times /
  // speed); the simulated frames, and so the outputs, are the same. In [0.01, 100].
  double speed = 1.0;
  LatencyStats* stats = nullptr;  // gather the frames here too (e.g. several replays into one benchmark)
};

struct ReplayReport {
  LatencySummary latency;
  LoopCounters loop;
  std::int64_t frames = 0;
  std::int64_t poses = 0, poses_dropped = 0;
  double simulated_s = 0.0, wall_s = 0.0;
  int incisions = 0;
  int snapshots_read = 0;         // by the reader thread (real time) or observer calls (fast)
  bool stopped_early = false;     // stop_after_s or stop_requested ended it before the trace's end
  bool geometry_flushed = false;  // the geometry stream's reader got the final mesh exactly
  GeometryCounters geometry;      // the stream's counters (zero without one)
};

// A run's figures from its simulation and loop (replay and LiveSession): latency, frames, poses, simulated
// time, incisions. The rest (wall time, geometry, early stop) is the caller's.
void fillReport(ReplayReport& report, const Simulation& sim, const LoopCounters& loop, std::int64_t period_us);

// Replays a trace through `world` and returns the statistics; the world is left as the replay made it
// (its tissue holds the cut). The trace must be in time order (as TraceReader guarantees). Throws
// std::invalid_argument for an empty trace or bad options; otherwise never throws.
ReplayReport replay(World& world, std::span<const devices::PoseSample> trace, const ReplayOptions& options,
                    ForceSink* sink = nullptr);

}  // namespace incise::sim
