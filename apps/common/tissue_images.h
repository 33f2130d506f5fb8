// The images a scenario's textured tissue is drawn with (view, train, render, replay --png): the skin's
// from the scenario's tissue.texture.skin (on every face), else one per material of the tissue: its
// `map_Kd` (the statement's last token: the path, absolute since the MTL was read; one that cannot be read
// is warned about on stderr), else its `Kd` colour, else the plain skin colour (a 1 x 1 image; also for a
// tissue without materials); the walls' from tissue.texture.wall, else incise's flesh (compiled into the
// mesh library: mesh::detail::wallTexturePng).
// Threads: any. Cost: the images' decoding (a few ms for 512 x 512 each). Failure: failWith (exit 2) naming
// the scenario's image that cannot be read as PNG.
#pragma once

#include <optional>

#include "incise/viewer/scene_renderer.h"
#include "scenario_run.h"

namespace incise::apps {

// nullopt for a tissue without texture coordinates (drawn in the plain colours).
std::optional<viewer::TissueImages> tissueImages(const char* command, const sim::Scenario& scenario,
                                                 const mesh::SurfaceMesh& tissue);
inline std::optional<viewer::TissueImages> tissueImages(const char* command, const LoadedScenario& run) {
  return tissueImages(command, run.scenario, run.world->tissue());
}

}  // namespace incise::apps
