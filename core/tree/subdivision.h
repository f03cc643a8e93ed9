// Subdivision of shortcut-tree cells (paper §4.1) and its parallel form
// (§4.2), as per-entry functions that both executors run.
//
// Invariant of every cell: for a sample p in the cell, the winding number of
// each path about p (horizontal ray towards +x) equals the sum over the
// path's entries in the cell of
//   SEGMENT        abstract_ray_winding(segment, p)
//   SHORTCUT_UP    +1 if p.y >= y          SHORTCUT_DOWN  -1 if p.y >= y
//   WINDING        its value.
//
// Why the rules below keep it (a derivation, since the paper gives the rules
// and figures only). Let a cell be c = [x0,x1) x [y0,y1) and take the entries
// of its parent as the input: closed chains of segments (a parent's shortcut
// runs from its point to +infinity above, and the chains close through that
// point at infinity). For each point q outside c define the potential U(q),
// the crossings of a canonical path from q to +infinity above that avoids c:
// straight up when q is right of every sample (q.x >= x1) and above the cut
// line y = y0 (q.y > y0); otherwise left first, then up, crossing no ray of
// c. So U(q) is a shortcut from q when q.x >= x1 and y0 < q.y < y1, nothing
// otherwise. For a segment s from a to b that does not touch the samples of
// c, the closed loop s + path(b) - path(a) winds around c as often as it
// crosses the cut half-line B = {y = y0, x >= x1}, i.e. as often as s does
// (the canonical paths never cross it). Hence, for every sample of c,
//   crossings(s) = k(s) + U(a) - U(b),   k(s) = signed crossings of B by s.
// Summed over a closed chain the potentials telescope, so each segment that
// is kept in c contributes U(end) - U(start) -- a SHORTCUT_UP from its end
// and a SHORTCUT_DOWN to its start when those lie in the band right of c --
// and each omitted entry contributes only its k (a winding increment). These
// are the shortcut segments of boundary A/C/D and the winding increments of
// half-lines B/E/F in Fig. 8. Kept segments are copied whole (never clipped).
//
// Ties are resolved as if every sample sat infinitesimally up and right of
// its position, which is what the half-open y-range and the strict "left"
// test of abstract_ray_winding mean. A segment is omitted from c only when
// it certainly misses those samples:
//   - its y-range (ymin, ymax) misses (y0, y1), or
//   - X(y) >= x1 over the common rows (right miss, k = direction if
//     ymin <= y0 < ymax), or X(y) <= x0 there (left miss).
// Both misses are decided by one side test at a corner of the common rows,
// and k reuses that decision, so rounding in the implicit test can only
// misplace samples that are themselves within rounding of the curve.
#pragma once
#include <cstdint>

#include "core/geometry/abstract_segment.h"
#include "core/hd.h"
#include "core/scan.h"
#include "core/tree/shortcut_tree.h"

