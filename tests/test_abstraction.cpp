// Abstraction (paper §3.1-3.2): pieces are monotonic, share endpoints, and
// their side test agrees with a parametric side test inside the bounding box.
#include <cmath>
#include <random>

#include "core/geometry/abstraction.h"
#include "core/geometry/quadratic.h"
#include "tests/catch.h"
#include "tests/oracle.h"

using namespace mpvg;

namespace {

InputSegment random_input(std::mt19937& rng, uint32_t type) {
  std::uniform_real_distribution<double> coord(-50.0, 150.0);
  std::uniform_real_distribution<double> weight(0.05, 4.0);
  InputSegment s{};
  s.type = type;
  s.w = type == INPUT_RQUAD ? weight(rng) : 1.0;
  const int deg = type == INPUT_LINE ? 1 : (type == INPUT_CUBIC ? 3 : 2);
  for (int i = 0; i <= deg; i++) {
    s.x[i] = coord(rng);
    s.y[i] = coord(rng);
  }
  return s;
}

// Random segments, plus degenerate ones: coincident control points, collinear
// control polygons, cusps, loops, near-quadratic cubics.
std::vector<InputSegment> test_segments(uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<InputSegment> out;
  for (uint32_t type = 0; type < 4; type++)
    for (int i = 0; i < 400; i++) out.push_back(random_input(rng, type));
  InputSegment s{};
  s.type = INPUT_CUBIC;
  s.w = 1;
  auto cubic = [&](double x0, double y0, double x1, double y1, double x2, double y2, double x3, double y3) {
    s.x[0] = x0; s.y[0] = y0; s.x[1] = x1; s.y[1] = y1; s.x[2] = x2; s.y[2] = y2; s.x[3] = x3; s.y[3] = y3;
    out.push_back(s);
  };
  cubic(0, 0, 0, 0, 100, 100, 100, 100);      // coincident control points
  cubic(0, 0, 100, 0, 0, 100, 100, 100);      // serpentine
  cubic(0, 0, 100, 100, 0, 100, 100, 0);      // loop
  cubic(0, 0, 100, 100, 0, 100, 100, 0.001);  // loop, nearly symmetric
  cubic(0, 0, 100, 100, 0, 100, 50, 0);       // cusp-like
  cubic(0, 0, 30, 60, 70, 60.0000001, 100, 0);  // near-degenerate
  cubic(0, 0, 33.3333333, 33.3333333, 66.6666667, 66.6666667, 100, 100);  // straight
  cubic(0, 0, 50, 100, 50, 100, 100, 0);      // degree-elevated quadratic
  cubic(10, 10, 10, 10, 10, 10, 10, 10);      // a point
  return out;
}

}  // namespace

TEST_CASE("solve_quadratic finds the real roots without cancellation", "[abstraction]") {
  double r[2];
  REQUIRE(solve_quadratic(1, 0, -4, r) == 2);  // t^2 - 4
  CHECK(r[0] == -2.0);
  CHECK(r[1] == 2.0);
  REQUIRE(solve_quadratic(1, 1e8, 1, r) == 2);  // t^2 - 2e8 t + 1: roots 5e-9 and 2e8
  CHECK(std::fabs(r[0] - 5e-9) < 1e-20);
  CHECK(std::fabs(r[1] - 2e8) < 1e-6);
  REQUIRE(solve_quadratic(0, 2, 8, r) == 1);  // -4t + 8
  CHECK(r[0] == 2.0);
  CHECK(solve_quadratic(1, 0, 1, r) == 0);
  REQUIRE(solve_quadratic(1, 1, 1, r) == 1);  // (t-1)^2
  CHECK(r[0] == 1.0);
}

