// SVG 2 features as equivalences: a document using the feature renders on
// the CPU backend to exactly the pixels of the same drawing written
// without it. pathLength (SVG 2 paths.html#PathLengthAttribute) against
// dash arrays, dash offsets and startOffsets scaled by hand; the d property
// (paths.html#TheDProperty) against the d attribute it stands for; a
// marked element's bounding box (coords.html#BoundingBoxes) against the
// region it gives a mask, written out.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "frame/frame.h"
#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "cpu/cpu_frame.h"

using namespace mpvg;

namespace {

// `body` in a 200 x 100 document, rendered at 200 x 100 pixels with the
// DejaVu Sans of Debian's fonts-dejavu-core for text (system fonts off).
std::vector<uint8_t> pixels(const std::string& body) {
  svg::ParseOptions po;
  po.font_dirs = {"/usr/share/fonts/truetype/dejavu"};
  po.system_fonts = false;
  po.view = [](double, double) { return Affine{}; };
  const std::string svg = svg_test::document(body, R"(width="200" height="100" font-family="DejaVu Sans")");
  RenderOptions o;
  o.width = 200;
  o.height = 100;
  o.backend = Backend::Cpu;
  return to_rgba8(render_cpu(svg::parse_svg_string(svg, ".", po).scene, o), o.gamma);
}

bool blank(const std::vector<uint8_t>& image) {
  for (uint8_t v : image)
    if (v != 0) return false;
  return true;
}

// Both bodies draw something, and the same pixels.
void check_same(const std::string& with_feature, const std::string& without) {
  const std::vector<uint8_t> a = pixels(with_feature), b = pixels(without);
  INFO(with_feature);
  CHECK_FALSE(blank(b));
  CHECK(a == b);
}

}  // namespace

TEST_CASE("pathLength scales dash arrays and offsets by computed length over pathLength", "[svg][features]") {
  const std::string stroke = R"~( fill="none" stroke="black" stroke-width="4")~";
  // A line of length 160 said to be 40 long: dashes four times longer.
  check_same(R"~(<path d="M 20 20 H 180" pathLength="40" stroke-dasharray="5 3" stroke-dashoffset="2")~" + stroke +
                 "/>",
             R"~(<path d="M 20 20 H 180" stroke-dasharray="20 12" stroke-dashoffset="8")~" + stroke + "/>");
  // Basic shapes too, a closed one measured with its closing side: a
  // 120 x 40 rectangle (320 around) said to be 160 long.
  check_same(R"~(<rect x="40" y="40" width="120" height="40" pathLength="160" stroke-dasharray="10")~" + stroke +
                 "/>",
             R"~(<rect x="40" y="40" width="120" height="40" stroke-dasharray="20")~" + stroke + "/>");
  // In the shape's user space, before its transform.
  check_same(R"~(<line x1="0" y1="50" x2="100" y2="50" transform="scale(2 1)" pathLength="25" stroke-dasharray="5")~" +
                 stroke + "/>",
             R"~(<line x1="0" y1="50" x2="100" y2="50" transform="scale(2 1)" stroke-dasharray="20")~" + stroke + "/>");
  // Zero (an infinite scale) makes the stroke solid, as in Chromium.
  check_same(R"~(<path d="M 20 20 H 180" pathLength="0" stroke-dasharray="5 3")~" + stroke + "/>",
             R"~(<path d="M 20 20 H 180")~" + stroke + "/>");
  // Negative and invalid values, and pathLength as a CSS property (it is
  // none), change nothing.
  for (const char* ignored : {R"~(pathLength="-40")~", R"~(pathLength="40px")~", R"~(style="pathLength: 40")~"})
    check_same(R"~(<path d="M 20 20 H 180" stroke-dasharray="5 3" )~" + std::string(ignored) + stroke + "/>",
               R"~(<path d="M 20 20 H 180" stroke-dasharray="5 3")~" + stroke + "/>");
  // Strokes without dashes, and fills, do not change.
  check_same(R"~(<path d="M 20 20 H 180 V 80 Z" pathLength="7" fill="green")~" + std::string(R"~( stroke="black"/>)~"),
             R"~(<path d="M 20 20 H 180 V 80 Z" fill="green" stroke="black"/>)~");
}

