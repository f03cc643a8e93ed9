// The <image> element: text dumps of the scene (as in test_svg_parser.cpp)
// for placement, sizes, filters and styling of raster images, the read
// policy as warnings, and SVG documents embedded as vectors, with their
// recursion cut. Images come from testdata/images/
// (scripts/make_test_images.py): wide4x2.png is 4 x 2 pixels, rgba8.png
// 2 x 2, nested/inner.svg a 20 x 10 document drawing a blue rect and
// rgba8.png on its right half.
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "lib/output/output_file.h"
#include "lib/output/png_writer.h"
#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "frame/scene_info.h"

namespace fs = std::filesystem;

namespace {

std::string images_dir() { return (fs::path(MPVG_SOURCE_DIR) / "testdata" / "images").string(); }

mpvg::svg::ParseResult parse(const std::string& body, const std::string& base = images_dir(),
                             const mpvg::svg::ParseOptions& options = {}) {
  return mpvg::svg::parse_svg_string(svg_test::document(body), base, options);
}

std::string dump_of(const std::string& body) { return mpvg::dump(parse(body).scene); }

// The lines of a dump that start with `prefix` (after any indentation).
std::string lines_of(const std::string& dump, const std::string& prefix) {
  return svg_test::dump_lines(dump, [&](std::string_view text, size_t) { return text.rfind(prefix, 0) == 0; });
}

// The texture line and the drawn rectangle of a document with one image.
std::string placed(const std::string& image_attributes) {
  const std::string d = dump_of("<image href=\"wide4x2.png\" " + image_attributes + "/>");
  return lines_of(d, "texture") + lines_of(d, "M ");
}

size_t fills_of(const mpvg::Scene& s) {
  size_t n = 0;
  for (const mpvg::ScenePath& p : s.paths) n += p.is_clip ? 0 : 1;
  return n;
}

bool has_warning_with(const mpvg::svg::ParseResult& r, const std::string& part) {
  for (const std::string& w : r.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace

// ------------------------------------------------------------------ raster placement

TEST_CASE("svg image: a raster is a texture paint on the rectangle it shows in", "[svg][image]") {
  // 4 x 2 pixels in a 40 x 40 viewport, xMidYMid meet: 10 units a pixel,
  // centred vertically; texel (i, j) covers [i, i+1] x [j, j+1] of the
  // texture space.
  CHECK(dump_of(R"~(<image x="10" y="20" width="40" height="40" href="wide4x2.png"/>)~") == R"~(scene 100 100
path 0 fill nonzero texture 0 opacity 1
  M 10 30 L 50 30 L 50 50 L 10 50 L 10 30 Z
texture 0 image 4x2x8 bicubic clamp clamp matrix(10 0 0 10 10 30)
stream F0
)~");
}

TEST_CASE("svg image: preserveAspectRatio, meet", "[svg][image]") {
  const std::string vp = R"~(x="10" y="20" width="40" height="40" )~";
  CHECK(placed(vp + R"~(preserveAspectRatio="xMinYMin")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(10 0 0 10 10 20)\n"
        "  M 10 20 L 50 20 L 50 40 L 10 40 L 10 20 Z\n");
  CHECK(placed(vp + R"~(preserveAspectRatio="xMaxYMax meet")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(10 0 0 10 10 40)\n"
        "  M 10 40 L 50 40 L 50 60 L 10 60 L 10 40 Z\n");
  // A tall viewport: the image fills the width whatever the x alignment.
  CHECK(placed(R"~(x="10" y="20" width="40" height="10" preserveAspectRatio="xMaxYMid")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(5 0 0 5 30 20)\n"
        "  M 30 20 L 50 20 L 50 30 L 30 30 L 30 20 Z\n");
}

TEST_CASE("svg image: preserveAspectRatio, slice and none", "[svg][image]") {
  const std::string vp = R"~(x="10" y="20" width="40" height="40" )~";
  // slice: 20 units a pixel, 80 x 40, clipped to the viewport.
  CHECK(placed(vp + R"~(preserveAspectRatio="xMidYMid slice")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(20 0 0 20 -10 20)\n"
        "  M 10 20 L 50 20 L 50 60 L 10 60 L 10 20 Z\n");
  CHECK(placed(vp + R"~(preserveAspectRatio="xMinYMin slice")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(20 0 0 20 10 20)\n"
        "  M 10 20 L 50 20 L 50 60 L 10 60 L 10 20 Z\n");
  CHECK(placed(vp + R"~(preserveAspectRatio="xMaxYMin slice")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(20 0 0 20 -30 20)\n"
        "  M 10 20 L 50 20 L 50 60 L 10 60 L 10 20 Z\n");
  // none: stretched to the viewport.
  CHECK(placed(vp + R"~(preserveAspectRatio="none")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(10 0 0 20 10 20)\n"
        "  M 10 20 L 50 20 L 50 60 L 10 60 L 10 20 Z\n");
  // An invalid value is the default, xMidYMid meet.
  CHECK(placed(vp + R"~(preserveAspectRatio="middle")~") == placed(vp));
}

TEST_CASE("svg image: auto sizes take the intrinsic size or keep its ratio", "[svg][image]") {
  CHECK(placed(R"~(x="5" y="6")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(1 0 0 1 5 6)\n"
        "  M 5 6 L 9 6 L 9 8 L 5 8 L 5 6 Z\n");
  CHECK(placed(R"~(x="5" y="6" width="auto" height="auto")~") == placed(R"~(x="5" y="6")~"));
  CHECK(placed(R"~(x="5" y="6" width="bad" height="1x")~") == placed(R"~(x="5" y="6")~"));
  // Only one given: the other from the aspect ratio (2:1).
  CHECK(placed(R"~(width="40")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(10 0 0 10 0 0)\n"
        "  M 0 0 L 40 0 L 40 20 L 0 20 L 0 0 Z\n");
  CHECK(placed(R"~(height="40" width="auto")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(20 0 0 20 0 0)\n"
        "  M 0 0 L 80 0 L 80 40 L 0 40 L 0 0 Z\n");
  // Percentages of the viewport.
  CHECK(placed(R"~(x="10%" width="50%" height="50%")~") ==
        "texture 0 image 4x2x8 bicubic clamp clamp matrix(12.5 0 0 12.5 10 12.5)\n"
        "  M 10 12.5 L 60 12.5 L 60 37.5 L 10 37.5 L 10 12.5 Z\n");
}

TEST_CASE("svg image: zero or negative sizes disable rendering", "[svg][image]") {
  for (const char* attrs : {R"~(width="0" height="10")~", R"~(width="10" height="0")~", R"~(width="-5")~",
                            R"~(height="-1" width="auto")~"}) {
    INFO(attrs);
    const auto r = parse(std::string("<image href=\"wide4x2.png\" ") + attrs + "/>");
    CHECK(r.scene.paths.empty());
    CHECK(r.warnings.empty());
  }
}

TEST_CASE("svg image: href wins over xlink:href; none means no image", "[svg][image]") {
  CHECK(lines_of(dump_of(R"~(<image href="rgba8.png" xlink:href="wide4x2.png"/>)~"), "texture") ==
        "texture 0 image 2x2x8 bicubic clamp clamp\n");
  CHECK(lines_of(dump_of(R"~(<image xlink:href="wide4x2.png"/>)~"), "texture") ==
        "texture 0 image 4x2x8 bicubic clamp clamp\n");
  const auto r = parse(R"~(<image width="10" height="10"/><image href=" " width="10" height="10"/>)~");
  CHECK(r.scene.paths.empty());
  CHECK(r.warnings.empty());
}

TEST_CASE("svg image: image-rendering picks the filter, inherited", "[svg][image]") {
  auto filter = [](const std::string& body) {
    const std::string t = lines_of(dump_of(body), "texture");
    return t.substr(t.find("x8 ") + 3, t.find(" clamp") - t.find("x8 ") - 3);
  };
  CHECK(filter(R"~(<image href="rgba8.png"/>)~") == "bicubic");
  CHECK(filter(R"~(<image href="rgba8.png" image-rendering="optimizeQuality"/>)~") == "bicubic");
  CHECK(filter(R"~(<image href="rgba8.png" image-rendering="high-quality"/>)~") == "bicubic");
  CHECK(filter(R"~(<image href="rgba8.png" image-rendering="smooth"/>)~") == "bilinear");
  CHECK(filter(R"~(<image href="rgba8.png" image-rendering="optimizeSpeed"/>)~") == "nearest");
  CHECK(filter(R"~(<image href="rgba8.png" style="image-rendering: pixelated"/>)~") == "nearest");
  CHECK(filter(R"~(<image href="rgba8.png" image-rendering="crisp-edges"/>)~") == "nearest");
  CHECK(filter(R"~(<g image-rendering="optimizeSpeed"><image href="rgba8.png"/></g>)~") == "nearest");
  CHECK(filter(R"~(<g image-rendering="optimizeSpeed"><image href="rgba8.png" image-rendering="auto"/></g>)~") ==
        "bicubic");
  // An invalid value is ignored: the inherited one applies.
  CHECK(filter(R"~(<g image-rendering="pixelated"><image href="rgba8.png" image-rendering="blurry"/></g>)~") ==
        "nearest");
}

TEST_CASE("svg image: transform, opacity, visibility, display and clip-path as for shapes", "[svg][image]") {
  // The rectangle stays in user space (the path's transform); the texture
  // maps texels through the same transform.
  const std::string d =
      dump_of(R"~(<image href="rgba8.png" width="10" height="10" transform="translate(5 5) scale(2)" opacity="0.5"/>)~");
  CHECK(lines_of(d, "path") == "path 0 fill nonzero texture 0 opacity 0.5 matrix(2 0 0 2 5 5)\n");
  CHECK(lines_of(d, "texture") == "texture 0 image 2x2x8 bicubic clamp clamp matrix(10 0 0 10 5 5)\n");
  CHECK(lines_of(d, "M ") == "  M 0 0 L 10 0 L 10 10 L 0 10 L 0 0 Z\n");
  CHECK(parse(R"~(<image href="rgba8.png" visibility="hidden"/>)~").scene.paths.empty());
  CHECK(parse(R"~(<g display="none"><image href="rgba8.png"/></g>)~").scene.paths.empty());
  CHECK(parse(R"~(<image href="rgba8.png" opacity="0"/>)~").scene.paths.empty());
  // clip-path with objectBoundingBox units: the box is the viewport, not
  // the smaller rectangle the image is drawn in.
  const std::string c = dump_of(R"~(<clipPath id="c" clipPathUnits="objectBoundingBox"><rect width="0.5" height="1"/></clipPath>)~"
                                R"~(<image href="wide4x2.png" x="10" y="20" width="40" height="40" clip-path="url(#c)"/>)~");
  CHECK(lines_of(c, "stream") == "stream ( C0 | F1 )\n");
  CHECK(lines_of(c, "path 0") == "path 0 clip nonzero matrix(40 0 0 40 10 20)\n");
  // A hidden image still has a bounding box.
  const std::string h = dump_of(R"~(<clipPath id="c" clipPathUnits="objectBoundingBox"><rect width="1" height="1"/></clipPath>)~"
                                R"~(<g clip-path="url(#c)"><image href="wide4x2.png" x="10" y="20" width="40" height="40" )~"
                                R"~(visibility="hidden"/><rect x="20" y="30" width="1" height="1"/></g>)~");
  CHECK(lines_of(h, "path 0") == "path 0 clip nonzero matrix(40 0 0 40 10 20)\n");
}

// ------------------------------------------------------------------ read policy

TEST_CASE("svg image: refused, missing and broken images warn and draw nothing", "[svg][image]") {
  struct Case {
    const char* href;
    const char* warning;
  } cases[] = {
      {"../golden/arcs.svg", "lies outside the folders the document may read"},
      {"http://example.com/image.png", "http: URLs are not loaded"},
      {"//example.com/image.png", "network references are not loaded"},
      {"missing.png", "cannot read 'missing.png': "},
      {"data:image/png;base64,iVBORw0KGgo=", "'data:image/png;base64,...': cannot decode the"},
      {"data:text/plain,hello", "'data:text/plain,...' is not a PNG, JPEG, GIF, WebP or SVG image"},
      {"data:image/svg+xml,%3Csvg", "<image> not rendered: 'data:image/svg+xml,...': XML parse error"},
      {"data:image/svg+xml,%3Chtml/%3E", "not rendered: "},
      {"data:;base64,!!!", "invalid base64"},
  };
  for (const Case& c : cases) {
    INFO(c.href);
    const auto r = parse(std::string("<image width=\"10\" height=\"10\" href=\"") + c.href + "\"/>");
    CHECK(r.scene.paths.empty());
    REQUIRE(r.warnings.size() == 1);
    CHECK(r.warnings[0].find(c.warning) != std::string::npos);
    CHECK(r.warnings[0].find('\n') == std::string::npos);
  }
}

TEST_CASE("svg image: allowed_dirs opens folders beyond the document's", "[svg][image]") {
  const std::string nested = (fs::path(images_dir()) / "nested").string();
  CHECK(fills_of(parse(R"~(<image href="../rgba8.png"/>)~", nested).scene) == 0);
  mpvg::svg::ParseOptions o;
  o.allowed_dirs = {images_dir()};
  CHECK(fills_of(parse(R"~(<image href="../rgba8.png"/>)~", nested, o).scene) == 1);
  CHECK(fills_of(parse("<image href=\"file://" + images_dir() + "/rgba8.png\"/>", nested, o).scene) == 1);
}

TEST_CASE("svg image: data: URIs of rasters", "[svg][image]") {
  // A 1 x 1 opaque red PNG.
  const auto r = parse(R"~(<image width="10" height="10" xlink:href="data:image/png;base64,
      iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4
      2mP4z8AAAAMBAQD3A0FDAAAAAElFTkSuQmCC"/>)~");
  CHECK(r.warnings.empty());
  CHECK(lines_of(mpvg::dump(r.scene), "texture") ==
        "texture 0 image 1x1x8 bicubic clamp clamp matrix(10 0 0 10 0 0)\n");
  REQUIRE(r.scene.textures.size() == 1);
  CHECK(r.scene.textures[0].image->rgba8 == std::vector<uint8_t>{255, 0, 0, 255});
}

// ------------------------------------------------------------------ SVG documents

TEST_CASE("svg image: an SVG document is embedded as vectors, clipped to what shows", "[svg][image]") {
  // inner.svg is 20 x 10; in a 40 x 40 viewport at (10, 20), meet: scale
  // 2, centred vertically (y 30). Its rgba8.png (one folder up from it)
  // covers its right half.
  const auto r = parse(R"~(<image x="10" y="20" width="40" height="40" href="nested/inner.svg"/>)~");
  CHECK(r.warnings.empty());
  CHECK(mpvg::dump(r.scene) == R"~(scene 100 100
path 0 clip nonzero
  M 10 30 L 50 30 L 50 50 L 10 50 L 10 30 Z
path 1 fill nonzero texture 0 opacity 1 matrix(2 0 0 2 10 30)
  M 10 0 L 20 0 L 20 10 L 10 10 L 10 0 Z
path 2 fill nonzero rgba(0,0,1,1) opacity 1 matrix(2 0 0 2 10 30)
  M 0 0 L 20 0 L 20 10 L 0 10 L 0 0 Z
texture 0 image 2x2x8 bicubic clamp clamp matrix(10 0 0 10 30 30)
stream ( C0 | F1 F2 )
)~");
  // svgz reads the same.
  CHECK(mpvg::dump(parse(R"~(<image x="10" y="20" width="40" height="40" href="nested/inner.svgz"/>)~").scene) ==
        mpvg::dump(r.scene));
}

TEST_CASE("svg image: SVG documents take auto sizes, slice and none, opacity", "[svg][image]") {
  // Intrinsic 20 x 10 at (5, 5).
  CHECK(lines_of(dump_of(R"~(<image x="5" y="5" href="nested/inner.svg"/>)~"), "path 2") ==
        "path 2 fill nonzero rgba(0,0,1,1) opacity 1 matrix(1 0 0 1 5 5)\n");
  // Height from the ratio: 40 x 20.
  CHECK(lines_of(dump_of(R"~(<image width="40" href="nested/inner.svg"/>)~"), "path 2") ==
        "path 2 fill nonzero rgba(0,0,1,1) opacity 1 matrix(2 0 0 2 0 0)\n");
  // slice in a square: scale 4, 80 x 40 from x = -20, clipped to the viewport.
  const std::string s =
      dump_of(R"~(<image width="40" height="40" preserveAspectRatio="xMidYMid slice" opacity="0.5" href="nested/inner.svg"/>)~");
  // Opacity on an embedded document is one group around it.
  CHECK(lines_of(s, "path") == "path 0 clip nonzero\n"
                               "path 1 fill nonzero texture 0 opacity 1 matrix(4 0 0 4 -20 0)\n"
                               "path 2 fill nonzero rgba(0,0,1,1) opacity 1 matrix(4 0 0 4 -20 0)\n");
  CHECK(lines_of(s, "group") == "group 0 opacity 0.5 normal\n");
  CHECK(lines_of(s, "M 0 0 L 40") == "  M 0 0 L 40 0 L 40 40 L 0 40 L 0 0 Z\n");
  CHECK(lines_of(dump_of(R"~(<image width="40" height="40" preserveAspectRatio="none" href="nested/inner.svg"/>)~"),
                 "path 2") == "path 2 fill nonzero rgba(0,0,1,1) opacity 1 matrix(2 0 0 4 0 0)\n");
  // Nothing inherits into the document: a red fill here stays ours.
  CHECK(lines_of(dump_of(R"~(<g fill="red"><image href="nested/inner.svg"/></g>)~"), "path 2") ==
        "path 2 fill nonzero rgba(0,0,1,1) opacity 1\n");
}

TEST_CASE("svg image: a document embedding itself draws one copy of itself", "[svg][image]") {
  const auto self = mpvg::svg::parse_svg_file((fs::path(images_dir()) / "self.svg").string());
  // The document's rect, and the copy's.
  CHECK(fills_of(self.scene) == 2);
  CHECK(has_warning_with(self, "<image> 'self.svg' embeds a document that is already being drawn"));
  // a -> b -> a: the second a is drawn, its b is cut.
  const auto cycle = mpvg::svg::parse_svg_file((fs::path(images_dir()) / "cycle_a.svg").string());
  CHECK(fills_of(cycle.scene) == 3);
  CHECK(has_warning_with(cycle, "<image> 'cycle_b.svg' embeds a document that is already being drawn"));
}

TEST_CASE("svg image: SVG images nest at most 8 deep", "[svg][image]") {
  // Each level a rect and an image of the next, as base64 data: URIs; 12
  // levels below the document.
  auto base64 = [](const std::string& s) {
    static const char* const abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < s.size(); i += 3) {
      uint32_t v = uint32_t(uint8_t(s[i])) << 16;
      if (i + 1 < s.size()) v |= uint32_t(uint8_t(s[i + 1])) << 8;
      if (i + 2 < s.size()) v |= uint8_t(s[i + 2]);
      out += abc[v >> 18];
      out += abc[(v >> 12) & 63];
      out += i + 1 < s.size() ? abc[(v >> 6) & 63] : '=';
      out += i + 2 < s.size() ? abc[v & 63] : '=';
    }
    return out;
  };
  std::string doc = "<svg xmlns='http://www.w3.org/2000/svg' width='10' height='10'><rect width='10' height='10'/></svg>";
  for (int i = 0; i < 12; i++)
    doc = "<svg xmlns='http://www.w3.org/2000/svg' width='10' height='10'><rect width='10' height='10'/>"
          "<image width='10' height='10' href='data:image/svg+xml;base64," +
          base64(doc) + "'/></svg>";
  const auto r = mpvg::svg::parse_svg_string(doc, images_dir());
  // The document and 8 levels below it.
  CHECK(fills_of(r.scene) == 9);
  CHECK(has_warning_with(r, "SVG images nested more than 8 deep"));
}

TEST_CASE("svg image: nested documents pass their warnings on", "[svg][image]") {
  const auto r = parse(R"~(<image href="data:image/svg+xml,%3Csvg xmlns='http://www.w3.org/2000/svg' width='5' height='5'%3E%3CforeignObject/%3E%3C/svg%3E"/>)~");
  CHECK(r.warnings == std::vector<std::string>{"<foreignObject> elements are not supported: ignored"});
}

TEST_CASE("svg image: embedded documents add a bounded number of segments", "[svg][image]") {
  // A document of one 200000-segment path (200001 with the closing line
  // of the fill), drawn 60 times through use (3 x 4 x 5): each embedding
  // copies it, so 49 fit in 10 million segments and the rest are not
  // rendered.
  std::string d = "M0 0";
  for (int i = 0; i < 100000; i++) d += "h1v1";
  std::string inner = "<svg xmlns='http://www.w3.org/2000/svg' width='10' height='10'><path d='" + d + "'/></svg>";
  std::string uri;
  for (char c : inner) uri += c == '<' ? std::string("%3C") : c == '>' ? std::string("%3E") : std::string(1, c);
  const auto r = parse("<defs><image id='i' width='10' height='10' href=\"data:image/svg+xml," + uri +
                       "\"/><g id='a'><use href='#i'/><use href='#i'/><use href='#i'/></g>"
                       "<g id='b'><use href='#a'/><use href='#a'/><use href='#a'/><use href='#a'/></g></defs>"
                       "<use href='#b'/><use href='#b'/><use href='#b'/><use href='#b'/><use href='#b'/>");
  CHECK(fills_of(r.scene) == 49);
  CHECK(has_warning_with(r, "embedded SVG documents would add more than 10000000 segments"));
}

TEST_CASE("svg image: a large raster drawn small is decoded reduced, placed as the full one", "[svg][image]") {
  // 4200 x 1000 texels (over 4 Mpixels) in a 40 x 10 box at 2 pixels a
  // unit: 0.0095 units, 0.019 pixels a texel, so blocks of k = 52 texels
  // make one: 81 x 20 texels of 52 x 0.0095238 = 0.495238 units.
  const fs::path dir = fs::temp_directory_path() / ("mpvg-reduce-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const int w = 4200, h = 1000;
  std::vector<uint8_t> px(size_t(w) * h * 4, 255);
  for (size_t i = 0; i < px.size(); i += 4) px[i + 1] = uint8_t(i / 4 % w * 255 / (w - 1));  // a ramp
  mpvg::write_output((dir / "big.png").string(), mpvg::png::encode_rgba8(w, h, px.data()));
  const auto r = parse(R"~(<image width="40" height="10" href="big.png"/>)~", dir.string());
  CHECK(r.warnings.empty());
  // Placed as the full image (meet: 9.5238 high, centred at y 0.238095).
  const std::string texture = lines_of(mpvg::dump(r.scene), "texture");
  CHECK(texture.rfind("texture 0 image 81x20x8 bicubic clamp clamp matrix(0.495238 0 0 0.495238 ", 0) == 0);
  CHECK(texture.find(" 0.238095)") != std::string::npos);
  const mpvg::Image& im = *r.scene.textures.at(0).image;
  // The ramp survives the averaging: texel 40 is the mean of 2080-2131.
  int sum = 0;
  for (int x = 40 * 52; x < 41 * 52; x++) sum += px[size_t(x) * 4 + 1];
  CHECK(int(im.rgba8[40 * 4 + 1]) == (sum + 26) / 52);
  // Limits apply to the reduced size; at full size it would be refused.
  mpvg::svg::ParseOptions small;
  small.max_image_pixels = 81 * 20 - 1;
  CHECK(has_warning_with(parse(R"~(<image width="40" height="10" href="big.png"/>)~", dir.string(), small),
                         "is over the limit of 1619 pixels"));
  fs::remove_all(dir);
}
