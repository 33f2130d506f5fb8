// The viewer's camera (viewer/src/camera.cpp): options refused with the value, gestures that keep what they
// should, the stroke framed inside the picture.
#include "incise/viewer/camera.h"

#include <catch2/catch.hpp>

#include <vector>

#include <Eigen/Geometry>

using incise::viewer::Camera;
using incise::viewer::CameraOption;
using incise::viewer::parseCameraOption;
using incise::viewer::parseSizeOption;

TEST_CASE("camera: --camera and --size are parsed, bad values refused with the option and the value", "[viewer]") {
  const CameraOption c = parseCameraOption("30,-20.5,0.12");
  CHECK(c.azimuth_deg == 30.0);
  CHECK(c.elevation_deg == -20.5);
  REQUIRE(c.distance_m);
  CHECK(*c.distance_m == 0.12);
  CHECK_FALSE(parseCameraOption("0,10").distance_m);
  for (const char* bad : {"", "30", "30,", "a,b", "30,20,0,1", "30,90", "30,20,-1", "30,nan"}) {
    INFO(bad);
    CHECK_THROWS_WITH(parseCameraOption(bad), Catch::StartsWith(std::string("--camera '") + bad + "'"));
  }
  CHECK(parseSizeOption("640x480").width == 640);
  CHECK(parseSizeOption("640x480").height == 480);
  for (const char* bad : {"640", "640x", "x480", "640x480x3", "10x480", "640x9000", "64.5x480", "axb"}) {
    INFO(bad);
    CHECK_THROWS_WITH(parseSizeOption(bad), Catch::StartsWith(std::string("--size '") + bad + "'"));
  }
}

TEST_CASE("camera: orbit keeps the distance, pan follows the cursor, zoom scales, reset restores", "[viewer]") {
  const std::vector<Eigen::Vector3d> stroke = {{0.0, 0.05, 0.0}, {0.05, 0.05, 0.01}};
  Camera camera = Camera::frameStroke(stroke, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 1.6, {});
  const Eigen::Vector3d target = camera.pose().target_m;
  const double distance = camera.pose().distance_m;
  camera.orbit(120.0, -40.0, 800);
  CHECK((camera.eye_m() - camera.pose().target_m).norm() == Approx(distance));
  CHECK((camera.pose().target_m - target).norm() < 1e-12);
  CHECK(camera.pose().eye_dir.dot(Eigen::Vector3d::UnitY()) < 0.999);  // it turned
  // The target moves with the cursor: after a pan of (dx, dy) pixels the old target is that far away.
  const Eigen::Vector2d before = *camera.project(target, 1280, 800);
  camera.pan(50.0, 30.0, 800);
  const Eigen::Vector2d after = *camera.project(target, 1280, 800);
  CHECK(after.x() - before.x() == Approx(50.0).margin(0.5));
  CHECK(after.y() - before.y() == Approx(30.0).margin(0.5));
  camera.zoom(2.0);
  CHECK(camera.pose().distance_m == Approx(distance * 0.81));
  camera.reset();
  CHECK((camera.pose().target_m - target).norm() < 1e-12);
  CHECK(camera.pose().distance_m == distance);
}

TEST_CASE("camera: the framed stroke lies inside the picture and fills a good part of it", "[viewer]") {
  std::vector<Eigen::Vector3d> stroke;
  for (int i = 0; i <= 50; ++i) stroke.emplace_back(0.001 * i, 0.03 + 0.0002 * i, -0.002 * i);
  for (const double aspect : {0.5, 1.0, 1.6, 3.0}) {
    const int width = static_cast<int>(800 * aspect), height = 800;
    const Camera camera =
        Camera::frameStroke(stroke, Eigen::Vector3d(0.1, 1.0, 0.2), Eigen::Vector3d::UnitY(), aspect, {});
    Eigen::AlignedBox2d box;
    for (const Eigen::Vector3d& p : stroke) {
      const auto q = camera.project(p, width, height);
      REQUIRE(q);
      box.extend(*q);
    }
    INFO("aspect " << aspect);
    CHECK(box.min().x() > 0.0);
    CHECK(box.min().y() > 0.0);
    CHECK(box.max().x() < width);
    CHECK(box.max().y() < height);
    CHECK(std::max(box.sizes().x() / width, box.sizes().y() / height) > 0.4);
    // Seen from outside: the eye is on the normal's side of the stroke.
    CHECK((camera.eye_m() - camera.pose().target_m).dot(Eigen::Vector3d(0.1, 1.0, 0.2)) > 0.0);
  }
}

TEST_CASE("camera: --camera places the eye at its azimuth, elevation and distance around the framing", "[viewer]") {
  const std::vector<Eigen::Vector3d> stroke = {{0.0, 0.0, 0.0}, {0.02, 0.0, 0.0}};
  const Camera framed = Camera::frameStroke(stroke, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 1.0, {});
  const Camera c = Camera::fromOption(parseCameraOption("90,0,0.2"), framed);
  CHECK((c.pose().target_m - framed.pose().target_m).norm() < 1e-12);
  CHECK((c.eye_m() - (framed.pose().target_m + Eigen::Vector3d(0.2, 0.0, 0.0))).norm() < 1e-9);
  const Camera above = Camera::fromOption(parseCameraOption("0,60"), framed);
  CHECK(above.pose().distance_m == framed.pose().distance_m);
  CHECK(above.pose().eye_dir.y() == Approx(std::sin(60.0 * 3.14159265358979 / 180.0)));
}
