// The CPU executor of the PNG stage's filtering and compression
// (cpu/png_encode.h): core/output/png_filter.h's and core/output/deflate.h's functions in
// loops, chunk after chunk (chunks in parallel where given threads).
#include "cpu/png_encode.h"

#include <algorithm>
#include <cstring>

#include "core/output/deflate.h"
#include "core/parallel.h"
#include "core/output/png_filter.h"

namespace mpvg::png {

namespace {

template <class Sample>
int filter(const Sample* rgba, int width, int height, int threads, std::vector<uint8_t>& out) {
  const size_t pixels = size_t(width) * size_t(height);
  // (blocks of pixels without a branch each, so that the test vectorises)
  bool opaque = true;
  for (size_t i0 = 0; i0 < pixels && opaque; i0 += 1024) {
    bool all = true;
    for (size_t i = i0; i < std::min(pixels, i0 + 1024); i++) all &= opaque_pixel(rgba, i);
    opaque = all;
  }
  FilterLayout l;
  l.width = width;
  l.height = height;
  l.channels = opaque ? 3 : 4;
  l.sample_bytes = sizeof(Sample);
  out.resize(l.size());
  const size_t n = l.row_bytes();
  const int bpp = l.bpp();
  // Row by row over raw bytes (the row and the one above converted once),
  // so that the byte loops vectorise; the same functions as per pixel.
  auto rows = [&](int y0, int y1) {
    std::vector<uint8_t> raw(2 * n), zero(n, 0);
    auto convert = [&](int y, uint8_t* d) {
      if (sizeof(Sample) == 1 && bpp == 4) {
        std::memcpy(d, rgba + size_t(y) * width * 4, n);
        return;
      }
      if (sizeof(Sample) == 1 && bpp == 3) {  // an opaque page: alpha dropped (raw_byte's bytes 0-2)
        const Sample* s = rgba + size_t(y) * width * 4;
        for (int x = 0; x < width; x++, s += 4, d += 3) {
          d[0] = static_cast<uint8_t>(s[0]);
          d[1] = static_cast<uint8_t>(s[1]);
          d[2] = static_cast<uint8_t>(s[2]);
        }
        return;
      }
      for (int x = 0; x < width; x++)
        for (int k = 0; k < bpp; k++) *d++ = raw_byte(rgba, l, y, x, k);
    };
    if (y0 > 0) convert(y0 - 1, raw.data() + size_t((y0 + 1) & 1) * n);
    const size_t lead = std::min(n, size_t(bpp));  // bytes with no pixel to their left
    for (int y = y0; y < y1; y++) {
      uint8_t* b = raw.data() + size_t(y & 1) * n;
      const uint8_t* above = y > 0 ? raw.data() + size_t((y + 1) & 1) * n : zero.data();
      convert(y, b);
      uint32_t up = 0, sub = 0;  // n * 128 < 2^32
      for (size_t i = 0; i < n; i++) up += signed_cost(filter_byte(kFilterUp, b[i], 0, above[i]));
      for (size_t i = 0; i < lead; i++) sub += signed_cost(filter_byte(kFilterSub, b[i], 0, 0));
      for (size_t i = lead; i < n; i++) sub += signed_cost(filter_byte(kFilterSub, b[i], b[i - bpp], 0));
      uint8_t* r = out.data() + size_t(y) * l.stride() + 1;
      const uint8_t type = r[-1] = choose_filter(up, sub);
      if (type == kFilterUp) {
        for (size_t i = 0; i < n; i++) r[i] = filter_byte(kFilterUp, b[i], 0, above[i]);
      } else {
        for (size_t i = 0; i < lead; i++) r[i] = filter_byte(kFilterSub, b[i], 0, 0);
        for (size_t i = lead; i < n; i++) r[i] = filter_byte(kFilterSub, b[i], b[i - bpp], 0);
      }
    }
  };
  const int cores = hardware_threads();
  const int strips = threads == 1 ? 1 : std::max(1, std::min(threads > 0 ? threads : cores, height / 64));
  if (strips == 1) {
    rows(0, height);
  } else {
    parallel_for(size_t(strips), strips, [&](size_t k) {
      rows(static_cast<int>(int64_t(height) * k / strips), static_cast<int>(int64_t(height) * (k + 1) / strips));
    });
  }
  return l.channels;
}

// One chunk's deflated bytes and its data's Adler-32 part.
struct ChunkOut {
  std::vector<uint32_t> words;
  size_t bytes = 0;
  deflate::AdlerPart adler;
};

struct ChunkScratch {
  std::vector<uint32_t> tokens;
  uint16_t table[1 << deflate::kHashBits];
  deflate::BlockCode code;
  deflate::Frequencies freq;
};

void deflate_chunk(const uint8_t* data, size_t n, size_t chunk, const deflate::Candidates& cand, ChunkScratch& s,
                   ChunkOut& out) {
  using namespace deflate;
  const size_t begin = chunk * kChunk, end = std::min(n, begin + kChunk);
  const bool final = end == n;
  s.tokens.resize(kChunk);
  int count[kPiecesPerChunk] = {};
  const int pieces = static_cast<int>((end - begin + kPiece - 1) / kPiece);
  std::memset(&s.freq, 0, sizeof s.freq);
  const auto add = [](uint32_t* c, uint32_t v) { *c += v; };
  for (int k = 0; k < pieces; k++) {
    const size_t pb = begin + size_t(k) * kPiece, pe = std::min(end, pb + kPiece);
    uint32_t* t = s.tokens.data() + size_t(k) * kPiece;
    count[k] = parse_piece(data, pb, pe, cand, s.table, t);
    for (int i = 0; i < count[k]; i++) count_token(t[i], s.freq, add);
  }
  build_block_code(s.freq, final, s.code);
  uint64_t bit[kPiecesPerChunk + 1];
  bit[0] = s.code.header_bits;
  for (int k = 0; k < pieces; k++) {
    uint64_t b = 0;
    const uint32_t* t = s.tokens.data() + size_t(k) * kPiece;
    for (int i = 0; i < count[k]; i++) b += token_bits(t[i], s.code);
    bit[k + 1] = bit[k] + b;
  }
  out.adler = adler_part(data + begin, end - begin);
  out.words.assign(kSlotBytes / 4, 0);
  const size_t dynamic = dynamic_bytes(bit[pieces], s.code, final), stored = stored_bytes(end - begin);
  if (dynamic <= stored) {
    std::memcpy(out.words.data(), s.code.header, sizeof s.code.header);
    for (int k = 0; k < pieces; k++) {
      BitStream<PlainOr> bs(out.words.data(), bit[k], PlainOr{});
      const uint32_t* t = s.tokens.data() + size_t(k) * kPiece;
      for (int i = 0; i < count[k]; i++) put_token(bs, t[i], s.code);
      bs.flush();
    }
    put_block_end(out.words.data(), bit[pieces], s.code, final, PlainOr{});
    out.bytes = dynamic;
  } else {
    uint8_t* o = reinterpret_cast<uint8_t*>(out.words.data());
    for (size_t j = 0; j < stored; j++) o[j] = stored_byte(data + begin, end - begin, final, j);
    out.bytes = stored;
  }
}

void put_be32(std::vector<uint8_t>& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<uint8_t>(v >> s));
}

}  // namespace

