// TIFF and JPEG output (lib/output/image_writer.h): known rasters encoded by
// image::encode and read back by OpenImageIO's readers (linked here, not
// through the module) give the same samples, exactly for TIFF (every
// compression but jpeg), within a tolerance for JPEG at quality 95; the
// tags say what the samples are (photometric, alpha, resolution); the
// same image gives the same bytes. Where the build has no OpenImageIO
// (MPVG_IMAGE_IO=png) the cases that need it say SKIPPED, and the writer's
// refusal is checked instead.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "lib/output/image_writer.h"
#include "core/error.h"
#include "tests/catch.h"

#ifdef MPVG_TEST_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

namespace {

using mpvg::image::EncodeOptions;
using mpvg::image::Format;
using mpvg::image::Raster;

// A smooth pattern (JPEG keeps it within a few levels) with both ends of
// the range: w x h x channels samples of `max`.
template <class T>
std::vector<T> pattern(int w, int h, int channels, uint32_t max) {
  std::vector<T> v(size_t(w) * h * channels);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      for (int c = 0; c < channels; c++) {
        const double t = (x + 2.0 * y + 37.0 * c) / (w + 2.0 * h + 37.0 * channels);
        v[(size_t(y) * w + x) * channels + c] = static_cast<T>(std::lround(std::fmod(t, 1.0) * max));
      }
  return v;
}

template <class T>
Raster raster(const std::vector<T>& v, int w, int h, int channels, bool cmyk = false) {
  Raster r;
  r.width = w;
  r.height = h;
  r.channels = channels;
  r.bits = 8 * int(sizeof(T));
  r.cmyk = cmyk;
  r.data = v.data();
  return r;
}

}  // namespace

#ifdef MPVG_TEST_OIIO
namespace {

// An OpenImageIO build without its module (not installed where it is
// looked for) says so, and the check below fails.
bool skipped() {
  std::string why;
  if (mpvg::image::encoder_available(&why)) return false;
  WARN("SKIPPED: no OpenImageIO encoder: " << why);
  return true;
}

struct Decoded {
  OIIO::ImageSpec spec;
  std::vector<uint8_t> bytes;  // samples of spec.format, as the file holds them
};

// Reads the first image of `file` with OpenImageIO, samples in the file's
// own type: alpha as stored (no premultiplying), CMYK as stored (no
// conversion to RGB) unless `convert` (which YCbCr needs: a TIFF's jpeg
// compression stores RGB as YCbCr).
Decoded decode(const std::vector<uint8_t>& file, const char* format, bool convert = false) {
  OIIO::Filesystem::IOMemReader mem(file.data(), file.size());
  OIIO::Filesystem::IOProxy* proxy = &mem;
  OIIO::ImageSpec config;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  config.attribute("oiio:UnassociatedAlpha", 1);
  if (!convert) config.attribute("oiio:RawColor", 1);
  auto in = OIIO::ImageInput::create(format, false, &config, proxy);
  REQUIRE(in);
  Decoded d;
  REQUIRE(in->open(std::string("image.") + format, d.spec, config));
  d.bytes.resize(d.spec.image_bytes());
  REQUIRE(in->read_image(0, 0, 0, d.spec.nchannels, d.spec.format, d.bytes.data()));
  in->close();
  return d;
}

template <class T>
std::vector<T> samples(const Decoded& d) {
  const T* p = reinterpret_cast<const T*>(d.bytes.data());
  return std::vector<T>(p, p + d.bytes.size() / sizeof(T));
}

bool tiff_magic(const std::vector<uint8_t>& b) {
  return b.size() > 8 && ((b[0] == 'I' && b[1] == 'I' && b[2] == 42 && b[3] == 0) ||
                          (b[0] == 'M' && b[1] == 'M' && b[2] == 0 && b[3] == 42));
}

bool jpeg_magic(const std::vector<uint8_t>& b) { return b.size() > 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF; }

// Whether the JPEG has a marker (0xFF then `code`) before its first scan.
bool has_marker(const std::vector<uint8_t>& b, uint8_t code) {
  for (size_t i = 2; i + 4 <= b.size();) {
    if (b[i] != 0xFF) return false;
    if (b[i + 1] == code) return true;
    if (b[i + 1] == 0xDA) return false;  // start of scan
    i += 2 + (size_t(b[i + 2]) << 8 | b[i + 3]);
  }
  return false;
}

}  // namespace

