// PNG images decoded by libpng (every build; other formats go to
// OpenImageIO's module, svg_image_decode.cpp): every colour type and depth,
// expanded to RGBA at 8 bits, or 16 for 16-bit sources. Samples are kept as stored: no
// gamma or ICC conversion, as resvg applies none.
#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include "parsers/svg/image_reduction.h"
#include "parsers/svg/svg_resources.h"

namespace mpvg::svg::detail {

namespace {

// Everything the decoder touches after setjmp lives here, behind a
// pointer, so that a longjmp from libpng's error handler leaves nothing
// indeterminate and skips no destructor.
struct PngDecoder {
  const std::vector<uint8_t>* bytes = nullptr;
  size_t pos = 0;
  const DecodeRequest* request = nullptr;
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::shared_ptr<Image> image;
  int full_w = 0, full_h = 0;
  std::vector<png_bytep> rows;
  std::vector<uint8_t> row;  // one row, streamed into a reducer
  std::unique_ptr<RowReducer<uint8_t>> reduce8;
  std::unique_ptr<RowReducer<uint16_t>> reduce16;
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

bool too_large(PngDecoder* d, size_t w, size_t h, size_t limit) {
  if (w * h <= limit) return false;
  std::snprintf(d->error, sizeof d->error, "image of %zux%zu pixels is over the limit of %zu pixels", w, h, limit);
  return true;
}

// Rows of the whole image into a reducer.
template <class T>
void reduce_whole(RowReducer<T>& r, const std::vector<T>& px, int w, int h) {
  for (int y = 0; y < h; y++) r.add_row(y, &px[size_t(y) * w * 4]);
}

// Decodes into d->image; false with d->error set on failure. No C++
// object with a destructor is created in this frame after setjmp.
bool decode(PngDecoder* d) {
  if (setjmp(png_jmpbuf(d->png))) return false;
  png_set_read_fn(d->png, d, on_read);
  png_read_info(d->png, d->info);
  const png_uint_32 w = png_get_image_width(d->png, d->info), h = png_get_image_height(d->png, d->info);
  d->full_w = static_cast<int>(w);
  d->full_h = static_cast<int>(h);
  const DecodeRequest& req = *d->request;
  const int k = req.reduction ? std::max(1, req.reduction(int(w), int(h))) : 1;
  const size_t out_w = (w + k - 1) / k, out_h = (h + k - 1) / k;
  if (too_large(d, out_w, out_h, req.max_pixels)) return false;
  if (too_large(d, w, h, req.max_decoded_pixels)) return false;
  const bool interlaced = png_get_interlace_type(d->png, d->info) != PNG_INTERLACE_NONE;
  // Interlaced rows are complete only after the last pass: such an image
  // is decoded whole, then reduced.
  const bool whole = k == 1 || interlaced;
  if (k > 1 && interlaced && too_large(d, w, h, req.max_whole_pixels)) return false;
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
  im.bits = wide ? 16 : 8;
  if (k > 1) {
    if (wide) d->reduce16 = std::make_unique<RowReducer<uint16_t>>(int(w), int(h), k);
    else d->reduce8 = std::make_unique<RowReducer<uint8_t>>(int(w), int(h), k);
  }
  if (whole) {
    im.width = static_cast<int>(w);
    im.height = static_cast<int>(h);
    d->rows.resize(h);
    if (wide) {
      im.rgba16.resize(size_t(w) * h * 4);
      for (png_uint_32 y = 0; y < h; y++) d->rows[y] = reinterpret_cast<png_bytep>(&im.rgba16[size_t(y) * w * 4]);
    } else {
      im.rgba8.resize(size_t(w) * h * 4);
      for (png_uint_32 y = 0; y < h; y++) d->rows[y] = &im.rgba8[size_t(y) * w * 4];
    }
    png_read_image(d->png, d->rows.data());
  } else {
    d->row.resize(row_bytes);
    for (png_uint_32 y = 0; y < h; y++) {
      png_read_row(d->png, d->row.data(), nullptr);
      if (wide) d->reduce16->add_row(int(y), reinterpret_cast<const uint16_t*>(d->row.data()));
      else d->reduce8->add_row(int(y), d->row.data());
    }
  }
  png_read_end(d->png, nullptr);
  return true;
}

}  // namespace

std::shared_ptr<Image> decode_png(const std::vector<uint8_t>& bytes, std::string* why, const DecodeRequest& request,
                                  int* full_w, int* full_h) {
  auto fail = [&](std::string msg) -> std::shared_ptr<Image> {
    if (why) *why = std::move(msg);
    return nullptr;
  };
  PngDecoder d;
  d.bytes = &bytes;
  d.request = &request;
  d.image = std::make_shared<Image>();
  d.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &d, on_error, on_warning);
  if (!d.png) return fail("cannot create a PNG reader");
  d.info = png_create_info_struct(d.png);
  if (!d.info) return fail("cannot create a PNG reader");
  if (!decode(&d)) return fail(d.error);
  if (full_w) *full_w = d.full_w;
  if (full_h) *full_h = d.full_h;
  Image& im = *d.image;
  if (d.reduce8 || d.reduce16) {
    // Interlaced: reduced now from the whole image.
    if (d.reduce8 && !im.rgba8.empty()) reduce_whole(*d.reduce8, im.rgba8, im.width, im.height);
    if (d.reduce16 && !im.rgba16.empty()) reduce_whole(*d.reduce16, im.rgba16, im.width, im.height);
    im.width = d.reduce8 ? d.reduce8->width() : d.reduce16->width();
    im.height = d.reduce8 ? d.reduce8->height() : d.reduce16->height();
    if (d.reduce8) im.rgba8 = std::move(d.reduce8->pixels());
    else im.rgba16 = std::move(d.reduce16->pixels());
  }
  return d.image;
}

std::string png_decoder_library() { return "libpng " PNG_LIBPNG_VER_STRING; }

}  // namespace mpvg::svg::detail
