// The SVG frontend's groups and masks (parsers/svg/svg_masks.cpp) as scene
// dumps: what becomes a transparency group, what folds into a paint, masks
// with their units, regions, types and references. Paths are listed
// top-most first; the rendering of these constructs is tested in
// test_groups.cpp and by the suite.
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

// Paths (without geometry), groups and the stream.
std::string summary(const mpvg::svg::ParseResult& r) {
  return svg_test::dump_lines(mpvg::dump(r.scene), [](std::string_view line, size_t indent) {
    return indent == 0 && (line.rfind("path", 0) == 0 || line.rfind("group", 0) == 0 || line.rfind("stream", 0) == 0);
  });
}

}  // namespace

TEST_CASE("svg groups: opacity on fill and stroke is one group; on one fill it folds", "[svg][groups]") {
  const auto r = parse(R"~(<rect width="10" height="10" fill="red" stroke="blue" opacity="0.5"/>)~"
                       R"~(<circle r="5" fill="green" opacity="0.25"/>)~");
  CHECK(summary(r) == R"~(path 0 fill nonzero rgba(0,0.501961,0,1) opacity 0.25
path 1 fill nonzero rgba(0,0,1,1) opacity 1 stroke 1 miter butt 4
path 2 fill nonzero rgba(1,0,0,1) opacity 1
group 0 opacity 0.5 normal
stream F0 {0 F1 F2 }
)~");
  CHECK(r.warnings.empty());
}

TEST_CASE("svg groups: mix-blend-mode and isolation make groups; the top level is wrapped", "[svg][groups]") {
  const auto r = parse(R"~(<rect width="10" height="10" fill="red"/>)~"
                       R"~(<g style="isolation:isolate"><rect width="5" height="5" fill="blue" mix-blend-mode="screen"/></g>)~"
                       R"~(<rect width="4" height="4" style="mix-blend-mode:source-atop"/>)~");
  // screen inside the isolated group: that group's list runs back to front;
  // source-atop is a compositing operator, not a blend mode: ignored.
  CHECK(summary(r) == R"~(path 0 fill nonzero rgba(0,0,0,1) opacity 1
path 1 fill nonzero rgba(0,0,1,1) opacity 1
path 2 fill nonzero rgba(1,0,0,1) opacity 1
group 0 opacity 1 normal back-to-front
group 1 opacity 1 screen
stream F0 {0 {1 F1 } } F2
)~");
}

