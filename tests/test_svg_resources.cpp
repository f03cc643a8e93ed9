// External resources of SVG documents (parsers/svg/svg_resources.h): data:
// URIs, the read policy for local files (canonical paths inside the
// allowed folders, whole components, symbolic links followed, every
// network URL refused), gzip, image signatures, and raster decoding of the
// tiny images in testdata/images/ (made by scripts/make_test_images.py).
#include <unistd.h>
#include <zlib.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "lib/output/png_writer.h"
#include "parsers/svg/svg_resources.h"
#include "tests/catch.h"

using namespace mpvg;
using namespace mpvg::svg::detail;
namespace fs = std::filesystem;
using namespace std::string_literals;

namespace {

std::string text_of(const Resource& r) { return std::string(r.bytes.begin(), r.bytes.end()); }

std::vector<uint8_t> bytes_of(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }

void write_file(const fs::path& p, const std::string& content) {
  std::ofstream f(p, std::ios::binary);
  f << content;
}

// A scratch tree, removed at the end:
//   root/doc/img.png, root/doc/sub/a.svg, root/doc/link.png -> ../outside.png,
//   root/doc/inlink.png -> img.png, root/doc/up -> .., root/docs/x.png,
//   root/outside.png
struct Tree {
  fs::path root;
  Tree() {
    root = fs::temp_directory_path() / ("mpvg_resources_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "doc" / "sub");
    fs::create_directories(root / "docs");
    write_file(root / "doc" / "img.png", "inside");
    write_file(root / "doc" / "sub" / "a.svg", "<svg/>");
    write_file(root / "docs" / "x.png", "sibling");
    write_file(root / "outside.png", "outside");
    fs::create_symlink("../outside.png", root / "doc" / "link.png");
    fs::create_symlink("img.png", root / "doc" / "inlink.png");
    fs::create_directory_symlink("..", root / "doc" / "up");
  }
  ~Tree() { fs::remove_all(root); }
  std::string doc() const { return (root / "doc").string(); }
};

std::optional<Resource> fetch(const Tree& t, const std::string& href, std::string* why,
                              std::vector<std::string> extra = {}) {
  std::vector<std::string> allowed{t.doc()};
  allowed.insert(allowed.end(), extra.begin(), extra.end());
  return fetch_resource(href, t.doc(), allowed, why);
}

std::vector<uint8_t> gzip_of(const std::string& s) {
  z_stream zs{};
  REQUIRE(deflateInit2(&zs, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) == Z_OK);
  std::vector<uint8_t> out(deflateBound(&zs, s.size()) + 64);
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(s.data()));
  zs.avail_in = static_cast<uInt>(s.size());
  zs.next_out = out.data();
  zs.avail_out = static_cast<uInt>(out.size());
  REQUIRE(deflate(&zs, Z_FINISH) == Z_STREAM_END);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

}  // namespace

// ------------------------------------------------------------------ data: URIs

TEST_CASE("data: URIs: base64 with white space inside", "[svg][resources]") {
  std::string why;
  const auto r = fetch_resource("  data:image/png;base64, aGVs\n\t bG8g\r\nd29y bGQ= ", ".", {}, &why);
  REQUIRE(r);
  CHECK(text_of(*r) == "hello world");
  CHECK(r->mime == "image/png");
  CHECK(r->path.empty());
}

TEST_CASE("data: URIs: media type lower-cased, parameters dropped, base64 without padding", "[svg][resources]") {
  std::string why;
  const auto r = fetch_resource("DATA:Image/SVG+XML;charset=utf-8;BASE64,PHN2Zy8+", ".", {}, &why);
  REQUIRE(r);
  CHECK(r->mime == "image/svg+xml");
  CHECK(text_of(*r) == "<svg/>");
  const auto u = fetch_resource("data:;base64,PHN2Zy8", ".", {}, &why);
  REQUIRE(u);
  CHECK(u->mime.empty());
  CHECK(text_of(*u) == "<svg/");
}

TEST_CASE("data: URIs: percent-encoded text, and escapes inside base64", "[svg][resources]") {
  std::string why;
  const auto r = fetch_resource("data:image/svg+xml,%3Csvg%20a='1%'/%3e", ".", {}, &why);
  REQUIRE(r);
  CHECK(text_of(*r) == "<svg a='1%'/>");
  const auto e = fetch_resource("data:,", ".", {}, &why);
  REQUIRE(e);
  CHECK(e->bytes.empty());
  CHECK(e->mime.empty());
  const auto b = fetch_resource("data:;base64,aGVs%0AbG8%3D", ".", {}, &why);
  REQUIRE(b);
  CHECK(text_of(*b) == "hello");
}

TEST_CASE("data: URIs: malformed ones and oversized ones are refused with a reason", "[svg][resources]") {
  std::string why;
  CHECK_FALSE(fetch_resource("data:image/png;base64", ".", {}, &why));
  CHECK(why == "malformed data: URI (no ',')");
  CHECK_FALSE(fetch_resource("data:;base64,aGV$sbG8=", ".", {}, &why));
  CHECK(why == "invalid base64 data in a data: URI");
  CHECK_FALSE(fetch_resource("data:;base64,aGVsbG8=aGVs", ".", {}, &why));
  CHECK_FALSE(fetch_resource("data:;base64,aGVsb", ".", {}, &why));
  CHECK_FALSE(fetch_resource("data:;base64,aGVsbG8gd29ybGQ=", ".", {}, &why, 5));
  CHECK(why.find("larger than 5 bytes") != std::string::npos);
  CHECK_FALSE(fetch_resource("data:,0123456789", ".", {}, &why, 5));
  CHECK(fetch_resource("data:,01234", ".", {}, &why, 5));
}

// ------------------------------------------------------------------ local files

TEST_CASE("files: relative paths inside the document's folder are read", "[svg][resources]") {
  Tree t;
  std::string why;
  const auto r = fetch(t, "img.png", &why);
  REQUIRE(r);
  CHECK(text_of(*r) == "inside");
  CHECK(r->mime == "image/png");
  CHECK(r->path == fs::canonical(t.root / "doc" / "img.png").string());
  const auto s = fetch(t, "sub/../sub/a.svg", &why);
  REQUIRE(s);
  CHECK(s->mime == "image/svg+xml");
  // Percent escapes are decoded; a fragment or query is not part of the file.
  CHECK(fetch(t, "im%67.png#frag", &why));
  CHECK(fetch(t, "img.png?v=2", &why));
  // A symbolic link inside the tree to a file inside it: the real path.
  const auto l = fetch(t, "inlink.png", &why);
  REQUIRE(l);
  CHECK(l->path == r->path);
}

TEST_CASE("files: escapes out of the allowed folders are refused", "[svg][resources]") {
  Tree t;
  std::string why;
  CHECK_FALSE(fetch(t, "../outside.png", &why));
  CHECK(why.find("outside the folders the document may read") != std::string::npos);
  CHECK_FALSE(fetch(t, "sub/../../outside.png", &why));
  CHECK_FALSE(fetch(t, "nothing/../../outside.png", &why));
  // A symbolic link inside the folder that leads out of it.
  CHECK_FALSE(fetch(t, "link.png", &why));
  CHECK(why.find("outside") != std::string::npos);
  CHECK_FALSE(fetch(t, "up/outside.png", &why));
  // Absolute paths and file: URLs are held to the same rule.
  CHECK_FALSE(fetch(t, (t.root / "outside.png").string(), &why));
  CHECK_FALSE(fetch(t, "file://" + (t.root / "outside.png").string(), &why));
  // A sibling folder whose name starts like the allowed one is not inside it.
  CHECK_FALSE(fetch(t, "../docs/x.png", &why));
  CHECK_FALSE(fetch(t, (t.root / "docs" / "x.png").string(), &why));
  // Refused before asking whether the file exists.
  CHECK_FALSE(fetch(t, "../missing.png", &why));
  CHECK(why.find("outside") != std::string::npos);
}

TEST_CASE("files: extra allowed folders, absolute paths and file: URLs", "[svg][resources]") {
  Tree t;
  std::string why;
  const std::string outside = (t.root / "outside.png").string();
  CHECK(fetch(t, "../outside.png", &why, {t.root.string()}));
  CHECK(fetch(t, "link.png", &why, {t.root.string()}));
  CHECK(fetch(t, outside, &why, {t.root.string()}));
  CHECK(fetch(t, "file://" + outside, &why, {t.root.string()}));
  CHECK(fetch(t, "file://localhost" + outside, &why, {t.root.string()}));
  CHECK(fetch(t, "file:" + outside, &why, {t.root.string()}));
  CHECK(fetch(t, "../docs/x.png", &why, {(t.root / "docs").string()}));
  const auto f = fetch(t, "file://" + (t.root / "doc" / "img.png").string(), &why);
  REQUIRE(f);
  CHECK(text_of(*f) == "inside");
  CHECK_FALSE(fetch(t, "file://server" + outside, &why, {t.root.string()}));
  CHECK(why.find("naming a host") != std::string::npos);
}

TEST_CASE("files: missing files, folders and oversized files", "[svg][resources]") {
  Tree t;
  std::string why;
  CHECK_FALSE(fetch(t, "missing.png", &why));
  CHECK(why.rfind("cannot read 'missing.png': ", 0) == 0);
  CHECK_FALSE(fetch(t, "sub", &why));
  CHECK(why == "cannot read 'sub': not a regular file");
  CHECK_FALSE(fetch_resource("img.png", t.doc(), {t.doc()}, &why, 3));
  CHECK(why.find("larger than 3 bytes") != std::string::npos);
  CHECK_FALSE(fetch(t, "", &why));
  CHECK_FALSE(fetch(t, "#frag", &why));
  // No allowed folder at all: nothing is read.
  CHECK_FALSE(fetch_resource("img.png", t.doc(), {}, &why));
}

TEST_CASE("network URLs are never loaded", "[svg][resources]") {
  Tree t;
  std::string why;
  for (const char* href : {"http://example.com/a.png", "https://example.com/a.svg", "ftp://example.com/a.png",
                           "HTTPS://example.com/a.png", "//example.com/a.png", "javascript:alert(1)"}) {
    INFO(href);
    CHECK_FALSE(fetch(t, href, &why, {"/"}));
    CHECK(why.find("not loaded") != std::string::npos);
    CHECK(why.find('\n') == std::string::npos);
  }
}

// ------------------------------------------------------------------ gzip

TEST_CASE("gunzip: svgz data, corrupt data and decompression bombs", "[svg][resources]") {
  std::string why;
  const std::string svg = "<svg xmlns='http://www.w3.org/2000/svg'/>";
  const std::vector<uint8_t> gz = gzip_of(svg);
  const auto ok = gunzip(gz, &why);
  REQUIRE(ok);
  CHECK(*ok == svg);
  // Two members concatenated read as one stream (RFC 1952 §2.2).
  std::vector<uint8_t> two = gz;
  two.insert(two.end(), gz.begin(), gz.end());
  CHECK(gunzip(two, &why).value_or("") == svg + svg);

  std::vector<uint8_t> bad = gz;
  bad[bad.size() / 2] ^= 0x55;
  bad[bad.size() / 2 + 1] ^= 0xaa;
  CHECK_FALSE(gunzip(bad, &why));
  CHECK(why.rfind("corrupt gzip data", 0) == 0);
  CHECK_FALSE(gunzip(std::vector<uint8_t>(gz.begin(), gz.begin() + gz.size() / 2), &why));
  CHECK(why == "truncated gzip data");
  CHECK_FALSE(gunzip(bytes_of("not gzip"), &why));

  // A megabyte of zeros is about a kilobyte of gzip.
  const std::vector<uint8_t> bomb = gzip_of(std::string(1 << 20, '\0'));
  CHECK(bomb.size() < 4096);
  CHECK_FALSE(gunzip(bomb, &why, 100000));
  CHECK(why == "gzip data inflates to more than 100000 bytes");
  CHECK(gunzip(bomb, &why, 1 << 20).value_or("").size() == size_t(1) << 20);
}

// ------------------------------------------------------------------ signatures

TEST_CASE("sniff_image: signatures first, then the media type", "[svg][resources]") {
  CHECK(sniff_image(bytes_of("\x89PNG\r\n\x1a\n...."), "") == ImageKind::Png);
  CHECK(sniff_image(bytes_of("\xff\xd8\xff\xe0"), "image/png") == ImageKind::Jpeg);
  CHECK(sniff_image(bytes_of("GIF89a.."), "") == ImageKind::Gif);
  CHECK(sniff_image(bytes_of("GIF87a.."), "") == ImageKind::Gif);
  CHECK(sniff_image(bytes_of("RIFF\x10\0\0\0WEBPVP8 "s), "") == ImageKind::Webp);
  CHECK(sniff_image(bytes_of("RIFF\x10\0\0\0WAVEfmt "s), "") == ImageKind::Unknown);
  CHECK(sniff_image(bytes_of("\x1f\x8b\x08"), "") == ImageKind::Svgz);
  CHECK(sniff_image(bytes_of("<svg/>"), "") == ImageKind::Svg);
  CHECK(sniff_image(bytes_of("<?xml version='1.0'?><svg/>"), "") == ImageKind::Svg);
  CHECK(sniff_image(bytes_of("\xef\xbb\xbf \n\t<svg/>"), "") == ImageKind::Svg);
  CHECK(sniff_image(bytes_of("svg"), "image/svg+xml") == ImageKind::Svg);
  CHECK(sniff_image(bytes_of("...."), "image/jpg") == ImageKind::Jpeg);
  CHECK(sniff_image(bytes_of("...."), "IMAGE/PNG") == ImageKind::Png);
  CHECK(sniff_image(bytes_of("...."), "text/plain") == ImageKind::Unknown);
  CHECK(sniff_image({}, "") == ImageKind::Unknown);
}

// ------------------------------------------------------------------ decoding

namespace {

std::vector<uint8_t> read_bytes(const std::string& name) {
  std::ifstream f(fs::path(MPVG_SOURCE_DIR) / "testdata" / "images" / name, std::ios::binary);
  REQUIRE(f);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

std::shared_ptr<Image> decode(const std::string& name) {
  std::string why;
  auto im = decode_raster(read_bytes(name), &why);
  INFO(name << ": " << why);
  REQUIRE(im);
  return im;
}

bool has_oiio() { return oiio_decoder_available(); }

}  // namespace

TEST_CASE("decode: 8-bit RGBA PNG keeps straight alpha", "[svg][resources][decode]") {
  const auto im = decode("rgba8.png");
  CHECK(im->width == 2);
  CHECK(im->height == 2);
  CHECK(im->bits == 8);
  CHECK(im->rgba8 == std::vector<uint8_t>{255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 64, 255, 255, 255, 0});
}

TEST_CASE("decode: palette PNG with tRNS, greyscale with and without alpha", "[svg][resources][decode]") {
  const auto p = decode("palette_trns.png");
  CHECK(p->width == 3);
  CHECK(p->height == 2);
  CHECK(p->bits == 8);
  CHECK(p->rgba8 == std::vector<uint8_t>{255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0,  //
                                         0, 0, 255, 0, 0, 255, 0, 128, 255, 0, 0, 255});
  CHECK(decode("grey.png")->rgba8 == std::vector<uint8_t>{0, 0, 0, 255, 200, 200, 200, 255});
  CHECK(decode("grey_alpha.png")->rgba8 == std::vector<uint8_t>{50, 50, 50, 255, 200, 200, 200, 100});
}

TEST_CASE("decode: 16-bit PNGs give 16-bit images", "[svg][resources][decode]") {
  const auto c = decode("rgba16.png");
  CHECK(c->bits == 16);
  CHECK(c->rgba8.empty());
  CHECK(c->rgba16 == std::vector<uint16_t>{0x1234, 0x5678, 0x9abc, 0xffff, 0xfedc, 0xba98, 0x7654, 0x8000});
  const auto g = decode("grey16.png");
  CHECK(g->bits == 16);
  CHECK(g->rgba16 == std::vector<uint16_t>{0x0102, 0x0102, 0x0102, 0xffff, 0xf0e0, 0xf0e0, 0xf0e0, 0xffff});
}

TEST_CASE("decode: JPEG (RGB, grey, CMYK), GIF and WebP with OpenImageIO", "[svg][resources][decode]") {
  std::string why;
  if (!has_oiio()) {
    CHECK_FALSE(decode_raster(read_bytes("rgb.jpg"), &why));
    CHECK(why == "JPEG images need OpenImageIO (built with MPVG_IMAGE_IO=png)");
    CHECK_FALSE(decode_raster(read_bytes("rgb.gif"), &why));
    CHECK_FALSE(decode_raster(read_bytes("rgba.webp"), &why));
    return;
  }
  auto near = [](const Image& im, size_t pixel, std::array<int, 4> want, int tol) {
    for (int c = 0; c < 4; c++) {
      INFO("pixel " << pixel << " channel " << c);
      CHECK(std::abs(int(im.rgba8[pixel * 4 + c]) - want[c]) <= tol);
    }
  };
  const auto rgb = decode("rgb.jpg");
  CHECK(rgb->width == 8);
  CHECK(rgb->bits == 8);
  for (size_t i = 0; i < 64; i += 9) near(*rgb, i, {200, 100, 50, 255}, 2);
  const auto grey = decode("grey.jpg");
  for (size_t i = 0; i < 64; i += 9) near(*grey, i, {128, 128, 128, 255}, 1);
  // CMYK comes out as RGB (full magenta and yellow: red).
  const auto cmyk = decode("cmyk.jpg");
  for (size_t i = 0; i < 64; i += 9) near(*cmyk, i, {255, 0, 0, 255}, 2);
  const auto gif = decode("rgb.gif");
  CHECK(gif->rgba8 == std::vector<uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 0, 0, 0, 0});
  // WebP's decoder premultiplies; straight alpha comes back within rounding.
  const auto webp = decode("rgba.webp");
  near(*webp, 0, {255, 0, 0, 255}, 0);
  near(*webp, 1, {0, 255, 0, 128}, 1);
  near(*webp, 2, {0, 0, 255, 64}, 2);
  near(*webp, 3, {200, 100, 50, 200}, 1);
}

DecodeRequest at_most(size_t pixels) {
  DecodeRequest r;
  r.max_pixels = pixels;
  return r;
}

TEST_CASE("decode: size limits, broken and unknown data", "[svg][resources][decode]") {
  std::string why;
  CHECK_FALSE(decode_raster(read_bytes("rgba8.png"), &why, at_most(3)));
  CHECK(why == "image of 2x2 pixels is over the limit of 3 pixels");
  CHECK(decode_raster(read_bytes("rgba8.png"), &why, at_most(4)));
  std::vector<uint8_t> cut = read_bytes("rgba8.png");
  cut.resize(cut.size() / 2);
  CHECK_FALSE(decode_raster(cut, &why));
  CHECK(why.rfind("cannot decode the ", 0) == 0);
  CHECK_FALSE(decode_raster(bytes_of("<svg/>"), &why));
  CHECK(why == "not a PNG, JPEG, GIF or WebP image");
  CHECK_FALSE(decode_raster({}, &why));
  if (has_oiio()) {
    CHECK_FALSE(decode_raster(read_bytes("rgb.jpg"), &why, at_most(63)));
    CHECK(why == "image of 8x8 pixels is over the limit of 63 pixels");
  }
}

// The brute-force box average of a k x k block (fewer at the edges) with
// premultiplied alpha, rounded as RowReducer rounds.
std::array<int, 4> block_average(const std::vector<uint8_t>& px, int w, int h, int k, int ox, int oy) {
  uint64_t s[4] = {0, 0, 0, 0}, n = 0;
  for (int y = oy * k; y < std::min(h, oy * k + k); y++)
    for (int x = ox * k; x < std::min(w, ox * k + k); x++, n++) {
      const uint8_t* p = &px[(size_t(y) * w + x) * 4];
      for (int c = 0; c < 3; c++) s[c] += uint64_t(p[c]) * p[3];
      s[3] += p[3];
    }
  std::array<int, 4> out{};
  for (int c = 0; c < 3; c++) out[c] = s[3] ? int((s[c] + s[3] / 2) / s[3]) : 0;
  out[3] = int((s[3] + n / 2) / n);
  return out;
}

TEST_CASE("decode: reduced while decoding, k x k blocks averaged with premultiplied alpha", "[svg][resources][decode]") {
  // A 37 x 23 PNG of random texels (some transparent), written here.
  const int w = 37, h = 23;
  std::vector<uint8_t> px(size_t(w) * h * 4);
  uint32_t state = 12345;
  for (uint8_t& v : px) v = uint8_t((state = state * 1664525u + 1013904223u) >> 24);
  for (size_t i = 3; i < px.size(); i += 28) px[i] = 0;
  const std::vector<uint8_t> png = png::encode_rgba8(w, h, px.data());
  for (int k : {1, 2, 3, 5, 37}) {
    CAPTURE(k);
    DecodeRequest r;
    int asked_w = 0, asked_h = 0, full_w = 0, full_h = 0;
    r.reduction = [&](int iw, int ih) {
      asked_w = iw;
      asked_h = ih;
      return k;
    };
    std::string why;
    const auto im = decode_raster(png, &why, r, &full_w, &full_h);
    REQUIRE(im);
    CHECK(asked_w == w);
    CHECK(asked_h == h);
    CHECK(full_w == w);
    CHECK(full_h == h);
    REQUIRE(im->width == (w + k - 1) / k);
    REQUIRE(im->height == (h + k - 1) / k);
    for (int oy = 0; oy < im->height; oy++)
      for (int ox = 0; ox < im->width; ox++) {
        // k = 1 is the image as stored (colours kept under alpha 0).
        const uint8_t* own = &px[(size_t(oy) * w + ox) * 4];
        const std::array<int, 4> want =
            k == 1 ? std::array<int, 4>{own[0], own[1], own[2], own[3]} : block_average(px, w, h, k, ox, oy);
        const uint8_t* got = &im->rgba8[(size_t(oy) * im->width + ox) * 4];
        INFO("texel " << ox << ", " << oy);
        for (int c = 0; c < 4; c++) CHECK(int(got[c]) == want[c]);
      }
  }
  // The limit applies to the reduced size: 37 x 23 reduced by 4 is 10 x 6.
  DecodeRequest r;
  r.reduction = [](int, int) { return 4; };
  r.max_pixels = 60;
  std::string why;
  CHECK(decode_raster(png, &why, r));
  r.max_pixels = 59;
  CHECK_FALSE(decode_raster(png, &why, r));
}
