// mpvg's PNG encoder: a PNG is a signature, an IHDR chunk, IDAT chunks
// holding one zlib stream of filtered rows, and IEND (the PNG
// specification's sections 5, 9 and 11). Rows are filtered by
// core/png_filter.h; the compression level chooses what deflates them:
//   0     stored blocks, no compression;
//   1     core/deflate.h's parallel deflate (the GPU's, FrameRenderer::
//         render_png; here its CPU executor, slower than libdeflate's 2);
//   2-12  libdeflate's whole-buffer deflate where the build found it (two
//         to four times zlib's speed at the same level, BENCHMARKS.md),
//         zlib's (2-9) otherwise.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

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

// The PNG of an image compressed elsewhere (core/png_encode.h's ImageData):
// bit_depth 8 or 16, channels 3 (RGB) or 4 (RGBA), the zlib stream.
std::vector<uint8_t> wrap(int width, int height, int bit_depth, int channels, const uint8_t* zlib, size_t n);

// Writes bytes to path ("-": standard output), whole or not at all
// (apps/output_file.h). Throws mpvg::Error.
void write_file(const std::string& path, const std::vector<uint8_t>& bytes);

// "libdeflate 1.14" or "zlib 1.2.13".
std::string compressor();

}  // namespace mpvg::png
