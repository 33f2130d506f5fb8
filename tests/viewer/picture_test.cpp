// Pictures that are looked at (viewer/src/picture.cpp, scene_renderer.cpp): the bunny before and after its
// cut, with the same camera (its surface, and a tet bunny's tet boundary). The wall colour appears near the stroke's projection and nowhere far from it,
// along most of the stroke; away from the stroke both pictures agree. Tagged [pixels]: they need OpenGL 3.3
// (CTest runs them under xvfb-run, and once more through EGL without a display).
#include "incise/viewer/picture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>

#include "support/temp_dir.h"
#include "viewer_fixture.h"

using namespace incise;

namespace {

constexpr int kWidth = 640, kHeight = 400;

// The wall's colour, shaded: strongly red (the skin's green is 0.77 of its red, the background grey).
bool wallPixel(const viewer::RgbImage& image, int x, int y) {
  const std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x)) * 3];
  return p[0] > 50 && p[1] < 0.45 * p[0] && p[2] < 0.45 * p[0];
}

// Distance in pixels from (x, y) to the polyline.
double distanceTo(const std::vector<Eigen::Vector2d>& line, double x, double y) {
  double best = 1e30;
  const Eigen::Vector2d p(x, y);
  for (std::size_t i = 1; i < line.size(); ++i) {
    const Eigen::Vector2d a = line[i - 1], ab = line[i] - a;
    const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - p).norm());
  }
  return best;
}

// The scenario `name` before its cut and at its end, with the same camera (the surface, or the tets'
// boundary): the wall colour near the stroke's projection only, along most of it; elsewhere the two agree.
// Returns the picture after the cut.
viewer::RgbImage requireWallsAlongStroke(const char* name, bool tets) {
  const auto before = test::followRun(name, 0.05);  // the tool has not touched the tissue yet
  const auto after = test::followRun(name);
  REQUIRE(before->world->incisions() == 0);
  REQUIRE(after->world->incisions() == 1);
  viewer::PictureOptions options;
  options.size = {kWidth, kHeight};
  options.tool.show = false;
  options.tets = tets;
  const std::vector<Eigen::Vector3d> stroke = after->stroke();
  viewer::Camera camera;
  const viewer::RgbImage b = viewer::renderPicture(before->mirror, stroke, options, &camera);
  options.exact_camera = camera;
  const viewer::RgbImage a = viewer::renderPicture(after->mirror, stroke, options);

  std::vector<Eigen::Vector2d> line;
  for (const Eigen::Vector3d& p : stroke) line.push_back(*camera.project(p, kWidth, kHeight));
  const double stroke_px = (line.back() - line.front()).norm();
  REQUIRE(stroke_px > 0.5 * kWidth);  // the default camera frames the incision
  // The wound lies within its depth and opening of the stroke's tips (in pixels at the stroke's scale);
  // "far" is half as far again.
  const auto& incision = after->scenario.world.cutter.incision;
  const double px_per_m = stroke_px / (stroke.back() - stroke.front()).norm();
  const double near_px = (incision.depth_m + incision.opening_m) * px_per_m, far_px = 1.5 * near_px;
  INFO("near " << near_px << " px, far " << far_px << " px");

  std::size_t wall_after = 0, wall_before = 0, wall_far = 0, far = 0, far_differing = 0;
  double wall_max_px = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const double d = distanceTo(line, x + 0.5, y + 0.5);
      wall_before += wallPixel(b, x, y);
      if (wallPixel(a, x, y)) ++wall_after, wall_far += d > near_px, wall_max_px = std::max(wall_max_px, d);
      if (d > far_px) {
        ++far;
        const std::size_t i = (static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x)) * 3;
        for (int c = 0; c < 3; ++c) far_differing += std::abs(int(a.rgb[i + c]) - int(b.rgb[i + c])) > 2;
      }
    }
  CHECK(wall_before == 0);
  CHECK(wall_after > 300);
  CHECK(wall_far == 0);
  UNSCOPED_INFO("wall pixels at most " << wall_max_px << " px from the stroke");
  if (const char* keep = std::getenv("INCISE_KEEP_PICTURES")) {  // for a person to look at
    const std::string prefix = std::string(name) + (tets ? "-tets-" : "-");
    viewer::writePng(std::filesystem::path(keep) / (prefix + "before.png"), b);
    viewer::writePng(std::filesystem::path(keep) / (prefix + "after.png"), a);
  }
  CHECK(far > static_cast<std::size_t>(kWidth * kHeight / 3));
  CHECK(far_differing == 0);
  // Along the stroke: most of its projection has wall pixels close by.
  int samples = 0, covered = 0;
  for (double t = 0.05; t <= 0.95; t += 0.05, ++samples) {
    const Eigen::Vector2d p = line[static_cast<std::size_t>(t * static_cast<double>(line.size() - 1))];
    bool near = false;
    for (int y = std::max(0, int(p.y()) - 15); y < std::min(kHeight, int(p.y()) + 15) && !near; ++y)
      for (int x = std::max(0, int(p.x()) - 15); x < std::min(kWidth, int(p.x()) + 15) && !near; ++x)
        near = wallPixel(a, x, y);
    covered += near;
  }
  CHECK(covered >= samples * 8 / 10);
  return a;
}

}  // namespace

