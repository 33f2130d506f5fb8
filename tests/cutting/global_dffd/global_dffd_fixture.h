// What the global DFFD's tests share: the upright bar they move models through and the lattice's options.
#pragma once

#include <string>

#include "incise/global_dffd/global_dffd.h"
#include "incise/mesh/shapes.h"

namespace incise::global_dffd::fixture {

// A vertical bar: a cylinder of radius 5 mm along z through the scene, centred at x = x_m, y = 0.
inline Obstacle bar(double x_m = 0.0, const std::string& name = "bar") {
  return {name, mesh::makeCylinder(Eigen::Vector3d(x_m, 0.0, -0.03), Eigen::Vector3d(0.0, 0.0, 0.06), 0.005, 48, 4, 2)};
}

// 24 x 16 x 8 controls, 2 cm margin, a kernel 6 spacings wide, 0.5 mm clearance.
inline GlobalDffdOptions options() {
  GlobalDffdOptions o;
  o.controls = {24, 16, 8};
  o.margin_m = 0.02;
  o.kernel_width = 6.0;
  o.clearance_m = 0.0005;
  return o;
}

}  // namespace incise::global_dffd::fixture