namespace mpvg {

// Split flags: what one parent entry writes into one child cell.
enum : uint32_t {
  SPLIT_KEEP = 1u << 0,            // copy the parent entry
  SPLIT_SHORTCUT_END = 1u << 1,    // SHORTCUT_UP from the segment's end
  SPLIT_SHORTCUT_START = 1u << 2,  // SHORTCUT_DOWN to the segment's start
};

MPVG_HD_INLINE uint32_t split_count(uint32_t flags) {
  return (flags & 1u) + ((flags >> 1) & 1u) + ((flags >> 2) & 1u);
}

// Classifies an abstract segment against a cell box: returns split flags and
// the winding increment k for the cell.
MPVG_HD_INLINE uint32_t split_segment(const AbstractSegment& s, const CellBox& c, int32_t* wind) {
  *wind = 0;
  const float ymin = abstract_ymin(s), ymax = abstract_ymax(s);
  bool keep;
  if (ymin == ymax) {
    // Horizontal: never crossed by a ray, but kept where it runs through the
    // samples so that the chain's potentials still telescope.
    keep = c.y0 < ymin && ymin < c.y1 && abstract_xmin(s) < c.x1 && abstract_xmax(s) > c.x0;
  } else if (ymin >= c.y1 || ymax <= c.y0) {
    keep = false;
  } else {
    const float lo = ymin > c.y0 ? ymin : c.y0;
    const float hi = ymax < c.y1 ? ymax : c.y1;
    const bool inc = abstract_increasing(s);
    if (abstract_side(s, c.x1, inc ? lo : hi) >= 0) {
      // Right of every sample in the common rows: crosses B iff it spans y0.
      if (ymin <= c.y0 && c.y0 < ymax) *wind = abstract_direction(s);
      keep = false;
    } else if (abstract_side(s, c.x0, inc ? hi : lo) <= 0) {
      keep = false;
    } else {
      keep = true;
    }
  }
  if (!keep) return 0;
  uint32_t flags = SPLIT_KEEP;
  if (s.x1 >= c.x1 && c.y0 < s.y1 && s.y1 < c.y1) flags |= SPLIT_SHORTCUT_END;
  if (s.x0 >= c.x1 && c.y0 < s.y0 && s.y0 < c.y1) flags |= SPLIT_SHORTCUT_START;
  return flags;
}

// The split of one parent entry into one child cell (first kernel of §4.2).
MPVG_HD_INLINE uint32_t split_entry(Entry e, const AbstractSegment* segments, const CellBox& c, int32_t* wind) {
  switch (entry_kind(e)) {
    case ENTRY_SEGMENT: return split_segment(segments[e.data], c, wind);
    case ENTRY_SHORTCUT_UP:
      // A parent shortcut lies right of the child too; only its crossing of
      // the child's cut half-line remains.
      *wind = entry_float(e) <= c.y0 ? 1 : 0;
      return 0;
    case ENTRY_SHORTCUT_DOWN:
      *wind = entry_float(e) <= c.y0 ? -1 : 0;
      return 0;
    case ENTRY_WINDING: *wind = static_cast<int32_t>(e.data); return 0;
    default: *wind = 0; return SPLIT_KEEP;  // delimiters go to every child
  }
}

// Number of entries one (parent entry, child) pair writes: its split plus,
// when it ends its path's run, one winding entry if the consolidated winding
// is non-zero (the "extra 1" of the third kernel of §4.2).
MPVG_HD_INLINE uint32_t split_output_count(uint32_t flags, bool last_of_run, int32_t run_wind) {
  return split_count(flags) + ((last_of_run && run_wind != 0) ? 1u : 0u);
}

// The second and third kernels of §4.2 as one scan: winding increments
// consolidated per path run (a segmented sum whose heads are the runs'
// first pairs) and the pairs' output counts summed, in one pass. A run's
// last pair counts its winding entry only once its run's sum is known, so
// a stretch of pairs carries the sum before its first head (`prefix`), and
// whether a run ends there (its winding entry still to count); the stretch
// that precedes settles it. Pairs of one child cell follow each other and
// its first is a head, so every inclusive prefix from the first pair is
// settled: at pair j, `count` is the outputs of pairs 0 .. j (the offset of
// pair j + 1) and `last` the consolidated winding of j's run so far.
// Slots between cells (the CPU's batches) are SplitScan{}: the identity.
struct SplitScan {
  int32_t prefix;  // winding before the first head (all of it without one)
  int32_t last;    // winding since the last head
  uint32_t count;  // outputs, less a run end's winding entry still unsettled in the prefix
  uint32_t flags;  // SPLIT_SCAN_HEAD, SPLIT_SCAN_OPEN_END
};
enum : uint32_t { SPLIT_SCAN_HEAD = 1u, SPLIT_SCAN_OPEN_END = 2u };

// The scan's item for one pair: its split flags and winding increment, and
// whether it starts or ends its path's run.
MPVG_HD_INLINE SplitScan split_scan_item(uint32_t flags, int32_t wind, bool head, bool last) {
  if (head) return SplitScan{0, wind, split_output_count(flags, last, wind), SPLIT_SCAN_HEAD};
  return SplitScan{wind, wind, split_count(flags), last ? SPLIT_SCAN_OPEN_END : 0u};
}

struct SplitScanOp {
  MPVG_HD_INLINE SplitScan operator()(SplitScan a, SplitScan b) const {
    const int32_t run = a.last + b.prefix;  // b's first run, continued from a
    SplitScan r;
    r.last = (b.flags & SPLIT_SCAN_HEAD) ? b.last : run;
    if (a.flags & SPLIT_SCAN_HEAD) {
      r.prefix = a.prefix;
      r.count = a.count + b.count + (((b.flags & SPLIT_SCAN_OPEN_END) && run != 0) ? 1u : 0u);
      r.flags = a.flags;
    } else {
      r.prefix = a.prefix + b.prefix;
      r.count = a.count + b.count;
      r.flags = (b.flags & SPLIT_SCAN_HEAD) | ((a.flags | b.flags) & SPLIT_SCAN_OPEN_END);
    }
    return r;
  }
};

// Writes the outputs of one (parent entry, child) pair at out (fourth kernel
// of §4.2). Order: the entry itself, its shortcuts, then the path's winding.
MPVG_HD_INLINE uint32_t split_scatter(Entry e, uint32_t flags, bool last_of_run, int32_t run_wind,
                                      const AbstractSegment* segments, Entry* out) {
  uint32_t n = 0;
  const uint32_t path = entry_path(e);
  if (flags & SPLIT_KEEP) out[n++] = e;
  if (flags & SPLIT_SHORTCUT_END)
    out[n++] = make_entry(ENTRY_SHORTCUT_UP, path, float_bits(segments[e.data].y1));
  if (flags & SPLIT_SHORTCUT_START)
    out[n++] = make_entry(ENTRY_SHORTCUT_DOWN, path, float_bits(segments[e.data].y0));
  if (last_of_run && run_wind != 0) out[n++] = make_entry(ENTRY_WINDING, path, static_cast<uint32_t>(run_wind));
  return n;
}

// Is entry i the first / last of its path run within [begin, end)?
MPVG_HD_INLINE bool run_starts(const Entry* entries, uint32_t i, uint32_t begin) {
  return i == begin || !entry_same_path(entries[i - 1], entries[i]);
}
MPVG_HD_INLINE bool run_ends(const Entry* entries, uint32_t i, uint32_t end) {
  return i + 1 == end || !entry_same_path(entries[i], entries[i + 1]);
}

// Counts the entries of a cell that subdivision works to reduce.
MPVG_HD_INLINE uint32_t entry_weight(Entry e) { return entry_is_geometry(e) ? 1u : 0u; }

}  // namespace mpvg
