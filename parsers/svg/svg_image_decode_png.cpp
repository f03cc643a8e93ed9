// PNG images decoded by libpng (every build; other formats go to
// OpenImageIO's module, svg_image_decode.cpp): every colour type and depth,
// expanded to RGBA at 8 bits, or 16 for 16-bit sources. Samples are kept as stored: no
// gamma or ICC conversion, as resvg applies none.
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "parsers/svg/svg_resources.h"

namespace mpvg::svg::detail {

namespace {

// Everything the decoder touches after setjmp lives here, behind a
// pointer, so that a longjmp from libpng's error handler leaves nothing
// indeterminate and skips no destructor.
struct PngDecoder {
  const std::vector<uint8_t>* bytes = nullptr;
  size_t pos = 0;
  size_t max_pixels = 0;
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::shared_ptr<Image> image;
  std::vector<png_bytep> rows;
  char error[200] = {};

  ~PngDecoder() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

void on_error(png_structp png, png_const_charp msg) {
  auto* d = static_cast<PngDecoder*>(png_get_error_ptr(png));
  std::snprintf(d->error, sizeof d->error, "cannot decode the PNG image: %s", msg);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}

void on_read(png_structp png, png_bytep out, png_size_t n) {
  auto* d = static_cast<PngDecoder*>(png_get_io_ptr(png));
  if (n > d->bytes->size() - d->pos) png_error(png, "truncated PNG data");
  std::memcpy(out, d->bytes->data() + d->pos, n);
  d->pos += n;
}

// Decodes into d->image; false with d->error set on failure. No C++
// object with a destructor is created in this frame after setjmp.
bool decode(PngDecoder* d) {
  if (setjmp(png_jmpbuf(d->png))) return false;
  png_set_read_fn(d->png, d, on_read);
  png_read_info(d->png, d->info);
  const png_uint_32 w = png_get_image_width(d->png, d->info), h = png_get_image_height(d->png, d->info);
  if (size_t(w) * size_t(h) > d->max_pixels) {
    std::snprintf(d->error, sizeof d->error, "image of %ux%u pixels is over the limit of %zu pixels", w, h,
                  d->max_pixels);
    return false;
  }
  const int depth = png_get_bit_depth(d->png, d->info);
  const int type = png_get_color_type(d->png, d->info);
  // Palettes to RGB, grey below 8 bits to 8, tRNS to an alpha channel.
  png_set_expand(d->png);
  if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(d->png);
  const bool wide = depth == 16;
  if (!(type & PNG_COLOR_MASK_ALPHA) && !png_get_valid(d->png, d->info, PNG_INFO_tRNS))
    png_set_add_alpha(d->png, wide ? 0xffff : 0xff, PNG_FILLER_AFTER);
  // PNG stores 16-bit samples big-endian; Image holds native uint16_t.
  const uint16_t probe = 1;
  if (wide && *reinterpret_cast<const uint8_t*>(&probe) == 1) png_set_swap(d->png);
  png_set_interlace_handling(d->png);
  png_read_update_info(d->png, d->info);
  const size_t row_bytes = png_get_rowbytes(d->png, d->info);
  if (row_bytes != size_t(w) * 4 * (wide ? 2 : 1)) {
    std::snprintf(d->error, sizeof d->error, "cannot decode the PNG image: unexpected row layout");
    return false;
  }
  Image& im = *d->image;
  im.width = static_cast<int>(w);
  im.height = static_cast<int>(h);
  im.bits = wide ? 16 : 8;
  d->rows.resize(h);
  if (wide) {
    im.rgba16.resize(size_t(w) * h * 4);
    for (png_uint_32 y = 0; y < h; y++) d->rows[y] = reinterpret_cast<png_bytep>(&im.rgba16[size_t(y) * w * 4]);
  } else {
    im.rgba8.resize(size_t(w) * h * 4);
    for (png_uint_32 y = 0; y < h; y++) d->rows[y] = &im.rgba8[size_t(y) * w * 4];
  }
  png_read_image(d->png, d->rows.data());
  png_read_end(d->png, nullptr);
  return true;
}

}  // namespace

std::shared_ptr<Image> decode_png(const std::vector<uint8_t>& bytes, std::string* why, size_t max_pixels) {
  auto fail = [&](std::string msg) -> std::shared_ptr<Image> {
    if (why) *why = std::move(msg);
    return nullptr;
  };
  PngDecoder d;
  d.bytes = &bytes;
  d.max_pixels = max_pixels;
  d.image = std::make_shared<Image>();
  d.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &d, on_error, on_warning);
  if (!d.png) return fail("cannot create a PNG reader");
  d.info = png_create_info_struct(d.png);
  if (!d.info) return fail("cannot create a PNG reader");
  if (!decode(&d)) return fail(d.error);
  return d.image;
}

std::string png_decoder_library() { return "libpng " PNG_LIBPNG_VER_STRING; }

}  // namespace mpvg::svg::detail
