// SVG frontend tests: text round trips. Each case parses a small document and
// compares mpvg::dump() of the scene with the exact expected text. Remember
// that the dump lists paths in stream order, which is top-most first: fills
// appear in reverse document order, clip tests in document order.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>

#include "core/error.h"
#include "parsers/svg/svg_dom.h"
#include "parsers/svg/svg_geometry.h"
#include "parsers/svg/svg_parser.h"
#include "parsers/svg/svg_values.h"
#include "parsers/svg/xml_encoding.h"
#include "parsers/svg/xml_syntax.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "frame/scene_info.h"

namespace {

const char* const kDefaultRoot = "viewBox=\"0 0 100 100\"";

// Parses `body` inside <svg ...root attributes...> with the SVG and XLink
// namespaces declared.
mpvg::svg::ParseResult parse(const std::string& body, const std::string& root = kDefaultRoot) {
  return mpvg::svg::parse_svg_string(svg_test::document(body, root));
}

std::string dump_of(const std::string& body, const std::string& root = kDefaultRoot) {
  return mpvg::dump(parse(body, root).scene);
}

// The dump without the geometry lines (those starting with two spaces).
std::string headers_of(const std::string& body, const std::string& root = kDefaultRoot) {
  return svg_test::without_geometry(dump_of(body, root));
}

// The message of the mpvg::Error that parsing `text` throws.
std::string error_of(const std::string& text) {
  try {
    mpvg::svg::parse_svg_string(text);
  } catch (const mpvg::Error& e) {
    return e.what();
  }
  return "(no error)";
}

bool has_warning(const mpvg::svg::ParseResult& r, const std::string& w) {
  for (const std::string& s : r.warnings)
    if (s == w) return true;
  return false;
}

}  // namespace

// ------------------------------------------------------------------ path data

TEST_CASE("svg path: every absolute command", "[svg][path]") {
  CHECK(
      dump_of(
          R"~(<path d="M 10 20 L 30 40 H 50 V 60 C 1 2 3 4 5 6 S 7 8 9 10 Q 11 12 13 14 T 15 16 A 5 5 0 0 1 25 16 Z"/>)~") ==
      R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 10 20 L 30 40 L 50 40 L 50 60 C 1 2 3 4 5 6 C 7 8 7 8 9 10 Q 11 12 13 14 Q 15 16 15 16 R 15 11 20 11 w 0.707107 R 25 11 25 16 w 0.707107 L 10 20 Z
stream F0
)~");
}

TEST_CASE("svg path: every relative command, and m after z", "[svg][path]") {
  // After z the current point is the subpath start (10 20), so "m 5 5" goes
  // to (15 25).
  CHECK(
      dump_of(
          R"~(<path d="m 10 20 l 10 10 h 5 v 5 c 1 2 3 4 5 6 s 1 1 2 2 q 1 1 2 2 t 2 0 a 5 5 0 0 0 10 0 z m 5 5 l 1 1"/>)~") ==
      R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 10 20 L 20 30 L 25 30 L 25 35 C 26 37 28 39 30 41 C 32 43 31 42 32 43 Q 33 44 34 45 Q 35 46 36 45 R 36 50 41 50 w 0.707107 R 46 50 46 45 w 0.707107 L 10 20 Z
  M 15 25 L 16 26
stream F0
)~");
}

