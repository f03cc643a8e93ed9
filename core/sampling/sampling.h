// Sampling (paper §5.2): the colour of one sample from the stream of the
// leaf cell that contains it. Front to back: each path's winding number is
// the sum of its entries (subdivision.h states the invariant), its fill rule
// decides inside/outside, and the flat-clipping machine decides what the
// result means. Paints are premultiplied; blending is "under":
//   acc += (1 - acc.a) * paint.
// Transparency groups and masks (core/paint/group.h) keep the colours of the
// lists that enclose the sample's position in the stream on a small stack;
// a group's list runs front to back like the top level, or back to front
// (blending "over", with blend modes) where the builder stored it so. A
// list that can change no more (opaque front to back, a mask of 0) is
// skipped to its group's end by the clip machine's fourth state, SG.
#pragma once
#include <cstdint>
#include <type_traits>

#include "core/geometry/abstract_segment.h"
#include "core/paint/blend.h"
#include "core/tree/flat_clipping.h"
#include "core/paint/gradient.h"
#include "core/paint/group.h"
#include "core/hd.h"
#include "core/paint/mesh.h"
#include "core/paint/paint.h"
#include "core/paint/paint_data.h"
#include "core/tree/shortcut_tree.h"
#include "core/paint/texture.h"

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
//   Kinds: which paint kinds the code handles (a PAINTS_* mask), and
//          whether it handles groups (SAMPLE_GROUPS); other kinds are
//          treated as solid, so a caller must pass a mask that covers the
//          scene's paints and groups (sampler_kinds).
// Both executors specialise their samplers by the scene's paint kinds
// (with_sampler_kinds): the texture lookups and above all the pattern
// recursion would otherwise raise the register count (and cut the
// occupancy) of every GPU sampler, and slow the CPU's by a third, solid
// colours or not.
enum : uint32_t {
  PAINTS_SOLID = 0,
  PAINTS_GRADIENTS = 1u << 0,  // gradients (linear, radial, sweep) and meshes
  PAINTS_TEXTURES = 1u << 1,
  PAINTS_PATTERNS = 1u << 2,
  PAINTS_ALL = PAINTS_GRADIENTS | PAINTS_TEXTURES | PAINTS_PATTERNS,
  SAMPLE_GROUPS = 1u << 3,  // transparency groups and masks: the per-sample stack
  SAMPLE_ALL = PAINTS_ALL | SAMPLE_GROUPS,
  // Paths drawn without antialiasing (PATH_ALIASED): compiled only for
  // scenes that have them, with solid paints or with everything.
  SAMPLE_ALIASED = 1u << 4,
};

// The specialisation a scene's tables need: the smallest of those compiled
// (solid; gradients; textures; gradients and textures; all; and with
// groups: solid; gradients and textures; all) that covers them. Patterns
// take all kinds, as their tiles may use any.
//
// Aliased paths (PATH_ALIASED) are drawn without antialiasing where unit
// areas are pixels (odd supports): a path then covers a pixel's samples as
// it covers the pixel's centre, which lies in the samples' own leaf cell.
// Frames planned for scenes with aliased paths always have an odd support
// (RenderOptions::aliased_paths: 3 x 3 unit areas for the hat, 5 x 5 for
// the cubics). Under an even support pixel centres are unit-area corners,
// shared by up to four leaf cells, none of whose entries is valid for all
// the samples that would need that centre: a frame planned without the
// option draws aliased paths antialiased (`aliasing` false).
inline uint32_t sampler_kinds(const PaintData& p, bool aliasing) {
  if (p.aliased && aliasing) {
    // Two aliased specialisations: solid colours only (crisp icons and
    // diagrams), and everything.
    const bool solid = p.groups.empty() && p.patterns.empty() && p.gradients.empty() && p.meshes.empty() &&
                       p.textures.empty();
    return (solid ? PAINTS_SOLID : SAMPLE_ALL) | SAMPLE_ALIASED;
  }
  const uint32_t groups = p.groups.empty() ? 0u : SAMPLE_GROUPS;
  if (!p.patterns.empty()) return PAINTS_ALL | groups;
  uint32_t k = PAINTS_SOLID;
  if (!p.gradients.empty() || !p.meshes.empty()) k |= PAINTS_GRADIENTS;  // meshes are smooth shadings too
  if (!p.textures.empty()) k |= PAINTS_TEXTURES;
  if (groups && k != PAINTS_SOLID) k = PAINTS_GRADIENTS | PAINTS_TEXTURES;
  return k | groups;
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
    case PAINTS_ALL: return f(std::integral_constant<uint32_t, PAINTS_ALL>{});
    case SAMPLE_GROUPS: return f(std::integral_constant<uint32_t, SAMPLE_GROUPS>{});
    case SAMPLE_GROUPS | PAINTS_GRADIENTS | PAINTS_TEXTURES:
      return f(std::integral_constant<uint32_t, SAMPLE_GROUPS | PAINTS_GRADIENTS | PAINTS_TEXTURES>{});
    case PAINTS_SOLID | SAMPLE_ALIASED: return f(std::integral_constant<uint32_t, PAINTS_SOLID | SAMPLE_ALIASED>{});
    case SAMPLE_ALL | SAMPLE_ALIASED: return f(std::integral_constant<uint32_t, SAMPLE_ALL | SAMPLE_ALIASED>{});
    default: return f(std::integral_constant<uint32_t, SAMPLE_ALL>{});
  }
}

