// The scalpel, the contact point and the force vector as triangles in the world (no GL): what the renderer
// draws for the tool. The scalpel is a blade (a third of the blade length, 3 mm wide, its edge on the tool's
// +x side, the tip at the pose's position) on a 4 x 1.5 mm handle up to the blade length along the tool's
// +z; the contact point a 0.6 mm octahedron; the force a 0.25 mm-thick bar from the contact point along the
// force, ToolView::metres_per_newton per newton, with an octahedron at its head.
// Shapes: 9 floats per vertex (position in metres, unit normal, RGB), 3 vertices per triangle, no index.
// Threads: any. Cost: O(1), allocates. Failure: none.
#pragma once

#include <vector>

#include "incise/viewer/scene_renderer.h"

namespace incise::viewer {

std::vector<float> toolTriangles(const ToolView& tool);

}  // namespace incise::viewer
