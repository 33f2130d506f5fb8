#include "incise/viewer/picture.h"

#include "incise/viewer/gl_context.h"

namespace incise::viewer {

Camera defaultCamera(const SurfaceModel& model, std::span<const Eigen::Vector3d> stroke_points_m, double aspect,
                     const std::optional<CameraOption>& option) {
  const Eigen::AlignedBox3d bounds = model.bounds();
  Camera framed;
  if (stroke_points_m.empty()) {  // the whole tissue, from +z
    const Eigen::Vector3d corners[2] = {bounds.min(), bounds.max()};
    framed = Camera::frameStroke(corners, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY(), aspect, bounds.center());
  } else {
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& p : stroke_points_m) box.extend(p);
    Eigen::Vector3d outward = model.normalNear(box.center());
    if (outward.norm() < 0.5) outward = Eigen::Vector3d::UnitZ();
    framed = Camera::frameStroke(stroke_points_m, outward, Eigen::Vector3d::UnitY(), aspect, bounds.center());
  }
  return option ? Camera::fromOption(*option, framed) : framed;
}

RgbImage renderPicture(const sim::GeometryMirror& mirror, std::span<const Eigen::Vector3d> stroke_points_m,
                       const PictureOptions& options, Camera* used) {
  if (!mirror.complete()) throw ViewerError("renderPicture: the geometry has not arrived in full");
  GlContext context(ContextKind::Offscreen, options.size.width, options.size.height, "incise render");
  SceneRenderer renderer;
  if (options.textures) renderer.setTextures(*options.textures);
  SurfaceModel model;
  if (options.tets && !mirror.tets().complete())
    throw ViewerError("renderPicture: the scenario has no tet tissue (\"tets\" in its tissue) to draw");
  if (options.tets)
    model.update(mirror.tets());
  else
    model.update(mirror);
  renderer.upload(model);
  const double aspect = static_cast<double>(options.size.width) / options.size.height;
  const Camera camera =
      options.exact_camera ? *options.exact_camera : defaultCamera(model, stroke_points_m, aspect, options.camera);
  if (used) *used = camera;
  RgbImage image;
  image.width = options.size.width;
  image.height = options.size.height;
  image.rgb = renderer.renderPixels(camera, image.width, image.height, options.tool, options.draw);
  return image;
}

}  // namespace incise::viewer
