// Test fixtures for incisions: the bunny in metres (optionally Loop-subdivided), a stroke across its back and a
// planar texture map.
#pragma once

#include <limits>

#include <Eigen/Core>

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

// A planar texture map, uv = kPlanarMap p + kPlanarOffset (p in metres, uv near (5, 7): never a default 0),
// plus `seam_shift` on the faces whose centroid lies at x > seam_x_m (a texture seam along the edges there).
inline const Eigen::Matrix<double, 2, 3> kPlanarMap =
    (Eigen::Matrix<double, 2, 3>() << 10.0, 2.0, 0.0, -1.0, 3.0, 10.0).finished();
inline const Eigen::Vector2d kPlanarOffset(5.0, 7.0);

inline Eigen::Vector2d planar(const Eigen::Vector3d& p) { return kPlanarMap * p + kPlanarOffset; }

inline void mapPlanar(mesh::SurfaceMesh& s, double seam_x_m = std::numeric_limits<double>::infinity(),
                      const Eigen::Vector2d& seam_shift = Eigen::Vector2d::Zero()) {
  s.addTexCoords();
  mesh::TriMesh& m = s.mesh();
  for (const auto f : m.faces()) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto v : m.fv_range(f)) centroid += mesh::toEigen(m.point(v)) / 3.0;
    const Eigen::Vector2d shift = centroid.x() > seam_x_m ? seam_shift : Eigen::Vector2d::Zero();
    for (const auto h : m.fh_range(f)) s.setTexCoord(h, planar(mesh::toEigen(m.point(m.to_vertex_handle(h)))) + shift);
  }
}

}  // namespace incise::incision::testing