int filter_image(const uint8_t* rgba, int width, int height, int threads, std::vector<uint8_t>& out) {
  return filter(rgba, width, height, threads, out);
}

int filter_image(const uint16_t* rgba, int width, int height, int threads, std::vector<uint8_t>& out) {
  return filter(rgba, width, height, threads, out);
}

ImageData compress_rgba8(const uint8_t* rgba, int width, int height, int threads) {
  thread_local std::vector<uint8_t> filtered;
  ImageData d;
  d.channels = filter_image(rgba, width, height, threads, filtered);
  deflate_zlib(filtered.data(), filtered.size(), static_cast<uint32_t>(d.channels),
               static_cast<uint32_t>(size_t(width) * d.channels + 1), threads, d.zlib);
  return d;
}

void deflate_zlib(const uint8_t* data, size_t n, uint32_t bpp, uint32_t stride, int threads, std::vector<uint8_t>& out) {
  using namespace deflate;
  const deflate::Candidates cand = png_candidates(bpp, stride);
  const size_t chunks = chunk_count(n);
  std::vector<ChunkOut> parts(chunks);
  if (threads == 1 || chunks == 1) {
    thread_local ChunkScratch s;
    for (size_t c = 0; c < chunks; c++) deflate_chunk(data, n, c, cand, s, parts[c]);
  } else {
    parallel_for(chunks, threads, [&](size_t c) {
      thread_local ChunkScratch s;
      deflate_chunk(data, n, c, cand, s, parts[c]);
    });
  }
  out.clear();
  out.push_back(0x78);  // deflate, 32 KiB window
  out.push_back(0x01);  // no dictionary, check bits (0x7801 % 31 == 0)
  AdlerPart sum;
  for (const ChunkOut& p : parts) {
    const uint8_t* b = reinterpret_cast<const uint8_t*>(p.words.data());
    out.insert(out.end(), b, b + p.bytes);
    sum = adler_join(sum, p.adler);
  }
  put_be32(out, adler_value(sum));
}

void store_zlib(const uint8_t* data, size_t n, std::vector<uint8_t>& out) {
  using namespace deflate;
  out.clear();
  out.push_back(0x78);
  out.push_back(0x01);
  const size_t bytes = stored_bytes(n);
  const size_t at = out.size();
  out.resize(at + bytes);
  for (size_t j = 0; j < bytes; j++) out[at + j] = stored_byte(data, n, true, j);
  put_be32(out, adler_value(adler_part(data, n)));
}

}  // namespace mpvg::png
