#include "incise/viewer/png_file.h"

#include <csetjmp>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include <png.h>

#include "incise/core/atomic_file.h"

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

RgbImage readPng(const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!in) throw std::runtime_error("readPng: cannot open " + path.string());
  std::string error;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    throw std::runtime_error("readPng: " + path.string() + ": libpng could not start");
  }
  RgbImage image;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw std::runtime_error("readPng: " + path.string() + ": " + error);
  }
  png_init_io(png, in.get());
  png_read_png(png, info, PNG_TRANSFORM_STRIP_16 | PNG_TRANSFORM_STRIP_ALPHA | PNG_TRANSFORM_EXPAND, nullptr);
  image.width = static_cast<int>(png_get_image_width(png, info));
  image.height = static_cast<int>(png_get_image_height(png, info));
  const int channels = png_get_channels(png, info);
  png_bytepp rows = png_get_rows(png, info);
  image.rgb.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c)
        image.rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) *
                      3 +
                  static_cast<std::size_t>(c)] = rows[y][x * channels + (channels >= 3 ? c : 0)];
  png_destroy_read_struct(&png, &info, nullptr);
  return image;
}

}  // namespace incise::viewer
