// Stroke adjustment (stroker/stroke_adjust.h): on random axis-aligned strokes
// and rectangles under random page maps (scale, quarter turns, flips,
// translation), the adjusted geometry's edges fall on pixel boundaries in
// device space, widths are whole pixels (at least one), abutting
// rectangles still abut, and whatever the rules leave alone is unchanged.
#include <cmath>
#include <random>

#include "stroker/stroke_adjust.h"
#include "tests/catch.h"

using namespace mpvg;

namespace {

bool whole(double v) { return std::fabs(v - std::round(v)) < 1e-6; }

// A page map: scale s, a quarter turn k, an optional flip, a translation.
Affine page_map(std::mt19937& rng) {
  std::uniform_real_distribution<double> scale(0.3, 6), shift(-50, 50);
  const double s = scale(rng);
  Affine m = Affine::rotate_degrees(90.0 * (rng() % 4));
  m = {std::round(m.a), std::round(m.b), std::round(m.c), std::round(m.d), 0, 0};
  if (rng() % 2) m = Affine::scale(1, -1) * m;
  return Affine::translate(shift(rng), shift(rng)) * Affine::scale(s, s) * m;
}

}  // namespace

TEST_CASE("adjusted strokes have whole-pixel widths and edges on pixel boundaries", "[stroke_adjust]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(0, 100), width(0.01, 4);
  for (int trial = 0; trial < 500; trial++) {
    const Affine m = page_map(rng);
    REQUIRE(grid_aligned(m));
    const double s = std::sqrt(std::fabs(m.det()));
    // An L of a horizontal and a vertical line, and a rectangle.
    Path p;
    const double x0 = coord(rng), y0 = coord(rng), x1 = coord(rng), y1 = coord(rng);
    p.move_to({x0, y0});
    p.line_to({x1, y0});
    p.line_to({x1, y1});
    p.append(Path::rectangle(x0, y0, x0 + 10, y0 + 5));
    double w = width(rng);
    const double want = std::max(1.0, std::floor(w * s + 0.5));
    const Path q = adjust_stroke(p, &w, m);
    CHECK(std::fabs(w * s - want) < 1e-9);
    REQUIRE(q.segments().size() == p.segments().size());
    for (const Path::Segment& seg : q.segments()) {
      const Vec2 a = m.apply(q.points()[seg.first_point]), b = m.apply(q.points()[seg.first_point + 1]);
      // Each line's two edges, centre -/+ n/2 across it, are on boundaries.
      if (std::fabs(a.y - b.y) < 1e-6) CHECK(whole(a.y - want / 2));
      if (std::fabs(a.x - b.x) < 1e-6) CHECK(whole(a.x - want / 2));
    }
  }
}

TEST_CASE("adjusted rectangles are on pixel boundaries, at least a pixel, and still abut", "[stroke_adjust]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(0, 100), size(0.01, 8);
  for (int trial = 0; trial < 500; trial++) {
    const Affine m = page_map(rng);
    const double x = coord(rng), y = coord(rng), w = size(rng), h = size(rng), w2 = size(rng);
    Path p = Path::rectangle(x, y, x + w, y + h);
    p.append(Path::rectangle(x + w, y, x + w + w2, y + h));  // abuts the first on its right
    const Path q = adjust_fill(p, m);
    REQUIRE(q.points().size() == p.points().size());
    double lo[2][2] = {{INFINITY, INFINITY}, {INFINITY, INFINITY}}, hi[2][2] = {{-INFINITY, -INFINITY}, {-INFINITY, -INFINITY}};
    for (size_t i = 0; i < q.points().size(); i++) {
      const Vec2 d = m.apply(q.points()[i]);
      CHECK(whole(d.x));
      CHECK(whole(d.y));
      const size_t c = i < q.points().size() / 2 ? 0 : 1;
      lo[c][0] = std::min(lo[c][0], d.x), hi[c][0] = std::max(hi[c][0], d.x);
      lo[c][1] = std::min(lo[c][1], d.y), hi[c][1] = std::max(hi[c][1], d.y);
    }
    for (int c = 0; c < 2; c++) {
      CHECK(hi[c][0] - lo[c][0] > 1 - 1e-6);
      CHECK(hi[c][1] - lo[c][1] > 1 - 1e-6);
    }
    // The shared edge: the first rectangle's far side is the second's near
    // side, in x or in y as the map turned them, unless a collapse moved one.
    const Vec2 shared_a = m.apply(q.points()[1]), shared_b = m.apply(q.points()[q.points().size() / 2]);
    const double span = std::min(w, w2) * std::sqrt(std::fabs(m.det()));
    if (span >= 1) CHECK((std::fabs(shared_a.x - shared_b.x) < 1e-6 || std::fabs(shared_a.y - shared_b.y) < 1e-6));
  }
}

TEST_CASE("stroke adjustment leaves curves, diagonals and rotated pages alone", "[stroke_adjust]") {
  Path p;
  p.move_to({1.3, 2.7});
  p.cubic_to({5, 9}, {8, 1}, {12.2, 4.4});
  p.move_to({0.2, 0.2});
  p.line_to({7.7, 5.1});
  double w = 0.3;
  const Path q = adjust_stroke(p, &w, Affine::scale(2, 2));
  CHECK(q.points() == p.points());
  CHECK(w == 0.5);  // widened to one pixel
  CHECK(adjust_fill(p, Affine::scale(2, 2)).points() == p.points());
  // A page turned by 30 degrees: no grid to snap to; a stroke still gets a pixel.
  const Affine turned = Affine::rotate_degrees(30) * Affine::scale(2, 2);
  CHECK_FALSE(grid_aligned(turned));
  CHECK_FALSE(grid_aligned(Affine::scale(2, 3)));
  const Path r = Path::rectangle(1.3, 1.3, 1.6, 9.2);
  CHECK(adjust_fill(r, turned).points() == r.points());
  w = 0.1;
  CHECK(adjust_stroke(r, &w, turned).points() == r.points());
  CHECK(std::fabs(w - 0.5) < 1e-12);
}
