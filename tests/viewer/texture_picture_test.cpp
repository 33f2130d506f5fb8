// Textured tissue in pictures (scene_renderer.cpp's textured program, picture.cpp): the bunny box-mapped
// (mesh::boxTexCoords) and cut, drawn with a black-and-white checkerboard on the skin and a green-and-blue
// one on the walls. The skin shows its checkerboard's frequency where the plain colours show none; the
// wound's walls take their image (its squares alternating along the stroke, never the plain wall red)
// exactly where the plain picture has its walls. Tagged [pixels] (OpenGL 3.3).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "incise/viewer/picture.h"
#include "viewer_fixture.h"

using namespace incise;

namespace texture_picture_test {

constexpr int kWidth = 640, kHeight = 400;
constexpr double kTile_m = 0.01;  // one image across a centimetre: 8 x 8 squares of 1.25 mm

using Rgb = std::array<std::uint8_t, 3>;

// A checkerboard of 8 x 8 squares, 8 texels each, in two colours.
viewer::RgbImage checkerboard(const Rgb& a, const Rgb& b) {
  viewer::RgbImage image;
  image.width = image.height = 64;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const Rgb& c = ((x / 8 + y / 8) % 2) ? a : b;
      image.rgb.insert(image.rgb.end(), c.begin(), c.end());
    }
  return image;
}

const std::uint8_t* pixel(const viewer::RgbImage& image, int x, int y) {
  return &image
              .rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) *
                   3];
}

// Jumps in brightness of more than 40 between neighbours along each of a few rows through the middle.
int brightnessJumps(const viewer::RgbImage& image) {
  int jumps = 0;
  for (int y = kHeight / 2 - 40; y <= kHeight / 2 + 40; y += 20)
    for (int x = 1; x < kWidth; ++x) {
      const auto lum = [&](int at) {
        const std::uint8_t* p = pixel(image, at, y);
        return (p[0] + p[1] + p[2]) / 3;
      };
      jumps += std::abs(lum(x) - lum(x - 1)) > 40;
    }
  return jumps;
}

// Channel c well above the other two (the plain walls' red, the wall image's blue; never the skin, the
// checkerboard's greys or the background).
bool dominant(const std::uint8_t* p, int c) {
  return p[c] > 40 && p[(c + 1) % 3] < 0.5 * p[c] && p[(c + 2) % 3] < 0.5 * p[c];
}
bool plainWallPixel(const std::uint8_t* p) { return dominant(p, 0); }
// The wall image's squares: 1 green, 2 blue, 0 neither.
int wallSquare(const std::uint8_t* p) { return dominant(p, 1) ? 1 : dominant(p, 2) ? 2 : 0; }
// The wall image at all: little red against its green and blue (where the wall is seen edge-on, its
// mipmaps mix the squares into cyan).
bool wallImagePixel(const std::uint8_t* p) {
  const int cool = std::max(p[1], p[2]);
  return cool > 20 && p[0] < 0.5 * cool;  // the walls in shadow too (the ambient 22%)
}

// Along each row, changes between the wall image's two colours from one wall pixel to the next (at most
// two pixels apart).
int wallSquareChanges(const viewer::RgbImage& image) {
  int changes = 0;
  for (int y = 0; y < kHeight; ++y) {
    int last = 0, last_x = -10;
    for (int x = 0; x < kWidth; ++x) {
      const int square = wallSquare(pixel(image, x, y));
      if (square == 0) continue;
      changes += last != 0 && square != last && x - last_x <= 2;
      last = square, last_x = x;
    }
  }
  return changes;
}

void boxMapped(sim::Scenario& s) {
  s.texture.given = s.texture.box_map = true;
  s.texture.tile_m = kTile_m;
}

