#include "incise/sim/tissue_physics.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <optional>
#include <span>
#include <stdexcept>
#include <thread>

#include "incise/mesh/surface_mesh.h"
#include "incise/physics/surface_embedding.h"
#include "incise/physics/tissue_model.h"
#include "incise/sim/spsc_queue.h"
#include "incise/tets/tet_cutter.h"

namespace incise::sim {

// The physics thread's state, shared by the steps and the thread's loop below: the step queue from the sim
// thread, the change buffers given back, the wake-up counter and the thread itself. Threads: `held` and
// `has_held` are the sim thread's; each queue has one end on each thread.
struct TissuePhysics::Worker {
  PhysicsThreadOptions options;
  std::int64_t period_ns = 0;                       // a step's wall time before it is late
  SpscQueue<StepMessage, kQueuedSteps> steps;       // sim thread -> physics thread
  SpscQueue<std::size_t, kChangeSlots> free_slots;  // physics thread -> sim thread: applied, cleared
  std::atomic<std::uint32_t> wake{0};               // bumped after every push and at stop
  std::atomic<bool> stop{false};                    // set once nothing more will be pushed
  StepMessage held;                                 // the sim thread's: a step the full queue held back
  bool has_held = false;
  std::thread thread;
};

namespace {

// Nodes the incisions may add before the model and the change buffer grow: as many as the tet cutter keeps
// room for (its own headroom, 20,000 nodes), or half the load mesh's when that is more.
std::size_t cutNodes(const tets::TetMesh& mesh) { return std::max<std::size_t>(20000, mesh.nodes_m.size() / 2); }

physics::ModelOptions modelOptions(const tets::TetMesh& mesh) {
  physics::ModelOptions o;
  o.reserve_nodes = static_cast<int>(cutNodes(mesh));
  o.reserve_elements = std::max(o.reserve_elements, static_cast<int>(mesh.tets.size()) / 2);
  return o;
}

// probeBeside (surface_embedding.h) of vertex v from its neighbours and faces.
Eigen::Vector3d probeBeside(const mesh::TriMesh& m, mesh::TriMesh::VertexHandle v,
                            std::vector<Eigen::Vector3d>& neighbours_m) {
  neighbours_m.clear();
  for (const auto u : m.vv_range(v)) neighbours_m.push_back(mesh::toEigen(m.point(u)));
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double area_sum = 0.0;
  for (const auto f : m.vf_range(v)) {
    std::array<Eigen::Vector3d, 3> p;
    int i = 0;
    for (const auto w : m.fv_range(f)) p[static_cast<std::size_t>(i++)] = mesh::toEigen(m.point(w));
    const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);  // area-weighted
    normal += cross, area_sum += cross.norm();
  }
  return physics::probeBeside(mesh::toEigen(m.point(v)), neighbours_m, normal, area_sum);
}

// The model's locate() as embedSurfaceVertex asks for it.
struct ModelLocator final : physics::PointLocator {
  explicit ModelLocator(const physics::TissueModel& m) : model(m) {}
  std::optional<physics::Embedded> locate(const Eigen::Vector3d& rest_m, physics::ElementFilter filter,
                                          double max_distance_m) const override {
    return model.locate(rest_m, filter, max_distance_m);
  }
  const physics::TissueModel& model;
};

}  // namespace

std::vector<physics::Embedded> TissuePhysics::embedSurface(const mesh::SurfaceMesh& surface) const {
  const mesh::TriMesh& m = surface.mesh();
  std::vector<physics::Embedded> out(m.n_vertices());
  const ModelLocator tets(*model_);
  std::vector<Eigen::Vector3d> neighbours_m;
  for (const auto v : m.vertices()) {
    if (m.is_isolated(v)) continue;
    const Eigen::Vector3d beside_m = probeBeside(m, v, neighbours_m);
    const std::optional<physics::Embedded> e = physics::embedSurfaceVertex(tets, mesh::toEigen(m.point(v)), beside_m);
    if (e) out[static_cast<std::size_t>(v.idx())] = *e;
  }
  return out;
}

