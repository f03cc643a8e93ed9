// Textures evaluated per sample: the sample's position in texel space, the
// wrap mode, and the lookup (nearest, bilinear, or bicubic with the
// Mitchell-Netravali B = C = 1/3 kernel, as tiny-skia and most image
// viewers use), or under minification a bilinear lookup in the two mip
// levels the encoder chose from the paint's constant footprint, mixed
// (trilinear with a constant level of detail). Shared by both executors: no
// hardware filtering, whose 8-bit weights would let the GPU drift from the
// CPU.
//
// Texels are premultiplied, so filtering never bleeds the colour of
// transparent texels; bicubic overshoot is clamped back to a valid
// premultiplied colour.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/hd.h"
#include "core/paint/paint.h"

namespace mpvg {

// Texel index i of a level n texels wide under a wrap mode; -1 outside a
// decal texture.
MPVG_HD_INLINE int texture_wrap(int i, int n, uint32_t mode) {
  if (mode == WRAP_REPEAT) {
    const int m = i % n;
    return m < 0 ? m + n : m;
  }
  if (mode == WRAP_DECAL) return (i < 0 || i >= n) ? -1 : i;
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// floor(x) as an int, for texel coordinates far outside the image too.
MPVG_HD_INLINE int texture_floor(float x) {
  const float f = floorf(x);
  return f < -1073741824.0f ? -1073741824 : (f > 1073741824.0f ? 1073741824 : static_cast<int>(f));
}

MPVG_HD_INLINE Rgba4 texel_fetch(const Texel16* texels, const TextureLevel& lv, int x, int y, uint32_t flags) {
  const int ix = texture_wrap(x, static_cast<int>(lv.width), (flags >> TEXTURE_WRAP_X_SHIFT) & TEXTURE_WRAP_MASK);
  const int iy = texture_wrap(y, static_cast<int>(lv.height), (flags >> TEXTURE_WRAP_Y_SHIFT) & TEXTURE_WRAP_MASK);
  if (ix < 0 || iy < 0) return Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  const Texel16 t = texels[lv.offset + static_cast<uint32_t>(iy) * lv.width + static_cast<uint32_t>(ix)];
  const float k = 1.0f / 65535.0f;
  return Rgba4{t.r * k, t.g * k, t.b * k, t.a * k};
}

MPVG_HD_INLINE void rgba_add_scaled(Rgba4& acc, float w, const Rgba4& c) {
  acc.r += w * c.r;
  acc.g += w * c.g;
  acc.b += w * c.b;
  acc.a += w * c.a;
}

// Lookups at (u, v) in the texel space of level lv (texel centres at
// integer + 1/2).
MPVG_HD_INLINE Rgba4 texture_nearest(const Texel16* tx, const TextureLevel& lv, float u, float v, uint32_t flags) {
  return texel_fetch(tx, lv, texture_floor(u), texture_floor(v), flags);
}

MPVG_HD_INLINE Rgba4 texture_bilinear(const Texel16* tx, const TextureLevel& lv, float u, float v, uint32_t flags) {
  const float fu = u - 0.5f, fv = v - 0.5f;
  const int x = texture_floor(fu), y = texture_floor(fv);
  const float s = fu - floorf(fu), t = fv - floorf(fv);
  Rgba4 acc{0.0f, 0.0f, 0.0f, 0.0f};
  rgba_add_scaled(acc, (1.0f - s) * (1.0f - t), texel_fetch(tx, lv, x, y, flags));
  rgba_add_scaled(acc, s * (1.0f - t), texel_fetch(tx, lv, x + 1, y, flags));
  rgba_add_scaled(acc, (1.0f - s) * t, texel_fetch(tx, lv, x, y + 1, flags));
  rgba_add_scaled(acc, s * t, texel_fetch(tx, lv, x + 1, y + 1, flags));
  return acc;
}

// Weights of the four taps at offsets -1, 0, 1, 2 from the texel left of
// the sample, s in [0, 1): the Mitchell-Netravali cubic (B = C = 1/3); they
// sum to 1.
MPVG_HD_INLINE void mitchell_weights(float s, float w[4]) {
  // k(x) = (7|x|^3 - 12|x|^2 + 16/3) / 6 for |x| < 1,
  //        (-7/3 |x|^3 + 12|x|^2 - 20|x| + 32/3) / 6 for 1 <= |x| < 2.
  auto near = [](float x) { return ((7.0f * x - 12.0f) * x * x + 16.0f / 3.0f) / 6.0f; };
  auto far = [](float x) { return (((-7.0f / 3.0f) * x + 12.0f) * x - 20.0f) * x / 6.0f + (32.0f / 3.0f) / 6.0f; };
  w[0] = far(1.0f + s);
  w[1] = near(s);
  w[2] = near(1.0f - s);
  w[3] = far(2.0f - s);
}

MPVG_HD_INLINE Rgba4 texture_bicubic(const Texel16* tx, const TextureLevel& lv, float u, float v, uint32_t flags) {
  const float fu = u - 0.5f, fv = v - 0.5f;
  const int x = texture_floor(fu), y = texture_floor(fv);
  float wx[4], wy[4];
  mitchell_weights(fu - floorf(fu), wx);
  mitchell_weights(fv - floorf(fv), wy);
  Rgba4 acc{0.0f, 0.0f, 0.0f, 0.0f};
  for (int j = 0; j < 4; j++) {
    Rgba4 row{0.0f, 0.0f, 0.0f, 0.0f};
    for (int i = 0; i < 4; i++) rgba_add_scaled(row, wx[i], texel_fetch(tx, lv, x - 1 + i, y - 1 + j, flags));
    rgba_add_scaled(acc, wy[j], row);
  }
  // Negative lobes can overshoot: back to 0 <= colour <= alpha <= 1.
  acc.a = fminf(fmaxf(acc.a, 0.0f), 1.0f);
  acc.r = fminf(fmaxf(acc.r, 0.0f), acc.a);
  acc.g = fminf(fmaxf(acc.g, 0.0f), acc.a);
  acc.b = fminf(fmaxf(acc.b, 0.0f), acc.a);
  return acc;
}

// Premultiplied colour of texture t at pixel (px, py).
MPVG_HD_INLINE Rgba4 texture_at(const TextureRecord& t, const TextureLevel* levels, const Texel16* texels, float px,
                                float py) {
  float u, v;
  affine_apply(t.m, px, py, u, v);
  if (t.lod_level == 0 && t.lod_frac == 0.0f) {
    const TextureLevel& lv = levels[t.level0];
    switch (t.flags & TEXTURE_FILTER_MASK) {
      case TEXTURE_NEAREST: return texture_nearest(texels, lv, u, v, t.flags);
      case TEXTURE_BICUBIC: return texture_bicubic(texels, lv, u, v, t.flags);
      default: return texture_bilinear(texels, lv, u, v, t.flags);
    }
  }
  const TextureLevel& l0 = levels[t.level0 + t.lod_level];
  Rgba4 c = texture_bilinear(texels, l0, u * l0.scale, v * l0.scale, t.flags);
  if (t.lod_frac > 0.0f) {
    const TextureLevel& l1 = levels[t.level0 + t.lod_level + 1];
    const Rgba4 d = texture_bilinear(texels, l1, u * l1.scale, v * l1.scale, t.flags);
    const float f = t.lod_frac;
    c = Rgba4{c.r + f * (d.r - c.r), c.g + f * (d.g - c.g), c.b + f * (d.b - c.b), c.a + f * (d.a - c.a)};
  }
  return c;
}

}  // namespace mpvg