TEST_CASE("TIFF: grey, RGB, 8 bits, every compression, exactly", "[image_writer]") {
  if (skipped()) return;
  const int w = 37, h = 23;
  for (int channels : {1, 3}) {
    const std::vector<uint8_t> v = pattern<uint8_t>(w, h, channels, 255);
    for (const char* compression : {"none", "packbits", "lzw", "deflate"}) {
      INFO(channels << " channels, " << compression);
      EncodeOptions o;
      o.tiff_compression = compression;
      o.dpi = 150;
      const std::vector<uint8_t> file = mpvg::image::encode(Format::Tiff, raster(v, w, h, channels), o);
      CHECK(tiff_magic(file));
      const Decoded d = decode(file, "tiff");
      CHECK(d.spec.width == w);
      CHECK(d.spec.height == h);
      CHECK(d.spec.nchannels == channels);
      CHECK(d.spec.format == OIIO::TypeDesc::UINT8);
      CHECK(d.spec.get_int_attribute("tiff:PhotometricInterpretation", -1) == (channels == 1 ? 1 : 2));
      CHECK(d.spec.get_float_attribute("XResolution") == 150.0f);
      CHECK(d.spec.get_float_attribute("YResolution") == 150.0f);
      CHECK(d.spec.get_string_attribute("ResolutionUnit") == "in");
      CHECK(samples<uint8_t>(d) == v);
    }
  }
}

TEST_CASE("TIFF: jpeg compression of RGB within a tolerance; of grey, deflated", "[image_writer]") {
  if (skipped()) return;
  const int w = 64, h = 48;
  EncodeOptions o;
  o.tiff_compression = "jpeg";
  o.jpeg_quality = 95;
  const std::vector<uint8_t> rgb = pattern<uint8_t>(w, h, 3, 255);
  const Decoded d = decode(mpvg::image::encode(Format::Tiff, raster(rgb, w, h, 3), o), "tiff", true);
  CHECK(d.spec.get_string_attribute("Compression") == "jpeg");
  REQUIRE(d.spec.nchannels == 3);
  const std::vector<uint8_t> back = samples<uint8_t>(d);
  REQUIRE(back.size() == rgb.size());
  int worst = 0;
  for (size_t i = 0; i < rgb.size(); i++) worst = std::max(worst, std::abs(int(back[i]) - int(rgb[i])));
  CHECK(worst <= 12);
  // Grey: OpenImageIO 2.4 compresses only 8-bit RGB with jpeg.
  const std::vector<uint8_t> grey = pattern<uint8_t>(w, h, 1, 255);
  const Decoded g = decode(mpvg::image::encode(Format::Tiff, raster(grey, w, h, 1), o), "tiff");
  CHECK(samples<uint8_t>(g) == grey);
}

TEST_CASE("TIFF: 16 bits, grey + alpha and RGBA, straight alpha, exactly", "[image_writer]") {
  if (skipped()) return;
  const int w = 19, h = 31;
  for (int channels : {1, 2, 3, 4}) {
    INFO(channels << " channels");
    const std::vector<uint16_t> v = pattern<uint16_t>(w, h, channels, 65535);
    const std::vector<uint8_t> file = mpvg::image::encode(Format::Tiff, raster(v, w, h, channels), EncodeOptions{});
    CHECK(tiff_magic(file));
    const Decoded d = decode(file, "tiff");
    CHECK(d.spec.nchannels == channels);
    CHECK(d.spec.format == OIIO::TypeDesc::UINT16);
    CHECK(d.spec.get_string_attribute("Compression") == "zip");  // deflate
    const bool alpha = channels == 2 || channels == 4;
    CHECK(d.spec.alpha_channel == (alpha ? channels - 1 : -1));
    // ExtraSamples 2: unassociated alpha.
    CHECK(d.spec.get_int_attribute("tiff:UnassociatedAlpha", 0) == (alpha ? 1 : 0));
    CHECK(samples<uint16_t>(d) == v);
  }
}

