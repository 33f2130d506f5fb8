#include "hud_panel.h"

#include <algorithm>

#include <imgui.h>

namespace incise::viewer::detail {

namespace {

void timeRow(const char* name, const Percentiles& p) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(name);
  ImGui::TableNextColumn();
  ImGui::Text("%7.1f", p.p50);
  ImGui::TableNextColumn();
  ImGui::Text("%7.1f", p.p99);
  ImGui::TableNextColumn();
  ImGui::Text("%7.1f", p.max);
}

}  // namespace

void drawHudPanel(const HudFigures& h, const PoseSourceStatus& source, const std::vector<float>& plot,
                  const HudText& text) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_Once);
  ImGui::SetNextWindowBgAlpha(0.8f);
  ImGui::Begin("incise", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%s%s", text.scenario.c_str(), text.paused ? "  [paused]" : "");
  if (!text.training.empty()) ImGui::TextUnformatted(text.training.c_str());
  ImGui::Text("pose source: %s (%s)", source.source.c_str(), source.state.c_str());
  ImGui::Separator();
  if (ImGui::BeginTable("times", 4, ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("us (last 5 s)");
    ImGui::TableSetupColumn("p50");
    ImGui::TableSetupColumn("p99");
    ImGui::TableSetupColumn("max");
    ImGui::TableHeadersRow();
    timeRow("frame", h.frame_us);
    timeRow("haptic", h.haptic_us);
    timeRow("cut", h.cut_us);
    timeRow("geometry", h.geometry_us);
    ImGui::EndTable();
  }
  ImGui::Text("budget used: frame p99 %.0f %% of the period, cut p99 %.0f %% of its budget", 100.0 * h.period_used,
              100.0 * h.cut_budget_used);
  ImGui::Text("deadline misses: %lld (%lld in the window)", static_cast<long long>(h.deadline_misses),
              static_cast<long long>(h.window_misses));
  ImGui::Text("force %.2f N   incisions %d", h.force_N, h.incisions);
  if (h.physics_steps_due > 0)
    ImGui::Text("physics: %lld steps, %lld behind, %lld late", static_cast<long long>(h.physics_steps_done),
                static_cast<long long>(h.physics_steps_due - h.physics_steps_done),
                static_cast<long long>(h.physics_late));
  if (h.pose_to_visible_frames_max >= 0)
    ImGui::Text("pose to visible: cut %d sim frames (max)", h.pose_to_visible_frames_max);
  else
    ImGui::TextUnformatted("pose to visible: no cut made visible lately");
  ImGui::Text("on screen: %.1f ms p50, %.1f ms max (%.2f display frames), %.0f fps", h.screen_latency_ms_p50,
              h.screen_latency_ms_max, h.screen_latency_display_frames_max, h.display_fps);
  const float top = std::max(1000.0f, plot.empty() ? 0.0f : *std::max_element(plot.begin(), plot.end()));
  ImGui::PlotLines("##frame", plot.data(), static_cast<int>(plot.size()), 0, "frame us, last 5 s (max per bar)", 0.0f,
                   top, ImVec2(360, 70));
  ImGui::Text("%zu triangles (%zu wall)%s%s", text.triangles, text.wall_triangles, text.drawn.c_str(),
              text.wireframe ? ", wireframe" : "");
  ImGui::TextDisabled("%s", text.gl.c_str());
  ImGui::TextDisabled("drag: orbit, right drag: pan, wheel: zoom | Space pause, R restart, W wireframe,");
  ImGui::TextDisabled("T tets' boundary or as simulated / at rest, S screenshot, C camera reset, Esc close");
  if (!text.status.empty()) ImGui::TextUnformatted(text.status.c_str());
  ImGui::End();
}

}  // namespace incise::viewer::detail
