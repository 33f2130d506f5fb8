// What a run writes once it has ended, for `replay` and `view` alike (replay_command.cpp): the cut mesh
// (cut.obj), report.json (latency statistics, counts, the geometry's hash; the tets' block and files with
// a tet tissue) and the summary line on stdout (which says so when no pose cut the tissue). Written through
// .tmp files and renamed. Returns the exit code: 1 when a check of the cut failed (the mesh is not a closed
// two-manifold, an incision's groove fell short of its stroke in contact, the cutter failed, a tet tissue
// has inverted tets or failed), else 0, also for a run that never cut; an I/O failure prints the message
// and exits with 2.
#pragma once

#include <string>

#include "incise/sim/simulation.h"
#include "scenario_run.h"

namespace incise::apps::run {

int writeReplayOutputs(const char* command, const LoadedScenario& run, const sim::ReplayOptions& options,
                       const sim::ReplayReport& report, const std::string& out_dir);

}  // namespace incise::apps::run
