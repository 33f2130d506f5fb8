// Pictures of a run's state for the commands (render, replay --png): the world's mesh copied into a mirror
// (sim::copyGeometry), drawn off-screen by the viewer (viewer/picture.h) and written as PNG (through a .tmp
// file, renamed). The default camera frames the stroke: the tips of the scenario's poses that hold the cut
// button (all of them when cutting needs no button). Bad options and a missing display / EGL / OpenGL 3.3
// are reported by failWith (exit 2).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "incise/sim/simulation.h"
#include "incise/viewer/camera.h"
#include "incise/viewer/scene_renderer.h"
#include "scenario_run.h"

namespace incise::apps {

// Exits with 2 (failWith) unless `png` ends in .png; `option` names the option in the message.
void checkPngPath(const char* command, const char* option, const std::string& png);

// Exits with 2 (failWith) when no off-screen OpenGL 3.3 context can be had (no display and no EGL, an old
// driver): checked before a run, so that the run is not done for nothing.
void checkPictureContext(const char* command);

// The points the default camera frames: the tips of the poses that cut.
std::vector<Eigen::Vector3d> strokePoints(const LoadedScenario& run);

// A polyline drawn over a picture after rendering (2D, in the picture's plane: never hidden by the mesh), e.g.
// the plan of `incise score --picture`. Points in metres, projected by the picture's camera.
struct OverlayLine {
  std::vector<Eigen::Vector3d> points_m;
  std::array<std::uint8_t, 3> rgb{40, 190, 60};
  int width_px = 3;
};

struct PictureArgs {
  viewer::ImageSize size{1280, 800};
  std::optional<viewer::CameraOption> camera;
  bool tool = true;
  bool wireframe = false;
  bool tets = false;                  // the tet mesh's boundary instead of the surface
  std::optional<sim::Snapshot> last;  // the tool, contact and force drawn (none: no tool)
  std::vector<OverlayLine> overlay;
  // A textured tissue's images (tissueImages), read before the run so that a bad image stops it before
  // the work; none: writePicture reads them itself.
  std::optional<viewer::TissueImages> textures;
};

// Renders the world as it is and writes `png`; prints "wrote ..." with the camera used.
void writePicture(const char* command, LoadedScenario& run, std::int64_t frame, const std::string& png,
                  const PictureArgs& args);
// The end state with the default picture options (replay --png), the images read before the run.
void writeEndPicture(const char* command, LoadedScenario& run, std::int64_t frame, const std::string& png,
                     std::optional<viewer::TissueImages> textures);

}  // namespace incise::apps
