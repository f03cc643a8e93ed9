// Pruning (paper §4.3-4.4): stream rewriting rules applied by parallel
// mark-and-sweep, as per-entry functions both executors run.
//
// Terminals in a cell: F0/C0, a fill/clip path that fails every sample of
// the cell, and F1/C1, one that passes every sample (F1 also with an opaque
// paint, or any paint in a knockout group, where covering is enough). The
// tree is tight, so these are the paths reduced to a single winding entry:
// the fill rule of that winding decides (rule 12/13 paths with no entry at
// all never reach a cell). Rules, with A, B, C well-formed streams:
//   (12) F0 -> e            (13) C0 -> e
//   (14) (A | B F1 C) -> (A | B F1)        also at the top level: F1 C -> F1,
//        and in a group's list: {M? B F1 C} -> {M? B F1}; an F1 occludes
//        only within its list, so a group's opacity or blend mode still
//        applies to what it covers
//   (14') in a list stored back to front (core/paint/group.h), F1 is on top of
//        what precedes it: (A | B F1 C) -> (A | F1 C), {M? B F1 C} -> {M? F1 C},
//        at the top level B F1 C -> F1 C
//   (15) ( | A ) -> e       (16) (A | ) -> e
//   (17) (A C1 B | C) -> C
//   (18) (A | B C1 C) -> (A | C1)
//   (19) {M?} -> e          an empty group leaves its backdrop unchanged
//   (20) {{} B} -> e        where the mask's emptiness makes it 0 (alpha
//                           masks; luminance masks over a backdrop of
//                           luminance 0): the group it masks is invisible;
//                           when that group is a mask itself, only B goes:
//                           {{} B} -> {{}}, as the outer mask's value is
//                           then its backdrop's, not 1
//   (21) {{F1} B} -> {B}     where F1 makes the mask 1 at every sample
//                           (white, or opaque for an alpha mask); also
//                           {{(C1 | F1)} B} -> {B}, a mask's region that
//                           covers the cell (prune_mask_full)
//   (22) (A | B {C F1 D} E) -> (A | B {C F1 D}) for a solid group (opacity
//        1, normal, not knockout, unmasked): opaque where its list holds an
//        F1, it hides what lies behind it like an F1 (before it in a list
//        stored back to front); also in groups' lists and at the top level,
//        and up through solid groups that hold it
//   (23) {X} -> X           for one item X (a path, or a group of normal
//                           blending that does not start from its
//                           backdrop) in an unmasked
//                           solid group that does not start from its
//                           backdrop and whose list runs in its parent's
//                           order: X alone composites exactly as the group
//                           would
// M is the group's mask, a group itself ('{' and '}' open and close like
// '(' and ')').
// Rule 18 is applied by the first C1 of the content section only: two C1s
// each erasing the other would leave (A | ), which is wrong (the paper's
// rule 19 fails for the same kind of reason). The first C1 is found by a
// minimum over the section (atomicMin on the GPU).
//
// Marking: +1 at the first element of a range to eliminate and -1 just past
// it, into an elimination array; an inclusive scan then gives every element
// to drop a positive count. Rules 16, 19 and 23 are marked after the others
// are scanned, on what those leave (prune_mark_empty, prune_mark_unwrap
// below), so that a round empties nested groups all at once.
//
// Cross-links: depth by an inclusive scan (+1 at '(', -1 just after ')'), so
// '(' and ')' share the depth of their group; then, over all depths at
// once, a stable sort by depth and a segmented scan give each element its
// group's '(' (open link), and the '|' and ')' register with their '(' (bar
// and close links; see prune_link below).
#pragma once
#include <cstdint>

#include "core/paint/group.h"
#include "core/hd.h"
#include "core/scan.h"
#include "core/tree/shortcut_tree.h"

