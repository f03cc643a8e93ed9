// TIFF and JPEG output (lib/output/image_writer.h): OpenImageIO in a module
// opened on first need (image_encode_oiio.cpp, mpvg_oiio_encoder.so), as
// parsers/svg/svg_image_decode.cpp opens the decoder's, so that the
// converters start without loading OpenImageIO's ~260 libraries.
#include "lib/output/image_writer.h"

#include <algorithm>

#include "core/error.h"
#include "parsers/oiio_module.h"

namespace mpvg::image {

namespace {

using EncodeFn = bool (*)(const char*, const Raster*, const EncodeOptions*, std::vector<uint8_t>*, std::string*);

// The encoder module, opened on first need.
struct Encoder {
  EncodeFn encode = nullptr;
  std::string version, error;
};

const Encoder& oiio_module() {
  static const Encoder module = [] {
    const OiioModule m = open_oiio_module("mpvg_oiio_encoder.so", "mpvg_oiio_encode", "encoder");
    return Encoder{reinterpret_cast<EncodeFn>(m.entry), m.version, m.error};
  }();
  return module;
}

using ReadFn = bool (*)(const std::vector<uint8_t>*, size_t, Decoded*, std::string*);

// The same module's reader, opened on first need.
struct Reader {
  ReadFn read = nullptr;
  std::string error;
};

const Reader& reader_module() {
  static const Reader module = [] {
    const OiioModule m = open_oiio_module("mpvg_oiio_encoder.so", "mpvg_oiio_read", "image file reader");
    return Reader{reinterpret_cast<ReadFn>(m.entry), m.error};
  }();
  return module;
}

// Grey (png::gray_of) or the colours as they are, alpha kept where any
// pixel is not opaque and the format has alpha, else composited over
// white (g a + max (1 - a), rounded); mono dithered to 0 or max.
template <class T>
std::vector<T> from_rgba(Format f, int width, int height, const T* rgba, png::Color color, int* channels) {
  constexpr uint32_t max = sizeof(T) == 1 ? 255 : 65535;
  const size_t n = size_t(width) * size_t(height);
  bool opaque = true;
  for (size_t i = 0; i < n && opaque; i++) opaque = rgba[4 * i + 3] == max;
  const bool alpha = !opaque && f != Format::Jpeg && color != png::Color::Mono;
  const int colours = color == png::Color::Rgb ? 3 : 1;
  *channels = colours + (alpha ? 1 : 0);
  std::vector<T> out(n * size_t(*channels));
  for (size_t i = 0; i < n; i++) {
    const T* p = rgba + 4 * i;
    T* q = out.data() + i * size_t(*channels);
    const uint32_t a = p[3];
    auto over = [&](uint32_t v) { return alpha ? v : (v * a + max * (max - a) + max / 2) / max; };
    if (colours == 3) {
      for (int c = 0; c < 3; c++) q[c] = static_cast<T>(over(p[c]));
    } else {
      uint32_t g = over(png::gray_of(p[0], p[1], p[2]));
      if (color == png::Color::Mono)
        g = png::mono_white(g, static_cast<int>(i % size_t(width)), static_cast<int>(i / size_t(width))) ? max : 0;
      q[0] = static_cast<T>(g);
    }
    if (alpha) q[colours] = static_cast<T>(a);
  }
  return out;
}

// A raster of 1-4 channels (not CMYK) as straight RGBA, for the PNG encoder.
template <class T>
std::vector<T> to_rgba(const Raster& r) {
  constexpr T max = sizeof(T) == 1 ? 255 : 65535;
  const T* in = static_cast<const T*>(r.data);
  const size_t n = size_t(r.width) * size_t(r.height);
  std::vector<T> out(n * 4);
  for (size_t i = 0; i < n; i++) {
    const T* p = in + i * size_t(r.channels);
    const bool grey = r.channels < 3;
    out[4 * i] = p[0];
    out[4 * i + 1] = grey ? p[0] : p[1];
    out[4 * i + 2] = grey ? p[0] : p[2];
    out[4 * i + 3] = r.channels == 2 ? p[1] : r.channels == 4 ? p[3] : max;
  }
  return out;
}

std::vector<uint8_t> encode_png(const Raster& r) {
  if (r.cmyk || r.channels < 1 || r.channels > 4 || (r.bits != 8 && r.bits != 16) || !r.data)
    throw Error("PNG holds grey or RGB, with or without alpha, of 8 or 16 bits");
  if (r.width <= 0 || r.height <= 0) throw Error("PNG: empty image");
  // The grey encoders take RGBA: gray_of(g, g, g) is g.
  const bool grey = r.channels < 3;
  if (r.bits == 16) {
    const std::vector<uint16_t> rgba = to_rgba<uint16_t>(r);
    return grey ? png::encode_gray16(r.width, r.height, rgba.data()) : png::encode_rgba16(r.width, r.height, rgba.data());
  }
  const std::vector<uint8_t> rgba = to_rgba<uint8_t>(r);
  return grey ? png::encode_gray8(r.width, r.height, rgba.data(), png::Color::Gray)
              : png::encode_rgba8(r.width, r.height, rgba.data());
}

template <class T>
std::vector<uint8_t> encode_rgba(Format f, int width, int height, const T* rgba, png::Color color,
                                 const EncodeOptions& o) {
  if (width <= 0 || height <= 0) throw Error("empty image");
  if (f == Format::Jpeg && color == png::Color::Mono) throw Error("JPEG has no 1-bit images");
  if (color == png::Color::Mono && sizeof(T) != 1) throw Error("1-bit images are made from 8 bits");
  int channels = 0;
  const std::vector<T> samples = from_rgba<T>(f, width, height, rgba, color, &channels);
  Raster r;
  r.width = width;
  r.height = height;
  r.channels = channels;
  r.bits = color == png::Color::Mono ? 1 : 8 * int(sizeof(T));
  r.data = samples.data();
  return encode(f, r, o);
}

}  // namespace

bool encoder_available(std::string* why) {
  const Encoder& m = oiio_module();
  if (!m.encode && why) *why = m.error;
  return m.encode != nullptr;
}

std::vector<uint8_t> encode(Format f, const Raster& r, const EncodeOptions& o) {
  if (f == Format::Png) return encode_png(r);
  const char* name = f == Format::Tiff ? "TIFF" : "JPEG";
  std::string no;
  if (!encoder_available(&no)) throw Error(std::string(name) + " output needs OpenImageIO (" + no + ")");
  std::vector<uint8_t> bytes;
  std::string why;
  if (!oiio_module().encode(f == Format::Tiff ? "tiff" : "jpeg", &r, &o, &bytes, &why))
    throw Error(std::string(name) + ": " + why);
  return bytes;
}

std::vector<uint8_t> encode_rgba8(Format f, int width, int height, const uint8_t* rgba, png::Color color,
                                  const EncodeOptions& o) {
  if (f == Format::Png) {
    return color == png::Color::Rgb ? png::encode_rgba8(width, height, rgba)
                                    : png::encode_gray8(width, height, rgba, color);
  }
  return encode_rgba<uint8_t>(f, width, height, rgba, color, o);
}

std::vector<uint8_t> encode_rgba16(Format f, int width, int height, const uint16_t* rgba, png::Color color,
                                   const EncodeOptions& o) {
  if (f == Format::Png) {
    if (color == png::Color::Mono) throw Error("PNG: 1-bit images are made from 8 bits");
    return color == png::Color::Rgb ? png::encode_rgba16(width, height, rgba) : png::encode_gray16(width, height, rgba);
  }
  return encode_rgba<uint16_t>(f, width, height, rgba, color, o);
}

const char* extension(Format f) {
  switch (f) {
    case Format::Jpeg: return "jpg";
    case Format::Tiff: return "tif";
    default: return "png";
  }
}

std::string encoder_library() {
  std::string no;
  return encoder_available(&no) ? oiio_module().version + " (module)" : "no OpenImageIO: " + no;
}

Decoded decode(const std::vector<uint8_t>& bytes, size_t max_pixels) {
  const Reader& m = reader_module();
  if (!m.read) throw Error("TIFF cannot be read: " + m.error);
  Decoded out;
  std::string why;
  if (!m.read(&bytes, max_pixels, &out, &why)) throw Error(why);
  return out;
}

}  // namespace mpvg::image
