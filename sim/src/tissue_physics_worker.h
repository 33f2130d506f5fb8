// The physics thread's state (tissue_physics_thread.cpp), shared by the TissuePhysics sources: the step
// queue from the sim thread, the change buffers given back, the wake-up counter and the thread itself.
// Threads: `held` and `has_held` are the sim thread's; each queue has one end on each thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>

#include "incise/sim/spsc_queue.h"
#include "incise/sim/tissue_physics.h"

namespace incise::sim {

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

}  // namespace incise::sim
