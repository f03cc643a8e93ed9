// SVG structure (issue 14): each case's scene dump equals the dump of an
// equivalent document written without the feature, by hand.
#include <cstdio>
#include <string>

#include "parsers/svg/svg_parser.h"
#include "parsers/svg/svg_values.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "frame/scene_info.h"

namespace {

std::string dump_of(const std::string& body, const std::string& root = "viewBox='0 0 200 200'") {
  return mpvg::dump(mpvg::svg::parse_svg_string(svg_test::document(body, root)).scene);
}

}  // namespace

TEST_CASE("transform-origin: keywords, lengths, percentages of the viewport", "[svg][structure]") {
  const std::string r = "<rect x='80' y='80' width='40' height='40' ";
  CHECK(dump_of(r + "transform='rotate(45)' transform-origin='bottom'/>") ==
        dump_of(r + "transform='translate(100 200) rotate(45) translate(-100 -200)'/>"));
  CHECK(dump_of(r + "transform='rotate(45)' transform-origin='top left'/>") == dump_of(r + "transform='rotate(45)'/>"));
  CHECK(dump_of(r + "transform='scale(2)' transform-origin='10 25%'/>") ==
        dump_of(r + "transform='translate(10 50) scale(2) translate(-10 -50)'/>"));
  CHECK(dump_of(r + "style='transform-origin: right' transform='rotate(10)'/>") ==
        dump_of(r + "transform='translate(200 100) rotate(10) translate(-200 -100)'/>"));
  // On a gradient's gradientTransform, in its own units.
  const std::string stops = "<stop offset='0' stop-color='red'/><stop offset='1' stop-color='blue'/>";
  CHECK(dump_of("<linearGradient id='g' gradientTransform='scale(2)' transform-origin='0.5 0.5'>" + stops +
                "</linearGradient>" + r + "fill='url(#g)'/>") ==
        dump_of("<linearGradient id='g' gradientTransform='translate(0.5 0.5) scale(2) translate(-0.5 -0.5)'>" +
                stops + "</linearGradient>" + r + "fill='url(#g)'/>"));
}

TEST_CASE("switch and conditional processing", "[svg][structure]") {
  const std::string green = "<rect width='10' height='10' fill='green'/>";
  // The first child whose conditions hold, and only it.
  CHECK(dump_of("<switch><rect width='10' height='10' fill='red' requiredExtensions='http://example.org/x'/>" + green +
                "<rect width='10' height='10' fill='red'/></switch>") == dump_of(green));
  CHECK(dump_of("<switch><rect width='10' height='10' fill='red' systemLanguage='ru-RU'/>" + green + "</switch>") ==
        dump_of(green));
  CHECK(dump_of("<switch><unknown/><rect width='10' height='10' fill='green' systemLanguage='fr, en-US'/>"
                "<rect width='10' height='10' fill='red'/></switch>") ==
        dump_of(green));
  // display="none" on the chosen child: nothing shows.
  CHECK(dump_of("<switch><rect width='10' height='10' fill='red' display='none'/>" + green + "</switch>") ==
        dump_of(""));
  // Outside a switch, a failing condition removes the element.
  CHECK(dump_of(green + "<rect width='10' height='10' fill='red' systemLanguage='ru'/>") == dump_of(green));
  CHECK(dump_of("<rect width='10' height='10' fill='green' systemLanguage='en'/>") == dump_of(green));
}

