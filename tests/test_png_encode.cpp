// The PNG stage's filtering and compression (core/output/png_filter.h,
// core/output/deflate.h, their CPU executor cpu/png_encode.h), each part against
// an independent oracle: the symbol tables against RFC 1951's, code lengths
// against a brute-force Huffman and Kraft's equality, Adler-32 parts
// against zlib's adler32, the filters against the specification's formulas
// written out here, and every stream inflated by zlib back to its data.
// The GPU executor's bytes are compared with these in test_gpu.
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <queue>
#include <random>
#include <vector>

#include "core/output/deflate.h"
#include "cpu/png_encode.h"
#include "core/output/png_filter.h"
#include "tests/catch.h"

using namespace mpvg;
using namespace mpvg::deflate;

namespace {

std::vector<uint8_t> inflate_all(const std::vector<uint8_t>& z, size_t expected) {
  std::vector<uint8_t> out(expected + 16);
  uLongf n = static_cast<uLongf>(out.size());
  const int rc = uncompress(out.data(), &n, z.data(), static_cast<uLong>(z.size()));
  REQUIRE(rc == Z_OK);
  out.resize(n);
  return out;
}

// The cost of an optimal (unlimited) prefix code: Huffman's merging.
uint64_t huffman_cost(const std::vector<uint32_t>& freq) {
  std::priority_queue<uint64_t, std::vector<uint64_t>, std::greater<>> q;
  for (uint32_t f : freq)
    if (f) q.push(f);
  if (q.size() < 2) return q.empty() ? 0 : q.top();
  uint64_t cost = 0;
  while (q.size() > 1) {
    const uint64_t a = q.top();
    q.pop();
    const uint64_t b = q.top();
    q.pop();
    cost += a + b;
    q.push(a + b);
  }
  return cost;
}

// Data of several kinds: flat, runs, repeated strings far apart, noise.
std::vector<uint8_t> sample_data(size_t n, int kind, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> d(n);
  for (size_t i = 0; i < n; i++) {
    switch (kind) {
      case 0: d[i] = 0; break;
      case 1: d[i] = static_cast<uint8_t>((i / 37) % 5); break;
      case 2: d[i] = static_cast<uint8_t>(rng()); break;
      case 3: d[i] = i % 1500 < 40 ? static_cast<uint8_t>("the quick brown fox jumps over the dog"[i % 38]) : 0; break;
      default: d[i] = rng() % 8 == 0 ? static_cast<uint8_t>(rng()) : static_cast<uint8_t>(i % 7); break;
    }
  }
  return d;
}

}  // namespace