// The specialisation for leaves whose colour is the same everywhere: solid
// paints only, groups as the scene has them (no geometry, so nothing to
// alias).
template <uint32_t Kinds>
constexpr uint32_t kUniformKinds = PAINTS_SOLID | (Kinds & SAMPLE_GROUPS);

// Winding contribution of one geometry or winding entry to sample (px, py).
// seg is the entry's abstract segment (SEGMENT entries only): the CPU reads
// it from the segment array, a GPU block from its shared-memory copy.
MPVG_HD_INLINE int32_t winding_entry_value(Entry e) { return static_cast<int32_t>(e.data); }
MPVG_HD_INLINE int shortcut_winding(Entry e, float py) {
  return select_int(py >= entry_float(e), entry_kind(e) == ENTRY_SHORTCUT_UP ? 1 : -1, 0);
}
MPVG_HD_INLINE int entry_winding(Entry e, const AbstractSegment* seg, float px, float py) {
  switch (entry_kind(e)) {
    case ENTRY_SEGMENT: return abstract_ray_winding(*seg, px, py);
    case ENTRY_SHORTCUT_UP:
    case ENTRY_SHORTCUT_DOWN: return shortcut_winding(e, py);
    default: return winding_entry_value(e);  // ENTRY_WINDING
  }
}

// Does entry e make colours vary inside its cell? Geometry does, and so
// does a path whose paint depends on the position. A cell without such
// entries has one colour everywhere and is evaluated once.
MPVG_HD_INLINE bool entry_varies(Entry e, const PathRecord* paths) {
  if (entry_is_geometry(e)) return true;
  return entry_kind(e) == ENTRY_WINDING && (paths[entry_path(e)].flags & PATH_VARYING) != 0;
}

// Adaptive sampling: is unit area (ux, uy) of a leaf flat, one colour at
// every sample? It is when no segment of the leaf's stream touches the unit
// area's closed square and no path of the stream has a position-dependent
// paint. The stream gives each sample of the leaf its path's true winding
// number, which changes only across the path's segments, and every segment
// that crosses the unit area is in the stream of the leaf holding it; a
// monotonic segment lies in its endpoints' box. Shortcuts and winding entries
// stand for geometry outside the leaf. A flat unit area needs one sample:
// both executors take its class's first, and send its colour times the
// weights' sums (integration.h), as for a uniform leaf.
//
// unit_area_spoils_flat: does entry e (seg: its segment, SEGMENT entries
// only) keep unit area (ux, uy) from being flat? Callers loop over the
// leaf's entries (the CPU from the tree, a GPU block from its shared copy).
MPVG_HD_INLINE bool unit_area_spoils_flat(Entry e, const AbstractSegment* seg, const PathRecord* paths, uint32_t ux,
                                          uint32_t uy) {
  const uint32_t kind = entry_kind(e);
  if (kind > ENTRY_WINDING) return false;  // delimiters and groups
  if ((paths[entry_path(e)].flags & PATH_VARYING) != 0) return true;
  if (kind != ENTRY_SEGMENT) return false;
  const float x0 = static_cast<float>(ux), y0 = static_cast<float>(uy);
  return fmaxf(seg->x0, seg->x1) >= x0 && fminf(seg->x0, seg->x1) <= x0 + 1.0f && fmaxf(seg->y0, seg->y1) >= y0 &&
         fminf(seg->y0, seg->y1) <= y0 + 1.0f;
}

