#include "apps/png_writer.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "apps/output_file.h"
#include "core/error.h"

#include <zlib.h>

#include <thread>

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
  std::vector<uint8_t> filtered, rows, zero, sub, deflated;
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
size_t deflate_all(Scratch& s, int level) {
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

// Rows y0 .. y1-1 of the image, as raw samples (big-endian where 16-bit,
// `channels` of each pixel), filtered into out (a filter byte and the row,
// each). The row above y0 is converted again for its filters.
template <class Sample>
void filter_rows(const Sample* rgba, int width, int y0, int y1, int channels, uint8_t* out, Scratch& sc) {
  constexpr int bytes = sizeof(Sample);
  const int bpp = channels * bytes;
  const size_t n = size_t(width) * bpp;
  sc.rows.resize(2 * n);
  sc.zero.assign(n, 0);
  sc.sub.resize(n);
  auto raw = [&](int y, uint8_t* d) {
    const Sample* src = rgba + size_t(y) * width * 4;
    for (int x = 0; x < width; x++, src += 4)
      for (int c = 0; c < channels; c++)
        if constexpr (bytes == 1) {
          *d++ = src[c];
        } else {
          *d++ = static_cast<uint8_t>(src[c] >> 8);
          *d++ = static_cast<uint8_t>(src[c]);
        }
  };
  // This row and the one above (zeros above the first).
  if (y0 > 0) raw(y0 - 1, sc.rows.data() + ((y0 + 1) & 1) * n);
  for (int y = y0; y < y1; y++) {
    uint8_t* row = sc.rows.data() + (y & 1) * n;
    const uint8_t* prev = y ? sc.rows.data() + ((y + 1) & 1) * n : sc.zero.data();
    raw(y, row);
    filter_row(row, prev, n, bpp, out + size_t(y - y0) * (n + 1), sc.sub.data());
  }
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

// Rows of raw samples (big-endian where 16-bit) -> the PNG bytes.
template <class Sample>
std::vector<uint8_t> encode(int width, int height, const Sample* rgba, const EncodeOptions& options) {
  if (width <= 0 || height <= 0) throw Error("PNG: empty image");
  constexpr int bytes = sizeof(Sample);
  constexpr Sample max = static_cast<Sample>(~Sample(0));
  const size_t pixels = size_t(width) * size_t(height);
  bool opaque = true;
  for (size_t i = 0; i < pixels && opaque; i++) opaque = rgba[4 * i + 3] == max;
  const int channels = opaque ? 3 : 4;
  const size_t n = size_t(width) * channels * bytes;

  Scratch& sc = scratch();
  sc.filtered.resize((n + 1) * height);
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = options.threads > 0 ? options.threads : cores;
  // Strips of at least 64 rows and 256 KiB: below that, threads cost more
  // than they save.
  const int strips = std::max(1, std::min({threads, height / 64, static_cast<int>(sc.filtered.size() >> 18)}));
  size_t zlen = 0;
  if (strips == 1) {
    filter_rows(rgba, width, 0, height, channels, sc.filtered.data(), sc);
    zlen = deflate_all(sc, options.level);
  } else {
    auto first_row = [&](int k) { return static_cast<int>(int64_t(height) * k / strips); };
    parallel_for(size_t(strips), strips, [&](size_t k) {
      Scratch rows;  // this strip's row buffers
      const int y0 = first_row(int(k)), y1 = first_row(int(k) + 1);
      filter_rows(rgba, width, y0, y1, channels, sc.filtered.data() + size_t(y0) * (n + 1), rows);
    });
    sc.strips.resize(strips);
    std::vector<uint32_t> adler(strips);
    std::vector<size_t> lengths(strips);
    parallel_for(size_t(strips), strips, [&](size_t k) {
      const size_t at = size_t(first_row(int(k))) * (n + 1), end = size_t(first_row(int(k) + 1)) * (n + 1);
      adler[k] = static_cast<uint32_t>(::adler32(1, sc.filtered.data() + at, static_cast<uInt>(end - at)));
      lengths[k] = end - at;
      deflate_strip(sc.filtered.data(), at, end, k + 1 == size_t(strips), options.level, sc.strips[k]);
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
    zlen = total;
  }
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

void write_file(const std::string& path, const std::vector<uint8_t>& bytes) { write_output(path, bytes); }

std::string compressor() {
#if MPVG_HAVE_LIBDEFLATE
  return std::string("libdeflate ") + LIBDEFLATE_VERSION_STRING;
#else
  return std::string("zlib ") + ZLIB_VERSION;
#endif
}

}  // namespace mpvg::png
