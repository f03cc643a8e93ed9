// Random centrelines for the stroke tests (test_stroker, test_stroke):
// every segment type with the hard cases of stroking.
#pragma once
#include <cmath>
#include <random>

#include "core/scene.h"

namespace mpvg::test {

inline Vec2 rpt(std::mt19937& rng, double lo = 0, double hi = 100) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng)};
}

// A cubic with an exact cusp at t = 1/2: c'(1/2) = 3/4 (a + 2b + c) = 0 for
// the control polygon legs a, b, c.
inline void cusp_cubic(Path& p, Vec2 a, Vec2 b) {
  const Vec2 p0 = p.current_point(), p1 = p0 + a, p2 = p1 + b, p3 = p2 + (-1.0) * (a + 2 * b);
  p.cubic_to(p1, p2, p3);
}

// Random subpaths mixing every segment type with the hard cases: cusps,
// near-cusps, loops, tight turns (radius of curvature far below h),
// coincident control points, 180° turns; open and closed.
inline Path random_path(std::mt19937& rng, int contours) {
  std::uniform_int_distribution<int> kind(0, 9), nseg(1, 4);
  std::uniform_real_distribution<double> weight(0.2, 3.0);
  std::bernoulli_distribution closed(0.4);
  Path p;
  for (int c = 0; c < contours; c++) {
    p.move_to(rpt(rng));
    const int n = nseg(rng);
    for (int i = 0; i < n; i++) {
      const Vec2 cur = p.current_point();
      switch (kind(rng)) {
        case 0: p.line_to(rpt(rng)); break;
        case 1: p.quad_to(rpt(rng), rpt(rng)); break;
        case 2: p.rquad_to(rpt(rng), rpt(rng), weight(rng)); break;
        case 3: p.cubic_to(rpt(rng), rpt(rng), rpt(rng)); break;
        case 4: cusp_cubic(p, rpt(rng, -40, 40), rpt(rng, -40, 40)); break;
        case 5: {  // near-cusp
          const Vec2 a = rpt(rng, -40, 40), b = rpt(rng, -40, 40);
          const Vec2 p1 = cur + a, p2 = p1 + b, p3 = p2 + (-1.0) * (a + 2 * b) + Vec2{0.3, -0.2};
          p.cubic_to(p1, p2, p3);
          break;
        }
        case 6: {  // a tight turn: the tangent reverses within a tiny radius
          const Vec2 d = rpt(rng, -60, 60);
          p.quad_to(cur + d, cur + Vec2{0.5, 0.5});
          break;
        }
        case 7: {  // coincident control points
          const Vec2 e = rpt(rng);
          p.cubic_to(cur, rpt(rng), e);
          break;
        }
        case 8: {  // 180° turn between lines
          const Vec2 e = rpt(rng);
          p.line_to(e);
          p.line_to(cur);
          break;
        }
        default: p.cubic_to(rpt(rng), rpt(rng), cur + rpt(rng, -5, 5)); break;  // loop-ish
      }
    }
    if (closed(rng)) p.close();
  }
  return p;
}

// A circle as four exact conic quarters: right, bottom, left, top.
inline Path circle(Vec2 c, double r) {
  const double k = M_SQRT1_2;
  Path p;
  p.move_to({c.x + r, c.y});
  p.rquad_to({c.x + r, c.y + r}, {c.x, c.y + r}, k);
  p.rquad_to({c.x - r, c.y + r}, {c.x - r, c.y}, k);
  p.rquad_to({c.x - r, c.y - r}, {c.x, c.y - r}, k);
  p.rquad_to({c.x + r, c.y - r}, {c.x + r, c.y}, k);
  p.close();
  return p;
}

}  // namespace mpvg::test
