// The mouse as a scalpel (viewer/src/mouse_scalpel.cpp) and the camera's ray through a pixel: the ray meets
// the tissue under the cursor, the blade goes down along the normal to the wheel's depth with the button
// held and hovers above it without, its edge follows the cursor, and a stroke across an open groove stays on
// the surface instead of falling through to the far side.
#include "incise/viewer/mouse_scalpel.h"

#include <catch2/catch.hpp>

#include "incise/mesh/shapes.h"
#include "incise/sim/geometry_mirror.h"
#include "incise/sim/world.h"
#include "incise/viewer/picture.h"
#include "viewer_fixture.h"

using namespace incise;

namespace {

constexpr int kW = 640, kH = 400;

viewer::Camera topDown() {
  viewer::CameraPose pose;
  pose.target_m = Eigen::Vector3d::Zero();
  pose.eye_dir = Eigen::Vector3d::UnitZ();
  pose.up = Eigen::Vector3d::UnitY();
  pose.distance_m = 0.3;
  return viewer::Camera(pose);
}

// A 10 x 10 x 2 cm box whose top is the plane z = 0, as the viewer has it.
viewer::SurfaceModel box() {
  sim::World world(
      mesh::makeBox(Eigen::AlignedBox3d(Eigen::Vector3d(-0.05, -0.05, -0.02), Eigen::Vector3d(0.05, 0.05, 0.0)), 8),
      sim::WorldOptions{});
  sim::GeometryMirror mirror;
  sim::copyGeometry(world, 0, mirror);
  viewer::SurfaceModel model;
  REQUIRE(model.update(mirror));
  return model;
}

viewer::MouseReading at(double x, double y, bool left, double t_s = 0.0) { return {x, y, kW, kH, left, t_s}; }

}  // namespace

TEST_CASE("mouse_scalpel: the camera's ray through a pixel projects back onto that pixel", "[viewer]") {
  viewer::Camera camera = topDown();
  camera.orbit(40.0, -25.0, kH);
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {320.0, 200.0}, {639.0, 17.0}, {101.5, 399.0}}) {
    const Eigen::Vector3d p = camera.eye_m() + 0.25 * camera.rayThrough(x, y, kW, kH);
    const std::optional<Eigen::Vector2d> back = camera.project(p, kW, kH);
    REQUIRE(back);
    CHECK(back->x() == Approx(x).margin(1e-3));  // project() goes through float matrices
    CHECK(back->y() == Approx(y).margin(1e-3));
  }
}

TEST_CASE("mouse_scalpel: the blade goes in once the way is known, along the normal to the wheel's depth", "[viewer]") {
  const viewer::SurfaceModel tissue = box();
  const viewer::Camera camera = topDown();
  viewer::MouseScalpel scalpel;
  CHECK(scalpel.poses(camera, tissue, at(2.0, 2.0, true)).count == 0);  // off the box: nothing to say yet
  CHECK_FALSE(scalpel.onTissue());

  const auto hover = scalpel.poses(camera, tissue, at(kW / 2.0, kH / 2.0, false, 0.05));
  REQUIRE(hover.count == 1);
  CHECK(hover.pose[0].tip_m.isApprox(Eigen::Vector3d(0.0, 0.0, 0.004), 1e-9));  // above, no button
  CHECK(hover.pose[0].buttons == 0u);
  CHECK(scalpel.poses(camera, tissue, at(kW / 2.0, kH / 2.0, true, 0.1)).count == 0);  // pressed: the way unknown
  CHECK(scalpel.poses(camera, tissue, at(kW / 2.0 + 1.0, kH / 2.0, true, 0.12)).count == 0);  // < 1 mm gone

  const auto in = scalpel.poses(camera, tissue, at(kW / 2.0 + 30.0, kH / 2.0, true, 0.2));  // screen right: +x
  REQUIRE(in.count == 2);
  const devices::PoseSample &entry = in.pose[0], &now = in.pose[1];
  CHECK(entry.time_s == 0.1);  // at the press, when it happened
  CHECK(entry.tip_m.isApprox(Eigen::Vector3d(0.0, 0.0, -0.003), 1e-9));
  CHECK(entry.buttons == 1u);
  CHECK((entry.orientation * Eigen::Vector3d::UnitX()).dot(Eigen::Vector3d::UnitX()) > 0.999);     // the edge: the way
  CHECK((entry.orientation * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitZ(), 1e-9));  // blade: -z in
  CHECK(now.time_s == 0.2);
  CHECK(now.tip_m.x() > 0.001);
  CHECK(now.tip_m.z() == Approx(-0.003));

  scalpel.scroll(2.0);
  CHECK(scalpel.depthM() == Approx(0.004));
  const auto deeper = scalpel.poses(camera, tissue, at(kW / 2.0 + 40.0, kH / 2.0, true, 0.3));
  REQUIRE(deeper.count == 1);
  CHECK(deeper.pose[0].tip_m.z() == Approx(-0.004));
  scalpel.scroll(-100.0);
  CHECK(scalpel.depthM() == 0.0);

  const auto off = scalpel.poses(camera, tissue, at(2.0, 2.0, true, 0.4));  // off the box after a hit: lifted
  REQUIRE(off.count == 1);
  CHECK_FALSE(scalpel.onTissue());
  CHECK(off.pose[0].tip_m.z() > 0.0);
  CHECK(off.pose[0].buttons == 0u);
}

