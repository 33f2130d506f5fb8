// The JSON documents that describe a run, as `incise replay` writes report.json and `incise cut` its
// summary.json: per incision where the groove runs and why it fell short, what went wrong with a cut,
// timing summaries, and the replay's whole report (counts, latency, the geometry's hash, the tets' figures).
// One definition for the CLI, the C API and the Python module, so the same run gives the same document.
//
// Units in every key (metres, microseconds). Threads: any, on a world nobody is stepping. Cost: the
// replay's report walks the mesh twice (its summary and its hash, O(V + F)) and, with tets, the tet mesh.
// Failure: none of these throw but std::bad_alloc.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "incise/incision/surface_cutter_options.h"
#include "incise/jobs/scenario_run.h"
#include "incise/sim/simulation.h"

namespace incise::tets {
class TetCutter;
struct TetView;
}  // namespace incise::tets

namespace incise::jobs {

// Per incision, in order: {"stroke_length_m", "groove_length_m"} (incision::IncisionFigures), where the groove
// runs along the stroke, the lattice columns that held no vertex, and the shortfall with its sentence ("why",
// empty when the groove is as long as the stroke).
nlohmann::json incisionFiguresJson(const std::vector<incision::IncisionFigures>& figures);
// What went wrong with the cut, for a report's failure field: the cutter's internal failure, else the first
// incision whose groove fell short of its stroke ("incision 2 of 3: a groove of ..."), else "".
std::string cutFailure(const incision::CutStats& stats);
// "no incision: none of the N poses cut the tissue (...)" when a replay with poses made no incision (the
// tool never touched the tissue, or touched it with the cut button up), else "". Not a failure: a run that
// did nothing says so.
std::string noIncision(const sim::ReplayReport& report);

// Sums over the incisions of their groove and stroke lengths (metres).
double totalGroove_m(const std::vector<incision::IncisionFigures>& figures);
double totalStroke_m(const std::vector<incision::IncisionFigures>& figures);

// count, p50, p99, max and mean of a list of durations in microseconds (nearest rank); {"count": 0} if empty.
nlohmann::json timingSummary(std::vector<double> values_us);

// The tet tissue's figures in a replay's report ("tets"): counts, volumes, dihedral angles, inverted tets,
// what the cutter did, failure. `deformed` is tets.view(TetShape::Deformed) when the caller has it already.
nlohmann::json tetsReport(const tets::TetCutter& tets, const tets::TetView& deformed);

// report.json of a replay that has ended, over run.world as the replay left it: scenario, mode, counts,
// the cut's figures and failure (cutFailure), "note" (noIncision), geometry_hash (mesh_hash.h, 16 hex digits), the mesh's summary, latency
// and loop figures, and with a tet tissue the "tets" block (tetsReport; the view is made here when
// `deformed` is null).
nlohmann::json replayReport(const ScenarioRun& run, const sim::ReplayOptions& options, const sim::ReplayReport& report,
                            const tets::TetView* deformed = nullptr);

// The options `incise replay` runs a scenario with: its period and settle time, the pace asked for.
sim::ReplayOptions scenarioReplayOptions(const sim::Scenario& scenario, sim::ReplayPace pace);

}  // namespace incise::jobs
