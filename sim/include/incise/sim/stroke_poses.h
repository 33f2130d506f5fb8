// The generated pose source: scalpel poses for a list of strokes over a tissue, as a steady hand on a
// stylus would give them at `rate_hz` — this is how the shipped traces were made (`incise record`).
// Per stroke: `pause_s` idle 5 mm above the start, a 30 ms descent to the blade's depth, the stroke itself
// (strokeAlongPath: each sample where a ray down -y meets the surface, the tip 0.9 x depth_m below it
// along the normal, the blade along -normal, its edge facing the direction of travel, the cut button held),
// then a 30 ms rise back 5 mm above the surface.
//
// Units: metres, seconds. Cost: O(samples * vertices near each ray). Threads: any, on a tissue nobody is
// changing. Failure: std::invalid_argument (bad stroke; the first ray of a stroke missing the tissue).
#pragma once

#include <vector>

#include "incise/devices/pose_sample.h"
#include "incise/sim/scenario.h"

namespace incise::sim {

std::vector<devices::PoseSample> posesForStrokes(const mesh::SurfaceMesh& tissue,
                                                 const std::vector<StrokeSpec>& strokes, const WorldOptions& world,
                                                 double rate_hz);

}  // namespace incise::sim
