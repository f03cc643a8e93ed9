// The PNG encoder of pdf2png's batches (and of builds without OpenImageIO):
// a PNG is a signature, an IHDR chunk, IDAT chunks holding one zlib stream
// of filtered rows, and IEND. The container and the row filters are the
// PNG specification's (sections 5, 9 and 11); compression is libdeflate's
// whole-buffer deflate where the build found it (two to four times
// zlib's speed at the same level, BENCHMARKS.md) and zlib's otherwise.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mpvg::png {

struct EncodeOptions {
  // Deflate effort, 1 (fastest) to 9 (libdeflate goes to 12).
  int level = 2;
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

// Writes bytes to path ("-": standard output), whole or not at all
// (apps/output_file.h). Throws mpvg::Error.
void write_file(const std::string& path, const std::vector<uint8_t>& bytes);

// "libdeflate 1.14" or "zlib 1.2.13".
std::string compressor();

}  // namespace mpvg::png
