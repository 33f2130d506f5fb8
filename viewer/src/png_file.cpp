#include "incise/viewer/png_file.h"

#include <csetjmp>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <string_view>

#include <png.h>

#include "incise/core/atomic_file.h"
#include "incise/mesh/surface_mesh.h"

namespace incise::viewer {

namespace {

// libpng's errors jump back to the setjmp in writePng / readPng; the message is kept unless one is there
// already (the AtomicFile's, set by writeToFile).
[[noreturn]] void pngError(png_structp png, png_const_charp message) {
  auto* error = static_cast<std::string*>(png_get_error_ptr(png));
  if (error->empty()) *error = message;
  std::longjmp(png_jmpbuf(png), 1);
}

void pngWarning(png_structp, png_const_charp) {}

void writeToFile(png_structp png, png_bytep data, png_size_t size) {
  auto* file = static_cast<core::AtomicFile*>(png_get_io_ptr(png));
  bool failed = false;
  try {
    *file << std::string_view(reinterpret_cast<const char*>(data), size);
  } catch (const std::exception& e) {
    *static_cast<std::string*>(png_get_error_ptr(png)) = e.what();
    failed = true;
  }
  if (failed) png_error(png, "write failed");  // outside the handler: no C++ frame is jumped over
}

void flushNothing(png_structp) {}

}  // namespace

void writePng(const std::filesystem::path& path, const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::invalid_argument("writePng: " + path.string() + ": the pixels do not match " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) + " RGB");
  core::AtomicFile file(path);
  std::string error;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("writePng: " + path.string() + ": libpng could not start");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("writePng: " + path.string() + ": " + error);
  }
  png_set_write_fn(png, &file, writeToFile, flushNothing);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const std::size_t stride = static_cast<std::size_t>(image.width) * 3;
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(image.rgb.data() + static_cast<std::size_t>(y) * stride));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  file.commit();
}

namespace {

struct MemoryReader {
  std::span<const std::uint8_t> bytes;
  std::size_t offset = 0;
};

void readFromMemory(png_structp png, png_bytep data, png_size_t size) {
  auto* reader = static_cast<MemoryReader*>(png_get_io_ptr(png));
  if (size > reader->bytes.size() - reader->offset) png_error(png, "the file ends early");
  std::memcpy(data, reader->bytes.data() + reader->offset, size);
  reader->offset += size;
}

// The decoded rows as 8-bit RGB (grey copied into all three channels).
void copyRows(png_structp png, png_infop info, RgbImage& image) {
  image.width = static_cast<int>(png_get_image_width(png, info));
  image.height = static_cast<int>(png_get_image_height(png, info));
  const std::size_t channels = png_get_channels(png, info), width = static_cast<std::size_t>(image.width);
  png_bytepp rows = png_get_rows(png, info);
  image.rgb.resize(width * static_cast<std::size_t>(image.height) * 3);
  std::uint8_t* out = image.rgb.data();
  for (int y = 0; y < image.height; ++y)
    for (std::size_t x = 0; x < width; ++x)
      for (std::size_t c = 0; c < 3; ++c) *out++ = rows[y][x * channels + (channels >= 3 ? c : 0)];
}

}  // namespace

RgbImage decodePng(std::span<const std::uint8_t> png_bytes, const std::string& what) {
  if (png_bytes.size() < 8 || png_sig_cmp(png_bytes.data(), 0, 8) != 0)
    throw std::runtime_error("readPng: " + what + ": not a PNG file");
  std::string error;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    throw std::runtime_error("readPng: " + what + ": libpng could not start");
  }
  MemoryReader reader{png_bytes, 0};
  RgbImage image;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw std::runtime_error("readPng: " + what + ": " + error);
  }
  png_set_read_fn(png, &reader, readFromMemory);
  png_read_png(png, info, PNG_TRANSFORM_STRIP_16 | PNG_TRANSFORM_STRIP_ALPHA | PNG_TRANSFORM_EXPAND, nullptr);
  copyRows(png, info, image);
  png_destroy_read_struct(&png, &info, nullptr);
  return image;
}

RgbImage fleshImage() {
  const std::span<const unsigned char> flesh = mesh::detail::wallTexturePng();
  return decodePng(flesh, "the compiled-in flesh image");
}

RgbImage readPng(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("readPng: cannot open " + path.string());
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw std::runtime_error("readPng: cannot read " + path.string());
  return decodePng(bytes, path.string());
}

}  // namespace incise::viewer