template <int Depth, uint32_t Kinds>
MPVG_HD_NOINLINE Rgba4 pattern_at(const PaintTables& t, const PatternRecord& p, float px, float py);

// Premultiplied colour of paint `index` at sample (px, py), in the colour
// space of integration.
template <int Depth = 0, uint32_t Kinds = SAMPLE_ALL>
MPVG_HD_INLINE Rgba4 paint_at(const PaintTables& t, uint32_t index, float px, float py) {
  const PaintRecord p = t.paints[index];
  if constexpr ((Kinds & PAINTS_GRADIENTS) != 0) {
    if (p.kind == PAINT_LINEAR || p.kind == PAINT_RADIAL || p.kind == PAINT_SWEEP)
      return paint_scale(gradient_at(t.gradients[p.index], p.kind, t.ramp_t, t.ramp_color, px, py), p);
    if (p.kind == PAINT_MESH) return paint_scale(mesh_at(t.meshes[p.index], t, px, py), p);
  }
  if constexpr ((Kinds & PAINTS_TEXTURES) != 0) {
    if (p.kind == PAINT_TEXTURE) return paint_scale(texture_at(t.textures[p.index], t.levels, t.texels, px, py), p);
  }
  if constexpr ((Kinds & PAINTS_PATTERNS) != 0 && Depth < kMaxPatternDepth) {
    if (p.kind == PAINT_PATTERN) return paint_scale(pattern_at<Depth, Kinds>(t, t.patterns[p.index], px, py), p);
  }
  return Rgba4{p.r, p.g, p.b, p.a};
}

// One open group on a sample's stack.
struct GroupFrame {
  Rgba4 saved;      // the enclosing list's colour when the group began
  float mask;       // product of the group's mask values so far
  float alpha_g;    // the enclosing list's group alpha
  int32_t d;        // the clip machine's depth inside the group
  uint32_t group;   // record index << 1 | the enclosing list's covered bit
};

// The stack of a sampler that handles groups; nothing otherwise.
template <bool On>
struct GroupStack {
  int32_t depth;  // open groups
  float alpha_g;  // union of the alphas composited into the innermost list
  bool covered;   // something in the innermost list covers the sample
  GroupFrame frames[kMaxGroupDepth];
};
template <>
struct GroupStack<false> {};

// Running state of one sample over a stream: the machine, the path whose
// entries are being summed, the colour so far (of the innermost open
// group's list), and the enclosing lists'. Kept explicit so that a GPU
// block can advance many samples chunk by chunk over one cell.
template <uint32_t Kinds>
struct SampleState {
  FlatClip clip;
  int32_t path;  // path being summed, or -1
  int32_t winding;
  Rgba4 color;
  bool done;  // nothing further in the stream can change the colour
  bool centre;  // the path being summed is aliased (SAMPLE_ALIASED only)
  GroupStack<(Kinds & SAMPLE_GROUPS) != 0> groups;
};

template <uint32_t Kinds>
MPVG_HD_INLINE SampleState<Kinds> sample_start() {
  SampleState<Kinds> st;
  st.clip = flat_clip_start();
  st.path = -1;
  st.winding = 0;
  st.color = Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  st.done = false;
  st.centre = false;
  if constexpr ((Kinds & SAMPLE_GROUPS) != 0) {
    st.groups.depth = 0;
    st.groups.alpha_g = 0.0f;
    st.groups.covered = false;
  }
  return st;
}

