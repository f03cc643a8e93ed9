// SVG text layout (parsers/svg/svg_text.cpp) through the parser: where the
// glyph outlines land for positioning lists, chunks and anchors, spacing,
// white space and clip paths. The font is DejaVu Sans from Debian's
// fonts-dejavu-core (the set-up script installs it); without it the tests
// say so and skip.
#include <algorithm>
#include <filesystem>
#include <limits>
#include <string>

#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "frame/scene_info.h"

namespace {

const char* kFontDir = "/usr/share/fonts/truetype/dejavu";

bool have_font() { return std::filesystem::exists(std::string(kFontDir) + "/DejaVuSans.ttf"); }

mpvg::svg::ParseResult parse(const std::string& body) {
  mpvg::svg::ParseOptions o;
  o.font_dirs = {kFontDir};
  o.system_fonts = false;
  return mpvg::svg::parse_svg_string(
      "<svg xmlns='http://www.w3.org/2000/svg' width='400' height='200' font-family='DejaVu Sans' font-size='20'>" +
          body + "</svg>",
      ".", o);
}

struct Box {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  bool empty() const { return x0 > x1; }
};

// The bounding box of the control points of path instance i (in scene
// units), or of all fills.
Box box_of(const mpvg::Scene& s, int only = -1) {
  Box b;
  for (size_t i = 0; i < s.paths.size(); i++) {
    if (only >= 0 && int(i) != only) continue;
    const mpvg::ScenePath& p = s.paths[i];
    for (const mpvg::Vec2& q : s.geometries[p.geometry].points()) {
      const mpvg::Vec2 t = p.xf.apply(q);
      b.x0 = std::min(b.x0, t.x);
      b.x1 = std::max(b.x1, t.x);
      b.y0 = std::min(b.y0, t.y);
      b.y1 = std::max(b.y1, t.y);
    }
  }
  return b;
}

#define REQUIRE_FONT()                                                                   \
  if (!have_font()) {                                                                    \
    WARN("skipped: DejaVu Sans is not installed (Debian package fonts-dejavu-core)"); \
    return;                                                                              \
  }

}  // namespace

TEST_CASE("text: glyphs sit on the baseline at x, y, as curves", "[svg][text]") {
  REQUIRE_FONT();
  const auto r = parse("<text x='50' y='100'>H</text>");
  CHECK(r.warnings.empty());
  REQUIRE(r.scene.paths.size() == 1);
  const Box b = box_of(r.scene);
  // DejaVu Sans 'H': left bearing ~0.1 em, cap height 0.729 em, on the baseline.
  CHECK(b.x0 > 50);
  CHECK(b.x0 < 50 + 0.2 * 20);
  CHECK(b.y1 == Approx(100).margin(1e-9));
  CHECK(b.y0 == Approx(100 - 0.729 * 20).margin(0.2));
  // 'O' keeps its curves: quadratic segments, two contours.
  const auto o = parse("<text x='50' y='100'>O</text>");
  const mpvg::Path& g = o.scene.geometries[o.scene.paths[0].geometry];
  CHECK(g.contours().size() == 2);
  bool curves = false;
  for (const auto& seg : g.segments()) curves |= seg.type == mpvg::SegmentType::Quad;
  CHECK(curves);
}

TEST_CASE("text: text-anchor moves the chunk by its advance", "[svg][text]") {
  REQUIRE_FONT();
  const Box start = box_of(parse("<text x='200' y='100'>Hello</text>").scene);
  const Box middle = box_of(parse("<text x='200' y='100' text-anchor='middle'>Hello</text>").scene);
  const Box end = box_of(parse("<text x='200' y='100' text-anchor='end'>Hello</text>").scene);
  const double advance = start.x0 - end.x0;  // the chunk's width
  CHECK(advance > 40);
  CHECK(start.x0 - middle.x0 == Approx(advance / 2).margin(1e-6));
  CHECK(end.x1 < 200 + 1e-6);
  CHECK(end.x1 > 200 - 0.2 * 20);
}

