#include "picture_output.h"

#include <cstdio>
#include <filesystem>

#include "incise/sim/geometry_mirror.h"
#include "incise/viewer/gl_context.h"
#include "incise/viewer/picture.h"
#include "incise/viewer/png_file.h"

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

void writePicture(const char* command, LoadedScenario& run, std::int64_t frame, const std::string& png,
                  const PictureArgs& args) {
  sim::GeometryMirror mirror;
  sim::copyGeometry(*run.world, frame, mirror);
  viewer::PictureOptions options;
  options.size = args.size;
  options.camera = args.camera;
  options.draw.wireframe = args.wireframe;
  options.tets = args.tets;
  options.tool.show = args.tool && args.last.has_value();
  if (args.last) {
    const sim::HapticState& h = args.last->haptic;
    options.tool.tip_m = h.tip_m;
    options.tool.orientation = h.orientation;
    options.tool.blade_length_m = run.scenario.world.tool.blade_length_m;
    options.tool.contact = h.contact;
    options.tool.contact_m = h.contact_m;
    options.tool.force_N = h.force_N;
  }
  const std::vector<Eigen::Vector3d> stroke = strokePoints(run);
  viewer::Camera camera;
  try {
    const viewer::RgbImage image = viewer::renderPicture(mirror, stroke, options, &camera);
    viewer::writePng(png, image);
  } catch (const std::exception& e) {
    failWith(command, e.what());
  }
  const viewer::CameraPose& c = camera.pose();
  std::printf("incise %s: wrote %s (%dx%d; camera target %.4f %.4f %.4f m, distance %.4f m)\n", command, png.c_str(),
              args.size.width, args.size.height, c.target_m.x(), c.target_m.y(), c.target_m.z(), c.distance_m);
}

void writeEndPicture(const char* command, LoadedScenario& run, std::int64_t frame, const std::string& png) {
  PictureArgs args;
  args.tool = false;
  writePicture(command, run, frame, png, args);
}

}  // namespace incise::apps
