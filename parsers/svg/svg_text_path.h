// textPath's path (SVG 2 text.html#TextPathElement): the path measured,
// for placing glyphs at distances along it (svg_text.cpp, step 9b).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/scene.h"
#include "parsers/svg/svg_geometry.h"

namespace mpvg::svg::detail {

// A textPath's path measured as resvg measures it, so that text on a path
// lands where resvg (the suite's reference) puts it: every segment a cubic
// (lines with inner points at 0.33 and 0.66, quadratics raised, conic arcs
// as kurbo's arc cubics), a closed contour's closing line included, moves not
// counted; each cubic's length by 9-point Gauss-Legendre quadrature,
// subdivided until its error estimate is under the accuracy; a distance
// found on a cubic by ITP root finding to that accuracy (kurbo's
// ParamCurveArclen, which resvg uses). The accuracy is 0.5 user units
// over the text's scale (at least 1).
class PathMeasure {
 public:
  struct Cubic {
    Vec2 p0, p1, p2, p3;
    Vec2 eval(double t) const {
      const double mt = 1 - t;
      return {p0.x * (mt * mt * mt) + (p1.x * (mt * mt * 3) + (p2.x * (mt * 3) + p3.x * t) * t) * t,
              p0.y * (mt * mt * mt) + (p1.y * (mt * mt * 3) + (p2.y * (mt * 3) + p3.y * t) * t) * t};
    }
    Vec2 deriv(double t) const {  // the derivative, a quadratic
      const Vec2 a{3 * (p1.x - p0.x), 3 * (p1.y - p0.y)}, b{3 * (p2.x - p1.x), 3 * (p2.y - p1.y)},
          c{3 * (p3.x - p2.x), 3 * (p3.y - p2.y)};
      const double mt = 1 - t;
      return {a.x * mt * mt + 2 * b.x * mt * t + c.x * t * t, a.y * mt * mt + 2 * b.y * mt * t + c.y * t * t};
    }
    Cubic subsegment(double t0, double t1) const {
      const Vec2 a = eval(t0), d = eval(t1), da = deriv(t0), dd = deriv(t1);
      const double k = (t1 - t0) * (1.0 / 3.0);
      return {a, {a.x + k * da.x, a.y + k * da.y}, {d.x - k * dd.x, d.y - k * dd.y}, d};
    }
    double gauss9() const {
      static const double c[9][2] = {{0.3302393550012598, 0.0000000000000000},  {0.1806481606948574, -0.8360311073266358},
                                     {0.1806481606948574, 0.8360311073266358},  {0.0812743883615744, -0.9681602395076261},
                                     {0.0812743883615744, 0.9681602395076261},  {0.3123470770400029, -0.3242534234038089},
                                     {0.3123470770400029, 0.3242534234038089},  {0.2606106964029354, -0.6133714327005904},
                                     {0.2606106964029354, 0.6133714327005904}};
      double sum = 0;
      for (const auto& w : c) {
        const Vec2 d = deriv(0.5 * (w[1] + 1));
        sum += w[0] * std::hypot(d.x, d.y);
      }
      return sum * 0.5;
    }
    double error_estimate() const {
      // The second derivative (a line) squared over the chord, to the 8th.
      const Vec2 s{6 * (p2.x - 2 * p1.x + p0.x), 6 * (p2.y - 2 * p1.y + p0.y)};
      const Vec2 e{6 * (p3.x - 2 * p2.x + p1.x), 6 * (p3.y - 2 * p2.y + p1.y)};
      const Vec2 dd{e.x - s.x, e.y - s.y};
      const double norm = s.x * s.x + s.y * s.y + (s.x * dd.x + s.y * dd.y) + (dd.x * dd.x + dd.y * dd.y) * (1.0 / 3.0);
      const double lc = std::hypot(p3.x - p0.x, p3.y - p0.y);
      const double lp = std::hypot(p1.x - p0.x, p1.y - p0.y) + std::hypot(p2.x - p1.x, p2.y - p1.y) +
                        std::hypot(p3.x - p2.x, p3.y - p2.y);
      return 2.56e-8 * std::pow(norm / (lc * lc), 8) * lp;
    }
    double arclen(double accuracy, int depth = 0) const {
      if (depth == 16 || error_estimate() < accuracy) return gauss9();
      const Cubic a = subsegment(0, 0.5), b = subsegment(0.5, 1);
      return a.arclen(accuracy * 0.5, depth + 1) + b.arclen(accuracy * 0.5, depth + 1);
    }
    // The parameter at arc length s (ITP root finding, tolerance accuracy).
    double inv_arclen(double s, double accuracy, double total) const {
      if (s <= 0) return 0;
      if (s >= total) return 1;
      double t_last = 0, s_last = 0;
      const double epsilon = accuracy / total;
      const double n = 1 - std::min(std::ceil(std::log2(epsilon)), 0.0);
      const double inner = accuracy / n;
      auto f = [&](double t) {
        if (t > t_last) s_last += subsegment(t_last, t).arclen(inner);
        else s_last -= subsegment(t, t_last).arclen(inner);
        t_last = t;
        return s_last - s;
      };
      double a = 0, b = 1, ya = -s, yb = total - s;
      const int nmax = 1 + std::max(0, static_cast<int>(std::ceil(std::log2((b - a) / epsilon)) - 1));
      double scaled = epsilon * std::ldexp(1.0, nmax);
      while (b - a > 2 * epsilon) {
        const double mid = 0.5 * (a + b), r = scaled - 0.5 * (b - a);
        const double xf = (yb * a - ya * b) / (yb - ya), sigma = mid - xf;
        const double delta = 0.2 * (b - a) * (b - a);
        const double xt = delta <= std::abs(mid - xf) ? xf + std::copysign(delta, sigma) : mid;
        const double x = std::abs(xt - mid) <= r ? xt : mid - std::copysign(r, sigma);
        const double y = f(x);
        if (y > 0) b = x, yb = y;
        else if (y < 0) a = x, ya = y;
        else return x;
        scaled *= 0.5;
      }
      return 0.5 * (a + b);
    }
  };

