// The viewer's camera: a perspective eye orbiting a target point, with the matrices OpenGL takes, the mouse
// gestures (orbit, pan, zoom), a reset to the framing it started from, the framing of a stroke (the
// default: the incision fills the picture, seen from outside along the surface normal there) and the
// parser of the `--camera` option.
//
// Units: metres, degrees in the option and the angles, radians nowhere outside camera.cpp. Matrices are
// column-major 4x4 floats (Eigen's default, what glUniformMatrix4fv takes with GL_FALSE): clip = P * V * x.
// Threads: a value type; no GL. Cost: O(1) per call (frameStroke O(points)). Failure: parseCameraOption
// and parseSizeOption throw std::invalid_argument with the option and the value; the rest never throws.
#pragma once

#include <optional>
#include <span>
#include <string>

#include <Eigen/Core>

namespace incise::viewer {

struct CameraPose {
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d eye_dir = Eigen::Vector3d::UnitZ();  // unit, from the target towards the eye
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();       // unit, perpendicular to eye_dir
  double distance_m = 0.3;
  double fov_y_deg = 35.0;
};

// `--camera AZ,EL[,DIST]`: the eye at azimuth AZ (degrees about +y, 0 = on +z, 90 = on +x) and elevation EL
// (degrees above the x-z plane, |EL| < 90) around the default target, DIST metres away (> 0; default: the
// framing distance).
struct CameraOption {
  double azimuth_deg = 0.0, elevation_deg = 0.0;
  std::optional<double> distance_m;
};
CameraOption parseCameraOption(const std::string& value);  // "auto" is not an option value: use no option

struct ImageSize {
  int width = 1280, height = 800;
};
// `--size WxH`, each in [16, 8192].
ImageSize parseSizeOption(const std::string& value);

class Camera {
 public:
  Camera() = default;
  explicit Camera(const CameraPose& pose) : pose_(pose), home_(pose) {}

  // Frames the points (e.g. the stroke's tip positions in contact): the target at their bounding box's
  // centre, the eye along `outward` (the surface normal there; any non-zero vector) tilted a little
  // towards `up_hint` so that the walls show, far enough for the box plus a margin to fill the view at
  // `aspect` (width / height). An empty span or a zero box frames a 2 cm neighbourhood of `fallback_m`.
  static Camera frameStroke(std::span<const Eigen::Vector3d> points_m, const Eigen::Vector3d& outward,
                            const Eigen::Vector3d& up_hint, double aspect, const Eigen::Vector3d& fallback_m);
  // The camera of the --camera option around `framed`'s target (and distance unless given).
  static Camera fromOption(const CameraOption& option, const Camera& framed);

  Eigen::Matrix4f view() const;
  Eigen::Matrix4f projection(double aspect) const;
  Eigen::Vector3d eye_m() const { return pose_.target_m + pose_.distance_m * pose_.eye_dir; }
  // Where a point lands in a width x height picture (pixels, origin top left); nullopt behind the eye.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& x_m, int width, int height) const;
  // The ray from the eye through pixel (x_px, y_px) of a width x height picture (origin top left): the
  // inverse of project(). Returns the unit direction; the ray starts at eye_m().
  Eigen::Vector3d rayThrough(double x_px, double y_px, int width, int height) const;

  // Mouse gestures, in pixels of a window `height` pixels high: orbit turns the eye about the target
  // (horizontal about `up`, vertical about the right axis, clamped short of the poles), pan moves the
  // target in the view plane so the picture follows the cursor, zoom multiplies the distance by
  // 0.9^steps (positive steps: closer).
  void orbit(double dx_px, double dy_px, int height);
  void pan(double dx_px, double dy_px, int height);
  void zoom(double steps);
  void reset() { pose_ = home_; }

  const CameraPose& pose() const noexcept { return pose_; }

 private:
  CameraPose pose_, home_;
};

}  // namespace incise::viewer