// Colour of a sample counts as opaque from here on.
constexpr float kOpaqueAlpha = 1.0f - 1.0f / 65536.0f;

// Nothing more in the innermost list can change its colour: skip to its
// group's end (state SG), or, at the top level, stop.
template <uint32_t Kinds>
MPVG_HD_INLINE void sample_close_list(SampleState<Kinds>& st) {
  if constexpr ((Kinds & SAMPLE_GROUPS) != 0) {
    if (st.groups.depth > 0) {
      st.clip.state = FLAT_SG;
      st.clip.s = st.groups.frames[st.groups.depth - 1].d;
      return;
    }
  }
  st.done = true;
}

// The backdrop of the open group in frame k: the enclosing list's colour,
// or, in a knockout list, that list's initial backdrop (transparent unless
// the knockout group is non-isolated itself).
template <uint32_t Kinds>
MPVG_HD_INLINE Rgba4 group_backdrop(const SampleState<Kinds>& st, const GroupRecord* groups, int32_t k) {
  const Rgba4 none{0.0f, 0.0f, 0.0f, 0.0f};
  if constexpr ((Kinds & SAMPLE_GROUPS) != 0) {
    for (; k >= 0; k--) {
      if (!(groups[st.groups.frames[k].group >> 1].flags & GROUP_IN_KNOCKOUT)) return st.groups.frames[k].saved;
      if (k == 0 || !(groups[st.groups.frames[k - 1].group >> 1].flags & GROUP_BACKDROP)) return none;
    }
  }
  return none;
}

// Composites an element's colour p (premultiplied) into the innermost list:
// under it front to back, over it with `blend` back to front; in a
// knockout list p replaces what the list holds, composited onto the list's
// initial backdrop. `channels`: a group's per-channel rules (ink scenes).
template <uint32_t Kinds>
MPVG_HD_INLINE void sample_composite(SampleState<Kinds>& st, const GroupRecord* groups, Rgba4 p, bool back,
                                     bool knockout, uint32_t blend, uint32_t channels = 0) {
  if constexpr ((Kinds & SAMPLE_GROUPS) != 0) {
    st.groups.covered = true;
    if (knockout) {
      if (!back) {
        st.color = p;
        sample_close_list(st);
        return;
      }
      const int32_t k = st.groups.depth - 1;
      const bool from_backdrop = (groups[st.groups.frames[k].group >> 1].flags & GROUP_BACKDROP) != 0;
      st.color = blend_over(blend, from_backdrop ? group_backdrop(st, groups, k) : Rgba4{0.0f, 0.0f, 0.0f, 0.0f}, p,
                            channels);
      st.groups.alpha_g = p.a;
      return;
    }
    if (back) {
      st.color = blend_over(blend, st.color, p, channels);
      st.groups.alpha_g = alpha_union(st.groups.alpha_g, p.a);
      return;
    }
  }
  st.color = rgba_under(st.color, p);
  if (st.color.a >= kOpaqueAlpha) sample_close_list(st);
}

// '{': the enclosing list's colour goes on the stack; the group starts from
// transparency, or from its backdrop if it is non-isolated and blends.
template <uint32_t Kinds>
MPVG_HD_INLINE void sample_group_begin(SampleState<Kinds>& st, const GroupRecord* groups, uint32_t id) {
  if constexpr ((Kinds & SAMPLE_GROUPS) != 0) {
    auto& G = st.groups;
    GroupFrame& f = G.frames[G.depth];
    f.saved = st.color;
    f.mask = 1.0f;
    f.alpha_g = G.alpha_g;
    f.d = st.clip.d;
    f.group = (id << 1) | (G.covered ? 1u : 0u);
    G.depth++;
    st.color = (groups[id].flags & GROUP_BACKDROP) ? group_backdrop(st, groups, G.depth - 1)
                                                    : Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
    G.alpha_g = 0.0f;
    G.covered = false;
  }
}