TEST_CASE("TIFF: CMYK is Separated with InkSet CMYK, spots as more inks", "[image_writer]") {
  if (skipped()) return;
  const int w = 16, h = 9;
  const std::vector<uint8_t> cmyk = pattern<uint8_t>(w, h, 4, 255);
  const std::vector<uint8_t> file = mpvg::image::encode(Format::Tiff, raster(cmyk, w, h, 4, true), EncodeOptions{});
  const Decoded d = decode(file, "tiff");
  CHECK(d.spec.get_int_attribute("tiff:PhotometricInterpretation", -1) == 5);  // separated
  CHECK(d.spec.get_string_attribute("tiff:ColorSpace") == "CMYK");             // InkSet 1
  REQUIRE(d.spec.nchannels == 4);
  CHECK(d.spec.channelnames == std::vector<std::string>{"C", "M", "Y", "K"});
  CHECK(samples<uint8_t>(d) == cmyk);
  // CMYK and one spot colour: five inks, multi-ink.
  const std::vector<uint8_t> five = pattern<uint8_t>(w, h, 5, 255);
  const Decoded s = decode(mpvg::image::encode(Format::Tiff, raster(five, w, h, 5, true), EncodeOptions{}), "tiff");
  CHECK(s.spec.get_int_attribute("tiff:PhotometricInterpretation", -1) == 5);
  CHECK(s.spec.get_string_attribute("tiff:ColorSpace") == "color separated");
  REQUIRE(s.spec.nchannels == 5);
  CHECK(samples<uint8_t>(s) == five);
  // 16-bit CMYK would come out 8 bits: refused.
  const std::vector<uint16_t> deep = pattern<uint16_t>(w, h, 4, 65535);
  CHECK_THROWS_AS(mpvg::image::encode(Format::Tiff, raster(deep, w, h, 4, true), EncodeOptions{}), mpvg::Error);
}

TEST_CASE("TIFF: the same image gives the same bytes", "[image_writer]") {
  if (skipped()) return;
  const std::vector<uint8_t> v = pattern<uint8_t>(10, 10, 3, 255);
  const std::vector<uint8_t> a = mpvg::image::encode(Format::Tiff, raster(v, 10, 10, 3), EncodeOptions{});
  const std::vector<uint8_t> b = mpvg::image::encode(Format::Tiff, raster(v, 10, 10, 3), EncodeOptions{});
  CHECK(a == b);
}

TEST_CASE("JPEG: grey and RGB at quality 95 within a tolerance, density, options", "[image_writer]") {
  if (skipped()) return;
  const int w = 64, h = 40;
  for (int channels : {1, 3}) {
    INFO(channels << " channels");
    const std::vector<uint8_t> v = pattern<uint8_t>(w, h, channels, 255);
    EncodeOptions o;
    o.jpeg_quality = 95;
    o.dpi = 300;
    const std::vector<uint8_t> file = mpvg::image::encode(Format::Jpeg, raster(v, w, h, channels), o);
    CHECK(jpeg_magic(file));
    CHECK(!has_marker(file, 0xC2));  // baseline, not progressive
    const Decoded d = decode(file, "jpeg");
    CHECK(d.spec.width == w);
    CHECK(d.spec.height == h);
    REQUIRE(d.spec.nchannels == channels);
    CHECK(d.spec.get_float_attribute("XResolution") == 300.0f);
    CHECK(d.spec.get_string_attribute("ResolutionUnit") == "in");
    const std::vector<uint8_t> back = samples<uint8_t>(d);
    REQUIRE(back.size() == v.size());
    int worst = 0;
    for (size_t i = 0; i < v.size(); i++) worst = std::max(worst, std::abs(int(back[i]) - int(v[i])));
    CHECK(worst <= 12);
    // Progressive: SOF2. Optimized tables: other bytes, the same pixels.
    o.progressive = true;
    CHECK(has_marker(mpvg::image::encode(Format::Jpeg, raster(v, w, h, channels), o), 0xC2));
    o.progressive = false;
    o.optimize = true;
    const std::vector<uint8_t> optimized = mpvg::image::encode(Format::Jpeg, raster(v, w, h, channels), o);
    CHECK(jpeg_magic(optimized));
    CHECK(optimized != file);
    const Decoded od = decode(optimized, "jpeg");
    CHECK(od.bytes == d.bytes);
    CHECK(od.spec.get_float_attribute("XResolution") == 300.0f);
  }
}

