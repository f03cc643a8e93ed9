// OpenType SVG glyphs (OpenType 1.9, the SVG table) against their drawing
// written out: text in testdata/fonts/MpvgTestSvg.ttf (made by
// scripts/make-test-font.py) renders on the CPU backend to the pixels of
// the glyph elements of its documents drawn directly, in font units scaled
// by size / units per em at each glyph's pen position.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "frame/frame.h"
#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "text/color_glyph.h"
#include "text/text.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"

using namespace mpvg;

namespace {

// `body` in a 200 x 100 document rendered at 200 x 100 pixels, with the
// test fonts only.
std::vector<uint8_t> pixels(const std::string& body, std::vector<std::string>* warnings = nullptr) {
  svg::ParseOptions po;
  po.font_dirs = {std::string(MPVG_SOURCE_DIR) + "/testdata/fonts"};
  po.system_fonts = false;
  po.view = [](double, double) { return Affine{}; };
  const std::string svg = svg_test::document(body, R"(width="200" height="100")");
  const svg::ParseResult r = svg::parse_svg_string(svg, ".", po);
  if (warnings) *warnings = r.warnings;
  RenderOptions o;
  o.width = 200;
  o.height = 100;
  o.backend = Backend::Cpu;
  return to_rgba8(render_cpu(r.scene, o), o.gamma);
}

// The largest difference of a channel between two images of one size.
int max_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  int d = 0;
  for (size_t i = 0; i < a.size(); i++) d = std::max(d, std::abs(int(a[i]) - int(b[i])));
  return d;
}

bool blank(const std::vector<uint8_t>& image) {
  for (uint8_t v : image)
    if (v != 0) return false;
  return true;
}

// The glyphs of scripts/make-test-font.py's SVG_GLYPHS_2_3 and SVG_GLYPH_4,
// as placed at font-size 50 (0.05 user units per font unit) from the pen at
// (x, y); `fill` stands for currentColor.
std::string glyph2(double x, double y, const std::string& fill) {
  return "<defs><linearGradient id='g' x1='0' x2='1'><stop offset='0' stop-color='#f00'/>"
         "<stop offset='1' stop-color='#00f'/></linearGradient></defs>"
         "<g transform='translate(" + std::to_string(x) + " " + std::to_string(y) + ") scale(0.05)'>"
         "<rect x='100' y='-700' width='500' height='700' fill='url(#g)'/>"
         "<circle cx='350' cy='-350' r='150' fill='" + fill + "'/></g>";
}
// Its viewBox of 500 units on the em square doubles it.
std::string glyph4(double x, double y) {
  return "<g transform='translate(" + std::to_string(x) + " " + std::to_string(y) + ") scale(0.1)'>"
         "<path d='M50 -350 h250 v350 h-250 z' fill='#0a0' stroke='#000' stroke-width='10'/></g>";
}

}  // namespace

TEST_CASE("svg glyphs: the glyph element drawn at the pen, defs reachable, the rest not drawn", "[svg][text]") {
  std::vector<std::string> warnings;
  const std::vector<uint8_t> text =
      pixels("<text x='20' y='80' font-family='Mpvg Test SVG' font-size='50' fill='#804000'>&#xE000;&#xE001;</text>",
             &warnings);
  for (const std::string& w : warnings) UNSCOPED_INFO(w);
  CHECK(warnings.empty());
  // Each glyph advances 700 font units: 35 user units.
  const std::vector<uint8_t> direct = pixels(glyph2(20, 80, "#804000") + glyph4(55, 80));
  REQUIRE(!blank(direct));
  CHECK(max_difference(text, direct) <= 1);
}

TEST_CASE("svg glyphs: currentColor is black where the fill is a paint server", "[svg][text]") {
  const std::vector<uint8_t> text = pixels(
      "<defs><pattern id='p' width='1' height='1'/></defs>"
      "<text x='30' y='90' font-family='Mpvg Test SVG' font-size='50' fill='url(#p) #fff'>&#xE000;</text>");
  CHECK(max_difference(text, pixels(glyph2(30, 90, "#000"))) <= 1);
}

TEST_CASE("svg glyphs: a glyph document reads no file", "[svg][text]") {
  // The same image the document itself may try to read (its folder is
  // allowed), a glyph document may not.
  std::vector<std::string> own, glyph;
  pixels("<image href='x.png' width='10' height='10'/>", &own);
  pixels("<text x='30' y='90' font-family='Mpvg Test SVG' font-size='50'>&#xE002;</text>", &glyph);
  auto says = [](const std::vector<std::string>& warnings, const std::string& what) {
    for (const std::string& w : warnings)
      if (w.find(what) != std::string::npos) return true;
    return false;
  };
  CHECK(says(own, "cannot read 'x.png'"));
  CHECK(says(glyph, "'x.png' lies outside the folders the document may read"));
}