TEST_CASE("nested svg and symbol: viewports", "[svg][structure]") {
  const std::string r = "<rect width='10' height='10'/>";
  // viewBox 0 0 10 10 into 50 x 100 at (10, 20), meet: scale 5, centred
  // vertically (25 units down); overflow visible: no clip.
  CHECK(dump_of("<svg x='10' y='20' width='50' height='100' viewBox='0 0 10 10' overflow='visible'>" + r + "</svg>") ==
        dump_of("<g transform='translate(10 20) translate(0 25) scale(5)'>" + r + "</g>"));
  // A symbol drawn by use, the use's size over the symbol's.
  CHECK(dump_of("<defs><symbol id='s' viewBox='0 0 10 10' width='1' height='1' overflow='visible'>" + r +
                "</symbol></defs><use href='#s' x='5' width='20' height='20'/>") ==
        dump_of("<g transform='translate(5 0) scale(2)'>" + r + "</g>"));
  // Percentages inside resolve against the nested viewport (its viewBox).
  CHECK(dump_of("<svg width='100' height='100' viewBox='0 0 50 50' overflow='visible'>"
                "<rect width='50%' height='100%'/></svg>") ==
        dump_of("<g transform='scale(2)'><rect width='25' height='50'/></g>"));
  // The default overflow clips: the dump differs from the unclipped one by
  // a clip group, and a zero size draws nothing.
  const std::string clipped = dump_of("<svg width='50' height='50'>" + r + "</svg>");
  CHECK(clipped != dump_of("<svg width='50' height='50' overflow='visible'>" + r + "</svg>"));
  CHECK(dump_of("<svg width='0' height='50'>" + r + "</svg>") == dump_of(""));
}

TEST_CASE("markers: placement, orient, units, paint order", "[svg][structure]") {
  const std::string marker =
      "<marker id='m' markerUnits='userSpaceOnUse' markerWidth='10' markerHeight='10' refX='1' refY='2' "
      "orient='auto' overflow='visible'><rect width='4' height='2' fill='blue'/></marker>";
  const std::string line = "<path d='M 10 10 L 10 50 L 50 50' stroke='black' ";
  // Start marker at (10, 10), turned to the first segment (down: 90°),
  // refX/refY on the vertex.
  CHECK(dump_of(marker + line + "marker-start='url(#m)'/>") ==
        dump_of(line + "/><rect width='4' height='2' fill='blue' "
                       "transform='translate(10 10) rotate(90) translate(-1 -2)'/>"));
  // Mid marker at (10, 50): the bisector of down and right, 45°; end
  // marker at (50, 50) along the last segment, 0°.
  CHECK(dump_of(marker + line + "marker-mid='url(#m)' marker-end='url(#m)'/>") ==
        dump_of(line + "/><rect width='4' height='2' fill='blue' "
                       "transform='translate(10 50) rotate(45) translate(-1 -2)'/>"
                       "<rect width='4' height='2' fill='blue' transform='translate(50 50) translate(-1 -2)'/>"));
  // markerUnits strokeWidth scales by the stroke width; orient an angle.
  const std::string scaled =
      "<marker id='s' markerWidth='10' markerHeight='10' orient='30deg' overflow='visible'>"
      "<rect width='4' height='2' fill='blue'/></marker>";
  CHECK(dump_of(scaled + "<path d='M 10 10 L 50 10' stroke='black' stroke-width='3' marker-end='url(#s)'/>") ==
        dump_of("<path d='M 10 10 L 50 10' stroke='black' stroke-width='3'/>"
                "<rect width='4' height='2' fill='blue' transform='translate(50 10) rotate(30) scale(3)'/>"));
  // paint-order markers first: under the stroke and fill.
  CHECK(dump_of(marker + line + "paint-order='markers' marker-start='url(#m)'/>") ==
        dump_of("<rect width='4' height='2' fill='blue' transform='translate(10 10) rotate(90) translate(-1 -2)'/>" +
                line + "/>"));
  // The marker shorthand works in style, not as an attribute.
  CHECK(dump_of(marker + line + "style='marker: url(#m)'/>") ==
        dump_of(marker + line + "marker-start='url(#m)' marker-mid='url(#m)' marker-end='url(#m)'/>"));
  CHECK(dump_of(marker + line + "marker='url(#m)'/>") == dump_of(line + "/>"));
}

TEST_CASE("context-fill and context-stroke", "[svg][structure]") {
  // In a marker: the marked shape's paints.
  const std::string marker = "<marker id='m' markerUnits='userSpaceOnUse' orient='0' overflow='visible'>"
                             "<rect width='4' height='2' fill='context-stroke' stroke='context-fill'/></marker>";
  CHECK(dump_of(marker + "<path d='M 10 10 L 50 10' fill='red' stroke='blue' marker-end='url(#m)'/>") ==
        dump_of("<path d='M 10 10 L 50 10' fill='red' stroke='blue'/>"
                "<rect width='4' height='2' fill='blue' stroke='red' transform='translate(50 10)'/>"));
  // In a use's tree: the use's paints; none outside both.
  CHECK(dump_of("<defs><rect id='r' width='4' height='2' fill='context-fill'/></defs><use href='#r' fill='green'/>") ==
        dump_of("<rect width='4' height='2' fill='green'/>"));
  CHECK(dump_of("<rect width='4' height='2' fill='context-fill'/>") == dump_of("<rect width='4' height='2' fill='none'/>"));
}

