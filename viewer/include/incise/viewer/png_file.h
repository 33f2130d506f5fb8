// PNG pictures through libpng: an 8-bit RGB image written to `path` through core::AtomicFile (to
// path.tmp, then renamed: never a torn file), and read back (for tests and checks).
// Shapes: rgb holds width x height x 3 bytes, rows top to bottom. Threads: any (distinct files). Cost:
// O(pixels). Failure: std::runtime_error (core::FileError for I/O, naming the path; libpng's message
// otherwise); std::invalid_argument for a buffer of the wrong size.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace incise::viewer {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

void writePng(const std::filesystem::path& path, const RgbImage& image);
RgbImage readPng(const std::filesystem::path& path);  // 8-bit RGB or RGBA files (alpha dropped)

}  // namespace incise::viewer