// '}': the group's result (its backdrop removed if it started from it),
// times its mask, becomes a mask value for the group it masks, or, times
// its opacity, an element of the enclosing list.
template <uint32_t Kinds>
MPVG_HD_INLINE void sample_group_end(SampleState<Kinds>& st, const GroupRecord* groups) {
  if constexpr ((Kinds & SAMPLE_GROUPS) != 0) {
    auto& G = st.groups;
    const GroupFrame f = G.frames[G.depth - 1];
    const GroupRecord& r = groups[f.group >> 1];
    Rgba4 res = st.color;
    if (r.flags & GROUP_BACKDROP) res = group_remove_backdrop(res, group_backdrop(st, groups, G.depth - 1), G.alpha_g);
    const bool covered = G.covered;
    G.depth--;
    st.color = f.saved;
    G.alpha_g = f.alpha_g;
    G.covered = (f.group & 1u) != 0;
    if (r.flags & (GROUP_MASK_LUMINANCE | GROUP_MASK_ALPHA)) {
      const float m = mask_value(r, rgba_scale(res, f.mask)) * r.opacity;
      G.frames[G.depth - 1].mask *= m;
      if (!(m > 0.0f)) sample_close_list(st);  // the masked group shows nothing here
      return;
    }
    if (!covered) return;
    sample_composite(st, groups, rgba_scale(res, r.opacity * f.mask), (r.flags & GROUP_IN_BACK_TO_FRONT) != 0,
                     (r.flags & GROUP_IN_KNOCKOUT) != 0, r.blend, r.channels);
  }
}

// A group delimiter: on the stack where the machine processes, counted in
// the depth where it skips (state SG ends at the end of its group).
template <uint32_t Kinds>
MPVG_HD_INLINE void sample_group_delimiter(SampleState<Kinds>& st, const GroupRecord* groups, Entry e) {
  if (entry_is_group_begin(e)) {
    st.clip.d++;
    if (st.clip.state == FLAT_P) sample_group_begin(st, groups, e.data);
    return;
  }
  if (st.clip.state == FLAT_SG && st.clip.d == st.clip.s) st.clip.state = FLAT_P;
  if (st.clip.state == FLAT_P) sample_group_end(st, groups);
  st.clip.d--;
}

// Closes the path being summed: inside-outside test, then blend (fill) or
// a clip-machine transition (clip test).
template <int Depth = 0, uint32_t Kinds = SAMPLE_ALL>
MPVG_HD_INLINE void sample_finish_path(SampleState<Kinds>& st, const SampleInputs& in, float px, float py) {
  if (st.path < 0) return;
  const PathRecord rec = in.paths[st.path];
  st.path = -1;
  if (!path_inside(rec.flags, st.winding)) return;
  if (rec.flags & PATH_CLIP) {
    flat_clip_pass(st.clip);
    return;
  }
  const Rgba4 p = paint_at<Depth, Kinds>(*in.paint, rec.paint, px, py);
  sample_composite(st, in.paint->groups, p, (rec.flags & PATH_BACK_TO_FRONT) != 0, (rec.flags & PATH_KNOCKOUT) != 0,
                   BLEND_NORMAL);
}

// The segment a SEGMENT entry refers to, or null for other entries.
MPVG_HD_INLINE const AbstractSegment* entry_segment(Entry e, const AbstractSegment* segments) {
  return entry_kind(e) == ENTRY_SEGMENT ? &segments[e.data] : nullptr;
}

// How far an aliased path's test point lies up and left of the pixel
// centre: exact in float for coordinates below 2^14.
constexpr float kCentreNudge = 1.0f / 512.0f;

// An aliased path's winding is that of the centre of the pixel holding
// the sample (the same leaf cell, as cells are whole pixels), nudged up
// and left by kCentreNudge: a centre on an edge then belongs to the shape
// on its top-left side, as in Skia and tiny-skia (a pixel is covered where
// left < centre <= right, top < centre <= bottom).
MPVG_HD_INLINE float aliased_centre(float p) { return floorf(p) + (0.5f - kCentreNudge); }