TEST_CASE("svg path: implicit repeats, compact numbers, smooth reflection per family", "[svg][path]") {
  CHECK(dump_of(R"~(<path d="M0 0 10 0 10 10z"/>)~"
                R"~(<path d="M1.5.5-1-2.5e1 1e-3"/>)~"
                R"~(<path d="M 0 0 a1 1 0 00 1 1"/>)~"
                R"~(<path d="M 0 0 Q 10 0 10 10 S 20 20 30 30"/>)~"
                R"~(<path d="M 0 0 C 0 10 10 10 10 0 T 20 0"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 C 0 10 10 10 10 0 Q 10 0 20 0
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 Q 10 0 10 10 C 10 10 20 20 30 30
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 R 0 1 1 1 w 0.707107
path 3 fill nonzero rgba(0,0,0,1) opacity 1
  M 1.5 0.5 L -1 -25
path 4 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 10 0 L 10 10 L 0 0 Z
stream F0 F1 F2 F3 F4
)~");
}

TEST_CASE("svg path: errors keep what came before, closepath starts a new subpath", "[svg][path]") {
  // 1: stops at '#'. 2: no initial moveto, nothing. 3: arc flag '2'.
  // 4: a segment after Z starts at the subpath start. 5: lone movetos leave
  // no contours. 6: a number after Z is an error, everything before stays.
  CHECK(dump_of(R"~(<path d="M 10 10 L 20 20 L 30 # 40"/>)~"
                R"~(<path d="L 10 10 L 20 20"/>)~"
                R"~(<path d="M 0 0 L 10 0 A 5 5 0 2 1 20 0"/>)~"
                R"~(<path d="M 0 0 L 10 0 L 10 10 Z L 0 20 Z"/>)~"
                R"~(<path d="M 5 5 M 0 0 L 1 0 L 1 1 M 7 7"/>)~"
                R"~(<path d="M 0 0 L 10 0 10 10 Z 5 5"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 10 0 L 10 10 L 0 0 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 1 0 L 1 1
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 10 0 L 10 10 L 0 0 Z
  M 0 0 L 0 20 L 0 0 Z
path 3 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 10 0
path 4 fill nonzero rgba(0,0,0,1) opacity 1
  M 10 10 L 20 20
stream F0 F1 F2 F3 F4
)~");
  CHECK(dump_of(R"~(<path d="M 10 10 L nan 3"/><path d="M 1e999 0 L 1 1"/><path d=""/><path/>)~") ==
        "scene 100 100\nstream\n");
}

TEST_CASE("svg path: arcs as rational quadratics", "[svg][path][arc]") {
  // 1: radii too small are scaled up: a semicircle of radius 10 through
  // (10 -10). 2: 270 degrees = three quarter pieces. 3: zero radius is a line,
  // identical endpoints omit the arc.
  CHECK(dump_of(R"~(<path d="M 0 0 A 1 1 0 0 1 20 0"/>)~"
                R"~(<path d="M 75 50 A 25 25 0 1 1 50 25"/>)~"
                R"~(<path d="M 0 0 A 0 5 0 0 1 10 10 A 5 5 0 0 1 10 10"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 10 10
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 75 50 R 75 75 50 75 w 0.707107 R 25 75 25 50 w 0.707107 R 25 25 50 25 w 0.707107
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 R 0 -10 10 -10 w 0.707107 R 20 -10 20 0 w 0.707107
stream F0 F1 F2
)~");
}

TEST_CASE("svg path: a rotated elliptical arc is exact", "[svg][path][arc]") {
  // Large arc on the ellipse rx=20 ry=10 rotated by 30 degrees. Mapped back by
  // the inverse of rotate(30) scale(20 10), every piece must be an arc of one
  // unit circle: endpoints at distance 1 from a common center, the control
  // point at the tangents' intersection (the center is P1 + (M - P1) /
  // (1 - w^2), M the chord midpoint), and w = cos(half the piece angle).
  const auto r = parse(R"~(<path d="M 0 0 A 20 10 30 1 1 30 10"/>)~");
  REQUIRE(r.scene.geometries.size() == 1);
  const mpvg::Path& p = r.scene.geometries[0];
  REQUIRE(p.segments().size() >= 3);
  const double c30 = std::cos(M_PI / 6), s30 = std::sin(M_PI / 6);
  auto unit = [&](mpvg::Vec2 q) {  // inverse of rotate(30) then scale(20, 10)
    return mpvg::Vec2{(c30 * q.x + s30 * q.y) / 20, (-s30 * q.x + c30 * q.y) / 10};
  };
  mpvg::Vec2 center{};
  double total = 0;
  for (size_t i = 0; i < p.segments().size(); i++) {
    const auto& seg = p.segments()[i];
    REQUIRE(seg.type == mpvg::SegmentType::RQuad);
    const double w = p.weights()[seg.first_weight];
    const mpvg::Vec2 a = unit(p.points()[seg.first_point]), c = unit(p.points()[seg.first_point + 1]),
                     b = unit(p.points()[seg.first_point + 2]);
    const mpvg::Vec2 m = 0.5 * (a + b);
    const mpvg::Vec2 o = c + (1 / (1 - w * w)) * (m - c);
    if (i == 0) center = o;
    CHECK(o.x == Approx(center.x).margin(1e-9));
    CHECK(o.y == Approx(center.y).margin(1e-9));
    CHECK(std::hypot(a.x - o.x, a.y - o.y) == Approx(1).epsilon(1e-9));
    CHECK(std::hypot(b.x - o.x, b.y - o.y) == Approx(1).epsilon(1e-9));
    const double half = std::acos(std::clamp(dot(a - o, b - o), -1.0, 1.0)) / 2;
    CHECK(w == Approx(std::cos(half)).epsilon(1e-9));
    CHECK(half <= M_PI / 4 + 1e-12);
    total += 2 * half;
  }
  CHECK(total > M_PI);  // the large arc
  CHECK(p.points().back().x == 30);
  CHECK(p.points().back().y == 10);
}

// ------------------------------------------------------------------ shapes

TEST_CASE("svg rect: sizes and corner radius rules", "[svg][shapes]") {
  // In document order: plain; rx only (ry = rx); ry=50 clamped to w/2 and h/2
  // (zero-length edges dropped); negative rx is auto (= ry); rx=0 means
  // square; zero width, missing height, negative width: not rendered;
  // auto/auto: square.
  CHECK(dump_of(R"~(<rect x="10" y="20" width="30" height="40"/>)~"
                R"~(<rect x="10" y="20" width="30" height="40" rx="5"/>)~"
                R"~(<rect width="30" height="40" ry="50"/>)~"
                R"~(<rect width="30" height="40" rx="-5" ry="4"/>)~"
                R"~(<rect width="30" height="40" rx="0" ry="10"/>)~"
                R"~(<rect width="0" height="10"/><rect width="10"/><rect width="-10" height="10"/>)~"
                R"~(<rect width="20" height="10" rx="auto" ry="auto"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 20 0 L 20 10 L 0 10 L 0 0 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 30 0 L 30 40 L 0 40 L 0 0 Z
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 4 0 L 26 0 R 30 0 30 4 w 0.707107 L 30 36 R 30 40 26 40 w 0.707107 L 4 40 R 0 40 0 36 w 0.707107 L 0 4 R 0 0 4 0 w 0.707107 Z
path 3 fill nonzero rgba(0,0,0,1) opacity 1
  M 15 0 R 30 0 30 20 w 0.707107 R 30 40 15 40 w 0.707107 R 0 40 0 20 w 0.707107 R 0 0 15 0 w 0.707107 Z
path 4 fill nonzero rgba(0,0,0,1) opacity 1
  M 15 20 L 35 20 R 40 20 40 25 w 0.707107 L 40 55 R 40 60 35 60 w 0.707107 L 15 60 R 10 60 10 55 w 0.707107 L 10 25 R 10 20 15 20 w 0.707107 Z
path 5 fill nonzero rgba(0,0,0,1) opacity 1
  M 10 20 L 40 20 L 40 60 L 10 60 L 10 20 Z
stream F0 F1 F2 F3 F4 F5
)~");
}

TEST_CASE("svg circle and ellipse", "[svg][shapes]") {
  // Percentages without a viewBox resolve against the 200x100 viewport; r
  // against sqrt((w^2 + h^2) / 2). An auto ellipse radius takes the other
  // one; negative, zero or missing radii are not rendered.
  CHECK(dump_of(R"~(<circle cx="50" cy="40" r="10"/>)~"
                R"~(<ellipse cx="50" cy="40" rx="20" ry="10"/>)~"
                R"~(<ellipse cx="5" cy="5" ry="3"/>)~"
                R"~(<ellipse rx="-1" ry="-1"/><circle r="-5"/><circle r="0"/><ellipse rx="0" ry="10"/>)~"
                R"~(<circle cx="10%" cy="50%" r="10%"/>)~",
                R"~(width="200" height="100")~") ==
        R"~(scene 200 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 35.8114 50 R 35.8114 65.8114 20 65.8114 w 0.707107 R 4.18861 65.8114 4.18861 50 w 0.707107 R 4.18861 34.1886 20 34.1886 w 0.707107 R 35.8114 34.1886 35.8114 50 w 0.707107 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 8 5 R 8 8 5 8 w 0.707107 R 2 8 2 5 w 0.707107 R 2 2 5 2 w 0.707107 R 8 2 8 5 w 0.707107 Z
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 70 40 R 70 50 50 50 w 0.707107 R 30 50 30 40 w 0.707107 R 30 30 50 30 w 0.707107 R 70 30 70 40 w 0.707107 Z
path 3 fill nonzero rgba(0,0,0,1) opacity 1
  M 60 40 R 60 50 50 50 w 0.707107 R 40 50 40 40 w 0.707107 R 40 30 50 30 w 0.707107 R 60 30 60 40 w 0.707107 Z
stream F0 F1 F2 F3
)~");
}

TEST_CASE("svg line, polyline, polygon", "[svg][shapes]") {
  // line has no fill area; polyline stays open (fills close it anyway); the
  // odd trailing coordinate is dropped; parsing stops at invalid data; a
  // single point is nothing.
  CHECK(dump_of(R"~(<line x1="0" y1="0" x2="10" y2="10"/>)~"
                R"~(<polyline points="0,0 10,0 10,10 5"/>)~"
                R"~(<polygon points="0 0 10 0 10 10"/>)~"
                R"~(<polygon points="1 1 2 2 oops 3 3"/>)~"
                R"~(<polyline points="5 5"/><polygon/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 1 1 L 2 2 L 1 1 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 10 0 L 10 10 L 0 0 Z
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 10 0 L 10 10
stream F0 F1 F2
)~");
}

// ------------------------------------------------------------------ viewport and transforms

TEST_CASE("svg root size: units, percentages, defaults", "[svg][viewport]") {
  auto size = [](const std::string& attrs) {
    const auto r = mpvg::svg::parse_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\" " + attrs + "/>");
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g %g", r.scene.width, r.scene.height);
    return std::string(buf);
  };
  CHECK(size(R"~(width="10cm" height="1in")~") == "377.953 96");
  CHECK(size(R"~(height="5mm" width="2pc")~") == "32 18.8976");
  CHECK(size(R"~(width="2em" height="3ex")~") == "32 24");
  CHECK(size(R"~(width="50%" height="10pt" viewBox="0 0 40 30")~") == "20 13.3333");
  CHECK(size(R"~(viewBox="0 0 40 30")~") == "40 30");
  CHECK(size(R"~(width="30")~") == "30 100");
  CHECK(size("") == "100 100");
  CHECK(size(R"~(viewBox="0 0 -5 10")~") == "100 100");  // negative: invalid viewBox, ignored
  CHECK(size(R"~(width="auto" height="7px")~") == "100 7");
}

TEST_CASE("svg root size: zero sizes give an empty scene", "[svg][viewport]") {
  CHECK(dump_of("<rect width=\"5\" height=\"5\"/>", R"~(width="0" height="10")~") == "scene 0 10\nstream\n");
  CHECK(dump_of("<rect width=\"5\" height=\"5\"/>", R"~(viewBox="0 0 0 10")~") == "scene 0 10\nstream\n");
  CHECK(dump_of("<rect width=\"5\" height=\"5\"/>", R"~(display="none")~") == "scene 100 100\nstream\n");
}

TEST_CASE("svg viewBox and preserveAspectRatio", "[svg][viewport]") {
  // viewBox 10 20 50 100 into a 200x100 viewport: meet scales by 1 and
  // leaves 150 units free horizontally; slice scales by 4 and crops 300
  // vertically.
  auto matrix = [](const std::string& par) {
    return headers_of("<rect width=\"1\" height=\"1\"/>",
                      "width=\"200\" height=\"100\" viewBox=\"10 20 50 100\" " + par);
  };
  auto expect = [](const std::string& m) {
    return "scene 200 100\npath 0 fill nonzero rgba(0,0,0,1) opacity 1 matrix(" + m + ")\nstream F0\n";
  };
  CHECK(matrix("") == expect("1 0 0 1 65 -20"));
  CHECK(matrix(R"~(preserveAspectRatio="xMinYMin")~") == expect("1 0 0 1 -10 -20"));
  CHECK(matrix(R"~(preserveAspectRatio="xMaxYMax meet")~") == expect("1 0 0 1 140 -20"));
  CHECK(matrix(R"~(preserveAspectRatio="xMidYMid slice")~") == expect("4 0 0 4 -40 -230"));
  CHECK(matrix(R"~(preserveAspectRatio="xMinYMax slice")~") == expect("4 0 0 4 -40 -380"));
  CHECK(matrix(R"~(preserveAspectRatio="none")~") == expect("4 0 0 1 -40 -20"));
  CHECK(matrix(R"~(preserveAspectRatio="defer xMaxYMin")~") == expect("1 0 0 1 140 -20"));
  CHECK(matrix(R"~(preserveAspectRatio="bogus")~") == expect("1 0 0 1 65 -20"));
}

TEST_CASE("svg transforms: each kind, lists, nesting under a viewBox", "[svg][transform]") {
  // The viewBox maps 100 user units to 200 px: every matrix includes scale(2).
  CHECK(headers_of(R"~(<rect width="1" height="1" transform="translate(10)"/>)~"
                   R"~(<rect width="1" height="1" transform="translate(10,20) scale(2)"/>)~"
                   R"~(<rect width="1" height="1" transform="scale(2 3)"/>)~"
                   R"~(<rect width="1" height="1" transform="rotate(90)"/>)~"
                   R"~(<rect width="1" height="1" transform="rotate(90 10 20)"/>)~"
                   R"~(<rect width="1" height="1" transform="skewX(45)"/>)~"
                   R"~(<rect width="1" height="1" transform="skewY(45)"/>)~"
                   R"~(<rect width="1" height="1" transform=" matrix(1,2,3,4,5,6) , translate(1 1)"/>)~"
                   R"~(<rect width="1" height="1" transform="translate(10) oops"/>)~"
                   R"~(<g transform="translate(5 5)"><rect width="1" height="1" transform="scale(2)"/></g>)~",
                   R"~(width="200" height="200" viewBox="0 0 100 100")~") ==
        R"~(scene 200 200
path 0 fill nonzero rgba(0,0,0,1) opacity 1 matrix(4 0 0 4 10 10)
path 1 fill nonzero rgba(0,0,0,1) opacity 1 matrix(2 0 0 2 0 0)
path 2 fill nonzero rgba(0,0,0,1) opacity 1 matrix(2 4 6 8 18 24)
path 3 fill nonzero rgba(0,0,0,1) opacity 1 matrix(2 2 0 2 0 0)
path 4 fill nonzero rgba(0,0,0,1) opacity 1 matrix(2 0 2 2 0 0)
path 5 fill nonzero rgba(0,0,0,1) opacity 1 matrix(0 2 -2 0 60 20)
path 6 fill nonzero rgba(0,0,0,1) opacity 1 matrix(0 2 -2 0 0 0)
path 7 fill nonzero rgba(0,0,0,1) opacity 1 matrix(4 0 0 6 0 0)
path 8 fill nonzero rgba(0,0,0,1) opacity 1 matrix(4 0 0 4 20 40)
path 9 fill nonzero rgba(0,0,0,1) opacity 1 matrix(2 0 0 2 20 0)
stream F0 F1 F2 F3 F4 F5 F6 F7 F8 F9
)~");
}

TEST_CASE("svg transforms: style property, degenerate matrices", "[svg][transform]") {
  // transform in style wins over the attribute; a non-invertible transform
  // shows nothing; an overflowing one neither.
  CHECK(
      headers_of(
          R"~(<rect width="1" height="1" transform="scale(5)" style="transform: translate(3 4)"/>)~"
          R"~(<rect width="1" height="1" transform="scale(0 1)"/>)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)"><g transform="scale(1e9)">)~"
          R"~(<rect width="1" height="1"/>)~"
          R"~(</g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g>)~"
          R"~(</g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g></g>)~") ==
      R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1 matrix(1 0 0 1 3 4)
stream F0
)~");
}

// ------------------------------------------------------------------ style

TEST_CASE("svg style: style attribute over presentation attributes, inheritance", "[svg][style]") {
  // In document order under a red evenodd group: inherits; style wins over
  // the attribute; an invalid declaration is dropped (inherit red, and
  // fill-rule from style); an invalid declaration falls back to the
  // attribute; comments and !important; "inherit"; invalid colour inherits.
  CHECK(headers_of(
            R"~(<g fill="red" fill-rule="evenodd">)~"
            R"~(<rect width="1" height="1"/>)~"
            R"~(<rect width="1" height="1" fill="blue" style="fill: lime"/>)~"
            R"~(<rect width="1" height="1" style="fill:bogus; fill-rule: nonzero"/>)~"
            R"~(<rect width="1" height="1" fill="blue" style="fill: bogus"/>)~"
            R"~(<rect width="1" height="1" style="/* c */ fill : #00f !important ; fill-opacity: 50%"/>)~"
            R"~(<rect width="1" height="1" fill="inherit" fill-opacity=".25"/>)~"
            R"~(<rect width="1" height="1" fill="nonsense"/></g>)~") ==
        R"~(scene 100 100
path 0 fill evenodd rgba(1,0,0,1) opacity 1
path 1 fill evenodd rgba(1,0,0,1) opacity 0.25
path 2 fill evenodd rgba(0,0,1,1) opacity 0.5
path 3 fill evenodd rgba(0,0,1,1) opacity 1
path 4 fill nonzero rgba(1,0,0,1) opacity 1
path 5 fill evenodd rgba(0,1,0,1) opacity 1
path 6 fill evenodd rgba(1,0,0,1) opacity 1
stream F0 F1 F2 F3 F4 F5 F6
)~");
}

TEST_CASE("svg style: colours of every syntax", "[svg][style][color]") {
  // Document order: named (any case); #rgb; #rgba; #rrggbb; #rrggbbaa;
  // rgb() integers; percentages clamped; rgba(); space syntax with "/ 25%";
  // hsl(); hsla(); transparent (alpha 0: not emitted); currentColor; integers
  // clamped; invalid (#12345) falls back to the default black.
  CHECK(headers_of(R"~(<rect width="1" height="1" fill="CornflowerBlue"/>)~"
                   R"~(<rect width="1" height="1" fill="#f80"/>)~"
                   R"~(<rect width="1" height="1" fill="#f808"/>)~"
                   R"~(<rect width="1" height="1" fill="#FF8000"/>)~"
                   R"~(<rect width="1" height="1" fill="#ff800080"/>)~"
                   R"~(<rect width="1" height="1" fill="rgb(255, 128, 0)"/>)~"
                   R"~(<rect width="1" height="1" fill="RGB(100%, 50%, 150%)"/>)~"
                   R"~(<rect width="1" height="1" fill="rgba(0,0,255,0.5)"/>)~"
                   R"~(<rect width="1" height="1" fill="rgb(0 0 255 / 25%)"/>)~"
                   R"~(<rect width="1" height="1" fill="hsl(120, 100%, 25%)"/>)~"
                   R"~(<rect width="1" height="1" fill="hsla(240,100%,50%,0.5)"/>)~"
                   R"~(<rect width="1" height="1" fill="transparent"/>)~"
                   R"~(<rect width="1" height="1" color="teal" fill="currentColor"/>)~"
                   R"~(<rect width="1" height="1" fill="rgb(-10,300,0)"/>)~"
                   R"~(<rect width="1" height="1" fill="#12345"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
path 1 fill nonzero rgba(0,1,0,1) opacity 1
path 2 fill nonzero rgba(0,0.501961,0.501961,1) opacity 1
path 3 fill nonzero rgba(0,0,1,0.5) opacity 1
path 4 fill nonzero rgba(0,0.5,0,1) opacity 1
path 5 fill nonzero rgba(0,0,1,0.25) opacity 1
path 6 fill nonzero rgba(0,0,1,0.5) opacity 1
path 7 fill nonzero rgba(1,0.5,1,1) opacity 1
path 8 fill nonzero rgba(1,0.501961,0,1) opacity 1
path 9 fill nonzero rgba(1,0.501961,0,0.501961) opacity 1
path 10 fill nonzero rgba(1,0.501961,0,1) opacity 1
path 11 fill nonzero rgba(1,0.533333,0,0.533333) opacity 1
path 12 fill nonzero rgba(1,0.533333,0,1) opacity 1
path 13 fill nonzero rgba(0.392157,0.584314,0.929412,1) opacity 1
stream F0 F1 F2 F3 F4 F5 F6 F7 F8 F9 F10 F11 F12 F13
)~");
}

TEST_CASE("svg style: an inherited currentColor takes the inheriting element's color", "[svg][style][color]") {
  // CSS Color 4 §6.4: currentColor inherits as the keyword, so the first
  // rect's inherited fill is its own color (red; Chromium and rsvg-convert
  // draw it so), the second declares fill=currentColor with color=olive,
  // the third has no color but the initial black.
  CHECK(headers_of(R"~(<g color="navy" fill="currentColor"><rect width="1" height="1" color="red"/>)~"
                   R"~(<rect width="1" height="1" color="olive" fill="currentColor"/></g>)~"
                   R"~(<rect width="1" height="1" fill="currentColor"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
path 1 fill nonzero rgba(0.501961,0.501961,0,1) opacity 1
path 2 fill nonzero rgba(1,0,0,1) opacity 1
stream F0 F1 F2
)~");
}

TEST_CASE("svg style: opacity and fill-opacity", "[svg][style][opacity]") {
  // fill-opacity x opacity x the group's opacity; opacity="inherit" takes the
  // parent's value (so the group's 0.5 counts twice); 150% clamps to 1;
  // opacity 0 is not emitted. A group of two shapes is one transparency
  // group; on a single shape opacity folds into its paint.
  const auto r =
      parse(R"~(<g opacity="0.5"><rect width="1" height="1" fill-opacity="0.5" opacity="0.5"/>)~"
            R"~(<rect width="2" height="2" opacity="inherit"/></g>)~"
            R"~(<rect width="3" height="3" opacity="150%"/><rect width="4" height="4" opacity="0"/>)~"
            R"~(<g opacity="0.25"><rect width="5" height="5"/></g>)~");
  CHECK(mpvg::dump(r.scene) == R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 0.25
  M 0 0 L 5 0 L 5 5 L 0 5 L 0 0 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 3 0 L 3 3 L 0 3 L 0 0 Z
path 2 fill nonzero rgba(0,0,0,1) opacity 0.5
  M 0 0 L 2 0 L 2 2 L 0 2 L 0 0 Z
path 3 fill nonzero rgba(0,0,0,1) opacity 0.25
  M 0 0 L 1 0 L 1 1 L 0 1 L 0 0 Z
group 0 opacity 0.5 normal
stream F0 F1 {0 F2 F3 }
)~");
  CHECK(r.warnings.empty());
}

TEST_CASE("svg style: display and visibility", "[svg][style]") {
  // display="none" removes the subtree (style wins over the attribute);
  // visibility is inherited and a child may override it.
  CHECK(
      headers_of(
          R"~(<g display="none"><rect width="1" height="1"/></g>)~"
          R"~(<g visibility="hidden"><rect width="2" height="2"/><rect width="3" height="3" visibility="visible"/></g>)~"
          R"~(<rect width="4" height="4" style="display:none" display="inline"/>)~"
          R"~(<rect width="5" height="5" display="block"/>)~"
          R"~(<rect width="6" height="6" visibility="collapse"/>)~") ==
      R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
path 1 fill nonzero rgba(0,0,0,1) opacity 1
stream F0 F1
)~");
  const auto r = parse(R"~(<g visibility="hidden"><rect width="3" height="3" visibility="visible"/></g>)~");
  CHECK(r.scene.geometries.at(0).points().at(1).x == 3);
}

TEST_CASE("svg style: paint servers fall back", "[svg][style][paint]") {
  // Document order: gradient with a fallback colour (the gradient paints);
  // gradient alone; missing element with a fallback; missing without (not
  // rendered); reference to a non-paint-server (not rendered despite the
  // fallback); quoted IRI with a currentColor fallback (the gradient).
  // tests/test_svg_paint_servers.cpp covers the paint servers themselves.
  const auto r = parse(R"~(<linearGradient id="lg"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient>)~"
                       R"~(<rect id="a" width="1" height="1" fill="url(#lg) green"/>)~"
                       R"~(<rect width="2" height="2" fill="url(#lg)"/>)~"
                       R"~(<rect width="3" height="3" fill="url(#missing) #00f"/>)~"
                       R"~(<rect width="4" height="4" fill="url(#missing)"/>)~"
                       R"~(<rect width="5" height="5" fill="url(#a) red"/>)~"
                       R"~(<rect width="6" height="6" color="olive" fill="url( '#lg' ) currentColor"/>)~");
  CHECK(mpvg::dump(r.scene) == R"~(scene 100 100
path 0 fill nonzero linear 2 opacity 1
  M 0 0 L 6 0 L 6 6 L 0 6 L 0 0 Z
path 1 fill nonzero rgba(0,0,1,1) opacity 1
  M 0 0 L 3 0 L 3 3 L 0 3 L 0 0 Z
path 2 fill nonzero linear 1 opacity 1
  M 0 0 L 2 0 L 2 2 L 0 2 L 0 0 Z
path 3 fill nonzero linear 0 opacity 1
  M 0 0 L 1 0 L 1 1 L 0 1 L 0 0 Z
gradient 0 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 1 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb matrix(2 0 0 2 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
gradient 2 linear 0 0 1 0 radial 0 0 0 0 0 0 pad srgb matrix(6 0 0 6 0 0)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream F0 F1 F2 F3
)~");
  CHECK(r.warnings.empty());
}

// ------------------------------------------------------------------ structure

TEST_CASE("svg use: translation, href precedence, inheritance, recursion", "[svg][use]") {
  // use#r with x/y and a transform: scale(2) then translate(5 6); the rect
  // inherits the use's fill. href wins over xlink:href; the group's rect
  // inherits through the use; the nested use inherits too. A self-reference
  // and a missing target render nothing.
  const auto r =
      parse(R"~(<defs><rect id="r" width="10" height="10" fill-opacity="0.5"/>)~"
            R"~(<g id="g"><rect width="1" height="1" fill="inherit"/><use href="#r" x="1"/></g></defs>)~"
            R"~(<use xlink:href="#r" x="5" y="6" fill="red" transform="scale(2)"/>)~"
            R"~(<use href="#g" xlink:href="#r" fill="blue" fill-opacity="0.1"/>)~"
            R"~(<use href="#self" id="self"/><use href="#missing"/>)~");
  CHECK(mpvg::dump(r.scene) == R"~(scene 100 100
path 0 fill nonzero rgba(0,0,1,1) opacity 0.5 matrix(1 0 0 1 1 0)
  M 0 0 L 10 0 L 10 10 L 0 10 L 0 0 Z
path 1 fill nonzero rgba(0,0,1,1) opacity 0.1
  M 0 0 L 1 0 L 1 1 L 0 1 L 0 0 Z
path 2 fill nonzero rgba(1,0,0,1) opacity 0.5 matrix(2 0 0 2 10 12)
  M 0 0 L 10 0 L 10 10 L 0 10 L 0 0 Z
stream F0 F1 F2
)~");
  CHECK(has_warning(r, "recursive use reference ignored"));
}

TEST_CASE("svg use: indirect recursion is cut, content before it stays", "[svg][use]") {
  // g1 uses itself through use2: the inner reference is dropped.
  CHECK(headers_of(R"~(<g id="g1"><rect width="1" height="1"/><use id="u1" href="#u2"/></g>)~"
                   R"~(<use id="u2" href="#g1" x="10"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1 matrix(1 0 0 1 10 0)
path 1 fill nonzero rgba(0,0,0,1) opacity 1
stream F0 F1
)~");
}

TEST_CASE("svg structure: defs, namespaces, unknown elements", "[svg][structure]") {
  // defs content is not rendered; elements of other namespaces (and their
  // subtrees) are ignored; a prefixed SVG element counts; unsupported
  // elements are ignored with one warning per name.
  const auto r = mpvg::svg::parse_svg_string(
      R"~(<s:svg xmlns:s="http://www.w3.org/2000/svg" viewBox="0 0 10 10">)~"
      R"~(<s:defs><s:rect width="9" height="9"/></s:defs>)~"
      R"~(<s:rect width="1" height="1"/><rect width="2" height="2"/>)~"
      R"~(<x:g xmlns:x="urn:other"><s:rect width="3" height="3"/></x:g>)~"
      R"~(<g xmlns="http://www.w3.org/2000/svg"><rect width="4" height="4"/><foreignObject/><foreignObject/></g>)~"
      R"~(<s:a><s:circle r="1"/></s:a></s:svg>)~");
  CHECK(mpvg::dump(r.scene) == R"~(scene 10 10
path 0 fill nonzero rgba(0,0,0,1) opacity 1
  M 1 0 R 1 1 0 1 w 0.707107 R -1 1 -1 0 w 0.707107 R -1 -1 0 -1 w 0.707107 R 1 -1 1 0 w 0.707107 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 4 0 L 4 4 L 0 4 L 0 0 Z
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 0 0 L 1 0 L 1 1 L 0 1 L 0 0 Z
stream F0 F1 F2
)~");
  CHECK(r.warnings == std::vector<std::string>{"<foreignObject> elements are not supported: ignored"});
  // Without any namespace declaration the document is still taken as SVG.
  CHECK(mpvg::dump(
            mpvg::svg::parse_svg_string(R"~(<svg width="5" height="5"><rect width="1" height="1"/></svg>)~")
                .scene) ==
        "scene 5 5\npath 0 fill nonzero rgba(0,0,0,1) opacity 1\n  M 0 0 L 1 0 L 1 1 L 0 1 L 0 0 Z\nstream "
        "F0\n");
}

TEST_CASE("svg structure: internal DTD entities", "[svg][structure]") {
  const auto r = mpvg::svg::parse_svg_string(
      "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [\n<!ENTITY ns \"http://www.w3.org/2000/svg\">\n"
      "<!ENTITY Shape \"<rect width='2' height='3' fill='green'/>\">\n]>\n"
      "<svg xmlns=\"&ns;\" viewBox=\"0 0 10 10\">&Shape;</svg>");
  CHECK(mpvg::dump(r.scene) == R"~(scene 10 10
path 0 fill nonzero rgba(0,0.501961,0,1) opacity 1
  M 0 0 L 2 0 L 2 3 L 0 3 L 0 0 Z
stream F0
)~");
}

// ------------------------------------------------------------------ clipping

TEST_CASE("svg clip-path: items, clip-rule, transforms, invalid children", "[svg][clip]") {
  // clipPath transform translate(1 2) applies inside the clipped element's
  // space translate(5 5); the circle's own transform and clip-rule apply;
  // g, display="none" and line children do not count (text in clip paths:
  // test_svg_text).
  const auto r = parse(
      R"~(<clipPath id="c" transform="translate(1 2)"><rect width="10" height="10"/>)~"
      R"~(<circle cx="5" cy="5" r="5" clip-rule="evenodd" transform="scale(2)"/>)~"
      R"~(<g><rect width="50" height="50"/></g><rect width="20" height="20" display="none"/>)~"
      R"~(<line x2="10" y2="10"/></clipPath>)~"
      R"~(<rect width="30" height="30" fill="green" clip-path="url(#c)" transform="translate(5 5)"/>)~");
  CHECK(mpvg::dump(r.scene) == R"~(scene 100 100
path 0 clip nonzero matrix(1 0 0 1 6 7)
  M 0 0 L 10 0 L 10 10 L 0 10 L 0 0 Z
path 1 clip evenodd matrix(2 0 0 2 6 7)
  M 10 5 R 10 10 5 10 w 0.707107 R 0 10 0 5 w 0.707107 R 0 0 5 0 w 0.707107 R 10 0 10 5 w 0.707107 Z
path 2 fill nonzero rgba(0,0.501961,0,1) opacity 1 matrix(1 0 0 1 5 5)
  M 0 0 L 30 0 L 30 30 L 0 30 L 0 0 Z
stream ( C0 C1 | F2 )
)~");
}

TEST_CASE("svg clip-path: clip-rule inherits from the clipPath's ancestors", "[svg][clip]") {
  CHECK(headers_of(R"~(<g clip-rule="evenodd"><clipPath id="c"><rect width="5" height="5"/></clipPath></g>)~"
                   R"~(<g clip-rule="nonzero"><rect width="9" height="9" clip-path="url(#c)"/></g>)~") ==
        R"~(scene 100 100
path 0 clip evenodd
path 1 fill nonzero rgba(0,0,0,1) opacity 1
stream ( C0 | F1 )
)~");
}

TEST_CASE("svg clip-path: empty, invisible, missing and invalid references", "[svg][clip]") {
  // Document order: an empty clipPath clips everything; a hidden-only
  // clipPath too; a missing id is ignored (resvg, masking/clipPath/
  // invalid-FuncIRI); a reference to a non-clipPath hides the element; a
  // group without fills is not wrapped at all.
  CHECK(
      headers_of(
          R"~(<clipPath id="e"/><clipPath id="h"><rect width="5" height="5" visibility="hidden"/></clipPath>)~"
          R"~(<rect width="1" height="1" clip-path="url(#e)"/>)~"
          R"~(<rect width="2" height="2" clip-path="url(#h)"/>)~"
          R"~(<rect width="3" height="3" clip-path="url(#nowhere)"/>)~"
          R"~(<rect id="notclip" width="4" height="4" clip-path="url(#notclip)"/>)~"
          R"~(<g clip-path="url(#e)" fill="none"><rect width="5" height="5"/></g>)~") ==
      R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
path 1 fill nonzero rgba(0,0,0,1) opacity 1
path 2 fill nonzero rgba(0,0,0,1) opacity 1
stream F0 ( | F1 ) ( | F2 )
)~");
}

TEST_CASE("svg clip-path: objectBoundingBox units use tight bounds", "[svg][clip]") {
  // circle: bounds 30..70. Cubic: its y extremum is 0.75 * 40 = 30, not the
  // control polygon's 40; the element's transform comes on top. Group: the
  // union of its children, fill="none" included. A line (no area) and a
  // fill-less rect draw nothing.
  CHECK(
      headers_of(
          R"~(<clipPath id="o" clipPathUnits="objectBoundingBox"><rect x="0.25" y="0.25" width="0.5" height="0.5"/></clipPath>)~"
          R"~(<circle cx="50" cy="50" r="20" clip-path="url(#o)"/>)~"
          R"~(<path d="M 0 0 C 0 40 40 40 40 0 Z" transform="translate(10 10)" clip-path="url(#o)"/>)~"
          R"~(<g clip-path="url(#o)"><rect x="10" y="10" width="10" height="10"/>)~"
          R"~(<rect x="30" y="5" width="10" height="10" fill="none"/></g>)~"
          R"~(<line x2="10" y2="0" clip-path="url(#o)"/>)~"
          R"~(<rect width="10" height="10" fill="none" clip-path="url(#o)"/>)~") ==
      R"~(scene 100 100
path 0 clip nonzero matrix(30 0 0 15 10 5)
path 1 fill nonzero rgba(0,0,0,1) opacity 1
path 2 clip nonzero matrix(40 0 0 30 10 10)
path 3 fill nonzero rgba(0,0,0,1) opacity 1 matrix(1 0 0 1 10 10)
path 4 clip nonzero matrix(40 0 0 40 30 30)
path 5 fill nonzero rgba(0,0,0,1) opacity 1
stream ( C0 | F1 ) ( C2 | F3 ) ( C4 | F5 )
)~");
}

TEST_CASE("svg clip-path: bounding boxes count hidden children and rotated curves", "[svg][clip]") {
  // A hidden shape still counts for the group's box (SVG 2 bounding boxes;
  // resvg painting/visibility/bbox-impact). The rotated rect's tight box is
  // 20 +- 10 sqrt(2).
  CHECK(headers_of(
            R"~(<clipPath id="o" clipPathUnits="objectBoundingBox"><rect width="1" height="1"/></clipPath>)~"
            R"~(<g clip-path="url(#o)"><rect x="0" y="0" width="50" height="50" visibility="hidden"/>)~"
            R"~(<rect x="10" y="10" width="20" height="20" transform="rotate(45 20 20)"/></g>)~") ==
        R"~(scene 100 100
path 0 clip nonzero matrix(50 0 0 50 0 0)
path 1 fill nonzero rgba(0,0,0,1) opacity 1 matrix(0.707107 0.707107 -0.707107 0.707107 20 -8.28427)
stream ( C0 | F1 )
)~");
  CHECK(
      headers_of(
          R"~(<clipPath id="o" clipPathUnits="objectBoundingBox"><rect width="1" height="1"/></clipPath>)~"
          R"~(<g clip-path="url(#o)"><rect x="10" y="10" width="20" height="20" transform="rotate(45 20 20)"/></g>)~") ==
      R"~(scene 100 100
path 0 clip nonzero matrix(28.2843 0 0 28.2843 5.85786 5.85786)
path 1 fill nonzero rgba(0,0,0,1) opacity 1 matrix(0.707107 0.707107 -0.707107 0.707107 20 -8.28427)
stream ( C0 | F1 )
)~");
}

TEST_CASE("svg clip-path: nested clip paths", "[svg][clip]") {
  // r is clipped by a; a is clipped by b (intersection, in r's space, not
  // a's transform); a's child rect is clipped by c in objectBoundingBox units
  // of that child. u holds a use (x=3) of r with its own clip c: the use's box
  // is r's box in the use's space (1..21, offset by 3). self references itself
  // twice; both references are ignored.
  const auto r = parse(
      R"~(<clipPath id="a" clip-path="url(#b)"><rect width="10" height="10" clip-path="url(#c)"/></clipPath>)~"
      R"~(<clipPath id="b" transform="translate(100 0)"><circle r="5"/></clipPath>)~"
      R"~(<clipPath id="c" clipPathUnits="objectBoundingBox"><rect width="0.5" height="1"/></clipPath>)~"
      R"~(<clipPath id="self" clip-path="url(#self)"><rect width="1" height="1" clip-path="url(#self)"/></clipPath>)~"
      R"~(<rect id="r" width="20" height="20" transform="translate(1 1)" clip-path="url(#a)"/>)~"
      R"~(<clipPath id="u"><use href="#r" x="3" clip-path="url(#c)"/></clipPath>)~"
      R"~(<rect width="2" height="2" clip-path="url(#self)"/>)~"
      R"~(<rect width="3" height="3" clip-path="url(#u)"/>)~");
  CHECK(svg_test::without_geometry(mpvg::dump(r.scene)) == R"~(scene 100 100
path 0 clip nonzero matrix(20 0 0 20 4 1)
path 1 clip nonzero matrix(1 0 0 1 104 1)
path 2 clip nonzero matrix(10 0 0 10 4 1)
path 3 clip nonzero matrix(1 0 0 1 4 1)
path 4 clip nonzero matrix(1 0 0 1 4 1)
path 5 fill nonzero rgba(0,0,0,1) opacity 1
path 6 clip nonzero
path 7 fill nonzero rgba(0,0,0,1) opacity 1
path 8 clip nonzero matrix(1 0 0 1 101 1)
path 9 clip nonzero matrix(10 0 0 10 1 1)
path 10 clip nonzero matrix(1 0 0 1 1 1)
path 11 fill nonzero rgba(0,0,0,1) opacity 1 matrix(1 0 0 1 1 1)
stream ( ( C0 | ( ( C1 | ( C2 | C3 ) ) | C4 ) ) | F5 ) ( C6 | F7 ) ( ( C8 | ( C9 | C10 ) ) | F11 )
)~");
  CHECK(r.warnings == std::vector<std::string>{"recursive clip-path reference ignored"});
}

TEST_CASE("svg clip-path: on groups, use and the root, with group opacity", "[svg][clip]") {
  // The group clip uses the group's box (rotated rect and the use's rect at
  // x+5) mapped through the clipPath transform; the group's opacity is one
  // transparency group inside the clip group, whose fills the stream lists
  // top-most first.
  const auto r = parse(
      R"~(<clipPath id="obb" clipPathUnits="objectBoundingBox" transform="translate(0.1 0)"><rect width="0.5" height="0.5"/></clipPath>)~"
      R"~(<clipPath id="k"><rect width="50" height="50"/></clipPath>)~"
      R"~(<g clip-path="url(#obb)" opacity="0.5" fill="blue">)~"
      R"~(<rect x="10" y="20" width="20" height="20" transform="rotate(45 20 30)"/>)~"
      R"~(<use href="#r" x="5" clip-path="url(#k)"/></g>)~"
      R"~(<rect id="r" x="60" y="10" width="10" height="10" fill="red"/>)~",
      R"~(width="200" height="100" viewBox="0 0 100 100" clip-path="url(#k)")~");
  CHECK(mpvg::dump(r.scene) == R"~(scene 200 100
path 0 clip nonzero matrix(1 0 0 1 50 0)
  M 0 0 L 50 0 L 50 50 L 0 50 L 0 0 Z
path 1 fill nonzero rgba(1,0,0,1) opacity 1 matrix(1 0 0 1 50 0)
  M 60 10 L 70 10 L 70 20 L 60 20 L 60 10 Z
path 2 clip nonzero matrix(69.1421 0 0 34.1421 55.9579 10)
  M 0 0 L 0.5 0 L 0.5 0.5 L 0 0.5 L 0 0 Z
path 3 clip nonzero matrix(1 0 0 1 55 0)
  M 0 0 L 50 0 L 50 50 L 0 50 L 0 0 Z
path 4 fill nonzero rgba(1,0,0,1) opacity 1 matrix(1 0 0 1 55 0)
  M 60 10 L 70 10 L 70 20 L 60 20 L 60 10 Z
path 5 fill nonzero rgba(0,0,1,1) opacity 1 matrix(0.707107 0.707107 -0.707107 0.707107 77.0711 -5.35534)
  M 10 20 L 30 20 L 30 40 L 10 40 L 10 20 Z
group 0 opacity 0.5 normal
stream ( C0 | F1 ( C2 | {0 ( C3 | F4 ) F5 } ) )
)~");
  CHECK(r.warnings.empty());
}

TEST_CASE("svg clip-path: use children of clipPath", "[svg][clip]") {
  // A use of a shape counts with the use's offset; a use of a group or a
  // line does not.
  CHECK(
      headers_of(
          R"~(<defs><rect id="s" width="4" height="4" transform="scale(2)"/><g id="g"><rect width="9" height="9"/></g>)~"
          R"~(<line id="l" x2="5" y2="5"/></defs>)~"
          R"~(<clipPath id="c"><use href="#s" x="1" y="2"/><use href="#g"/><use href="#l"/></clipPath>)~"
          R"~(<rect width="20" height="20" clip-path="url(#c)"/>)~") ==
      R"~(scene 100 100
path 0 clip nonzero matrix(2 0 0 2 1 2)
path 1 fill nonzero rgba(0,0,0,1) opacity 1
stream ( C0 | F1 )
)~");
}

// ------------------------------------------------------------------ bounds

TEST_CASE("svg bounds: tight boxes of conics and cubics", "[svg][bounds]") {
  using mpvg::svg::detail::add_path_bounds;
  using mpvg::svg::detail::Bounds;
  using mpvg::svg::detail::ellipse_path;
  // An ellipse rx=2 ry=1 rotated by 45 degrees: half extents
  // sqrt(rx^2 cos^2 + ry^2 sin^2) = sqrt(2.5) on both axes.
  const double c = std::sqrt(0.5);
  Bounds b;
  add_path_bounds(ellipse_path(0, 0, 2, 1), mpvg::Affine{c, c, -c, c, 10, 20}, b);
  CHECK(b.x0 == Approx(10 - std::sqrt(2.5)));
  CHECK(b.x1 == Approx(10 + std::sqrt(2.5)));
  CHECK(b.y0 == Approx(20 - std::sqrt(2.5)));
  CHECK(b.y1 == Approx(20 + std::sqrt(2.5)));
  // A cubic whose control points overshoot: x in [0, 10], y up to 7.5.
  mpvg::Path cubic;
  cubic.move_to({0, 0});
  cubic.cubic_to({0, 10}, {10, 10}, {10, 0});
  Bounds cb;
  add_path_bounds(cubic, mpvg::Affine{}, cb);
  CHECK(cb.x0 == 0);
  CHECK(cb.x1 == 10);
  CHECK(cb.y0 == 0);
  CHECK(cb.y1 == Approx(7.5));
}

// ------------------------------------------------------------------ errors and robustness

TEST_CASE("svg errors: one clear line each", "[svg][errors]") {
  CHECK(error_of("<svg><g></svg>") ==
        "XML parse error at line 1, column 9: </svg> does not close <g> (opened at line 1, column 6)");
  CHECK(error_of("<svg>\n<rect x='1' x='2'/></svg>") ==
        "XML parse error at line 2, column 13: the attribute 'x' appears twice in <rect>");
  CHECK(error_of("") == "XML parse error at line 1, column 1: no element: the document is empty or holds no XML");
  // Files handed to svg2png by mistake.
  CHECK(error_of("%PDF-1.7\n%\xe2\xe3\n1 0 obj") == "the input is a PDF document, not SVG: render it with pdf2png");
  CHECK(error_of("\x89PNG\r\n\x1a\n....") == "the input is a PNG image, not SVG");
  CHECK(error_of("<html xmlns='http://www.w3.org/1999/xhtml'/>") ==
        "not an SVG document: the root element is <html>, not <svg>");
  CHECK(error_of("<svg xmlns='http://example.org/'/>") ==
        "not an SVG document: the root <svg> is in namespace 'http://example.org/', not "
        "http://www.w3.org/2000/svg");
  CHECK(error_of("<!-- nothing -->") == "not an SVG document: no root element");
  CHECK(error_of("<svg width='-5' height='10'/>") == "invalid root <svg>: negative width '-5'");
  CHECK(error_of("<svg height='-1%' viewBox='0 0 10 10'/>") == "invalid root <svg>: negative height '-1%'");
  CHECK_THROWS_AS(mpvg::svg::parse_svg_string("<svg><g></svg>"), mpvg::Error);
}

TEST_CASE("svg files: reading and unreadable paths", "[svg][errors]") {
  const std::string missing = std::string(MPVG_BINARY_DIR) + "/no-such-file.svg";
  try {
    mpvg::svg::parse_svg_file(missing);
    FAIL("no error thrown");
  } catch (const mpvg::Error& e) {
    CHECK(std::string(e.what()) == "cannot read '" + missing + "': No such file or directory");
  }
  try {
    mpvg::svg::parse_svg_file(MPVG_BINARY_DIR);
    FAIL("no error thrown");
  } catch (const mpvg::Error& e) {
    CHECK(std::string(e.what()) == "cannot read '" + std::string(MPVG_BINARY_DIR) + "': Is a directory");
  }
  const std::string path = std::string(MPVG_BINARY_DIR) + "/test_svg_parser_file.svg";
  {
    std::ofstream f(path);
    f << "<svg xmlns='http://www.w3.org/2000/svg' width='4' height='3'><rect width='1' height='2'/></svg>";
  }
  const auto r = mpvg::svg::parse_svg_file(path);
  std::remove(path.c_str());
  CHECK(mpvg::dump(r.scene) ==
        "scene 4 3\npath 0 fill nonzero rgba(0,0,0,1) opacity 1\n  M 0 0 L 1 0 L 1 2 L 0 2 L 0 0 Z\nstream "
        "F0\n");
}

namespace {

// `levels` nested groups (each on a line of its own) around `inner`.
std::string nested(int levels, const std::string& inner, const std::string& tag = "g") {
  std::string s;
  for (int i = 0; i < levels; i++) s += "<" + tag + ">\n";
  s += inner;
  for (int i = 0; i < levels; i++) s += "</" + tag + ">\n";
  return s;
}

}  // namespace

TEST_CASE("svg nesting: as deep as the converter's limit, past tinyxml2's", "[svg][robustness]") {
  // tinyxml2 refuses past ~98 levels; the document is parsed in pieces
  // (split_deep_xml) up to 257 levels, deeper elements are left out.
  const std::string rect = "<rect width='4' height='5' fill='green'/>\n";
  const std::string one = mpvg::dump(parse(rect).scene);
  for (int levels : {63, 64, 65, 97, 98, 99, 200, 255}) {
    INFO(levels << " levels");
    const auto r = parse(nested(levels, rect));
    CHECK(mpvg::dump(r.scene) == one);
    CHECK(r.warnings.empty());
  }
  // Namespace prefixes declared at the root reach every piece; a foreign
  // element's subtree stays out of the drawing in any piece.
  const auto ns = parse(nested(150, "<s:rect width='4' height='5' fill='green'/>\n", "s:g"),
                        "xmlns:s='http://www.w3.org/2000/svg' viewBox='0 0 100 100'");
  CHECK(mpvg::dump(ns.scene) == one);
  CHECK(mpvg::dump(parse(nested(70, nested(80, rect), "x:foreign"),
                         "xmlns:x='http://example.org/' viewBox='0 0 100 100'").scene) ==
        "scene 100 100\nstream\n");
  // Text and siblings around pieces keep their places.
  const auto around =
      parse(nested(80, "<rect width='1' height='1'/>" + nested(20, rect) + "<circle r='2'/>") + "<rect width='9' height='9'/>");
  CHECK(svg_test::without_geometry(mpvg::dump(around.scene)) ==
        svg_test::without_geometry(dump_of("<rect width='1' height='1'/>" + rect + "<circle r='2'/><rect width='9' height='9'/>")));
  // Deeper than the limit: left out with a warning, what is above drawn.
  const auto deep = parse("<rect width='9' height='9'/>" + nested(400, rect));
  CHECK(mpvg::dump(deep.scene) == dump_of("<rect width='9' height='9'/>"));
  REQUIRE(deep.warnings.size() == 1);
  CHECK(deep.warnings[0] == "elements nested deeper than 257 levels: left out with their content");
  // A million levels: bounded time and stack.
  std::string million;
  for (int i = 0; i < 1000000; i++) million += "<g>";
  for (int i = 0; i < 1000000; i++) million += "</g>";
  CHECK(mpvg::dump(parse(million).scene) == "scene 100 100\nstream\n");
}

// svg2png --dpi, --query and --export-id, as the parser serves them.
TEST_CASE("svg options: dpi, element boxes, one element exported", "[svg][options]") {
  using mpvg::svg::ParseOptions;
  // --dpi: absolute units at that many pixels per inch; px stays.
  ParseOptions at300;
  at300.dpi = 300;
  const auto sized = mpvg::svg::parse_svg_string(svg_test::document("", "width='2in' height='2.54cm'"), ".", at300);
  CHECK(sized.scene.width == Approx(600));
  CHECK(sized.scene.height == Approx(300));
  CHECK(mpvg::svg::parse_svg_string(svg_test::document("", "width='2in' height='10'"), ".", at300).scene.height == 10);
  CHECK(parse("", "width='2in' height='2.54cm'").scene.width == Approx(192));  // 96 by default
  // A stroke's width in pt follows too: 3pt at 300 dpi is 12.5 px.
  ParseOptions q300 = at300;
  q300.query = true;
  const auto stroked = mpvg::svg::parse_svg_string(
      svg_test::document("<path id='p' d='M 10 50 H 90' stroke='black' stroke-width='3pt'/>"), ".", q300);
  REQUIRE(stroked.elements.size() == 1);
  CHECK(stroked.elements[0].height == Approx(12.5));

  // --query: drawn elements with an id, in document order, in the root
  // viewport's units (here twice the viewBox's), strokes included; not
  // what is hidden or only defined; an element drawn through <use> where
  // it is drawn first.
  ParseOptions query;
  query.query = true;
  const std::string body =
      "<defs><rect id='template' width='10' height='10' fill='green'/></defs>"
      "<g id='group' transform='translate(10 20)'>"
      "  <rect id='box' width='30' height='10' fill='red'/>"
      "  <circle id='ring' cx='50' cy='5' r='5' fill='none' stroke='blue' stroke-width='2'/>"
      "  <rect id='hidden' width='5' height='5' fill='none'/>"
      "  <rect id='gone' width='5' height='5' display='none'/>"
      "</g>"
      "<use id='copy' href='#template' x='80' y='80'/>";
  const auto r = mpvg::svg::parse_svg_string(svg_test::document(body, "width='200' height='200' viewBox='0 0 100 100'"),
                                             ".", query);
  std::string listed;
  for (const auto& e : r.elements) {
    char line[160];
    std::snprintf(line, sizeof line, "%s %g %g %g %g\n", e.id.c_str(), e.x, e.y, e.width, e.height);
    listed += line;
  }
  CHECK(listed ==
        "group 20 38 112 24\n"
        "box 20 40 60 20\n"
        "ring 108 38 24 24\n"
        "copy 160 160 20 20\n"
        "template 160 160 20 20\n");

  // --export-id: the element alone, its ancestors' transform kept and their
  // opacity not, the scene its box at the origin.
  ParseOptions one;
  one.export_id = "box";
  const std::string doc = svg_test::document(
      "<rect width='100' height='100' fill='blue'/>"
      "<g transform='translate(10 20)' opacity='0.5'><rect id='box' x='5' y='5' width='30' height='10' fill='red'/></g>",
      "width='100' height='100'");
  const auto ex = mpvg::svg::parse_svg_string(doc, ".", one);
  CHECK(ex.scene.width == 30);
  CHECK(ex.scene.height == 10);
  const std::string dump = mpvg::dump(ex.scene);
  INFO(dump);
  CHECK(dump.find("0 0 1 1") == std::string::npos);   // no blue
  CHECK(dump.find("group") == std::string::npos);     // no opacity group
  // The view is asked for the element's size.
  ParseOptions sized_view = one;
  double asked_w = 0, asked_h = 0;
  sized_view.view = [&](double w, double h) {
    asked_w = w, asked_h = h;
    return mpvg::Affine::scale(2, 2);
  };
  mpvg::svg::parse_svg_string(doc, ".", sized_view);
  CHECK(asked_w == 30);
  CHECK(asked_h == 10);
  one.export_id = "nothing";
  CHECK_THROWS_WITH(mpvg::svg::parse_svg_string(doc, ".", one), "no element has the id 'nothing' (--export-id)");
}

// Where find_xml_fault puts each kind of well-formedness error, and that
// it finds none in documents that are well-formed.
TEST_CASE("xml faults: line, column and a sentence", "[svg][errors]") {
  using mpvg::svg::detail::find_xml_fault;
  auto at = [](const std::string& text) {
    const auto f = find_xml_fault(text);
    return f ? std::to_string(f->line) + ":" + std::to_string(f->column) + " " + f->what : std::string("none");
  };
  CHECK(at("<svg>\n  <rect x=1/>\n</svg>") == "2:11 the value of the attribute 'x' of <rect> must be in quotes");
  CHECK(at("<svg><rect x/></svg>") == "1:12 the attribute 'x' of <rect> has no value (write x=\"...\")");
  CHECK(at("<svg><rect x='1'y='2'/></svg>") == "1:17 attributes of <rect> must be separated by white space");
  CHECK(at("<svg><rect x='1 /></svg>") == "1:14 the value of the attribute 'x' is not closed");
  CHECK(at("<svg><rect x='<'/></svg>") == "1:15 '<' in the value of the attribute 'x' (write &lt;)");
  CHECK(at("<svg><rect</svg>") == "1:11 unexpected '<' in the <rect> tag");
  CHECK(at("<svg>\n<g>\n</svg>") == "3:1 </svg> does not close <g> (opened at line 2, column 1)");
  CHECK(at("<svg><g>") == "1:9 the document ends inside <g> (opened at line 1, column 6)");
  CHECK(at("<svg></svg></g>") == "1:12 an end tag without a start tag");
  CHECK(at("<svg/><svg/>") == "1:7 a second root element (a document has one)");
  CHECK(at("hello <svg/>") == "1:1 text before the root element");
  CHECK(at("<svg/> x") == "1:8 text after the end of the root element");
  CHECK(at("<svg><!-- open </svg>") == "1:6 a comment is not closed with -->");
  CHECK(at("<svg><![CDATA[ x </svg>") == "1:6 a CDATA section is not closed with ]]>");
  CHECK(at("<svg>a & b</svg>") == "1:8 '&' must start an entity reference (write &amp; for an '&')");
  CHECK(at("<svg>&amp</svg>") == "1:6 an entity reference is not closed with ';' (write &amp; for an '&')");
  CHECK(at("<svg>&#xZZ;</svg>") == "1:6 a malformed character reference (&#N; or &#xH;)");
  CHECK(at("<svg>a < b</svg>") == "1:8 '<' must start a tag (write &lt; for a '<' in text)");
  CHECK(at("") == "1:1 no element: the document is empty or holds no XML");
  // Columns count characters: two-byte UTF-8 letters before the fault.
  CHECK(at("<svg><text>\xc3\xa9\xc3\xa9 & </text></svg>") == "1:15 '&' must start an entity reference (write &amp; for an '&')");
  // Well-formed: a declaration, a DOCTYPE with an internal subset (its
  // '>' and quotes inside), comments, CDATA, processing instructions,
  // references, both quotes, white space around '='.
  CHECK(at("\xef\xbb\xbf<?xml version='1.0'?>\n<!DOCTYPE svg [ <!ENTITY e \"<g>\"> ]>\n<!-- c -->"
           "<svg a = \"1\" b='2'><![CDATA[ < & ]]><?pi x?>&e;&#65;&#x41;<g/></svg>\n<!-- end -->\n") == "none");
  // Every document of the test data that tinyxml2 reads is well-formed
  // to the scanner too.
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(std::string(MPVG_SOURCE_DIR) + "/testdata")) {
    if (entry.path().extension() != ".svg" || entry.path().string().find("hostile") != std::string::npos ||
        entry.path().string().find("fuzz") != std::string::npos)
      continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string utf8;
    try {
      utf8 = mpvg::svg::detail::xml_to_utf8(text);
    } catch (const mpvg::Error&) {
      continue;
    }
    INFO(entry.path().string());
    CHECK(at(utf8) == "none");
    files++;
  }
  CHECK(files > 50);
}

TEST_CASE("svg nesting: errors inside and after pieces name their lines", "[svg][robustness][errors]") {
  // Line 1 is <svg>; the groups take a line each.
  const std::string bad = "<rect x='1' x='2'/>\n";
  CHECK(error_of("<svg>\n" + nested(120, bad) + "</svg>") ==
        "XML parse error at line 122, column 13: the attribute 'x' appears twice in <rect>");
  CHECK(error_of("<svg>\n" + nested(120, "<rect/>\n") + bad + "</svg>") ==
        "XML parse error at line 243, column 13: the attribute 'x' appears twice in <rect>");
  // A piece left open at the end of the text.
  const std::string open = "<svg>\n" + nested(120, "").substr(0, 120 * 4);
  CHECK(error_of(open).rfind("XML parse error at line ", 0) == 0);
  CHECK(error_of("<svg>" + nested(100, "<g>") + "</svg>").rfind("XML parse error at line ", 0) == 0);
}

TEST_CASE("svg robustness: hostile input terminates with bounded output", "[svg][robustness]") {
  // Exponential use fan-out and clip-path chains hit the frontend's limits
  // with a warning.
  std::string bomb = "<defs><rect id='l0' width='1' height='1'/>";
  for (int i = 1; i <= 8; i++) {
    bomb += "<g id='l" + std::to_string(i) + "'>";
    for (int k = 0; k < 10; k++) bomb += "<use href='#l" + std::to_string(i - 1) + "'/>";
    bomb += "</g>";
  }
  bomb += "</defs><use href='#l8'/>";
  const auto b = parse(bomb);
  CHECK(has_warning(b, "more than 1000000 element instances: the rest of the document is ignored"));
  CHECK(b.scene.paths.size() < 1000000);

  std::string chain;
  for (int i = 0; i < 300; i++)
    chain += "<clipPath id='k" + std::to_string(i) + "' clip-path='url(#k" + std::to_string(i + 1) +
             ")'><rect width='5' height='5'/></clipPath>";
  const auto c = parse(chain + "<rect width='1' height='1' clip-path='url(#k0)'/>");
  CHECK(c.warnings.size() == 1);
  CHECK(mpvg::dump(c.scene) == "scene 100 100\nstream\n");

  // Numbers out of range or not numbers at all are syntax errors, never
  // NaN or infinity in the scene.
  const auto n = parse(
      R"~(<rect width="1e999" height="1"/><rect width="NaN" height="1"/><rect width="inf" height="1"/>)~"
      R"~(<circle r="1e10"/><path d="M 0 0 L 1e10 0 L 1 1"/><rect width="2" height="2" transform="scale(1e400)"/>)~");
  CHECK(mpvg::dump(n.scene) ==
        "scene 100 100\npath 0 fill nonzero rgba(0,0,0,1) opacity 1\n  M 0 0 L 2 0 L 2 2 L 0 2 L 0 0 "
        "Z\nstream F0\n");
}

// ------------------------------------------------------------------ strokes

TEST_CASE("svg stroke: a line and a polyline become stroked centrelines with their styles", "[svg][stroke]") {
  // Width 1 (the initial value), square caps, bevel join; the line's width
  // 4. The scene holds each centreline and its style; the stroke stage
  // builds the outline when the scene is rendered (test_stroke).
  CHECK(dump_of(R"~(<line x1="10" y1="10" x2="30" y2="10" stroke="red" stroke-width="4" fill="blue"/>)~"
                R"~(<polyline points="10 50 30 50 30 70" fill="none" stroke="#00f" stroke-linecap="square" )~"
                R"~(stroke-linejoin="bevel"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,1,1) opacity 1 stroke 1 bevel square 4
  M 10 50 L 30 50 L 30 70
path 1 fill nonzero rgba(1,0,0,1) opacity 1 stroke 4 miter butt 4
  M 10 10 L 30 10
stream F0 F1
)~");
}

TEST_CASE("svg stroke: paint-order, inheritance, stroke-opacity, currentColor, percentages", "[svg][stroke]") {
  // Document order: rect 1 strokes then fills (paint-order: stroke); rect 2
  // "markers stroke" means markers, stroke, fill. stroke, stroke-width and
  // stroke-opacity inherit from the group; currentColor is the colour where
  // stroke is declared; 10% of the viewport diagonal (100) is 10.
  const std::string body = R"~(<g stroke="green" stroke-width="2" stroke-opacity="0.5" color="#f00">)~"
                           R"~(<rect x="10" y="10" width="20" height="20" fill="currentColor" paint-order="stroke"/>)~"
                           R"~(<rect x="40" y="10" width="20" height="20" stroke="currentColor" stroke-width="10%")~"
                           R"~( paint-order="markers stroke"/></g>)~";
  CHECK(headers_of(body) == R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1
path 1 fill nonzero rgba(1,0,0,1) opacity 0.5 stroke 10 miter butt 4
path 2 fill nonzero rgba(1,0,0,1) opacity 1
path 3 fill nonzero rgba(0,0.501961,0,1) opacity 0.5 stroke 2 miter butt 4
stream F0 F1 F2 F3
)~");
  const auto r = parse(body);
  // The 10% stroke: width 10 (its outer edge 5 outside the rect).
  REQUIRE(r.scene.paths.at(1).stroke >= 0);
  CHECK(r.scene.strokes.at(r.scene.paths.at(1).stroke).width == 10);
  CHECK(r.stroked_paths == 2);
}

TEST_CASE("svg stroke: paint-order values", "[svg][stroke]") {
  auto order = [](const std::string& po) {
    return headers_of(R"~(<rect width="10" height="10" fill="#00f" stroke="#f00" paint-order=")~" + po + "\"/>");
  };
  const std::string fill_first = "scene 100 100\npath 0 fill nonzero rgba(1,0,0,1) opacity 1 stroke 1 miter butt 4\n"
                                 "path 1 fill nonzero rgba(0,0,1,1) opacity 1\nstream F0 F1\n";
  const std::string stroke_first = "scene 100 100\npath 0 fill nonzero rgba(0,0,1,1) opacity 1\n"
                                   "path 1 fill nonzero rgba(1,0,0,1) opacity 1 stroke 1 miter butt 4\nstream F0 F1\n";
  CHECK(order("normal") == fill_first);
  CHECK(order("fill") == fill_first);
  CHECK(order("markers") == fill_first);
  CHECK(order("stroke") == stroke_first);
  CHECK(order("markers stroke fill") == stroke_first);
  CHECK(order("stroke stroke") == fill_first);  // invalid: ignored
  CHECK(order("bogus") == fill_first);
}

TEST_CASE("svg stroke: dash arrays and offsets, invalid values ignored", "[svg][stroke]") {
  // "10, 5 5" and offset -5 as given (the stroke stage repeats an odd list
  // and takes a negative offset from the end of the pattern: dashes at
  // 5-15, 20-25, 35-40, test_stroker "dash: positions").
  CHECK(dump_of(R"~(<line x2="40" stroke="#000" stroke-dasharray="10, 5 5" stroke-dashoffset="-5"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1 stroke 1 miter butt 4 dashes 10 5 5 offset -5
  M 0 0 L 40 0
stream F0
)~");
  // A negative dash invalidates the declaration: the inherited 10% (of the
  // diagonal 100) applies.
  CHECK(dump_of(R"~(<g stroke-dasharray="10%"><line x2="40" stroke="#000" stroke-dasharray="5 -5"/></g>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 1 stroke 1 miter butt 4 dashes 10 offset 0
  M 0 0 L 40 0
stream F0
)~");
  // All zeros: solid. mm units; em units follow font-size.
  CHECK(headers_of(R"~(<line x2="40" stroke="#000" stroke-dasharray="0 0"/>)~") ==
        "scene 100 100\npath 0 fill nonzero rgba(0,0,0,1) opacity 1 stroke 1 miter butt 4 dashes 0 0 offset 0\nstream F0\n");
  const auto mm = parse(R"~(<line x2="100" stroke="#000" stroke-dasharray="10mm"/>)~");
  REQUIRE(mm.scene.strokes.size() == 1);
  REQUIRE(mm.scene.strokes[0].dashes.size() == 1);
  CHECK(mm.scene.strokes[0].dashes[0] == Approx(37.795).epsilon(1e-4));  // 10 mm = 37.8 px
  const auto em = parse(R"~(<g font-size="20"><line x2="100" stroke="#000" stroke-dasharray="1em 0.5em"/></g>)~");
  REQUIRE(em.scene.strokes.size() == 1);
  CHECK(em.scene.strokes[0].dashes == std::vector<double>{20, 10});
}

TEST_CASE("svg stroke: width, miter limit and line join values", "[svg][stroke]") {
  // An angle of 33.7 degrees: miter ratio 1 / sin(16.85) = 3.45, within the
  // initial limit 4; 0.5 is invalid and ignored (were it clamped to 1, the
  // join would be a bevel).
  const auto r = parse(R"~(<polyline points="0 0 40 0 10 20" fill="none" stroke="#000" stroke-width="2" )~"
                       R"~(stroke-miterlimit="0.5"/>)~");
  REQUIRE(r.scene.strokes.size() == 1);
  CHECK(r.scene.strokes[0].miter_limit == 4);
  CHECK(r.scene.strokes[0].join == mpvg::LineJoin::Miter);
  // Negative widths are invalid (the inherited width applies); zero draws
  // nothing.
  CHECK(headers_of(R"~(<g stroke-width="3"><line x2="10" stroke="#000" stroke-width="-1"/></g>)~") ==
        "scene 100 100\npath 0 fill nonzero rgba(0,0,0,1) opacity 1 stroke 3 miter butt 4\nstream F0\n");
  CHECK(dump_of(R"~(<line x2="10" stroke="#000" stroke-width="0"/>)~") == "scene 100 100\nstream\n");
  CHECK(dump_of(R"~(<line x2="10" stroke="#000" stroke-opacity="0"/>)~") == "scene 100 100\nstream\n");
  CHECK(dump_of(R"~(<line x2="10" stroke="#000" visibility="hidden"/>)~") == "scene 100 100\nstream\n");
  // Round joins and caps; the other keywords.
  const auto round = parse(R"~(<polyline points="0 0 40 0 40 20" fill="none" stroke="#000" stroke-width="4" )~"
                           R"~(stroke-linejoin="round" stroke-linecap="round"/>)~");
  REQUIRE(round.scene.strokes.size() == 1);
  CHECK(round.scene.strokes[0].join == mpvg::LineJoin::Round);
  CHECK(round.scene.strokes[0].cap == mpvg::LineCap::Round);
  CHECK(headers_of(R"~(<line x2="10" stroke="#000" stroke-linejoin="miter-clip"/>)~"
                   R"~(<line x2="10" stroke="#000" stroke-linejoin="arcs" stroke-linecap="square"/>)~") ==
        "scene 100 100\npath 0 fill nonzero rgba(0,0,0,1) opacity 1 stroke 1 arcs square 4\n"
        "path 1 fill nonzero rgba(0,0,0,1) opacity 1 stroke 1 miter-clip butt 4\nstream F0 F1\n");
}

TEST_CASE("svg stroke: zero-length subpaths get dots and squares", "[svg][stroke]") {
  // "M p Z" and "M p L p" are kept as subpaths: the stroke stage draws
  // disks of the stroke width for round caps, squares for square caps,
  // nothing for butt caps (test_stroke).
  CHECK(dump_of(R"~(<path d="M 10 10 Z M 20 20 L 20 20" stroke="red" stroke-width="4" stroke-linecap="round"/>)~"
                R"~(<path d="M 50 50 Z" stroke="red" stroke-linecap="butt"/>)~"
                R"~(<path d="M 60 60 Z" stroke="red" stroke-width="2" stroke-linecap="square" fill="blue"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(1,0,0,1) opacity 1 stroke 2 miter square 4
  M 60 60 Z
path 1 fill nonzero rgba(1,0,0,1) opacity 1 stroke 1 miter butt 4
  M 50 50 Z
path 2 fill nonzero rgba(1,0,0,1) opacity 1 stroke 4 miter round 4
  M 10 10 Z
  M 20 20 L 20 20
path 3 fill nonzero rgba(0,0,0,1) opacity 1
  M 10 10 Z
  M 20 20 L 20 20
stream F0 F1 F2 F3
)~");
  // A lone moveto is not a subpath: nothing, caps or not.
  CHECK(dump_of(R"~(<path d="M 10 10" stroke="red" stroke-linecap="round"/>)~") == "scene 100 100\nstream\n");
}

TEST_CASE("svg stroke: vector-effect non-scaling-stroke strokes in scene units", "[svg][stroke]") {
  // scale(2 1): the stroke keeps width 2 in scene units: the centreline is
  // mapped to scene space (no transform on the path) and stroked there.
  CHECK(dump_of(R"~(<rect x="10" y="10" width="20" height="20" fill="none" stroke="red" stroke-width="2" )~"
                R"~(transform="scale(2 1)" vector-effect="non-scaling-stroke" stroke-linejoin="bevel"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(1,0,0,1) opacity 1 stroke 2 bevel butt 4
  M 20 10 L 60 10 L 60 30 L 20 30 L 20 10 Z
stream F0
)~");
  // Without it the stroke is transformed with the shape.
  CHECK(headers_of(R"~(<rect x="10" y="10" width="20" height="20" fill="none" stroke="red" transform="scale(2 1)"/>)~") ==
        "scene 100 100\npath 0 fill nonzero rgba(1,0,0,1) opacity 1 stroke 1 miter butt 4 matrix(2 0 0 1 0 0)\nstream F0\n");
}

TEST_CASE("svg stroke: hairlines are widened to the device scale with their opacity scaled", "[svg][stroke]") {
  // ParseOptions::device_scale 2: a stroke thinner than half a unit is drawn
  // half a unit wide; 0.1 keeps a fifth of its opacity.
  CHECK(dump_of(R"~(<line x2="40" stroke="#000" stroke-width="0.1"/>)~") ==
        R"~(scene 100 100
path 0 fill nonzero rgba(0,0,0,1) opacity 0.2 stroke 0.5 miter butt 4
  M 0 0 L 40 0
stream F0
)~");
  mpvg::svg::ParseOptions o;
  o.device_scale = 20;
  const auto r = mpvg::svg::parse_svg_string(
      R"~(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><line x2="40" stroke="#000" stroke-width="0.1"/></svg>)~",
      ".", o);
  CHECK(r.scene.paints.at(0).opacity == 1);
  CHECK(r.scene.strokes.at(0).width == Approx(0.1));
}

TEST_CASE("svg stroke: ParseOptions::view gives the output's pixels", "[svg][stroke]") {
  // The callback sees the document size and its transform decides what a
  // pixel is: at_width(50) on a 100-unit document makes 0.5 px per unit,
  // so a 1-unit stroke is half a pixel (widened to 2 units, opacity 0.5);
  // at_width(400), 4 px per unit, leaves it alone.
  const std::string doc =
      R"~(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 50"><line x2="40" stroke="#000"/></svg>)~";
  double seen_w = 0, seen_h = 0;
  mpvg::svg::ParseOptions probe;
  probe.view = [&](double w, double h) {
    seen_w = w;
    seen_h = h;
    return mpvg::Affine::scale(1, 1);
  };
  mpvg::svg::parse_svg_string(doc, ".", probe);
  CHECK(seen_w == 100);
  CHECK(seen_h == 50);
  const auto small = mpvg::svg::parse_svg_string(doc, ".", mpvg::svg::ParseOptions::at_width(50));
  CHECK(small.scene.paints.at(0).opacity == Approx(0.5));
  CHECK(small.scene.strokes.at(0).width == Approx(2));
  const auto large = mpvg::svg::parse_svg_string(doc, ".", mpvg::svg::ParseOptions::at_width(400));
  CHECK(large.scene.paints.at(0).opacity == 1);
  CHECK(large.scene.strokes.at(0).width == Approx(1));
}

TEST_CASE("svg stroke: clip paths and bounding boxes use fill geometry only", "[svg][stroke]") {
  // The clipPath child's stroke is not part of the clip region.
  CHECK(dump_of(R"~(<defs><clipPath id="c"><rect width="50" height="50" stroke="red" stroke-width="20"/></clipPath></defs>)~"
                R"~(<rect width="100" height="100" fill="blue" clip-path="url(#c)"/>)~") ==
        R"~(scene 100 100
path 0 clip nonzero
  M 0 0 L 50 0 L 50 50 L 0 50 L 0 0 Z
path 1 fill nonzero rgba(0,0,1,1) opacity 1
  M 0 0 L 100 0 L 100 100 L 0 100 L 0 0 Z
stream ( C0 | F1 )
)~");
  // objectBoundingBox: the box of the fill (10..30), not of the stroke.
  CHECK(headers_of(R"~(<defs><clipPath id="o" clipPathUnits="objectBoundingBox"><rect width="1" height="1"/></clipPath></defs>)~"
                   R"~(<rect x="10" y="10" width="20" height="20" fill="blue" stroke="red" stroke-width="10" clip-path="url(#o)"/>)~") ==
        R"~(scene 100 100
path 0 clip nonzero matrix(20 0 0 20 10 10)
path 1 fill nonzero rgba(1,0,0,1) opacity 1 stroke 10 miter butt 4
path 2 fill nonzero rgba(0,0,1,1) opacity 1
stream ( C0 | F1 F2 )
)~");
}

TEST_CASE("svg stroke: paint servers fall back and unsupported paints warn as for fills", "[svg][stroke][paint]") {
  // The gradient has no stops: it cannot paint, the fallback applies.
  const auto r = parse(R"~(<linearGradient id="lg"/>)~"
                       R"~(<rect width="5" height="5" stroke="url(#lg)"/>)~"
                       R"~(<rect width="5" height="5" stroke="url(#lg) #00f" fill="none"/>)~"
                       R"~(<rect width="5" height="5" stroke="context-stroke"/>)~"
                       R"~(<rect width="5" height="5" stroke="url(#missing)"/>)~"
                       R"~(<rect width="5" height="5" stroke="url(#lg)" marker-end="url(#m)"/>)~");
  // Three black fills and the fallback-blue stroke.
  CHECK(r.scene.paths.size() == 5);
  CHECK(r.scene.paints.at(r.scene.paths.at(3).paint).color.b == 1);
  // (context-stroke outside a marker or use, and a marker that does not
  // exist, draw nothing, silently.)
  CHECK(r.warnings.empty());
}

namespace {

// Built by hand: the path of kSubpaths below, in the same commands.
mpvg::Path many_subpaths() {
  mpvg::Path p;
  p.move_to({10, 10});
  p.line_to({40, 10});
  p.line_to({40, 30});
  p.close();
  p.move_to({50, 50});
  p.line_to({80, 60});
  p.quad_to({90, 90}, {60, 90});
  p.move_to({10, 80});
  p.close();
  p.move_to({20, 60});
  p.cubic_to({30, 40}, {5, 40}, {15, 60});
  return p;
}
constexpr const char* kSubpaths = "M10 10 L40 10 L40 30 Z M50 50 L80 60 Q90 90 60 90 M10 80 Z M20 60 C30 40 5 40 15 60";

}  // namespace

TEST_CASE("core Path: contours taken apart and appended again give the same path", "[svg][stroke]") {
  const mpvg::Path whole = many_subpaths();
  REQUIRE(whole.contours().size() == 4);
  mpvg::Path again = whole.contour_path(0);
  for (size_t i = 1; i < whole.contours().size(); i++) again.append(whole.contour_path(i));
  CHECK(again.points() == whole.points());
  CHECK(again.weights() == whole.weights());
  REQUIRE(again.segments().size() == whole.segments().size());
  for (size_t i = 0; i < whole.segments().size(); i++) {
    CHECK(again.segments()[i].type == whole.segments()[i].type);
    CHECK(again.segments()[i].first_point == whole.segments()[i].first_point);
  }
  REQUIRE(again.contours().size() == whole.contours().size());
  for (size_t i = 0; i < whole.contours().size(); i++) {
    CHECK(again.contours()[i].first_segment == whole.contours()[i].first_segment);
    CHECK(again.contours()[i].segment_count == whole.contours()[i].segment_count);
    CHECK(again.contours()[i].start_point == whole.contours()[i].start_point);
    CHECK(again.contours()[i].closed == whole.contours()[i].closed);
  }
}

TEST_CASE("svg stroke: a path of many subpaths is one stroke of its whole centreline", "[svg][stroke]") {
  // Dashes restart per subpath, zero-length and closed subpaths keep their
  // own caps and joins: the stroke stage takes the centreline whole.
  const mpvg::Path whole = many_subpaths();
  const auto r = parse(std::string(R"~(<path fill="none" stroke="#000" stroke-width="2" stroke-dasharray="7 3" )~"
                                   R"~(stroke-dashoffset="2" stroke-linecap="square" d=")~") +
                       kSubpaths + "\"/>");
  REQUIRE(r.scene.geometries.size() == 1);
  REQUIRE(r.scene.strokes.size() == 1);
  const mpvg::Path& got = r.scene.geometries[0];
  CHECK(got.points() == whole.points());
  CHECK(got.weights() == whole.weights());
  CHECK(got.segments().size() == whole.segments().size());
  CHECK(got.contours().size() == whole.contours().size());
  CHECK(r.scene.strokes[0].dashes == std::vector<double>{7, 3});
  CHECK(r.scene.strokes[0].dash_offset == 2);
  CHECK(r.scene.strokes[0].cap == mpvg::LineCap::Square);
}

namespace {

// UTF-16 code units of a UTF-8 string (BMP and astral), in either order,
// as a file in that encoding would hold them.
std::string utf16(const std::u16string& s, bool big_endian, bool bom) {
  std::string out;
  auto put = [&](char16_t u) {
    const char hi = char(u >> 8), lo = char(u & 0xFF);
    out += big_endian ? hi : lo;
    out += big_endian ? lo : hi;
  };
  if (bom) put(0xFEFF);
  for (char16_t u : s) put(u);
  return out;
}

}  // namespace

TEST_CASE("svg encodings: UTF-16 either way, with or without a BOM, and 8-bit declared encodings parse as UTF-8",
          "[svg][xml]") {
  const std::u16string doc =
      u"<?xml version=\"1.0\" encoding=\"UTF-16\"?><svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\">"
      u"<rect id=\"\u00e9\u20ac\U0001F600\" width=\"5\" height=\"5\" fill=\"#00f\"/></svg>";
  const std::string expected = mpvg::dump(mpvg::svg::parse_svg_string(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><rect width=\"5\" height=\"5\" "
      "fill=\"#00f\"/></svg>").scene);
  for (bool be : {false, true})
    for (bool bom : {false, true}) {
      CAPTURE(be, bom);
      const std::string bytes = utf16(doc, be, bom);
      CHECK(mpvg::dump(mpvg::svg::parse_svg_string(bytes).scene) == expected);
    }
  // The code points themselves survive: U+00E9, U+20AC and an astral
  // character (a surrogate pair) in an id that CSS then selects.
  const std::u16string styled =
      u"<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><style>#\u00e9\u20ac\U0001F600 { fill: "
      u"#00f }</style><rect id=\"\u00e9\u20ac\U0001F600\" width=\"5\" height=\"5\" fill=\"red\"/></svg>";
  CHECK(mpvg::dump(mpvg::svg::parse_svg_string(utf16(styled, false, true)).scene) == expected);
  // ISO-8859-1 and windows-1252: é is 0xE9 in both, € is 0x80 in 1252.
  const std::string latin1 =
      "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?><svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 "
      "10\"><style>#\xe9 { fill: #00f }</style><rect id=\"\xe9\" width=\"5\" height=\"5\" fill=\"red\"/></svg>";
  CHECK(mpvg::dump(mpvg::svg::parse_svg_string(latin1).scene) == expected);
  const std::string cp1252 =
      "<?xml version='1.0' encoding='windows-1252'?><svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 "
      "10\"><style>#\x80 { fill: #00f }</style><rect id=\"\x80\" width=\"5\" height=\"5\" fill=\"red\"/></svg>";
  CHECK(mpvg::dump(mpvg::svg::parse_svg_string(cp1252).scene) == expected);
  // The characters themselves: € in windows-1252, é in ISO-8859-1.
  using mpvg::svg::detail::xml_to_utf8;
  CHECK(xml_to_utf8("<?xml version='1.0' encoding='windows-1252'?>\x80\xe9") ==
        "<?xml version='1.0' encoding='windows-1252'?>\xe2\x82\xac\xc3\xa9");
  CHECK(xml_to_utf8("<?xml version='1.0' encoding='ISO-8859-1'?>\x80\xe9") ==
        "<?xml version='1.0' encoding='ISO-8859-1'?>\xc2\x80\xc3\xa9");
  CHECK(xml_to_utf8(utf16(u"<a>\U0001F600</a>", true, false)) == "<a>\xf0\x9f\x98\x80</a>");
  // A UTF-8 byte-order mark is dropped.
  CHECK(mpvg::dump(mpvg::svg::parse_svg_string(
                       "\xef\xbb\xbf<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><rect width=\"5\" "
                       "height=\"5\" fill=\"#00f\"/></svg>")
                       .scene) == expected);
}

// build_document copies the text only where a step changes it: UTF-8
// comes back as a view of the input (after the byte-order mark), a
// document without an internal subset as itself; what changes is the
// same text the copying forms give.
TEST_CASE("svg encodings: text that needs no change is viewed and not copied", "[svg][xml]") {
  using mpvg::svg::detail::expand_internal_entities;
  using mpvg::svg::detail::xml_to_utf8;
  std::string storage;
  const std::string utf8 = "\xef\xbb\xbf<svg xmlns=\"http://www.w3.org/2000/svg\"><text>\xc3\xa9</text></svg>";
  const std::string_view viewed = xml_to_utf8(utf8, storage);
  CHECK(viewed.data() == utf8.data() + 3);
  CHECK(viewed == xml_to_utf8(utf8));
  CHECK(storage.empty());
  const std::string latin1 = "<?xml version='1.0' encoding='ISO-8859-1'?><a>\xe9</a>";
  const std::string_view converted = xml_to_utf8(latin1, storage);
  CHECK(converted.data() == storage.data());
  CHECK(converted == xml_to_utf8(latin1));

  for (const std::string text : {"<svg/>", "<!DOCTYPE svg PUBLIC \"-//W3C//DTD SVG 1.1//EN\" \"x.dtd\"><svg/>",
                                 "<!DOCTYPE svg [ <!ENTITY a \"b\"> <svg/>"}) {
    std::string kept;
    const std::string_view same = expand_internal_entities(text, kept);
    CHECK(same.data() == text.data());
    CHECK(same.size() == text.size());
    CHECK(kept.empty());
  }
  for (const std::string text : {"<!DOCTYPE svg [ <!ENTITY a \"b&amp;\"> ]>\n<svg a=\"&a;&c;&\">&a;</svg>",
                                 "<!DOCTYPE svg [\n<!ELEMENT svg ANY>\n]><svg/>"}) {
    std::string expanded;
    const std::string_view out = expand_internal_entities(text, expanded);
    CHECK(out.data() == expanded.data());
    CHECK(out == expand_internal_entities(text));
  }
  std::string expanded;
  CHECK(expand_internal_entities("<!DOCTYPE svg [ <!ENTITY a \"b&amp;\"> ]>\n<svg a=\"&a;&c;&\">&a;</svg>",
                                 expanded) ==
        std::string(39, ' ') + "\n<svg a=\"b&amp;&c;&\">b&amp;</svg>");
}

TEST_CASE("svg encodings: UTF-32 and undecodable declared encodings are one clear error", "[svg][xml]") {
  CHECK_THROWS_WITH(mpvg::svg::parse_svg_string(std::string("\xff\xfe\x00\x00<\x00\x00\x00", 8)),
                    "UTF-32 documents are not supported");
  CHECK_THROWS_WITH(mpvg::svg::parse_svg_string("<?xml version=\"1.0\" encoding=\"Shift_JIS\"?><svg "
                                                "xmlns=\"http://www.w3.org/2000/svg\"><text>\x82\xa0</text></svg>"),
                    Catch::Contains("encoding 'shift_jis' is not supported"));
  // Declared otherwise but valid UTF-8 (a common mislabel): read as UTF-8.
  CHECK_NOTHROW(mpvg::svg::parse_svg_string("<?xml version=\"1.0\" encoding=\"Shift_JIS\"?><svg "
                                            "xmlns=\"http://www.w3.org/2000/svg\" width=\"1\" height=\"1\"/>"));
}

TEST_CASE("svg numbers: the fast path reads the double from_chars reads", "[svg][values]") {
  // Scanner::number reads short significands with small exponents by one
  // exact operation (Clinger's fast path); every number must still be the
  // correctly rounded double std::from_chars gives. Random numbers of every
  // form path data holds: signs, leading and trailing zeros, fractions
  // without an integer part, exponents, long significands past 2^53.
  std::mt19937_64 rng(7);
  auto digits = [&](int n) {
    std::string d;
    for (int k = 0; k < n; k++) d += char('0' + rng() % 10);
    return d;
  };
  int fast = 0;
  for (int t = 0; t < 200000; t++) {
    std::string text;
    const int sign = int(rng() % 3);
    if (sign == 1) text += '-';
    if (sign == 2) text += '+';
    const int int_len = int(rng() % 12), frac_len = int(rng() % (rng() % 4 == 0 ? 24 : 9));
    text += digits(int_len);
    if (frac_len > 0 || int_len == 0) {
      text += '.';
      text += digits(std::max(frac_len, int_len == 0 ? 1 : 0));
    }
    if (rng() % 4 == 0) {
      text += rng() % 2 ? 'e' : 'E';
      if (rng() % 2) text += rng() % 2 ? '-' : '+';
      text += std::to_string(rng() % 40);
    }
    INFO(text);
    mpvg::svg::detail::Scanner s(text, 1e300);
    const std::optional<double> got = s.number();
    REQUIRE(got);
    CHECK(s.at_end());
    double want = 0;
    const char* first = text.data() + (text[0] == '-' || text[0] == '+');
    const auto r = std::from_chars(first, text.data() + text.size(), want);
    REQUIRE(r.ec == std::errc());
    if (text[0] == '-') want = -want;
    uint64_t a, b;
    std::memcpy(&a, &*got, 8);
    std::memcpy(&b, &want, 8);
    CHECK(a == b);
    fast += int_len + frac_len <= 15;
  }
  CHECK(fast > 50000);
}
