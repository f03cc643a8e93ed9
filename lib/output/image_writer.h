// Image files other than PNG: TIFF and JPEG (pdf2png's -tiff and -jpeg, as
// pdftoppm's; TIFFs read back for mpvg-compare), encoded by OpenImageIO in a module opened on first need
// (lib/output/image_encode_oiio.cpp, mpvg_oiio_encoder.so; built where
// MPVG_IMAGE_IO=oiio), as SVG images are decoded: a process that writes
// only PNGs never loads OpenImageIO's ~260 libraries. PNG goes through
// mpvg's own encoder (lib/output/png_writer.h). Bytes are encoded in memory; the
// caller writes them with write_output() (lib/output/output_file.h), whole or
// not at all.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lib/output/png_writer.h"

namespace mpvg::image {

enum class Format { Png, Jpeg, Tiff };

struct EncodeOptions {
  // JPEG (pdftoppm's -jpegopt): quality 1-100, progressive scans,
  // optimized Huffman tables (a progressive JPEG always has them). Also the
  // quality of TIFF's jpeg compression.
  int jpeg_quality = 75;
  bool progressive = false, optimize = false;
  // TIFF (pdftoppm's -tiffcompression): none, packbits, lzw, deflate or
  // jpeg (8-bit RGB only: OpenImageIO 2.4 deflates anything else).
  std::string tiff_compression = "deflate";
  // deflate's level, 1 (fastest, the default: as the PNGs' default level
  // 2 of libdeflate, files a few percent larger than level 6 for pages)
  // to 9 (pdf2png's --compression N).
  int deflate_level = 1;
  // Resolution written into the file (TIFF's XResolution and YResolution
  // per inch, JPEG's JFIF density); 0: none. dpi_y: the vertical one
  // where it differs (pdf2png's -rx/-ry); 0: dpi.
  double dpi = 0, dpi_y = 0;
};

// Interleaved samples, top row first, rows packed: width * channels
// samples a row. bits 8 (uint8_t) or 16 (uint16_t, native byte order); 1:
// uint8_t samples of 0 or 255 written one bit each (TIFF, grey). Channels:
// 1 grey, 2 grey and straight alpha, 3 RGB, 4 RGBA; with cmyk, 4 or more:
// C, M, Y, K, then spot colours, as ink amounts (0: no ink).
struct Raster {
  int width = 0, height = 0, channels = 0, bits = 8;
  bool cmyk = false;
  const void* data = nullptr;
};

// Whether TIFF and JPEG can be written (the module loads); `why` gets one
// line when not ("built with MPVG_IMAGE_IO=png", "its encoder module is not
// installed (looked for ...)").
bool encoder_available(std::string* why);

// The file's bytes. Throws mpvg::Error with one line: the module missing,
// a raster the format cannot hold (alpha or 16 bits in a JPEG), or
// OpenImageIO's own message.
std::vector<uint8_t> encode(Format f, const Raster& r, const EncodeOptions& o);

// Straight-alpha RGBA as the converters render it (width * height * 4
// samples) in the colours of pdf2png's -gray and -mono (png::Color): alpha
// is kept only where a pixel is not opaque, as the PNG writer keeps it,
// and where the format has it (a JPEG is composited over white); grey is
// png::gray_of, mono png::mono_white's dither over white (one bit per
// pixel in a TIFF, 0 or 255 in a JPEG). Format::Png gives png::encode_*'s
// bytes at its default level.
std::vector<uint8_t> encode_rgba8(Format f, int width, int height, const uint8_t* rgba, png::Color color,
                                  const EncodeOptions& o);
std::vector<uint8_t> encode_rgba16(Format f, int width, int height, const uint16_t* rgba, png::Color color,
                                   const EncodeOptions& o);

// An image file read back (mpvg-compare reads the TIFFs pdf2png writes):
// its first subimage, width * height * channels samples in [0, 1],
// interleaved, top row first.
struct Decoded {
  int width = 0, height = 0, channels = 0, bits = 8;
  bool cmyk = false;               // C, M, Y, K, then spot colours: ink amounts (0: no ink)
  int alpha = -1;                  // the channel of (straight) alpha; -1: none
  std::vector<std::string> names;  // the channels' names ("R", "C", "PANTONE 185 C", "A")
  std::vector<float> samples;
};

// The most channels decode() reads (CMYK, spot colours, alpha).
constexpr int kMaxDecodedChannels = 16;

// Reads a TIFF (or any file OpenImageIO reads) of at most max_pixels
// pixels and kMaxDecodedChannels channels through the module. Throws
// mpvg::Error with one line.
Decoded decode(const std::vector<uint8_t>& bytes, size_t max_pixels);

// The file name extension pdftoppm gives the format: "png", "jpg", "tif".
const char* extension(Format f);

// "OpenImageIO 2.4.7 (module)", or why there is none.
std::string encoder_library();

}  // namespace mpvg::image
