// The PNG encoder (lib/output/png_writer.h): what it writes, read back by the
// project's image decoder (OpenImageIO or libpng, neither of which shares
// code with the encoder), equals what it was given; opaque images become
// RGB; each row's filter is Sub or Up as the specification's heuristic
// picks; the file ends as a PNG must.
#include <zlib.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "lib/output/png_writer.h"
#include "cpu/png_encode.h"
#include "core/error.h"
#include "parsers/svg/svg_resources.h"
#include "tests/catch.h"

namespace {

using mpvg::png::encode_rgba16;
using mpvg::png::encode_rgba8;

uint32_t be32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b[at]) << 24 | uint32_t(b[at + 1]) << 16 | uint32_t(b[at + 2]) << 8 | b[at + 3];
}

struct Chunk {
  std::string type;
  std::vector<uint8_t> data;
};

// The file's chunks, each CRC checked with zlib's crc32.
std::vector<Chunk> chunks_of(const std::vector<uint8_t>& png) {
  static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  REQUIRE(png.size() >= 8);
  REQUIRE(std::equal(signature, signature + 8, png.begin()));
  std::vector<Chunk> out;
  for (size_t at = 8; at < png.size();) {
    REQUIRE(at + 12 <= png.size());
    const uint32_t n = be32(png, at);
    REQUIRE(at + 12 + n <= png.size());
    const uint32_t crc = static_cast<uint32_t>(crc32(0, png.data() + at + 4, n + 4));
    CHECK(be32(png, at + 8 + n) == crc);
    out.push_back({std::string(png.begin() + at + 4, png.begin() + at + 8),
                   std::vector<uint8_t>(png.begin() + at + 8, png.begin() + at + 8 + n)});
    at += 12 + n;
  }
  return out;
}

// The filtered rows: IDAT data concatenated and inflated with zlib.
std::vector<uint8_t> inflated_rows(const std::vector<uint8_t>& png, size_t expected) {
  std::vector<uint8_t> z;
  for (const Chunk& c : chunks_of(png))
    if (c.type == "IDAT") z.insert(z.end(), c.data.begin(), c.data.end());
  std::vector<uint8_t> out(expected + 1);
  uLongf n = static_cast<uLongf>(out.size());
  REQUIRE(uncompress(out.data(), &n, z.data(), static_cast<uLong>(z.size())) == Z_OK);
  out.resize(n);
  return out;
}

std::shared_ptr<mpvg::Image> decode(const std::vector<uint8_t>& png) {
  std::string why;
  auto image = mpvg::svg::detail::decode_raster(png, &why);
  INFO(why);
  REQUIRE(image);
  return image;
}

std::vector<uint8_t> random_rgba8(int w, int h, bool opaque, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> px(size_t(w) * h * 4);
  for (size_t i = 0; i < px.size(); i++) px[i] = (i % 4 == 3 && opaque) ? 255 : static_cast<uint8_t>(rng());
  return px;
}

}  // namespace

TEST_CASE("png writer: 8-bit RGBA read back exactly, widths from 1 pixel", "[png]") {
  for (int w : {1, 2, 7, 300})
    for (int h : {1, 5}) {
      const auto px = random_rgba8(w, h, false, unsigned(w * 31 + h));
      const auto png = encode_rgba8(w, h, px.data());
      const auto image = decode(png);
      CHECK(image->width == w);
      CHECK(image->height == h);
      CHECK(image->bits == 8);
      CHECK(image->rgba8 == px);
      CHECK(chunks_of(png)[0].data[9] == 6);  // RGBA
    }
}

TEST_CASE("png writer: an opaque image is written as RGB and read back opaque", "[png]") {
  const auto px = random_rgba8(33, 9, true, 5);
  const auto png = encode_rgba8(33, 9, px.data());
  const auto chunks = chunks_of(png);
  REQUIRE(chunks.front().type == "IHDR");
  CHECK(be32(chunks.front().data, 0) == 33);
  CHECK(be32(chunks.front().data, 4) == 9);
  CHECK(chunks.front().data[8] == 8);  // bit depth
  CHECK(chunks.front().data[9] == 2);  // RGB
  CHECK(chunks.back().type == "IEND");
  CHECK(chunks.back().data.empty());
  CHECK(decode(png)->rgba8 == px);
  // One translucent pixel keeps the alpha channel.
  auto translucent = px;
  translucent[4 * 100 + 3] = 254;
  CHECK(chunks_of(encode_rgba8(33, 9, translucent.data()))[0].data[9] == 6);
}

TEST_CASE("png writer: 16-bit values read back exactly, opaque or not", "[png]") {
  for (bool opaque : {false, true}) {
    std::mt19937 rng(opaque ? 3 : 4);
    const int w = 17, h = 6;
    std::vector<uint16_t> px(size_t(w) * h * 4);
    for (size_t i = 0; i < px.size(); i++) px[i] = (i % 4 == 3 && opaque) ? 65535 : static_cast<uint16_t>(rng());
    const auto png = encode_rgba16(w, h, px.data());
    CHECK(chunks_of(png)[0].data[8] == 16);
    CHECK(chunks_of(png)[0].data[9] == (opaque ? 2 : 6));
    const auto image = decode(png);
    REQUIRE(image->bits == 16);
    CHECK(image->rgba16 == px);
  }
}