TEST_CASE("picture: a textured tissue is drawn with its skin image, the walls with their own", "[viewer][pixels]") {
  test::FollowOptions f;
  f.edit_scenario = boxMapped;
  f.stop_after_s = 0.05;
  const auto before = test::followRun("bunny-straight", f);
  f.stop_after_s = std::numeric_limits<double>::infinity();
  const auto after = test::followRun("bunny-straight", f);
  REQUIRE(after->world->incisions() == 1);
  REQUIRE(after->mirror.faceTexCoords().size() == after->mirror.faces().size());

  viewer::PictureOptions options;
  options.size = {kWidth, kHeight};
  options.tool.show = false;
  viewer::Camera camera;
  const viewer::RgbImage plain = viewer::renderPicture(after->mirror, after->stroke(), options, &camera);
  options.exact_camera = camera;
  options.textures =
      viewer::TissueImages{{checkerboard({255, 255, 255}, {20, 20, 20})}, checkerboard({30, 220, 60}, {30, 60, 230})};
  const viewer::RgbImage textured_before = viewer::renderPicture(before->mirror, after->stroke(), options);
  const viewer::RgbImage textured = viewer::renderPicture(after->mirror, after->stroke(), options);
  if (const char* keep = std::getenv("INCISE_KEEP_PICTURES")) {
    viewer::writePng(std::filesystem::path(keep) / "textured-plain.png", plain);
    viewer::writePng(std::filesystem::path(keep) / "textured-after.png", textured);
  }

  // The skin: the checkerboard's squares (about 20 pixels each at this framing) against smooth shading.
  const int plain_jumps = brightnessJumps(plain), textured_jumps = brightnessJumps(textured);
  INFO("brightness jumps: plain " << plain_jumps << ", textured " << textured_jumps);
  CHECK(plain_jumps <= 20);  // the wound's edges
  CHECK(textured_jumps > 100);

  // The walls: the wall image's squares where the plain picture has its wall red; none before the cut.
  std::size_t wall = 0, wall_before = 0, plain_red = 0, textured_red = 0, wall_where_red = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const bool red = plainWallPixel(pixel(plain, x, y));
      const bool square = wallImagePixel(pixel(textured, x, y));
      plain_red += red;
      textured_red += plainWallPixel(pixel(textured, x, y));
      wall += square;
      wall_before += wallImagePixel(pixel(textured_before, x, y));
      wall_where_red += red && square;
    }
  const int changes = wallSquareChanges(textured);
  INFO("plain wall pixels " << plain_red << ", wall image's " << wall << ", of them where the plain walls are "
                            << wall_where_red << "; square changes along rows " << changes);
  CHECK(plain_red > 300);
  CHECK(textured_red == 0);
  CHECK(wall_before == 0);
  CHECK(wall_where_red > plain_red * 9 / 10);
  CHECK(wall < plain_red * 11 / 10);
  // Along the 5 cm stroke the wall image repeats every centimetre: 8 squares a repeat.
  CHECK(changes > 20);
}

TEST_CASE("picture: each material's faces are drawn with its own image", "[viewer][pixels]") {
  test::FollowOptions f;
  f.edit_scenario = boxMapped;
  f.edit_tissue = test::twoMaterials;
  const auto run = test::followRun("bunny-straight", f);
  REQUIRE(run->world->tissue().materials().size() == 2);
  viewer::PictureOptions options;
  options.size = {kWidth, kHeight};
  options.tool.show = false;
  options.camera = viewer::parseCameraOption("0,10,0.25");  // the whole bunny from the front
  const auto solid = [](const Rgb& c) {  // 2 x 3 texels: the skins' layers are resampled to a common size
    viewer::RgbImage image;
    image.width = 2, image.height = 3;
    for (int i = 0; i < 6; ++i) image.rgb.insert(image.rgb.end(), c.begin(), c.end());
    return image;
  };
  options.textures =
      viewer::TissueImages{{solid({230, 220, 30}), checkerboard({200, 30, 200}, {120, 20, 120})}, solid({30, 60, 230})};
  const viewer::RgbImage two = viewer::renderPicture(run->mirror, run->stroke(), options);
  options.textures->skins.resize(1);  // one image: every face takes it
  const viewer::RgbImage one = viewer::renderPicture(run->mirror, run->stroke(), options);
  const auto count = [](const viewer::RgbImage& image) {
    std::size_t yellow = 0, magenta = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const std::uint8_t* p = pixel(image, x, y);
        yellow += p[0] > 40 && p[1] > 0.7 * p[0] && p[2] < 0.4 * p[0];
        magenta += p[0] > 40 && p[2] > 0.7 * p[0] && p[1] < 0.4 * p[0];
      }
    return std::pair{yellow, magenta};
  };
  const auto [yellow2, magenta2] = count(two);
  const auto [yellow1, magenta1] = count(one);
  INFO("two images: yellow " << yellow2 << ", magenta " << magenta2 << "; one: yellow " << yellow1 << ", magenta "
                             << magenta1);
  CHECK(yellow2 > 5000);
  CHECK(magenta2 > 5000);
  CHECK(magenta1 == 0);
  CHECK(yellow1 > yellow2 + magenta2 * 9 / 10);  // the right half yellow too
  // Images the renderer refuses, naming why.
  options.textures->skins.clear();
  CHECK_THROWS_WITH(viewer::renderPicture(run->mirror, run->stroke(), options), Catch::Contains("no skin image"));
  options.textures->skins = {solid({230, 220, 30})};
  options.textures->wall.rgb.pop_back();
  CHECK_THROWS_WITH(viewer::renderPicture(run->mirror, run->stroke(), options),
                    Catch::Contains("do not match its 2x3 RGB size"));
}

}  // namespace texture_picture_test

namespace texture_picture_test {

TEST_CASE("picture: the walls' compiled-in flesh decodes to the shipped image, pixel for pixel", "[viewer]") {
  const viewer::RgbImage flesh = viewer::fleshImage();
  const viewer::RgbImage shipped = viewer::readPng(INCISE_SCENARIOS_DIR "/textures/flesh.png");
  CHECK(flesh.width == shipped.width);
  CHECK(flesh.height == shipped.height);
  CHECK(flesh.rgb == shipped.rgb);
  CHECK(flesh.width > 1);
}

}  // namespace texture_picture_test