TEST_CASE("abstract segments are monotonic pieces sharing endpoints", "[abstraction]") {
  AbstractSegment pieces[kMaxPieces];
  int checked = 0;
  for (const InputSegment& in : test_segments(1)) {
    const int n = abstract_input_segment(in, pieces);
    REQUIRE(n <= kMaxPieces);
    REQUIRE(n == abstract_input_segment(in, nullptr));
    for (int i = 0; i < n; i++) {
      const AbstractSegment& s = pieces[i];
      // Consecutive pieces share endpoints bit for bit; the chain runs from
      // the segment's start to its end.
      if (i > 0) {
        CHECK(s.x0 == pieces[i - 1].x1);
        CHECK(s.y0 == pieces[i - 1].y1);
      }
      const oracle::Pt a = oracle::eval(in, s.t0), b = oracle::eval(in, s.t1);
      CHECK(std::fabs(a.x - s.x0) < 1e-3);
      CHECK(std::fabs(b.y - s.y1) < 1e-3);
      // Monotonic between the endpoints (the piece's float endpoints span its
      // bounding box).
      for (int k = 1; k < 64; k++) {
        const oracle::Pt p = oracle::eval(in, s.t0 + (s.t1 - s.t0) * (k / 64.0));
        const double tol = 1e-4 * (1.0 + std::fabs(p.x) + std::fabs(p.y));
        CHECK(p.x >= std::min(s.x0, s.x1) - tol);
        CHECK(p.x <= std::max(s.x0, s.x1) + tol);
        CHECK(p.y >= std::min(s.y0, s.y1) - tol);
        CHECK(p.y <= std::max(s.y0, s.y1) + tol);
      }
      checked++;
    }
    if (n > 0) {
      CHECK(pieces[0].x0 == float(in.x[0]));
      const int last = in.type == INPUT_LINE ? 1 : (in.type == INPUT_CUBIC ? 3 : 2);
      CHECK(pieces[n - 1].x1 == float(in.x[last]));
      CHECK(pieces[n - 1].y1 == float(in.y[last]));
    }
  }
  CHECK(checked > 3000);
}

// A piece's implicit evaluated in double from its stored coefficients.
static double implicit_double(const AbstractSegment& s, double px, double py) {
  const double b0 = (double(s.x1) - s.cx) * (py - s.cy) - (double(s.y1) - s.cy) * (px - s.cx);
  const double bc = (py - s.y0) * (double(s.x1) - s.x0) - (px - s.x0) * (double(s.y1) - s.y0);
  const double b1 = (double(s.cx) - s.x0) * (py - s.y0) - (double(s.cy) - s.y0) * (px - s.x0);
  const float* k = s.k;
  if (abstract_type(s) == ABSTRACT_QUAD) return k[0] * bc * bc + k[1] * b0 * b1;
  return b0 * (b0 * (k[0] * b0 + k[1] * bc + k[2] * b1) + bc * (k[3] * bc + k[4] * b1) + k[5] * b1 * b1) +
         bc * (bc * (k[6] * bc + k[7] * b1) + k[8] * b1 * b1) + k[9] * b1 * b1 * b1;
}

static double implicit_gradient(const AbstractSegment& s, double px, double py) {
  const double h = 1e-4 * (1.0 + std::fabs(s.x1 - s.x0) + std::fabs(s.y1 - s.y0));
  const double gx = (implicit_double(s, px + h, py) - implicit_double(s, px - h, py)) / (2 * h);
  const double gy = (implicit_double(s, px, py + h) - implicit_double(s, px, py - h)) / (2 * h);
  return std::sqrt(gx * gx + gy * gy);
}

TEST_CASE("implicit functions vanish on their curves", "[abstraction]") {
  AbstractSegment pieces[kMaxPieces];
  double worst = 0;
  int checked = 0;
  for (const InputSegment& in : test_segments(2)) {
    const int n = abstract_input_segment(in, pieces);
    for (int i = 0; i < n; i++) {
      const AbstractSegment& s = pieces[i];
      if (abstract_type(s) == ABSTRACT_LINE) continue;
      const oracle::Pt m = oracle::eval(in, 0.5 * (s.t0 + s.t1));
      const double gmid = implicit_gradient(s, m.x, m.y);
      for (int k = 1; k < 16; k++) {
        const oracle::Pt p = oracle::eval(in, s.t0 + (s.t1 - s.t0) * (k / 16.0));
        // |f| / |grad f| estimates how far (in pixels) the zero set of the
        // float implicit is from the true curve. Near a singular point (node
        // or cusp) of the curve the gradient vanishes and this says nothing.
        const double g = implicit_gradient(s, p.x, p.y);
        if (g < 0.05 * gmid) continue;
        worst = std::max(worst, std::fabs(abstract_implicit(s, float(p.x), float(p.y))) / g);
        checked++;
      }
    }
  }
  INFO("largest distance of the implicit zero set from the curve: " << worst << " px");
  CHECK(worst < 1e-4);
  CHECK(checked > 5000);
}

