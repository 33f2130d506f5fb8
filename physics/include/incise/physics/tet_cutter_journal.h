// A tet cutter's journal applied to a TissueModel in one call, for a program that cuts and steps on one
// thread (tests, benchmarks, a single-threaded tool). A threaded program does the two halves apart:
// collectCutChanges on the cutting thread (cut_changes.h), TissueModel::apply on the physics thread.
//
// The model must have been built from the mesh the cutter was built with (same node and tet order), and the
// cutter must record its changes (TetCutter::recordChanges(true)) from its first follow(). Threads: the
// owner of both. Cost O(journal + changed pieces). Allocation: none within both reserves.
#pragma once

#include "incise/physics/cut_changes.h"
#include "incise/physics/tissue_model.h"

namespace incise::tets {
class TetCutter;
}

namespace incise::physics {

// scratch is cleared, filled from cutter.changes() and applied; the cutter's journal is then cleared.
ChangeStats applyTetCutterJournal(TissueModel& model, tets::TetCutter& cutter, CutChanges& scratch);

}  // namespace incise::physics