// Advances one sample over one entry, all but the entry's winding: true
// when entry e belongs to the path the sample is now summing, whose
// winding is then to be added.
template <int Depth = 0, uint32_t Kinds = SAMPLE_ALL>
MPVG_HD_INLINE bool sample_enter(SampleState<Kinds>& st, const SampleInputs& in, Entry e, float px, float py) {
  if (st.done) return false;
  if (entry_is_delimiter(e)) {
    sample_finish_path<Depth, Kinds>(st, in, px, py);
    if (st.done) return false;
    if constexpr ((Kinds & SAMPLE_GROUPS) != 0) {
      if (entry_kind(e) == ENTRY_GROUP) {
        sample_group_delimiter(st, in.paint->groups, e);
        return false;
      }
    }
    flat_clip_delimiter(st.clip, entry_kind(e));
    return false;
  }
  const int32_t path = static_cast<int32_t>(entry_path(e));
  if (path != st.path) {
    sample_finish_path<Depth, Kinds>(st, in, px, py);
    if (st.done) return false;
    if (st.clip.state != FLAT_P) return false;  // skipped by the clip machine
    st.path = path;
    st.winding = 0;
    if constexpr ((Kinds & SAMPLE_ALIASED) != 0) st.centre = (in.paths[path].flags & PATH_ALIASED) != 0;
  }
  return true;
}

// Advances one sample over one entry; seg as in entry_winding.
template <int Depth = 0, uint32_t Kinds = SAMPLE_ALL>
MPVG_HD_INLINE void sample_step(SampleState<Kinds>& st, const SampleInputs& in, Entry e, const AbstractSegment* seg,
                                float px, float py) {
  if (!sample_enter<Depth, Kinds>(st, in, e, px, py)) return;
  if constexpr ((Kinds & SAMPLE_ALIASED) != 0) {
    if (st.centre) {
      st.winding += entry_winding(e, seg, aliased_centre(px), aliased_centre(py));
      return;
    }
  }
  st.winding += entry_winding(e, seg, px, py);
}

// Colour of sample (px, py) from the entries [begin, end) of its leaf cell.
template <int Depth = 0, uint32_t Kinds = SAMPLE_ALL>
MPVG_HD_INLINE Rgba4 sample_cell(const SampleInputs& in, uint32_t begin, uint32_t end, float px, float py) {
  SampleState<Kinds> st = sample_start<Kinds>();
  for (uint32_t i = begin; i < end && !st.done; i++) {
    const Entry e = in.entries[i];
    sample_step<Depth, Kinds>(st, in, e, entry_segment(e, in.segments), px, py);
  }
  sample_finish_path<Depth, Kinds>(st, in, px, py);
  return st.color;
}

// Sample lanes (the CPU's sampler): the samples of one unit area stepped
// together over their leaf's stream, entry by entry, each lane as in
// sample_cell, so that each lane's colour is sample_cell's bit for bit
// (test_sample_lanes checks it on random scenes). Within a path's run (its
// consecutive non-delimiter entries) only the run's first entry can change
// a sample's state beyond its winding number (sample_enter): every entry of
// the run then adds its winding to the samples summing that path, and
// nothing to the others, whose path is then -1 (a sample that is done, or
// skipped by the clip machine, sums no path). So each lane enters the run's
// first entry, and the run's windings go to all lanes at once, one loop
// over the lanes per entry that the compiler vectorises (a line's test is
// selects); a run that no lane sums is skipped whole. Lanes whose path is
// -1 collect windings that nothing reads (a path's first entry sets its
// sum to 0); lanes past the last sample repeat it and are dropped.
constexpr int kSampleLanes = 16;