TEST_CASE("text: x lists place characters; dx and dy shift them; chunks anchor apart", "[svg][text]") {
  REQUIRE_FONT();
  const auto a = parse("<text x='10 100 200' y='50'>HHH</text>");
  REQUIRE(a.scene.paths.size() == 1);
  const Box b = box_of(a.scene);
  CHECK(b.x1 > 200);  // the third H at 200
  CHECK(b.x1 < 200 + 20);
  const Box plain = box_of(parse("<text x='10' y='50'>HH</text>").scene);
  const Box shifted = box_of(parse("<text x='10' y='50' dx='0 30' dy='0 7'>HH</text>").scene);
  CHECK(shifted.x1 - plain.x1 == Approx(30).margin(1e-6));
  CHECK(shifted.y1 - plain.y1 == Approx(7).margin(1e-6));
  // A tspan's own list wins for its characters; its dx moves what follows too.
  const Box t = box_of(parse("<text x='10' y='50'>H<tspan dx='40'>H</tspan>H</text>").scene);
  CHECK(t.x1 - box_of(parse("<text x='10' y='50'>HHH</text>").scene).x1 == Approx(40).margin(1e-6));
}

TEST_CASE("text: each span is a path of its own with its own paint", "[svg][text]") {
  REQUIRE_FONT();
  // A span is one text node's characters, in document order: the text's
  // "Ab", the tspan's "Cd", the text's "Ef".
  const auto r = parse("<text x='10' y='50' fill='red'>Ab<tspan fill='blue'>Cd</tspan>Ef</text>");
  REQUIRE(r.scene.paths.size() == 3);
  std::vector<mpvg::RGBA> colours;
  for (const mpvg::ScenePath& p : r.scene.paths) colours.push_back(r.scene.paints[p.paint].color);
  CHECK((colours[0].r == 1 && colours[0].b == 0));
  CHECK((colours[1].b == 1 && colours[1].r == 0));
  CHECK((colours[2].r == 1 && colours[2].b == 0));
}

TEST_CASE("text: white space collapses unless xml:space='preserve'", "[svg][text]") {
  REQUIRE_FONT();
  const Box one = box_of(parse("<text x='10' y='50'>a b</text>").scene);
  const Box many = box_of(parse("<text x='10' y='50'>\n   a  \n\t  b   </text>").scene);
  CHECK(many.x0 == Approx(one.x0));
  CHECK(many.x1 == Approx(one.x1));
  const Box kept = box_of(parse("<text x='10' y='50' xml:space='preserve'>a   b</text>").scene);
  CHECK(kept.x1 > one.x1 + 10);
}

TEST_CASE("text: letter-spacing and word-spacing widen the line", "[svg][text]") {
  REQUIRE_FONT();
  const Box plain = box_of(parse("<text x='10' y='50'>ab cd</text>").scene);
  const Box letters = box_of(parse("<text x='10' y='50' letter-spacing='5'>ab cd</text>").scene);
  const Box words = box_of(parse("<text x='10' y='50' word-spacing='12'>ab cd</text>").scene);
  CHECK(letters.x1 - plain.x1 == Approx(4 * 5).margin(1e-6));  // after each of the first four characters
  CHECK(words.x1 - plain.x1 == Approx(12).margin(1e-6));
}

TEST_CASE("text: text in a clip path clips", "[svg][text]") {
  REQUIRE_FONT();
  const auto r = parse(
      "<clipPath id='c'><text x='10' y='50'>H</text></clipPath>"
      "<rect width='400' height='200' clip-path='url(#c)'/>");
  CHECK(r.warnings.empty());
  int clips = 0;
  for (const mpvg::ScenePath& p : r.scene.paths) clips += p.is_clip;
  CHECK(clips == 1);
}

