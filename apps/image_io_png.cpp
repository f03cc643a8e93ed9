#include <png.h>

#include <cstdio>

#include "apps/image_io.h"
#include "core/error.h"

namespace mpvg {

namespace {

void write(const std::string& path, int width, int height, const void* data, bool sixteen) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(width);
  img.height = static_cast<png_uint_32>(height);
  img.format = sixteen ? PNG_FORMAT_RGBA | PNG_FORMAT_FLAG_LINEAR : PNG_FORMAT_RGBA;
  // libpng's 16-bit "linear" format means premultiplied linear light; write
  // 16-bit data through the low-level API instead.
  if (sixteen) {
    FILE* f = path == "-" ? stdout : std::fopen(path.c_str(), "wb");
    if (!f) throw Error("cannot write '" + path + "'");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
      png_destroy_write_struct(&png, &info);
      if (f != stdout) std::fclose(f);
      throw Error("cannot write '" + path + "'");
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, width, height, 16, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_set_swap(png);  // our uint16 are little-endian in memory
    const uint16_t* p = static_cast<const uint16_t*>(data);
    for (int y = 0; y < height; y++) png_write_row(png, reinterpret_cast<png_const_bytep>(p + size_t(y) * width * 4));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (f != stdout) std::fclose(f);
    return;
  }
  const int ok = path == "-" ? png_image_write_to_stdio(&img, stdout, 0, data, 0, nullptr)
                             : png_image_write_to_file(&img, path.c_str(), 0, data, 0, nullptr);
  if (!ok) throw Error("cannot write '" + path + "': " + img.message);
}

}  // namespace

void write_png_rgba8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba) {
  write(path, width, height, rgba.data(), false);
}

void write_png_rgba16(const std::string& path, int width, int height, const std::vector<uint16_t>& rgba) {
  write(path, width, height, rgba.data(), true);
}

std::string image_io_library() { return std::string("libpng ") + PNG_LIBPNG_VER_STRING; }

}  // namespace mpvg
