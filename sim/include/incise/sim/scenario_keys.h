// The keys a scenario file may hold, one list per kind of scenario: what the scenario readers refuse a key
// against (an unknown key is an error naming the nearest known one), what `incise keys` prints and what
// docs/scenarios.md documents (a test checks that every key is there).
// A key is its dotted path from the document's root ("tissue.tets.max_volume_m3"); the entries of an array of
// objects are written "pose_source.strokes[].length_m"; objects are listed themselves ("tissue.tets").
// Threads: any. Cost: O(1).
#pragma once

#include <span>
#include <string_view>

namespace incise::sim {

// Replay scenarios (scenario.h): tissue, tool, incision, rates and budget, plan, pose source and mappings.
std::span<const std::string_view> replayScenarioKeys();

// Wrap scenarios (wrap_scenario.h): the model, obstacles, lattice, motion and openings of a global DFFD scene.
std::span<const std::string_view> wrapScenarioKeys();

}  // namespace incise::sim
