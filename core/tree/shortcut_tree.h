// The shortcut tree's flat layout (paper §4, §4.2), shared by the CPU and
// CUDA executors. Every structure here crosses the host/device boundary and
// is compared entry for entry between backends in tests.
//
// A cell holds a specialised copy of the scene stream: delimiters '(' '|' ')'
// and, per path, a run of segment entries. A path's run is its abstract
// segments that touch the cell (kept whole), the shortcut segments that stand
// for the parts of its contours outside the cell, and at most one winding
// entry (last in the run) holding the path's initial winding number in the
// cell. A path that leaves no entry in a cell does not cover it.
//
// Entry (8 bytes):
//
//   head  31     29 28                                 0
//        +--------+------------------------------------+
//        |  kind  |             path index              |
//        +--------+------------------------------------+
//   data  SEGMENT: abstract segment index
//         SHORTCUT_UP / SHORTCUT_DOWN: float bits of the shortcut's y
//         WINDING: signed winding increment
//         PUSH / ACTIVATE / POP: 0 (the path field is 0 too)
//         GROUP: the group's record (core/paint/group.h); the path field holds
//                GROUP_ENTRY_* bits: begin or end, mask, ...
//
// Shortcut segments (§4): vertical half-lines to the right of the cell, from
// height y up to +infinity. SHORTCUT_UP adds +1 to the winding of every
// sample whose y >= the shortcut's y, SHORTCUT_DOWN adds -1. Their x is never
// needed: they lie right of every sample of the cell and of its descendants.
#pragma once
#include <cstdint>
#include <cstring>

#include "core/hd.h"

