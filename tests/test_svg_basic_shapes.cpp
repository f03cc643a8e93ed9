// clip-path basic shapes and reference boxes (CSS Masking 1 §3.1, CSS
// Shapes 1 §3.1; parsers/svg/svg_basic_shapes.cpp) as images: each
// document clipped by a basic shape renders on the CPU backend exactly as
// the same drawing clipped by a <clipPath> holding the equivalent element,
// whose geometry is worked out by hand in the comments. Invalid values drop
// the declaration. The scene they give is in testdata/svg-dumps/
// clip-path-basic-shapes.dump.
#include <cstdint>
#include <string>
#include <vector>

#include "frame/frame.h"
#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "cpu/cpu_frame.h"

using namespace mpvg;

namespace {

// `body` in a 100 x 100 document rendered at 100 x 100 pixels.
std::vector<uint8_t> render(const std::string& body) {
  RenderOptions o;
  o.width = o.height = 100;
  o.view = Affine{};
  o.samples = 32;
  o.seed = 0;
  o.backend = Backend::Cpu;
  svg::ParseOptions po;
  po.view = [](double, double) { return Affine{}; };
  const svg::ParseResult doc =
      svg::parse_svg_string(svg_test::document(body, R"~(width="100" height="100" viewBox="0 0 100 100")~"), ".", po);
  return to_rgba8(render_cpu(doc.scene, o), o.gamma);
}

// A document whose `clipped` element (its attributes up to the clip, then
// `clip` as the clip-path of a style attribute) renders like `element`
// clipped by a clipPath holding `equivalent`; and unlike it unclipped, so
// that the clip does something.
void check_clip(const std::string& clipped, const std::string& clip, const std::string& equivalent,
                const std::string& clip_rule = "nonzero") {
  INFO(clip);
  const std::string shape = "<" + clipped + " style=\"clip-path: " + clip + "\"/>";
  const std::string reference = "<clipPath id=\"c\" clip-rule=\"" + clip_rule + "\">" + equivalent +
                                "</clipPath><" + clipped + " clip-path=\"url(#c)\"/>";
  const std::vector<uint8_t> image = render(shape);
  const bool equivalent_clip = image == render(reference), clips = image != render("<" + clipped + "/>");
  CHECK(equivalent_clip);
  CHECK(clips);
}

// A 80 x 60 rectangle at (10, 10): fill box (10, 10)-(90, 70).
const std::string kRect = R"~(rect x="10" y="10" width="80" height="60" fill="blue")~";
// A 60 x 60 square at (20, 20) with a 10 wide stroke: stroke box
// (15, 15)-(85, 85).
const std::string kStroked = R"~(rect x="20" y="20" width="60" height="60" fill="blue" stroke="green" stroke-width="10")~";

}  // namespace

TEST_CASE("clip-path circle(): radius, position and reference boxes", "[svg][clip][shapes]") {
  // The default box (border-box) is the stroke box, here the fill box:
  // centre (10 + 30% 80, 10 + 40% 60).
  check_clip(kRect, "circle(20px at 30% 40%)", R"~(<circle cx="34" cy="34" r="20"/>)~");
  // closest-side from the centre (50, 40): 30 to the top and bottom.
  check_clip(kRect, "circle() fill-box", R"~(<circle cx="50" cy="40" r="30"/>)~");
  check_clip(kRect, "circle(farthest-side at left top) content-box", R"~(<circle cx="10" cy="10" r="80"/>)~");
  // 50% of the view box's normalised diagonal sqrt((100² + 100²) / 2).
  check_clip(kRect, "view-box circle(50%)", R"~(<circle cx="50" cy="50" r="50"/>)~");
  // em of the element's font size.
  check_clip(kRect + R"~( font-size="20")~", "circle(1em at 0 0)", R"~(<circle cx="10" cy="10" r="20"/>)~");
  // The stroke box of the stroked square, at its top-left corner.
  check_clip(kStroked, "circle(25px at 0 0) stroke-box", R"~(<circle cx="15" cy="15" r="25"/>)~");
  check_clip(kStroked, "circle(25px at 0 0) margin-box", R"~(<circle cx="15" cy="15" r="25"/>)~");
  check_clip(kStroked, "circle(25px at 0 0) padding-box", R"~(<circle cx="20" cy="20" r="25"/>)~");
}

