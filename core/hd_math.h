// Elementary functions that give the same bits on both executors.
//
// CUDA's expf and powf and the C library's differ in the last place now and
// then, so a filter's Gaussian weights, a lighting exponent or an sRGB
// conversion on the GPU could differ from the CPU's and, rarely, change an
// output byte (issue 32: byte-identical outputs across backends). These are
// written out in IEEE operations both sides perform exactly alike (+, -, *,
// / in double, never contracted: the build turns contraction off; frexp,
// ldexp and rint, which are exact): the argument reduced to a power of two
// times a small remainder, the remainder's series summed to below double's
// precision, the result rounded once to float. Accurate to within one unit
// in the last place of float (tests/test_hd_math.cpp holds them to long
// double's functions).
#pragma once
#include <cmath>

#include "core/hd.h"

namespace mpvg {

// 2^t for finite t in double's range.
MPVG_HD_INLINE double hd_exp2_d(double t) {
  if (t < -1100.0) return 0.0;
  if (t > 1100.0) return HUGE_VAL;
  const double k = rint(t);
  const double f = (t - k) * 0.69314718055994530942;  // |f| <= ln 2 / 2
  // e^f: Taylor to degree 13 (the next term is below 2^-56 of the sum).
  double p = 1.0 / 6227020800.0;                      // 1/13!
  p = p * f + 1.0 / 479001600.0;                      // 1/12!
  p = p * f + 1.0 / 39916800.0;
  p = p * f + 1.0 / 3628800.0;
  p = p * f + 1.0 / 362880.0;
  p = p * f + 1.0 / 40320.0;
  p = p * f + 1.0 / 5040.0;
  p = p * f + 1.0 / 720.0;
  p = p * f + 1.0 / 120.0;
  p = p * f + 1.0 / 24.0;
  p = p * f + 1.0 / 6.0;
  p = p * f + 0.5;
  p = p * f + 1.0;
  p = p * f + 1.0;
  return ldexp(p, static_cast<int>(k));
}

// log2(x) for finite x > 0.
MPVG_HD_INLINE double hd_log2_d(double x) {
  int e = 0;
  double m = frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  if (m < 0.70710678118654752440) {
    m *= 2.0;
    e -= 1;
  }
  // ln m = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.1716: the odd series
  // to s^23 (the next term is below 2^-60).
  const double s = (m - 1.0) / (m + 1.0), s2 = s * s;
  double q = 1.0 / 23.0;
  for (int k = 21; k >= 1; k -= 2) q = q * s2 + 1.0 / k;
  return static_cast<double>(e) + 2.0 * s * q * 1.44269504088896340736;
}

// e^x.
MPVG_HD_INLINE float hd_expf(float x) {
  if (x != x) return x;
  return static_cast<float>(hd_exp2_d(static_cast<double>(x) * 1.44269504088896340736));
}

// x^y, as powf for x >= 0 (0^y: 0 for y > 0, 1 for y = 0, +inf for y < 0;
// x^0 = 1); NaN for x < 0 (callers clamp first) or NaN arguments.
MPVG_HD_INLINE float hd_powf(float x, float y) {
  if (x != x || y != y) return x + y;
  if (y == 0.0f || x == 1.0f) return 1.0f;
  if (x < 0.0f) return NAN;
  if (x == 0.0f) return y > 0.0f ? 0.0f : HUGE_VALF;
  if (x == HUGE_VALF) return y > 0.0f ? HUGE_VALF : 0.0f;
  return static_cast<float>(hd_exp2_d(static_cast<double>(y) * hd_log2_d(static_cast<double>(x))));
}

// atan2(y, x) in radians, (-pi, pi], in double, for finite arguments.
MPVG_HD_INLINE double hd_atan2_d(double y, double x) {
  if (x != x || y != y) return x + y;
  const double kPi = 3.14159265358979323846;
  const double ax = fabs(x), ay = fabs(y);
  const bool neg_x = copysign(1.0, x) < 0.0, neg_y = copysign(1.0, y) < 0.0;
  if (ax == 0.0 && ay == 0.0) {  // signed zeros as atan2: +-0 or +-pi
    const double r = neg_x ? kPi : 0.0;
    return neg_y ? -r : r;
  }
  // t = min / max in [0, 1], then t - 1 over t + 1 above tan(pi / 8) so
  // that |u| <= tan(pi / 8) and atan(t) = base + atan(u).
  const bool swap = ay > ax;
  const double t = swap ? ax / ay : ay / ax;
  double base = 0.0, u = t;
  if (t > 0.41421356237309504880) {
    base = kPi / 4;
    u = (t - 1.0) / (t + 1.0);
  }
  // atan(u) = u - u^3/3 + u^5/5 - ...: 24 terms (|u|^49 / 49 < 2^-64).
  const double u2 = u * u;
  double q = -1.0 / 47.0;  // n = 23: (-1)^n / (2n + 1)
  for (int n = 22; n >= 0; n--) q = (n % 2 ? -1.0 : 1.0) / (2 * n + 1) + u2 * q;
  double a = base + u * q;
  if (swap) a = kPi / 2 - a;
  if (neg_x) a = kPi - a;
  return neg_y ? -a : a;
}

// atan2(y, x) in radians, (-pi, pi], as atan2f for finite arguments.
MPVG_HD_INLINE float hd_atan2f(float y, float x) {
  return static_cast<float>(hd_atan2_d(static_cast<double>(y), static_cast<double>(x)));
}

// sin and cos of x (radians, finite) in double: x less the nearest
// multiple k of pi/2 (pi/2 in three parts, the first two products exact
// for |k| < 2^20; beyond, the reduction is only as good as double's, and
// both executors take the same steps), then the series of the remainder r,
// |r| <= pi/4, swapped and signed by k mod 4.
MPVG_HD_INLINE void hd_sincos_d(double x, double* s, double* c) {
  const double k = rint(x * 0.63661977236758134308);  // 2 / pi
  // pi/2 = 1.5707963267341256 + 6.077100506303966e-11 + 2.0222662487959506e-21,
  // the first two of 33 bits.
  const double r = ((x - k * 1.5707963267341256) - k * 6.077100506303966e-11) - k * 2.0222662487959506e-21;
  const double r2 = r * r;
  // sin r = r (1 - r^2/3! + r^4/5! - ...) to r^21, cos r = 1 - r^2/2! +
  // r^4/4! - ... to r^22 (the next terms are below 2^-60 for |r| <= pi/4).
  double ps = -1.0 / 51090942171709440000.0;          // -1/21!
  ps = ps * r2 + 1.0 / 121645100408832000.0;           // 1/19!
  ps = ps * r2 - 1.0 / 355687428096000.0;              // 1/17!
  ps = ps * r2 + 1.0 / 1307674368000.0;                // 1/15!
  ps = ps * r2 - 1.0 / 6227020800.0;                   // 1/13!
  ps = ps * r2 + 1.0 / 39916800.0;                     // 1/11!
  ps = ps * r2 - 1.0 / 362880.0;                       // 1/9!
  ps = ps * r2 + 1.0 / 5040.0;
  ps = ps * r2 - 1.0 / 120.0;
  ps = ps * r2 + 1.0 / 6.0;
  ps = 1.0 - ps * r2;
  double pc = -1.0 / 1124000727777607680000.0;         // -1/22!
  pc = pc * r2 + 1.0 / 2432902008176640000.0;          // 1/20!
  pc = pc * r2 - 1.0 / 6402373705728000.0;             // 1/18!
  pc = pc * r2 + 1.0 / 20922789888000.0;               // 1/16!
  pc = pc * r2 - 1.0 / 87178291200.0;                  // 1/14!
  pc = pc * r2 + 1.0 / 479001600.0;                    // 1/12!
  pc = pc * r2 - 1.0 / 3628800.0;                      // 1/10!
  pc = pc * r2 + 1.0 / 40320.0;
  pc = pc * r2 - 1.0 / 720.0;
  pc = pc * r2 + 1.0 / 24.0;
  pc = pc * r2 - 0.5;
  pc = 1.0 + pc * r2;
  const double sr = r * ps, cr = pc;
  const long long q = static_cast<long long>(k) & 3;
  *s = q == 0 ? sr : q == 1 ? cr : q == 2 ? -sr : -cr;
  *c = q == 0 ? cr : q == 1 ? -sr : q == 2 ? -cr : sr;
}

}  // namespace mpvg