TEST_CASE("pathLength scales a textPath's startOffset lengths but not its percentages", "[svg][features]") {
  if (!std::filesystem::exists("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")) {
    WARN("skipped: DejaVu Sans is not installed (Debian package fonts-dejavu-core)");
    return;
  }
  // A path of length 180 said to be 90 long.
  auto text = [](const std::string& path_length, const std::string& offset) {
    return R"~(<path id="p" d="M 10 60 H 190" )~" + path_length + R"~(/><text font-size="20"><textPath href="#p" )~" +
           offset + ">Text</textPath></text>";
  };
  if (blank(pixels(text("", "")))) {
    WARN("skipped: mpvg was built without text");
    return;
  }
  check_same(text(R"~(pathLength="90")~", R"~(startOffset="30")~"), text("", R"~(startOffset="60")~"));
  check_same(text(R"~(pathLength="90")~", R"~(startOffset="25%")~"), text("", R"~(startOffset="25%")~"));
}

TEST_CASE("the d property overrides a path's d attribute", "[svg][features]") {
  const std::string square = "M 20 20 H 60 V 60 H 20 Z", attribute = R"~(<path d="M 100 20 H 180 V 80 Z"/>)~";
  const std::string plain = R"~(<path d=")~" + square + R"~("/>)~";
  // From a style sheet, over the attribute whatever the rule's specificity.
  check_same(R"~(<style>path { d: path(")~" + square + R"~(") }</style>)~" + attribute, plain);
  // From the style attribute, over a sheet's rule.
  check_same(R"~(<style>#p { d: path("M 0 0 H 9 V 9 Z") }</style><path id="p" style="d: path(')~" + square +
                 R"~(')" d="M 100 20 H 180 V 80 Z"/>)~",
             plain);
  // An invalid declaration is dropped: the attribute stays, or an earlier
  // valid declaration. Path data with an error, a fill rule (the d
  // property takes none), a bare string, path data in the attribute's form.
  for (const char* invalid : {"path('M 20 20 H 60 V 60 H 20 Z L')", "path(evenodd, 'M 0 0 H 9 V 9 Z')",
                              "'M 0 0 H 9 V 9 Z'", "M 0 0 H 9 V 9 Z"}) {
    check_same(R"~(<path style="d: )~" + std::string(invalid) + R"~(" d=")~" + square + R"~("/>)~", plain);
    check_same(R"~(<path style="d: path(')~" + square + "'); d: " + invalid + R"~(" d="M 100 20 H 180 V 80 Z"/>)~",
               plain);
  }
  // none, initial and an empty path draw nothing, whatever the attribute.
  for (const char* nothing : {"none", "initial", "path('')"})
    check_same(plain + R"~(<path style="d: )~" + nothing + R"~(" d="M 100 20 H 180 V 80 Z"/>)~", plain);
  // Not a property of other shapes; not path data in the attribute.
  check_same(R"~(<rect x="20" y="20" width="40" height="40" style="d: path('M 100 20 H 180 V 80 Z')"/>)~",
             R"~(<rect x="20" y="20" width="40" height="40"/>)~");
  check_same(plain + R"~(<path d="path('M 100 20 H 180 V 80 Z')"/>)~", plain);
  // inherit takes the parent's value, set on a group where it does nothing.
  check_same(R"~(<g style="d: path(')~" + square + R"~(')"><path style="d: inherit" d="M 100 20 H 180 V 80 Z"/></g>)~",
             plain);
}

TEST_CASE("markers are outside their element's bounding box: an objectBoundingBox mask cuts them", "[svg][features]") {
  // The polyline's box is x 20..180, y 70..80 (markers and stroke left out,
  // SVG 2 coords.html#BoundingBoxes); the mask's default region, -10 % and
  // 120 % of it, is x 4..196, y 69..81: the same mask given in user units.
  const std::string defs = R"~(<marker id="m" markerWidth="20" markerHeight="20" refX="10" refY="10"
      markerUnits="userSpaceOnUse"><circle cx="10" cy="10" r="10" fill="blue"/></marker>)~";
  const std::string line = R"~(<polyline points="20,80 100,70 180,80" fill="none" stroke="black" stroke-width="4"
      marker-start="url(#m)" marker-mid="url(#m)" marker-end="url(#m)" mask="url(#k)"/>)~";
  check_same("<defs>" + defs + R"~(<mask id="k"><rect width="200" height="100" fill="white"/></mask></defs>)~" + line,
             "<defs>" + defs +
                 R"~(<mask id="k" maskUnits="userSpaceOnUse" x="4" y="69" width="192" height="12">
                     <rect width="200" height="100" fill="white"/></mask></defs>)~" + line);
}