TEST_CASE("png writer: each row takes Sub or Up, whichever leaves the smaller signed sum", "[png]") {
  // Row 0: a horizontal ramp (Sub leaves 3s, Up the ramp itself); row 1
  // equal to row 0 (Up leaves zeros); row 2 row 1 plus one (Up leaves 1s,
  // Sub 3s); rows 3-4 noise, read back exactly whatever their filters.
  const int w = 64, h = 5;
  std::vector<uint8_t> px = random_rgba8(w, h, true, 9);
  for (int x = 0; x < w; x++)
    for (int c = 0; c < 3; c++) {
      px[(0 * w + x) * 4 + c] = static_cast<uint8_t>(3 * x + c);
      px[(1 * w + x) * 4 + c] = static_cast<uint8_t>(3 * x + c);
      px[(2 * w + x) * 4 + c] = static_cast<uint8_t>(3 * x + c + 1);
    }
  const auto png = encode_rgba8(w, h, px.data());
  const size_t stride = size_t(w) * 3 + 1;
  const auto rows = inflated_rows(png, stride * h);
  REQUIRE(rows.size() == stride * h);
  CHECK(int(rows[0 * stride]) == 1);  // Sub
  CHECK(int(rows[1 * stride]) == 2);  // Up, all zeros
  CHECK(int(rows[2 * stride]) == 2);  // Up
  for (int y = 0; y < h; y++) CHECK((rows[y * stride] == 1 || rows[y * stride] == 2));
  CHECK(decode(png)->rgba8 == px);
}

TEST_CASE("png writer: large images span IDAT chunks; effort levels agree on pixels", "[png]") {
  const int w = 800, h = 500;  // 1.2 MB of noise: more than one 1 MiB IDAT
  const auto px = random_rgba8(w, h, true, 11);
  for (int level : {0, 1, 2, 6, 9}) {
    const auto png = encode_rgba8(w, h, px.data(), {level});
    int idat = 0;
    for (const Chunk& c : chunks_of(png)) idat += c.type == "IDAT";
    CHECK(idat >= 2);
    CHECK(decode(png)->rgba8 == px);
  }
}

TEST_CASE("png writer: strips deflated in parallel join into the same rows", "[png]") {
  // Images with structure (runs that reach back across strip boundaries)
  // and noise, 8 and 16 bits, opaque and not, strip counts 2 to 7: the
  // zlib stream (checksum included) inflates to the rows the one-thread
  // path filters, and the decoder reads the pixels back.
  const int w = 700, h = 450;
  for (bool opaque : {true, false}) {
    std::vector<uint8_t> px = random_rgba8(w, h, opaque, 21);
    for (int y = 0; y < h; y += 3)
      for (int x = 0; x < w; x++)
        for (int c = 0; c < 3; c++) px[(size_t(y) * w + x) * 4 + c] = static_cast<uint8_t>(x / 7 + c);
    const auto serial = encode_rgba8(w, h, px.data());
    const size_t stride = size_t(w) * (opaque ? 3 : 4) + 1;
    const auto rows = inflated_rows(serial, stride * h);
    for (int threads : {2, 3, 7}) {
      mpvg::png::EncodeOptions o;
      o.threads = threads;
      const auto png = encode_rgba8(w, h, px.data(), o);
      CHECK(png != serial);  // another stream: the strips are deflated apart
      CHECK(inflated_rows(png, stride * h) == rows);
      CHECK(decode(png)->rgba8 == px);
    }
  }
  std::vector<uint16_t> px16(size_t(w) * h * 4);
  std::mt19937 rng(5);
  for (auto& v : px16) v = static_cast<uint16_t>(rng() % 4 == 0 ? rng() : 0x1234);
  mpvg::png::EncodeOptions o;
  o.threads = 4;
  const auto png16 = encode_rgba16(w, h, px16.data(), o);
  CHECK(decode(png16)->rgba16 == px16);
}

TEST_CASE("png writer: rows filtered elsewhere give encode_rgba8's bytes", "[png]") {
  // png::encode_filtered (the rows filtered where the image was rendered,
  // deflated here): the same file as encode_rgba8 at every level, opaque
  // (RGB) or not, one thread or strips; rows of the wrong size are refused.
  const int w = 300, h = 170;
  for (bool opaque : {true, false}) {
    std::vector<uint8_t> px = random_rgba8(w, h, opaque, 31);
    for (int y = 0; y < h; y += 2)
      for (int x = 0; x < w; x++) px[(size_t(y) * w + x) * 4 + 1] = static_cast<uint8_t>(x / 5);
    mpvg::png::FilteredRows rows;
    rows.channels = mpvg::png::filter_image(px.data(), w, h, 1, rows.rows);
    CHECK(rows.channels == (opaque ? 3 : 4));
    for (int level : {0, 1, 2, 6}) {
      for (int threads : {1, 3}) {
        INFO("opaque " << opaque << ", level " << level << ", threads " << threads);
        mpvg::png::EncodeOptions o;
        o.level = level;
        o.threads = threads;
        const auto png = mpvg::png::encode_filtered(w, h, rows, o);
        CHECK(png == encode_rgba8(w, h, px.data(), o));
        CHECK(decode(png)->rgba8 == px);
      }
    }
    mpvg::png::FilteredRows short_rows = rows;
    short_rows.rows.pop_back();
    CHECK_THROWS_AS(mpvg::png::encode_filtered(w, h, short_rows), mpvg::Error);
  }
}

TEST_CASE("png writer: an unwritable path is an error", "[png]") {
  const auto png = encode_rgba8(1, 1, std::vector<uint8_t>{1, 2, 3, 4}.data());
  CHECK_THROWS_AS(mpvg::png::write_file("/nonexistent-dir/x.png", png), mpvg::Error);
  CHECK_THROWS_AS(encode_rgba8(0, 3, nullptr), mpvg::Error);
}
