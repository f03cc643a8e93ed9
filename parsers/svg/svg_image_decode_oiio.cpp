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

namespace {

using mpvg::Image;

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

std::shared_ptr<Image> decode(const std::vector<uint8_t>& bytes, const char* format, size_t max_pixels,
                              std::string* why) {
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
  OIIO::ImageSpec spec;
  // The name only tells the reader what to report; the bytes come from `mem`.
  if (!in->open(std::string("image.") + format, spec, config)) return failed();
  if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1)
    return fail(why, std::string("the ") + format + " image has no pixels");
  const size_t pixels = size_t(spec.width) * size_t(spec.height);
  if (pixels > max_pixels)
    return fail(why, "image of " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                         " pixels is over the limit of " + std::to_string(max_pixels) + " pixels");
  const int nc = spec.nchannels;
  if (nc < 1 || nc > 4)
    return fail(why, std::string("the ") + format + " image has " + std::to_string(nc) + " channels");
  const bool has_alpha = nc == 2 || nc == 4;
  const bool associated = has_alpha && spec.get_int_attribute("oiio:UnassociatedAlpha", 0) == 0;

  auto image = std::make_shared<Image>();
  image->width = spec.width;
  image->height = spec.height;
  // The first subimage (a GIF's first frame) at its own depth: 16 bits only
  // for 16-bit sources.
  if (spec.format == OIIO::TypeDesc::UINT16) {
    std::vector<uint16_t> raw(pixels * nc);
    if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT16, raw.data())) return failed();
    image->bits = 16;
    image->rgba16 = to_rgba<uint16_t>(raw, pixels, nc, associated, 65535);
  } else {
    std::vector<uint8_t> raw(pixels * nc);
    if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, raw.data())) return failed();
    image->bits = 8;
    image->rgba8 = to_rgba<uint8_t>(raw, pixels, nc, associated, 255);
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
                                                                       const char* format, size_t max_pixels,
                                                                       std::shared_ptr<Image>* result,
                                                                       std::string* why) {
  // No exception may cross into the caller through a C-linkage function.
  try {
    *result = decode(*bytes, format, max_pixels, why);
  } catch (const std::exception& e) {
    *result = nullptr;
    if (why) *why = std::string("cannot decode the ") + format + " image: " + e.what();
  }
}