namespace mpvg {

enum EntryKind : uint32_t {
  ENTRY_SEGMENT = 0,
  ENTRY_SHORTCUT_UP = 1,
  ENTRY_SHORTCUT_DOWN = 2,
  ENTRY_WINDING = 3,
  ENTRY_PUSH = 4,
  ENTRY_ACTIVATE = 5,
  ENTRY_POP = 6,
  ENTRY_GROUP = 7,  // a transparency group's or mask's begin or end ('{' '}')
};

constexpr uint32_t kEntryKindShift = 29;
constexpr uint32_t kEntryPathMask = (1u << kEntryKindShift) - 1;
constexpr uint32_t kMaxPaths = kEntryPathMask;

struct Entry {
  uint32_t head;
  uint32_t data;
};
static_assert(sizeof(Entry) == 8, "Entry is an 8-byte record shared by CPU and GPU");

MPVG_HD_INLINE uint32_t entry_kind(Entry e) { return e.head >> kEntryKindShift; }
MPVG_HD_INLINE uint32_t entry_path(Entry e) { return e.head & kEntryPathMask; }
MPVG_HD_INLINE bool entry_is_delimiter(Entry e) { return entry_kind(e) >= ENTRY_PUSH; }
MPVG_HD_INLINE bool entry_is_geometry(Entry e) {
  const uint32_t k = entry_kind(e);
  return k == ENTRY_SEGMENT || k == ENTRY_SHORTCUT_UP || k == ENTRY_SHORTCUT_DOWN;
}
MPVG_HD_INLINE Entry make_entry(uint32_t kind, uint32_t path, uint32_t data) {
  return Entry{(kind << kEntryKindShift) | path, data};
}
MPVG_HD_INLINE float entry_float(Entry e) {
  float f;
  memcpy(&f, &e.data, sizeof f);
  return f;
}
MPVG_HD_INLINE uint32_t float_bits(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  return u;
}
// Group entries: the path field's bits (core/paint/group.h, GROUP_ENTRY_*).
MPVG_HD_INLINE bool entry_is_group_begin(Entry e) { return entry_kind(e) == ENTRY_GROUP && !(e.head & 1u); }
MPVG_HD_INLINE bool entry_is_group_end(Entry e) { return entry_kind(e) == ENTRY_GROUP && (e.head & 1u); }
// Does the entry open ('(' or '{') or close (')' or '}') a nesting level?
MPVG_HD_INLINE bool entry_opens(Entry e) { return entry_kind(e) == ENTRY_PUSH || entry_is_group_begin(e); }
MPVG_HD_INLINE bool entry_closes(Entry e) { return entry_kind(e) == ENTRY_POP || entry_is_group_end(e); }
MPVG_HD_INLINE bool operator==(Entry a, Entry b) { return a.head == b.head && a.data == b.data; }

// Do entries a and b (adjacent in one cell) belong to the same path run?
MPVG_HD_INLINE bool entry_same_path(Entry a, Entry b) {
  return !entry_is_delimiter(a) && !entry_is_delimiter(b) && entry_path(a) == entry_path(b);
}

// A cell of one tree level. Cells are squares of side root_size >> level,
// aligned to the pixel grid: cell (ix, iy) covers samples in
// [ix*s, (ix+1)*s) x [iy*s, (iy+1)*s) of its scene's grid. Its entries are
// [begin, end) of its level's entry array. `root` is the scene of a forest
// frame it belongs to (frame/forest.h; 0 for a frame of one scene): every
// cell descends from that scene's root and holds only its elements.
struct Cell {
  uint32_t begin, end;
  uint16_t ix, iy;
  uint16_t level;
  uint16_t root;
};
static_assert(sizeof(Cell) == 16, "Cell is a 16-byte record shared by CPU and GPU");

struct CellBox {
  float x0, y0, x1, y1;
};

MPVG_HD_INLINE CellBox cell_box(uint16_t ix, uint16_t iy, uint16_t level, uint32_t root_size) {
  const uint32_t s = root_size >> level;
  return CellBox{float(ix * s), float(iy * s), float((ix + 1) * s), float((iy + 1) * s)};
}

// Tree node for descending with a sample position; a forest's roots are
// nodes 0 .. roots - 1 (frame/forest.h). Children of a node are
// four consecutive nodes in quadrant order q = (y bit << 1) | x bit:
// 0 = (low x, low y), 1 = (high x, low y), 2 = (low x, high y), 3 = (high x,
// high y).
struct Node {
  int32_t child;  // first child node, or -1 for a leaf
  uint32_t leaf;  // leaf index (into the leaf table) when child == -1
};
static_assert(sizeof(Node) == 8, "Node is an 8-byte record shared by CPU and GPU");

// Per-path flags of the path table.
enum : uint32_t {
  PATH_EVENODD = 1u << 0,
  PATH_CLIP = 1u << 1,
  PATH_OPAQUE = 1u << 2,   // fill whose paint is opaque at every sample
  PATH_VARYING = 1u << 3,  // fill whose paint depends on the sample's position
  // Fill in a list that runs back to front (a group's whose blend modes
  // need their backdrop; core/paint/group.h): it goes over the colour so far.
  PATH_BACK_TO_FRONT = 1u << 4,
  PATH_KNOCKOUT = 1u << 5,  // fill in a knockout group's list
  // Fill in a mask's list whose paint, covering a sample, makes the mask 1
  // there (opaque for an alpha mask; luminance 1 for a luminance mask).
  PATH_MASK_FULL = 1u << 6,
  // Drawn without antialiasing (SVG shape-rendering: crispEdges): the
  // path covers all of a pixel's samples or none, as its winding at the
  // pixel's centre says (core/sampling/sampling.h).
  PATH_ALIASED = 1u << 7,
};

struct PathRecord {
  uint32_t flags;
  uint32_t paint;  // fills: index into the paint table (core/paint/paint.h)
};
static_assert(sizeof(PathRecord) == 8, "PathRecord is an 8-byte record shared by CPU and GPU");

MPVG_HD_INLINE bool path_inside(uint32_t path_flags, int winding) {
  return (path_flags & PATH_EVENODD) ? (winding & 1) != 0 : winding != 0;
}

}  // namespace mpvg
