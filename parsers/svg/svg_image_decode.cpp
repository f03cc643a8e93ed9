// Raster images in SVG documents: PNG by libpng in the process
// (svg_image_decode_png.cpp); JPEG, GIF and WebP by OpenImageIO in a module
// opened on first need (svg_image_decode_oiio.cpp, mpvg_oiio_decoder.so),
// so that svg2png starts without loading OpenImageIO's ~260 libraries.
#include "parsers/oiio_module.h"
#include "parsers/svg/svg_resources.h"

namespace mpvg::svg::detail {

namespace {

using DecodeFn = void (*)(const std::vector<uint8_t>*, const char*, const DecodeRequest*, std::shared_ptr<Image>*,
                          std::string*, int*, int*);

// The decoder module, opened on first need.
struct Decoder {
  DecodeFn decode = nullptr;
  std::string version, error;
};

const Decoder& oiio_module() {
  static const Decoder module = [] {
    const OiioModule m = open_oiio_module("mpvg_oiio_decoder.so", "mpvg_oiio_decode", "decoder");
    return Decoder{reinterpret_cast<DecodeFn>(m.entry), m.version, m.error};
  }();
  return module;
}

}  // namespace

bool oiio_decoder_available(std::string* why) {
  const Decoder& m = oiio_module();
  if (!m.decode && why) *why = m.error;
  return m.decode != nullptr;
}

std::shared_ptr<Image> decode_raster(const std::vector<uint8_t>& bytes, std::string* why, const DecodeRequest& request,
                                     int* full_w, int* full_h) {
  const char* format = nullptr;
  const char* name = nullptr;
  switch (sniff_image(bytes, "")) {
    case ImageKind::Png: return decode_png(bytes, why, request, full_w, full_h);
    case ImageKind::Jpeg: format = "jpeg", name = "JPEG"; break;
    case ImageKind::Gif: format = "gif", name = "GIF"; break;
    case ImageKind::Webp: format = "webp", name = "WebP"; break;
    default:
      if (why) *why = "not a PNG, JPEG, GIF or WebP image";
      return nullptr;
  }
  std::string no;
  if (!oiio_decoder_available(&no)) {
    if (why) *why = std::string(name) + " images need OpenImageIO (" + no + ")";
    return nullptr;
  }
  std::shared_ptr<Image> image;
  int w = 0, h = 0;
  oiio_module().decode(&bytes, format, &request, &image, why, &w, &h);
  if (full_w) *full_w = w;
  if (full_h) *full_h = h;
  return image;
}

std::string image_decoder_library() {
  std::string no;
  const bool oiio = oiio_decoder_available(&no);
  return png_decoder_library() + "; " + (oiio ? oiio_module().version + " (module)" : "no OpenImageIO: " + no);
}

}  // namespace mpvg::svg::detail