TEST_CASE("svg masks: units, region, type, and opacity with clip-path on one element", "[svg][groups][mask]") {
  // objectBoundingBox units (the default): the region -10% .. 120% of the
  // rect's box (x 10..30, y 10..20) becomes a clip in the mask group.
  const auto r = parse(R"~(<mask id="m"><rect width="100" height="100" fill="white"/></mask>)~"
                       R"~(<clipPath id="c"><rect width="50" height="50"/></clipPath>)~"
                       R"~(<rect x="10" y="10" width="20" height="10" fill="red" stroke="blue" mask="url(#m)" )~"
                       R"~(opacity="0.5" clip-path="url(#c)"/>)~");
  const std::string d = mpvg::dump(r.scene);
  CHECK(svg_test::dump_lines(d, [](std::string_view l, size_t) { return l.rfind("group", 0) == 0 || l.rfind("stream", 0) == 0; }) ==
        R"~(group 0 opacity 0.5 normal
group 1 opacity 1 normal mask luminance 0.2125 0.7154 0.0721 srgb
stream ( C0 | {0 {1 ( C1 | F2 ) } F3 F4 } )
)~");
  CHECK(d.find("path 1 clip nonzero matrix(20 0 0 10 10 10)\n  M -0.1 -0.1 L 1.1 -0.1 L 1.1 1.1 L -0.1 1.1 L -0.1 -0.1 Z") !=
        std::string::npos);

  // userSpaceOnUse region, objectBoundingBox content, mask-type alpha in style.
  const auto u = parse(R"~(<mask id="m" maskUnits="userSpaceOnUse" x="0" y="0" width="50" height="60" )~"
                       R"~(maskContentUnits="objectBoundingBox" style="mask-type:alpha">)~"
                       R"~(<rect width="0.5" height="1"/></mask>)~"
                       R"~(<rect x="10" y="10" width="20" height="10" mask="url(#m)"/>)~");
  const std::string ud = mpvg::dump(u.scene);
  CHECK(ud.find("group 1 opacity 1 normal mask alpha\n") != std::string::npos);
  CHECK(ud.find("M 0 0 L 50 0 L 50 60 L 0 60 L 0 0 Z") != std::string::npos);
  CHECK(ud.find("fill nonzero rgba(0,0,0,1) opacity 1 matrix(20 0 0 10 10 10)\n  M 0 0 L 0.5 0") != std::string::npos);
}

TEST_CASE("svg masks: masks on masks, recursion, bad references", "[svg][groups][mask]") {
  // A mask on the mask element is the mask's own mask; one on itself is
  // ignored with a warning.
  const auto r = parse(R"~(<mask id="a" mask="url(#b)"><rect width="100" height="100" fill="white"/></mask>)~"
                       R"~(<mask id="b" mask="url(#a)"><rect width="50" height="100" fill="white"/></mask>)~"
                       R"~(<rect width="10" height="10" mask="url(#a)"/>)~");
  CHECK(svg_test::dump_lines(mpvg::dump(r.scene), [](std::string_view l, size_t) { return l.rfind("stream", 0) == 0; }) ==
        "stream {0 {1 {2 ( C0 | F1 ) } ( C2 | F3 ) } F4 }\n");
  CHECK(r.warnings == std::vector<std::string>{"recursive mask reference ignored"});
  // The cut is b's reference to a (a comes first), so b entered directly
  // has no mask of its own.
  const auto b = parse(R"~(<mask id="a" mask="url(#b)"><rect width="100" height="100" fill="white"/></mask>)~"
                       R"~(<mask id="b" mask="url(#a)"><rect width="50" height="100" fill="white"/></mask>)~"
                       R"~(<rect width="10" height="10" mask="url(#b)"/>)~");
  CHECK(svg_test::dump_lines(mpvg::dump(b.scene), [](std::string_view l, size_t) { return l.rfind("stream", 0) == 0; }) ==
        "stream {0 {1 ( C0 | F1 ) } F2 }\n");
  // A missing mask is ignored; a reference to something else hides the element;
  // objectBoundingBox units on a box without area hide it too.
  CHECK(summary(parse(R"~(<rect width="10" height="10" mask="url(#none)"/>)~")) ==
        "path 0 fill nonzero rgba(0,0,0,1) opacity 1\nstream F0\n");
  CHECK(summary(parse(R"~(<linearGradient id="g"/><rect width="10" height="10" mask="url(#g)"/>)~")) == "stream\n");
  CHECK(summary(parse(R"~(<mask id="m"><rect width="10" height="10" fill="white"/></mask>)~"
                      R"~(<line x2="10" stroke="black" mask="url(#m)"/>)~")) == "stream\n");
}

TEST_CASE("svg masks: a recursive chain is cut once for the document", "[svg][groups][mask]") {
  // resvg's masking/mask/recursive-on-child: m1's child uses m2 and m2's
  // child uses m1. Walking the masks in document order cuts the reference
  // of m2's child (it leads back to m1), so m1 is its child masked by m2,
  // and m2 is its child alone, wherever the chain is entered.
  const auto r = parse(R"~(<mask id="m1"><rect width="10" height="10" fill="white" mask="url(#m2)"/></mask>)~"
                       R"~(<mask id="m2"><rect width="5" height="10" fill="white" mask="url(#m1)"/></mask>)~"
                       R"~(<rect width="10" height="4" mask="url(#m1)"/><rect y="5" width="10" height="4" mask="url(#m2)"/>)~");
  CHECK(svg_test::dump_lines(mpvg::dump(r.scene), [](std::string_view l, size_t) { return l.rfind("stream", 0) == 0; }) ==
        "stream {4 {5 ( C0 | F1 ) } F2 } {0 {1 ( C3 | {2 {3 ( C4 | F5 ) } F6 } ) } F7 }\n");
  CHECK(r.warnings == std::vector<std::string>{"recursive mask reference ignored"});
}

TEST_CASE("svg masks: objectBoundingBox for both units, userSpaceOnUse for both", "[svg][groups][mask]") {
  const auto b = parse(R"~(<mask id="m" maskContentUnits="objectBoundingBox" x="0" y="0" width="0.5" height="1">)~"
                       R"~(<rect width="0.5" height="1" fill="white"/></mask>)~"
                       R"~(<rect x="10" y="10" width="20" height="10" mask="url(#m)"/>)~");
  // The region and the content both in the rect's box.
  CHECK(mpvg::dump(b.scene) == R"~(scene 100 100
path 0 clip nonzero matrix(20 0 0 10 10 10)
  M 0 0 L 0.5 0 L 0.5 1 L 0 1 L 0 0 Z
path 1 fill nonzero rgba(1,1,1,1) opacity 1 matrix(20 0 0 10 10 10)
  M 0 0 L 0.5 0 L 0.5 1 L 0 1 L 0 0 Z
path 2 fill nonzero rgba(0,0,0,1) opacity 1
  M 10 10 L 30 10 L 30 20 L 10 20 L 10 10 Z
group 0 opacity 1 normal
group 1 opacity 1 normal mask luminance 0.2125 0.7154 0.0721 srgb
stream {0 {1 ( C0 | F1 ) } F2 }
)~");
  const auto u = parse(R"~(<mask id="m" maskUnits="userSpaceOnUse" width="50%" mask-type="alpha">)~"
                       R"~(<rect width="50" height="10"/></mask>)~"
                       R"~(<rect x="10" y="10" width="20" height="10" mask="url(#m)" transform="translate(5 0)"/>)~");
  // Percentages of the viewport, defaults -10% and 120%, in the element's
  // user space.
  CHECK(mpvg::dump(u.scene) == R"~(scene 100 100
path 0 clip nonzero matrix(1 0 0 1 5 0)
  M -10 -10 L 40 -10 L 40 110 L -10 110 L -10 -10 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1 matrix(1 0 0 1 5 0)
  M 0 0 L 50 0 L 50 10 L 0 10 L 0 0 Z
path 2 fill nonzero rgba(0,0,0,1) opacity 1 matrix(1 0 0 1 5 0)
  M 10 10 L 30 10 L 30 20 L 10 20 L 10 10 Z
group 0 opacity 1 normal
group 1 opacity 1 normal mask alpha
stream {0 {1 ( C0 | F1 ) } F2 }
)~");
  // An invalid mask-type is luminance.
  const auto i = parse(R"~(<mask id="m" mask-type="bright"><rect width="50" height="10" fill="white"/></mask>)~"
                       R"~(<rect width="20" height="10" mask="url(#m)"/>)~");
  CHECK(svg_test::dump_lines(mpvg::dump(i.scene), [](std::string_view l, size_t) { return l.rfind("group", 0) == 0; }) ==
        "group 0 opacity 1 normal\ngroup 1 opacity 1 normal mask luminance 0.2125 0.7154 0.0721 srgb\n");
}

TEST_CASE("svg groups: opacity 0 draws nothing but its box counts", "[svg][groups]") {
  // The group's objectBoundingBox clip spans both rects, the hidden one too.
  const auto r = parse(R"~(<clipPath id="c" clipPathUnits="objectBoundingBox"><rect width="1" height="1"/></clipPath>)~"
                       R"~(<g clip-path="url(#c)"><rect width="10" height="10" fill="red" stroke="blue" opacity="0"/>)~"
                       R"~(<rect x="20" y="20" width="10" height="10"/></g>)~");
  CHECK(mpvg::dump(r.scene) == R"~(scene 100 100
path 0 clip nonzero matrix(30 0 0 30 0 0)
  M 0 0 L 1 0 L 1 1 L 0 1 L 0 0 Z
path 1 fill nonzero rgba(0,0,0,1) opacity 1
  M 20 20 L 30 20 L 30 30 L 20 30 L 20 20 Z
stream ( C0 | F1 )
)~");
}

TEST_CASE("svg groups: nesting past the sample stack is drawn flattened with one warning", "[svg][groups]") {
  // 20 groups of two shapes each (no opacity folds away): the 4 deepest are
  // flattened into the 16th, the document renders.
  std::string body;
  for (int i = 0; i < 20; i++) body += R"(<g opacity="0.9"><rect width="4" height="4" fill="blue"/>)";
  body += R"(<rect x="10" width="30" height="40" fill="red"/>)";
  for (int i = 0; i < 20; i++) body += "</g>";
  const auto r = parse(body);
  REQUIRE(r.warnings.size() == 1);
  CHECK(r.warnings[0] ==
        "groups and masks nested more than 16 deep: 4 drawn flattened (opacity folded into their content; their "
        "masks and blend modes ignored)");
  int depth = 0, deepest = 0;
  for (const mpvg::Element& e : r.scene.stream) {
    if (e.kind == mpvg::ElementKind::BeginGroup) deepest = std::max(deepest, ++depth);
    if (e.kind == mpvg::ElementKind::EndGroup) depth--;
  }
  CHECK(deepest == 16);
  // The red rectangle's paint carries the four flattened groups' opacity.
  const mpvg::ScenePath& red = r.scene.paths[0];  // top-most first
  CHECK(r.scene.paints[red.paint].opacity == Approx(0.9f * 0.9f * 0.9f * 0.9f));
}
