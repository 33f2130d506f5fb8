#include "tissue_images.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "incise/mesh/surface_mesh.h"
#include "incise/viewer/png_file.h"

namespace incise::apps {

namespace {

// The statement of `material` that starts with `keyword`, split into its tokens after the keyword.
std::vector<std::string> statement(const mesh::Material& material, const std::string& keyword) {
  for (const std::string& line : material.statements) {
    std::istringstream tokens(line);
    std::string first, token;
    tokens >> first;
    if (first != keyword) continue;
    std::vector<std::string> rest;
    while (tokens >> token) rest.push_back(token);
    return rest;
  }
  return {};
}

viewer::RgbImage plainColour(const std::array<float, 3>& rgb) {
  viewer::RgbImage image;
  image.width = image.height = 1;
  for (const float c : rgb)
    image.rgb.push_back(
        static_cast<std::uint8_t>(std::isfinite(c) ? std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f) : 0));
  return image;
}

viewer::RgbImage readImage(const char* command, const std::filesystem::path& path, const char* what) {
  try {
    return viewer::readPng(path);
  } catch (const std::exception& e) {
    failWith(command, std::string("the ") + what + " image: " + e.what());
  }
}

// A material's image: its map_Kd (the path is its last token), else its Kd colour, else the plain skin.
// A map that cannot be read is the mesh file's problem, not the run's: warned about, the colour drawn.
viewer::RgbImage materialImage(const char* command, const mesh::Material& material) {
  const std::vector<std::string> map = statement(material, "map_Kd");
  if (!map.empty()) {
    try {
      return viewer::readPng(map.back());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "incise %s: warning: material %s is drawn in its colour: %s\n", command,
                   material.name.c_str(), e.what());
    }
  }
  const std::vector<std::string> kd = statement(material, "Kd");
  if (kd.size() >= 3) {
    try {
      return plainColour({std::stof(kd[0]), std::stof(kd[1]), std::stof(kd[2])});
    } catch (const std::exception&) {  // not numbers: the plain skin
    }
  }
  return plainColour(viewer::kSkinColour);
}

}  // namespace

std::optional<viewer::TissueImages> tissueImages(const char* command, const sim::Scenario& scenario,
                                                 const mesh::SurfaceMesh& tissue) {
  if (!tissue.hasTexCoords()) return std::nullopt;
  const sim::TextureSpec& spec = scenario.texture;
  viewer::TissueImages images;
  if (!spec.skin_image.empty()) {
    images.skins.push_back(readImage(command, spec.skin_image, "skin"));
  } else if (tissue.hasMaterials() && !tissue.materials().empty()) {
    for (const mesh::Material& material : tissue.materials()) images.skins.push_back(materialImage(command, material));
  } else {
    images.skins.push_back(plainColour(viewer::kSkinColour));
  }
  if (!spec.wall_image.empty()) {
    images.wall = readImage(command, spec.wall_image, "wall");
  } else {
    images.wall = viewer::fleshImage();
  }
  return images;
}

}  // namespace incise::apps
