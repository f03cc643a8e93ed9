#include "lib/output/png_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "lib/output/output_file.h"
#include "core/error.h"
#include "cpu/png_encode.h"

#include <zlib.h>


#include "core/parallel.h"

#if MPVG_HAVE_LIBDEFLATE
#include <libdeflate.h>
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
  std::vector<uint8_t> filtered, deflated;
  std::vector<std::vector<uint8_t>> strips;  // the parallel path's deflated strips
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
size_t deflate_all(Scratch& s, const uint8_t* data, size_t size, int level) {
#if MPVG_HAVE_LIBDEFLATE
  level = level < 1 ? 1 : level > 12 ? 12 : level;
  if (!s.compressor || s.level != level) {
    if (s.compressor) libdeflate_free_compressor(s.compressor);
    s.compressor = libdeflate_alloc_compressor(level);
    s.level = level;
    if (!s.compressor) throw Error("PNG: out of memory");
  }
  const size_t bound = libdeflate_zlib_compress_bound(s.compressor, size);
  if (s.deflated.size() < bound) s.deflated.resize(bound);
  const size_t n = libdeflate_zlib_compress(s.compressor, data, size, s.deflated.data(), s.deflated.size());
  if (n == 0) throw Error("PNG: compression failed");
  return n;
#else
  uLongf n = compressBound(static_cast<uLong>(size));
  if (s.deflated.size() < n) s.deflated.resize(n);
  if (compress2(s.deflated.data(), &n, data, static_cast<uLong>(size), level < 1 ? 1 : level > 9 ? 9 : level) !=
      Z_OK)
    throw Error("PNG: compression failed");
  return n;
#endif
}