TEST_CASE("clip-path ellipse(): radii along each axis", "[svg][clip][shapes]") {
  // Centre (90 - 10, 10 + 20); farthest side along x 70, 25% of 60 along y.
  check_clip(kRect, "ellipse(farthest-side 25% at right 10px top 20px) fill-box",
             R"~(<ellipse cx="80" cy="30" rx="70" ry="15"/>)~");
  // closest-side from the centre of the stroke box (50, 50): 35 both ways.
  check_clip(kStroked, "ellipse(closest-side 10px)", R"~(<ellipse cx="50" cy="50" rx="35" ry="10"/>)~");
}

TEST_CASE("clip-path inset(): sides and rounded corners", "[svg][clip][shapes]") {
  // 10 from top and bottom, 20% of 80 from left and right.
  check_clip(kRect, "inset(10px 20% round 10px)", R"~(<rect x="26" y="20" width="48" height="40" rx="10"/>)~");
  // Radii past the sides scale down together until they fit (48 / 60).
  check_clip(kRect, "fill-box inset(10px 20% round 30px / 20px)",
             R"~(<rect x="26" y="20" width="48" height="40" rx="24" ry="16"/>)~");
  check_clip(kStroked, "inset(5px 10px 15px 20px) stroke-box", R"~(<rect x="35" y="20" width="40" height="50"/>)~");
}

TEST_CASE("clip-path polygon(): points in the box, fill rule", "[svg][clip][shapes]") {
  // A pentagram in the stroke box (origin (15, 15)); evenodd leaves its
  // centre out.
  const std::string star = "35px 0, 57px 70px, 0 26px, 70px 26px, 13px 70px";
  check_clip(kStroked, "polygon(evenodd, " + star + ")",
             R"~(<polygon points="50,15 72,85 15,41 85,41 28,85"/>)~", "evenodd");
  check_clip(kStroked, "polygon(" + star + ") stroke-box", R"~(<polygon points="50,15 72,85 15,41 85,41 28,85"/>)~");
  check_clip(kRect, "polygon(50% 0%, 100% 100%, 0 100%) view-box", R"~(<polygon points="50,0 100,100 0,100"/>)~");
}

TEST_CASE("clip-path path(): SVG path data from the box's origin", "[svg][clip][shapes]") {
  check_clip(kRect, "path('M0 0 H40 V40 Z') fill-box", R"~(<path d="M10 10 H50 V50 Z"/>)~");
  check_clip(kStroked, "path(evenodd, &quot;M0 0 h70 v70 h-70 Z M10 10 h20 v20 h-20 Z&quot;)",
             R"~(<path d="M15 15 h70 v70 h-70 Z M25 25 h20 v20 h-20 Z"/>)~", "evenodd");
}

TEST_CASE("clip-path reference box alone clips to the box", "[svg][clip][shapes]") {
  check_clip(kStroked, "fill-box", R"~(<rect x="20" y="20" width="60" height="60"/>)~");
  // The view box in the element's user space, which its transform moves.
  check_clip(R"~(rect x="-20" y="20" width="60" height="60" fill="blue" stroke="green" stroke-width="10" )~"
             R"~(transform="translate(30 0)")~",
             "view-box", R"~(<rect width="100" height="100"/>)~");
}

