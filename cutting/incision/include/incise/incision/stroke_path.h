// Scalpel strokes made from a path over a surface: the samples a blade drawn along the path at a steady
// speed would give, at a fixed sample rate. Used to generate recorded traces, by the tests and the
// benchmarks. Each sample is where a ray along `down`, from `height_m` above the path point, first meets
// the surface, with that face's outward normal.
//
// Units: metres, seconds, hertz. Cost: O(samples * (vertices near the ray + their faces)) after an O(V)
// grid build. Threads: any, on a mesh nobody is changing. Failure: std::invalid_argument for bad options
// (named, with the value) or when the first ray misses the surface; the stroke stops at the first ray that
// misses (it left the surface).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "incise/incision/incision.h"
#include "incise/mesh/surface_mesh.h"

namespace incise::incision {

struct StrokePathOptions {
  Eigen::Vector3d start_m = Eigen::Vector3d::Zero();     // first path point (above or on the surface)
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // straight-line direction of travel
  double length_m = 0.05;
  double bend_m = 0.0;  // sideways bulge at the middle (a circular-ish arc), 0 for a straight line
  // sideways S: wave_m * sin(2 pi x) added at x = along / length_m (one full wave over the stroke), towards
  // direction x down (as bend_m)
  double wave_m = 0.0;
  double speed_m_per_s = 0.05;
  double rate_hz = 1000.0;
  double start_time_s = 0.0;
  Eigen::Vector3d down = -Eigen::Vector3d::UnitY();  // the rays' direction
  double height_m = 0.15;                            // where the rays start above the path
};

struct Stroke {
  StrokeSample first;                 // where the blade first touches
  Eigen::Vector3d blade_direction;    // the direction of travel at the start
  std::vector<StrokeSample> samples;  // the following samples, one per 1/rate_hz
};

Stroke strokeAlongPath(const mesh::SurfaceMesh& surface, const StrokePathOptions& options);

}  // namespace incise::incision
