// A scenario made ready to run: the scenario file read, its tissue loaded (or made), its plan projected onto
// the tissue, its poses read or generated (a CSV trace, a hid-recorder file through the HID profile, or
// strokes over the tissue) and a World built over the tissue. What `incise replay`, `view`, `record`,
// `bench`, the C API's incise_world_create_from_scenario and the Python module's replay share; and the
// tissue's fingerprint that traces carry in a comment, so a trace is scored on the tissue it was recorded on.
//
// Threads: any (the functions share no state; a ScenarioRun belongs to one thread at a time, its World to
// the sim thread while one runs). Cost: the tissue's load and the World's construction (its grids, the
// cutter's reserve, TetGen for a tet tissue): milliseconds to seconds. Failure: loadScenarioRun throws
// ScenarioError, mesh::MeshError, devices::TraceError or std::invalid_argument with a message naming the
// file (and line) at fault; warnings (a HID recording's bad reports, skipped) go to `warn`.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "incise/devices/pose_sample.h"
#include "incise/sim/plan.h"
#include "incise/sim/scenario.h"
#include "incise/sim/world.h"

namespace incise::jobs {

// Receives a warning's text (no prefix, no newline). Empty: "incise: warning: <text>" on stderr.
using Warn = std::function<void(const std::string&)>;

struct ScenarioRun {
  sim::Scenario scenario;
  std::unique_ptr<sim::World> world;
  std::vector<devices::PoseSample> poses;
  std::optional<sim::Plan> plan;  // the scenario's plan projected onto the tissue (none without a plan)
};

// Loads everything a run needs; a plan is projected onto the tissue (a bad one is refused here).
ScenarioRun loadScenarioRun(const std::string& path, const Warn& warn = {});

// The poses of a scenario's pose source (a recorded trace, a hid-recorder file, or strokes generated over
// `tissue`, the scenario's uncut tissue). Throws as loadScenarioRun.
std::vector<devices::PoseSample> scenarioPoses(const sim::Scenario& scenario, const mesh::SurfaceMesh& tissue,
                                               const Warn& warn = {});

// A 64-bit value as 16 lower-case hex digits (geometry hashes in reports and trace comments).
std::string hexText(std::uint64_t value);
// The tissue's fingerprint as recorders write it in a trace's comment ("tissue: <16 hex digits>": the geometry
// hash of the uncut tissue, mesh_hash.h), and the one a trace's comments carry ("" if none: traces made
// before tissues were fingerprinted, or imported).
std::string tissueHashText(const mesh::SurfaceMesh& tissue);
inline constexpr const char* kTissueComment = "tissue: ";
std::string traceTissueHash(const std::vector<std::string>& comments);

// Says `text` through `warn`, or on stderr as "incise: warning: <text>" when `warn` is empty.
void warnWith(const Warn& warn, const std::string& text);

}  // namespace incise::jobs