// Adds entry e's winding at every lane's point (x[k], y[k]) to w[k].
MPVG_HD_INLINE void lanes_add_winding(Entry e, const AbstractSegment* segments, const float* x, const float* y,
                                      int32_t* w) {
  if (entry_kind(e) == ENTRY_SEGMENT) {
    const AbstractSegment s = segments[e.data];
    if (abstract_type(s) == ABSTRACT_LINE) {
      const LineTest line(s);
      for (int k = 0; k < kSampleLanes; k++) w[k] += line.winding(x[k], y[k]);
    } else if (abstract_type(s) == ABSTRACT_QUAD) {
      const CurveTest<ABSTRACT_QUAD> quad(s);
      for (int k = 0; k < kSampleLanes; k++) w[k] += quad.winding(x[k], y[k]);
    } else {
      const CurveTest<ABSTRACT_CUBIC> cubic(s);
      for (int k = 0; k < kSampleLanes; k++) w[k] += cubic.winding(x[k], y[k]);
    }
    return;
  }
  if (entry_kind(e) == ENTRY_WINDING) {
    const int32_t v = winding_entry_value(e);
    for (int k = 0; k < kSampleLanes; k++) w[k] += v;
    return;
  }
  for (int k = 0; k < kSampleLanes; k++) w[k] += shortcut_winding(e, y[k]);
}

// Colours out[k] of the n samples (px[k], py[k]) of one leaf's entries
// [begin, end): sample_cell's for each.
template <int Depth = 0, uint32_t Kinds = SAMPLE_ALL>
MPVG_HD_INLINE void sample_cell_lanes(const SampleInputs& in, uint32_t begin, uint32_t end, const float* px,
                                      const float* py, int n, Rgba4* out) {
  for (int k0 = 0; k0 < n; k0 += kSampleLanes) {
    const int m = n - k0 < kSampleLanes ? n - k0 : kSampleLanes;
    float x[kSampleLanes], y[kSampleLanes], cx[kSampleLanes], cy[kSampleLanes];
    int32_t w[kSampleLanes];
    SampleState<Kinds> st[kSampleLanes];
    for (int k = 0; k < kSampleLanes; k++) {
      const int s = k0 + (k < m ? k : m - 1);
      x[k] = px[s];
      y[k] = py[s];
      cx[k] = aliased_centre(x[k]);
      cy[k] = aliased_centre(y[k]);
      w[k] = 0;
    }
    for (int k = 0; k < m; k++) st[k] = sample_start<Kinds>();
    for (uint32_t i = begin; i < end;) {
      const Entry e = in.entries[i];
      bool live = false;
      for (int k = 0; k < m; k++) {
        sample_enter<Depth, Kinds>(st[k], in, e, x[k], y[k]);
        live |= !st[k].done;
      }
      if (!live) break;
      if (entry_is_delimiter(e)) {
        i++;
        continue;
      }
      uint32_t j = i + 1;
      while (j < end && entry_same_path(e, in.entries[j])) j++;
      const int32_t path = static_cast<int32_t>(entry_path(e));
      bool summing = false;
      for (int k = 0; k < m; k++) summing |= st[k].path == path;
      if (summing) {
        const bool centre = (Kinds & SAMPLE_ALIASED) != 0 && (in.paths[path].flags & PATH_ALIASED) != 0;
        const float* qx = centre ? cx : x;
        const float* qy = centre ? cy : y;
        for (int k = 0; k < m; k++) w[k] = st[k].winding;
        for (; i < j; i++) lanes_add_winding(in.entries[i], in.segments, qx, qy, w);
        for (int k = 0; k < m; k++) st[k].winding = w[k];
      }
      i = j;
    }
    for (int k = 0; k < m; k++) {
      sample_finish_path<Depth, Kinds>(st[k], in, x[k], y[k]);
      out[k0 + k] = st[k].color;
    }
  }
}

// Is unit area (ux, uy) of the leaf with entries [begin, end) flat
// (unit_area_spoils_flat)?
MPVG_HD_INLINE bool unit_area_flat(const SampleInputs& in, uint32_t begin, uint32_t end, uint32_t ux, uint32_t uy) {
  for (uint32_t i = begin; i < end; i++) {
    const Entry e = in.entries[i];
    if (unit_area_spoils_flat(e, entry_segment(e, in.segments), in.paths, ux, uy)) return false;
  }
  return true;
}

// Leaf containing pixel (ix, iy): descend from the root by the bits of the
// pixel coordinates (cells are aligned to the pixel grid, §5.3).
MPVG_HD_INLINE uint32_t tree_find_leaf(const Node* nodes, uint32_t root_size, uint32_t ix, uint32_t iy,
                                        uint32_t root = 0) {
  uint32_t node = root;
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
