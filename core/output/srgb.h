// The sRGB transfer function (IEC 61966-2-1), shared by the encoder (paint
// colours, images and the final image) and the samplers (luminance masks
// in the other colour space than integration's), with core/hd_math.h's pow:
// the same bits on both executors.
#pragma once
#include <cmath>

#include "core/hd.h"
#include "core/hd_math.h"

namespace mpvg {

MPVG_HD_INLINE float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : hd_powf((c + 0.055f) / 1.055f, 2.4f); }

MPVG_HD_INLINE float linear_to_srgb(float c) {
  return c <= 0.0031308f ? 12.92f * c : 1.055f * hd_powf(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace mpvg
