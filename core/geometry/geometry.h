// Small geometry types: points and affine transforms in double precision.
// Points and their operators are MPVG_HD: the stroke stage (stroker/stroke.h)
// uses them on both executors; transforms stay on the host.
#pragma once
#include <cmath>

#include "core/hd.h"

namespace mpvg {

struct Vec2 {
  double x = 0, y = 0;
};

MPVG_HD_INLINE Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
MPVG_HD_INLINE Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
MPVG_HD_INLINE Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
MPVG_HD_INLINE bool operator==(Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }
MPVG_HD_INLINE bool operator!=(Vec2 a, Vec2 b) { return !(a == b); }
MPVG_HD_INLINE double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
MPVG_HD_INLINE double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
MPVG_HD_INLINE Vec2 lerp(Vec2 a, Vec2 b, double t) { return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t}; }

// SVG's matrix(a b c d e f): x' = a x + c y + e, y' = b x + d y + f.
struct Affine {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;

  Vec2 apply(Vec2 p) const { return {a * p.x + c * p.y + e, b * p.x + d * p.y + f}; }
  Vec2 apply_linear(Vec2 v) const { return {a * v.x + c * v.y, b * v.x + d * v.y}; }
  double det() const { return a * d - b * c; }
  bool is_identity() const { return a == 1 && b == 0 && c == 0 && d == 1 && e == 0 && f == 0; }
  // Finite coefficients and a finite, non-zero determinant.
  bool invertible() const {
    const double dt = det();
    return std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d) && std::isfinite(e) &&
           std::isfinite(f) && std::isfinite(dt) && dt != 0;
  }
  // The inverse; only meaningful when invertible().
  Affine inverted() const {
    const double dt = det();
    return {d / dt, -b / dt, -c / dt, a / dt, (c * f - d * e) / dt, (b * e - a * f) / dt};
  }

  static Affine translate(double tx, double ty) { return {1, 0, 0, 1, tx, ty}; }
  static Affine scale(double sx, double sy) { return {sx, 0, 0, sy, 0, 0}; }
  static Affine rotate_degrees(double deg) {
    const double r = deg * (M_PI / 180.0);
    const double cs = std::cos(r), sn = std::sin(r);
    return {cs, sn, -sn, cs, 0, 0};
  }
  static Affine skew_x_degrees(double deg) { return {1, 0, std::tan(deg * (M_PI / 180.0)), 1, 0, 0}; }
  static Affine skew_y_degrees(double deg) { return {1, std::tan(deg * (M_PI / 180.0)), 0, 1, 0, 0}; }
};

// (l * r) applies r first, then l: the SVG convention for nested transforms,
// where an element's own transform is applied before its parent's.
inline Affine operator*(const Affine& l, const Affine& r) {
  return {l.a * r.a + l.c * r.b, l.b * r.a + l.d * r.b,
          l.a * r.c + l.c * r.d, l.b * r.c + l.d * r.d,
          l.a * r.e + l.c * r.f + l.e, l.b * r.e + l.d * r.f + l.f};
}

}  // namespace mpvg
