// JPEG, GIF and WebP images decoded by OpenImageIO, from memory through an
// IOProxy (nothing touches the disk). Built as a module of its own,
// mpvg_oiio_decoder.so (MPVG_IMAGE_IO=oiio), that svg_image_decode.cpp
// opens on first need: OpenImageIO's ~260 libraries cost 0.3 s to load,
// which a process meeting only PNGs, or no images, does not pay.
//
// What OpenImageIO 2.4 hands back, checked against PIL: PNG (palette and
// tRNS expanded) keeps straight alpha when asked with
// oiio:UnassociatedAlpha; WebP comes premultiplied whatever the hint, GIF
// with binary alpha; CMYK JPEGs come as RGB; no colour conversion (no
// gAMA, no ICC profile) is applied, as resvg applies none; the EXIF
// orientation is reported, not applied, and ignored here as resvg does.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "core/scene.h"
#include "parsers/svg/image_reduction.h"

namespace {

using mpvg::Image;
using mpvg::svg::detail::DecodeRequest;
using mpvg::svg::detail::RowReducer;

// The size a GIF (logical screen) or WebP (VP8, VP8L or VP8X header)
// claims, read before its decoder allocates for it; false when the header
// is not understood (the decoder then finds out).
bool header_size(const std::vector<uint8_t>& b, const char* format, int* w, int* h) {
  auto le16 = [&](size_t i) { return int(b[i]) | int(b[i + 1]) << 8; };
  auto le24 = [&](size_t i) { return int(b[i]) | int(b[i + 1]) << 8 | int(b[i + 2]) << 16; };
  if (std::string(format) == "gif") {
    if (b.size() < 13) return false;  // the header and logical screen descriptor: b[10] is read below
    *w = le16(6);
    *h = le16(8);
    // The first image descriptor may be larger than the screen.
    size_t i = 13 + ((b[10] & 0x80) ? 3 * (size_t(2) << (b[10] & 7)) : 0);
    while (i < b.size()) {
      if (b[i] == 0x2C && i + 9 < b.size()) {
        *w = std::max(*w, le16(i + 5));
        *h = std::max(*h, le16(i + 7));
        break;
      }
      if (b[i] != 0x21 || i + 2 >= b.size()) break;  // not an extension: stop looking
      i += 2;
      while (i < b.size() && b[i] != 0) i += size_t(b[i]) + 1;  // sub-blocks
      i++;
    }
    return true;
  }
  if (b.size() < 30) return false;
  const std::string chunk(reinterpret_cast<const char*>(&b[12]), 4);
  if (chunk == "VP8X") {
    *w = le24(24) + 1;
    *h = le24(27) + 1;
  } else if (chunk == "VP8L") {
    const uint32_t bits = uint32_t(b[21]) | uint32_t(b[22]) << 8 | uint32_t(b[23]) << 16 | uint32_t(b[24]) << 24;
    *w = int(bits & 0x3FFF) + 1;
    *h = int((bits >> 14) & 0x3FFF) + 1;
  } else if (chunk == "VP8 ") {
    *w = le16(26) & 0x3FFF;
    *h = le16(28) & 0x3FFF;
  } else {
    return false;
  }
  return true;
}

// OpenImageIO's messages can span lines (one per error met): joined.
std::shared_ptr<Image> fail(std::string* why, std::string msg) {
  while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
  for (size_t i; (i = msg.find('\n')) != std::string::npos;) msg.replace(i, 1, "; ");
  if (why) *why = std::move(msg);
  return nullptr;
}

// 1 = grey, 2 = grey + alpha, 3 = RGB, 4 = RGBA, to RGBA; associated alpha
// back to straight.
template <class T>
std::vector<T> to_rgba(const std::vector<T>& src, size_t pixels, int nc, bool associated, T max) {
  std::vector<T> out(pixels * 4);
  for (size_t i = 0; i < pixels; i++) {
    const T* p = &src[i * nc];
    T* q = &out[i * 4];
    const bool grey = nc < 3;
    q[0] = p[0];
    q[1] = grey ? p[0] : p[1];
    q[2] = grey ? p[0] : p[2];
    q[3] = nc == 2 ? p[1] : (nc == 4 ? p[3] : max);
    if (associated && q[3] < max) {
      const double a = q[3];
      for (int c = 0; c < 3; c++)
        q[c] = a > 0 ? static_cast<T>(std::min<double>(max, std::floor(q[c] * double(max) / a + 0.5))) : T(0);
    }
  }
  return out;
}

// Rows of the first subimage, converted to RGBA, into `reduce`, one
// scanline at a time (JPEG's reader decodes as it goes; GIF's and WebP's
// hold the whole image already).
template <class T>
bool read_rows(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, bool associated, T max,
               RowReducer<T>& reduce) {
  const int nc = spec.nchannels;
  std::vector<T> raw(size_t(spec.width) * nc);
  for (int y = 0; y < spec.height; y++) {
    if (!in.read_scanline(spec.y + y, 0, type, raw.data())) return false;
    const std::vector<T> rgba = to_rgba<T>(raw, size_t(spec.width), nc, associated, max);
    reduce.add_row(y, rgba.data());
  }
  return true;
}

std::shared_ptr<Image> decode(const std::vector<uint8_t>& bytes, const char* format, const DecodeRequest& req,
                              std::string* why, int* full_w, int* full_h) {
  OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
  OIIO::Filesystem::IOProxy* proxy = &mem;
  OIIO::ImageSpec config;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::create(format, false, &config, proxy);
  if (!in) return fail(why, std::string("no ") + format + " reader in OpenImageIO: " + OIIO::geterror());
  in->set_ioproxy(proxy);
  // A failure: every message the reader holds is taken, as OpenImageIO
  // prints those left behind when the reader is destroyed.
  auto failed = [&]() {
    std::string msg = in->geterror();
    in->close();
    const std::string more = in->geterror();
    in.reset();
    OIIO::geterror();
    return fail(why, std::string("cannot decode the ") + format + " image: " + (msg.empty() ? more : msg));
  };
  auto too_large = [&](size_t w, size_t h, size_t limit) {
    return fail(why, "image of " + std::to_string(w) + "x" + std::to_string(h) + " pixels is over the limit of " +
                         std::to_string(limit) + " pixels");
  };
  // GIF's and WebP's readers decode the whole image into memory of their
  // own when it is opened: the size in the header is checked before.
  const bool whole = std::string(format) != "jpeg";
  if (whole) {
    int w = 0, h = 0;
    if (header_size(bytes, format, &w, &h) && size_t(w) * size_t(h) > req.max_whole_pixels)
      return too_large(size_t(w), size_t(h), req.max_whole_pixels);
  }
  OIIO::ImageSpec spec;
  // The name only tells the reader what to report; the bytes come from `mem`.
  if (!in->open(std::string("image.") + format, spec, config)) return failed();
  if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1)
    return fail(why, std::string("the ") + format + " image has no pixels");
  *full_w = spec.width;
  *full_h = spec.height;
  if (whole && size_t(spec.width) * size_t(spec.height) > req.max_whole_pixels)
    return too_large(size_t(spec.width), size_t(spec.height), req.max_whole_pixels);
  if (size_t(spec.width) * size_t(spec.height) > req.max_decoded_pixels)
    return too_large(size_t(spec.width), size_t(spec.height), req.max_decoded_pixels);
  const int k = req.reduction ? std::max(1, req.reduction(spec.width, spec.height)) : 1;
  const size_t out_w = (size_t(spec.width) + k - 1) / k, out_h = (size_t(spec.height) + k - 1) / k;
  if (out_w * out_h > req.max_pixels) return too_large(size_t(spec.width), size_t(spec.height), req.max_pixels);
  const int nc = spec.nchannels;
  if (nc < 1 || nc > 4)
    return fail(why, std::string("the ") + format + " image has " + std::to_string(nc) + " channels");
  const bool has_alpha = nc == 2 || nc == 4;
  const bool associated = has_alpha && spec.get_int_attribute("oiio:UnassociatedAlpha", 0) == 0;

