// WorkBudget: how much cutting work one call of a cutter may do (SurfaceCutter::advance/settleStep with
// either limit, TetCutter::follow with units only). Two limits, whichever comes first:
//   - units: node inversions and refinement splits (the dominant costs, 2-4 us each here), counted; and for
//     the surface cutter, a column's grid query, its crossings and the wound's re-deform, charged in units
//     by how many vertices they touch (SurfaceCutter's kCandidatesPerUnit, kFreshPerUnit, kMovesPerUnit).
//     A replay that is not against the clock uses units alone, so how the work falls into calls is the same
//     on every machine.
//   - a deadline on std::chrono::steady_clock (optional): the real-time loop's end of the cut phase, so a
//     frame's cutting stops on time whatever a unit costs on this machine at this moment.
// The work itself never depends on where a call stopped (the cutters resume in the same order), so the
// deadline changes when the cut is done, not what it is (tests/sim/world_test.cpp: every cut phase stopped
// at once gives the same hash; replay_test.cpp: the same bytes fast and in real time).
// Cost: spent() is a compare; take() reads the clock once when a deadline is set (about 25 ns here, per
// inversion of about 2 us). Thread: the cutter's owner. No allocation, never throws.
#pragma once

#include <chrono>
#include <climits>
#include <cstddef>

namespace incise::core {

class WorkBudget {
 public:
  using Clock = std::chrono::steady_clock;

  // `units` <= 0: no limit in units. `deadline` = Clock::time_point::max(): none.
  explicit WorkBudget(int units, Clock::time_point deadline = Clock::time_point::max()) noexcept
      : units_(units > 0 ? units : INT_MAX), initial_(units_), deadline_(deadline) {}
  static WorkBudget unlimited() noexcept { return WorkBudget(0); }

  bool spent() const noexcept { return units_ <= 0; }
  // One unit of work is about to be done: counts it, and ends the budget once the deadline has passed.
  void take() noexcept {
    --units_;
    if (deadline_ != Clock::time_point::max() && Clock::now() >= deadline_) {
      units_ = 0;
      deadline_hit_ = true;
    }
  }
  // `units` (>= 1) units of work were just done at once (e.g. a grid query's worth): counts them; the
  // deadline as take().
  void take(int units) noexcept {
    units_ -= units - 1;
    take();
  }
  // Units left (may be negative after take(units)); nothing taken yet.
  int remaining() const noexcept { return units_; }
  bool untouched() const noexcept { return units_ == initial_ && !deadline_hit_; }
  // Whether a step of `units` should start in this call: enough is left, or nothing was done yet (so a step
  // larger than a whole budget still runs, alone in its call).
  bool affords(int units) const noexcept { return untouched() || units_ >= units; }
  // For work counted in items, one unit per `per_unit` of them: at every per_unit-th item (0, per_unit, ...)
  // takes a unit, or returns false when the budget is spent (stop before item `item`, resume there).
  bool takeEvery(std::size_t item, std::size_t per_unit) noexcept {
    if (item % per_unit != 0) return true;
    if (spent()) return false;
    take();
    return true;
  }
  // True when the deadline, not the units, ended this budget.
  bool deadlineHit() const noexcept { return deadline_hit_; }

 private:
  int units_;
  int initial_;
  Clock::time_point deadline_;
  bool deadline_hit_ = false;
};

}  // namespace incise::core
