#include "stroker/curve.h"

#include <algorithm>
#include <cmath>

namespace mpvg::stroke {

namespace {

// (1-t) a + t b: exact at t = 0 and t = 1, so that sub-curves reproduce the
// end points of the curve they come from.
inline double mix(double a, double b, double t) { return (1 - t) * a + t * b; }

struct H {  // a homogeneous point (x w, y w, w)
  double x, y, w;
};

// The blossom (polar form) of a polynomial Bezier curve of degree n at
// (u[0], ..., u[n-1]): de Casteljau's algorithm with a different parameter
// at each level. B(t, ..., t) is the point at t; the control points of the
// piece on [t0, t1] are B(t0, ..., t0, t1, ..., t1).
H blossom(const H* p, int n, const double* u) {
  H q[4];
  for (int i = 0; i <= n; i++) q[i] = p[i];
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n - j; i++)
      q[i] = {mix(q[i].x, q[i + 1].x, u[j]), mix(q[i].y, q[i + 1].y, u[j]), mix(q[i].w, q[i + 1].w, u[j])};
  return q[0];
}

// Control points in homogeneous form: weights 1 except the conic's middle one.
int homogeneous(const Curve& c, H* h) {
  const int n = c.degree();
  for (int i = 0; i <= n; i++) h[i] = {c.p[i].x, c.p[i].y, 1};
  if (c.type == SegmentType::RQuad) h[1] = {c.p[1].x * c.w, c.p[1].y * c.w, c.w};
  return n;
}

// 5-point Gauss-Legendre nodes and weights on [-1, 1].
constexpr double kGaussX[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                               0.9061798459386640};
constexpr double kGaussW[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                               0.2369268850561891, 0.2369268850561891};

double gauss(const Curve& c, double a, double b) {
  const double half = (b - a) / 2, mid = (a + b) / 2;
  double s = 0;
  for (int i = 0; i < 5; i++) s += kGaussW[i] * length(c.derivative(mid + half * kGaussX[i]));
  return s * half;
}

// Adaptive quadrature: split until the two halves agree with the whole to
// `tol` (absolute). The speed |c'| has kinks at cusps, where the
// subdivision concentrates.
double adaptive(const Curve& c, double a, double b, double whole, double tol, int depth) {
  const double m = (a + b) / 2;
  const double left = gauss(c, a, m), right = gauss(c, m, b);
  if (depth >= 30 || std::fabs(left + right - whole) <= tol) return left + right;
  return adaptive(c, a, m, left, tol / 2, depth + 1) + adaptive(c, m, b, right, tol / 2, depth + 1);
}

constexpr int kTableIntervals = 16;

}  // namespace

Curve Curve::line(Vec2 a, Vec2 b) {
  Curve c;
  c.type = SegmentType::Line;
  c.p[0] = a;
  c.p[1] = b;
  return c;
}

Vec2 Curve::point(double t) const {
  if (t == 0) return p[0];
  if (t == 1) return end();
  const double s = 1 - t;
  switch (type) {
    case SegmentType::Line: return s * p[0] + t * p[1];
    case SegmentType::Quad: return (s * s) * p[0] + (2 * s * t) * p[1] + (t * t) * p[2];
    case SegmentType::RQuad: {
      const double b0 = s * s, b1 = 2 * s * t * w, b2 = t * t;
      return (1 / (b0 + b1 + b2)) * (b0 * p[0] + b1 * p[1] + b2 * p[2]);
    }
    default: return (s * s * s) * p[0] + (3 * s * s * t) * p[1] + (3 * s * t * t) * p[2] + (t * t * t) * p[3];
  }
}

