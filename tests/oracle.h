// Brute-force references for tests, deliberately independent of core/'s
// algorithms: curves are evaluated from their definitions in double
// precision, monotonic pieces are found by sampling the derivative and
// bisecting, and ray crossings by bisection on the curve itself.
#pragma once
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "core/geometry/abstraction.h"
#include "core/paint/paint.h"
#include "core/scene.h"

namespace mpvg::oracle {

struct Pt {
  double x, y;
};

inline Pt eval(const InputSegment& s, double t) {
  const double u = 1.0 - t;
  switch (s.type) {
    case INPUT_LINE: return {u * s.x[0] + t * s.x[1], u * s.y[0] + t * s.y[1]};
    case INPUT_QUAD:
    case INPUT_RQUAD: {
      const double w = s.type == INPUT_QUAD ? 1.0 : s.w;
      const double b0 = u * u, b1 = 2.0 * w * u * t, b2 = t * t, d = b0 + b1 + b2;
      return {(b0 * s.x[0] + b1 * s.x[1] + b2 * s.x[2]) / d, (b0 * s.y[0] + b1 * s.y[1] + b2 * s.y[2]) / d};
    }
    default: {
      const double b0 = u * u * u, b1 = 3 * u * u * t, b2 = 3 * u * t * t, b3 = t * t * t;
      return {b0 * s.x[0] + b1 * s.x[1] + b2 * s.x[2] + b3 * s.x[3], b0 * s.y[0] + b1 * s.y[1] + b2 * s.y[2] + b3 * s.y[3]};
    }
  }
}

// Parameters splitting [0,1] into pieces on which y (axis 1) or x (axis 0)
// is monotonic, found by dense sampling and bisection of the coordinate's
// change of direction.
inline std::vector<double> monotone_breaks(const InputSegment& s, int axis) {
  std::vector<double> ts{0.0};
  const int n = 512;
  auto coord = [&](double t) { const Pt p = eval(s, t); return axis ? p.y : p.x; };
  double prev_d = 0.0;
  for (int i = 0; i < n; i++) {
    const double a = double(i) / n, b = double(i + 1) / n;
    const double d = coord(b) - coord(a);
    if (i > 0 && d * prev_d < 0.0) {
      // The extremum lies in [(i-1)/n, (i+1)/n]: ternary search.
      double lo = double(i - 1) / n, hi = b;
      const bool is_max = prev_d > 0.0;
      for (int k = 0; k < 100; k++) {
        const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        const bool left = is_max ? coord(m1) < coord(m2) : coord(m1) > coord(m2);
        if (left) lo = m1; else hi = m2;
      }
      ts.push_back(0.5 * (lo + hi));
    }
    if (d != 0.0) prev_d = d;
  }
  ts.push_back(1.0);
  return ts;
}

// Signed crossings of the horizontal ray from (px, py) towards +x with the
// segment, or nullopt when the point is within `band` of the curve or of a
// horizontal tangency/endpoint height (where the count is ambiguous).
inline std::optional<int> ray_crossings(const InputSegment& s, const std::vector<double>& ts, double px, double py,
                                        double band) {
  int w = 0;
  for (size_t i = 0; i + 1 < ts.size(); i++) {
    const Pt a = eval(s, ts[i]), b = eval(s, ts[i + 1]);
    const double ylo = std::min(a.y, b.y), yhi = std::max(a.y, b.y);
    if (std::fabs(py - a.y) < band || std::fabs(py - b.y) < band) {
      // Near a vertex height: ambiguous only if the curve is near in x too.
      const double xlo = std::min(a.x, b.x), xhi = std::max(a.x, b.x);
      if (px > xlo - 1.0 && px < xhi + 1.0) return std::nullopt;
      if (px >= xhi + 1.0) continue;  // right of the piece: no crossing either way
    }
    if (py < ylo || py >= yhi) continue;
    // Bisection for y(t) = py on the monotonic piece.
    double lo = ts[i], hi = ts[i + 1];
    const bool up = b.y > a.y;
    for (int k = 0; k < 200; k++) {
      const double m = 0.5 * (lo + hi);
      const double ym = eval(s, m).y;
      if ((ym < py) == up) lo = m; else hi = m;
    }
    const double x = eval(s, 0.5 * (lo + hi)).x;
    if (std::fabs(x - px) < band) return std::nullopt;
    if (x > px) w += up ? 1 : -1;
  }
  return w;
}

// Winding numbers of every path of an encoded scene.
class Windings {
 public:
  Windings(const std::vector<InputSegment>& segs, size_t npaths) : segs_(segs), npaths_(npaths) {
    for (const InputSegment& s : segs_) breaks_.push_back(monotone_breaks(s, 1));
  }
  // About (px, py); nullopt when the point is within band of a curve.
  std::optional<std::vector<int>> at(double px, double py, double band) const {
    std::vector<int> w(npaths_, 0);
    for (size_t i = 0; i < segs_.size(); i++) {
      const std::optional<int> c = ray_crossings(segs_[i], breaks_[i], px, py, band);
      if (!c) return std::nullopt;
      w[segs_[i].path] += *c;
    }
    return w;
  }

 private:
  std::vector<InputSegment> segs_;
  size_t npaths_;
  std::vector<std::vector<double>> breaks_;
};

// The rectangle [x0, x1] x [y0, y1] as a closed path.
inline Path rect(double x0, double y0, double x1, double y1) { return Path::rectangle(x0, y0, x1, y1); }

// Are two samples identical to the last bit (pruned against unpruned trees)?
inline bool identical(const Rgba4& a, const Rgba4& b) { return a.r == b.r && a.g == b.g && a.b == b.b && a.a == b.a; }

// A random closed path mixing every segment type. Some control points fall
// outside [lo, hi]; a share of vertices snap to the integer grid, the way
// real drawings align edges with pixels and cell boundaries.
inline Path random_path(std::mt19937& rng, double lo, double hi, int contours, int max_segments) {
  std::uniform_real_distribution<double> coord(lo, hi);
  std::uniform_int_distribution<int> kind(0, 5);
  std::uniform_real_distribution<double> weight(0.1, 3.0);
  std::uniform_int_distribution<int> nseg(2, max_segments);
  std::bernoulli_distribution snap(0.3);
  auto pt = [&]() {
    Vec2 p{coord(rng), coord(rng)};
    if (snap(rng)) p = Vec2{std::round(p.x), std::round(p.y)};
    return p;
  };
  Path path;
  for (int c = 0; c < contours; c++) {
    const Vec2 start = pt();
    path.move_to(start);
    const int n = nseg(rng);
    Vec2 cur = start;
    for (int i = 0; i < n; i++) {
      Vec2 end = pt();
      const int k = kind(rng);
      if (k == 5) {
        // Axis-aligned line: horizontal or vertical through the current point.
        end = (i % 2) ? Vec2{cur.x, end.y} : Vec2{end.x, cur.y};
        path.line_to(end);
      } else if (k == 0) {
        path.line_to(end);
      } else if (k == 1) {
        path.quad_to(pt(), end);
      } else if (k == 2) {
        path.rquad_to(pt(), end, weight(rng));
      } else {
        path.cubic_to(pt(), pt(), end);
      }
      cur = end;
    }
    path.close();
  }
  return path;
}

}  // namespace mpvg::oracle