TEST_CASE("markers: orient on curves, overflow inherit", "[svg][structure]") {
  const std::string marker = "<marker id='m' markerUnits='userSpaceOnUse' orient='auto' overflow='visible'>"
                             "<rect width='4' height='2' fill='blue'/></marker>";
  // A curve's end direction runs from its last distinct control point:
  // here (120 140) -> (170 140), 0°; its start from its first distinct
  // one: (40 155) -> (100 40) when the first control point is the start.
  CHECK(dump_of(marker + "<path d='M 100 60 C 100 110 120 140 170 140' marker-end='url(#m)'/>") ==
        dump_of("<path d='M 100 60 C 100 110 120 140 170 140'/><rect width='4' height='2' fill='blue' "
                "transform='translate(170 140)'/>"));
  CHECK(dump_of(marker + "<path d='M 40 40 C 40 40 100 40 100 100' marker-start='url(#m)'/>") ==
        dump_of("<path d='M 40 40 C 40 40 100 40 100 100'/><rect width='4' height='2' fill='blue' "
                "transform='translate(40 40)'/>"));
  // overflow="inherit" on a marker whose parent sets none: visible, no clip.
  const std::string inherit = "<marker id='i' markerUnits='userSpaceOnUse' overflow='inherit'>"
                              "<rect width='40' height='2' fill='blue'/></marker>";
  const std::string visible = "<marker id='i' markerUnits='userSpaceOnUse' overflow='visible'>"
                              "<rect width='40' height='2' fill='blue'/></marker>";
  CHECK(dump_of(inherit + "<path d='M 10 10 L 50 10' marker-end='url(#i)'/>") ==
        dump_of(visible + "<path d='M 10 10 L 50 10' marker-end='url(#i)'/>"));
}

TEST_CASE("svgz input: gzip-compressed documents are inflated", "[svg][structure]") {
  const std::string dir = std::string(MPVG_SOURCE_DIR) + "/testdata/svgz/";
  CHECK(mpvg::dump(mpvg::svg::parse_svg_file(dir + "square.svgz").scene) ==
        mpvg::dump(mpvg::svg::parse_svg_file(dir + "square.svg").scene));
  // Truncated gzip data is one clear error.
  std::string gz;
  {
    std::FILE* f = std::fopen((dir + "square.svgz").c_str(), "rb");
    REQUIRE(f);
    char buf[256];
    const size_t n = std::fread(buf, 1, sizeof buf, f);
    std::fclose(f);
    gz.assign(buf, n / 2);
  }
  std::string message;
  try {
    mpvg::svg::parse_svg_string(gz);
  } catch (const std::exception& e) {
    message = e.what();
  }
  CHECK(message == "cannot inflate the gzip-compressed (svgz) input: truncated gzip data");
}

TEST_CASE("rem: the root element's font size", "[svg][structure]") {
  CHECK(dump_of("<rect width='2rem' height='1rem'/>", "viewBox='0 0 200 200' font-size='10'") ==
        dump_of("<rect width='20' height='10'/>", "viewBox='0 0 200 200' font-size='10'"));
  CHECK(dump_of("<g font-size='50'><rect width='2rem' height='1em'/></g>") ==
        dump_of("<rect width='32' height='50'/>"));
}

TEST_CASE("background-color on the root fills the viewport under everything", "[svg][structure]") {
  const std::string d = dump_of("<rect x='10' y='10' width='5' height='5' fill='green'/>",
                                "viewBox='-100 -100 200 200' width='50' height='50' style='background-color: #0000ff80'");
  // Stream order is top-most first: the rect, then the background over the
  // whole 50 x 50 viewport in scene units.
  CHECK(d.find("M 0 0 L 50 0 L 50 50 L 0 50 L 0 0 Z") != std::string::npos);
  CHECK(d.find("rgba(0,0,1,0.501961)") != std::string::npos);
  CHECK(d.find("stream F0 F1") != std::string::npos);
  CHECK(d.find("path 1 fill nonzero rgba(0,0,1,0.501961)") != std::string::npos);
  // Without it, no background.
  CHECK(dump_of("", "width='50' height='50'").find("path") == std::string::npos);
}

