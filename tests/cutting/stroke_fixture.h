// Test fixtures for incisions: the bunny in metres (optionally Loop-subdivided) and a stroke across its back.
#pragma once

#include "incise/incision/stroke_path.h"
#include "incise/mesh/surface_mesh.h"

namespace incise::incision::testing {

// The bunny file is in centimetres (about 10 units across): 0.01 makes it a 10 cm bunny in metres.
inline mesh::SurfaceMesh bunny(int subdivisions = 0) {
  mesh::SurfaceMesh mesh = mesh::loadSurfaceMesh(INCISE_SCENARIOS_DIR "/meshes/bunny.obj", 0.01);
  return subdivisions > 0 ? mesh::subdivided(mesh, subdivisions) : mesh;
}

// A stroke over the bunny's back (from x = -12 mm, z = 15 mm, along +x), 1 kHz at 5 cm/s.
inline Stroke backStroke(const mesh::SurfaceMesh& mesh, double length_m = 0.05, double bend_m = 0.0,
                         Eigen::Vector3d start_m = Eigen::Vector3d(-0.012, 0.0, 0.015),
                         Eigen::Vector3d direction = Eigen::Vector3d::UnitX(), double start_time_s = 0.0) {
  StrokePathOptions options;
  options.start_m = start_m;
  options.direction = direction;
  options.length_m = length_m;
  options.bend_m = bend_m;
  options.start_time_s = start_time_s;
  return strokeAlongPath(mesh, options);
}

}  // namespace incise::incision::testing
