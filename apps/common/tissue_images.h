// The images a scenario's textured tissue is drawn with (view, train, render, replay --png): the skin's
// from the scenario's tissue.texture.skin, else the first material's `map_Kd` (its last token: the path,
// absolute since the MTL was read; one that cannot be read is warned about on stderr), else a 1 x 1 image of the plain skin colour; the walls' from
// tissue.texture.wall, else incise's flesh (compiled into the mesh library: mesh::detail::wallTexturePng).
// Threads: any. Cost: the images' decoding (a few ms for 512 x 512). Failure: failWith (exit 2) naming the
// file that cannot be read as PNG.
#pragma once

#include <optional>

#include "incise/viewer/scene_renderer.h"
#include "scenario_run.h"

namespace incise::apps {

// nullopt for a tissue without texture coordinates (drawn in the plain colours).
std::optional<viewer::TissueImages> tissueImages(const char* command, const LoadedScenario& run);

}  // namespace incise::apps