mesh::SurfaceMesh TissuePhysics::deformedSurface(const mesh::SurfaceMesh& surface) const {
  const std::vector<physics::Embedded> embedded = embedSurface(surface);
  mesh::SurfaceMesh out = surface;
  const std::span<const Eigen::Vector3d> x = model_->positions_m();
  for (const auto v : out.mesh().vertices()) {
    const physics::Embedded& e = embedded[static_cast<std::size_t>(v.idx())];
    if (e.nodes[0] < 0) continue;
    const Eigen::Vector3d p = physics::embeddedPosition(e, x);
    out.mesh().set_point(v, mesh::TriMesh::Point(p.x(), p.y(), p.z()));
  }
  return out;
}

Eigen::Vector3d TissuePhysics::deformedPoint(const Eigen::Vector3d& rest_m) const {
  const std::optional<physics::Embedded> e = model_->locate(rest_m);
  return e ? physics::embeddedPosition(*e, model_->positions_m()) : rest_m;
}

std::uint64_t TissuePhysics::positionsHash() const noexcept {
  std::uint64_t h = 14695981039346656037ull;
  for (const Eigen::Vector3d& p : model_->positions_m())
    for (int a = 0; a < 3; ++a) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &p[a], sizeof bits);
      for (int b = 0; b < 8; ++b) h = (h ^ ((bits >> (8 * b)) & 0xffu)) * 1099511628211ull;
    }
  return h;
}

void TissuePhysics::deform(tets::TetView& view, const tets::TetCutter& cutter) const {
  std::vector<char> used(static_cast<std::size_t>(cutter.nodeCount()), 0);
  for (int t = 0; t < cutter.baseTetCount(); ++t)
    for (const tets::TetChild& c : cutter.children(t))
      for (const int n : c.nodes) used[static_cast<std::size_t>(n)] = 1;
  const std::span<const Eigen::Vector3d> x = model_->positions_m();
  std::size_t k = 0;
  for (std::size_t n = 0; n < used.size() && k < view.mesh.nodes_m.size(); ++n) {
    if (!used[n]) continue;
    if (n < x.size()) view.mesh.nodes_m[k] = x[n];
    ++k;
  }
}

TissuePhysics::TissuePhysics(const tets::TetMesh& mesh, const PhysicsOptions& options) : options_(options) {
  if (!(std::isfinite(options.rate_hz) && options.rate_hz > 0.0))
    throw std::invalid_argument("TissuePhysics: rate_hz must be finite and > 0");
  physics::validate(options.material);
  model_ = std::make_unique<physics::TissueModel>(mesh, options.material, options.boundary, modelOptions(mesh));
  maps_ = std::make_unique<SpscQueue<MapMessage, kQueuedMaps>>();
  const std::size_t added = cutNodes(mesh);
  slots_[0].reserve(mesh.nodes_m.size() + added, mesh.tets.size() + 8 * added, 16 * added);
  // Made here, not when the thread starts: a reader (a viewer) may look for a state from the start.
  PhysicsState initial;
  initial.x_m.resize(static_cast<std::size_t>(model_->nodeCount() + model_->options().reserve_nodes));
  states_ = std::make_unique<TripleBuffer<PhysicsState>>(initial);
}

void TissuePhysics::collect(const tets::TetCutter& cutter) noexcept {
  const tets::TetChanges& journal = cutter.changes();
  if (journal.nodes.size() == read_nodes_ && journal.base_tets.size() == read_base_tets_) return;
  physics::CutChanges& changes = slots_[collecting_];
  const std::size_t node_capacity = changes.node_entry.capacity() + changes.nodes.capacity();
  const std::size_t piece_capacity = changes.pieces.capacity() + changes.base_entry.capacity();
  try {
    collectCutChanges(cutter, std::span(journal.nodes).subspan(read_nodes_),
                      std::span(journal.base_tets).subspan(read_base_tets_), changes);
  } catch (const std::bad_alloc&) {
    ++collect_failed_;
  }
  if (changes.node_entry.capacity() + changes.nodes.capacity() != node_capacity ||
      changes.pieces.capacity() + changes.base_entry.capacity() != piece_capacity)
    ++collect_overflows_;
  read_nodes_ = journal.nodes.size();
  read_base_tets_ = journal.base_tets.size();
}

