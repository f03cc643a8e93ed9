// One path segment as a parametric curve on t in [0, 1], with what the
// stroker needs of it: derivatives, sub-curves, tangents at the ends, and
// arc length with its inverse. Internal to the stroker (tests use it too).
//
// Rational quadratics are written c(t) = N(t) / D(t) with
//   N = (1-t)^2 P0 + 2t(1-t) w P1 + t^2 P2,   D = (1-t)^2 + 2t(1-t) w + t^2,
// so that their derivatives follow from N and D by the quotient rule:
//   c' = (N' - c D') / D,   c'' = (N'' - 2 c' D' - c D'') / D.
#pragma once
#include <vector>

#include "core/geometry.h"
#include "core/scene.h"

namespace mpvg::stroke {

inline double length(Vec2 v) { return std::sqrt(v.x * v.x + v.y * v.y); }
// v rotated by +90 degrees: the left normal of a direction in a y-up frame.
inline Vec2 rot90(Vec2 v) { return {-v.y, v.x}; }
inline Vec2 normalized(Vec2 v) {
  const double l = length(v);
  return l > 0 ? Vec2{v.x / l, v.y / l} : Vec2{};
}

struct Curve {
  SegmentType type = SegmentType::Line;  // Line, Quad, RQuad or Cubic
  Vec2 p[4];
  double w = 1;  // RQuad: weight of p[1]

  static Curve line(Vec2 a, Vec2 b);

  int degree() const { return segment_degree(type); }
  Vec2 start() const { return p[0]; }
  Vec2 end() const { return p[degree()]; }
  bool is_line() const { return type == SegmentType::Line; }

  Vec2 point(double t) const;
  // c'(t) and c''(t).
  void derivatives(double t, Vec2* d1, Vec2* d2) const;
  Vec2 derivative(double t) const;

  // The same curve restricted to [t0, t1], reparametrised to [0, 1]; the
  // ends are exactly point(t0) and point(t1) (the original end points when
  // t0 = 0 or t1 = 1).
  Curve sub(double t0, double t1) const;

  // Unit tangents at the ends (direction of travel), from the first control
  // point that differs from the end point: the limit of c'/|c'| even where
  // control points coincide. Zero for a curve whose points all coincide.
  Vec2 start_tangent() const;
  Vec2 end_tangent() const;

  // Largest distance of a control point from p[0]: the scale of the curve.
  double extent() const;
  // Every control point within `eps` of p[0]: the segment has no length.
  bool is_point(double eps) const;
};

// The arc length of c over [t0, t1], by adaptive Gauss-Legendre quadrature
// of |c'(t)| to a relative accuracy of about 1e-10.
double arc_length(const Curve& c, double t0 = 0, double t1 = 1);

// Arc length along a curve as a function of t, tabulated once so that
// parameters can be found for lengths (dashing).
class ArcLengthTable {
 public:
  explicit ArcLengthTable(const Curve& c);
  double total() const { return cumulative_.back(); }
  // The parameter t with arc_length(c, 0, t) = s, for s in [0, total()]:
  // Newton's method on the tabulated interval, safeguarded by bisection.
  double param_at(double s) const;

 private:
  Curve c_;
  std::vector<double> cumulative_;  // at t = k / kIntervals
};

}  // namespace mpvg::stroke
