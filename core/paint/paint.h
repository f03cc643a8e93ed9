// Paint records: the flat tables that every executor reads to colour a
// sample (paper abstract and §5.2: paths painted "with semi-transparent
// colors, gradients, or textures", each paint evaluated at the sample).
//
// The encoder (frame/encoding.cpp) turns a Scene's paints into these records
// in the colour space integration works in; gradient.h, texture.h and
// sampling.h evaluate them as host/device code. Everything here crosses the
// host/device boundary; records refer to each other by index.
//
//   PaintRecord ──kind──> GradientRecord ──first,count──> ramp_t[], ramp_color[]
//               │──────> TextureRecord ──level0,levels──> TextureLevel[] ──offset──> texels[]
//               │──────> PatternRecord ──tree──> TreeView[] (a tile's own shortcut tree)
//               └──────> MeshRecord ──cells──> mesh_cells[] ──> mesh_items[] ──> MeshTriangle[]
#pragma once
#include <cstdint>

#include "core/geometry/abstract_segment.h"
#include "core/hd.h"
#include "core/tree/shortcut_tree.h"

namespace mpvg {

// Pattern tiles nest at most this deep (a tile whose content is painted
// with a pattern whose tile ... ): the sampler's recursion is unrolled to
// this depth at compile time.
constexpr int kMaxPatternDepth = 4;

struct Rgba4 {
  float r, g, b, a;
};

// x' = a x + c y + e, y' = b x + d y + f (SVG's matrix order), in floats:
// pixel space to a paint's space, computed in double on the host.
struct Affine2f {
  float a, b, c, d, e, f;
};

MPVG_HD_INLINE void affine_apply(const Affine2f& m, float x, float y, float& u, float& v) {
  u = m.a * x + m.c * y + m.e;
  v = m.b * x + m.d * y + m.f;
}

enum PaintKind : uint32_t {
  PAINT_SOLID = 0,
  PAINT_LINEAR = 1,
  PAINT_RADIAL = 2,
  PAINT_TEXTURE = 3,
  PAINT_PATTERN = 4,
  PAINT_MESH = 5,
  PAINT_SWEEP = 6,  // a sweep (conic) gradient: a GradientRecord
};

// One paint. r, g, b, a are premultiplied: for PAINT_SOLID the colour; for
// the other kinds a factor every component of the paint's colour is
// multiplied by (opacity, and a texture's tint).
struct PaintRecord {
  float r, g, b, a;
  uint32_t kind;
  uint32_t index;  // GradientRecord (linear, radial, sweep), TextureRecord, PatternRecord or MeshRecord
  uint32_t pad0, pad1;
};
static_assert(sizeof(PaintRecord) == 32, "PaintRecord is a 32-byte record shared by CPU and GPU");

// GradientRecord::flags.
enum : uint32_t {
  GRADIENT_SPREAD_MASK = 3u,  // 0 pad, 1 reflect, 2 repeat
  GRADIENT_NO_EXTEND_START = 1u << 2,
  GRADIENT_NO_EXTEND_END = 1u << 3,
  GRADIENT_UNIFORM_KNOTS = 1u << 4,  // knots at t = i / (count - 1): a lookup table
};

// A gradient in a normalised space. Linear: t = m.a x + m.c y + m.e
// directly. Radial: m maps pixels to a space where the start circle is
// centred at the origin and the gradient's extent is about 1; the end
// circle's centre is (cdx, cdy), the radius r0 + t dr, and
// a = cdx^2 + cdy^2 - dr^2 (0 when the circles are tangent internally).
// Sweep: m maps pixels to gradient space translated so that the centre is
// the origin; r0 holds start_angle and dr holds 1 / (end_angle -
// start_angle), both in degrees, so t = (theta - r0) dr with theta the
// point's angle in [0, 360); dr = 0 for equal angles (pad only: t below 0
// for theta < r0, above 1 from r0 on). cdx, cdy and a are unused.
struct GradientRecord {
  Affine2f m;
  float cdx, cdy, r0, dr, a;
  uint32_t first, count;  // the ramp's knots
  uint32_t flags;
};
static_assert(sizeof(GradientRecord) == 56, "GradientRecord is a 56-byte record shared by CPU and GPU");

// TextureRecord::flags: filter in bits 0-1 (TextureFilter order: nearest,
// bilinear, bicubic), wrap x in bits 2-3, wrap y in bits 4-5 (clamp,
// repeat, decal).
enum : uint32_t {
  TEXTURE_FILTER_MASK = 3u,
  TEXTURE_WRAP_X_SHIFT = 2,
  TEXTURE_WRAP_Y_SHIFT = 4,
  TEXTURE_WRAP_MASK = 3u,
};
enum : uint32_t { TEXTURE_NEAREST = 0, TEXTURE_BILINEAR = 1, TEXTURE_BICUBIC = 2 };
enum : uint32_t { WRAP_CLAMP = 0, WRAP_REPEAT = 1, WRAP_DECAL = 2 };

// A texture: m maps pixels to texel space of level 0 (texel (i, j) covers
// [i, i+1) x [j, j+1)). The footprint of a unit area in texel space is the
// same everywhere (m is affine), so the level of detail is chosen once, by
// the encoder: lod_level and lod_frac say which mip levels to mix (levels
// lod_level and lod_level + 1, weights 1 - lod_frac and lod_frac); with
// lod_level = 0 and lod_frac = 0 the texture is magnified or at scale and
// `filter` applies.
struct TextureRecord {
  Affine2f m;
  uint32_t level0;  // first TextureLevel of the image's chain
  uint32_t levels;  // levels in the chain
  uint32_t lod_level;
  float lod_frac;
  uint32_t flags;
  uint32_t pad;
};
static_assert(sizeof(TextureRecord) == 48, "TextureRecord is a 48-byte record shared by CPU and GPU");

// One mip level: width x height texels from texels[offset], row-major.
// Level k samples level 0's texel space scaled by 2^-k.
struct TextureLevel {
  uint32_t offset, width, height;
  float scale;  // 2^-k
};
static_assert(sizeof(TextureLevel) == 16, "TextureLevel is a 16-byte record shared by CPU and GPU");

// Premultiplied RGBA in the integration colour space, 16 bits per channel.
struct Texel16 {
  uint16_t r, g, b, a;
};
static_assert(sizeof(Texel16) == 8, "Texel16 is 8 bytes");

// A pattern: m maps pixels to the tile's grid space, in which the tile is
// [0, W) x [0, H) for the tile tree's grid of W x H unit areas; positions
// wrap with that period.
struct PatternRecord {
  Affine2f m;
  uint32_t tree;  // index into the tile trees
  uint32_t pad;
};
static_assert(sizeof(PatternRecord) == 32, "PatternRecord is a 32-byte record shared by CPU and GPU");

// A mesh of Gouraud-shaded triangles (core/paint/mesh.h), located per sample
// through a uniform grid over its bounding box in pixels: cell (i, j) lists
// the triangles that meet it, down to the top-most one that covers it
// whole (core/paint/mesh_build.h), as mesh_items[mesh_cells[c] .. mesh_cells[c +
// 1]) with c = cells + j * grid_w + i, in ascending order (later triangles
// lie over earlier ones).
struct MeshRecord {
  float x0, y0;  // the grid's corner, pixels
  float sx, sy;  // cells per pixel
  uint16_t grid_w, grid_h;  // at most 1024 each
  uint32_t flags;           // MESH_AREA_BY_TRIANGLES
  uint32_t cells;
  uint32_t ramp;  // GradientRecord whose ramp maps the interpolated t (PDF shadings with a Function), or kNoMeshRamp
};
static_assert(sizeof(MeshRecord) == 32, "MeshRecord is a 32-byte record shared by CPU and GPU");
constexpr uint32_t kNoMeshRamp = 0xffffffffu;
// MeshRecord::flags. The mesh is filled over an area larger than its
// triangles (Mesh::area_by_triangles): a point no triangle contains (beyond
// a rounding slack) is transparent instead of taking the nearest
// triangle's colour.
constexpr uint32_t MESH_AREA_BY_TRIANGLES = 1u << 0;

// One triangle, in pixels: barycentric coordinates (s, t) of a point p are
// (m00 dx + m01 dy, m10 dx + m11 dy) with (dx, dy) = p - a, and its colour
// there is c0 + s d1 + t d2 (straight alpha, the integration colour space;
// with a ramp, t of the ramp in c0.r + s d1.r + t d2.r).
struct MeshTriangle {
  float ax, ay;
  float m00, m01, m10, m11;
  Rgba4 c0, d1, d2;
};
static_assert(sizeof(MeshTriangle) == 72, "MeshTriangle is a 72-byte record shared by CPU and GPU");

// A built shortcut tree as a sampler reads it: the main scene's, or a
// pattern tile's (built over a grid of width x height unit areas).
struct TreeView {
  const Node* nodes;
  const Cell* leaves;
  const Entry* entries;
  const AbstractSegment* segments;
  const PathRecord* paths;
  uint32_t root_size, width, height, pad;
};

struct GroupRecord;  // core/paint/group.h

// Every paint table, and the group table, as pointers into host or device
// memory.
struct PaintTables {
  const PaintRecord* paints;
  const GradientRecord* gradients;
  const float* ramp_t;
  const Rgba4* ramp_color;  // straight alpha
  const TextureRecord* textures;
  const TextureLevel* levels;
  const Texel16* texels;
  const PatternRecord* patterns;
  const TreeView* tiles;
  const GroupRecord* groups;  // transparency groups and masks, the tiles' included
  const MeshRecord* meshes;
  const MeshTriangle* mesh_triangles;
  const uint32_t* mesh_cells;
  const uint32_t* mesh_items;
};

// The paint multiplied by a record's factor.
MPVG_HD_INLINE Rgba4 paint_scale(Rgba4 c, const PaintRecord& p) {
  return Rgba4{c.r * p.r, c.g * p.g, c.b * p.b, c.a * p.a};
}

}  // namespace mpvg