void TissuePhysics::applyChanges(physics::CutChanges& changes) noexcept {
  if (changes.empty()) return;
  const int overflows = model_->reserveOverflows();
  try {
    const physics::ChangeStats applied = model_->apply(changes);
    counters_.pieces_refused += applied.pieces_refused;
    ++counters_.cuts_applied;
  } catch (const std::bad_alloc&) {
    ++counters_.failed_applies;
  }
  counters_.reserve_overflows += model_->reserveOverflows() - overflows;
  changes.clear();
}

void TissuePhysics::pressTool(const ToolAt* tool) noexcept {
  const bool was_pressing = press_located_;
  press_located_ = false;
  if (tool == nullptr || !tool->press.on || !(options_.press_stiffness_N_per_m > 0.0)) {
    model_->clearToolPress();
    return;
  }
  std::optional<physics::Embedded> at;
  try {
    at = model_->locate(tool->press.rest_point_m);
  } catch (const std::bad_alloc&) {  // locate's scratch list outgrew its reserve: no press this step
    at.reset();
  }
  if (!at) {
    model_->clearToolPress();
    return;
  }
  // The press pushes along the skin's normal as it was when the press began (before the dent, which tilts
  // the small tets under a point load far more than the skin around it).
  if (!was_pressing || tool->press.rest_point_m != press_rest_point_m_)
    press_normal_ =
        physics::embeddedNormal(*at, model_->restPositions_m(), model_->positions_m(), tool->press.rest_normal);
  press_rest_point_m_ = tool->press.rest_point_m;
  model_->setToolPress(*at, press_normal_, tool->tip_m, options_.press_stiffness_N_per_m);
  press_anchor_ = *at, press_located_ = true;
}

void TissuePhysics::stepOnce(const ToolAt* tool) noexcept {
  pressTool(tool);
  const physics::StepStats s = model_->step(stepS());
  ++counters_.steps;
  if (!model_->toolPressForce_N().isZero()) ++counters_.pressed_steps;
  if (s.status == physics::StepStatus::IterationLimit) ++counters_.cg_limited;
  if (s.status == physics::StepStatus::NonFinite) ++counters_.non_finite;
  counters_.max_inverted = std::max(counters_.max_inverted, s.inverted_elements);
  publishMap(tool != nullptr ? &tool->tip_m : nullptr);
  steps_done_.store(counters_.steps, std::memory_order_release);
}

int TissuePhysics::advance(double t_s, const ToolTrack* track) noexcept {
  if (!started_) {
    started_ = true;
    t_first_s_ = t_s;
  }
  int taken = 0;
  // Step k is due at t_first + k / rate; the tick's time computed from k (no accumulated sum).
  while (t_first_s_ + static_cast<double>(next_step_) / options_.rate_hz <= t_s + 1e-9 / options_.rate_hz) {
    ToolAt tool;
    const bool has_tip =
        track != nullptr &&
        track->tipAt(t_first_s_ + static_cast<double>(next_step_) / options_.rate_hz, tool.tip_m, &tool.press);
    if (worker_) {
      handOver(next_step_,
               std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
                   .count(),
               has_tip ? &tool : nullptr);
    } else {
      applyChanges(slots_[collecting_]);
      stepOnce(has_tip ? &tool : nullptr);
    }
    ++next_step_, ++taken;
  }
  return taken;
}

PhysicsCounters TissuePhysics::counters() const noexcept {
  PhysicsCounters c = counters_;
  c.failed_applies += collect_failed_;
  c.reserve_overflows += collect_overflows_;
  c.deferred = deferred_;
  c.stale_maps = stale_maps_;
  c.dropped_maps = dropped_maps_.load(std::memory_order_relaxed);
  return c;
}

// The physics thread: the handoff from the sim thread (a step message per due step, change buffers given
// back once applied) and the thread's loop.