TEST_CASE("text: decorations are bars under, over and through the glyphs, painted in order", "[svg][text]") {
  REQUIRE_FONT();
  const auto plain = parse("<text x='10' y='100'>Hello</text>");
  const auto under = parse("<text x='10' y='100' text-decoration='underline'>Hello</text>");
  REQUIRE(under.scene.paths.size() == 2);
  // The stream lists top-most first: the glyphs over the underline.
  const mpvg::Scene& s = under.scene;
  const int bar = int(s.stream[1].path), glyphs = int(s.stream[0].path);
  const Box b = box_of(s, bar), g = box_of(s, glyphs);
  CHECK((b.y0 + b.y1) / 2 > 100);  // centred below the baseline (the post table's position)
  CHECK(b.y1 < 100 + 5);           // DejaVu's underline: close under it
  CHECK(b.x0 == Approx(10).margin(1e-9));  // from the pen's start
  CHECK(b.x1 > g.x1);       // to its end, past the last glyph's ink
  CHECK(box_of(plain.scene).x1 == Approx(g.x1));
  // One bar for the run: a stroked decoration has no joins.
  CHECK(s.geometries[s.paths[bar].geometry].contours().size() == 1);
  // A line-through goes over the glyphs, above the baseline.
  const auto through = parse("<text x='10' y='100' text-decoration='line-through'>Hello</text>");
  const Box t = box_of(through.scene, int(through.scene.stream[0].path));
  CHECK(t.y1 < 100);
  CHECK(t.y0 > 100 - 0.729 * 20);
  // Declared outside the text, painted with the text's paint.
  const auto outside = parse("<g text-decoration='overline' fill='red'><text x='10' y='100' fill='blue'>Hi</text></g>");
  REQUIRE(outside.scene.paths.size() == 2);
  for (const mpvg::ScenePath& p : outside.scene.paths) CHECK(outside.scene.paints[p.paint].color.b == 1);
}

TEST_CASE("text: baseline-shift raises a span, nested shifts add; dominant-baseline moves the run", "[svg][text]") {
  REQUIRE_FONT();
  const auto r = parse("<text x='10' y='100'>H<tspan baseline-shift='5'>H<tspan baseline-shift='50%'>H</tspan></tspan></text>");
  REQUIRE(r.scene.paths.size() == 3);
  std::vector<double> bottoms;
  for (int i = 0; i < 3; i++) bottoms.push_back(box_of(r.scene, i).y1);
  std::sort(bottoms.begin(), bottoms.end());
  CHECK(bottoms[0] == Approx(100 - 5 - 10).margin(1e-9));  // 5 + 50% of 20
  CHECK(bottoms[1] == Approx(100 - 5).margin(1e-9));
  CHECK(bottoms[2] == Approx(100).margin(1e-9));
  // text-before-edge: the ascent line on y, the glyphs below it.
  const Box top = box_of(parse("<text x='10' y='100' dominant-baseline='text-before-edge'>H</text>").scene);
  CHECK(top.y0 > 100);
  const Box mid = box_of(parse("<text x='10' y='100' dominant-baseline='central'>H</text>").scene);
  CHECK(mid.y0 < 100);
  CHECK(mid.y1 > 100);
}

TEST_CASE("text: textPath lays glyphs along the path", "[svg][text]") {
  REQUIRE_FONT();
  // On a straight path the glyphs are those of plain text at startOffset,
  // to the accuracy distances along a path are found with (0.5 user units,
  // as resvg finds them).
  const Box straight = box_of(
      parse("<defs><path id='p' d='M 20 100 L 380 100'/></defs><text><textPath href='#p' startOffset='30'>Hello</textPath></text>")
          .scene);
  const Box plain = box_of(parse("<text x='50' y='100'>Hello</text>").scene);
  CHECK(straight.x0 == Approx(plain.x0).margin(0.5));
  CHECK(straight.x1 == Approx(plain.x1).margin(0.5));
  CHECK(straight.y0 == Approx(plain.y0).margin(1e-6));
  // A vertical path turns them a quarter turn: they stack down along x = 200.
  const Box down = box_of(
      parse("<defs><path id='p' d='M 200 10 L 200 190'/></defs><text><textPath href='#p'>Hello</textPath></text>").scene);
  CHECK(down.y1 - down.y0 > down.x1 - down.x0);
  // Turned clockwise with the path: what was above the baseline is right of it.
  CHECK(down.x0 > 200 - 0.3 * 20);
  CHECK(down.x1 > 200 + 0.5 * 20);
  // Glyphs past the path's end are not drawn.
  const auto shortp = parse("<defs><path id='p' d='M 20 100 L 40 100'/></defs><text><textPath href='#p'>Hello</textPath></text>");
  CHECK(box_of(shortp.scene).x1 < 45);
}

