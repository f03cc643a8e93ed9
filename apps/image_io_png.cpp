#include <png.h>

#include <cstdint>
#include <cstdio>

#include "apps/image_io.h"
#include "core/error.h"

namespace mpvg {

namespace {

// Writes rows of RGBA, 8 or 16 bits per channel; an image that is opaque
// throughout is written as RGB (a quarter less to compress, as pdftoppm and
// mutool write pages). Compression is tuned for speed (batches of pages):
// zlib level 2 and the sub and up row filters cost about a third of
// libpng's defaults and files stay within a few percent of their size on
// rendered pages (BENCHMARKS.md).
void write(const std::string& path, int width, int height, const void* data, bool sixteen) {
  const size_t n = size_t(width) * height;
  bool opaque = true;
  if (sixteen) {
    const uint16_t* p = static_cast<const uint16_t*>(data);
    for (size_t i = 0; i < n && opaque; i++) opaque = p[4 * i + 3] == 65535;
  } else {
    const uint8_t* p = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < n && opaque; i++) opaque = p[4 * i + 3] == 255;
  }
  FILE* f = path == "-" ? stdout : std::fopen(path.c_str(), "wb");
  if (!f) throw Error("cannot write '" + path + "'");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    if (f != stdout) std::fclose(f);
    throw Error("cannot write '" + path + "'");
  }
  png_init_io(png, f);
  png_set_compression_level(png, 2);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB | PNG_FILTER_UP);
  png_set_IHDR(png, info, width, height, sixteen ? 16 : 8, opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGBA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (opaque) png_set_filler(png, 0, PNG_FILLER_AFTER);  // drops the alpha byte of every pixel
  if (sixteen) png_set_swap(png);                        // our uint16 are little-endian in memory
  const size_t row = size_t(width) * 4 * (sixteen ? 2 : 1);
  const png_const_bytep p = static_cast<png_const_bytep>(data);
  for (int y = 0; y < height; y++) png_write_row(png, p + size_t(y) * row);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (f != stdout && std::fclose(f) != 0) throw Error("cannot write '" + path + "'");
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
