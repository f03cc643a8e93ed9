// Blend modes of W3C Compositing and Blending Level 1 (§5, §9), per sample,
// on premultiplied colours: the groundwork of transparency groups (issue
// 10), shared by both executors like every per-element decision.
//
// With backdrop Cb (alpha ab) and source Cs (alpha as), both premultiplied,
// source-over with blending is (Compositing §5.8 / §9.1.4):
//   co = (1 - ab) cs + (1 - as) cb + as ab B(Cb / ab, Cs / as)
//   ao = as + ab (1 - as)
// where B works on straight colours in [0, 1]. Normal blending (B = Cs)
// reduces it to plain source-over. The sampler composites front to back
// ("under"), which only normal blending allows; a blended group is
// composited onto its backdrop once its content is known.
//
// After the blend modes come three Porter-Duff operators (Compositing 1
// §9.1; plus-lighter from Compositing 2 §6), whole compositing operators
// rather than B functions, premultiplied:
//   plus-lighter: co = min(1, cs + cb),             ao = min(1, as + ab)
//   source-atop:  co = cs ab + cb (1 - as),         ao = ab
//   xor:          co = cs (1 - ab) + cb (1 - as),   ao = as + ab - 2 as ab
// Each is bounded: a transparent source leaves the backdrop unchanged,
// which is what lets groups treat them like blend modes (core/scene.h).
#pragma once
#include <cmath>
#include <cstdint>

#include "core/hd.h"
#include "core/paint/paint.h"