TEST_CASE("text: tref draws the referenced element's characters with its own style", "[svg][text]") {
  REQUIRE_FONT();
  const Box plain = box_of(parse("<text x='10' y='100'>Text</text>").scene);
  const auto r = parse("<defs><text id='t'>Te<tspan>xt</tspan></text></defs><text x='10' y='100' fill='blue'><tref href='#t'/></text>");
  REQUIRE(r.scene.paths.size() == 1);
  CHECK(box_of(r.scene).x1 == Approx(plain.x1).margin(1e-6));
  CHECK(r.scene.paints[r.scene.paths[0].paint].color.b == 1);
}

TEST_CASE("text: decorations break where dx moves a cluster", "[svg][text]") {
  REQUIRE_FONT();
  // One underline rectangle for a run of clusters, a new one after dx.
  // (The stream lists top-most first: the glyphs, then the underline.)
  auto rectangles = [](const mpvg::Scene& s) {
    return s.geometries[s.paths[s.stream[1].path].geometry].contours().size();
  };
  CHECK(rectangles(parse("<text x='10' y='50' text-decoration='underline'>Hello</text>").scene) == 1);
  // Every character with a dx value (0 too) starts a piece, as in resvg:
  // "H", "e", "llo".
  const auto broken = parse("<text x='10' y='50' text-decoration='underline' dx='0 0 20'>Hello</text>");
  CHECK(rectangles(broken.scene) == 3);
  // The pieces cover the advances, with the gap of 20 before "llo".
  const mpvg::Scene& s = broken.scene;
  const Box whole = box_of(s, int(s.stream[1].path));
  const Box plain = box_of(parse("<text x='10' y='50' text-decoration='underline'>Hello</text>").scene,
                           int(parse("<text x='10' y='50' text-decoration='underline'>Hello</text>").scene.stream[1].path));
  CHECK(whole.x0 == Approx(10).margin(1e-9));
  CHECK(whole.x1 - plain.x1 == Approx(20).margin(1e-6));
}

TEST_CASE("text: letter-spacing does not pull cursive scripts apart", "[svg][text]") {
  REQUIRE_FONT();
  const double arabic = box_of(parse("<text x='10' y='50'>\u0628\u064A\u062A</text>").scene).x1;
  const double spaced = box_of(parse("<text x='10' y='50' letter-spacing='20'>\u0628\u064A\u062A</text>").scene).x1;
  CHECK(spaced == Approx(arabic).margin(1e-9));
  const double latin = box_of(parse("<text x='10' y='50'>HHH</text>").scene).x1;
  const double latin_spaced = box_of(parse("<text x='10' y='50' letter-spacing='20'>HHH</text>").scene).x1;
  CHECK(latin_spaced - latin == Approx(40).margin(1e-6));  // not after the last
}

TEST_CASE("text: textLength stretches the spacing or the glyphs", "[svg][text]") {
  REQUIRE_FONT();
  const Box plain = box_of(parse("<text x='10' y='50'>HHHH</text>").scene);
  const Box spacing = box_of(parse("<text x='10' y='50' textLength='200'>HHHH</text>").scene);
  const Box glyphs = box_of(parse("<text x='10' y='50' textLength='200' lengthAdjust='spacingAndGlyphs'>HHHH</text>").scene);
  // Both end near 10 + 200, where the advances end (less the last glyph's
  // right side bearing).
  CHECK(spacing.x1 > 200);
  CHECK(spacing.x1 < 210);
  CHECK(glyphs.x1 > 200);
  CHECK(glyphs.x1 < 210);
  // spacingAndGlyphs widens the glyphs, not their height; spacing keeps
  // the first glyph where it was.
  CHECK(glyphs.y1 - glyphs.y0 == Approx(plain.y1 - plain.y0));
  CHECK(spacing.x0 == Approx(plain.x0));
  CHECK(glyphs.x0 - 10 > 2 * (plain.x0 - 10));
}