TEST_CASE("deflate: length and distance symbols are RFC 1951's (3.2.5)", "[png]") {
  const int lbase[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31,
                         35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
  const int lextra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
  for (int len = 3; len <= 258; len++) {
    int s = 28;
    while (lbase[s] > len) s--;
    int eb;
    uint32_t ex;
    INFO("length " << len);
    CHECK(length_symbol(uint32_t(len), eb, ex) == 257 + s);
    CHECK(eb == lextra[s]);
    CHECK(int(ex) == len - lbase[s]);
  }
  const int dbase[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129,
                         193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
  for (int d = 1; d <= 32768; d++) {
    int s = 29;
    while (dbase[s] > d) s--;
    const int extra = s < 4 ? 0 : s / 2 - 1;
    int eb;
    uint32_t ex;
    INFO("distance " << d);
    REQUIRE(distance_symbol(uint32_t(d), eb, ex) == s);
    REQUIRE(eb == extra);
    REQUIRE(int(ex) == d - dbase[s]);
  }
}

TEST_CASE("deflate: canonical codes follow RFC 1951's example (3.2.2)", "[png]") {
  const uint8_t len[8] = {3, 3, 3, 3, 3, 2, 4, 4};
  const uint16_t want[8] = {0b010, 0b011, 0b100, 0b101, 0b110, 0b00, 0b1110, 0b1111};
  uint16_t code[8];
  canonical_codes(len, 8, code);
  for (int s = 0; s < 8; s++) {
    uint16_t reversed = 0;
    for (int b = 0; b < len[s]; b++) reversed = uint16_t(reversed << 1 | ((code[s] >> b) & 1));
    CHECK(reversed == want[s]);
  }
}

TEST_CASE("deflate: code lengths are complete, within the limit, optimal where the limit allows", "[png]") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 400; trial++) {
    const int n = trial % 3 == 0 ? kLitLenSymbols : trial % 3 == 1 ? kDistSymbols : kCodeLengthSymbols;
    const int limit = n == kCodeLengthSymbols ? 7 : 15;
    std::vector<uint32_t> freq(n, 0);
    const int kind = trial % 4;
    for (int s = 0; s < n; s++) {
      if (rng() % 3 == 0 && kind != 3) continue;
      freq[s] = kind == 0 ? 1 + rng() % 5 : kind == 1 ? 1 + rng() % 60000 : kind == 2 ? 1u << (rng() % 17) : 1 + s;
    }
    if (kind == 2 && n >= 30)  // Fibonacci weights: an unlimited code far deeper than 15
      for (int s = 0, a = 1, b = 1; s < 25; s++, b = a + b, a = b - a) freq[s] = uint32_t(a);
    freq[0] = std::max(freq[0], 1u);
    freq[1] = std::max(freq[1], 1u);
    std::vector<uint8_t> len(n);
    huffman_lengths(freq.data(), n, limit, len.data());
    double kraft = 0;
    uint64_t cost = 0;
    int longest = 0;
    for (int s = 0; s < n; s++) {
      CHECK((len[s] == 0) == (freq[s] == 0));
      if (len[s]) kraft += std::ldexp(1.0, -len[s]);
      cost += uint64_t(freq[s]) * len[s];
      longest = std::max<int>(longest, len[s]);
    }
    INFO("trial " << trial);
    CHECK(kraft == 1.0);
    CHECK(longest <= limit);
    for (int a = 0; a < n; a++)
      for (int b = 0; b < n; b++)
        if (freq[a] && freq[b] && freq[a] > freq[b]) CHECK(len[a] <= len[b]);
    const uint64_t best = huffman_cost(freq);
    CHECK(cost >= best);
    if (kind == 0 || kind == 3) CHECK(cost == best);  // shallow codes: the limit never binds
  }
}

TEST_CASE("deflate: Adler-32 parts join to zlib's checksum", "[png]") {
  const auto d = sample_data(300000, 2, 3);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; trial++) {
    std::vector<size_t> cut{0, d.size()};
    for (int k = 0; k < trial % 6; k++) cut.push_back(rng() % d.size());
    std::sort(cut.begin(), cut.end());
    AdlerPart sum;
    for (size_t k = 0; k + 1 < cut.size(); k++) sum = adler_join(sum, adler_part(d.data() + cut[k], cut[k + 1] - cut[k]));
    CHECK(adler_value(sum) == uint32_t(adler32(1, d.data(), uInt(d.size()))));
  }
}

TEST_CASE("deflate: zlib inflates every stream back to its data", "[png]") {
  for (int kind = 0; kind < 5; kind++)
    for (size_t n : {size_t(1), size_t(2), size_t(300), size_t(kPiece - 1), size_t(kPiece + 1), kChunk - 1, kChunk,
                     kChunk + 1, 3 * kChunk + 4097, size_t(700001)}) {
      INFO("kind " << kind << ", " << n << " bytes");
      const auto d = sample_data(n, kind, unsigned(n));
      for (uint32_t stride : {4u, 301u, 4097u}) {
        std::vector<uint8_t> z;
        png::deflate_zlib(d.data(), n, stride == 301 ? 3 : 4, stride, 1, z);
        CHECK(inflate_all(z, n) == d);
        if (kind == 0 && n > 1000) CHECK(z.size() * 100 < n);  // flat data: a few bytes per chunk
        if (kind == 2) CHECK(z.size() <= n + 5 * (n / 65535 + 1) * chunk_count(n) + 6);  // noise: stored
      }
      std::vector<uint8_t> z;
      png::store_zlib(d.data(), n, z);
      CHECK(inflate_all(z, n) == d);
    }
}

