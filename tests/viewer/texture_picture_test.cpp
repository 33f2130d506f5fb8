// Textured tissue in pictures (scene_renderer.cpp's textured program, picture.cpp): the bunny box-mapped
// (mesh::boxTexCoords) and cut, drawn with a checkerboard skin image and a solid blue wall image. The
// skin shows the checkerboard's frequency where the plain colours show none; the wound's walls take the
// wall image (blue, never the plain wall red), near the stroke only. Tagged [pixels] (OpenGL 3.3).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>

#include "incise/viewer/picture.h"
#include "viewer_fixture.h"

using namespace incise;

namespace texture_picture_test {

constexpr int kWidth = 640, kHeight = 400;
constexpr double kTile_m = 0.01;  // one image across a centimetre: 8 x 8 squares of 1.25 mm

// A black-and-white checkerboard of 8 x 8 squares, 8 texels each.
viewer::RgbImage checkerboard() {
  viewer::RgbImage image;
  image.width = image.height = 64;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const std::uint8_t v = ((x / 8 + y / 8) % 2) ? 255 : 20;
      image.rgb.insert(image.rgb.end(), {v, v, v});
    }
  return image;
}

viewer::RgbImage solid(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  viewer::RgbImage image;
  image.width = image.height = 4;
  for (int i = 0; i < 16; ++i) image.rgb.insert(image.rgb.end(), {r, g, b});
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
bool bluePixel(const std::uint8_t* p) { return dominant(p, 2); }
bool plainWallPixel(const std::uint8_t* p) { return dominant(p, 0); }

TEST_CASE("picture: a textured tissue is drawn with its skin image, the walls with their own", "[viewer][pixels]") {
  const auto boxMapped = [](sim::Scenario& s) {
    s.texture.given = s.texture.box_map = true;
    s.texture.tile_m = kTile_m;
  };
  const auto before = test::followRun("bunny-straight", 0.05, {}, boxMapped);
  const auto after = test::followRun("bunny-straight", std::numeric_limits<double>::infinity(), {}, boxMapped);
  REQUIRE(after->world->incisions() == 1);
  REQUIRE(after->mirror.faceTexCoords().size() == after->mirror.faces().size());

  viewer::PictureOptions options;
  options.size = {kWidth, kHeight};
  options.tool.show = false;
  viewer::Camera camera;
  const viewer::RgbImage plain = viewer::renderPicture(after->mirror, after->stroke(), options, &camera);
  options.exact_camera = camera;
  options.textures = viewer::TissueImages{checkerboard(), solid(30, 60, 230)};
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

  // The walls: the wall image's blue, where the plain picture has its wall red; none before the cut.
  std::size_t blue = 0, blue_before = 0, plain_red = 0, textured_red = 0, blue_where_red = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const bool red = plainWallPixel(pixel(plain, x, y));
      plain_red += red;
      textured_red += plainWallPixel(pixel(textured, x, y));
      blue += bluePixel(pixel(textured, x, y));
      blue_before += bluePixel(pixel(textured_before, x, y));
      blue_where_red += red && bluePixel(pixel(textured, x, y));
    }
  INFO("plain wall pixels " << plain_red << ", blue " << blue << ", of them where the plain walls are "
                            << blue_where_red);
  CHECK(plain_red > 300);
  CHECK(textured_red == 0);
  CHECK(blue_before == 0);
  CHECK(blue_where_red > plain_red * 9 / 10);
  CHECK(blue < plain_red * 11 / 10);
}

}  // namespace texture_picture_test