TEST_CASE("text: vertical writing runs down from x, y", "[svg][text]") {
  REQUIRE_FONT();
  const Box across = box_of(parse("<text x='100' y='20'>HHHH</text>").scene);
  const Box down = box_of(parse("<text x='100' y='20' writing-mode='tb'>HHHH</text>").scene);
  CHECK(across.x1 - across.x0 > across.y1 - across.y0);
  CHECK(down.y1 - down.y0 > down.x1 - down.x0);
  CHECK(down.y0 > 20 - 1);
  CHECK(down.y1 - down.y0 == Approx(across.x1 - across.x0).margin(2));
  // Latin turns clockwise: its ascenders point right... from the line at x.
  CHECK(down.x0 < 100);
}

TEST_CASE("text: textPath side='right' walks the path backwards", "[svg][text]") {
  REQUIRE_FONT();
  const char* path = "<defs><path id='p' d='M 20 100 L 380 100'/></defs>";
  const Box left = box_of(parse(std::string(path) + "<text><textPath href='#p'>Hello</textPath></text>").scene);
  const Box right = box_of(parse(std::string(path) + "<text><textPath href='#p' side='right'>Hello</textPath></text>").scene);
  // From the path's end, upside down: below the line, ending at x = 380.
  CHECK(left.y1 <= 100 + 5);
  CHECK(right.y0 >= 100 - 5);
  CHECK(right.x1 == Approx(380).margin(3));
  CHECK(right.x1 - right.x0 == Approx(left.x1 - left.x0).margin(1));
}

TEST_CASE("text: white space between tspans is kept", "[svg][text]") {
  REQUIRE_FONT();
  const Box joined = box_of(parse("<text x='10' y='50'><tspan>a</tspan><tspan>b</tspan></text>").scene);
  const Box spaced = box_of(parse("<text x='10' y='50'><tspan>a</tspan> <tspan>b</tspan></text>").scene);
  const Box one = box_of(parse("<text x='10' y='50'>a b</text>").scene);
  CHECK(spaced.x1 == Approx(one.x1));
  CHECK(spaced.x1 > joined.x1 + 3);
}

namespace {

// testdata/fonts (scripts/make-test-font.py): colour glyphs.
mpvg::svg::ParseResult parse_color(const std::string& body) {
  mpvg::svg::ParseOptions o;
  o.font_dirs = {std::string(MPVG_SOURCE_DIR) + "/testdata/fonts"};
  o.system_fonts = false;
  return mpvg::svg::parse_svg_string(
      "<svg xmlns='http://www.w3.org/2000/svg' width='400' height='200' font-family='Mpvg Test Color' "
      "font-size='50'>" + body + "</svg>", ".", o);
}

}  // namespace

TEST_CASE("text: COLR glyphs are their layers, palette colours and the text's fill", "[svg][text]") {
  const auto r = parse_color("<text x='10' y='60' fill='blue' stroke='black'>O</text>");
  REQUIRE(r.scene.paths.size() == 2);
  // The stream lists top-most first: the foreground bar over the red square.
  const mpvg::Scene& s = r.scene;
  const mpvg::ScenePath& square = s.paths[s.stream[1].path];
  const mpvg::ScenePath& bar = s.paths[s.stream[0].path];
  CHECK(s.paints[square.paint].color.r == 1);
  CHECK(s.paints[square.paint].color.b == 0);
  CHECK(s.paints[bar.paint].color.b == 1);
  // Layers are filled only; the square is 50..650 of 1000 units at 50.
  const Box b = box_of(s, int(s.stream[1].path));
  CHECK(b.x0 == Approx(10 + 2.5));
  CHECK(b.x1 == Approx(10 + 32.5));
  CHECK(b.y1 == Approx(60));
  CHECK(box_of(s, int(s.stream[0].path)).x0 == Approx(10 + 12.5));
}

