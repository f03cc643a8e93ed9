// Stage "stroke", the centreline: one path segment as a parametric curve
// on t in [0, 1], with what stroke expansion needs of it (derivatives,
// sub-curves, end tangents, arc length and its inverse), written once as
// MPVG_HD code for both executors (stroker/stroke.h).
//
// Rational quadratics are written c(t) = N(t) / D(t) with
//   N = (1-t)^2 P0 + 2t(1-t) w P1 + t^2 P2,   D = (1-t)^2 + 2t(1-t) w + t^2,
// so that their derivatives follow from N and D by the quotient rule:
//   c' = (N' - c D') / D,   c'' = (N'' - 2 c' D' - c D'') / D.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/geometry/geometry.h"
#include "core/hd.h"

namespace mpvg::stroking {

constexpr double kPi = 3.14159265358979323846;

// Segment kinds, as the encoder's INPUT_* values (core/geometry/abstraction.h).
enum : uint32_t { CURVE_LINE = 0, CURVE_QUAD = 1, CURVE_RQUAD = 2, CURVE_CUBIC = 3 };

MPVG_HD_INLINE double dmin(double a, double b) { return a < b ? a : b; }
MPVG_HD_INLINE double dmax(double a, double b) { return a > b ? a : b; }
MPVG_HD_INLINE double dclamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }
// Finite: false for infinities and NaN.
MPVG_HD_INLINE bool finite(double x) { return x - x == 0; }
MPVG_HD_INLINE bool finite(Vec2 p) { return finite(p.x) && finite(p.y); }

MPVG_HD_INLINE double length(Vec2 v) { return sqrt(v.x * v.x + v.y * v.y); }
// v rotated by +90 degrees: the left normal of a direction in a y-up frame.
MPVG_HD_INLINE Vec2 rot90(Vec2 v) { return {-v.y, v.x}; }
MPVG_HD_INLINE Vec2 normalized(Vec2 v) {
  const double l = length(v);
  return l > 0 ? Vec2{v.x / l, v.y / l} : Vec2{};
}

// The index of the lowest / highest set bit of m (m != 0).
MPVG_HD_INLINE int lowest_bit(uint64_t m) {
#if defined(__CUDA_ARCH__)
  return __ffsll(static_cast<long long>(m)) - 1;
#else
  return __builtin_ctzll(m);
#endif
}
MPVG_HD_INLINE int highest_bit(uint64_t m) {
#if defined(__CUDA_ARCH__)
  return 63 - __clzll(static_cast<long long>(m));
#else
  return 63 - __builtin_clzll(m);
#endif
}

struct Curve {
  uint32_t type = CURVE_LINE;
  Vec2 p[4];
  double w = 1;  // CURVE_RQUAD: weight of p[1]

  MPVG_HD static Curve line(Vec2 a, Vec2 b) {
    Curve c;
    c.p[0] = a;
    c.p[1] = b;
    return c;
  }
  MPVG_HD int degree() const { return type == CURVE_LINE ? 1 : (type == CURVE_CUBIC ? 3 : 2); }
  MPVG_HD Vec2 start() const { return p[0]; }
  MPVG_HD Vec2 end() const { return p[degree()]; }
  MPVG_HD bool is_line() const { return type == CURVE_LINE; }

  MPVG_HD Vec2 point(double t) const {
    if (t == 0) return p[0];
    if (t == 1) return end();
    const double s = 1 - t;
    switch (type) {
      case CURVE_LINE: return s * p[0] + t * p[1];
      case CURVE_QUAD: return (s * s) * p[0] + (2 * s * t) * p[1] + (t * t) * p[2];
      case CURVE_RQUAD: {
        const double b0 = s * s, b1 = 2 * s * t * w, b2 = t * t;
        return (1 / (b0 + b1 + b2)) * (b0 * p[0] + b1 * p[1] + b2 * p[2]);
      }
      default: return (s * s * s) * p[0] + (3 * s * s * t) * p[1] + (3 * s * t * t) * p[2] + (t * t * t) * p[3];
    }
  }