TEST_CASE("shape-rendering: crispEdges and optimizeSpeed draw without antialiasing", "[svg][structure]") {
  // The aliased paths of a document, by paint colour (red, green, blue).
  auto aliased = [](const std::string& body) {
    const mpvg::Scene s = mpvg::svg::parse_svg_string(svg_test::document(body)).scene;
    std::string out;
    for (const char* name : {"red", "green", "blue"}) {
      const mpvg::RGBA c{name[0] == 'r' ? 1.0f : 0.0f, name[0] == 'g' ? 128 / 255.0f : 0.0f,
                         name[0] == 'b' ? 1.0f : 0.0f, 1.0f};
      for (const mpvg::ScenePath& p : s.paths) {
        const mpvg::RGBA q = s.paints[p.paint].color;
        if (!p.is_clip && q.r == c.r && q.g == c.g && q.b == c.b) out += std::string(name) + (p.aliased ? "+" : "-");
      }
    }
    return out;
  };
  const std::string r = "<rect width='10' height='10' ";
  CHECK(aliased(r + "fill='red'/>" + r + "fill='green' shape-rendering='crispEdges'/>" + r +
                "fill='blue' shape-rendering='optimizeSpeed'/>") == "red-green+blue+");
  // Inherited; auto and geometricPrecision turn it off; invalid values
  // are ignored; a stroke follows its element.
  CHECK(aliased("<g shape-rendering='crispEdges'>" + r + "fill='red'/>" + r +
                "fill='green' shape-rendering='geometricPrecision'/>" + r + "fill='blue' shape-rendering='bogus'/></g>") ==
        "red+green-blue+");
  CHECK(aliased("<g style='shape-rendering: crispEdges'>" + r + "fill='red' stroke='blue'/>" + r +
                "fill='green' shape-rendering='auto'/></g>") == "red+green-blue+");
  // text-rendering does not apply to shapes.
  CHECK(aliased(r + "fill='red' text-rendering='optimizeSpeed'/>") == "red-");
  // A clip path's children clip aliased as they would draw.
  const mpvg::Scene s = mpvg::svg::parse_svg_string(svg_test::document(
      "<clipPath id='c'><circle r='5' shape-rendering='crispEdges'/><rect width='3' height='3'/></clipPath>" + r +
      "clip-path='url(#c)'/>")).scene;
  int clips = 0, aliased_clips = 0;
  for (const mpvg::ScenePath& p : s.paths) {
    clips += p.is_clip;
    aliased_clips += p.is_clip && p.aliased;
  }
  CHECK(clips == 2);
  CHECK(aliased_clips == 1);
  // The dump says so.
  CHECK(dump_of(r + "shape-rendering='crispEdges'/>").find(" aliased") != std::string::npos);
  CHECK(dump_of(r + "/>").find(" aliased") == std::string::npos);
}

TEST_CASE("calc(): the grammar and its typing", "[svg][structure]") {
  using mpvg::svg::detail::CalcOk;
  using mpvg::svg::detail::parse_length;
  using mpvg::svg::detail::resolve_length;
  // Resolved with 100% = 200, 1em = 10, 1rem = 16.
  auto value = [](const char* text) -> std::optional<double> {
    const auto l = parse_length(text, CalcOk::Yes);
    if (!l) return std::nullopt;
    return resolve_length(*l, 200, 10, 16);
  };
  CHECK(value("calc(50% - 10px)") == Approx(90));
  CHECK(value("calc(1in + 2em)") == Approx(116));
  CHECK(value("CALC( 2 * (1em + 1ex) )") == Approx(30));
  CHECK(value("calc(100% / 4 - 1rem * 0.5)") == Approx(42));
  CHECK(value("calc(calc(10px + 5px) * 2)") == Approx(30));
  CHECK(value("calc(-10px)") == Approx(-10));
  CHECK(value("calc(10px - -5px)") == Approx(15));
  // Invalid: a number where a length is needed, length * length, division
  // by a length or by zero, '+' or '-' without spaces, unknown units,
  // unbalanced parentheses, anything after.
  for (const char* bad : {"calc(10 + 5)", "calc(10px + 5)", "calc(2px * 3px)", "calc(10px / 2px)",
                          "calc(10px / 0)", "calc(10px+5px)", "calc(10px -5px)", "calc(10qq)", "calc((10px)",
                          "calc(10px) 5", "calc()", "calc(10px"})
    CHECK_FALSE(value(bad).has_value());
  // Not where the value is no CSS property.
  CHECK_FALSE(parse_length("calc(10px)").has_value());
  CHECK(parse_length("12.5%")->unit == mpvg::svg::detail::Unit::Percent);
}

