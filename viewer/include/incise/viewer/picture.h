// Pictures of the tissue without a window (incise render, incise replay --png, the pixel tests): the
// mirror's mesh drawn off-screen into a framebuffer (GlContext::Offscreen: a hidden window under Xvfb or
// any display, else EGL on Mesa) with the default camera or the --camera one, read back as RGB.
// Also the default framing both the window and the pictures use.
// Threads: the calling thread (it makes its own context current). Cost: a context (tens of ms), one draw.
// Failure: ViewerError (no display and no EGL, no OpenGL 3.3, an incomplete framebuffer).
#pragma once

#include <optional>
#include <span>

#include <Eigen/Core>

#include "incise/sim/geometry_mirror.h"
#include "incise/viewer/camera.h"
#include "incise/viewer/png_file.h"
#include "incise/viewer/scene_renderer.h"
#include "incise/viewer/surface_model.h"

namespace incise::viewer {

// The stroke framed (Camera::frameStroke) seen along the skin's normal nearest its centre, tilted towards
// +y; or the --camera option around that framing. Without stroke points, the whole tissue is framed.
Camera defaultCamera(const SurfaceModel& model, std::span<const Eigen::Vector3d> stroke_points_m, double aspect,
                     const std::optional<CameraOption>& option);

struct PictureOptions {
  ImageSize size;
  std::optional<CameraOption> camera;
  std::optional<Camera> exact_camera;  // overrides the two above (tests: the same camera for two pictures)
  ToolView tool;                       // tool.show = false leaves the scalpel out
  DrawOptions draw;
  bool tets = false;  // the tet mesh's boundary instead of the surface (ViewerError without a tet tissue)
  std::optional<TissueImages> textures;  // drawn on a textured tissue's surface; none: the plain colours
};

// Needs mirror.complete(). The camera used is returned through `used` when given.
RgbImage renderPicture(const sim::GeometryMirror& mirror, std::span<const Eigen::Vector3d> stroke_points_m,
                       const PictureOptions& options, Camera* used = nullptr);

}  // namespace incise::viewer
