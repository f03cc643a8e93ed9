// mpvg's PNG encoder: a PNG is a signature, an IHDR chunk, IDAT chunks
// holding one zlib stream of filtered rows, and IEND (the PNG
// specification's sections 5, 9 and 11). Rows are filtered by
// core/output/png_filter.h; the compression level chooses what deflates them:
//   0     stored blocks, no compression;
//   1     core/output/deflate.h's parallel deflate (the GPU's, FrameRenderer::
//         render_png; here its CPU executor, slower than libdeflate's 2);
//   2-12  libdeflate's whole-buffer deflate where the build found it (two
//         to four times zlib's speed at the same level, BENCHMARKS.md),
//         zlib's (2-9) otherwise.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/output/png_encode.h"

namespace mpvg::png {

// The default level: libdeflate's 2, the same bytes whichever backend
// renders (BENCHMARKS.md "PNG stage": also the faster batch on a 16-core
// GPU host; level 1 compresses on the device, for CPU-starved hosts and
// one image at a time).
constexpr int kDefaultCpuLevel = 2;

struct EncodeOptions {
  int level = kDefaultCpuLevel;
  // Threads for one image (0: every core). With more than one, a large
  // image is cut into strips of rows filtered and deflated in parallel
  // (zlib streams ended by a sync flush, each primed with the 32 KiB
  // before it, then joined: one valid zlib stream, a few bytes larger),
  // for a single image on idle cores; batches keep one per image.
  int threads = 1;
};

// Encodes straight-alpha RGBA pixels, row after row, width * height * 4
// values. An image opaque throughout is written as RGB, as pdftoppm and
// mutool write pages. 16-bit values are taken in native byte order.
std::vector<uint8_t> encode_rgba8(int width, int height, const uint8_t* rgba, const EncodeOptions& options = {});
std::vector<uint8_t> encode_rgba16(int width, int height, const uint16_t* rgba, const EncodeOptions& options = {});

// The PNG of 8-bit RGB or RGBA rows filtered elsewhere (FrameRenderer::
// render_filtered: on the device, where the image was rendered), deflated
// here at options.level: the same bytes as encode_rgba8 of the image.
std::vector<uint8_t> encode_filtered(int width, int height, const FilteredRows& rows, const EncodeOptions& options = {});

// Greyscale output (pdf2png's -gray and -mono, as pdftoppm's). Grey is
// weighted from the rendered sRGB values with the weights of PDF 32000-1
// §10.3.5 (DeviceRGB to DeviceGray), which MuPDF (fz_convert_color's
// rgb_to_gray) and poppler (GfxDeviceRGBColorSpace::getGray, what
// pdftoppm -gray and -mono draw with) both use:
//   grey = 0.30 R + 0.59 G + 0.11 B, rounded to the nearest value.
// Exact in integers: 100 * 65535 fits 32 bits.
inline uint32_t gray_of(uint32_t r, uint32_t g, uint32_t b) { return (30 * r + 59 * g + 11 * b + 50) / 100; }

// -mono: poppler's Splash in mono1 mode (pdftoppm -mono) dithers its grey
// through a SplashScreen: below 300 dpi (SplashOutputDev::
// setupScreenParams) a dispersed-dot (Bayer) threshold matrix of size 4,
// thresholds 1 + 254 (v - 1) / 15 for SplashScreen::buildDispersedMatrix's
// visiting order v = 1..16; a pixel is white where grey >= its threshold
// (SplashScreen::test). So 0 is all black, 255 all white. At 300 dpi and
// up pdftoppm switches to a stochastic clustered-dot screen built from
// random numbers (not reproducible); this matrix serves every resolution.
// pdftoppm 22.12 -mono at 72 dpi: every pixel of testdata/pdf/grey-ramp.pdf
// equals this matrix applied to its own -gray output.
inline bool mono_white(uint32_t gray8, int x, int y) {
  static constexpr uint8_t kThreshold[4][4] = {
      {17, 255, 34, 204}, {153, 85, 170, 102}, {51, 221, 1, 238}, {187, 119, 136, 68}};
  return gray8 >= kThreshold[y & 3][x & 3];
}

enum class Color {
  Rgb,   // RGB, or RGBA where any pixel is not opaque
  Gray,  // grey (colour type 0), or grey and alpha (4) where any pixel is not opaque
  Mono,  // 1 bit per pixel (colour type 0, depth 1), over a white page
};

// Straight-alpha RGBA of 8 or 16 bits -> a greyscale PNG of the same depth
// (Color::Gray), or of 1 bit (Color::Mono: a pixel not opaque is first
// composited over white).
std::vector<uint8_t> encode_gray8(int width, int height, const uint8_t* rgba, Color color,
                                  const EncodeOptions& options = {});
std::vector<uint8_t> encode_gray16(int width, int height, const uint16_t* rgba, const EncodeOptions& options = {});

// The PNG of an image compressed elsewhere (core/output/png_encode.h's ImageData):
// bit_depth 1, 8 or 16, channels 1 (grey), 2 (grey, alpha), 3 (RGB) or 4
// (RGBA), the zlib stream.
std::vector<uint8_t> wrap(int width, int height, int bit_depth, int channels, const uint8_t* zlib, size_t n);

// Records the resolution in a PNG made above: a pHYs chunk (pixels per
// metre, as pdftoppm writes it) after IHDR. dpi_y 0: dpi_x; dpi_x 0: none.
void set_resolution(std::vector<uint8_t>& png, double dpi_x, double dpi_y = 0);

// Writes bytes to path ("-": standard output), whole or not at all
// (lib/output/output_file.h). Throws mpvg::Error.
void write_file(const std::string& path, const std::vector<uint8_t>& bytes);

// "libdeflate 1.14" or "zlib 1.2.13".
std::string compressor();

}  // namespace mpvg::png
