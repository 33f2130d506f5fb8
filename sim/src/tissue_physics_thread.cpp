// The physics thread of a simulated tissue (tissue_physics.h): the handoff from the sim thread (a step
// message per due step, change buffers given back once applied) and the thread's loop.
#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <thread>

#include "incise/physics/tissue_model.h"
#include "incise/sim/tissue_physics.h"
#include "tissue_physics_worker.h"

namespace incise::sim {

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
  w->options = std::move(options);
  const physics::CutChanges& first = slots_[collecting_];
  for (std::size_t i = 0; i < kChangeSlots; ++i) {
    if (i == collecting_) continue;
    if (slots_[i].nodes.capacity() == 0)
      slots_[i].reserve(first.nodes.capacity(), first.base_tets.capacity(), first.pieces.capacity());
    w->free_slots.tryPush(i);
  }
  step_times_.reserve(kStoredStepTimes);
  if (!states_) {
    PhysicsState initial;
    initial.x_m.resize(static_cast<std::size_t>(model_->nodeCount() + model_->options().reserve_nodes));
    states_ = std::make_unique<TripleBuffer<PhysicsState>>(initial);
  }
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
}

const PhysicsState* TissuePhysics::latestState() noexcept {
  if (!states_) return nullptr;
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

// Sim thread: step `step`, with the changes collected so far, to the physics thread.
void TissuePhysics::handOver(std::int64_t step, std::int64_t due_ns) noexcept {
  Worker& w = *worker_;
  const bool wait = w.options.wait_for_room;
  while (w.has_held && !pushMessage(w.held)) {
    if (!wait) {  // the queue is still full: this step goes with the held one, its changes later
      w.held.last_step = step;
      if (!slots_[collecting_].empty()) ++deferred_;
      return;
    }
    std::this_thread::sleep_for(kRoomPoll);
  }
  w.has_held = false;
  StepMessage m{step, step, -1, due_ns};
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
      stepOnce();
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

}  // namespace incise::sim
