// Gradients evaluated per sample: t from the sample's position (linear,
// the general two-point conical radial gradient, or the sweep around a
// centre), the spread mode, then the colour ramp. Host/device code shared by both executors; the encoder
// (frame/encoding.cpp) prepares the records.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/hd.h"
#include "core/hd_math.h"
#include "core/paint/paint.h"

namespace mpvg {

// t of a radial gradient at (u, v) of its normalised space (GradientRecord):
// the largest t with |(u, v) - t cd| = r0 + t dr and r0 + t dr >= 0 (the
// circle of largest t through the point wins, as in canvas and PDF type-3
// shadings), restricted to t >= 0 / t <= 1 where the extend flags say so.
// Returns false where no circle reaches the point.
//
// With b = u cdx + v cdy + r0 dr and c = u^2 + v^2 - r0^2 the circles
// through the point solve a t^2 - 2 b t + c = 0. The roots are taken in the
// cancellation-free form q / a and c / q with q = b + sign(b) sqrt(b^2 - a c),
// which also gives the single root c / 2b when a = 0 (one circle tangent
// inside the other, where the quadratic degenerates).
MPVG_HD_INLINE bool radial_t(const GradientRecord& g, float u, float v, float& t) {
  const float b = u * g.cdx + v * g.cdy + g.r0 * g.dr;
  const float c = u * u + v * v - g.r0 * g.r0;
  const float disc = b * b - g.a * c;
  if (disc < 0.0f) return false;
  const float q = b + copysignf(sqrtf(disc), b);
  float t1 = c / q;                                  // finite unless q = 0
  float t2 = g.a != 0.0f ? q / g.a : t1;             // a = 0: one root only
  if (q == 0.0f) t1 = t2 = (g.a != 0.0f ? 0.0f : -INFINITY);  // b = 0 and disc = 0: the double root 0 (c = 0)
  const float hi = fmaxf(t1, t2), lo = fminf(t1, t2);
  const bool no_start = (g.flags & GRADIENT_NO_EXTEND_START) != 0, no_end = (g.flags & GRADIENT_NO_EXTEND_END) != 0;
  auto valid = [&](float s) {
    return s == s && fabsf(s) < INFINITY && g.r0 + s * g.dr >= 0.0f && !(no_start && s < 0.0f) && !(no_end && s > 1.0f);
  };
  if (valid(hi)) {
    t = hi;
    return true;
  }
  if (valid(lo)) {
    t = lo;
    return true;
  }
  return false;
}

// t of a sweep gradient at (u, v), the point relative to its centre
// (GradientRecord): theta = atan2(v, u) in degrees, in [0, 360), and 0 at
// the centre itself (where atan2f(0, -0) would say 180), then
// t = (theta - start) / (end - start). Equal angles (dr = 0, pad only)
// make a step at the start angle: t = -1 before it, 2 from it on, which
// the pad spread turns into the first or the last stop.
MPVG_HD_INLINE float sweep_t(const GradientRecord& g, float u, float v) {
  float theta = (u == 0.0f && v == 0.0f) ? 0.0f : hd_atan2f(v, u) * 57.2957795f;
  if (theta < 0.0f) theta += 360.0f;
  if (g.dr == 0.0f) return theta < g.r0 ? -1.0f : 2.0f;
  return (theta - g.r0) * g.dr;
}

// The spread mode applied to t: pad clamps to [0, 1], repeat keeps the
// fractional part, reflect mirrors every other period. Returns false where
// a pad gradient without extension paints nothing.
MPVG_HD_INLINE bool gradient_spread(uint32_t flags, float& t) {
  switch (flags & GRADIENT_SPREAD_MASK) {
    case 1: {  // reflect
      const float s = fabsf(t);
      const float m = s - 2.0f * floorf(s * 0.5f);  // in [0, 2)
      t = m > 1.0f ? 2.0f - m : m;
      return true;
    }
    case 2:  // repeat
      t = t - floorf(t);
      return true;
    default:
      if (t < 0.0f) {
        if (flags & GRADIENT_NO_EXTEND_START) return false;
        t = 0.0f;
      } else if (t > 1.0f) {
        if (flags & GRADIENT_NO_EXTEND_END) return false;
        t = 1.0f;
      }
      return true;
  }
}

// The ramp's straight colour at t: knots ramp_t[first .. first + count) in
// non-decreasing order, linear between neighbours, constant beyond the ends.
// Equal neighbouring knots make a step: the later one holds from t on.
// Knots are found by binary search, or, for a lookup table
// (GRADIENT_UNIFORM_KNOTS), by index.
MPVG_HD_INLINE Rgba4 ramp_at(const GradientRecord& g, const float* kt, const Rgba4* kc, float t) {
  const uint32_t first = g.first, last = g.first + g.count - 1;
  if (!(t > kt[first])) return kc[first];
  if (t >= kt[last]) return kc[last];
  uint32_t lo, hi;
  if (g.flags & GRADIENT_UNIFORM_KNOTS) {
    const float x = t * float(g.count - 1);
    const uint32_t i = static_cast<uint32_t>(x);
    lo = first + (i < g.count - 2 ? i : g.count - 2);
    hi = lo + 1;
  } else {
    lo = first;  // kt[lo] <= t < kt[hi]
    hi = last;
    while (hi - lo > 1) {
      const uint32_t mid = (lo + hi) >> 1;
      if (kt[mid] <= t)
        lo = mid;
      else
        hi = mid;
    }
  }
  const float span = kt[hi] - kt[lo];
  const float s = span > 0.0f ? (t - kt[lo]) / span : 1.0f;
  const Rgba4 a = kc[lo], b = kc[hi];
  return Rgba4{a.r + s * (b.r - a.r), a.g + s * (b.g - a.g), a.b + s * (b.b - a.b), a.a + s * (b.a - a.a)};
}

// Premultiplied colour of gradient g, of paint kind `kind` (PAINT_LINEAR,
// PAINT_RADIAL or PAINT_SWEEP), at pixel (px, py); transparent where
// nothing is painted. Out of line in kernels: the gradient sampler drops from
// 75 to 62 registers and tiger_gradients renders 4 % faster (BENCHMARKS.md).
MPVG_HD_NOINLINE inline Rgba4 gradient_at(const GradientRecord& g, uint32_t kind, const float* kt, const Rgba4* kc,
                                          float px, float py) {
  float u, v, t;
  affine_apply(g.m, px, py, u, v);
  if (kind == PAINT_RADIAL) {
    if (!radial_t(g, u, v, t)) return Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  } else if (kind == PAINT_SWEEP) {
    t = sweep_t(g, u, v);
  } else {
    t = u;
  }
  if (!gradient_spread(g.flags, t)) return Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  const Rgba4 c = ramp_at(g, kt, kc, t);
  return Rgba4{c.r * c.a, c.g * c.a, c.b * c.a, c.a};
}

}  // namespace mpvg
