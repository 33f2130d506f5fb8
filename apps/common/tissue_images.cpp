#include "tissue_images.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "incise/mesh/surface_mesh.h"
#include "incise/viewer/png_file.h"

namespace incise::apps {

namespace {

// The path of the first material's `map_Kd`, or empty.
std::filesystem::path diffuseMap(const mesh::SurfaceMesh& tissue) {
  if (!tissue.hasMaterials()) return {};
  for (const mesh::Material& material : tissue.materials()) {
    for (const std::string& statement : material.statements) {
      std::istringstream tokens(statement);
      std::string keyword, token, last;
      tokens >> keyword;
      while (tokens >> token) last = token;
      if (keyword == "map_Kd" && !last.empty()) return last;
    }
  }
  return {};
}

viewer::RgbImage plainSkin() {
  viewer::RgbImage image;
  image.width = image.height = 1;
  for (const float c : viewer::kSkinColour) image.rgb.push_back(static_cast<std::uint8_t>(std::lround(c * 255.0f)));
  return image;
}

viewer::RgbImage readImage(const char* command, const std::filesystem::path& path, const char* what) {
  try {
    return viewer::readPng(path);
  } catch (const std::exception& e) {
    failWith(command, std::string("the ") + what + " image: " + e.what());
  }
}

}  // namespace

std::optional<viewer::TissueImages> tissueImages(const char* command, const LoadedScenario& run) {
  if (!run.world->tissue().hasTexCoords()) return std::nullopt;
  const sim::TextureSpec& spec = run.scenario.texture;
  viewer::TissueImages images;
  const std::filesystem::path map = diffuseMap(run.world->tissue());
  if (!spec.skin_image.empty()) {
    images.skin = readImage(command, spec.skin_image, "skin");
  } else if (!map.empty()) {
    try {  // the mesh's own material: a missing or broken image is the file's problem, not the run's
      images.skin = viewer::readPng(map);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "incise %s: warning: the skin is drawn in its plain colour: %s\n", command, e.what());
      images.skin = plainSkin();
    }
  } else {
    images.skin = plainSkin();
  }
  if (!spec.wall_image.empty()) {
    images.wall = readImage(command, spec.wall_image, "wall");
  } else {
    const auto flesh = mesh::detail::wallTexturePng();
    images.wall = viewer::decodePng({flesh.data(), flesh.size()}, "the compiled-in flesh image");
  }
  return images;
}

}  // namespace incise::apps