TEST_CASE("deflate: the same bytes on one thread or several", "[png]") {
  const auto d = sample_data(5 * kChunk + 123, 4, 9);
  std::vector<uint8_t> one, three;
  png::deflate_zlib(d.data(), d.size(), 4, 4097, 1, one);
  png::deflate_zlib(d.data(), d.size(), 4, 4097, 3, three);
  CHECK(one == three);
}

TEST_CASE("png filter: rows are the specification's Sub or Up, whichever sums smaller", "[png]") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 24; trial++) {
    const int w = 1 + int(rng() % 90), h = 1 + int(rng() % 12);
    const bool opaque = trial % 2 == 0, wide = trial % 3 == 0;
    std::vector<uint16_t> px16(size_t(w) * h * 4);
    std::vector<uint8_t> px8(px16.size());
    for (size_t i = 0; i < px16.size(); i++) {
      const bool alpha = i % 4 == 3;
      // smooth rows and noise
      const uint32_t v = (trial % 4 < 2) ? uint32_t((i / 4) % w * 3 + (i / 4 / w) * (trial % 3)) : rng();
      px16[i] = alpha && opaque ? 65535 : static_cast<uint16_t>(v * 257);
      px8[i] = alpha && opaque ? 255 : static_cast<uint8_t>(v);
    }
    std::vector<uint8_t> out;
    const int channels = wide ? png::filter_image(px16.data(), w, h, 1, out) : png::filter_image(px8.data(), w, h, 1, out);
    CHECK(channels == (opaque ? 3 : 4));
    const int sb = wide ? 2 : 1, bpp = channels * sb;
    const size_t n = size_t(w) * bpp;
    REQUIRE(out.size() == (n + 1) * h);
    auto raw = [&](int y, size_t i) -> int {  // byte i of row y, big-endian samples
      if (y < 0) return 0;
      const size_t x = i / bpp, c = (i % bpp) / sb;
      const size_t at = (size_t(y) * w + x) * 4 + c;
      return wide ? (i % 2 == 0 ? px16[at] >> 8 : px16[at] & 255) : px8[at];
    };
    for (int y = 0; y < h; y++) {
      uint64_t up = 0, sub = 0;
      for (size_t i = 0; i < n; i++) {
        const int u = (raw(y, i) - raw(y - 1, i)) & 255, s = (raw(y, i) - (i >= size_t(bpp) ? raw(y, i - bpp) : 0)) & 255;
        up += u < 128 ? u : 256 - u;
        sub += s < 128 ? s : 256 - s;
      }
      const uint8_t type = out[y * (n + 1)];
      INFO("trial " << trial << " row " << y);
      CHECK(type == (up <= sub ? 2 : 1));
      for (size_t i = 0; i < n; i++) {
        const int ref = type == 2 ? raw(y - 1, i) : i >= size_t(bpp) ? raw(y, i - bpp) : 0;
        REQUIRE(out[y * (n + 1) + 1 + i] == ((raw(y, i) - ref) & 255));
      }
    }
    // several threads: the same rows
    std::vector<uint8_t> again;
    if (wide) png::filter_image(px16.data(), w, h, 3, again);
    else png::filter_image(px8.data(), w, h, 3, again);
    CHECK(again == out);
  }
}

TEST_CASE("png encode: an image's data inflates to its filtered rows", "[png]") {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 6; trial++) {
    const int w = 100 + trial * 173, h = 30 + trial * 41;
    std::vector<uint8_t> px(size_t(w) * h * 4);
    for (size_t i = 0; i < px.size(); i++) {
      const size_t x = (i / 4) % w, y = i / 4 / w;
      px[i] = trial % 2 && i % 4 == 3 ? 255 : (x / 9 + y / 5) % 3 == 0 ? static_cast<uint8_t>(rng()) : static_cast<uint8_t>(x + y);
    }
    const png::ImageData d = png::compress_rgba8(px.data(), w, h);
    std::vector<uint8_t> rows;
    CHECK(png::filter_image(px.data(), w, h, 1, rows) == d.channels);
    CHECK(inflate_all(d.zlib, rows.size()) == rows);
  }
}
