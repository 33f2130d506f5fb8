// Scoring recorded sessions as `incise score` does: the scenario read, its tissue loaded and its plan
// projected (a plan that does not project is refused before any trace is read); each trace read and checked
// against the tissue (its "tissue:" comment, scenario_run.h) before it is scored (sim::scoreSession); one
// JSON line per trace ({"trace": FILE} then sim::scoreJson's keys) and a summary of the means. One definition
// for the CLI, the C API and the Python module: the same scenario and traces give the same bytes.
//
// Threads: any (nothing shared). Cost: the tissue's load; per trace its read (O(lines)) and its score (the
// replay as `incise replay --fast` plus the cut's measure, score.h). Failure: loadScoringScenario throws
// ScenarioError or mesh::MeshError; readScoreTrace devices::TraceError (file:line), or std::invalid_argument
// "FILE: the trace is empty (no pose to score)" or "FILE: recorded on another tissue (...)"; a trace without a
// tissue comment is scored with a warning through `warn`.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "incise/devices/pose_sample.h"
#include "incise/jobs/scenario_run.h"
#include "incise/mesh/surface_mesh.h"
#include "incise/sim/scenario.h"
#include "incise/sim/score.h"

namespace incise::jobs {

struct ScoringScenario {
  sim::Scenario scenario;
  mesh::SurfaceMesh tissue;  // uncut
  std::string tissue_hash;   // tissueHashText(tissue)
};

ScoringScenario loadScoringScenario(const std::filesystem::path& path);

// The poses of the trace at `file`, checked as said above.
std::vector<devices::PoseSample> readScoreTrace(const std::filesystem::path& file, const ScoringScenario& scoring,
                                                const Warn& warn = {});

// A trace's line as `incise score` prints it (and `incise train` writes it): {"trace": trace_file} then
// sim::scoreJson's keys; no newline. Same score and name -> same bytes.
std::string scoreLine(const std::string& trace_file, const sim::Score& score);

// The summary line after the traces' lines: {"summary": {"traces": n, "mean": {key: mean, ...}}}, the means
// over the lines of the headline figures (and of the plan's, when the first line has a plan), each over the
// lines where it is a number.
nlohmann::ordered_json scoreSummary(const std::vector<nlohmann::ordered_json>& lines);

}  // namespace incise::jobs
