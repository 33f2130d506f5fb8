#include "picture_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "incise/sim/geometry_mirror.h"
#include "incise/sim/tissue_physics.h"
#include "incise/viewer/gl_context.h"
#include "incise/viewer/picture.h"
#include "incise/viewer/png_file.h"
#include "tissue_images.h"

namespace incise::apps {

void checkPngPath(const char* command, const char* option, const std::string& png) {
  if (std::filesystem::path(png).extension() != ".png")
    failWith(command, std::string(option) + " '" + png + "': the picture's file name must end in .png");
}

void checkPictureContext(const char* command) {
  try {
    viewer::GlContext probe(viewer::ContextKind::Offscreen, 64, 64, "incise: probe");
  } catch (const std::exception& e) {
    failWith(command, e.what());
  }
}

std::vector<Eigen::Vector3d> strokePoints(const LoadedScenario& run) {
  const int button = run.scenario.world.tool.cut_button;
  std::vector<Eigen::Vector3d> points;
  for (const devices::PoseSample& p : run.poses)
    if (button < 0 || ((p.buttons >> button) & 1u) != 0) points.push_back(p.tip_m);
  return points;
}

namespace {

// Each segment stepped a pixel at a time, a square of width_px painted at each step (segments behind the
// eye are left out).
void drawOverlay(viewer::RgbImage& image, const viewer::Camera& camera, const OverlayLine& line) {
  const auto paint = [&](const Eigen::Vector2d& at) {
    const int half = line.width_px / 2;
    for (int dy = -half; dy <= half; ++dy) {
      for (int dx = -half; dx <= half; ++dx) {
        const int x = static_cast<int>(std::floor(at.x())) + dx, y = static_cast<int>(std::floor(at.y())) + dy;
        if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + x);
        for (int c = 0; c < 3; ++c) image.rgb[i + static_cast<std::size_t>(c)] = line.rgb[static_cast<std::size_t>(c)];
      }
    }
  };
  for (std::size_t k = 0; k + 1 < line.points_m.size(); ++k) {
    const auto a = camera.project(line.points_m[k], image.width, image.height);
    const auto b = camera.project(line.points_m[k + 1], image.width, image.height);
    if (!a || !b) continue;
    const int steps = std::max(1, static_cast<int>(std::ceil((*b - *a).norm())));
    for (int s = 0; s <= steps; ++s) paint(*a + (*b - *a) * (static_cast<double>(s) / steps));
  }
}

}  // namespace

void writePicture(const char* command, LoadedScenario& run, std::int64_t frame, const std::string& png,
                  const PictureArgs& args) {
  sim::GeometryMirror mirror;
  sim::copySimulatedGeometry(*run.world, frame, mirror);  // a simulated tissue as simulated
  viewer::PictureOptions options;
  options.size = args.size;
  options.camera = args.camera;
  options.draw.wireframe = args.wireframe;
  options.tets = args.tets;
  options.textures = args.textures ? args.textures : tissueImages(command, run);
  options.tool.show = args.tool && args.last.has_value();
  if (args.last) {
    const sim::HapticState& h = args.last->haptic;
    options.tool.tip_m = h.tip_m;
    options.tool.orientation = h.orientation;
    options.tool.blade_length_m = run.scenario.world.tool.blade_length_m;
    options.tool.contact = h.contact;
    options.tool.contact_m = h.contact_m;
    options.tool.force_N = h.force_N;
    // A tissue drawn as simulated: the tool where it was among it, the contact where the tissue took it.
    const sim::TissuePhysics* physics = run.world->physics();
    if (physics != nullptr && !physics->threaded()) {
      options.tool.tip_m = h.world_tip_m;
      options.tool.orientation = h.world_orientation;
      options.tool.contact_m = physics->deformedPoint(h.contact_m);
    }
  }
  const std::vector<Eigen::Vector3d> stroke = strokePoints(run);
  viewer::Camera camera;
  try {
    viewer::RgbImage image = viewer::renderPicture(mirror, stroke, options, &camera);
    for (const OverlayLine& line : args.overlay) drawOverlay(image, camera, line);
    viewer::writePng(png, image);
  } catch (const std::exception& e) {
    failWith(command, e.what());
  }
  const viewer::CameraPose& c = camera.pose();
  std::printf("incise %s: wrote %s (%dx%d; camera target %.4f %.4f %.4f m, distance %.4f m)\n", command, png.c_str(),
              args.size.width, args.size.height, c.target_m.x(), c.target_m.y(), c.target_m.z(), c.distance_m);
}

void writeEndPicture(const char* command, LoadedScenario& run, std::int64_t frame, const std::string& png,
                     std::optional<viewer::TissueImages> textures) {
  PictureArgs args;
  args.tool = false;
  args.textures = std::move(textures);
  writePicture(command, run, frame, png, args);
}

}  // namespace incise::apps