TEST_CASE("mouse_scalpel: the cutting edge follows the cursor's motion over the surface", "[viewer]") {
  const viewer::SurfaceModel tissue = box();
  const viewer::Camera camera = topDown();
  viewer::MouseScalpel scalpel;
  REQUIRE(scalpel.poses(camera, tissue, at(300, 200, true)).count == 0);
  const auto right = scalpel.poses(camera, tissue, at(360, 200, true));  // screen right is world +x here
  REQUIRE(right.count == 2);
  CHECK((right.pose[1].orientation * Eigen::Vector3d::UnitX()).dot(Eigen::Vector3d::UnitX()) > 0.999);
  const auto still = scalpel.poses(camera, tissue, at(360, 200, true));  // resting: the edge stays
  CHECK((still.pose[0].orientation * Eigen::Vector3d::UnitX()).dot(Eigen::Vector3d::UnitX()) > 0.999);
  const auto down_screen = scalpel.poses(camera, tissue, at(360, 260, true));  // screen down is world -y
  CHECK((down_screen.pose[0].orientation * Eigen::Vector3d::UnitX()).dot(-Eigen::Vector3d::UnitY()) > 0.999);
  CHECK_THROWS_WITH(viewer::MouseScalpel(viewer::MouseScalpelOptions{0.05}), Catch::Contains("depth_m"));
}

TEST_CASE("mouse_scalpel: over an open groove the blade stays on the surface, not on the tissue's far side",
          "[viewer]") {
  const auto run = test::followRun("bunny-straight");
  REQUIRE(run->world->incisions() == 1);
  viewer::SurfaceModel tissue;
  REQUIRE(tissue.update(run->mirror));
  REQUIRE(tissue.wallFaces() > 0);
  const std::vector<Eigen::Vector3d> stroke = run->stroke();
  const viewer::Camera camera = viewer::defaultCamera(tissue, stroke, double(kW) / kH, std::nullopt);
  const Eigen::Vector3d middle = stroke[stroke.size() / 2];
  const Eigen::Vector2d p = *camera.project(middle, kW, kH);
  viewer::MouseScalpel scalpel;
  REQUIRE(scalpel.poses(camera, tissue, at(p.x(), p.y() + 40.0, false)).count == 1);  // beside the groove
  const Eigen::Vector3d beside_normal = scalpel.normal();
  int on_surface = 0, poses = 0;
  for (int step = 40; step >= 0; step -= 4) {  // the cursor moves onto the groove's middle, cutting
    poses += scalpel.poses(camera, tissue, at(p.x(), p.y() + step, true)).count;
    on_surface += (scalpel.surfacePointM() - middle).norm() < 0.006;
  }
  CHECK(poses >= 8);  // none until the way is known (1 mm), then the entry and one per reading
  CHECK(on_surface == 11);
  CHECK(scalpel.onTissue());
  CHECK(scalpel.normal().dot(beside_normal) > 0.8);
}