TEST_CASE("calc() and geometry properties in style sheets", "[svg][structure]") {
  CHECK(dump_of("<rect x='calc(10% + 5px)' y='calc(1em)' width='calc(50% - 10px)' height='calc(2 * 15px)'/>") ==
        dump_of("<rect x='25' y='16' width='90' height='30'/>"));
  CHECK(dump_of("<circle cx='calc(100% / 4)' cy='50' r='calc(5px + 5px)' font-size='calc(8px + 2px)'/>") ==
        dump_of("<circle cx='50' cy='50' r='10'/>"));
  // Geometry properties from a style attribute or a sheet, over the
  // attribute.
  CHECK(dump_of("<style>circle { r: 20px }</style><circle cx='50' cy='50' r='5'/>") ==
        dump_of("<circle cx='50' cy='50' r='20'/>"));
  CHECK(dump_of("<rect width='10' height='10' style='width: calc(100% - 150px); x: 5px'/>") ==
        dump_of("<rect x='5' width='50' height='10'/>"));
  // Not in a document that declares SVG 1.1, where geometry is attributes
  // only (calc() in them still works).
  const std::string v11 = "viewBox='0 0 200 200' version='1.1'";
  CHECK(dump_of("<rect width='10' height='10' style='width: 50px; x: 5px'/>", v11) ==
        dump_of("<rect width='10' height='10'/>", v11));
  CHECK(dump_of("<rect width='calc(10px + 5%)' height='10'/>", v11) == dump_of("<rect width='20' height='10'/>", v11));
  // Style lengths: stroke-width, font-size, stroke-dashoffset.
  CHECK(dump_of("<rect width='10' height='10' stroke='black' stroke-width='calc(1px + 1px)'/>") ==
        dump_of("<rect width='10' height='10' stroke='black' stroke-width='2'/>"));
  // An invalid calc() is ignored like any invalid value; x1 is no property.
  CHECK(dump_of("<rect width='calc(10 + 5)' height='10'/>") == dump_of("<rect height='10'/>"));
  CHECK(dump_of("<line x1='calc(10px)' x2='50' y2='50' stroke='black'/>") ==
        dump_of("<line x2='50' y2='50' stroke='black'/>"));
}

TEST_CASE("markers: a marker whose content uses the marked path marks that instance, once", "[svg][structure]") {
  // path2's start marker m1 draws path1, whose end marker m2 draws path1
  // again, whose markers (m1, m2) are both being drawn: the chain stops.
  // Likewise from the end marker: 1 + 2 + 2 strokes.
  const mpvg::Scene s = mpvg::svg::parse_svg_string(svg_test::document(
      "<defs><marker id='m1' markerWidth='6' markerHeight='6' orient='auto' refX='1' refY='3'>"
      "<use href='#path1' transform='matrix(-1 0 0 1 6 0)'/></marker>"
      "<marker id='m2' markerWidth='6' markerHeight='6' orient='auto' refX='5' refY='3'><use href='#path1'/></marker>"
      "<path id='path1' d='M 1 1 5 3 1 5' fill='none' stroke='blue' marker-start='url(#m1)' marker-end='url(#m2)'/>"
      "</defs><path d='M 10 10 L 190 190' fill='none' stroke='green' stroke-width='5' marker-start='url(#m1)' "
      "marker-end='url(#m2)'/>")).scene;
  int fills = 0, clips = 0;
  for (const mpvg::ScenePath& p : s.paths) (p.is_clip ? clips : fills)++;
  CHECK(fills == 5);
  CHECK(clips == 4);  // each marker instance clipped to its box
  // A use cycle through containers is still cut.
  const mpvg::Scene c = mpvg::svg::parse_svg_string(svg_test::document(
      "<defs><g id='a'><rect width='5' height='5'/><use href='#b'/></g><g id='b'><use href='#a'/></g></defs>"
      "<use href='#a'/>")).scene;
  CHECK(c.paths.size() <= 2);
}