TEST_CASE("transform-box fill-box: transform-origin's percentages and keywords of the object bounding box", "[svg][features]") {
  // CSS Transforms 1 §5, §6: the box of x 20..80, y 30..70; its centre is
  // (50, 50), 25 % 100 % is (35, 70), and with no transform-origin (0 0)
  // the origin is the box's corner (20, 30).
  check_same(R"~(<rect x="20" y="30" width="60" height="40" fill="green"
                  style="transform-box: fill-box; transform-origin: center" transform="rotate(30)"/>)~",
             R"~(<rect x="20" y="30" width="60" height="40" fill="green" transform="rotate(30 50 50)"/>)~");
  check_same(R"~(<circle cx="50" cy="50" r="20" fill="blue"
                  style="transform-box: content-box; transform-origin: 25% 100%" transform="rotate(-20)"/>)~",
             R"~(<circle cx="50" cy="50" r="20" fill="blue" transform="rotate(-20 40 70)"/>)~");
  check_same(R"~(<rect x="20" y="30" width="60" height="40" fill="red" style="transform-box: fill-box"
                  transform="scale(0.5)"/>)~",
             R"~(<rect x="20" y="30" width="60" height="40" fill="red"
                  transform="translate(20 30) scale(0.5) translate(-20 -30)"/>)~");
  // view-box is the default: percentages of the viewport (200 x 100).
  check_same(R"~(<rect x="20" y="30" width="60" height="40" fill="green"
                  style="transform-box: view-box; transform-origin: 50% 50%" transform="rotate(30)"/>)~",
             R"~(<rect x="20" y="30" width="60" height="40" fill="green" transform="rotate(30 100 50)"/>)~");
}

TEST_CASE("transform-box fill-box on a group: the union of its children's boxes under their transforms", "[svg][features]") {
  // SVG 2 coords.html#BoundingBoxes: a rect at x 20..60, y 20..40 and a
  // rect of 10 x 10 moved by (70, 50), whose own rotation about its centre
  // (fill-box, center) leaves its box 70..80 x 50..60 wide as its
  // diagonal: 75 -/+ 7.07. A hidden child (display none) adds nothing.
  // Union: x 20..82.07, y 20..62.07, centre (51.04, 41.04).
  const double half = 5 * std::sqrt(2.0);
  const double cx = (20 + 75 + half) / 2, cy = (20 + 55 + half) / 2;
  const std::string children =
      R"~(<rect x="20" y="20" width="40" height="20" fill="green"/>)~"
      R"~(<rect width="10" height="10" fill="blue" transform="translate(70 50)"/>)~"
      R"~(<rect x="150" y="90" width="5" height="5" fill="red" display="none"/>)~";
  const std::string rotated_child =
      R"~(<rect x="20" y="20" width="40" height="20" fill="green"/>)~"
      R"~(<g transform="translate(70 50)"><rect width="10" height="10" fill="blue"
            style="transform-box: fill-box; transform-origin: center" transform="rotate(45)"/></g>)~";
  check_same(R"~(<g style="transform-box: fill-box; transform-origin: center" transform="rotate(30)">)~" +
                 rotated_child + "</g>",
             "<g transform='rotate(30 " + std::to_string(cx) + " " + std::to_string(cy) + ")'>" + rotated_child +
                 "</g>");
  // Percentages of the box; a group of a group.
  check_same(R"~(<g style="transform-box: fill-box; transform-origin: 0% 100%" transform="scale(0.5)"><g>)~" +
                 children + "</g></g>",
             "<g transform='translate(20 60) scale(0.5) translate(-20 -60)'>" + children + "</g>");
}