TEST_CASE("text: bitmap glyphs are images on their rectangle", "[svg][text]") {
  const auto r = parse_color("<text x='10' y='60'>E</text>");
  REQUIRE(r.scene.paths.size() == 1);
  const mpvg::Scene& s = r.scene;
  CHECK(s.paints[s.paths[0].paint].type == mpvg::PaintType::Texture);
  REQUIRE(s.textures.size() == 1);
  CHECK(s.textures[0].image->width == 8);
  // 8 pixels at 8 per em: 50 units square, its lower left corner at the
  // outline box's (0, -100) units, i.e. 5 below the baseline.
  const Box b = box_of(s, 0);
  CHECK(b.x0 == Approx(10).margin(0.01));
  CHECK(b.x1 == Approx(60).margin(0.01));
  CHECK(b.y1 == Approx(65).margin(0.5));
  CHECK(b.y1 - b.y0 == Approx(50).margin(0.01));
}

TEST_CASE("text: synthetic oblique and bold where the family has no such face", "[svg][text]") {
  // Lohit Devanagari has one face, regular and upright.
  const char* lohit = "/usr/share/fonts/truetype/lohit-devanagari";
  if (!std::filesystem::exists(lohit)) {
    WARN("skipped: Lohit Devanagari is not installed (Debian package fonts-lohit-deva)");
    return;
  }
  mpvg::svg::ParseOptions o;
  o.font_dirs = {lohit};
  o.system_fonts = false;
  auto lo = [&](const char* style) {
    return box_of(mpvg::svg::parse_svg_string(std::string("<svg xmlns='http://www.w3.org/2000/svg' width='400' height='200' "
                                                          "font-family='Lohit Devanagari' font-size='20'><text x='10' y='100' ") +
                                                  style + ">l</text></svg>",
                                              ".", o)
                      .scene);
  };
  // Italic slants the upright face by a quarter of the height, to the right
  // above the baseline; the stem's foot stays.
  const Box upright = lo(""), slanted = lo("font-style='italic'");
  CHECK(slanted.y0 == Approx(upright.y0));
  CHECK(slanted.x1 - upright.x1 == Approx(0.25 * (100 - upright.y0)).margin(1e-6));
  CHECK(slanted.x0 == Approx(upright.x0));
  // Bold grows the outlines by 1/32 em (20 / 32 units) overall.
  const Box bold = lo("font-weight='bold'");
  CHECK((bold.x1 - bold.x0) - (upright.x1 - upright.x0) == Approx(20.0 / 32).margin(0.05));
  CHECK((bold.y1 - bold.y0) - (upright.y1 - upright.y0) == Approx(20.0 / 32).margin(0.05));
}

TEST_CASE("text: the font shorthand, overridden by longhands; font-size-adjust", "[svg][text]") {
  REQUIRE_FONT();
  const Box h20 = box_of(parse("<text x='10' y='100' font-size='40'>H</text>").scene);
  const Box shorthand = box_of(parse("<text x='10' y='100' font='bold 40px DejaVu Sans'>H</text>").scene);
  const Box bold = box_of(parse("<text x='10' y='100' font-size='40' font-weight='bold'>H</text>").scene);
  CHECK(shorthand.x1 == Approx(bold.x1));
  CHECK(shorthand.y0 == Approx(h20.y0));
  // A plain number before the size is a weight; a longhand after wins.
  const Box weight = box_of(parse("<text x='10' y='100' style='font: 700 40px/1.2 DejaVu Sans'>H</text>").scene);
  CHECK(weight.x1 == Approx(bold.x1));
  const Box longhand = box_of(parse("<text x='10' y='100' font='bold 10px DejaVu Sans' font-size='40'>H</text>").scene);
  CHECK(longhand.x1 == Approx(bold.x1));
  // font-size-adjust 0.5: the x-height is half the font size, whatever the
  // face's own aspect.
  const Box x = box_of(parse("<text x='10' y='100' font-size='40' font-size-adjust='0.5'>x</text>").scene);
  CHECK(100 - x.y0 == Approx(20).margin(0.05));
}

