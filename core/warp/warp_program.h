// User-defined warps (paper §4.4, §7): the bytecode of a warp expression
// (core/warp/warp_parse.h makes it from the language's text) and the one
// interpreter both executors run. A program maps an output-space sample
// (x, y) of a w x h image to the point of the scene that the sample shows;
// it is a list of stack operations whose last two values are that point's
// X and Y. Programs run in double: every operation is an IEEE one or one
// of core/hd_math.h's double functions, so that the CPU and a GPU give the
// same bits (no contraction anywhere: the build turns it off), and a
// sample's position goes in and comes out exactly (the executors move it
// between unit-area and output coordinates by a half-integer: exact in
// double, not always in float).
#pragma once
#include <cmath>
#include <cstdint>

#include "core/hd.h"
#include "core/hd_math.h"

namespace mpvg {

enum WarpOpcode : uint32_t {
  WARP_CONST = 0,  // push value
  WARP_X, WARP_Y, WARP_W, WARP_H,  // push the sample's x, y, the image's width, height
  WARP_LOAD,   // push slot[slot]
  WARP_STORE,  // slot[slot] = pop
  WARP_NEG, WARP_ABS, WARP_FLOOR, WARP_SQRT, WARP_EXP, WARP_LOG, WARP_SIN, WARP_COS, WARP_TAN,  // unary
  WARP_ADD, WARP_SUB, WARP_MUL, WARP_DIV, WARP_POW, WARP_ATAN2, WARP_HYPOT, WARP_MIN, WARP_MAX,  // binary
  WARP_CLAMP, WARP_MIX,  // ternary
  WARP_OPCODES
};

// One operation: its code, and a constant (WARP_CONST) or a slot index
// (WARP_LOAD, WARP_STORE).
struct WarpOp {
  uint32_t code;
  uint32_t slot;
  double value;
};

// A program's bounds (the parser refuses programs past them): values on
// the stack at once, let-bound names, operations.
constexpr int kWarpStack = 64;
constexpr int kWarpSlots = 64;
constexpr uint32_t kWarpMaxOps = 1u << 16;

// x^y as C's pow: to an integer power of at most 64 by multiplications
// (exact where the products are: 3^2 is 9), a negative base to any other
// power NaN, 0^y 0 for y > 0 and +inf for y < 0, otherwise 2^(y log2 x).
MPVG_HD_INLINE double warp_pow(double x, double y) {
  if (x != x || y != y) return x + y;
  if (y == floor(y) && fabs(y) <= 64.0) {
    double r = 1.0, b = x;
    for (int n = static_cast<int>(fabs(y)); n > 0; n >>= 1) {
      if (n & 1) r *= b;
      b *= b;
    }
    return y < 0.0 ? 1.0 / r : r;
  }
  if (x < 0.0) {
    if (!(y == floor(y))) return NAN;
    const double r = warp_pow(-x, y);
    return fmod(y, 2.0) != 0.0 ? -r : r;
  }
  if (x == 1.0) return 1.0;
  if (x == 0.0) return y > 0.0 ? 0.0 : HUGE_VAL;
  if (x == HUGE_VAL) return y > 0.0 ? HUGE_VAL : 0.0;
  return hd_exp2_d(y * hd_log2_d(x));
}

MPVG_HD_INLINE double warp_log(double x) {
  if (x != x || x < 0.0) return NAN;
  if (x == 0.0) return -HUGE_VAL;
  if (x == HUGE_VAL) return x;
  return hd_log2_d(x) * 0.69314718055994530942;
}

// sin, cos, tan: NaN for infinite or NaN x.
MPVG_HD_INLINE double warp_trig(uint32_t code, double x) {
  if (!(x - x == 0.0)) return NAN;
  double s, c;
  hd_sincos_d(x, &s, &c);
  return code == WARP_SIN ? s : code == WARP_COS ? c : s / c;
}

// Runs program ops[0 .. n) for sample (x, y) of a w x h image: the point
// (*ox, *oy). Returns false (and leaves them) if the program does not end
// with exactly two values (the parser never makes such a program).
MPVG_HD_INLINE bool warp_run(const WarpOp* ops, uint32_t n, double x, double y, double w, double h, double* ox,
                             double* oy) {
  double st[kWarpStack];
  double slot[kWarpSlots];
  int sp = 0;
  for (uint32_t i = 0; i < n; i++) {
    const WarpOp op = ops[i];
    switch (op.code) {
      case WARP_CONST: st[sp++] = op.value; break;
      case WARP_X: st[sp++] = x; break;
      case WARP_Y: st[sp++] = y; break;
      case WARP_W: st[sp++] = w; break;
      case WARP_H: st[sp++] = h; break;
      case WARP_LOAD: st[sp++] = slot[op.slot]; break;
      case WARP_STORE: slot[op.slot] = st[--sp]; break;
      case WARP_NEG: st[sp - 1] = -st[sp - 1]; break;
      case WARP_ABS: st[sp - 1] = fabs(st[sp - 1]); break;
      case WARP_FLOOR: st[sp - 1] = floor(st[sp - 1]); break;
      case WARP_SQRT: st[sp - 1] = sqrt(st[sp - 1]); break;
      case WARP_EXP: {
        const double v = st[sp - 1];
        st[sp - 1] = v != v ? v : hd_exp2_d(v * 1.44269504088896340736);
        break;
      }
      case WARP_LOG: st[sp - 1] = warp_log(st[sp - 1]); break;
      case WARP_SIN:
      case WARP_COS:
      case WARP_TAN: st[sp - 1] = warp_trig(op.code, st[sp - 1]); break;
      default: {
        if (op.code >= WARP_CLAMP) {  // ternary
          const double c = st[--sp], b = st[--sp], a = st[sp - 1];
          st[sp - 1] = op.code == WARP_CLAMP ? fmin(fmax(a, b), c) : a + (b - a) * c;
          break;
        }
        const double b = st[--sp], a = st[sp - 1];
        double r;
        switch (op.code) {
          case WARP_ADD: r = a + b; break;
          case WARP_SUB: r = a - b; break;
          case WARP_MUL: r = a * b; break;
          case WARP_DIV: r = a / b; break;
          case WARP_POW: r = warp_pow(a, b); break;
          case WARP_ATAN2: r = hd_atan2_d(a, b); break;
          case WARP_HYPOT: r = sqrt(a * a + b * b); break;
          case WARP_MIN: r = fmin(a, b); break;
          default: r = fmax(a, b); break;  // WARP_MAX
        }
        st[sp - 1] = r;
      }
    }
  }
  if (sp != 2) return false;
  *ox = st[0];
  *oy = st[1];
  return true;
}

}  // namespace mpvg