TEST_CASE("svg glyphs: fill-opacity fades the glyph as a whole", "[svg][text]") {
  // As a group of the glyph's drawing with that opacity (COLR's layers
  // take it the same way).
  const std::vector<uint8_t> text = pixels(
      "<text x='20' y='80' font-family='Mpvg Test SVG' font-size='50' fill='#804000' fill-opacity='0.4'>"
      "&#xE000;</text>");
  const std::vector<uint8_t> direct = pixels("<g opacity='0.4'>" + glyph2(20, 80, "#804000") + "</g>");
  CHECK(max_difference(text, direct) <= 1);
  CHECK(max_difference(text, pixels(glyph2(20, 80, "#804000"))) > 20);
  CHECK(blank(pixels("<text x='20' y='80' font-family='Mpvg Test SVG' font-size='50' fill-opacity='0'>"
                     "&#xE000;</text>")));
}

TEST_CASE("svg glyphs: synthetic oblique slants the glyph's drawing at its pen", "[svg][text]") {
  // The test font has no italic face: font-style italic slants each glyph
  // by a quarter of its height about its pen position, as outlines are.
  const std::vector<uint8_t> text = pixels(
      "<text x='40' y='80' font-family='Mpvg Test SVG' font-size='50' fill='#804000' font-style='italic'>"
      "&#xE000;&#xE001;</text>");
  auto slanted = [](double x, double y, const std::string& content) {
    return "<g transform='translate(" + std::to_string(x) + " " + std::to_string(y) + ") matrix(1 0 -0.25 1 0 0) "
           "translate(" + std::to_string(-x) + " " + std::to_string(-y) + ")'>" + content + "</g>";
  };
  const std::vector<uint8_t> direct = pixels(slanted(40, 80, glyph2(40, 80, "#804000")) + slanted(75, 80, glyph4(75, 80)));
  CHECK(max_difference(text, direct) <= 1);
  CHECK(max_difference(text, pixels(glyph2(40, 80, "#804000") + glyph4(75, 80))) > 100);
}

// COLR v1 glyphs (testdata/fonts/MpvgTestColrV1.ttf): text draws the scene
// of the glyph's paint graph (text/color_glyph.h, tested against the
// graphs in test_color_glyph) at the pen, scaled by the font size, with the
// text's fill as the foreground and its fill-opacity fading it as a whole.
TEST_CASE("colr v1 glyphs: text draws the paint graph's scene at the pen", "[svg][text][colr]") {
  text::FontDb db;
  db.add_dir(std::string(MPVG_SOURCE_DIR) + "/testdata/fonts");
  const int face = db.match({"Mpvg Test COLRv1"}, 400, false);
  REQUIRE(face >= 0);
  REQUIRE(db.faces()[face].family == "Mpvg Test COLRv1");
  const std::vector<text::ShapedGlyph> shaped = text::shape(db, face, "\xee\x84\x80", 1);  // U+E100
  REQUIRE(shaped.size() == 1);
  text::ColorGlyphOptions o;
  o.foreground = RGBA{0, 0.5f, 1, 1};
  const std::shared_ptr<const Scene> glyph = text::color_glyph_scene(db, face, shaped[0].glyph, o);
  std::vector<std::string> warnings;
  const std::vector<uint8_t> text = pixels(
      "<text x='30' y='80' font-family='Mpvg Test COLRv1' font-size='60' fill='#0080ff' fill-opacity='0.6'>"
      "&#xE100;</text>",
      &warnings);
  if (!glyph) {
    // FreeType without the COLR v1 API (Debian 12's): the glyph falls back
    // to its outline, and the document says why once.
    WARN("SKIPPED: this FreeType's COLR v1 API gives no paint graph");
    int said = 0;
    for (const std::string& w : warnings) said += w.find("COLR v1") != std::string::npos;
    CHECK(said == 1);
    CHECK(!blank(text));
    return;
  }
  for (const std::string& w : warnings) UNSCOPED_INFO(w);
  CHECK(warnings.empty());
  SceneBuilder b(200, 100);
  Group g;
  g.opacity = 0.6f;
  b.begin_group(g);
  b.append(*glyph, Affine::translate(30, 80) * Affine::scale(60, 60));
  b.end_group();
  RenderOptions ro;
  ro.width = 200;
  ro.height = 100;
  ro.backend = Backend::Cpu;
  const std::vector<uint8_t> direct = to_rgba8(render_cpu(b.finish(), ro), ro.gamma);
  REQUIRE(!blank(direct));
  CHECK(max_difference(text, direct) <= 1);
}