namespace {

constexpr std::int64_t kNeverLateNs = std::numeric_limits<std::int64_t>::max();  // not against the clock

// How often a fast replay's frame looks for room in the handoff (sleeping leaves the core to the physics
// thread).
constexpr std::chrono::microseconds kRoomPoll{50};

std::int64_t nowNs() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

TissuePhysics::~TissuePhysics() {
  try {
    stopThread();
  } catch (...) {  // join failed: nothing more can be done here
  }
}

void TissuePhysics::startThread(PhysicsThreadOptions options) {
  if (worker_) throw std::logic_error("TissuePhysics: startThread() while the physics thread runs");
  auto w = std::make_unique<Worker>();
  const double period_s = options.wall_per_simulated_s / options_.rate_hz;
  w->period_ns = period_s > 0.0 ? static_cast<std::int64_t>(std::min(period_s * 1e9, 1e15)) : kNeverLateNs;
  wait_for_maps_ = options.wait_for_room;
  w->options = std::move(options);
  const physics::CutChanges& first = slots_[collecting_];
  for (std::size_t i = 0; i < kChangeSlots; ++i) {
    if (i == collecting_) continue;
    if (slots_[i].nodes.capacity() == 0)
      slots_[i].reserve(first.nodes.capacity(), first.base_tets.capacity(), first.pieces.capacity());
    w->free_slots.tryPush(i);
  }
  step_times_.reserve(kStoredStepTimes);
  worker_ = std::move(w);
  try {
    worker_->thread = std::thread([this] { runWorker(); });
  } catch (...) {
    worker_.reset();
    throw;
  }
}

void TissuePhysics::stopThread() {
  if (!worker_) return;
  Worker& w = *worker_;
  while (w.has_held && !pushMessage(w.held)) std::this_thread::sleep_for(std::chrono::microseconds(100));
  w.has_held = false;
  w.stop.store(true, std::memory_order_release);
  w.wake.fetch_add(1, std::memory_order_release);
  w.wake.notify_all();
  w.thread.join();
  worker_.reset();
  wait_for_maps_ = false;
}

const PhysicsState* TissuePhysics::latestState() noexcept {
  states_->update();
  const PhysicsState& s = states_->read();
  return s.step > 0 ? &s : nullptr;
}

bool TissuePhysics::pushMessage(const StepMessage& m) noexcept {
  Worker& w = *worker_;
  if (!w.steps.tryPush(m)) return false;
  w.wake.fetch_add(1, std::memory_order_release);
  w.wake.notify_one();  // a system call only when the physics thread sleeps in wait()
  return true;
}

// The tool at a step through the handoff's plain values, and back.
void TissuePhysics::packTool(const ToolAt& tool, StepMessage& m) noexcept {
  m.tip_m = {tool.tip_m.x(), tool.tip_m.y(), tool.tip_m.z()};
  m.has_tip = true;
  const Eigen::Vector3d &p = tool.press.rest_point_m, &n = tool.press.rest_normal;
  m.press = {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()};
  m.has_press = tool.press.on;
}

TissuePhysics::ToolAt TissuePhysics::unpackTool(const StepMessage& m) noexcept {
  ToolAt tool;
  tool.tip_m = Eigen::Vector3d(m.tip_m[0], m.tip_m[1], m.tip_m[2]);
  tool.press.on = m.has_press;
  tool.press.rest_point_m = Eigen::Vector3d(m.press[0], m.press[1], m.press[2]);
  tool.press.rest_normal = Eigen::Vector3d(m.press[3], m.press[4], m.press[5]);
  return tool;
}

// Sim thread: step `step`, with the changes collected so far, to the physics thread.
void TissuePhysics::handOver(std::int64_t step, std::int64_t due_ns, const ToolAt* tool) noexcept {
  Worker& w = *worker_;
  const bool wait = w.options.wait_for_room;
  while (w.has_held && !pushMessage(w.held)) {
    if (!wait) {  // the queue is still full: this step goes with the held one, its changes later
      w.held.last_step = step;
      if (tool != nullptr) packTool(*tool, w.held);
      if (!slots_[collecting_].empty()) ++deferred_;
      return;
    }
    std::this_thread::sleep_for(kRoomPoll);
  }
  w.has_held = false;
  StepMessage m{step, step, -1, due_ns};
  if (tool != nullptr) packTool(*tool, m);
  if (!slots_[collecting_].empty()) {
    std::size_t fresh = 0;
    bool got = w.free_slots.tryPop(fresh);
    while (!got && wait) {
      std::this_thread::sleep_for(kRoomPoll);
      got = w.free_slots.tryPop(fresh);
    }
    if (got) {
      m.slot = static_cast<int>(collecting_);
      collecting_ = fresh;
    } else {
      ++deferred_;  // every buffer in flight: the changes go with a later step
    }
  }
  while (!pushMessage(m)) {
    if (!wait) {
      w.held = m;
      w.has_held = true;
      return;
    }
    std::this_thread::sleep_for(kRoomPoll);
  }
}

// The physics thread: each message's changes, then its steps, each timed against its deadline.
void TissuePhysics::runWorker() noexcept {
  Worker& w = *worker_;
  StepMessage m;
  while (true) {
    const std::uint32_t seen = w.wake.load(std::memory_order_acquire);
    if (!w.steps.tryPop(m)) {
      // stop is stored after the last push: seen set, one more pop finds every message left.
      if (!w.stop.load(std::memory_order_acquire)) {
        w.wake.wait(seen, std::memory_order_acquire);
        continue;
      }
      if (!w.steps.tryPop(m)) return;
    }
    if (m.slot >= 0) {
      const auto slot = static_cast<std::size_t>(m.slot);
      applyChanges(slots_[slot]);
      w.free_slots.tryPush(slot);  // never full: it holds at most the other slots
    }
    for (std::int64_t k = m.first_step; k <= m.last_step; ++k) {
      if (w.options.before_step) w.options.before_step(k);
      const std::int64_t start_ns = nowNs();
      const ToolAt tool = unpackTool(m);
      stepOnce(m.has_tip ? &tool : nullptr);
      const std::int64_t end_ns = nowNs();
      const bool late = w.period_ns < kNeverLateNs && end_ns > m.due_ns + (k - m.first_step + 1) * w.period_ns;
      if (late) {
        ++counters_.late;
        late_.fetch_add(1, std::memory_order_relaxed);
      }
      if (step_times_.size() < step_times_.capacity())
        step_times_.push_back({static_cast<float>(1e-3 * static_cast<double>(end_ns - start_ns)), late});
      PhysicsState& state = states_->writeSlot();
      state.step = k;
      state.nodes = model_->copyPositions(state.x_m);
      states_->publish();
    }
  }
}

// The blade's mapping to the rest frame: the tool's recent tips, the rest map made after each step on the
// stepping thread, and the frame's choice of map by a pose's time.

void ToolTrack::record(double time_s, const Eigen::Vector3d& tip_m, const ToolPress& press) noexcept {
  time_s_[next_] = time_s;
  tip_m_[next_] = tip_m;
  press_[next_] = press;
  next_ = (next_ + 1) % kCapacity;
  size_ = std::min(size_ + 1, kCapacity);
}

bool ToolTrack::tipAt(double t_s, Eigen::Vector3d& tip_m, ToolPress* press) const noexcept {
  if (size_ == 0) return false;
  // Newest first; the poses are in time order (World rejects one not after the last).
  for (std::size_t i = 1; i <= size_; ++i) {
    const std::size_t at = (next_ + kCapacity - i) % kCapacity;
    tip_m = tip_m_[at];
    if (press != nullptr) *press = press_[at];
    if (time_s_[at] <= t_s) return true;
  }
  return true;  // every kept pose is later: the oldest
}

void TissuePhysics::publishMap(const Eigen::Vector3d* tip_m) noexcept {
  physics::RestMap map;  // the identity
  if (tip_m != nullptr) {
    map = model_->restMap(*tip_m, map_guess_m_.allFinite() ? map_guess_m_ : *tip_m);
    map_guess_m_ = map.located ? map.toRest(*tip_m) : *tip_m;
  }
  MapMessage m{{}, {}, counters_.steps, map.located, press_located_};
  if (press_located_) {
    const Eigen::Vector3d point_m = physics::embeddedPosition(press_anchor_, model_->positions_m());
    const Eigen::Vector3d& normal = press_normal_;
    m.press = {point_m.x(), point_m.y(), point_m.z(), normal.x(), normal.y(), normal.z()};
    m.pressed = point_m.allFinite() && normal.allFinite();
  }
  std::copy_n(map.world_m.data(), 3, m.values.begin());
  std::copy_n(map.rest_m.data(), 3, m.values.begin() + 3);
  std::copy_n(map.world_to_rest.data(), 9, m.values.begin() + 6);
  if (!maps_->tryPush(m)) dropped_maps_.fetch_add(1, std::memory_order_relaxed);
}

void TissuePhysics::takeMaps() noexcept {
  MapMessage m;
  while (maps_->tryPop(m)) {
    physics::RestMap& map = recent_maps_[static_cast<std::size_t>(m.step) % kRecentMaps];
    std::copy_n(m.values.begin(), 3, map.world_m.data());
    std::copy_n(m.values.begin() + 3, 3, map.rest_m.data());
    std::copy_n(m.values.begin() + 6, 9, map.world_to_rest.data());
    map.step = m.step, map.located = m.located;
    PressPoint& press = recent_presses_[static_cast<std::size_t>(m.step) % kRecentMaps];
    press.point_m = Eigen::Vector3d(m.press[0], m.press[1], m.press[2]);
    press.normal = Eigen::Vector3d(m.press[3], m.press[4], m.press[5]);
    press.step = m.step, press.on = m.pressed;
    newest_map_ = std::max(newest_map_, m.step);
  }
}

void TissuePhysics::awaitMaps() noexcept {
  takeMaps();
  while (wait_for_maps_ && newest_map_ < stepsDue() - kMapLagSteps) {
    std::this_thread::sleep_for(kRoomPoll);
    takeMaps();
  }
}

std::int64_t TissuePhysics::mapStep(double t_s, double& fraction) const noexcept {
  fraction = 0.0;
  if (!started_ || !std::isfinite(t_s)) return 0;
  // The last step due at t_s (never past the steps made due so far), less the lag.
  const double ticks = (t_s - t_first_s_) * options_.rate_hz + 1e-9, due = std::floor(ticks);
  const std::int64_t last_due =
      due < 0.0 ? 0 : std::min(static_cast<std::int64_t>(std::min(due, 1e15)), next_step_ - 1);
  // A step not made due yet (the frame's poses come before its physics): the end of the period before it.
  fraction = static_cast<double>(last_due) == due ? std::clamp(ticks - due, 0.0, 1.0) : 1.0;
  return std::max<std::int64_t>(0, last_due - kMapLagSteps);
}

PressPoint TissuePhysics::pressPointAt(double t_s) noexcept {
  takeMaps();
  double fraction = 0.0;
  const std::int64_t want = mapStep(t_s, fraction);
  const auto made = [&](std::int64_t k) -> const PressPoint* {
    const PressPoint& p = recent_presses_[static_cast<std::size_t>(k) % kRecentMaps];
    return k > 0 && p.step == k ? &p : nullptr;
  };
  const PressPoint* newer = made(want);
  if (newer == nullptr || !newer->on) return {};
  const PressPoint* older = made(want - 1);
  if (older == nullptr || !older->on) return *newer;
  PressPoint blended = *newer;
  blended.point_m = older->point_m + fraction * (newer->point_m - older->point_m);
  const Eigen::Vector3d normal = older->normal + fraction * (newer->normal - older->normal);
  if (normal.norm() > 0.0) blended.normal = normal.normalized();
  return blended;
}

physics::RestMap TissuePhysics::restMapAt(double t_s) noexcept {
  takeMaps();
  double fraction = 0.0;
  const std::int64_t want = mapStep(t_s, fraction);
  if (want <= 0) return {};  // the tissue at rest
  const auto made = [&](std::int64_t k) { return recent_maps_[static_cast<std::size_t>(k) % kRecentMaps].step == k; };
  if (made(want)) return recent_maps_[static_cast<std::size_t>(want) % kRecentMaps];
  ++stale_maps_;
  // The newest map made before the one wanted (the physics behind), else the oldest kept after it (the
  // pose older than the maps kept); the ring holds steps (newest - kRecentMaps, newest].
  const std::int64_t oldest_kept = std::max<std::int64_t>(1, newest_map_ - static_cast<std::int64_t>(kRecentMaps) + 1);
  for (std::int64_t k = std::min(want, newest_map_); k >= oldest_kept; --k)
    if (made(k)) return recent_maps_[static_cast<std::size_t>(k) % kRecentMaps];
  for (std::int64_t k = std::max(want + 1, oldest_kept); k <= newest_map_; ++k)
    if (made(k)) return recent_maps_[static_cast<std::size_t>(k) % kRecentMaps];
  return {};
}

}  // namespace incise::sim
