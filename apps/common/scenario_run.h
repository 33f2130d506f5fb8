// What replay, record and bench share: a scenario's tissue, world and poses.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "incise/devices/pose_sample.h"
#include "incise/sim/plan.h"
#include "incise/sim/scenario.h"
#include "incise/sim/world.h"

namespace incise::apps {

struct LoadedScenario {
  sim::Scenario scenario;
  std::unique_ptr<sim::World> world;
  std::vector<devices::PoseSample> poses;
  std::optional<sim::Plan> plan;  // the scenario's plan projected onto the tissue (none without a plan)
};

// Loads everything a run needs (a plan is projected onto the tissue: every command refuses a bad one); throws (ScenarioError, MeshError, TraceError, invalid_argument) with a
// message that names the file (and line) at fault.
LoadedScenario loadScenarioRun(const std::string& path);

// The poses of a scenario's pose source (a recorded trace, or generated strokes over the tissue).
std::vector<devices::PoseSample> scenarioPoses(const sim::Scenario& scenario, const mesh::SurfaceMesh& tissue);

// The tissue's fingerprint as a trace's recorders write it in a comment ("tissue: <16 hex digits>", the
// geometry hash of the uncut tissue, mesh/mesh_hash.h), and the one a trace's comments carry ("" if none:
// traces from elsewhere, e.g. imported).
std::string tissueHashText(const mesh::SurfaceMesh& tissue);
inline constexpr const char* kTissueComment = "tissue: ";
std::string traceTissueHash(const std::vector<std::string>& comments);

// Prints "incise <command>: <message>" to stderr and exits with code 2 (bad input or I/O).
[[noreturn]] void failWith(const char* command, const std::string& message);

}  // namespace incise::apps
