// SVG paint servers as scene paints: text round trips of mpvg::dump(), as
// in test_svg_parser.cpp. Paths are listed top-most first (reverse document
// order); pattern tiles are dumped inside their pattern, indented. Most
// cases drop the geometry lines ("M ...") to keep the paint lines in view.
#include <string>
#include <vector>

#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "frame/scene_info.h"

namespace {

mpvg::svg::ParseResult parse(const std::string& body) {
  return mpvg::svg::parse_svg_string(svg_test::document(body));
}

// The dump without geometry lines, at any nesting depth.
std::string paints_of(const mpvg::Scene& scene) {
  return svg_test::dump_lines(mpvg::dump(scene),
                              [](std::string_view text, size_t) { return text.rfind("M ", 0) != 0; });
}

std::string paints_of(const std::string& body) { return paints_of(parse(body).scene); }

// Two stops, red to blue, for gradients whose stops do not matter.
const char* const kStops = R"~(<stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/>)~";

}  // namespace

// ------------------------------------------------------------------ gradients

TEST_CASE("svg gradients: linear defaults map the object bounding box", "[svg][paint]") {
  // x1 y1 x2 y2 default to 0% 0% 100% 0% of the box: (0,0)-(1,0) in
  // gradient space, which the box matrix maps onto the rect.
  CHECK(mpvg::dump(parse(std::string("<linearGradient id=\"g\">") + kStops + "</linearGradient>" +
                         R"~(<rect x="10" y="20" width="40" height="30" fill="url(#g)"/>)~")
                       .scene) == R"~(scene 100 100
path 0 fill nonzero linear 0 opacity 1
  M 10 20 L 50 20 L 50 50 L 10 50 L 10 20 Z
gradient 0 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb matrix(40 0 0 30 10 20)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0
)~");
}

TEST_CASE("svg gradients: userSpaceOnUse resolves lengths against the viewport", "[svg][paint]") {
  // x1 = 10% of the 100-unit viewport, y2 = 1em = 16; gradientTransform
  // applies in the user space, which scale(2) maps to scene units.
  CHECK(paints_of(std::string(R"~(<linearGradient id="g" gradientUnits="userSpaceOnUse" x1="10%" y1="5" x2="50%")~"
                              R"~( y2="1em" gradientTransform="translate(5 0)">)~") +
                  kStops + R"~(</linearGradient><g transform="scale(2)"><rect width="4" height="3" fill="url(#g)"/></g>)~") ==
        R"~(scene 100 100
path 0 fill nonzero linear 0 opacity 1 matrix(2 0 0 2 0 0)
gradient 0 linear 10 5 50 16 radial 0 0 0 0 0 0 pad srgb matrix(2 0 0 2 10 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0
)~");
}

TEST_CASE("svg gradients: radial defaults, focal point and focal radius", "[svg][paint]") {
  // f: fx fy given, fr 10% of the box. u: user space, r = 50% of the
  // viewport diagonal (sqrt((100^2 + 100^2) / 2) = 100), focal point far
  // outside the end circle and kept there (two-point conical, no SVG 1.1
  // focal correction, as resvg).
  CHECK(paints_of(std::string("<radialGradient id=\"r\">") + kStops +
                  R"~(</radialGradient><radialGradient id="f" href="#r" fx="0.9" fy="0.1" fr="10%"/>)~"
                  R"~(<radialGradient id="u" href="#r" gradientUnits="userSpaceOnUse" r="50%" cx="10" fx="200" fy="50"/>)~"
                  R"~(<rect width="20" height="10" fill="url(#r)"/><rect width="20" height="10" fill="url(#f)"/>)~"
                  R"~(<rect width="20" height="10" fill="url(#u)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero radial 2 opacity 1
path 1 fill nonzero radial 1 opacity 1
path 2 fill nonzero radial 0 opacity 1
gradient 0 linear 0 0 0 0 radial 0.5 0.5 0 0.5 0.5 0.5 pad srgb matrix(20 0 0 10 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 0 0 radial 0.9 0.1 0.1 0.5 0.5 0.5 pad srgb matrix(20 0 0 10 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 2 linear 0 0 0 0 radial 200 50 0 10 50 50 pad srgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0 F1 F2
)~");
}

TEST_CASE("svg gradients: coinciding circles, and a focal circle larger than the end circle", "[svg][paint]") {
  // a: fr = r with the same centre. SVG 2 draws nothing; resvg and Blink
  // draw the limit of nearly coinciding circles: with pad, the first stop
  // inside and the last outside (a step at t = 1). b: the same with
  // reflect: nothing, not the fallback. c: fr 0.7 > r 0.5 is an ordinary
  // two-point conical gradient.
  CHECK(paints_of(R"~(<radialGradient id="a" fr="0.5"><stop offset="0" stop-color="red"/>)~"
                  R"~(<stop offset="0.5" stop-color="lime"/><stop offset="1" stop-color="blue"/></radialGradient>)~"
                  R"~(<radialGradient id="b" href="#a" spreadMethod="reflect"/><radialGradient id="c" href="#a" fr="0.7"/>)~"
                  R"~(<rect width="1" height="1" fill="url(#a)"/><rect width="2" height="2" fill="url(#b) red"/>)~"
                  R"~(<rect width="3" height="3" fill="url(#c)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero radial 1 opacity 1
path 1 fill nonzero radial 0 opacity 1
gradient 0 linear 0 0 0 0 radial 0.5 0.5 0 0.5 0.5 0.5 pad srgb
  stops 0 rgba(1,0,0,1) 1 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 0 0 radial 0.5 0.5 0.7 0.5 0.5 0.5 pad srgb matrix(3 0 0 3 0 0)
  stops 0 rgba(1,0,0,1) 0.5 rgba(0,1,0,1) 1 rgba(0,0,1,1)
stream F0 F1
)~");
}

TEST_CASE("svg gradients: fx and fy default to the resolved cx and cy; spreadMethod", "[svg][paint]") {
  // fx from the template, cx from the referencing gradient; an invalid
  // spreadMethod is pad.
  CHECK(paints_of(R"~(<radialGradient id="a" fx="0.6" spreadMethod="repeat"/>)~"
                  R"~(<radialGradient id="b" href="#a" cx="0.7">)~" +
                  std::string(kStops) +
                  R"~(</radialGradient><linearGradient id="c" spreadMethod="Reflect">)~" + kStops +
                  R"~(</linearGradient><rect width="1" height="1" fill="url(#b)"/><rect width="1" height="1" fill="url(#c)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero linear 1 opacity 1
path 1 fill nonzero radial 0 opacity 1
gradient 0 linear 0 0 0 0 radial 0.6 0.5 0 0.7 0.5 0.5 repeat srgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0 F1
)~");
  // An invalid fx is ignored: the default, cx.
  CHECK(paints_of(R"~(<radialGradient id="r" cx="0.3" fx="bogus">)~" + std::string(kStops) +
                  R"~(</radialGradient><rect width="1" height="1" fill="url(#r)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero radial 0 opacity 1
gradient 0 linear 0 0 0 0 radial 0.3 0.5 0 0.3 0.5 0.5 pad srgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0
)~");
}

TEST_CASE("svg gradients: href inherits shared attributes from either kind, geometry from the same kind", "[svg][paint]") {
  // c (linear) -> b (radial) -> a (linear). c takes units and spread from
  // a through b, gradientTransform from b; x1 stops at b (another kind):
  // the default 0. b takes units from a, its own cx; cy is not taken from
  // the linear a: 50% of the viewport. href wins over xlink:href.
  CHECK(paints_of(R"~(<linearGradient id="a" x1="0.3" spreadMethod="reflect" gradientUnits="userSpaceOnUse">)~" +
                  std::string(kStops) +
                  R"~(</linearGradient><radialGradient id="b" xlink:href="#a" cx="0.2" gradientTransform="scale(2)"/>)~"
                  R"~(<linearGradient id="c" href="#b" x2="0.6" xlink:href="#nothing"/>)~"
                  R"~(<rect width="20" height="10" fill="url(#c)"/><rect width="20" height="10" fill="url(#b)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero radial 1 opacity 1
path 1 fill nonzero linear 0 opacity 1
gradient 0 linear 0 0 0.6 0 radial 0 0 0 0 0 0 reflect srgb matrix(2 0 0 2 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 0 0 radial 0.2 50 0 0.2 50 50 reflect srgb matrix(2 0 0 2 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0 F1
)~");
}

TEST_CASE("svg gradients: href cycles end the chain, unresolved hrefs are ignored", "[svg][paint]") {
  // c -> b -> a -> c: the chain from c is c, b, a. c's y1 is its own, x1
  // comes from b, the stops from a. d's href leads nowhere.
  const auto r = parse(R"~(<linearGradient id="a" href="#c">)~" + std::string(kStops) +
                       R"~(</linearGradient><linearGradient id="b" href="#a" x1="0.5"/>)~"
                       R"~(<linearGradient id="c" href="#b" y1="0.5"/><linearGradient id="d" href="#missing">)~" +
                       kStops +
                       R"~(</linearGradient><rect width="10" height="10" fill="url(#c)"/>)~"
                       R"~(<rect width="10" height="10" fill="url(#d)"/>)~");
  CHECK(paints_of(r.scene) == R"~(scene 100 100
path 0 fill nonzero linear 1 opacity 1
path 1 fill nonzero linear 0 opacity 1
gradient 0 linear 0.5 0.5 1 0 radial 0 0 0 0 0 0 pad srgb matrix(10 0 0 10 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb matrix(10 0 0 10 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0 F1
)~");
  CHECK(r.warnings == std::vector<std::string>{"recursive href between paint servers: the chain ends where it repeats"});
}

TEST_CASE("svg gradients: a chain ends at an element that is not a gradient", "[svg][paint]") {
  // a finds no stops before the rect (which has no size: no geometry):
  // it cannot paint, the fallback green applies. b has stops of its own;
  // the rect's x2 is not inherited.
  CHECK(paints_of(R"~(<rect id="r" x2="0.5">)~" + std::string(kStops) +
                  R"~(</rect><linearGradient id="a" href="#r"/><linearGradient id="b" href="#r">)~"
                  R"~(<stop offset="0" stop-color="lime"/><stop offset="1" stop-color="blue"/></linearGradient>)~"
                  R"~(<rect width="10" height="10" fill="url(#a) green"/><rect width="10" height="10" fill="url(#b)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero linear 0 opacity 1
path 1 fill nonzero rgba(0,0.501961,0,1) opacity 1
gradient 0 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb matrix(10 0 0 10 0 0)
  stops 0 rgba(0,1,0,1) 1 rgba(0,0,1,1)
stream F0 F1
)~");
}

TEST_CASE("svg gradients: stop offsets, colours and opacities", "[svg][paint][stop]") {
  // In order: offset -1 clamps to 0; 50% with hsla alpha 0.5 times
  // stop-opacity 0.5; 0.2 is raised to the previous 0.5, currentColor is
  // the stop's own color; 5mm is not a valid offset (0, raised to 0.5) and
  // inherit takes the gradient element's stop-color and stop-opacity (not
  // inherited further: the g's lime is not used); the style attribute with
  // currentColor (inherited olive) and 25%, offset 2 clamps to 1; an
  // unparsable stop-color is the initial black. The rect child is ignored.
  CHECK(paints_of(R"~(<g color="olive" stop-color="lime"><linearGradient id="a" stop-color="teal" stop-opacity="0.5">)~"
                  R"~(<stop offset="-1" stop-color="red"/>)~"
                  R"~(<stop offset="50%" stop-color="hsla(120, 100%, 50%, 0.5)" stop-opacity="0.5"/>)~"
                  R"~(<stop offset="0.2" stop-color="currentColor" color="#00f"/>)~"
                  R"~(<stop offset="5mm" stop-color="inherit" stop-opacity="inherit"/>)~"
                  R"~(<stop style="stop-color: currentColor; stop-opacity: 25%" offset="2"/>)~"
                  R"~(<stop offset="0.9" stop-color="bogus"/><rect/></linearGradient></g>)~"
                  R"~(<rect width="10" height="10" fill="url(#a)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero linear 0 opacity 1
gradient 0 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb matrix(10 0 0 10 0 0)
  stops 0 rgba(1,0,0,1) 0.5 rgba(0,1,0,0.25) 0.5 rgba(0,0,1,1) 0.5 rgba(0,0.501961,0.501961,0.5) 1 rgba(0.501961,0.501961,0,0.25) 1 rgba(0,0,0,1)
stream F0
)~");
}

TEST_CASE("svg gradients: single stop, no stops, zero radius, zero-length vector", "[svg][paint]") {
  // Document order: one stop (its colour, stop-opacity in the alpha,
  // fill-opacity in the paint); no stops with a fallback (the fallback);
  // no stops, stroked with the single stop; r = 0 (the last stop); a
  // negative r (warned, as r = 0); x1 y1 = x2 y2 (the last stop).
  const auto r =
      parse(R"~(<linearGradient id="one"><stop offset="0.5" stop-color="green" stop-opacity="0.5"/></linearGradient>)~"
            R"~(<linearGradient id="none"/>)~"
            R"~(<radialGradient id="r0" r="0"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></radialGradient>)~"
            R"~(<radialGradient id="rn" r="-5"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="lime"/></radialGradient>)~"
            R"~(<linearGradient id="z" x1="0.5" x2="0.5" y1="1" y2="1"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="aqua"/></linearGradient>)~"
            R"~(<rect width="1" height="1" fill="url(#one)" fill-opacity="0.5"/>)~"
            R"~(<rect width="2" height="2" fill="url(#none) red"/>)~"
            R"~(<rect width="3" height="3" fill="url(#none)" stroke="url(#one)"/>)~"
            R"~(<rect width="4" height="4" fill="url(#r0)"/>)~"
            R"~(<rect width="5" height="5" fill="url(#rn)"/>)~"
            R"~(<rect width="6" height="6" fill="url(#z)"/>)~");
  CHECK(paints_of(r.scene) == R"~(scene 100 100
path 0 fill nonzero rgba(0,1,1,1) opacity 1
path 1 fill nonzero rgba(0,1,0,1) opacity 1
path 2 fill nonzero rgba(0,0,1,1) opacity 1
path 3 fill nonzero rgba(0,0.501961,0,0.5) opacity 1 stroke 1 miter butt 4
path 4 fill nonzero rgba(1,0,0,1) opacity 1
path 5 fill nonzero rgba(0,0.501961,0,0.5) opacity 0.5
stream F0 F1 F2 F3 F4 F5
)~");
  CHECK(r.warnings == std::vector<std::string>{"negative r on <radialGradient>: painted as r = 0"});
}

TEST_CASE("svg gradients: strokes use the fill's box; a box without area falls back", "[svg][paint][stroke]") {
  // A horizontal line has no height: an objectBoundingBox gradient cannot
  // paint its stroke (nothing, or the fallback yellow); userSpaceOnUse can.
  // The diagonal path's stroke uses its 10x10 fill box, with the stroke
  // opacity; its (degenerate) fill is black.
  CHECK(paints_of(std::string("<linearGradient id=\"g\">") + kStops +
                  "</linearGradient><linearGradient id=\"u\" gradientUnits=\"userSpaceOnUse\">" + kStops +
                  R"~(</linearGradient><line x2="10" stroke="url(#g)"/><line y2="10" stroke="url(#g) yellow"/>)~"
                  R"~(<line x2="10" stroke="url(#u)"/>)~"
                  R"~(<path d="M 0 0 L 10 10" stroke="url(#g)" stroke-width="2" stroke-opacity="0.5"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero linear 1 opacity 0.5 stroke 2 miter butt 4
path 1 fill nonzero rgba(0,0,0,1) opacity 1
path 2 fill nonzero linear 0 opacity 1 stroke 1 miter butt 4
path 3 fill nonzero rgba(1,1,0,1) opacity 1 stroke 1 miter butt 4
gradient 0 linear 0 0 100 0 radial 0 0 0 0 0 0 pad srgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb matrix(10 0 0 10 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0 F1 F2 F3
)~");
}

TEST_CASE("svg gradients: color-interpolation, and opacities multiplied into the paint", "[svg][paint]") {
  // color-interpolation is an inherited property of the gradient element
  // (not taken through href): linearRGB, auto (sRGB), inherit (from the g).
  // Group opacity and fill-opacity multiply: 0.25.
  CHECK(paints_of(R"~(<linearGradient id="g" color-interpolation="linearRGB">)~" + std::string(kStops) +
                  R"~(</linearGradient><g color-interpolation="linearRGB">)~"
                  R"~(<linearGradient id="h" href="#g" color-interpolation="auto"/>)~"
                  R"~(<linearGradient id="i" href="#g" color-interpolation="inherit"/></g>)~"
                  R"~(<rect width="1" height="1" fill="url(#g)"/><rect width="1" height="1" fill="url(#h)"/>)~"
                  R"~(<rect width="1" height="1" fill="url(#i)"/>)~"
                  R"~(<g opacity="0.5"><rect width="1" height="1" fill="url(#g)" fill-opacity="0.5"/></g>)~") ==
        R"~(scene 100 100
path 0 fill nonzero linear 3 opacity 0.25
path 1 fill nonzero linear 2 opacity 1
path 2 fill nonzero linear 1 opacity 1
path 3 fill nonzero linear 0 opacity 1
gradient 0 linear 0 0 1 0 radial 0 0 0 0 0 0 pad linearrgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 2 linear 0 0 1 0 radial 0 0 0 0 0 0 pad linearrgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 3 linear 0 0 1 0 radial 0 0 0 0 0 0 pad linearrgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0 F1 F2 F3
)~");
}

// ------------------------------------------------------------------ fallbacks

TEST_CASE("svg paint servers: fallbacks and unsupported references", "[svg][paint]") {
  // Document order: missing with a fallback (red); missing without
  // (none); an element that is not a paint server (none, fallback or
  // not); meshgradient (unsupported: the fallback blue); hatch without a
  // fallback (none); another document (the fallback lime); currentColor
  // fallback (olive).
  const auto r = parse(R"~(<defs><meshgradient id="m"/><hatch id="h"/><circle id="c" r="1"/></defs>)~"
                       R"~(<rect width="1" height="1" fill="url(#missing) red"/>)~"
                       R"~(<rect width="2" height="2" fill="url(#missing)"/>)~"
                       R"~(<rect width="3" height="3" fill="url(#c) red"/>)~"
                       R"~(<rect width="4" height="4" fill="url(#m) blue"/>)~"
                       R"~(<rect width="5" height="5" fill="url(#h)"/>)~"
                       R"~(<rect width="6" height="6" fill="url(other.svg#g) lime"/>)~"
                       R"~(<rect width="7" height="7" color="olive" fill="url(#missing) currentColor"/>)~");
  CHECK(paints_of(r.scene) == R"~(scene 100 100
path 0 fill nonzero rgba(0.501961,0.501961,0,1) opacity 1
path 1 fill nonzero rgba(0,1,0,1) opacity 1
path 2 fill nonzero rgba(0,0,1,1) opacity 1
path 3 fill nonzero rgba(1,0,0,1) opacity 1
stream F0 F1 F2 F3
)~");
  CHECK(r.warnings == std::vector<std::string>{
                          "<meshgradient> paint servers are not supported: fill painted with the fallback colour",
                          "<hatch> paint servers are not supported: fill not rendered",
                          "references to other documents are not supported: fill falls back"});
}

// ------------------------------------------------------------------ patterns

TEST_CASE("svg patterns: a userSpaceOnUse tile, patternTransform and x y", "[svg][paint][pattern]") {
  // The tile is a scene of its own, 10 x 20 units; its units map to the
  // scene by patternTransform (rotate(90)) after the translation to (x, y).
  CHECK(mpvg::dump(parse(R"~(<pattern id="p" patternUnits="userSpaceOnUse" x="5" y="5" width="10" height="20")~"
                         R"~( patternTransform="rotate(90)"><rect width="5" height="5" fill="green"/></pattern>)~"
                         R"~(<rect width="50" height="50" fill="url(#p)"/>)~")
                       .scene) == R"~(scene 100 100
path 0 fill nonzero pattern 0 opacity 1
  M 0 0 L 50 0 L 50 50 L 0 50 L 0 0 Z
pattern 0 matrix(0 1 -1 0 -5 5)
    scene 10 20
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
      M 0 0 L 5 0 L 5 5 L 0 5 L 0 0 Z
    stream F0
stream F0
)~");
}

TEST_CASE("svg patterns: objectBoundingBox units and content units", "[svg][paint][pattern]") {
  // p: the tile is x 0.1, y 0.2, width 25%, height 0.5 of the 40x20 box at
  // (10, 10): (14, 14), 10 x 10; its content in user units. q: content in
  // fractions of the box, scaled by it (not moved: the tile's origin is
  // already the box corner plus x, y).
  CHECK(paints_of(R"~(<pattern id="p" x="0.1" y="0.2" width="25%" height="0.5"><rect width="5" height="5" fill="green"/></pattern>)~"
                  R"~(<pattern id="q" width="0.5" height="0.5" patternContentUnits="objectBoundingBox">)~"
                  R"~(<rect width="0.25" height="0.25" fill="green"/></pattern>)~"
                  R"~(<rect x="10" y="10" width="40" height="20" fill="url(#p)"/>)~"
                  R"~(<rect x="10" y="10" width="40" height="20" fill="url(#q)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero pattern 1 opacity 1
path 1 fill nonzero pattern 0 opacity 1
pattern 0 matrix(1 0 0 1 14 14)
    scene 10 10
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
    stream F0
pattern 1 matrix(1 0 0 1 10 10)
    scene 20 10
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1 matrix(40 0 0 20 0 0)
    stream F0
stream F0 F1
)~");
}

TEST_CASE("svg patterns: viewBox and preserveAspectRatio, inherited through href", "[svg][paint][pattern]") {
  // v: the 5x5 viewBox sliced into the 20x10 tile, xMin YMid: scale 4,
  // moved up by 5. w: everything from v but preserveAspectRatio none
  // (scale 4 x 2); patternContentUnits is ignored with a viewBox.
  CHECK(paints_of(R"~(<pattern id="v" patternUnits="userSpaceOnUse" width="20" height="10" viewBox="0 0 5 5")~"
                  R"~( preserveAspectRatio="xMinYMid slice"><rect width="5" height="5" fill="green"/></pattern>)~"
                  R"~(<pattern id="w" href="#v" preserveAspectRatio="none" patternContentUnits="objectBoundingBox"/>)~"
                  R"~(<rect width="50" height="50" fill="url(#v)"/><rect width="50" height="50" fill="url(#w)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero pattern 1 opacity 1
path 1 fill nonzero pattern 0 opacity 1
pattern 0
    scene 20 10
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1 matrix(4 0 0 4 0 -5)
    stream F0
pattern 1
    scene 20 10
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1 matrix(4 0 0 2 0 0)
    stream F0
stream F0 F1
)~");
}

TEST_CASE("svg patterns: children through href; properties inherit from where the pattern is", "[svg][paint][pattern]") {
  // b has no children: a's are used, with a's size and b's x. They inherit
  // fill, stroke and stroke-width from a's ancestors and fill-opacity from
  // a itself, not the yellow fill around the referencing rect; the child
  // with display none is not drawn. The stroke comes first (top-most).
  CHECK(paints_of(R"~(<g fill="blue" stroke="red" stroke-width="0.5"><pattern id="a" patternUnits="userSpaceOnUse")~"
                  R"~( width="10" height="10" fill-opacity="0.5"><rect width="4" height="4"/>)~"
                  R"~(<rect x="5" width="4" height="4" display="none"/></pattern></g>)~"
                  R"~(<pattern id="b" href="#a" x="2"/><g fill="yellow"><rect width="50" height="50" fill="url(#b)"/></g>)~") ==
        R"~(scene 100 100
path 0 fill nonzero pattern 0 opacity 1
pattern 0 matrix(1 0 0 1 2 0)
    scene 10 10
    path 0 fill nonzero rgba(1,0,0,1) opacity 1 stroke 0.5 miter butt 4
    path 1 fill nonzero rgba(0,0,1,1) opacity 0.5
    stream F0 F1
stream F0
)~");
}

TEST_CASE("svg patterns: no content or no size fall back", "[svg][paint][pattern]") {
  // No children (a title does not count), zero width, content that paints
  // nothing: the fallback, or nothing without one. An objectBoundingBox
  // pattern on a line (no area) falls back too.
  CHECK(paints_of(R"~(<pattern id="e" patternUnits="userSpaceOnUse" width="10" height="10"><title>t</title></pattern>)~"
                  R"~(<pattern id="z" patternUnits="userSpaceOnUse" height="10"><rect width="5" height="5"/></pattern>)~"
                  R"~(<pattern id="n" patternUnits="userSpaceOnUse" width="10" height="10"><rect width="5" height="5" fill="none"/></pattern>)~"
                  R"~(<pattern id="o" width="1" height="1"><rect width="5" height="5"/></pattern>)~"
                  R"~(<rect width="1" height="1" fill="url(#e) red"/><rect width="2" height="2" fill="url(#z)"/>)~"
                  R"~(<rect width="3" height="3" fill="url(#n) lime"/><line x2="10" stroke="url(#o) blue"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,1,1) opacity 1 stroke 1 miter butt 4
path 1 fill nonzero rgba(0,1,0,1) opacity 1
path 2 fill nonzero rgba(1,0,0,1) opacity 1
stream F0 F1 F2
)~");
}

TEST_CASE("svg patterns: recursion is cut where the pattern is used inside itself", "[svg][paint][pattern]") {
  // p's rect fills with p (cut: nothing, not the fallback) and strokes
  // with q; q's tile uses p again (cut) beside a green square.
  const auto r = parse(R"~(<pattern id="p" patternUnits="userSpaceOnUse" width="10" height="10">)~"
                       R"~(<rect width="10" height="10" fill="url(#p) red" stroke="url(#q)"/></pattern>)~"
                       R"~(<pattern id="q" patternUnits="userSpaceOnUse" width="10" height="10">)~"
                       R"~(<rect width="5" height="5" fill="url(#p)"/><rect x="5" width="5" height="5" fill="green"/></pattern>)~"
                       R"~(<rect width="50" height="50" fill="url(#p)"/>)~");
  CHECK(paints_of(r.scene) == R"~(scene 100 100
path 0 fill nonzero pattern 0 opacity 1
pattern 0
    scene 10 10
    path 0 fill nonzero pattern 0 opacity 1 stroke 1 miter butt 4
    pattern 0
        scene 10 10
        path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
        stream F0
    stream F0
stream F0
)~");
  CHECK(r.warnings == std::vector<std::string>{"recursive pattern reference: the inner use is not rendered"});
}

TEST_CASE("svg patterns: nesting stops at the core's limit", "[svg][paint][pattern]") {
  // p1 .. p5 each fill a square with the next: tiles nest 4 deep
  // (kMaxPatternDepth); p5's use in p4's tile is not rendered.
  std::string body;
  for (int i = 1; i <= 5; i++)
    body += "<pattern id=\"p" + std::to_string(i) +
            "\" patternUnits=\"userSpaceOnUse\" width=\"10\" height=\"10\"><rect width=\"5\" height=\"5\" fill=\"url(#p" +
            std::to_string(i + 1) + ") red\"/><rect x=\"5\" width=\"5\" height=\"5\" fill=\"green\"/></pattern>";
  body += R"~(<pattern id="p6" patternUnits="userSpaceOnUse" width="10" height="10"><rect width="5" height="5"/></pattern>)~";
  body += R"~(<rect width="50" height="50" fill="url(#p1)"/>)~";
  const auto r = parse(body);
  CHECK(paints_of(r.scene) == R"~(scene 100 100
path 0 fill nonzero pattern 0 opacity 1
pattern 0
    scene 10 10
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
    path 1 fill nonzero pattern 0 opacity 1
    pattern 0
        scene 10 10
        path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
        path 1 fill nonzero pattern 0 opacity 1
        pattern 0
            scene 10 10
            path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
            path 1 fill nonzero pattern 0 opacity 1
            pattern 0
                scene 10 10
                path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
                stream F0
            stream F0 F1
        stream F0 F1
    stream F0 F1
stream F0
)~");
  CHECK(r.warnings == std::vector<std::string>{"patterns nested more than 4 deep: the innermost are not rendered"});
}

TEST_CASE("svg patterns: tiles are shared by uses with the same box and scale", "[svg][paint][pattern]") {
  // The fill and stroke of the first rect and the fill of the second share
  // one pattern (same user space). translate(7 3) needs a pattern of its
  // own but shares the tile (strokes depend on the scale only); scale(2)
  // gets a tile of its own.
  const auto r = parse(R"~(<pattern id="p" patternUnits="userSpaceOnUse" width="10" height="10"><rect width="5" height="5"/></pattern>)~"
                       R"~(<rect width="50" height="50" fill="url(#p)" stroke="url(#p)"/>)~"
                       R"~(<rect x="50" width="50" height="50" fill="url(#p)"/>)~"
                       R"~(<rect width="50" height="50" fill="url(#p)" transform="translate(7 3)"/>)~"
                       R"~(<rect width="50" height="50" fill="url(#p)" transform="scale(2)"/>)~");
  CHECK(paints_of(r.scene) == R"~(scene 100 100
path 0 fill nonzero pattern 2 opacity 1 matrix(2 0 0 2 0 0)
path 1 fill nonzero pattern 1 opacity 1 matrix(1 0 0 1 7 3)
path 2 fill nonzero pattern 0 opacity 1
path 3 fill nonzero pattern 0 opacity 1 stroke 1 miter butt 4
path 4 fill nonzero pattern 0 opacity 1
pattern 0
    scene 10 10
    path 0 fill nonzero rgba(0,0,0,1) opacity 1
    stream F0
pattern 1 matrix(1 0 0 1 7 3)
    scene 10 10
    path 0 fill nonzero rgba(0,0,0,1) opacity 1
    stream F0
pattern 2 matrix(2 0 0 2 0 0)
    scene 10 10
    path 0 fill nonzero rgba(0,0,0,1) opacity 1
    stream F0
stream F0 F1 F2 F3 F4
)~");
  REQUIRE(r.scene.patterns.size() == 3);
  CHECK(r.scene.patterns[0].tile == r.scene.patterns[1].tile);
  CHECK(r.scene.patterns[0].tile != r.scene.patterns[2].tile);
}

TEST_CASE("svg patterns: strokes in a tile are prepared for the tile's size on screen", "[svg][paint][pattern]") {
  // At the default 2 pixels per unit, a 0.1-wide stroke is 0.2 px: a
  // hairline drawn 1 px wide at opacity 0.2. Scaled by patternTransform
  // scale(10) it is 2 px wide: an ordinary stroke.
  CHECK(paints_of(R"~(<pattern id="a" patternUnits="userSpaceOnUse" width="2" height="2">)~"
                  R"~(<path d="M 0 1 L 2 1" fill="none" stroke="green" stroke-width="0.1"/></pattern>)~"
                  R"~(<pattern id="b" href="#a" patternTransform="scale(10)"/>)~"
                  R"~(<rect width="50" height="50" fill="url(#a)"/><rect width="50" height="50" fill="url(#b)"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero pattern 1 opacity 1
path 1 fill nonzero pattern 0 opacity 1
pattern 0
    scene 2 2
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 0.2 stroke 0.5 miter butt 4
    stream F0
pattern 1 matrix(10 0 0 10 0 0)
    scene 2 2
    path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1 stroke 0.1 miter butt 4
    stream F0
stream F0 F1
)~");
}

TEST_CASE("svg patterns: uses that multiply through nested tiles are bounded", "[svg][paint][pattern]") {
  // A, B and C each fill 25 strips with the next pattern, D with green.
  // The encoder encodes a tile for each use, nested ones included: C costs
  // 25 encodings, B 25 x 26 = 650, and A's uses of B 651 each, so A's tile
  // keeps 15 of them (9765 encodings) under the budget of 10000.
  std::string body;
  const char* const names[] = {"A", "B", "C", "D"};
  for (int level = 0; level < 4; level++) {
    body += std::string("<pattern id=\"") + names[level] + "\" patternUnits=\"userSpaceOnUse\" width=\"25\" height=\"10\">";
    const std::string fill = level < 3 ? std::string("url(#") + names[level + 1] + ")" : "green";
    for (int i = 0; i < 25; i++) body += "<rect x=\"" + std::to_string(i) + "\" width=\"1\" height=\"10\" fill=\"" + fill + "\"/>";
    body += "</pattern>";
  }
  body += R"~(<rect width="100" height="100" fill="url(#A)"/>)~";
  const auto r = parse(body);
  REQUIRE(r.scene.patterns.size() == 1);
  const mpvg::Scene& a = *r.scene.patterns[0].tile;
  size_t uses = 0;
  for (const mpvg::Paint& p : a.paints) uses += p.type == mpvg::PaintType::Pattern ? 1 : 0;
  CHECK(uses == 15);
  CHECK(r.warnings ==
        std::vector<std::string>{"patterns would need more than 10000 tile encodings: further pattern uses are not rendered"});
}
