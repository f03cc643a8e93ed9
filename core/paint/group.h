// Transparency groups and masks per sample (PDF 32000-1 §11.4, W3C
// Compositing and Blending Level 1 §3-§5, CSS Masking 1 §7): what a group
// does to colours, shared by both executors. sampling.h walks the stream
// and calls these at the group delimiters and fills.
//
// A group's content is composited on its own into a colour of its own; at
// its end the result, times its opacity and its mask, goes onto the colour
// of the list the group is in: "under" it when that list runs front to
// back (normal blending only), with the group's blend mode (or Porter-Duff
// operator, core/paint/blend.h) over it when the list runs back to front. A per-sample stack keeps the enclosing lists'
// colours, kMaxGroupDepth deep (checked by SceneBuilder).
//
// Every sample has shape 0 or 1 (a point is inside a path or not), so the
// PDF formulas reduce to:
//   isolated group:     content composited onto transparency;
//   non-isolated group: onto its backdrop B (the enclosing colour), and at
//                       the end the backdrop's contribution is removed:
//                       result = composite - (1 - alpha_g) B, where alpha_g
//                       is the union of the content's alphas (§11.4.8, in
//                       premultiplied form: the result over B is the
//                       composite);
//   knockout group:     the top-most element that covers the sample,
//                       composited onto the group's initial backdrop;
//   mask:               a group whose result becomes a value: the alpha,
//                       or the luminance of the result over its backdrop
//                       colour; it multiplies the group it masks.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/paint/blend.h"
#include "core/hd.h"
#include "core/paint/paint.h"
#include "core/output/srgb.h"

namespace mpvg {

// Transparency groups and masks nest at most this deep in a scene (and in
// each pattern tile): the size of every sample's stack.
constexpr int kMaxGroupDepth = 16;

// GroupRecord::flags.
enum : uint32_t {
  // Non-isolated content that blends: starts from the backdrop, which is
  // removed at the end (the list runs back to front).
  GROUP_BACKDROP = 1u << 0,
  // The list the group is in runs back to front: its result is blended
  // over what lies below it; otherwise it goes under the colour so far
  // (normal blending).
  GROUP_IN_BACK_TO_FRONT = 1u << 1,
  GROUP_IN_KNOCKOUT = 1u << 2,  // the list it is in is a knockout group's
  GROUP_MASK_LUMINANCE = 1u << 3,
  GROUP_MASK_ALPHA = 1u << 4,
  // Luminance in the other colour space than integration's: sRGB-encode
  // (or decode) the straight colour first.
  GROUP_LUMINANCE_ENCODE = 1u << 5,
  GROUP_LUMINANCE_DECODE = 1u << 6,
};

struct GroupRecord {
  float opacity;
  uint32_t flags;
  uint32_t blend;      // BlendModeCode (blend.h): a blend mode or a Porter-Duff operator
  float lum[3];        // luminance masks: weights of r, g, b
  Rgba4 backdrop;      // luminance masks: premultiplied, in integration's space
  uint32_t channels;   // ink scenes: blend_channels() of the group's ChannelRules
  uint32_t pad1;
};
static_assert(sizeof(GroupRecord) == 48, "GroupRecord is a 48-byte record shared by CPU and GPU");

// The group entry's path field (shortcut_tree.h, ENTRY_GROUP): begin or
// end, and what pruning needs to know without the group table.
enum : uint32_t {
  GROUP_ENTRY_END = 1u << 0,
  GROUP_ENTRY_MASK = 1u << 1,         // the group is a mask
  GROUP_ENTRY_EMPTY_HIDES = 1u << 2,  // a mask whose empty content makes it 0
  // Opacity 1, normal blending, not knockout, not a mask, in a list that is
  // not knockout: unmasked, the group is opaque wherever its list holds an
  // opaque element, and hides what lies behind it.
  GROUP_ENTRY_SOLID = 1u << 3,
  GROUP_ENTRY_IN_BACK_TO_FRONT = 1u << 4,  // the list it is in runs back to front
  // Solid, isolated (or not starting from its backdrop), and its list runs
  // in the same order as the one it is in: unmasked, a group of a single
  // element composites exactly as that element alone (rule 23).
  GROUP_ENTRY_DISSOLVES = 1u << 5,
  GROUP_ENTRY_BACKDROP = 1u << 6,  // the group starts from its backdrop (GROUP_BACKDROP)
  GROUP_ENTRY_NORMAL = 1u << 7,    // normal blending
};

// A group's ChannelRules (core/scene.h) for blend_over: two bits a channel
// (CHANNEL_*, core/paint/blend.h), and BLEND_SUBTRACTIVE.
inline uint32_t blend_channels(uint32_t r, uint32_t g, uint32_t b, bool subtractive) {
  return r | g << 2 | b << 4 | (subtractive ? BLEND_SUBTRACTIVE : 0u);
}

// Does a record composite as plain source-over?
MPVG_HD_INLINE bool group_record_normal(const GroupRecord& r) {
  return r.blend == BLEND_NORMAL && !blend_keeps_a_channel(r.channels);
}

MPVG_HD_INLINE Rgba4 rgba_scale(Rgba4 c, float k) { return Rgba4{c.r * k, c.g * k, c.b * k, c.a * k}; }

// p under acc: acc += (1 - acc.a) p (front to back, normal blending).
MPVG_HD_INLINE Rgba4 rgba_under(Rgba4 acc, Rgba4 p) {
  const float t = 1.0f - acc.a;
  return Rgba4{acc.r + t * p.r, acc.g + t * p.g, acc.b + t * p.b, acc.a + t * p.a};
}

// Union of two alphas (the alpha of one over the other); exactly 1 when
// either is, so that an opaque element hides what came before it to the
// last bit (pruning rule 14' relies on it).
MPVG_HD_INLINE float alpha_union(float a, float b) { return 1.0f - (1.0f - a) * (1.0f - b); }

// A non-isolated group's result: its composite less the backdrop's share.
MPVG_HD_INLINE Rgba4 group_remove_backdrop(Rgba4 composite, Rgba4 backdrop, float alpha_g) {
  const float k = 1.0f - alpha_g;
  auto pos = [](float v) { return v > 0.0f ? v : 0.0f; };
  return Rgba4{pos(composite.r - k * backdrop.r), pos(composite.g - k * backdrop.g), pos(composite.b - k * backdrop.b),
               alpha_g};
}

// The value of a mask whose content composited to r (premultiplied),
// before the mask's opacity; in [0, 1].
MPVG_HD_INLINE float mask_value(const GroupRecord& g, Rgba4 r) {
  float v;
  if (g.flags & GROUP_MASK_ALPHA) {
    v = r.a;
  } else {
    const Rgba4 c = rgba_under(r, g.backdrop);
    float cr = c.r, cg = c.g, cb = c.b;
    if ((g.flags & (GROUP_LUMINANCE_ENCODE | GROUP_LUMINANCE_DECODE)) && c.a > 0.0f) {
      const bool enc = (g.flags & GROUP_LUMINANCE_ENCODE) != 0;
      auto conv = [&](float x) {
        const float s = x / c.a;
        return c.a * (enc ? linear_to_srgb(s) : srgb_to_linear(s));
      };
      cr = conv(cr);
      cg = conv(cg);
      cb = conv(cb);
    }
    v = g.lum[0] * cr + g.lum[1] * cg + g.lum[2] * cb;
    // Weights that sum to 1 (SVG's: 0.99999994 in floats) make white 1.
    if (v > 1.0f - 1.0f / 65536.0f) v = 1.0f;
  }
  return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

}  // namespace mpvg
