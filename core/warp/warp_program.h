// User-defined warps (paper §4.4, §7): the bytecode of a warp expression
// (core/warp/warp_parse.h makes it from the language's text) and the one
// interpreter both executors run. A program maps an output-space sample
// (x, y) of a w x h image to the point of the scene that the sample shows;
// it is a list of stack operations whose last two values are that point's
// X and Y. Every operation's result is a float computed with the IEEE
// operations or core/hd_math.h's functions, so that the CPU and a GPU give
// the same bits (no contraction anywhere: the build turns it off).
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
  float value;
};

// A program's bounds (the parser refuses programs past them): values on
// the stack at once, let-bound names, operations.
constexpr int kWarpStack = 64;
constexpr int kWarpSlots = 64;
constexpr uint32_t kWarpMaxOps = 1u << 16;

// x^y as C's pow: a negative base to an integer power keeps its sign by
// the power's parity, to any other power is NaN (hd_powf otherwise).
MPVG_HD_INLINE float warp_pow(float x, float y) {
  if (x < 0.0f) {
    if (!(y == floorf(y))) return NAN;
    const float r = hd_powf(-x, y);
    return fmodf(y, 2.0f) != 0.0f ? -r : r;
  }
  return hd_powf(x, y);
}

// sqrt(a^2 + b^2) in double, rounded once.
MPVG_HD_INLINE float warp_hypot(float a, float b) {
  const double da = a, db = b;
  return static_cast<float>(sqrt(da * da + db * db));
}

// Runs program ops[0 .. n) for sample (x, y) of a w x h image: the point
// (*ox, *oy). Returns false (and leaves them) if the program does not end
// with exactly two values (the parser never makes such a program).
MPVG_HD_INLINE bool warp_run(const WarpOp* ops, uint32_t n, float x, float y, float w, float h, float* ox,
                             float* oy) {
  float st[kWarpStack];
  float slot[kWarpSlots];
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
      case WARP_ABS: st[sp - 1] = fabsf(st[sp - 1]); break;
      case WARP_FLOOR: st[sp - 1] = floorf(st[sp - 1]); break;
      case WARP_SQRT: st[sp - 1] = sqrtf(st[sp - 1]); break;
      case WARP_EXP: st[sp - 1] = hd_expf(st[sp - 1]); break;
      case WARP_LOG: st[sp - 1] = hd_logf(st[sp - 1]); break;
      case WARP_SIN: st[sp - 1] = hd_sinf(st[sp - 1]); break;
      case WARP_COS: st[sp - 1] = hd_cosf(st[sp - 1]); break;
      case WARP_TAN: st[sp - 1] = hd_tanf(st[sp - 1]); break;
      default: {
        if (op.code >= WARP_CLAMP) {  // ternary
          const float c = st[--sp], b = st[--sp], a = st[sp - 1];
          st[sp - 1] = op.code == WARP_CLAMP ? fminf(fmaxf(a, b), c) : a + (b - a) * c;
          break;
        }
        const float b = st[--sp], a = st[sp - 1];
        float r;
        switch (op.code) {
          case WARP_ADD: r = a + b; break;
          case WARP_SUB: r = a - b; break;
          case WARP_MUL: r = a * b; break;
          case WARP_DIV: r = a / b; break;
          case WARP_POW: r = warp_pow(a, b); break;
          case WARP_ATAN2: r = hd_atan2f(a, b); break;
          case WARP_HYPOT: r = warp_hypot(a, b); break;
          case WARP_MIN: r = fminf(a, b); break;
          default: r = fmaxf(a, b); break;  // WARP_MAX
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
