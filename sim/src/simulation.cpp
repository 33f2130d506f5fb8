#include "incise/sim/simulation.h"
#include "incise/incision/surface_cutter.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

namespace incise::sim {

namespace {

using Clock = std::chrono::steady_clock;

double microseconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

// The calling thread's CPU time in ns (time it was running, not descheduled), -1 if unavailable.
std::int64_t threadCpuNs() noexcept {
  timespec ts{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return -1;
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

Simulation::Simulation(World& world, ForceSink* sink, std::int64_t period_us, double t0_s, LatencyStats* stats)
    : world_(world),
      sink_(sink),
      dt_s_(static_cast<double>(period_us) * 1e-6),
      period_us_(static_cast<double>(period_us)),
      t0_s_(t0_s),
      own_stats_(stats ? 1 : LatencyStats::kDefaultCapacity),
      stats_(stats ? stats : &own_stats_),
      arrivals_(World::kQueuedPoses + 2) {
  if (period_us <= 0) throw std::invalid_argument("Simulation: period_us must be > 0");
}

bool Simulation::pushPose(const devices::PoseSample& pose) noexcept {
  if (queue_.push(pose)) return true;
  dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

void Simulation::resetOnNewIncision() noexcept {
  if (world_.incisions() == last_incisions_) return;
  last_incisions_ = world_.incisions();  // a new lattice: its columns count from 0 again
  last_final_ = 0;
  pending_size_ = 0;
}

// Each pending batch of columns once, in the frame it is cut; the frame's largest latency is returned (-1:
// none became visible).
int Simulation::poseToVisible(std::int64_t frame) noexcept {
  const incision::SurfaceCutter& cutter = world_.cutter();
  resetOnNewIncision();
  int latency = -1;
  const int done = cutter.columnsDone();
  while (pending_size_ > 0 && pending_[pending_head_].column <= done) {
    const int frames = static_cast<int>(frame - pending_[pending_head_].frame);
    stats_->recordPoseToVisible(frames);
    latency = std::max(latency, frames);
    pending_head_ = (pending_head_ + 1) % pending_.size();
    --pending_size_;
  }
  return latency;
}

void Simulation::noteArrivals(int accepted, std::int64_t frame) noexcept {
  if (accepted <= 0) return;
  accepted_ += accepted;
  if (arrivals_size_ == arrivals_.size()) {  // cannot happen within the world's queue; keep the newest
    arrivals_head_ = (arrivals_head_ + 1) % arrivals_.size();
    --arrivals_size_;
  }
  arrivals_[(arrivals_head_ + arrivals_size_++) % arrivals_.size()] = {accepted_, frame};
}

// The frame pose number `pose` arrived in (`frame` when unknown); forgets the frames before it.
std::int64_t Simulation::arrivalFrame(std::int64_t pose, std::int64_t frame) noexcept {
  while (arrivals_size_ > 0 && arrivals_[arrivals_head_].accepted_through <= pose) {
    arrivals_head_ = (arrivals_head_ + 1) % arrivals_.size();
    --arrivals_size_;
  }
  return arrivals_size_ > 0 ? arrivals_[arrivals_head_].frame : frame;
}

// After the cut phase: the columns it made final, with the frame the oldest pose it handled came in.
void Simulation::notePending(std::int64_t frame) noexcept {
  resetOnNewIncision();
  const std::int64_t handled_before = handled_;
  handled_ = accepted_ - static_cast<std::int64_t>(world_.queuedPoses());
  // The oldest pose handled in this frame; with none (columns made final by work alone), the newest handled.
  const std::int64_t oldest = handled_ > handled_before ? handled_before : handled_ - 1;
  const int final_columns = world_.cutter().columnsFinal();
  if (final_columns > last_final_ && pending_size_ < pending_.size()) {
    last_final_ = final_columns;
    pending_[(pending_head_ + pending_size_++) % pending_.size()] = {last_final_, arrivalFrame(oldest, frame)};
  }
  arrivalFrame(handled_ - 1, frame);  // forget the frames whose poses are all handled
}

// The frame's poses into frame_poses_, oldest first; with hold_, none later than t_s (kept for its frame).
int Simulation::takePoses(double t_s) noexcept {
  const double latest_s = hold_ ? t_s + 1e-12 : std::numeric_limits<double>::infinity();
  int count = 0;
  if (has_held_ && !(held_.time_s > latest_s))
    frame_poses_[static_cast<std::size_t>(count++)] = held_, has_held_ = false;
  while (!has_held_ && count < kMaxPosesPerFrame && queue_.pop(frame_poses_[static_cast<std::size_t>(count)])) {
    if (frame_poses_[static_cast<std::size_t>(count)].time_s > latest_s) {
      held_ = frame_poses_[static_cast<std::size_t>(count)];
      has_held_ = true;
      break;
    }
    ++count;
  }
  taken_.fetch_add(count, std::memory_order_relaxed);
  return count;
}

// The frame's snapshot for the readers (viewer, HUD), published through the triple buffer.
void Simulation::publishSnapshot(std::int64_t frame, double t_s, const HapticState& haptic, int poses, double haptic_us,
                                 double cut_us, std::int64_t start_ns) noexcept {
  const incision::SurfaceCutter& cutter = world_.cutter();
  Snapshot& s = snapshots_.writeSlot();
  s.frame = frame;
  s.t_s = t_s;
  s.haptic = haptic;
  s.incisions = world_.incisions();
  s.columns_final = cutter.columnsFinal();
  s.columns_done = cutter.columnsDone();
  s.edges_split = cutter.stats().edges_split;
  s.seam_vertices_opened = cutter.stats().vertices_duplicated;
  s.groove_depth_m = cutter.active() ? cutter.incision()->frontDepthM() : 0.0;
  s.profile.haptic_us = haptic_us;
  s.profile.cut_us = cut_us;
  s.profile.poses = poses;
  s.profile.queue_backlog = static_cast<int>(queue_.sizeApprox());
  // A snapshot cannot hold its own publish time: it carries the previous frame's publish and frame times.
  s.profile.publish_us = last_publish_us_;
  s.profile.frame_us = last_frame_us_;
  s.profile.geometry_us = last_geometry_us_;
  s.deadline_misses = stats_->deadlineMisses();
  s.frame_start_ns = start_ns;
  if (const TissuePhysics* physics = world_.physics()) {
    s.physics_steps_due = physics->stepsDue();
    s.physics_steps_done = physics->stepsDone();
    s.physics_late = physics->lateSteps();
  }
  const auto publish_start = Clock::now();
  snapshots_.publish();
  last_publish_us_ = microseconds(publish_start, Clock::now());
}

void Simulation::frame(const FrameInfo& info) noexcept {
  const std::int64_t cpu_start_ns = info.against_clock ? threadCpuNs() : -1;  // a system call: the clock only
  const auto start = Clock::now();
  const double t_s = frameTime(info.frame);
  const int count = takePoses(t_s);

  const HapticState haptic =
      world_.updateTool(std::span(frame_poses_.data(), static_cast<std::size_t>(count)), info.dt_s);
  noteArrivals(haptic.poses, info.frame);
  if (sink_) sink_->apply(haptic.force_N, t_s);
  const auto haptic_end = Clock::now();
  const std::int64_t cpu_haptic_ns = cpu_start_ns >= 0 ? threadCpuNs() : -1;  // after the force is out

  // The cut phase takes the poses and makes lattice columns final; remember when the oldest pose it handled
  // came (poses numbered in arrival order), to measure when the columns are cut.
  // Against the clock the surface's budgeted work also stops at its share of cut_budget_us (work_budget.h);
  // not for a simulated tissue, whose model takes each cut in the frame it is made: where the work stops
  // would change its motion (it keeps to the inversion budget, as the tets do).
  const auto cut_deadline = info.against_clock && !world_.physics()
                                ? haptic_end + std::chrono::nanoseconds(std::llround(1e3 * world_.surfaceCutBudgetUs()))
                                : core::WorkBudget::Clock::time_point::max();
  world_.cut(t_s, cut_deadline);
  const auto cut_end = Clock::now();
  // A simulated tissue: the frame's tet changes applied and the physics steps due at t_s (simulated time).
  auto physics_end = cut_end;
  const TissuePhysics* physics = world_.physics();
  if (physics && world_.stepPhysics(t_s) > 0 && !physics->threaded()) {
    physics_end = Clock::now();
    const double physics_us = microseconds(cut_end, physics_end);
    stats_->recordPhysicsStep(physics_us, physics_us > period_us_);
  }
  notePending(info.frame);
  const int visible = poseToVisible(info.frame);
  if (geometry_) geometry_->publish(world_, info.frame);
  const auto geometry_end = Clock::now();

  publishSnapshot(info.frame, t_s, haptic, count, microseconds(start, haptic_end), microseconds(haptic_end, cut_end),
                  std::chrono::duration_cast<std::chrono::nanoseconds>(start.time_since_epoch()).count());
  const auto end = Clock::now();

  FrameTiming timing;
  timing.haptic_us = microseconds(start, haptic_end);  // not from `s`: the reader owns that slot now
  if (cpu_haptic_ns >= 0) timing.haptic_cpu_us = 1e-3 * static_cast<double>(cpu_haptic_ns - cpu_start_ns);
  timing.cut_us = microseconds(haptic_end, cut_end);
  timing.geometry_us = last_geometry_us_ = geometry_ ? microseconds(physics_end, geometry_end) : 0.0;
  timing.frame_us = last_frame_us_ = microseconds(start, end);
  timing.period_error_us = info.period_error_us;
  timing.deadline_missed = info.period_error_us + timing.frame_us > period_us_;
  timing.overrun = timing.frame_us > period_us_;
  if (timing.overrun && cpu_start_ns >= 0) {
    const std::int64_t cpu_end_ns = threadCpuNs();
    timing.preempted = cpu_end_ns >= 0 && 1e-3 * static_cast<double>(cpu_end_ns - cpu_start_ns) <= period_us_;
  }
  stats_->record(timing);
  if (times_)
    times_->tryPush({info.frame, static_cast<float>(timing.frame_us), static_cast<float>(timing.haptic_us),
                     static_cast<float>(timing.cut_us), static_cast<float>(timing.geometry_us),
                     static_cast<std::int16_t>(std::min(visible, 32767)), timing.deadline_missed});
}

void Simulation::startPhysicsThread(PhysicsThreadOptions options) {
  if (TissuePhysics* physics = world_.physics()) physics->startThread(std::move(options));
}

void Simulation::finishPhysics() {
  TissuePhysics* physics = world_.physics();
  if (!physics || !physics->threaded()) return;
  physics->stopThread();
  for (const PhysicsStepTime& s : physics->stepTimes()) stats_->recordPhysicsStep(s.us, s.late);
  physics->clearStepTimes();
}

void Simulation::attachGeometry(GeometryStream* stream) {
  geometry_ = stream;
  if (stream) stream->attach(world_);
}

bool Simulation::takeSnapshot(Snapshot& out) noexcept {
  if (!snapshots_.update()) return false;
  out = snapshots_.read();
  return true;
}

namespace {

// The feeder and the reader keep off the loop's core (the last one) when the options pin threads.
void pinToOtherCpus(bool pin, int cpus) noexcept {
  if (!pin) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c = 0; c < cpus - 1; ++c) CPU_SET(c, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

// What both paces share: the trace, the simulation, its loop and the test for the end of the replay.
struct ReplayRun {
  World& world;
  std::span<const devices::PoseSample> trace;
  const ReplayOptions& options;
  Simulation& sim;
  FixedRateLoop& loop;
  ReplayReport& report;
  double end_s;
  bool pin;
  int cpus;
  std::atomic<std::size_t> fed{0};

  std::atomic<bool> stop{false};  // stop_after_s reached or stop_requested (set by the replay's thread)
  std::int64_t last_frame = -1;

  // Every pose fed and taken (or dropped), no cutting work carried, and the settle time reached; or told
  // to stop.
  bool finished(const FrameInfo& info) noexcept {
    last_frame = info.frame;
    if (sim.frameTime(info.frame) >= stop_s) stop.store(true, std::memory_order_relaxed);
    if (stop.load(std::memory_order_relaxed)) return true;
    return fed.load(std::memory_order_acquire) == trace.size() &&
           sim.posesTaken() + sim.posesDropped() == static_cast<std::int64_t>(trace.size()) && !world.pending() &&
           sim.frameTime(info.frame) >= end_s;
  }
  double stop_s = std::numeric_limits<double>::infinity();
  std::atomic<std::int64_t> paused_frames{0};
  double wall_period_s = 1e-3;
  double lead_s = 0.0;  // the feeder releases poses this much before their time (real time)
};

// How many frames early a real-time replay of a simulated tissue feeds its poses: a feeder thread woken
// this late still gives every pose to the frame of its time.
constexpr double kPoseLeadFrames = 5.0;

void replayFast(ReplayRun& run) {
  Snapshot snapshot;
  run.loop.runFast(
      [&](const FrameInfo& info) {
        const double t_s = run.sim.frameTime(info.frame);
        std::size_t i = run.fed.load(std::memory_order_relaxed);
        while (i < run.trace.size() && run.trace[i].time_s <= t_s + 1e-12) run.sim.pushPose(run.trace[i++]);
        run.fed.store(i, std::memory_order_release);
        run.sim.frame(info);
        if (run.options.observer && run.sim.takeSnapshot(snapshot)) {
          run.options.observer(snapshot);
          ++run.report.snapshots_read;
        }
        if (run.options.geometry_reader) run.options.geometry_reader();
        if (run.options.stop_requested && run.options.stop_requested()) run.stop.store(true);
        if (run.finished(info)) run.loop.requestStop();
      },
      std::numeric_limits<std::int64_t>::max());
}

// When the feeder releases pose i: at its time from the start at the replay's speed, later by every frame
// a pause skipped.
Clock::time_point releaseTime(const ReplayRun& run, Clock::time_point start, std::size_t i) {
  const double wall_s = (run.trace[i].time_s - run.trace.front().time_s) / run.options.speed +
                        static_cast<double>(run.paused_frames.load()) * run.wall_period_s;
  return start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wall_s - run.lead_s));
}

void replayRealTime(ReplayRun& run) {
  std::atomic<bool> done{false};
  const auto start = Clock::now() + std::chrono::milliseconds(5);
  const auto paused = [&] { return run.options.pause && run.options.pause->load(std::memory_order_relaxed); };
  std::thread feeder([&] {  // the "device": releases each pose at its time
    pinToOtherCpus(run.pin, run.cpus);
    for (std::size_t i = 0; i < run.trace.size() && !done.load(std::memory_order_acquire); ++i) {
      while (!done.load(std::memory_order_acquire)) {  // re-read the pause offset until the pose is due
        const auto now = Clock::now(), due = releaseTime(run, start, i);
        if (!paused() && now >= due) break;
        std::this_thread::sleep_until(paused() ? now + std::chrono::milliseconds(1)
                                               : std::min(due, now + std::chrono::milliseconds(2)));
      }
      while (!run.sim.pushPose(run.trace[i]) && !done.load()) std::this_thread::yield();
      run.fed.store(i + 1, std::memory_order_release);
    }
  });
  std::thread reader([&] {  // a viewer: takes snapshots while the loop runs
    pinToOtherCpus(run.pin, run.cpus);
    Snapshot snapshot;
    while (true) {
      const bool last = done.load(std::memory_order_acquire);  // after the loop stopped: one final take
      if (run.sim.takeSnapshot(snapshot)) {
        ++run.report.snapshots_read;
        if (run.options.observer) run.options.observer(snapshot);
      }
      if (last) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  std::this_thread::sleep_until(start);
  run.loop.start([&](const FrameInfo& info) {
    if (paused()) {  // the simulated time stands still: the frame is not run
      run.paused_frames.fetch_add(1);
      if (run.stop.load(std::memory_order_relaxed)) run.loop.requestStop();
      return;
    }
    FrameInfo frame = info;  // frames count on from before the pause: the same times as without it
    frame.frame -= run.paused_frames.load(std::memory_order_relaxed);
    frame.t_s = static_cast<double>(frame.frame) * frame.dt_s;
    run.sim.frame(frame);
    if (run.finished(frame)) run.loop.requestStop();
  });
  while (run.loop.running()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (run.options.stop_requested && run.options.stop_requested()) run.stop.store(true);
  }
  run.loop.stop();
  done.store(true, std::memory_order_release);
  feeder.join();
  reader.join();
}

}  // namespace

void fillReport(ReplayReport& report, const Simulation& sim, const LoopCounters& loop, std::int64_t period_us) {
  report.latency = sim.stats().summary();
  report.loop = loop;
  report.frames = report.latency.frames;
  report.poses = sim.posesTaken();
  report.poses_dropped = sim.posesDropped();
  report.simulated_s = static_cast<double>(report.frames) * static_cast<double>(period_us) * 1e-6;
  report.incisions = sim.world().incisions();
}

ReplayReport replay(World& world, std::span<const devices::PoseSample> trace, const ReplayOptions& options,
                    ForceSink* sink) {
  if (trace.empty()) throw std::invalid_argument("replay: the trace is empty");
  if (options.period_us <= 0 || !(options.settle_s >= 0.0))
    throw std::invalid_argument("replay: bad period or settle time");
  Simulation sim(world, sink, options.period_us, trace.front().time_s, options.stats);
  if (!(options.speed >= 0.01 && options.speed <= 100.0))
    throw std::invalid_argument("replay: speed " + std::to_string(options.speed) + " is outside [0.01, 100]");
  FixedRateLoopOptions loop_options;
  loop_options.period_us = std::max<std::int64_t>(
      1, static_cast<std::int64_t>(std::llround(static_cast<double>(options.period_us) / options.speed)));
  sim.setDeadlinePeriodUs(static_cast<double>(loop_options.period_us));
  loop_options.realtime_priority = options.realtime_priority;
  loop_options.spin_us = options.spin_us;
  const int cpus = static_cast<int>(std::thread::hardware_concurrency());
  const bool pin = options.pin_threads && cpus >= 2;
  if (pin) loop_options.cpu = lastCpu();
  FixedRateLoop loop(loop_options);
  ReplayReport report;
  ReplayRun run{world, trace, options, sim, loop, report, trace.back().time_s + options.settle_s, pin, cpus};
  run.stop_s = trace.front().time_s + options.stop_after_s;
  run.wall_period_s = static_cast<double>(loop_options.period_us) * 1e-6;
  if (world.physics()) {  // a simulated tissue: each pose in the frame of its time (holdPosesToTheirFrame)
    sim.holdPosesToTheirFrame(true);
    run.lead_s = kPoseLeadFrames * run.wall_period_s;
    // Its steps on their own thread; a fast replay waits for it rather than defer a cut to a later step.
    PhysicsThreadOptions physics;
    physics.wait_for_room = options.pace == ReplayPace::Fast;
    physics.wall_per_simulated_s = options.pace == ReplayPace::Fast ? 0.0 : 1.0 / options.speed;
    physics.before_step = options.physics_before_step;
    sim.startPhysicsThread(std::move(physics));
  }
  sim.attachGeometry(options.geometry);
  sim.attachTimes(options.times);

  const auto wall_start = Clock::now();
  if (options.pace == ReplayPace::Fast)
    replayFast(run);
  else
    replayRealTime(run);
  sim.finishPhysics();  // the physics' last steps (the outputs need them) and their times
  report.wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  fillReport(report, sim, loop.counters(), options.period_us);
  report.stopped_early = run.stop.load();
  if (options.geometry) {  // the loop has stopped: this thread is the stream's writer now
    const auto reader = options.pace == ReplayPace::Fast ? options.geometry_reader : std::function<void()>{};
    report.geometry_flushed = options.geometry->flush(world, std::max<std::int64_t>(run.last_frame, 0),
                                                      std::chrono::milliseconds(options.flush_timeout_ms), reader);
    report.geometry = options.geometry->counters();
  }
  return report;
}

}  // namespace incise::sim