  auto image = std::make_shared<Image>();
  // The first subimage (a GIF's first frame) at its own depth: 16 bits only
  // for 16-bit sources.
  if (spec.format == OIIO::TypeDesc::UINT16) {
    RowReducer<uint16_t> reduce(spec.width, spec.height, k);
    if (!read_rows<uint16_t>(*in, spec, OIIO::TypeDesc::UINT16, associated, 65535, reduce)) return failed();
    image->bits = 16;
    image->rgba16 = std::move(reduce.pixels());
    image->width = reduce.width();
    image->height = reduce.height();
  } else {
    RowReducer<uint8_t> reduce(spec.width, spec.height, k);
    if (!read_rows<uint8_t>(*in, spec, OIIO::TypeDesc::UINT8, associated, 255, reduce)) return failed();
    image->bits = 8;
    image->rgba8 = std::move(reduce.pixels());
    image->width = reduce.width();
    image->height = reduce.height();
  }
  return image;
}

}  // namespace

// The module's entry points, looked up by name by svg_image_decode.cpp,
// which holds their types. `format` is "jpeg", "gif" or "webp": the caller
// chose it from the signature (OpenImageIO's own search would try every
// format, some by opening the name on disk). Built by the same compiler
// against the same libstdc++ as the caller, so C++ types cross.
extern "C" __attribute__((visibility("default"))) const char* mpvg_oiio_version() {
  return "OpenImageIO " OIIO_VERSION_STRING;
}

extern "C" __attribute__((visibility("default"))) void mpvg_oiio_decode(const std::vector<uint8_t>* bytes,
                                                                       const char* format,
                                                                       const DecodeRequest* request,
                                                                       std::shared_ptr<Image>* result,
                                                                       std::string* why, int* full_w, int* full_h) {
  // No exception may cross into the caller through a C-linkage function.
  try {
    *result = decode(*bytes, format, *request, why, full_w, full_h);
  } catch (const std::exception& e) {
    *result = nullptr;
    if (why) *why = std::string("cannot decode the ") + format + " image: " + e.what();
  }
}