TEST_CASE("clip-path basic shapes from style sheets, inherited and on clipPath children", "[svg][clip][shapes]") {
  const std::vector<uint8_t> reference = render(R"~(<clipPath id="c"><circle cx="50" cy="40" r="20"/></clipPath>)~"
                                                "<" + kRect + R"~( clip-path="url(#c)"/>)~");
  CHECK((render("<style>rect { clip-path: circle(20px) }</style><" + kRect + "/>") == reference));
  // inherit: the group and the rectangle, of the same box, clip alike.
  CHECK((render(R"~(<g style="clip-path: circle(20px) fill-box"><)~" + kRect + R"~( clip-path="inherit"/></g>)~") ==
        render(R"~(<clipPath id="c"><circle cx="50" cy="40" r="20"/></clipPath><g clip-path="url(#c)"><)~" + kRect +
               R"~( clip-path="url(#c)"/></g>)~")));
  // A clipPath child clipped by a basic shape of its own box.
  CHECK((render(R"~(<clipPath id="c"><rect x="10" y="10" width="80" height="60" clip-path="circle(20px)"/></clipPath>)~"
               "<" + kRect + R"~( clip-path="url(#c)"/>)~") ==
        render(R"~(<clipPath id="c"><circle cx="50" cy="40" r="20"/></clipPath><)~" + kRect +
               R"~( clip-path="url(#c)"/>)~")));
}

TEST_CASE("clip-path invalid basic shapes drop the declaration", "[svg][clip][shapes]") {
  const std::vector<uint8_t> unclipped = render("<" + kRect + "/>");
  const std::vector<uint8_t> attribute =
      render(R"~(<clipPath id="c"><circle cx="50" cy="40" r="20"/></clipPath><)~" + kRect + R"~( clip-path="url(#c)"/>)~");
  for (const char* v : {"circle(-10px)", "circle(10px 20px)", "circle(10px) fill-box view-box", "circle(10px) x-box",
                        "circle(10px at left 10px top)", "circle(at)", "ellipse(10px)", "inset()",
                        "inset(1px 2px 3px 4px 5px)", "inset(10px round -1px)", "polygon()", "polygon(evenodd)",
                        "polygon(10px)", "polygon(1px 2px, 3px)", "path('M 0 0 L')", "path(nonzero)",
                        "path(M0 0 H10 V10Z)", "circle(10px) path('M0 0 H1 V1 Z')", "url(#c) fill-box",
                        "fill-box fill-box"}) {
    INFO(v);
    // Alone: drawn unclipped; over a presentation attribute: that applies.
    CHECK((render("<" + kRect + " style=\"clip-path: " + v + "\"/>") == unclipped));
    CHECK((render(R"~(<clipPath id="c"><circle cx="50" cy="40" r="20"/></clipPath><)~" + kRect +
                 " clip-path=\"url(#c)\" style=\"clip-path: " + v + "\"/>") == attribute));
  }
  // Shapes without area clip everything away.
  const std::vector<uint8_t> empty = render("");
  CHECK((render("<" + kRect + " style=\"clip-path: circle(0)\"/>") == empty));
  CHECK((render("<" + kRect + " style=\"clip-path: inset(50%)\"/>") == empty));
  CHECK((render("<" + kRect + " style=\"clip-path: path('')\"/>") == empty));
}

TEST_CASE("clip-path basic shape on a clipPath element intersects, against the clipped element's box", "[svg][clip][shapes]") {
  // circle(30px at 50% 50%) of the rectangle's fill box (10, 10)-(90, 70):
  // the circle at (50, 40), r 30, intersected with the clipPath's own
  // half-plane x < 50.
  const std::string with_shape = R"~(<clipPath id="c" style="clip-path: circle(30px at 50% 50%) fill-box">
      <rect x="0" y="0" width="50" height="100"/></clipPath><)~" + kRect + R"~( clip-path="url(#c)"/>)~";
  const std::string written = R"~(<clipPath id="k"><circle cx="50" cy="40" r="30"/></clipPath>
      <clipPath id="c" clip-path="url(#k)"><rect x="0" y="0" width="50" height="100"/></clipPath><)~" + kRect +
                              R"~( clip-path="url(#c)"/>)~";
  const std::vector<uint8_t> image = render(with_shape);
  CHECK(image == render(written));
  CHECK(image != render(R"~(<clipPath id="c"><rect x="0" y="0" width="50" height="100"/></clipPath><)~" + kRect +
                        R"~( clip-path="url(#c)"/>)~"));
}