TEST_CASE("side test agrees with a parametric side test inside the bounding box", "[abstraction]") {
  AbstractSegment pieces[kMaxPieces];
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0, implicit_used = 0;
  for (const InputSegment& in : test_segments(4)) {
    const int n = abstract_input_segment(in, pieces);
    for (int i = 0; i < n; i++) {
      const AbstractSegment& s = pieces[i];
      if (abstract_horizontal(s)) continue;
      const double xmin = abstract_xmin(s), xmax = abstract_xmax(s);
      const double ymin = abstract_ymin(s), ymax = abstract_ymax(s);
      for (int k = 0; k < 200; k++) {
        const float px = float(xmin + (xmax - xmin) * unit(rng));
        const float py = float(ymin + (ymax - ymin) * unit(rng));
        // Parametric: bisect the piece for y(t) = py, compare x(t) with px.
        double lo = s.t0, hi = s.t1;
        const bool up = s.y1 > s.y0;
        for (int it = 0; it < 200; it++) {
          const double m = 0.5 * (lo + hi);
          if ((oracle::eval(in, m).y < py) == up) lo = m; else hi = m;
        }
        const double tm = 0.5 * (lo + hi);
        const double x = oracle::eval(in, tm).x;
        // Distance to the curve, from the horizontal offset and the tangent.
        const oracle::Pt d0 = oracle::eval(in, tm - 1e-7), d1 = oracle::eval(in, tm + 1e-7);
        const double tx = d1.x - d0.x, ty = d1.y - d0.y;
        const double dist = std::fabs(x - px) * std::fabs(ty) / std::max(1e-300, std::sqrt(tx * tx + ty * ty));
        if (dist < 1e-3) continue;  // too close to call in floats
        const int side = abstract_side(s, px, py);
        INFO("type " << in.type << " w " << in.w << " ctrl (" << in.x[0] << "," << in.y[0] << ") (" << in.x[1] << ","
                     << in.y[1] << ") (" << in.x[2] << "," << in.y[2] << ") (" << in.x[3] << "," << in.y[3] << ")");
        INFO("piece " << i << " t [" << s.t0 << ", " << s.t1 << "] flags " << s.flags << " from (" << s.x0 << ","
                      << s.y0 << ") to (" << s.x1 << "," << s.y1 << ") apex (" << s.cx << "," << s.cy << ")");
        INFO("p = (" << px << ", " << py << ") curve x " << x << " chord " << abstract_chord(s, px, py)
                     << " implicit " << abstract_implicit(s, px, py));
        REQUIRE(side == (x > px ? 1 : -1));
        compared++;
        const float d = abstract_chord(s, px, py);
        if (abstract_type(s) != ABSTRACT_LINE && ((s.flags & ABSTRACT_BULGE_LEFT) ? d > 0 : d < 0)) implicit_used++;
      }
    }
  }
  CHECK(compared > 100000);
  CHECK(implicit_used > 10000);
}

TEST_CASE("tri_index numbers the cubic monomials in AbstractSegment::k order", "[abstraction]") {
  // b0^3, b0^2 bc, b0^2 b1, b0 bc^2, b0 bc b1, b0 b1^2, bc^3, bc^2 b1,
  // bc b1^2, b1^3: each exponent triple of degree 3 once, in that order.
  const int order[10][3] = {{3, 0, 0}, {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {1, 1, 1},
                            {1, 0, 2}, {0, 3, 0}, {0, 2, 1}, {0, 1, 2}, {0, 0, 3}};
  for (int i = 0; i < 10; i++) {
    INFO("b0^" << order[i][0] << " bc^" << order[i][1] << " b1^" << order[i][2]);
    CHECK(mpvg::abstraction_detail::tri_index(order[i][0], order[i][1], order[i][2]) == i);
  }
}