TEST_CASE("JPEG: what it cannot hold is refused with one line", "[image_writer]") {
  if (skipped()) return;
  const std::vector<uint8_t> v = pattern<uint8_t>(8, 8, 4, 255);
  auto message = [&](const Raster& r) {
    try {
      mpvg::image::encode(Format::Jpeg, r, EncodeOptions{});
    } catch (const mpvg::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message(raster(v, 8, 8, 4, true)).find("CMYK") != std::string::npos);
  CHECK(message(raster(v, 8, 8, 4)).find("alpha") != std::string::npos);
  const std::vector<uint16_t> deep = pattern<uint16_t>(8, 8, 3, 65535);
  CHECK(message(raster(deep, 8, 8, 3)).find("8 bits") != std::string::npos);
}

TEST_CASE("encode_rgba8: grey keeps alpha in a TIFF, JPEG goes over white, mono is 1 bit", "[image_writer]") {
  if (skipped()) return;
  // Two pixels: opaque red, half-transparent blue.
  const uint8_t rgba[8] = {255, 0, 0, 255, 0, 0, 255, 128};
  using mpvg::png::Color;
  const Decoded grey = decode(mpvg::image::encode_rgba8(Format::Tiff, 2, 1, rgba, Color::Gray, {}), "tiff");
  CHECK(samples<uint8_t>(grey) == std::vector<uint8_t>{77, 255, 28, 128});  // gray_of, alpha
  const Decoded rgb = decode(mpvg::image::encode_rgba8(Format::Tiff, 2, 1, rgba, Color::Rgb, {}), "tiff");
  CHECK(samples<uint8_t>(rgb) == std::vector<uint8_t>{255, 0, 0, 255, 0, 0, 255, 128});
  // 16x16 of mid grey, opaque: -mono's dither, one bit per pixel.
  std::vector<uint8_t> mid(16 * 16 * 4, 128);
  for (size_t i = 3; i < mid.size(); i += 4) mid[i] = 255;
  const Decoded mono = decode(mpvg::image::encode_rgba8(Format::Tiff, 16, 16, mid.data(), Color::Mono, {}), "tiff");
  CHECK(mono.spec.get_int_attribute("oiio:BitsPerSample") == 1);
  const std::vector<uint8_t> bits = samples<uint8_t>(mono);
  REQUIRE(bits.size() == 256);
  int mismatched = 0;
  for (int y = 0; y < 16; y++)
    for (int x = 0; x < 16; x++) mismatched += bits[y * 16 + x] != (mpvg::png::mono_white(128, x, y) ? 255 : 0);
  CHECK(mismatched == 0);
  // JPEG: the blue pixel over white, (0, 0, 255) half over (255, 255, 255).
  EncodeOptions o;
  o.jpeg_quality = 100;
  const std::vector<uint8_t> flat = {0, 0, 255, 128, 0, 0, 255, 128, 0, 0, 255, 128, 0, 0, 255, 128};
  const Decoded jpeg = decode(mpvg::image::encode_rgba8(Format::Jpeg, 2, 2, flat.data(), Color::Rgb, o), "jpeg");
  REQUIRE(jpeg.spec.nchannels == 3);
  const std::vector<uint8_t> j = samples<uint8_t>(jpeg);
  CHECK(std::abs(int(j[0]) - 127) <= 3);
  CHECK(std::abs(int(j[2]) - 255) <= 3);
  CHECK_THROWS_AS(mpvg::image::encode_rgba8(Format::Jpeg, 2, 2, flat.data(), Color::Mono, o), mpvg::Error);
}

TEST_CASE("PNG through image::encode: grey and RGBA read back exactly", "[image_writer]") {
  const std::vector<uint8_t> ga = pattern<uint8_t>(9, 7, 2, 255);
  const std::vector<uint8_t> file = mpvg::image::encode(Format::Png, raster(ga, 9, 7, 2), EncodeOptions{});
  REQUIRE(file.size() > 8);
  CHECK(file[1] == 'P');
  const Decoded d = decode(file, "png");
  CHECK(d.spec.nchannels == 2);
  CHECK(samples<uint8_t>(d) == ga);
  const std::vector<uint16_t> rgba = pattern<uint16_t>(9, 7, 4, 65535);
  const Decoded e = decode(mpvg::image::encode(Format::Png, raster(rgba, 9, 7, 4), EncodeOptions{}), "png");
  CHECK(e.spec.nchannels == 4);
  CHECK(samples<uint16_t>(e) == rgba);
}
#endif

TEST_CASE("without the module: encoder_available says why, encode throws one line", "[image_writer]") {
  std::string why;
  const bool available = mpvg::image::encoder_available(&why);
#ifdef MPVG_TEST_OIIO
  CHECK(available);
  CHECK(mpvg::image::encoder_library().rfind("OpenImageIO ", 0) == 0);
#else
  WARN("SKIPPED: the TIFF and JPEG read-back cases (built with MPVG_IMAGE_IO=png: no OpenImageIO)");
  CHECK(!available);
  CHECK(!why.empty());
  CHECK(why.find('\n') == std::string::npos);
  const std::vector<uint8_t> v(12, 0);
  try {
    mpvg::image::encode(Format::Tiff, raster(v, 2, 2, 3), EncodeOptions{});
    FAIL("no error");
  } catch (const mpvg::Error& e) {
    CHECK(std::string(e.what()).find("needs OpenImageIO") != std::string::npos);
  }
#endif
  CHECK(std::string(mpvg::image::extension(Format::Tiff)) == "tif");
  CHECK(std::string(mpvg::image::extension(Format::Jpeg)) == "jpg");
  CHECK(std::string(mpvg::image::extension(Format::Png)) == "png");
}
