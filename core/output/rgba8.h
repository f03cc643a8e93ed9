// The final image as 8-bit codes: straight alpha, sRGB-encoded colour. The
// PNG stage's conversion, written once and run per pixel by both executors
// (to_rgba8 on the CPU, a kernel after rendering on the GPU, so that a
// quarter of the float image crosses the bus).
//
// Colour codes are lround(linear_to_srgb(v) * 255) for an image integrated
// in linear light and lround(v * 255) otherwise, v the unpremultiplied
// channel clamped to [0, 1]; alpha is lround(a * 255). The sRGB codes come
// without a pow per channel: code k starts at the smallest float start[k]
// that gives it (found once on the host by bisection over the floats with
// that very expression, so the codes are exactly the formula's), and a
// lookup starts from the code of v's 1/4096 bucket and steps up or down (at
// most about one code per bucket, where the curve is steepest).
#pragma once
#include <cstdint>

#include "core/hd.h"

namespace mpvg {

struct SrgbCodeTable {
  static constexpr int kBuckets = 4096;
  float start[257];  // start[256] = +infinity
  uint8_t bucket[kBuckets + 1];
};

// The table, built on first use (thread-safe).
const SrgbCodeTable& srgb_code_table();

// lround(x) for x >= 0 (halves away from zero), the same on host and device.
MPVG_HD_INLINE int round_nonnegative(float x) {
  const int r = static_cast<int>(x);
  return x - static_cast<float>(r) >= 0.5f ? r + 1 : r;
}

// The sRGB code of linear v in [0, 1].
MPVG_HD_INLINE uint8_t srgb_code(const SrgbCodeTable& t, float v) {
  int k = t.bucket[static_cast<int>(v * SrgbCodeTable::kBuckets)];  // corrected either way for v * 4096's rounding
  while (t.start[k + 1] <= v) k++;
  while (t.start[k] > v) k--;
  return static_cast<uint8_t>(k);
}

// One premultiplied pixel p (r, g, b, a) to straight 8-bit codes, packed
// r | g << 8 | b << 16 | a << 24 (the bytes r, g, b, a in memory). A
// pixel whose alpha code is 0 is (0, 0, 0, 0), whatever colour the faint
// coverage under it had: equal images are equal bytes (issue 32; colour
// divided by an alpha of 1e-6 is noise that differed between executors).
MPVG_HD_INLINE uint32_t rgba8_pixel(float r, float g, float b, float a, bool linear, const SrgbCodeTable& t) {
  a = a > 0.0f ? a : 0.0f;  // NaN to 0
  a = a < 1.0f ? a : 1.0f;
  const float c[3] = {r, g, b};
  const uint32_t alpha = static_cast<uint32_t>(round_nonnegative(a * 255.0f));
  if (alpha == 0) return 0;
  uint32_t out = alpha << 24;
  for (int i = 0; i < 3; i++) {
    float v = a > 0.0f ? c[i] / a : 0.0f;
    v = v > 0.0f ? v : 0.0f;
    v = v < 1.0f ? v : 1.0f;
    const uint32_t code = linear ? srgb_code(t, v) : static_cast<uint32_t>(round_nonnegative(v * 255.0f));
    out |= code << (8 * i);
  }
  return out;
}

}  // namespace mpvg
