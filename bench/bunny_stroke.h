// The benchmarks' stroke: 5 cm along +x over the bunny's back (start (-12, 0, 15) mm, rays down -y), at
// StrokePathOptions' default speed and rate (5 cm/s at 1 kHz: 1001 samples) — the same stroke as
// `incise cut`'s default. One definition for the incision and tet benchmarks; and the planar texture map the
// incision and viewer benchmarks' `--textured` give the bunny.
#pragma once

#include <Eigen/Core>

#include "incise/incision/stroke_path.h"

namespace incise::bench {

inline incision::Stroke bunnyBackStroke(const mesh::SurfaceMesh& mesh) {
  incision::StrokePathOptions path;
  path.start_m = Eigen::Vector3d(-0.012, 0.0, 0.015);
  path.direction = Eigen::Vector3d::UnitX();
  path.length_m = 0.05;
  return incision::strokeAlongPath(mesh, path);
}

// A planar texture map on every corner of `mesh` (u, v = x, z over 10 cm, centred): the benchmarks' textured
// tissue, so every face the cut makes carries texture coordinates.
inline void mapPlanar(mesh::SurfaceMesh& mesh) {
  mesh.addTexCoords();
  for (const auto h : mesh.mesh().halfedges()) {
    if (mesh.mesh().is_boundary(h)) continue;
    const auto p = mesh.mesh().point(mesh.mesh().to_vertex_handle(h));
    mesh.setTexCoord(h, Eigen::Vector2d(p[0] / 0.1 + 0.5, p[2] / 0.1 + 0.5));
  }
}

}  // namespace incise::bench
