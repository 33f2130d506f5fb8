// Private: the Dear ImGui panel of the viewer's HUD (viewer_window.cpp draws it each display frame).
#pragma once

#include <string>
#include <vector>

#include "incise/viewer/hud_model.h"

namespace incise::viewer::detail {

struct HudText {
  std::string scenario, gl, status, training;
  std::string drawn;  // what the tissue drawn is (", the tets' boundary", ", as simulated", ...): appended
  bool paused = false, wireframe = false;
  std::size_t triangles = 0, wall_triangles = 0;
  std::int64_t display_frames = 0;
};

// Between ImGui::NewFrame() and ImGui::Render().
void drawHudPanel(const HudFigures& figures, const PoseSourceStatus& source, const std::vector<float>& plot,
                  const HudText& text);

}  // namespace incise::viewer::detail
