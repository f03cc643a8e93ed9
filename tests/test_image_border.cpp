// The image's border (core/paint/image_border.h): content that stops at the
// canvas edge stays opaque to it, content 3 px inside leaves the edge
// clear, content that crosses the border is filtered as in a larger canvas
// cropped; at every filter and sample count.
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/paint/image_border.h"
#include "frame/frame.h"
#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "cpu/cpu_frame.h"

using namespace mpvg;

namespace {

struct Mode {
  Filter filter;
  int samples;
};
// The presets (1x8, 1x32: the box; 4x4x32: the cardinal cubic) and the hat.
const Mode kModes[] = {{Filter::Box, 8}, {Filter::Box, 32}, {Filter::Cardinal, 32}, {Filter::Hat, 32},
                       {Filter::Mitchell, 8}};

std::vector<uint8_t> render(const std::string& svg, int size, Mode m) {
  const Scene s = svg::parse_svg_string(svg).scene;
  RenderOptions o;
  o.width = o.height = size;
  o.view = Affine::scale(size / s.width, size / s.height);
  o.filter = m.filter;
  o.samples = m.samples;
  o.pattern = PatternKind::BlueNoise;
  return to_rgba8(render_cpu(s, o), Gamma::Srgb);
}

std::string svg64(const std::string& body) {
  return "<svg xmlns='http://www.w3.org/2000/svg' width='64' height='64'>" + body + "</svg>";
}

bool edge(int x, int y, int n) { return x == 0 || y == 0 || x == n - 1 || y == n - 1; }

}  // namespace

TEST_CASE("content that fills the canvas is opaque in every edge pixel") {
  const std::string defs =
      "<defs><linearGradient id='g'><stop offset='0' stop-color='red'/><stop offset='1' stop-color='blue'/>"
      "</linearGradient><pattern id='p' width='8' height='8' patternUnits='userSpaceOnUse'>"
      "<rect width='4' height='8' fill='green'/><rect x='4' width='4' height='8' fill='yellow'/></pattern>"
      "<clipPath id='c'><rect width='64' height='64'/></clipPath></defs>";
  const std::string cases[] = {
      "<rect width='64' height='64' fill='#3060c0'/>",
      defs + "<rect width='100%' height='100%' fill='url(#g)'/>",
      defs + "<rect width='64' height='64' fill='url(#p)'/>",
      defs + "<g clip-path='url(#c)'><rect x='-9' y='-9' width='90' height='90' fill='#3060c0'/></g>",
      // Two halves meeting inside: each stops at the border on three sides.
      "<rect width='32' height='64' fill='#c03020'/><rect x='32' width='32' height='64' fill='#20c030'/>",
  };
  for (const Mode m : kModes)
    for (const std::string& body : cases) {
      const std::vector<uint8_t> px = render(svg64(body), 64, m);
      int lowest = 255;
      for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++)
          if (edge(x, y, 64)) lowest = std::min<int>(lowest, px[(size_t(y) * 64 + x) * 4 + 3]);
      INFO(filter_name(m.filter) << " x" << m.samples << ": " << body);
      CHECK(lowest == 255);
    }
}

TEST_CASE("content 3 px inside the canvas leaves its edge clear") {
  for (const Mode m : kModes) {
    const std::vector<uint8_t> px = render(svg64("<rect x='3' y='3' width='58' height='58' fill='#3060c0'/>"), 64, m);
    int highest = 0;
    for (int y = 0; y < 64; y++)
      for (int x = 0; x < 64; x++)
        if (edge(x, y, 64)) highest = std::max<int>(highest, px[(size_t(y) * 64 + x) * 4 + 3]);
    INFO(filter_name(m.filter) << " x" << m.samples);
    // The cardinal interpolator rings (|z|^k): 1/255 at 2.5 px; the others
    // reach 2 px at most.
    CHECK(highest <= (m.filter == Filter::Cardinal ? 1 : 0));
  }
}

TEST_CASE("content crossing the border is filtered as in a larger canvas cropped") {
  const std::string shapes =
      "<circle cx='50' cy='20' r='23' fill='#c03020'/>"
      "<path d='M-5 40 L70 55 L70 70 L-5 70 z' fill='#208040' fill-opacity='0.8'/>"
      "<path d='M20 -6 L28 -6 L44 10 z' fill='#2040a0'/>";
  for (const Mode m : kModes) {
    const std::vector<uint8_t> a = render(svg64(shapes), 64, m);
    // 96 px over the same plane, the 64 px image 16 px in (a multiple of
    // every support: the same unit areas, the same pattern classes).
    const std::vector<uint8_t> big = render(
        "<svg xmlns='http://www.w3.org/2000/svg' width='96' height='96' viewBox='-16 -16 96 96'>" + shapes + "</svg>",
        96, m);
    int worst = 0;
    for (int y = 0; y < 64; y++)
      for (int x = 0; x < 64; x++)
        for (int c = 0; c < 4; c++)
          worst = std::max(worst, std::abs(int(a[(size_t(y) * 64 + x) * 4 + c]) -
                                           int(big[(size_t(y + 16) * 96 + x + 16) * 4 + c])));
    INFO(filter_name(m.filter) << " x" << m.samples);
    CHECK(worst <= 1);
  }
}

TEST_CASE("push_out_border_edges adds only what lies in the margin") {
  ImageBorder b;
  b.set = true;
  b.x0 = b.y0 = 13.5, b.x1 = b.y1 = 77.5;
  b.fx1 = b.fy1 = 91;
  auto line = [](double x0, double y0, double x1, double y1) {
    InputSegment s{};
    s.type = INPUT_LINE;
    s.w = 1;
    s.x[0] = x0, s.y[0] = y0, s.x[1] = x1, s.y[1] = y1;
    return s;
  };
  // The canvas's rectangle, a triangle with one edge on the right border,
  // and an edge inside: 4 + 1 pushed out, the inner ones kept.
  std::vector<InputSegment> segs = {line(13.5, 13.5, 77.5, 13.5), line(77.5, 13.5, 77.5, 77.5),
                                    line(77.5, 77.5, 13.5, 77.5), line(13.5, 77.5, 13.5, 13.5),
                                    line(77.5, 30, 77.5, 40.0004),  line(77.5, 40.0004, 50, 35),
                                    line(50, 35, 77.5, 30)};
  CHECK(push_out_border_edges(b, segs, 0) == 5);
  REQUIRE(segs.size() == 7 + 2 * 5);
  // Every point is in the image's closed box or outside it by the margin;
  // the corners went to the frame's corners, one unit area past them.
  int outside = 0;
  for (const InputSegment& s : segs)
    for (int k = 0; k < 2; k++) {
      const bool in = s.x[k] >= 13.5 && s.x[k] <= 77.5 && s.y[k] >= 13.5 && s.y[k] <= 77.5;
      const bool beyond = s.x[k] < 0 || s.x[k] > 91 || s.y[k] < 0 || s.y[k] > 91;
      CHECK((in || beyond));
      outside += beyond;
    }
  CHECK(outside == 2 * 2 * 5);
  CHECK(segs[1].x[0] == -1);
  CHECK(segs[1].y[0] == -1);
  CHECK(segs[1].x[1] == 92);
  CHECK(segs[1].y[1] == -1);
  // Unset: nothing changes.
  std::vector<InputSegment> same = {line(13.5, 13.5, 77.5, 13.5)};
  CHECK(push_out_border_edges(ImageBorder{}, same, 0) == 0);
  CHECK(same.size() == 1);
}