namespace mpvg {

// Terminal classes of a path run (prune_classify).
enum : uint32_t {
  TERM_NONE = 0,  // undecided path, or a delimiter
  TERM_F0 = 1,
  TERM_F1 = 2,
  TERM_C0 = 3,
  TERM_C1 = 4,
  TERM_F1_BACK = 5,  // F1 in a list stored back to front (rule 14')
  TERM_CLASS = 7,
  TERM_FILLS_MASK = 8,  // with F1 / F1_BACK: a fill that makes its mask 1 (rule 21)
};

// Depth scan input for element i.
MPVG_HD_INLINE int32_t prune_depth_delta(const Entry* entries, uint32_t i) {
  int32_t d = entry_opens(entries[i]) ? 1 : 0;
  if (i > 0 && entry_closes(entries[i - 1])) d -= 1;
  return d;
}

// Cross-links over all depths at once. A group's elements of its own
// depth (its '(' or '{', its direct content, '|', ')') are those of that
// depth after its opening and before the next opening of that depth (the
// element after a ')' drops the depth, a nested group raises it). So the
// elements are sorted stably by depth (`sorted` holds their indices: in
// order of (depth, index)), and a segmented max-scan over that order, one
// segment per depth, carries the last opening seen: 1 + its index, 0 for
// none (LinkSeg, SegmentedMax in core/scan.h).
using LinkSeg = Segmented<uint32_t>;

// The scan's input at sorted position p.
MPVG_HD_INLINE LinkSeg prune_link_start(const Entry* e, const uint32_t* sorted, const int32_t* depth, uint32_t p) {
  const uint32_t i = sorted[p];
  const bool head = p == 0 || depth[sorted[p - 1]] != depth[i];
  return LinkSeg{entry_opens(e[i]) ? i + 1 : 0u, head ? 1u : 0u};
}

// The first position of the (key, index) order `sorted` (of n elements)
// at or after (k, i), by binary search.
MPVG_HD_INLINE uint32_t prune_lower_bound(const uint32_t* sorted, const int32_t* key, uint32_t n, int32_t k,
                                          uint32_t i) {
  uint32_t lo = 0, hi = n;
  while (lo < hi) {
    const uint32_t mid = lo + (hi - lo) / 2;
    const uint32_t j = sorted[mid];
    if (key[j] < k || (key[j] == k && j < i)) lo = mid + 1; else hi = mid;
  }
  return lo;
}

// The links of the element at sorted position p of n, from the scanned
// `last`: its group's opening (open), and as that opening's '|' or ')'
// (bar, close); for an opening of depth d >= 2, the group it lies in
// (parent: the last opening of depth d - 1 before it, at the last sorted
// position before (d - 1, i), found by binary search). Depth-0 elements
// lie in no group. Every write has one writer.
MPVG_HD_INLINE void prune_link(const Entry* e, const uint32_t* sorted, const int32_t* depth, const LinkSeg* last,
                               uint32_t n, uint32_t p, uint32_t* open, uint32_t* bar, uint32_t* close,
                               uint32_t* parent) {
  const uint32_t i = sorted[p];
  const int32_t d = depth[i];
  if (d <= 0) return;
  const uint32_t o = last[p].value - 1;
  open[i] = o;
  if (entry_kind(e[i]) == ENTRY_ACTIVATE) bar[o] = i;
  if (entry_closes(e[i])) close[o] = i;
  if (!entry_opens(e[i]) || d < 2) return;
  parent[i] = last[prune_lower_bound(sorted, depth, n, d - 1, i) - 1].value - 1;
}

// Classifies element i of a cell [begin, end): is it a whole path reduced to
// one winding entry, and what does its fill rule say?
MPVG_HD_INLINE uint32_t prune_classify(const Entry* entries, uint32_t i, uint32_t begin, uint32_t end,
                                       const PathRecord* paths) {
  const Entry e = entries[i];
  if (entry_kind(e) != ENTRY_WINDING) return TERM_NONE;
  if (i > begin && entry_same_path(entries[i - 1], e)) return TERM_NONE;
  if (i + 1 < end && entry_same_path(e, entries[i + 1])) return TERM_NONE;
  const PathRecord rec = paths[entry_path(e)];
  const bool inside = path_inside(rec.flags, static_cast<int32_t>(e.data));
  if (rec.flags & PATH_CLIP) return inside ? TERM_C1 : TERM_C0;
  if (!inside) return TERM_F0;
  if (!(rec.flags & (PATH_OPAQUE | PATH_KNOCKOUT))) return TERM_NONE;
  return ((rec.flags & PATH_BACK_TO_FRONT) ? TERM_F1_BACK : TERM_F1) |
         ((rec.flags & PATH_MASK_FULL) ? TERM_FILLS_MASK : 0u);
}

// Is element k a mask's '{'?
MPVG_HD_INLINE bool prune_is_mask_begin(const Entry* entries, uint32_t k) {
  return entry_is_group_begin(entries[k]) && (entries[k].head & GROUP_ENTRY_MASK) != 0;
}

// Links of one element, filled by the link scans. For elements at depth 0
// open is ~0u. bar and close are meaningful at '(' elements.
struct PruneLinks {
  const int32_t* depth;
  const uint32_t* open;
  const uint32_t* bar;
  const uint32_t* close;
  const uint32_t* first_c1;  // per '(' element: index of the first C1 after its '|', or ~0u
  const uint32_t* parent;    // per '(' or '{' element: the '(' or '{' it lies in, or ~0u at the top level
};

// Does a C1 at i lie in the content section of its group (after the '|')?
MPVG_HD_INLINE bool prune_c1_in_content(const PruneLinks& l, uint32_t i) {
  const uint32_t o = l.open[i];
  return i > l.bar[o];
}

// First element of the fill list that the '(' or '{' at o holds: after
// the '|' of a clip group, after the mask of a masked group.
MPVG_HD_INLINE uint32_t prune_list_start(const Entry* entries, const PruneLinks& l, uint32_t o) {
  if (entry_kind(entries[o]) == ENTRY_PUSH) return l.bar[o] + 1;
  return prune_is_mask_begin(entries, o + 1) ? l.close[o + 1] + 1 : o + 1;
}

// Is [a, b] one item of a list that composites the same in any list of
// its order: one path's run (a path has one run in a cell), or one group
// of normal blending that does not start from its backdrop (a blend mode or
// a backdrop would meet another backdrop)?
MPVG_HD_INLINE bool prune_single_item(const Entry* entries, const PruneLinks& l, uint32_t a, uint32_t b) {
  if (entry_is_group_begin(entries[a]))
    return l.close[a] == b && (entries[a].head & (GROUP_ENTRY_BACKDROP | GROUP_ENTRY_NORMAL)) == GROUP_ENTRY_NORMAL;
  if (entry_opens(entries[a])) return false;
  return !entry_is_delimiter(entries[a]) && !entry_is_delimiter(entries[b]) &&
         entry_path(entries[a]) == entry_path(entries[b]);
}

// The marks of element i. add(index, delta) accumulates into the
// elimination array (atomically on the GPU). [cell_begin, cell_end) is i's
// cell.
// Does the mask whose '{' is at m and '}' at close make its group's mask 1
// at every sample of the cell, so that rule 21 removes it this round: one
// fill that makes it 1, {F1}, or the same in a clip group that passes
// every sample, {( C1 | F1 )} (a mask's region in the cell's inside: rule
// 17 dissolves that clip group in the same round).
MPVG_HD_INLINE bool prune_mask_full(const Entry* entries, const uint32_t* term, uint32_t m, uint32_t close) {
  if (close == m + 2) return (term[m + 1] & TERM_FILLS_MASK) != 0;
  return close == m + 6 && entry_kind(entries[m + 1]) == ENTRY_PUSH && term[m + 2] == TERM_C1 &&
         entry_kind(entries[m + 3]) == ENTRY_ACTIVATE && (term[m + 4] & TERM_FILLS_MASK) != 0 &&
         entry_kind(entries[m + 5]) == ENTRY_POP;
}

// Is the group whose '{' is at o unmasked in this cell: no mask, or one
// that rule 21 removes in this very round?
MPVG_HD_INLINE bool prune_unmasked(const Entry* entries, const uint32_t* term, const PruneLinks& l, uint32_t o) {
  if (!prune_is_mask_begin(entries, o + 1)) return true;
  return prune_mask_full(entries, term, o + 1, l.close[o + 1]);
}

// Rule 22: an unmasked solid group with an opaque element F1 in its list
// (the group at o, F1 at i) hides what lies behind it in the list it is
// in; being opaque, it makes that list's group opaque too if that one is
// solid and unmasked, and so on up.
template <class Add>
MPVG_HD_INLINE void prune_mark_solid_group(const Entry* entries, const uint32_t* term, const PruneLinks& l, uint32_t o,
                                           uint32_t cell_begin, uint32_t cell_end, Add&& add) {
  for (;;) {
    if (!entry_is_group_begin(entries[o]) || !(entries[o].head & GROUP_ENTRY_SOLID) ||
        !prune_unmasked(entries, term, l, o))
      return;
    const uint32_t p = l.parent[o];
    if (entries[o].head & GROUP_ENTRY_IN_BACK_TO_FRONT) {
      const uint32_t start = p != ~0u ? prune_list_start(entries, l, p) : cell_begin;
      if (start < o) {
        add(start, 1);
        add(o, -1);
      }
    } else {
      const uint32_t stop = p != ~0u ? l.close[p] : cell_end;
      if (l.close[o] + 1 < stop) {
        add(l.close[o] + 1, 1);
        add(stop, -1);
      }
    }
    if (p == ~0u) return;
    o = p;
  }
}

template <class Add>
MPVG_HD_INLINE void prune_mark(const Entry* entries, const uint32_t* term, const PruneLinks& l, uint32_t i,
                               uint32_t cell_begin, uint32_t cell_end, Add&& add) {
  const uint32_t t = term[i] & TERM_CLASS;
  const uint32_t kind = entry_kind(entries[i]);
  if (t == TERM_F0 || t == TERM_C0) {  // rules 12, 13
    add(i, 1);
    add(i + 1, -1);
    return;
  }
  if (t == TERM_F1) {  // rule 14: everything after F1 in its fill list
    const uint32_t stop = l.depth[i] > 0 ? l.close[l.open[i]] : cell_end;
    if (i + 1 < stop) {
      add(i + 1, 1);
      add(stop, -1);
    }
    if (l.depth[i] > 0) prune_mark_solid_group(entries, term, l, l.open[i], cell_begin, cell_end, add);
    return;
  }
  if (t == TERM_F1_BACK) {  // rule 14': everything before F1 in its list
    const uint32_t start = l.depth[i] > 0 ? prune_list_start(entries, l, l.open[i]) : cell_begin;
    if (start < i) {
      add(start, 1);
      add(i, -1);
    }
    if (l.depth[i] > 0) prune_mark_solid_group(entries, term, l, l.open[i], cell_begin, cell_end, add);
    return;
  }
  if (t == TERM_C1) {
    const uint32_t o = l.open[i];
    const uint32_t bar = l.bar[o], close = l.close[o];
    if (i < bar) {  // rule 17: drop "( A C1 B |" and ")"
      add(o, 1);
      add(bar + 1, -1);
      add(close, 1);
      add(close + 1, -1);
    } else if (l.first_c1[o] == i) {  // rule 18: keep only this C1
      add(bar + 1, 1);
      add(i, -1);
      add(i + 1, 1);
      add(close, -1);
    }
    return;
  }
  if (kind == ENTRY_PUSH && entry_kind(entries[i + 1]) == ENTRY_ACTIVATE) {  // rule 15
    add(i, 1);
    add(l.close[i] + 1, -1);
    return;
  }
  if (entry_is_group_end(entries[i])) {
    const uint32_t o = l.open[i];
    if ((entries[i].head & GROUP_ENTRY_MASK) && prune_mask_full(entries, term, o, i)) {  // rule 21
      add(o, 1);
      add(i + 1, -1);
      return;
    }
    if ((entries[i].head & GROUP_ENTRY_MASK) && o + 1 == i && (entries[i].head & GROUP_ENTRY_EMPTY_HIDES)) {  // rule 20
      const uint32_t p = o - 1;  // the group this mask belongs to
      if (!(entries[p].head & GROUP_ENTRY_MASK)) {
        add(p, 1);
        add(l.close[p] + 1, -1);
      } else if (i + 1 < l.close[p]) {
        // A mask of a mask: the outer mask's content goes, the outer mask
        // stays (its value is then its backdrop's).
        add(i + 1, 1);
        add(l.close[p], -1);
      }
    }
  }
}

// Rules 16, 19 and 23 ask what a list holds, and a round's other rules
// empty lists. Applied to the stream the round starts from, a group
// emptied by a round goes in the next, its parent in the one after
// (tiger_groups: about four rounds per level, one per nesting step). So
// they are applied to what the round's other marks leave, as if deepest
// group first, by counting survivors: after prune_mark's marks are
// scanned, prune_mark_empty (rules 16, 19) and then prune_mark_unwrap
// (rule 23) mark into a second elimination array; an element is kept when
// neither array eliminates it.
//
// A list's emptiness. The paths of a clip section or of a mask show
// nothing by themselves: an element's section count (scan of
// prune_section_delta) is how many of those it lies in. A group's list, a
// clip group's content, and the lists and contents nested in them share
// the section count of the group's opening; masks and clip sections
// nested in them count more. So the list, with everything nested in it,
// is empty after the round when no surviving path entry of that count
// lies in its range: counted by binary search in the elements' (section,
// index) order and a prefix sum of survivors over that order (PruneShown).
// Emptying happens deepest first in effect: a list holding only groups
// whose lists are empty is empty too, and each of those goes by its own
// count.
MPVG_HD_INLINE int32_t prune_section_delta(const Entry* e, uint32_t i) {
  int32_t d = 0;
  if (prune_is_mask_begin(e, i)) d += 1;  // a mask's content, with its '{' and '}'
  if (entry_kind(e[i]) == ENTRY_ACTIVATE) d -= 1;
  if (i > 0) {
    if (entry_kind(e[i - 1]) == ENTRY_PUSH) d += 1;  // a clip section, after its '('
    if (entry_is_group_end(e[i - 1]) && (e[i - 1].head & GROUP_ENTRY_MASK)) d -= 1;
  }
  return d;
}

// Is element i a path entry that survives the round's first marks (the
// scanned elimination array)?
MPVG_HD_INLINE uint32_t prune_shows(const Entry* e, const int32_t* elim, uint32_t i) {
  return !entry_is_delimiter(e[i]) && elim[i] <= 0 ? 1u : 0u;
}

struct PruneShown {
  const int32_t* section;  // per element
  const uint32_t* sorted;  // elements in (section, index) order
  const uint32_t* shown;   // n + 1: elements that show, before each position of `sorted`
  uint32_t n;
};

// Elements of section count c in [a, b) that show.
MPVG_HD_INLINE uint32_t prune_shown_in(const PruneShown& s, int32_t c, uint32_t a, uint32_t b) {
  if (a >= b) return 0;
  return s.shown[prune_lower_bound(s.sorted, s.section, s.n, c, b)] -
         s.shown[prune_lower_bound(s.sorted, s.section, s.n, c, a)];
}

// Rule 23 counts the items of a list: a path's run at the list's depth,
// and a group or clip group (its opening, one deeper). prune_mark_empty
// gives every element its weight as an item: 1 for the first entry of a
// surviving path run, kItemGroup for an opening that stays, 2 kItemGroup
// for a clip group that rule 17 dissolves with content left (one item or
// more: rule 23 then waits a round). Prefix sums of the weights in the
// (depth, index) order of the cross-links count the items of any list.
constexpr uint64_t kItemGroup = uint64_t{1} << 32;

// Rules 16 and 19 at element i, and i's weight as an item. [cell_begin,
// ...) is i's cell; elim is the scanned first marks.
//   (16) (A | ) -> e     a clip group whose content shows nothing
//   (19) {M?} -> e       a group whose list shows nothing
template <class Add>
MPVG_HD_INLINE uint64_t prune_mark_empty(const Entry* e, const int32_t* elim, const PruneLinks& l,
                                         const PruneShown& s, uint32_t i, uint32_t cell_begin, Add&& add) {
  const Entry x = e[i];
  const bool survives = elim[i] <= 0;
  if (!entry_is_delimiter(x)) return survives && (i == cell_begin || !entry_same_path(e[i - 1], x)) ? 1u : 0u;
  if (!entry_opens(x) || prune_is_mask_begin(e, i)) return 0;  // a mask empties by rule 20
  const uint32_t close = l.close[i];
  const uint32_t first = entry_kind(x) == ENTRY_PUSH ? l.bar[i] + 1 : prune_list_start(e, l, i);
  if (prune_shown_in(s, s.section[i], first, close) == 0) {
    add(i, 1);
    add(close + 1, -1);
    return 0;
  }
  return survives ? kItemGroup : 2 * kItemGroup;
}

struct PruneItems {
  const uint32_t* sorted;  // the cross-links' (depth, index) order
  const uint64_t* items;   // n + 1: item weights before each position of `sorted`
  uint32_t n;
};

// Rule 23 at the group opening at o, on the list the round leaves:
//   (23) {X} -> X        one item X (a path, or a group of normal blending
//                        that does not start from its backdrop) in an
//                        unmasked solid group that does not start from its
//                        backdrop and whose list runs in its parent's order
template <class Add>
MPVG_HD_INLINE void prune_mark_unwrap(const Entry* e, const uint32_t* term, const PruneLinks& l, const PruneItems& it,
                                      uint32_t o, Add&& add) {
  const Entry x = e[o];
  if (!entry_is_group_begin(x) || (x.head & GROUP_ENTRY_MASK) || !(x.head & GROUP_ENTRY_DISSOLVES) ||
      !prune_unmasked(e, term, l, o))
    return;
  const uint32_t first = prune_list_start(e, l, o), close = l.close[o];  // after a mask rule 21 removes
  const int32_t d = l.depth[o];
  const uint64_t* w = it.items;
  const uint32_t paths = static_cast<uint32_t>(w[prune_lower_bound(it.sorted, l.depth, it.n, d, close)] -
                                               w[prune_lower_bound(it.sorted, l.depth, it.n, d, first)]);
  uint32_t q = prune_lower_bound(it.sorted, l.depth, it.n, d + 1, first);
  const uint32_t q1 = prune_lower_bound(it.sorted, l.depth, it.n, d + 1, close);
  const uint64_t g0 = w[q] >> 32;
  const uint64_t groups = (w[q1] >> 32) - g0;
  if (paths + groups != 1) return;
  if (groups == 1) {  // the group: the position where the count rises
    uint32_t hi = q1 - 1;
    while (q < hi) {
      const uint32_t mid = q + (hi - q) / 2;
      if ((w[mid + 1] >> 32) > g0) hi = mid; else q = mid + 1;
    }
    const uint32_t j = it.sorted[q];
    if (!prune_single_item(e, l, j, l.close[j])) return;
  }
  add(o, 1);
  add(o + 1, -1);
  add(close, 1);
  add(close + 1, -1);
}

}  // namespace mpvg