void Curve::derivatives(double t, Vec2* d1, Vec2* d2) const {
  const double s = 1 - t;
  switch (type) {
    case SegmentType::Line:
      *d1 = p[1] - p[0];
      *d2 = {};
      return;
    case SegmentType::Quad:
      *d1 = 2 * (s * (p[1] - p[0]) + t * (p[2] - p[1]));
      *d2 = 2 * (p[2] - 2 * p[1] + p[0]);
      return;
    case SegmentType::Cubic:
      *d1 = 3 * (s * s * (p[1] - p[0]) + 2 * t * s * (p[2] - p[1]) + t * t * (p[3] - p[2]));
      *d2 = 6 * (s * (p[2] - 2 * p[1] + p[0]) + t * (p[3] - 2 * p[2] + p[1]));
      return;
    default: {
      // Quotient rule on N / D (see the header), with the points taken
      // relative to p[0]: derivatives do not depend on the origin, and this
      // way no cancellation of coordinates spoils them where c' vanishes
      // (a control point on an end point).
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

Vec2 Curve::derivative(double t) const {
  Vec2 d1, d2;
  derivatives(t, &d1, &d2);
  return d1;
}

Curve Curve::sub(double t0, double t1) const {
  if (t0 == 0 && t1 == 1) return *this;
  H h[4];
  const int n = homogeneous(*this, h);
  H q[4];
  for (int k = 0; k <= n; k++) {
    double u[3];
    for (int j = 0; j < n; j++) u[j] = j < n - k ? t0 : t1;
    q[k] = blossom(h, n, u);
  }
  Curve out;
  out.type = type;
  for (int k = 0; k <= n; k++) out.p[k] = {q[k].x / q[k].w, q[k].y / q[k].w};
  if (t0 == 0) out.p[0] = p[0];
  if (t1 == 1) out.p[n] = end();
  if (type == SegmentType::RQuad) {
    // Back to the standard form with unit end weights: w' = w1 / sqrt(w0 w2).
    out.w = q[1].w / std::sqrt(q[0].w * q[2].w);
  }
  return out;
}

Vec2 Curve::start_tangent() const {
  const int n = degree();
  const double eps = 1e-12 * extent();
  for (int i = 1; i <= n; i++)
    if (length(p[i] - p[0]) > eps) return normalized(p[i] - p[0]);
  return {};
}

Vec2 Curve::end_tangent() const {
  const int n = degree();
  const double eps = 1e-12 * extent();
  for (int i = n - 1; i >= 0; i--)
    if (length(p[n] - p[i]) > eps) return normalized(p[n] - p[i]);
  return {};
}

double Curve::extent() const {
  double e = 0;
  for (int i = 1; i <= degree(); i++) e = std::max(e, length(p[i] - p[0]));
  return e;
}

bool Curve::is_point(double eps) const { return extent() <= eps; }

double arc_length(const Curve& c, double t0, double t1) {
  if (t1 <= t0) return 0;
  if (c.type == SegmentType::Line) return (t1 - t0) * length(c.p[1] - c.p[0]);
  const double whole = gauss(c, t0, t1);
  // Relative accuracy against the control polygon, an upper bound of the
  // length that never vanishes unless the curve is a point.
  double poly = 0;
  for (int i = 0; i < c.degree(); i++) poly += length(c.p[i + 1] - c.p[i]);
  return adaptive(c, t0, t1, whole, 1e-11 * poly + 1e-300, 0);
}

ArcLengthTable::ArcLengthTable(const Curve& c) : c_(c) {
  cumulative_.resize(kTableIntervals + 1);
  cumulative_[0] = 0;
  for (int k = 0; k < kTableIntervals; k++)
    cumulative_[k + 1] =
        cumulative_[k] + arc_length(c, double(k) / kTableIntervals, double(k + 1) / kTableIntervals);
}

double ArcLengthTable::param_at(double s) const {
  if (s <= 0) return 0;
  if (s >= total()) return 1;
  const int k = static_cast<int>(std::upper_bound(cumulative_.begin(), cumulative_.end(), s) - cumulative_.begin()) - 1;
  const int kk = std::clamp(k, 0, kTableIntervals - 1);
  double lo = double(kk) / kTableIntervals, hi = double(kk + 1) / kTableIntervals;
  const double base = cumulative_[kk], span = cumulative_[kk + 1] - base;
  const double t_lo = lo;
  double t = span > 0 ? lo + (hi - lo) * (s - base) / span : lo;
  const double tol = 1e-12 * std::max(total(), 1e-300);
  for (int it = 0; it < 100; it++) {
    const double f = base + arc_length(c_, t_lo, t) - s;
    if (std::fabs(f) <= tol) break;
    if (f < 0)
      lo = t;
    else
      hi = t;
    const double speed = length(c_.derivative(t));
    double next = speed > 0 ? t - f / speed : -1;
    if (!(next > lo && next < hi)) next = (lo + hi) / 2;
    if (hi - lo <= 1e-16) break;
    t = next;
  }
  return t;
}

}  // namespace mpvg::stroke
