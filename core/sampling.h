// Sampling (paper §5.2): the colour of one sample from the stream of the
// leaf cell that contains it. Front to back: each path's winding number is
// the sum of its entries (subdivision.h states the invariant), its fill rule
// decides inside/outside, and the flat-clipping machine decides what the
// result means. Paints are premultiplied; blending is "under":
//   acc += (1 - acc.a) * paint.
#pragma once
#include <cstdint>
#include <type_traits>

#include "core/abstract_segment.h"
#include "core/flat_clipping.h"
#include "core/gradient.h"
#include "core/hd.h"
#include "core/paint.h"
#include "core/paint_data.h"
#include "core/shortcut_tree.h"
#include "core/texture.h"

namespace mpvg {

// Everything a sampler reads, as flat arrays: one tree's cell streams,
// segments and paths, and the paint tables (shared by the scene and its
// pattern tiles; held by pointer, so that a pattern tile's inputs cost a
// few registers, not a copy of every table pointer).
struct SampleInputs {
  const Entry* entries;
  const AbstractSegment* segments;
  const PathRecord* paths;
  const PaintTables* paint;
};

// The sampling functions are templates on two compile-time parameters:
//   Depth: the depth of pattern nesting they run at (0: the scene itself;
//          a pattern tile is sampled one level deeper);
//   Kinds: which paint kinds the code handles (a PAINTS_* mask); other
//          kinds are treated as solid, so a caller must pass a mask that
//          covers the scene's paints (sampler_kinds).
// Both executors specialise their samplers by the scene's paint kinds
// (with_sampler_kinds): the texture lookups and above all the pattern
// recursion would otherwise raise the register count (and cut the
// occupancy) of every GPU sampler, and slow the CPU's by a third, solid
// colours or not.
enum : uint32_t {
  PAINTS_SOLID = 0,
  PAINTS_GRADIENTS = 1u << 0,
  PAINTS_TEXTURES = 1u << 1,
  PAINTS_PATTERNS = 1u << 2,
  PAINTS_ALL = PAINTS_GRADIENTS | PAINTS_TEXTURES | PAINTS_PATTERNS,
};

// The specialisation a scene's paint tables need: the smallest of those
// compiled (solid; gradients; textures; gradients and textures; all) that
// covers them. Patterns take all kinds, as their tiles may use any.
inline uint32_t sampler_kinds(const PaintData& p) {
  if (!p.patterns.empty()) return PAINTS_ALL;
  uint32_t k = PAINTS_SOLID;
  if (!p.gradients.empty()) k |= PAINTS_GRADIENTS;
  if (!p.textures.empty()) k |= PAINTS_TEXTURES;
  return k;
}

// Calls f(std::integral_constant<uint32_t, K>{}) for the compiled
// specialisation K equal to `kinds` (one of sampler_kinds' results).
template <class F>
decltype(auto) with_sampler_kinds(uint32_t kinds, F&& f) {
  switch (kinds) {
    case PAINTS_SOLID: return f(std::integral_constant<uint32_t, PAINTS_SOLID>{});
    case PAINTS_GRADIENTS: return f(std::integral_constant<uint32_t, PAINTS_GRADIENTS>{});
    case PAINTS_TEXTURES: return f(std::integral_constant<uint32_t, PAINTS_TEXTURES>{});
    case PAINTS_GRADIENTS | PAINTS_TEXTURES:
      return f(std::integral_constant<uint32_t, PAINTS_GRADIENTS | PAINTS_TEXTURES>{});
    default: return f(std::integral_constant<uint32_t, PAINTS_ALL>{});
  }
}

// Winding contribution of one geometry or winding entry to sample (px, py).
// seg is the entry's abstract segment (SEGMENT entries only): the CPU reads
// it from the segment array, a GPU block from its shared-memory copy.
MPVG_HD_INLINE int entry_winding(Entry e, const AbstractSegment* seg, float px, float py) {
  switch (entry_kind(e)) {
    case ENTRY_SEGMENT: return abstract_ray_winding(*seg, px, py);
    case ENTRY_SHORTCUT_UP: return py >= entry_float(e) ? 1 : 0;
    case ENTRY_SHORTCUT_DOWN: return py >= entry_float(e) ? -1 : 0;
    default: return static_cast<int32_t>(e.data);  // ENTRY_WINDING
  }
}

// Does entry e make colours vary inside its cell? Geometry does, and so
// does a path whose paint depends on the position. A cell without such
// entries has one colour everywhere and is evaluated once.
MPVG_HD_INLINE bool entry_varies(Entry e, const PathRecord* paths) {
  if (entry_is_geometry(e)) return true;
  return entry_kind(e) == ENTRY_WINDING && (paths[entry_path(e)].flags & PATH_VARYING) != 0;
}

template <int Depth, uint32_t Kinds>
MPVG_HD_NOINLINE Rgba4 pattern_at(const PaintTables& t, const PatternRecord& p, float px, float py);

// Premultiplied colour of paint `index` at sample (px, py), in the colour
// space of integration.
template <int Depth = 0, uint32_t Kinds = PAINTS_ALL>
MPVG_HD_INLINE Rgba4 paint_at(const PaintTables& t, uint32_t index, float px, float py) {
  const PaintRecord p = t.paints[index];
  if constexpr ((Kinds & PAINTS_GRADIENTS) != 0) {
    if (p.kind == PAINT_LINEAR || p.kind == PAINT_RADIAL)
      return paint_scale(gradient_at(t.gradients[p.index], p.kind == PAINT_RADIAL, t.ramp_t, t.ramp_color, px, py),
                         p);
  }
  if constexpr ((Kinds & PAINTS_TEXTURES) != 0) {
    if (p.kind == PAINT_TEXTURE) return paint_scale(texture_at(t.textures[p.index], t.levels, t.texels, px, py), p);
  }
  if constexpr ((Kinds & PAINTS_PATTERNS) != 0 && Depth < kMaxPatternDepth) {
    if (p.kind == PAINT_PATTERN) return paint_scale(pattern_at<Depth, Kinds>(t, t.patterns[p.index], px, py), p);
  }
  return Rgba4{p.r, p.g, p.b, p.a};
}

// Running state of one sample over a stream: the machine, the path whose
// entries are being summed, and the colour so far. Kept explicit so that a
// GPU block can advance many samples chunk by chunk over one cell.
struct SampleState {
  FlatClip clip;
  int32_t path;  // path being summed, or -1
  int32_t winding;
  Rgba4 color;
  bool done;  // opaque: nothing behind can show
};

MPVG_HD_INLINE SampleState sample_start() {
  SampleState st;
  st.clip = flat_clip_start();
  st.path = -1;
  st.winding = 0;
  st.color = Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  st.done = false;
  return st;
}

// Colour of a sample counts as opaque from here on.
constexpr float kOpaqueAlpha = 1.0f - 1.0f / 65536.0f;

// Closes the path being summed: inside-outside test, then blend (fill) or
// a clip-machine transition (clip test).
template <int Depth = 0, uint32_t Kinds = PAINTS_ALL>
MPVG_HD_INLINE void sample_finish_path(SampleState& st, const SampleInputs& in, float px, float py) {
  if (st.path < 0) return;
  const PathRecord rec = in.paths[st.path];
  st.path = -1;
  if (!path_inside(rec.flags, st.winding)) return;
  if (rec.flags & PATH_CLIP) {
    flat_clip_pass(st.clip);
    return;
  }
  const Rgba4 p = paint_at<Depth, Kinds>(*in.paint, rec.paint, px, py);
  const float t = 1.0f - st.color.a;
  st.color.r += t * p.r;
  st.color.g += t * p.g;
  st.color.b += t * p.b;
  st.color.a += t * p.a;
  if (st.color.a >= kOpaqueAlpha) st.done = true;
}

// The segment a SEGMENT entry refers to, or null for other entries.
MPVG_HD_INLINE const AbstractSegment* entry_segment(Entry e, const AbstractSegment* segments) {
  return entry_kind(e) == ENTRY_SEGMENT ? &segments[e.data] : nullptr;
}

// Advances one sample over one entry; seg as in entry_winding.
template <int Depth = 0, uint32_t Kinds = PAINTS_ALL>
MPVG_HD_INLINE void sample_step(SampleState& st, const SampleInputs& in, Entry e, const AbstractSegment* seg, float px,
                                float py) {
  if (st.done) return;
  if (entry_is_delimiter(e)) {
    sample_finish_path<Depth, Kinds>(st, in, px, py);
    if (st.done) return;
    flat_clip_delimiter(st.clip, entry_kind(e));
    return;
  }
  const int32_t path = static_cast<int32_t>(entry_path(e));
  if (path != st.path) {
    sample_finish_path<Depth, Kinds>(st, in, px, py);
    if (st.done) return;
    if (st.clip.state != FLAT_P) return;  // skipped by the clip machine
    st.path = path;
    st.winding = 0;
  }
  st.winding += entry_winding(e, seg, px, py);
}

// Colour of sample (px, py) from the entries [begin, end) of its leaf cell.
template <int Depth = 0, uint32_t Kinds = PAINTS_ALL>
MPVG_HD_INLINE Rgba4 sample_cell(const SampleInputs& in, uint32_t begin, uint32_t end, float px, float py) {
  SampleState st = sample_start();
  for (uint32_t i = begin; i < end && !st.done; i++) {
    const Entry e = in.entries[i];
    sample_step<Depth, Kinds>(st, in, e, entry_segment(e, in.segments), px, py);
  }
  sample_finish_path<Depth, Kinds>(st, in, px, py);
  return st.color;
}

// Leaf containing pixel (ix, iy): descend from the root by the bits of the
// pixel coordinates (cells are aligned to the pixel grid, §5.3).
MPVG_HD_INLINE uint32_t tree_find_leaf(const Node* nodes, uint32_t root_size, uint32_t ix, uint32_t iy) {
  uint32_t node = 0;
  uint32_t half = root_size >> 1;
  while (nodes[node].child >= 0) {
    const uint32_t q = ((iy & half) ? 2u : 0u) | ((ix & half) ? 1u : 0u);
    node = static_cast<uint32_t>(nodes[node].child) + q;
    half >>= 1;
  }
  return nodes[node].leaf;
}

// A pattern at a sample: the sample's position in the tile's grid, wrapped
// into [0, W) x [0, H), then that position evaluated in the leaf of the
// tile's own tree that holds it (the tile's content clipped to the tile,
// at full precision wherever the sample lands). Tiles nest at most
// kMaxPatternDepth deep (the encoder refuses deeper nesting).
template <int Depth, uint32_t Kinds>
MPVG_HD_NOINLINE Rgba4 pattern_at(const PaintTables& t, const PatternRecord& p, float px, float py) {
  if constexpr (Depth >= kMaxPatternDepth) {
    return Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  } else {
    const TreeView& tv = t.tiles[p.tree];
    float u, v;
    affine_apply(p.m, px, py, u, v);
    const float w = static_cast<float>(tv.width), h = static_cast<float>(tv.height);
    u -= w * floorf(u / w);
    v -= h * floorf(v / h);
    // Rounding can land exactly on the far edge, which is the near one.
    if (!(u < w)) u = 0.0f;
    if (!(v < h)) v = 0.0f;
    const Cell c = tv.leaves[tree_find_leaf(tv.nodes, tv.root_size, static_cast<uint32_t>(u), static_cast<uint32_t>(v))];
    const SampleInputs in{tv.entries, tv.segments, tv.paths, &t};
    return sample_cell<Depth + 1, Kinds>(in, c.begin, c.end, u, v);
  }
}

}  // namespace mpvg
