#include "incise/physics/tet_cutter_journal.h"

#include "incise/tets/tet_cutter.h"

namespace incise::physics {

ChangeStats applyTetCutterJournal(TissueModel& model, tets::TetCutter& cutter, CutChanges& scratch) {
  scratch.clear();
  collectCutChanges(cutter, cutter.changes(), scratch);
  cutter.clearChanges();
  return model.apply(scratch);
}

}  // namespace incise::physics
