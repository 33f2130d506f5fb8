// PNG pictures through libpng: an 8-bit RGB image written to `path` through core::AtomicFile (to
// path.tmp, then renamed: never a torn file), and read back (the tissue's texture images, tests and checks)
// from a file or from a PNG file's bytes in memory (an image compiled into the program).
// Shapes: rgb holds width x height x 3 bytes, rows top to bottom. Threads: any (distinct files). Cost:
// O(pixels). Failure: std::runtime_error (core::FileError for I/O, naming the path; libpng's message
// otherwise); std::invalid_argument for a buffer of the wrong size.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace incise::viewer {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

void writePng(const std::filesystem::path& path, const RgbImage& image);
// 8- or 16-bit grey, RGB, palette or with alpha (alpha dropped, 16 bits cut to 8). `what` names the bytes
// in the error (a path, "the compiled-in flesh image").
RgbImage readPng(const std::filesystem::path& path);
RgbImage decodePng(std::span<const std::uint8_t> png_bytes, const std::string& what);
// The walls' flesh compiled into the mesh library (mesh::detail::wallTexturePng), decoded.
RgbImage fleshImage();

}  // namespace incise::viewer