namespace mpvg {

enum BlendModeCode : uint32_t {  // Scene's BlendMode (core/scene.h), same order
  BLEND_NORMAL = 0,
  BLEND_MULTIPLY,
  BLEND_SCREEN,
  BLEND_OVERLAY,
  BLEND_DARKEN,
  BLEND_LIGHTEN,
  BLEND_COLOR_DODGE,
  BLEND_COLOR_BURN,
  BLEND_HARD_LIGHT,
  BLEND_SOFT_LIGHT,
  BLEND_DIFFERENCE,
  BLEND_EXCLUSION,
  // Non-separable: the three channels together.
  BLEND_HUE,
  BLEND_SATURATION,
  BLEND_COLOR,
  BLEND_LUMINOSITY,
  // Porter-Duff operators: composited as a whole by blend_porter_duff.
  BLEND_PLUS_LIGHTER,
  BLEND_SOURCE_ATOP,
  BLEND_XOR,
  BLEND_MODE_COUNT
};

// Per-channel rules of ink scenes (core/scene.h ChannelRule), two bits a
// channel, r in the lowest: blend with the mode, take the source, keep the
// backdrop. BLEND_SUBTRACTIVE: the channels are ink amounts, complemented
// before and after the blend function (PDF 32000-1 §11.3.4); the
// non-separable modes then work on the complements of three inks as RGB.
enum : uint32_t { CHANNEL_BLEND = 0, CHANNEL_SOURCE = 1, CHANNEL_BACKDROP = 2 };
constexpr uint32_t BLEND_SUBTRACTIVE = 1u << 6;

MPVG_HD_INLINE uint32_t blend_channel_rule(uint32_t channels, int k) { return (channels >> (2 * k)) & 3u; }
MPVG_HD_INLINE bool blend_keeps_a_channel(uint32_t channels) {
  return blend_channel_rule(channels, 0) == CHANNEL_BACKDROP || blend_channel_rule(channels, 1) == CHANNEL_BACKDROP ||
         blend_channel_rule(channels, 2) == CHANNEL_BACKDROP;
}

MPVG_HD_INLINE bool blend_separable(uint32_t mode) { return mode < BLEND_HUE; }
MPVG_HD_INLINE bool blend_is_porter_duff(uint32_t mode) { return mode >= BLEND_PLUS_LIGHTER && mode < BLEND_MODE_COUNT; }

MPVG_HD_INLINE float blend_min(float a, float b) { return a < b ? a : b; }
MPVG_HD_INLINE float blend_max(float a, float b) { return a > b ? a : b; }

// Hard light: multiply by 2 cs below one half, screen with 2 cs - 1 above.
MPVG_HD_INLINE float blend_hard_light(float cb, float cs) {
  return cs <= 0.5f ? cb * 2.0f * cs : 1.0f - (1.0f - cb) * (1.0f - (2.0f * cs - 1.0f));
}

// B(cb, cs) of a separable mode, straight channel values in [0, 1].
MPVG_HD_INLINE float blend_channel(uint32_t mode, float cb, float cs) {
  switch (mode) {
    case BLEND_MULTIPLY: return cb * cs;
    case BLEND_SCREEN: return cb + cs - cb * cs;
    case BLEND_OVERLAY: return blend_hard_light(cs, cb);  // the layers swapped
    case BLEND_DARKEN: return blend_min(cb, cs);
    case BLEND_LIGHTEN: return blend_max(cb, cs);
    case BLEND_COLOR_DODGE:
      if (cb <= 0.0f) return 0.0f;
      if (cs >= 1.0f) return 1.0f;
      return blend_min(1.0f, cb / (1.0f - cs));
    case BLEND_COLOR_BURN:
      if (cb >= 1.0f) return 1.0f;
      if (cs <= 0.0f) return 0.0f;
      return 1.0f - blend_min(1.0f, (1.0f - cb) / cs);
    case BLEND_HARD_LIGHT: return blend_hard_light(cb, cs);
    case BLEND_SOFT_LIGHT: {
      if (cs <= 0.5f) return cb - (1.0f - 2.0f * cs) * cb * (1.0f - cb);
      const float d = cb <= 0.25f ? ((16.0f * cb - 12.0f) * cb + 4.0f) * cb : sqrtf(cb);
      return cb + (2.0f * cs - 1.0f) * (d - cb);
    }
    case BLEND_DIFFERENCE: return cb > cs ? cb - cs : cs - cb;
    case BLEND_EXCLUSION: return cb + cs - 2.0f * cb * cs;
    default: return cs;  // normal
  }
}

// The non-separable helpers of §9.2, on straight RGB.
struct Rgb3 {
  float r, g, b;
};

MPVG_HD_INLINE float blend_lum(Rgb3 c) { return 0.3f * c.r + 0.59f * c.g + 0.11f * c.b; }

MPVG_HD_INLINE Rgb3 blend_clip_color(Rgb3 c) {
  const float l = blend_lum(c);
  const float n = blend_min(c.r, blend_min(c.g, c.b));
  const float x = blend_max(c.r, blend_max(c.g, c.b));
  if (n < 0.0f) {
    const float s = l - n > 0.0f ? l / (l - n) : 0.0f;
    c = Rgb3{l + (c.r - l) * s, l + (c.g - l) * s, l + (c.b - l) * s};
  }
  if (x > 1.0f) {
    const float s = x - l > 0.0f ? (1.0f - l) / (x - l) : 0.0f;
    c = Rgb3{l + (c.r - l) * s, l + (c.g - l) * s, l + (c.b - l) * s};
  }
  return c;
}

MPVG_HD_INLINE Rgb3 blend_set_lum(Rgb3 c, float l) {
  const float d = l - blend_lum(c);
  return blend_clip_color(Rgb3{c.r + d, c.g + d, c.b + d});
}

MPVG_HD_INLINE float blend_sat(Rgb3 c) {
  return blend_max(c.r, blend_max(c.g, c.b)) - blend_min(c.r, blend_min(c.g, c.b));
}

// The spec's SetSat: the largest channel becomes s, the smallest 0, the
// middle one keeps its relative place; a grey stays black.
MPVG_HD_INLINE Rgb3 blend_set_sat(Rgb3 c, float s) {
  float* ch[3] = {&c.r, &c.g, &c.b};
  // Sort the three pointers by value: max, mid, min.
  int hi = 0, lo = 0;
  for (int i = 1; i < 3; i++) {
    if (*ch[i] > *ch[hi]) hi = i;
    if (*ch[i] < *ch[lo]) lo = i;
  }
  if (hi == lo) return Rgb3{0.0f, 0.0f, 0.0f};
  const int mid = 3 - hi - lo;
  const float range = *ch[hi] - *ch[lo];
  *ch[mid] = range > 0.0f ? (*ch[mid] - *ch[lo]) * s / range : 0.0f;
  *ch[hi] = s;
  *ch[lo] = 0.0f;
  return c;
}

// B(Cb, Cs) of a non-separable mode, straight colours.
MPVG_HD_INLINE Rgb3 blend_nonseparable(uint32_t mode, Rgb3 cb, Rgb3 cs) {
  switch (mode) {
    case BLEND_HUE: return blend_set_lum(blend_set_sat(cs, blend_sat(cb)), blend_lum(cb));
    case BLEND_SATURATION: return blend_set_lum(blend_set_sat(cb, blend_sat(cs)), blend_lum(cb));
    case BLEND_COLOR: return blend_set_lum(cs, blend_lum(cb));
    case BLEND_LUMINOSITY: return blend_set_lum(cb, blend_lum(cs));
    default: return cs;
  }
}

// Source `s` onto backdrop `b` with Porter-Duff operator `mode` (one of
// plus-lighter, source-atop, xor; see the top of this file), premultiplied.
MPVG_HD_INLINE Rgba4 blend_porter_duff(uint32_t mode, Rgba4 b, Rgba4 s) {
  const float as = s.a, ab = b.a;
  if (mode == BLEND_PLUS_LIGHTER) {
    return Rgba4{blend_min(1.0f, s.r + b.r), blend_min(1.0f, s.g + b.g), blend_min(1.0f, s.b + b.b),
                 blend_min(1.0f, as + ab)};
  }
  const float fs = mode == BLEND_SOURCE_ATOP ? ab : 1.0f - ab;  // the source's factor
  const float fb = 1.0f - as;                                   // the backdrop's
  const float ao = mode == BLEND_SOURCE_ATOP ? ab : as * fs + ab * fb;
  return Rgba4{s.r * fs + b.r * fb, s.g * fs + b.g * fb, s.b * fs + b.b * fb, ao};
}

// Source `s` over backdrop `b` with blend mode `mode`, both premultiplied
// (a Porter-Duff operator instead of source-over for those modes);
// `channels`: ink scenes' per-channel rules and BLEND_SUBTRACTIVE (0: every
// channel blends, additively). A channel kept as the backdrop takes
// B = Cb: where the backdrop is opaque it is left as it was.
MPVG_HD_INLINE Rgba4 blend_over(uint32_t mode, Rgba4 b, Rgba4 s, uint32_t channels = 0) {
  // Before the shortcut below: source-atop over nothing is nothing.
  if (blend_is_porter_duff(mode)) return blend_porter_duff(mode, b, s);
  const float as = s.a, ab = b.a;
  const float ao = as + ab * (1.0f - as);
  if ((mode == BLEND_NORMAL && !blend_keeps_a_channel(channels)) || as <= 0.0f || ab <= 0.0f) {
    // B only matters where both are present.
    return Rgba4{s.r + (1.0f - as) * b.r, s.g + (1.0f - as) * b.g, s.b + (1.0f - as) * b.b, ao};
  }
  auto unit = [](float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); };
  const bool sub = (channels & BLEND_SUBTRACTIVE) != 0;
  auto in = [sub, &unit](float v, float a) { return sub ? 1.0f - unit(v / a) : unit(v / a); };
  const Rgb3 cb{in(b.r, ab), in(b.g, ab), in(b.b, ab)};
  const Rgb3 cs{in(s.r, as), in(s.g, as), in(s.b, as)};
  Rgb3 m;
  if (blend_separable(mode)) {
    m = Rgb3{blend_channel(mode, cb.r, cs.r), blend_channel(mode, cb.g, cs.g), blend_channel(mode, cb.b, cs.b)};
  } else {
    m = blend_nonseparable(mode, cb, cs);
  }
  if (channels) {
    auto rule = [channels, sub](int k, float mv, float bv, float sv) {
      const uint32_t r = blend_channel_rule(channels, k);
      const float v = r == CHANNEL_SOURCE ? sv : r == CHANNEL_BACKDROP ? bv : mv;
      return sub ? 1.0f - v : v;
    };
    m = Rgb3{rule(0, m.r, cb.r, cs.r), rule(1, m.g, cb.g, cs.g), rule(2, m.b, cb.b, cs.b)};
  }
  const float both = as * ab;
  return Rgba4{(1.0f - ab) * s.r + (1.0f - as) * b.r + both * m.r, (1.0f - ab) * s.g + (1.0f - as) * b.g + both * m.g,
               (1.0f - ab) * s.b + (1.0f - as) * b.b + both * m.b, ao};
}

}  // namespace mpvg