// Raw deflate of data[at, end) into out: primed with the 32 KiB before it
// (the stream's back-references may reach them: the strips join into one
// stream), ended by a sync flush (byte-aligned, not final) or, for the last
// strip, as the final block.
void deflate_strip(const uint8_t* data, size_t at, size_t end, bool last, int level, std::vector<uint8_t>& out) {
  z_stream z{};
  if (deflateInit2(&z, level < 1 ? 1 : level > 9 ? 9 : level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw Error("PNG: out of memory");
  const size_t dict = std::min<size_t>(at, 32768);
  if (dict) deflateSetDictionary(&z, data + at - dict, static_cast<uInt>(dict));
  out.resize(deflateBound(&z, static_cast<uLong>(end - at)) + 16);
  z.next_in = const_cast<uint8_t*>(data + at);
  z.avail_in = static_cast<uInt>(end - at);
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
  const bool ok = last ? rc == Z_STREAM_END : rc == Z_OK && z.avail_in == 0;
  out.resize(out.size() - z.avail_out);
  deflateEnd(&z);
  if (!ok) throw Error("PNG: compression failed");
}

// The zlib stream of the filtered rows (height rows of `stride` bytes) by
// libdeflate or zlib at `level` (2 and up), into sc.deflated; returns its
// length. With several threads, a large image is deflated in strips by zlib.
size_t deflate_filtered(Scratch& sc, const uint8_t* data, int height, size_t stride, int level, int threads) {
  const size_t size = stride * size_t(height);
  const int cores = hardware_threads();
  threads = threads > 0 ? threads : cores;
  // Strips of at least 64 rows and 256 KiB: below that, threads cost more
  // than they save.
  const int strips = std::max(1, std::min({threads, height / 64, static_cast<int>(size >> 18)}));
  if (strips == 1) return deflate_all(sc, data, size, level);
  auto first_row = [&](int k) { return static_cast<int>(int64_t(height) * k / strips); };
  sc.strips.resize(strips);
  std::vector<uint32_t> adler(strips);
  std::vector<size_t> lengths(strips);
  parallel_for(size_t(strips), strips, [&](size_t k) {
    const size_t at = size_t(first_row(int(k))) * stride, end = size_t(first_row(int(k) + 1)) * stride;
    adler[k] = static_cast<uint32_t>(::adler32(1, data + at, static_cast<uInt>(end - at)));
    lengths[k] = end - at;
    deflate_strip(data, at, end, k + 1 == size_t(strips), level, sc.strips[k]);
  });
  // The zlib stream: header (deflate, 32 KiB window, fastest), the strips,
  // the Adler-32 of all the data.
  size_t total = 2 + 4;
  for (const auto& st : sc.strips) total += st.size();
  if (sc.deflated.size() < total) sc.deflated.resize(total);
  uint8_t* d = sc.deflated.data();
  *d++ = 0x78;
  *d++ = 0x01;
  uLong a = adler[0];
  for (int k = 0; k < strips; k++) {
    std::memcpy(d, sc.strips[k].data(), sc.strips[k].size());
    d += sc.strips[k].size();
    if (k > 0) a = ::adler32_combine(a, adler[k], static_cast<z_off_t>(lengths[k]));
  }
  const uint8_t tail[4] = {uint8_t(a >> 24), uint8_t(a >> 16), uint8_t(a >> 8), uint8_t(a)};
  std::memcpy(d, tail, 4);
  return total;
}

// The PNG of filtered rows (height rows of 1 + width * channels *
// bit_depth / 8 bytes), deflated at options.level: stored (0), the PNG
// stage's deflate (1), libdeflate or zlib (2 and up).
std::vector<uint8_t> deflate_rows(Scratch& sc, int width, int height, int bit_depth, int channels,
                                  const uint8_t* rows, const EncodeOptions& options) {
  const uint32_t bpp = static_cast<uint32_t>(std::max(1, channels * bit_depth / 8));
  const size_t stride = (size_t(width) * channels * bit_depth + 7) / 8 + 1;
  const size_t size = stride * size_t(height);
  ImageData data;
  if (options.level <= 0) {
    store_zlib(rows, size, data.zlib);
  } else if (options.level == 1) {
    deflate_zlib(rows, size, bpp, static_cast<uint32_t>(stride), options.threads, data.zlib);
  } else {
    const size_t zlen = deflate_filtered(sc, rows, height, stride, options.level, options.threads);
    return wrap(width, height, bit_depth, channels, sc.deflated.data(), zlen);
  }
  return wrap(width, height, bit_depth, channels, data.zlib.data(), data.zlib.size());
}

// Samples of 8 or 16 bits -> the PNG bytes.
template <class Sample>
std::vector<uint8_t> encode(int width, int height, const Sample* rgba, const EncodeOptions& options) {
  if (width <= 0 || height <= 0) throw Error("PNG: empty image");
  constexpr int bytes = sizeof(Sample);
  Scratch& sc = scratch();
  const int channels = filter_image(rgba, width, height, options.threads, sc.filtered);
  return deflate_rows(sc, width, height, 8 * bytes, channels, sc.filtered.data(), options);
}

// The PNG of the unfiltered rows in sc.filtered's place: `raw` (height
// rows of `row_bytes`), filtered Up (specification 9.2, type 2: the byte
// above subtracted, bpp-free, so the same for 1-, 8- and 16-bit grey),
// deflated at options.level as encode() does.
std::vector<uint8_t> encode_raw(int width, int height, int bit_depth, int channels, const std::vector<uint8_t>& raw,
                                size_t row_bytes, const EncodeOptions& options) {
  Scratch& sc = scratch();
  const size_t stride = row_bytes + 1;
  sc.filtered.resize(stride * size_t(height));
  parallel_for(size_t(height), options.threads > 0 ? options.threads : hardware_threads(), [&](size_t y) {
    uint8_t* out = sc.filtered.data() + y * stride;
    const uint8_t* row = raw.data() + y * row_bytes;
    out[0] = 2;
    if (y == 0) {
      std::memcpy(out + 1, row, row_bytes);
    } else {
      const uint8_t* up = row - row_bytes;
      for (size_t i = 0; i < row_bytes; i++) out[1 + i] = static_cast<uint8_t>(row[i] - up[i]);
    }
  });
  return deflate_rows(sc, width, height, bit_depth, channels, sc.filtered.data(), options);
}

template <class Sample>
bool opaque(const Sample* rgba, size_t pixels) {
  constexpr Sample full = static_cast<Sample>(~Sample(0));
  for (size_t i = 0; i < pixels; i++)
    if (rgba[4 * i + 3] != full) return false;
  return true;
}

}  // namespace

std::vector<uint8_t> encode_filtered(int width, int height, const FilteredRows& rows, const EncodeOptions& options) {
  if (width <= 0 || height <= 0) throw Error("PNG: empty image");
  if ((rows.channels != 3 && rows.channels != 4) ||
      rows.rows.size() != (size_t(width) * rows.channels + 1) * size_t(height))
    throw Error("PNG: filtered rows of the wrong size");
  return deflate_rows(scratch(), width, height, 8, rows.channels, rows.rows.data(), options);
}

std::vector<uint8_t> encode_gray8(int width, int height, const uint8_t* rgba, Color color,
                                  const EncodeOptions& options) {
  if (width <= 0 || height <= 0) throw Error("PNG: empty image");
  const size_t w = size_t(width);
  if (color == Color::Mono) {
    // Eight pixels a byte, the leftmost in the high bit (specification 7.2).
    const size_t row_bytes = (w + 7) / 8;
    std::vector<uint8_t> raw(row_bytes * size_t(height), 0);
    for (int y = 0; y < height; y++) {
      const uint8_t* p = rgba + size_t(y) * w * 4;
      uint8_t* out = raw.data() + size_t(y) * row_bytes;
      for (size_t x = 0; x < w; x++, p += 4) {
        // Over white: g a + 255 (1 - a), rounded.
        const uint32_t g = gray_of(p[0], p[1], p[2]);
        const uint32_t over = (g * p[3] + 255 * (255 - p[3]) + 127) / 255;
        if (mono_white(over, static_cast<int>(x), y)) out[x >> 3] |= static_cast<uint8_t>(0x80 >> (x & 7));
      }
    }
    return encode_raw(width, height, 1, 1, raw, row_bytes, options);
  }
  const int channels = opaque(rgba, w * size_t(height)) ? 1 : 2;
  const size_t row_bytes = w * size_t(channels);
  std::vector<uint8_t> raw(row_bytes * size_t(height));
  for (size_t i = 0, n = w * size_t(height); i < n; i++) {
    const uint8_t* p = rgba + 4 * i;
    raw[i * channels] = static_cast<uint8_t>(gray_of(p[0], p[1], p[2]));
    if (channels == 2) raw[i * 2 + 1] = p[3];
  }
  return encode_raw(width, height, 8, channels, raw, row_bytes, options);
}

std::vector<uint8_t> encode_gray16(int width, int height, const uint16_t* rgba, const EncodeOptions& options) {
  if (width <= 0 || height <= 0) throw Error("PNG: empty image");
  const size_t w = size_t(width);
  const int channels = opaque(rgba, w * size_t(height)) ? 1 : 2;
  const size_t row_bytes = w * size_t(channels) * 2;
  std::vector<uint8_t> raw(row_bytes * size_t(height));
  // Big-endian samples (specification 7.1).
  auto put = [&raw](size_t at, uint32_t v) {
    raw[at] = static_cast<uint8_t>(v >> 8);
    raw[at + 1] = static_cast<uint8_t>(v);
  };
  for (size_t i = 0, n = w * size_t(height); i < n; i++) {
    const uint16_t* p = rgba + 4 * i;
    put(i * channels * 2, gray_of(p[0], p[1], p[2]));
    if (channels == 2) put(i * 4 + 2, p[3]);
  }
  return encode_raw(width, height, 16, channels, raw, row_bytes, options);
}

std::vector<uint8_t> wrap(int width, int height, int bit_depth, int channels, const uint8_t* zlib, size_t n) {
  static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  std::vector<uint8_t> out(signature, signature + 8);
  out.reserve(n + 128);
  const uint8_t ihdr[13] = {uint8_t(width >> 24), uint8_t(width >> 16), uint8_t(width >> 8), uint8_t(width),
                            uint8_t(height >> 24), uint8_t(height >> 16), uint8_t(height >> 8), uint8_t(height),
                            uint8_t(bit_depth),
                            // colour type: grey, grey and alpha, RGB or RGBA
                            uint8_t(channels == 1 ? 0 : channels == 2 ? 4 : channels == 3 ? 2 : 6),
                            0, 0, 0};  // deflate, adaptive filtering, not interlaced
  put_chunk(out, "IHDR", ihdr, sizeof ihdr);
  // IDAT chunks of at most 1 MiB, within every reader's limits.
  constexpr size_t chunk = size_t(1) << 20;
  for (size_t at = 0; at < n; at += chunk) put_chunk(out, "IDAT", zlib + at, std::min(chunk, n - at));
  put_chunk(out, "IEND", nullptr, 0);
  return out;
}

std::vector<uint8_t> encode_rgba8(int width, int height, const uint8_t* rgba, const EncodeOptions& options) {
  return encode(width, height, rgba, options);
}

std::vector<uint8_t> encode_rgba16(int width, int height, const uint16_t* rgba, const EncodeOptions& options) {
  return encode(width, height, rgba, options);
}

void set_resolution(std::vector<uint8_t>& png, double dpi_x, double dpi_y) {
  // After the signature (8 bytes) and IHDR (25): before IDAT, as the
  // specification orders pHYs (5.6).
  constexpr size_t kAfterIhdr = 8 + 25;
  if (!(dpi_x > 0) || png.size() < kAfterIhdr) return;
  if (!(dpi_y > 0)) dpi_y = dpi_x;
  auto per_metre = [](double dpi) { return static_cast<uint32_t>(std::min(4e9, std::lround(dpi / 0.0254) * 1.0)); };
  std::vector<uint8_t> data;
  put32(data, per_metre(dpi_x));
  put32(data, per_metre(dpi_y));
  data.push_back(1);  // unit: the metre
  std::vector<uint8_t> chunk;
  put_chunk(chunk, "pHYs", data.data(), data.size());
  png.insert(png.begin() + kAfterIhdr, chunk.begin(), chunk.end());
}

void write_file(const std::string& path, const std::vector<uint8_t>& bytes) { write_output(path, bytes); }

std::string compressor() {
#if MPVG_HAVE_LIBDEFLATE
  return std::string("libdeflate ") + LIBDEFLATE_VERSION_STRING;
#else
  return std::string("zlib ") + ZLIB_VERSION;
#endif
}

}  // namespace mpvg::png
