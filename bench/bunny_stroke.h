// The benchmarks' stroke: 5 cm along +x over the bunny's back (start (-12, 0, 15) mm, rays down -y), at
// StrokePathOptions' default speed and rate (5 cm/s at 1 kHz: 1001 samples) — the same stroke as
// `incise cut`'s default. One definition for the incision and tet benchmarks.
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

}  // namespace incise::bench