TEST_CASE("markers: a zero-length segment points along +x, as in Chrome and resvg", "[svg][structure]") {
  auto doc = [](const std::string& start, const std::string& mid, const std::string& end) {
    auto marker = [](const char* id, const std::string& orient) {
      return "<marker id='" + std::string(id) + "' markerWidth='20' markerHeight='20' refY='2' orient='" + orient +
             "' markerUnits='userSpaceOnUse'><path d='M 0 0 L 16 2 L 0 4 z'/></marker>";
    };
    return marker("s", start) + marker("m", mid) + marker("e", end) +
           "<path d='M 100 20 L 100 20 L 130 50' fill='none' stroke='black' marker-start='url(#s)' "
           "marker-mid='url(#m)' marker-end='url(#e)'/>";
  };
  // Start: the zero-length segment's 0; mid: halfway between 0 and 45
  // degrees; end: the diagonal's 45.
  CHECK(dump_of(doc("auto", "auto", "auto")) == dump_of(doc("0", "22.5", "45")));
}

TEST_CASE("markers: an arc command is one segment, whatever its conic pieces", "[svg][structure]") {
  const std::string marker =
      "<marker id='m' markerWidth='20' markerHeight='20' orient='auto'><path d='M 0 0 L 6 3 L 0 6 z'/></marker>";
  // A 250-degree arc (three conic pieces): no mid marker, as in browsers.
  const std::string arc = "<path d='M 40 60 A 40 30 20 1 1 150 120' fill='none' stroke='green' ";
  CHECK(dump_of(marker + arc + "marker-mid='url(#m)'/>") == dump_of(marker + arc + "/>"));
  // Two arcs: one mid marker, where they meet (the same as on a polyline
  // corner there with the same directions in and out).
  auto count = [](const std::string& body) {
    int fills = 0;
    for (const mpvg::ScenePath& p : mpvg::svg::parse_svg_string(svg_test::document(body)).scene.paths)
      fills += !p.is_clip;
    return fills;
  };
  CHECK(count(marker + "<path d='M 20 50 A 30 30 0 0 1 80 50 A 30 30 0 0 1 140 50' fill='none' stroke='green' "
                       "marker-mid='url(#m)'/>") == 2);
}

TEST_CASE("markers: context-fill inherited from a marker's ancestors follows each marked shape", "[svg][structure]") {
  // CSS inherits context-fill as a keyword: the marker content resolves it
  // against the shape being marked, for every shape (the marker's cached
  // ancestor cascade must not freeze the first one).
  const mpvg::Scene s = mpvg::svg::parse_svg_string(svg_test::document(
      "<g fill='context-fill'><marker id='m' markerWidth='4' markerHeight='4' overflow='visible'>"
      "<rect width='2' height='2'/></marker></g>"
      "<g><marker id='n' markerWidth='4' markerHeight='4' overflow='visible'><rect width='2' height='2'/></marker></g>"
      "<path d='M 10 10 L 20 10' fill='rgb(255,0,0)' stroke='black' marker-end='url(#m)' marker-start='url(#n)'/>"
      "<path d='M 10 30 L 20 30' fill='rgb(0,0,255)' stroke='black' marker-end='url(#m)' marker-start='url(#n)'/>")).scene;
  std::string marker_fills;
  for (const mpvg::ScenePath& p : s.paths) {
    const mpvg::RGBA c = s.paints[p.paint].color;
    if (p.xf.e == 0 && p.xf.f == 0) continue;  // the strokes
    marker_fills += c.r == 1 ? "red " : c.b == 1 ? "blue " : "black ";
  }
  // Top-most first: blue path's end (blue), its start (black: #n is
  // outside any context-fill), red path's end (red), its start (black).
  CHECK(marker_fills == "blue black red black ");
}