  PathMeasure(const Path& path, double accuracy) : accuracy_(accuracy) {
    const auto& pts = path.points();
    auto line = [&](Vec2 a, Vec2 b) {
      add({a, {a.x + (b.x - a.x) * 0.33, a.y + (b.y - a.y) * 0.33}, {a.x + (b.x - a.x) * 0.66, a.y + (b.y - a.y) * 0.66}, b});
    };
    for (const Path::Contour& c : path.contours()) {
      Vec2 last = pts[c.start_point];
      for (uint32_t k = 0; k < c.segment_count; k++) {
        const Path::Segment& sg = path.segments()[c.first_segment + k];
        const Vec2* q = &pts[sg.first_point];
        switch (sg.type) {
          case SegmentType::Line: line(q[0], q[1]); last = q[1]; break;
          default: {
            const std::array<Vec2, 4> cubic = segment_cubic(path, sg);
            add({cubic[0], cubic[1], cubic[2], cubic[3]});
            last = cubic[3];
            break;
          }
        }
      }
      if (c.closed) line(last, pts[c.start_point]);
    }
  }

  // The same path walked from its end (textPath side="right").
  void reverse() {
    std::vector<Cubic> cubics(cubics_.rbegin(), cubics_.rend());
    std::vector<double> lengths(lengths_.rbegin(), lengths_.rend());
    cubics_.clear(), starts_.clear(), lengths_.clear();
    total_ = 0;
    for (size_t i = 0; i < cubics.size(); i++) {
      const Cubic& c = cubics[i];
      cubics_.push_back({c.p3, c.p2, c.p1, c.p0});
      starts_.push_back(total_);
      lengths_.push_back(lengths[i]);
      total_ += lengths[i];
    }
  }

  bool empty() const { return cubics_.empty(); }
  double total() const { return total_; }

  // The point and the direction (degrees) at distance d: on the first
  // cubic whose span holds d; false off the path.
  bool at(double d, Vec2& p, double& angle) const {
    if (d < 0) return false;
    for (size_t i = 0; i < cubics_.size(); i++) {
      if (d >= starts_[i] && d <= starts_[i] + lengths_[i]) {
        const double t = std::clamp(cubics_[i].inv_arclen(d - starts_[i], accuracy_, lengths_[i]), 0.0, 1.0);
        p = cubics_[i].eval(t);
        const Vec2 v = cubics_[i].deriv(t);
        angle = std::atan2(v.x, -v.y) * 180 / M_PI - 90;
        return true;
      }
    }
    return false;
  }

 private:
  void add(const Cubic& c) {
    const double l = c.arclen(accuracy_);
    cubics_.push_back(c);
    starts_.push_back(total_);
    lengths_.push_back(l);
    total_ += l;
  }
  double accuracy_;
  std::vector<Cubic> cubics_;
  std::vector<double> starts_, lengths_;
  double total_ = 0;
};

}  // namespace mpvg::svg::detail
