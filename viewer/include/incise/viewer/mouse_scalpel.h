// The mouse as a scalpel (incise train --input mouse): the cursor's ray through the camera meets the
// tissue as the viewer has it (SurfaceModel); the left button held puts the blade down, to a depth below
// the surface that the wheel sets; the blade stands along the surface normal at the hit (local -z into the
// tissue, as sim::World reads a pose) with its cutting edge (local +x) along the cursor's motion over the
// surface. The poses go to the simulation like any live device's (devices::PoseSink).
// Over a wound, hovering and the blade's entry: above MouseScalpel.
//
// Units: metres, seconds; pixels with the origin at the top left. Threads: the viewer's (a value type).
// Cost: pose() O(F) (a ray against every face of the model: ~1 ms on 60k triangles). Failure: the
// constructor throws std::invalid_argument for bad options; nothing else throws.
#pragma once

#include <array>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/devices/pose_sample.h"
#include "incise/viewer/camera.h"
#include "incise/viewer/surface_model.h"

namespace incise::viewer {

struct MouseScalpelOptions {
  double depth_m = 0.003;         // below the surface with the button held, at the start
  double depth_step_m = 0.0005;   // per wheel notch (up: deeper)
  double max_depth_m = 0.02;      // the wheel's range is [0, max_depth_m]
  double hover_m = 0.004;         // above the surface with the button up
  double groove_reach_m = 0.006;  // how far from the last skin hit the tangent plane stands in for it
  double start_m = 0.001;         // the cursor's way over the surface before the blade goes in
  int cut_button = 0;             // the button bit the poses carry while the left button is held
};

// One cursor reading: position in a width x height window, the left button, the time (the session's clock).
struct MouseReading {
  double x_px = 0.0, y_px = 0.0;
  int width_px = 1, height_px = 1;
  bool left = false;
  double time_s = 0.0;
};

// Over a wound the ray meets the walls or falls into the groove: the wall faces are left out and, within
// `groove_reach_m` of the last skin hit, the ray is met with the tangent plane there instead, so that a
// stroke crosses its own (or an earlier) incision without the blade jumping to the far side of the tissue.
// With the button up the tip hovers `hover_m` above the hit (no contact); a ray that meets nothing lifts
// the tip off the tissue along the last normal. The blade goes in once the cursor, button held, has moved
// `start_m` over the surface from where the button went down: its first pose in the tissue is at that
// point, stamped with the press's time, its edge along the way the cursor went (the simulation lays the
// incision along the edge at first contact, so it must be the stroke's direction), then the pose under the
// cursor.
class MouseScalpel {
 public:
  explicit MouseScalpel(const MouseScalpelOptions& options = {});

  // Wheel notches (positive: deeper), clamped to [0, max_depth_m].
  void scroll(double notches) noexcept;
  double depthM() const noexcept { return depth_m_; }

  // The poses for this reading, oldest first: none before the cursor has ever met the tissue, or while the
  // button is held but the cursor has not yet gone start_m; two when the blade goes in; else one.
  struct Poses {
    std::array<devices::PoseSample, 2> pose;
    int count = 0;
  };
  Poses poses(const Camera& camera, const SurfaceModel& tissue, const MouseReading& m);

  bool onTissue() const noexcept { return on_tissue_; }  // the last reading's ray met the tissue
  const Eigen::Vector3d& surfacePointM() const noexcept { return hit_m_; }
  const Eigen::Vector3d& normal() const noexcept { return normal_; }

 private:
  struct Hit {
    Eigen::Vector3d point_m, normal;
  };
  std::optional<Hit> cast(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& dir,
                          const SurfaceModel& tissue) const;
  Eigen::Quaterniond orientation(const Eigen::Vector3d& point_m);

  MouseScalpelOptions options_;
  double depth_m_;
  bool has_hit_ = false, on_tissue_ = false;
  bool pressed_ = false, in_ = false;  // the button is held; the blade is in (the way start_m gone)
  Eigen::Vector3d press_m_ = Eigen::Vector3d::Zero(), press_normal_ = Eigen::Vector3d::UnitZ();
  double press_s_ = 0.0;
  Eigen::Vector3d hit_m_ = Eigen::Vector3d::Zero(), normal_ = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d edge_ = Eigen::Vector3d::UnitX();  // the blade's cutting direction, in the tangent plane
};

}  // namespace incise::viewer
