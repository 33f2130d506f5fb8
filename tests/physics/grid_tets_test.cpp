// Tests for physics/src/grid_tets.cpp: the regular tet grid is conforming, positive, fills its box, and is
// accepted by the tet cutter.
#include "incise/physics/grid_tets.h"

#include <stdexcept>

#include <catch2/catch.hpp>

#include "incise/tets/tet_mesh.h"

namespace incise::physics {
namespace {

TEST_CASE("grid_tets: SOFA's 8 x 26 x 8 grid has 7,350 positive tets filling the box, conforming", "[physics]") {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.007, 0.0, -0.025), Eigen::Vector3d(0.007, 0.014, 0.025));
  const tets::TetMesh mesh = gridTets(box, Eigen::Vector3i(7, 7, 25));
  CHECK(mesh.nodes_m.size() == 8 * 8 * 26);
  CHECK(mesh.tets.size() == 7350);
  CHECK(tets::volume(mesh) == Approx(box.volume()).epsilon(1e-12));
  for (int t = 0; t < static_cast<int>(mesh.tets.size()); ++t) REQUIRE(tets::tetVolume(mesh, t) > 0);
  const tets::TetCheck check = tets::checkConforming(mesh);
  INFO(check.first_problem);
  CHECK(check.conforming);
  // The box's surface: 2 triangles per cell face on the outside.
  CHECK(check.boundary_faces == 2 * 2 * (7 * 7 + 7 * 25 + 7 * 25));
  CHECK(mesh.nodes_m[1 + 8 * (2 + 8 * 3)].isApprox(box.min() + Eigen::Vector3d(0.002, 0.004, 0.006)));
}

TEST_CASE("grid_tets: bad cells and boxes are refused", "[physics]") {
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  CHECK_THROWS_AS(gridTets(box, Eigen::Vector3i(0, 1, 1)), std::invalid_argument);
  CHECK_THROWS_AS(
      gridTets(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 1)), Eigen::Vector3i::Ones()),
      std::invalid_argument);
}

}  // namespace
}  // namespace incise::physics