TEST_CASE("text: objectBoundingBox paint servers use the glyph cells' box", "[svg][text]") {
  REQUIRE_FONT();
  // A gradient across the text's box: the cells span the advance and the
  // font's ascent to descent, wider than the ink of "ll" (side bearings) and
  // taller (the descent): the gradient vector equals the cells' box.
  const auto r = parse("<linearGradient id='g'><stop offset='0' stop-color='red'/><stop offset='1' stop-color='blue'/>"
                       "</linearGradient><text x='10' y='100' fill='url(#g)'>ll</text>");
  const mpvg::Scene& s = r.scene;
  REQUIRE(s.paths.size() == 1);
  const Box ink = box_of(s);
  // The gradient's transform maps (0,0)-(1,0) to the box's left and right.
  const mpvg::Paint& p = s.paints[s.paths[0].paint];
  REQUIRE(p.type == mpvg::PaintType::LinearGradient);
  const mpvg::Affine& xf = s.gradients[p.index].xf;
  CHECK(xf.apply({0, 0}).x == Approx(10).margin(1e-6));  // the pen's start, left of the ink
  CHECK(xf.apply({0, 0}).x < ink.x0);
  CHECK(xf.apply({1, 0}).x > ink.x1);
  CHECK(xf.apply({0, 1}).y > 100);  // the descent, below the baseline
}

TEST_CASE("text: text-rendering optimizeSpeed draws glyphs without antialiasing; shape-rendering does not", "[svg][text]") {
  REQUIRE_FONT();
  auto all = [](const mpvg::Scene& s, bool aliased) {
    bool ok = !s.paths.empty();
    for (const mpvg::ScenePath& p : s.paths) ok = ok && p.aliased == aliased;
    return ok;
  };
  CHECK(all(parse("<text x='10' y='50' text-rendering='optimizeSpeed' text-decoration='underline'>Ab</text>").scene,
            true));
  CHECK(all(parse("<g text-rendering='optimizeSpeed'><text x='10' y='50' text-rendering='optimizeLegibility'>Ab</text></g>")
                .scene,
            false));
  CHECK(all(parse("<text x='10' y='50' shape-rendering='crispEdges'>Ab</text>").scene, false));
  // In a clip path too.
  const auto r = parse("<clipPath id='c'><text x='10' y='50' text-rendering='optimizeSpeed'>Ab</text></clipPath>"
                       "<rect width='100' height='100' clip-path='url(#c)'/>");
  int aliased_clips = 0;
  for (const mpvg::ScenePath& p : r.scene.paths) aliased_clips += p.is_clip && p.aliased;
  CHECK(aliased_clips >= 1);
}

TEST_CASE("text: the text-decoration shorthand's grammar", "[svg][text]") {
  REQUIRE_FONT();
  // CSS Text Decoration 3 §2.4: lines, a style and a colour in any order,
  // keywords in any case; none alone; anything else invalid, so the
  // cascade falls back (here to the attribute's overline).
  auto paths = [](const std::string& value) {
    return parse("<text x='10' y='50' text-decoration='overline' style='text-decoration: " + value +
                 "'>Hi</text>").scene.paths.size();
  };
  const size_t none = parse("<text x='10' y='50'>Hi</text>").scene.paths.size();
  const size_t one = parse("<text x='10' y='50' text-decoration='underline'>Hi</text>").scene.paths.size();
  REQUIRE(one == none + 1);
  CHECK(paths("UNDERLINE") == one);
  CHECK(paths("underline rgb(255, 0, 0) wavy") == one);
  CHECK(paths("dotted underline line-through") == one + 1);
  CHECK(paths("none") == none);
  // Invalid: the attribute's overline stays (one line).
  CHECK(paths("none underline") == one);
  CHECK(paths("underline underline") == one);
  CHECK(paths("underline bogus") == one);
  const auto over = parse("<text x='10' y='50' text-decoration='overline' style='text-decoration: none underline'>Hi</text>");
  const auto plain_over = parse("<text x='10' y='50' text-decoration='overline'>Hi</text>");
  CHECK(mpvg::dump(over.scene) == mpvg::dump(plain_over.scene));
}