  // c'(t) and c''(t).
  MPVG_HD void derivatives(double t, Vec2* d1, Vec2* d2) const {
    const double s = 1 - t;
    switch (type) {
      case CURVE_LINE:
        *d1 = p[1] - p[0];
        *d2 = {};
        return;
      case CURVE_QUAD:
        *d1 = 2 * (s * (p[1] - p[0]) + t * (p[2] - p[1]));
        *d2 = 2 * (p[2] - 2 * p[1] + p[0]);
        return;
      case CURVE_CUBIC:
        *d1 = 3 * (s * s * (p[1] - p[0]) + 2 * t * s * (p[2] - p[1]) + t * t * (p[3] - p[2]));
        *d2 = 6 * (s * (p[2] - 2 * p[1] + p[0]) + t * (p[3] - 2 * p[2] + p[1]));
        return;
      default: {
        // Quotient rule on N / D, with the points taken relative to p[0]:
        // derivatives do not depend on the origin, and this way no
        // cancellation of coordinates spoils them where c' vanishes.
        const Vec2 wp1 = w * (p[1] - p[0]), p2 = p[2] - p[0];
        const Vec2 n0 = 2 * t * s * wp1 + t * t * p2;
        const Vec2 n1 = 2 * (s * wp1 + t * (p2 - wp1));
        const Vec2 n2 = 2 * (p2 - 2 * wp1);
        const double d0 = s * s + 2 * t * s * w + t * t;
        const double dd1 = 2 * (w - 1) * (1 - 2 * t);
        const double dd2 = 4 * (1 - w);
        const Vec2 c = (1 / d0) * n0;
        const Vec2 c1 = (1 / d0) * (n1 - dd1 * c);
        *d1 = c1;
        *d2 = (1 / d0) * (n2 - (2 * dd1) * c1 - dd2 * c);
        return;
      }
    }
  }
  MPVG_HD Vec2 derivative(double t) const {
    Vec2 d1, d2;
    derivatives(t, &d1, &d2);
    return d1;
  }

  // The same curve restricted to [t0, t1], reparametrised to [0, 1], by
  // blossoming in homogeneous coordinates; the ends are exactly point(t0)
  // and point(t1) (the original end points when t0 = 0 or t1 = 1).
  MPVG_HD Curve sub(double t0, double t1) const {
    if (t0 == 0 && t1 == 1) return *this;
    const int n = degree();
    double hx[4], hy[4], hw[4];
    for (int i = 0; i <= n; i++) hx[i] = p[i].x, hy[i] = p[i].y, hw[i] = 1;
    if (type == CURVE_RQUAD) hx[1] *= w, hy[1] *= w, hw[1] = w;
    Curve out;
    out.type = type;
    double ow[4];
    for (int k = 0; k <= n; k++) {
      // Blossom at (t0 x (n - k), t1 x k): de Casteljau with one parameter per level.
      double qx[4], qy[4], qw[4];
      for (int i = 0; i <= n; i++) qx[i] = hx[i], qy[i] = hy[i], qw[i] = hw[i];
      for (int j = 0; j < n; j++) {
        const double u = j < n - k ? t0 : t1;
        for (int i = 0; i < n - j; i++) {
          qx[i] = (1 - u) * qx[i] + u * qx[i + 1];
          qy[i] = (1 - u) * qy[i] + u * qy[i + 1];
          qw[i] = (1 - u) * qw[i] + u * qw[i + 1];
        }
      }
      out.p[k] = {qx[0] / qw[0], qy[0] / qw[0]};
      ow[k] = qw[0];
    }
    if (t0 == 0) out.p[0] = p[0];
    if (t1 == 1) out.p[n] = end();
    // Back to the standard form with unit end weights: w' = w1 / sqrt(w0 w2).
    if (type == CURVE_RQUAD) out.w = ow[1] / sqrt(ow[0] * ow[2]);
    return out;
  }

  // Largest distance of a control point from p[0]: the scale of the curve.
  MPVG_HD double extent() const {
    double e = 0;
    for (int i = 1; i <= degree(); i++) e = dmax(e, length(p[i] - p[0]));
    return e;
  }

  // Unit tangents at the ends (direction of travel), from the first control
  // point that differs from the end point: the limit of c'/|c'| even where
  // control points coincide. Zero for a curve whose points all coincide.
  MPVG_HD Vec2 start_tangent() const {
    const int n = degree();
    const double eps = 1e-12 * extent();
    for (int i = 1; i <= n; i++)
      if (length(p[i] - p[0]) > eps) return normalized(p[i] - p[0]);
    return {};
  }
  MPVG_HD Vec2 end_tangent() const {
    const int n = degree();
    const double eps = 1e-12 * extent();
    for (int i = n - 1; i >= 0; i--)
      if (length(p[n] - p[i]) > eps) return normalized(p[n] - p[i]);
    return {};
  }
};

