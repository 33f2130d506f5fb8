// A training plan drawn on the tissue (incise train): the planned line, the edges of its lateral tolerance
// band and markers at its start and end, as thin ribbons lying a little above the surface along the plan's
// normals, in colours of their own (none is the wall's red, which the pixel tests look for).
// Shapes: planTriangles() returns triangles as 9 floats per vertex (position m, normal, linear RGB), the
// layout SceneRenderer's overlay takes. Threads: any (a pure function). Cost: O(stations).
#pragma once

#include <array>
#include <vector>

#include "incise/sim/plan.h"

namespace incise::viewer {

inline constexpr std::array<float, 3> kPlanColour = {0.15f, 0.45f, 0.95f};
inline constexpr std::array<float, 3> kBandColour = {0.55f, 0.75f, 1.0f};
inline constexpr std::array<float, 3> kStartColour = {0.1f, 0.8f, 0.2f};
inline constexpr std::array<float, 3> kEndColour = {0.95f, 0.85f, 0.1f};

std::vector<float> planTriangles(const sim::Plan& plan);

}  // namespace incise::viewer
