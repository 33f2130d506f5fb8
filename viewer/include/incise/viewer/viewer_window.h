// The interactive viewer (incise view): a GLFW window on the main thread that follows a running
// simulation at display rate — the tissue from the geometry stream (GeometryMirror -> SurfaceModel ->
// SceneRenderer), the tool, contact and force from the newest snapshot — with an orbit / pan / zoom camera
// and a Dear ImGui HUD (HudModel's numbers, the pose source and its state, a frame-time plot).
//
// Mouse: left drag orbits, right or middle drag (or shift + left) pans, the wheel zooms. Keys: Space or P
// pause, R restart, W wireframe, T the tets' boundary instead of the surface (a tet tissue; a simulated
// tissue starts with its tets' boundary as simulated, and T shows the skin at rest), S screenshot
// (PNG), C or Home reset the camera, Esc or Q close.
// Threads: the main thread (GLFW's rule), which is the geometry stream's reader; it never waits for the
// sim thread. Cost per display frame: the records since the last frame, the changed vertices' normals and
// uploads, one draw of the mesh. Failure: the constructor throws ViewerError (no display, no OpenGL 3.3
// core, shader errors); frame() reports a failed screenshot in the HUD and carries on.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include <Eigen/Core>

#include "incise/sim/geometry_mirror.h"
#include "incise/sim/geometry_stream.h"
#include "incise/sim/plan.h"
#include "incise/sim/simulation.h"
#include "incise/viewer/camera.h"
#include "incise/viewer/hud_model.h"
#include "incise/viewer/mouse_scalpel.h"
#include "incise/viewer/scene_renderer.h"

namespace incise::viewer {

struct ViewerWindowOptions {
  std::string title = "incise view";
  ImageSize size;
  std::filesystem::path screenshot_dir = ".";  // screenshots go to screenshot_dir/incise-view-N.png
  std::optional<CameraOption> camera;          // else the stroke is framed
};

// What one run shows: where its data comes from. The window reads, never writes, these.
struct ViewerFeed {
  sim::GeometryStream* geometry = nullptr;
  std::function<bool(sim::Snapshot&)> take_snapshot;  // the newest snapshot, true when there was one
  sim::FrameTimesQueue* times = nullptr;              // every frame's timings (popped here)
  const PoseSourceMonitor* source = nullptr;
  double period_us = 1000.0, cut_budget_us = 300.0, blade_length_m = 0.03;
  std::span<const Eigen::Vector3d> stroke_points_m;  // framed by the default camera
  std::string scenario;
  // Training (incise train): the plan drawn on the tissue and the live lateral error against it in the HUD.
  const sim::Plan* plan = nullptr;
  // The mouse as the scalpel (MouseScalpel): every cursor event becomes a pose pushed here, stamped by
  // clock_s (the session's clock); the left button cuts, the wheel sets the depth, right drag orbits, shift
  // + right or middle drag pans, ctrl + wheel zooms. nullptr: the mouse moves the camera only.
  devices::PoseSink* scalpel = nullptr;
  std::function<double()> clock_s;
  MouseScalpelOptions scalpel_options;
  // A simulated tissue: its newest published node positions (sim::TissuePhysics::latestState, this window
  // its one reader), nullptr before the first. Set: the window draws the tets' boundary as simulated and
  // the tool where the device holds it (T: the skin at rest and the tool in the rest frame instead).
  std::function<const sim::PhysicsState*()> physics_state;
  // A textured tissue's images (SceneRenderer::setTextures, uploaded at follow()); none: plain colours.
  std::optional<TissueImages> textures;
};

// What the user asked for during a frame.
struct ViewerRequests {
  bool close = false, restart = false, pause_toggled = false;
};

class ViewerWindow {
 public:
  explicit ViewerWindow(const ViewerWindowOptions& options);
  ~ViewerWindow();
  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;

  // Starts following a (new) run with a fresh HUD: from `seeded` (GeometryStream::seed, before the run), or
  // with a fresh copy that asks the stream for a full re-sync.
  void follow(const ViewerFeed& feed, sim::GeometryMirror seeded = {});
  // One display frame: pull, update, draw, HUD, swap; then the user's requests.
  ViewerRequests frame();  // after follow()
  // The HUD's numbers now (for the benchmark and the report).
  HudFigures figures() const;
  std::int64_t displayFrames() const noexcept;
  std::string glDescription() const;
  // Where a point lands in the window now (pixels from its top left; nullopt before the camera is framed,
  // or behind the eye): for scripts that drive the mouse (the training test).
  std::optional<Eigen::Vector2d> pixelOf(const Eigen::Vector3d& x_m) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace incise::viewer