TEST_CASE("picture: the cut shows its walls along the stroke only, elsewhere before and after agree",
          "[viewer][pixels]") {
  const viewer::RgbImage a = requireWallsAlongStroke("bunny-straight", false);
  test::TempDir dir;
  viewer::writePng(dir.path() / "after.png", a);
  const viewer::RgbImage back = viewer::readPng(dir.path() / "after.png");
  CHECK(back.width == kWidth);
  CHECK(back.height == kHeight);
  CHECK(back.rgb == a.rgb);
  CHECK_FALSE(std::filesystem::exists(dir.path() / "after.png.tmp"));
}

TEST_CASE("picture: the tets' boundary shows the wound's walls along the stroke only", "[viewer][pixels][tets]") {
  requireWallsAlongStroke("bunny-tets", true);
}

TEST_CASE("picture: the scalpel, contact point and force vector are drawn where the tool is", "[viewer][pixels]") {
  const auto run = test::followRun("bunny-straight", 0.6);  // mid-stroke, in contact
  viewer::PictureOptions options;
  options.size = {kWidth, kHeight};
  options.camera = viewer::parseCameraOption("90,30");  // from the side: the blade and handle in profile
  const viewer::RgbImage without = viewer::renderPicture(run->mirror, run->stroke(), options);
  const auto& h = run->report;  // the tool's last pose
  (void)h;
  const devices::PoseSample* last = nullptr;
  for (const auto& p : run->poses)
    if (p.time_s <= run->poses.front().time_s + 0.6) last = &p;
  REQUIRE(last);
  options.tool.show = true;
  options.tool.tip_m = last->tip_m;
  options.tool.orientation = last->orientation;
  options.tool.contact = true;
  options.tool.contact_m = last->tip_m;
  options.tool.force_N = Eigen::Vector3d(0.0, 2.0, 0.0);
  viewer::Camera camera;
  const viewer::RgbImage with = viewer::renderPicture(run->mirror, run->stroke(), options, &camera);
  const Eigen::Vector2d tip = *camera.project(last->tip_m, kWidth, kHeight);
  const Eigen::Vector3d handle_end = last->tip_m + last->orientation * Eigen::Vector3d(0, 0, 0.03);
  const Eigen::Vector2d handle = *camera.project(handle_end, kWidth, kHeight);
  std::size_t changed = 0, changed_far = 0, green = 0;
  const std::vector<Eigen::Vector2d> axis = {tip, handle};
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x)) * 3;
      const bool differs = with.rgb[i] != without.rgb[i] || with.rgb[i + 1] != without.rgb[i + 1];
      const double d = std::min(distanceTo(axis, x, y), (Eigen::Vector2d(x, y) - tip).norm());
      changed += differs;
      if (differs && d > 60.0) ++changed_far;
      green += with.rgb[i + 1] > 150 && with.rgb[i] < 0.5 * with.rgb[i + 1] && with.rgb[i + 2] < 0.6 * with.rgb[i + 1];
    }
  CHECK(changed > 200);
  CHECK(changed_far == 0);
  CHECK(green > 5);  // the force vector
}
