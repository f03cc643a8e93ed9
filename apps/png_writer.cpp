#include "apps/png_writer.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/error.h"

#if MPVG_HAVE_LIBDEFLATE
#include <libdeflate.h>
#else
#include <zlib.h>
#endif

namespace mpvg::png {

namespace {

uint32_t crc32_of(uint32_t crc, const uint8_t* p, size_t n) {
#if MPVG_HAVE_LIBDEFLATE
  return libdeflate_crc32(crc, p, n);
#else
  return static_cast<uint32_t>(::crc32(crc, p, static_cast<uInt>(n)));
#endif
}

void put32(std::vector<uint8_t>& out, uint32_t v) {
  const uint8_t b[4] = {uint8_t(v >> 24), uint8_t(v >> 16), uint8_t(v >> 8), uint8_t(v)};
  out.insert(out.end(), b, b + 4);
}

// A chunk: length, type, data, CRC of type and data (specification 5.3).
void put_chunk(std::vector<uint8_t>& out, const char type[4], const uint8_t* data, size_t n) {
  put32(out, static_cast<uint32_t>(n));
  const size_t at = out.size();
  out.insert(out.end(), type, type + 4);
  if (n) out.insert(out.end(), data, data + n);
  put32(out, crc32_of(0, out.data() + at, n + 4));
}

// Buffers kept per thread from image to image: a batch's pages are of one
// size, and fresh memory costs a page fault per 4 KiB where it is first
// written (several times the encoding's own time per page in a virtual
// machine, BENCHMARKS.md).
struct Scratch {
  std::vector<uint8_t> filtered, rows, zero, sub, deflated;
#if MPVG_HAVE_LIBDEFLATE
  libdeflate_compressor* compressor = nullptr;
  int level = 0;
  ~Scratch() {
    if (compressor) libdeflate_free_compressor(compressor);
  }
#endif
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// The zlib stream (RFC 1950) of the filtered rows, into s.deflated;
// returns its length.
size_t deflate(Scratch& s, int level) {
  const std::vector<uint8_t>& in = s.filtered;
#if MPVG_HAVE_LIBDEFLATE
  level = level < 1 ? 1 : level > 12 ? 12 : level;
  if (!s.compressor || s.level != level) {
    if (s.compressor) libdeflate_free_compressor(s.compressor);
    s.compressor = libdeflate_alloc_compressor(level);
    s.level = level;
    if (!s.compressor) throw Error("PNG: out of memory");
  }
  const size_t bound = libdeflate_zlib_compress_bound(s.compressor, in.size());
  if (s.deflated.size() < bound) s.deflated.resize(bound);
  const size_t n = libdeflate_zlib_compress(s.compressor, in.data(), in.size(), s.deflated.data(), s.deflated.size());
  if (n == 0) throw Error("PNG: compression failed");
  return n;
#else
  uLongf n = compressBound(static_cast<uLong>(in.size()));
  if (s.deflated.size() < n) s.deflated.resize(n);
  if (compress2(s.deflated.data(), &n, in.data(), static_cast<uLong>(in.size()), level < 1 ? 1 : level > 9 ? 9 : level) !=
      Z_OK)
    throw Error("PNG: compression failed");
  return n;
#endif
}

// Sum of the filtered bytes taken as signed values: the specification's
// heuristic for choosing a row's filter (12.8), smaller compresses better.
uint64_t signed_sum(const uint8_t* p, size_t n) {
  uint64_t s = 0;
  for (size_t i = 0; i < n; i++) s += p[i] < 128 ? p[i] : 256 - p[i];
  return s;
}

// Filters one row of n bytes (bpp bytes per pixel) into out: a filter-type
// byte and n filtered bytes. prev is the previous raw row (zeros above the
// first). The row takes Up or Sub, whichever leaves the smaller signed sum;
// Up is tried first and kept at once when it is all zeros, the common case
// of a row equal to the one above. None, Average and Paeth are not tried:
// on rendered pages they make files no smaller (within 1 %) and Paeth
// alone costs a third of the encoding time (BENCHMARKS.md).
void filter_row(const uint8_t* row, const uint8_t* prev, size_t n, int bpp, uint8_t* out, uint8_t* scratch) {
  uint8_t* up = out + 1;
  for (size_t i = 0; i < n; i++) up[i] = static_cast<uint8_t>(row[i] - prev[i]);
  const uint64_t s_up = signed_sum(up, n);
  out[0] = 2;
  if (s_up == 0) return;
  uint8_t* sub = scratch;
  for (size_t i = 0; i < size_t(bpp) && i < n; i++) sub[i] = row[i];
  for (size_t i = bpp; i < n; i++) sub[i] = static_cast<uint8_t>(row[i] - row[i - bpp]);
  if (signed_sum(sub, n) < s_up) {
    out[0] = 1;
    std::memcpy(up, sub, n);
  }
}

// Rows of raw samples (big-endian where 16-bit) -> the PNG bytes.
template <class Sample>
std::vector<uint8_t> encode(int width, int height, const Sample* rgba, const EncodeOptions& options) {
  if (width <= 0 || height <= 0) throw Error("PNG: empty image");
  constexpr int bytes = sizeof(Sample);
  constexpr Sample max = static_cast<Sample>(~Sample(0));
  const size_t pixels = size_t(width) * size_t(height);
  bool opaque = true;
  for (size_t i = 0; i < pixels && opaque; i++) opaque = rgba[4 * i + 3] == max;
  const int channels = opaque ? 3 : 4, bpp = channels * bytes;
  const size_t n = size_t(width) * bpp;

  Scratch& sc = scratch();
  sc.filtered.resize((n + 1) * height);
  // This row and the one above (zeros above the first), and room for the
  // Sub candidate.
  sc.rows.resize(2 * n);
  sc.zero.assign(n, 0);
  sc.sub.resize(n);
  for (int y = 0; y < height; y++) {
    uint8_t* row = sc.rows.data() + (y & 1) * n;
    const uint8_t* prev = y ? sc.rows.data() + ((y + 1) & 1) * n : sc.zero.data();
    const Sample* src = rgba + size_t(y) * width * 4;
    uint8_t* d = row;
    for (int x = 0; x < width; x++, src += 4)
      for (int c = 0; c < channels; c++)
        if constexpr (bytes == 1) {
          *d++ = src[c];
        } else {
          *d++ = static_cast<uint8_t>(src[c] >> 8);
          *d++ = static_cast<uint8_t>(src[c]);
        }
    filter_row(row, prev, n, bpp, sc.filtered.data() + size_t(y) * (n + 1), sc.sub.data());
  }
  const size_t zlen = deflate(sc, options.level);
  const uint8_t* idat = sc.deflated.data();

  static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  std::vector<uint8_t> out(signature, signature + 8);
  out.reserve(zlen + 128);
  const uint8_t ihdr[13] = {uint8_t(width >> 24), uint8_t(width >> 16), uint8_t(width >> 8), uint8_t(width),
                            uint8_t(height >> 24), uint8_t(height >> 16), uint8_t(height >> 8), uint8_t(height),
                            uint8_t(8 * bytes),  // bit depth
                            uint8_t(opaque ? 2 : 6),  // colour type: RGB or RGBA
                            0, 0, 0};  // deflate, adaptive filtering, not interlaced
  put_chunk(out, "IHDR", ihdr, sizeof ihdr);
  // IDAT chunks of at most 1 MiB, within every reader's limits.
  constexpr size_t chunk = size_t(1) << 20;
  for (size_t at = 0; at < zlen; at += chunk) put_chunk(out, "IDAT", idat + at, std::min(chunk, zlen - at));
  put_chunk(out, "IEND", nullptr, 0);
  return out;
}

}  // namespace

std::vector<uint8_t> encode_rgba8(int width, int height, const uint8_t* rgba, const EncodeOptions& options) {
  return encode(width, height, rgba, options);
}

std::vector<uint8_t> encode_rgba16(int width, int height, const uint16_t* rgba, const EncodeOptions& options) {
  return encode(width, height, rgba, options);
}

void write_file(const std::string& path, const std::vector<uint8_t>& bytes) {
  FILE* f = path == "-" ? stdout : std::fopen(path.c_str(), "wb");
  if (!f) throw Error("cannot write '" + path + "'");
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const bool closed = f == stdout ? std::fflush(f) == 0 : std::fclose(f) == 0;
  if (!ok || !closed) throw Error("cannot write '" + path + "'");
}

std::string compressor() {
#if MPVG_HAVE_LIBDEFLATE
  return std::string("libdeflate ") + LIBDEFLATE_VERSION_STRING;
#else
  return std::string("zlib ") + ZLIB_VERSION;
#endif
}

}  // namespace mpvg::png