// ---------------------------------------------------------------- arc length

// 5-point Gauss-Legendre quadrature of |c'| over [a, b].
MPVG_HD_INLINE double gauss_length(const Curve& c, double a, double b) {
  const double x[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
  const double wt[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                        0.2369268850561891};
  const double half = (b - a) / 2, mid = (a + b) / 2;
  double s = 0;
  for (int i = 0; i < 5; i++) s += wt[i] * length(c.derivative(mid + half * x[i]));
  return s * half;
}

// The arc length of c over [t0, t1], by adaptive Gauss-Legendre quadrature
// to a relative accuracy of about 1e-11 of the control polygon: intervals
// are split until their halves agree with them (an explicit stack, depth
// at most kArcDepth; the speed |c'| has kinks at cusps, where the
// subdivision concentrates).
constexpr int kArcDepth = 30;

MPVG_HD_INLINE double arc_length(const Curve& c, double t0 = 0, double t1 = 1) {
  if (!(t1 > t0)) return 0;
  if (c.is_line()) return (t1 - t0) * length(c.p[1] - c.p[0]);
  double poly = 0;
  for (int i = 0; i < c.degree(); i++) poly += length(c.p[i + 1] - c.p[i]);
  struct Item {
    double a, b, whole, tol;
    int depth;
  };
  Item stack[kArcDepth + 2];
  int top = 0;
  stack[top++] = {t0, t1, gauss_length(c, t0, t1), 1e-11 * poly + 1e-300, 0};
  double total = 0;
  while (top > 0) {
    const Item it = stack[--top];
    const double m = (it.a + it.b) / 2;
    const double left = gauss_length(c, it.a, m), right = gauss_length(c, m, it.b);
    if (it.depth >= kArcDepth || fabs(left + right - it.whole) <= it.tol) {
      total += left + right;
      continue;
    }
    // Right half pushed first: the left one is summed first, as recursion would.
    stack[top++] = {m, it.b, right, it.tol / 2, it.depth + 1};
    stack[top++] = {it.a, m, left, it.tol / 2, it.depth + 1};
  }
  return total;
}

// Arc length along a curve as a function of t, tabulated at kArcTable
// intervals so that parameters can be found for lengths (dashing).
constexpr int kArcTable = 16;

struct ArcTable {
  Curve c;
  double cum[kArcTable + 1];

  MPVG_HD explicit ArcTable(const Curve& curve) : c(curve) {
    cum[0] = 0;
    for (int k = 0; k < kArcTable; k++)
      cum[k + 1] = cum[k] + arc_length(c, double(k) / kArcTable, double(k + 1) / kArcTable);
  }
  MPVG_HD double total() const { return cum[kArcTable]; }

  // The parameter t with arc_length(c, 0, t) = s, for s in [0, total()]:
  // Newton's method on the tabulated interval, safeguarded by bisection.
  MPVG_HD double param_at(double s) const {
    if (s <= 0) return 0;
    if (s >= total()) return 1;
    int k = 0;
    while (k < kArcTable - 1 && cum[k + 1] <= s) k++;
    double lo = double(k) / kArcTable, hi = double(k + 1) / kArcTable;
    const double base = cum[k], span = cum[k + 1] - base;
    const double t_lo = lo;
    double t = span > 0 ? lo + (hi - lo) * (s - base) / span : lo;
    const double tol = 1e-12 * dmax(total(), 1e-300);
    for (int it = 0; it < 100; it++) {
      const double f = base + arc_length(c, t_lo, t) - s;
      if (fabs(f) <= tol) break;
      if (f < 0)
        lo = t;
      else
        hi = t;
      const double speed = length(c.derivative(t));
      double next = speed > 0 ? t - f / speed : -1;
      if (!(next > lo && next < hi)) next = (lo + hi) / 2;
      if (hi - lo <= 1e-16) break;
      t = next;
    }
    return t;
  }
};

}  // namespace mpvg::stroking
