// Stage "stroke" (paper §7, future work: stroked paths converted to filled
// primitives in parallel): the stroke of a path as fill geometry, computed
// per element from flat data by both executors, the CPU's loops
// (cpu/stroke.cpp) and the GPU's kernels (gpu/stroke.cu).
//
// The stroke of a path is, by SVG 2 (painting.html#StrokeShape), the union
// of (a) for every segment, the normal segments of length stroke-width
// centred on it, (b) a join shape at every vertex inside a subpath (and at
// the start of a closed one), and (c) a cap shape at both ends of every open
// subpath or dash. Each of these pieces is emitted here by its own element,
// as closed contours oriented so that their winding number is positive
// everywhere inside; the nonzero fill of all of them is their union,
// however they overlap (Nehab 2020, "Converting stroked primitives to
// filled primitives", builds strokes from such pieces). Output curves:
// offsets are quadratics within the tolerance (never polylines), lines stay
// lines, circular arcs are exact conics.
//
// Items, each independent of the others of its kind once the kinds before
// it are done:
//   - segment i: the parts of it to build bodies for (the whole segment, or
//     with dashes the dashes' parts on it), the caps of the dashes that
//     begin or end on it, and its zero-length dashes;
//   - vertex v of a subpath: the join there (stroker/stroke_joins.h) when the
//     stroke runs through it, the caps of an undashed open subpath, the dot
//     of a zero-length subpath;
//   - the parts, their spans and their fit items (stroker/stroke_body.h).
// Dash phases come from the arc length at each segment's start: segment
// lengths (the measuring pass), summed by a scan within each subpath. The
// GPU runs each kind twice, counting its output segments, then (after a
// scan of the counts) writing them; the CPU appends them in one pass.
// Segments are written in pixels, as the abstraction stage's input.
#pragma once
#include <cstdint>

#include "stroker/stroke_body.h"
#include "stroker/stroke_curve.h"
#include "stroker/stroke_joins.h"
#include "stroker/stroke_output.h"

namespace mpvg::stroking {

// One stroked path.
struct StrokeRecord {
  double xf[6];          // user space -> pixels (a b c d e f, as Affine)
  double h;              // half width, user units (> 0)
  double miter_limit;    // >= 1
  double tol;            // tolerance, user units
  double dash_offset;    // in [0, dash_sum)
  double dash_sum;       // sum of the pattern
  uint32_t join, cap;
  uint32_t dash_first;   // into StrokeInput::dashes
  uint32_t dash_count;   // even; 0: no dashes
  uint32_t path;         // output path id
  uint32_t pad = 0;
};

enum : uint32_t { SUBPATH_CLOSED = 1, SUBPATH_ZERO_LENGTH = 2 };

// One subpath of a stroked path: its segments (zero-length ones already left
// out), or none for a zero-length subpath ("M p Z", "M p L p"), which only
// has caps.
struct StrokeSubpath {
  uint32_t stroke;
  uint32_t first_segment, segment_count;
  uint32_t first_vertex;  // vertices: segment_count (closed), segment_count + 1 (open), 1 (zero length)
  uint32_t flags;
  uint32_t pad = 0;
  Vec2 start;
};

MPVG_HD_INLINE uint32_t subpath_vertices(const StrokeSubpath& sp) {
  if (sp.flags & SUBPATH_ZERO_LENGTH) return 1;
  return sp.segment_count + ((sp.flags & SUBPATH_CLOSED) ? 0 : 1);
}

struct StrokeSegment {
  Curve curve;
  uint32_t subpath;
  uint32_t index;  // within the subpath
};

// A body to build: segment `segment`'s curve on [t0, t1] (the whole
// segment, or a dash's part of it).
struct StrokePart {
  uint32_t segment;
  uint32_t pad = 0;
  double t0, t1;
};

// A span of a part, and a fit item (a knot interval of a span, a boundary role).
struct SpanRef {
  uint32_t part, index;
};
struct FitRef {
  uint32_t span;
  uint16_t interval, role;
};

// The flat input of the stage, as pointers into either executor's memory.
struct StrokeInput {
  const StrokeRecord* strokes;
  const StrokeSubpath* subpaths;
  const StrokeSegment* segments;
  const double* dashes;
  const double* dash_ends;   // per dash element, the pattern's sum up to it (StrokeBatch::dash_ends)
  const double* seg_length;  // measuring pass: arc length of each segment
  const double* seg_start;   // scan: arc length from the subpath's start
  const double* sub_length;  // arc length of each subpath
  const uint32_t* first_element;  // per subpath: its first element (see element_of)
  uint32_t nstrokes, nsubpaths, nsegments, nelements;
};

// ---------------------------------------------------------------- dashes

// More dashes than this in one subpath are not drawn as dashes: the stroke
// is drawn solid instead (Skia applies the same kind of limit).
constexpr double kMaxDashes = 1e6;

// The dash pattern of a stroke placed along a subpath of length len (SVG 2
// painting.html#StrokeDashing). Pattern element j of period k covers arc
// lengths [k sum + cum_j - offset, ... + d_j]; even elements are dashes.
// e[j] = d_0 + ... + d_j, summed in that order (StrokeBatch::dash_ends):
// cum_j is e[j - 1], and elements are found by binary search on e, with
// the same values a running sum over d gives, in O(log n).
struct DashPattern {
  const double* d;
  const double* e;
  uint32_t n;
  double sum, offset, len;

  MPVG_HD double cum(uint32_t j) const { return j == 0 ? 0.0 : e[j - 1]; }
  MPVG_HD double element_start(double k, uint32_t j) const { return k * sum + cum(j) - offset; }
  // The first j with e[j] > r (n if none): e ascends.
  MPVG_HD uint32_t first_end_above(double r) const {
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
      const uint32_t mid = lo + (hi - lo) / 2;
      if (r < e[mid])
        hi = mid;
      else
        lo = mid + 1;
    }
    return lo;
  }
  // The element whose interior follows arc length s (the one that begins
  // there at a boundary; never a zero-length one): *k its period.
  MPVG_HD uint32_t element_after(double s, double* k) const {
    const double q = s + offset;
    double per = floor(q / sum);
    double r = q - per * sum;
    if (r >= sum) r -= sum, per += 1;
    if (r < 0) r += sum, per -= 1;
    const uint32_t j = first_end_above(r);
    if (j < n) {
      *k = per;
      return j;
    }
    *k = per + 1;
    return 0;
  }
  // The element whose interior precedes arc length s (the one that ends
  // there at a boundary; never a zero-length one).
  MPVG_HD uint32_t element_before(double s) const {
    const double q = s + offset;
    double r = q - ceil(q / sum - 1) * sum;  // in (0, sum]
    if (r <= 0) r += sum;
    if (r > sum) r -= sum;
    // The first j with r <= e[j] and d[j] > 0: past the first with
    // r <= e[j], the first where e rises (zero-length elements keep it).
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
      const uint32_t mid = lo + (hi - lo) / 2;
      if (r <= e[mid])
        hi = mid;
      else
        lo = mid + 1;
    }
    if (lo == n) return n - 1;
    if (d[lo] > 0) return lo;
    const uint32_t j = first_end_above(e[lo]);
    return j < n ? j : n - 1;
  }
  // Whether arc length s lies strictly inside a dash.
  MPVG_HD bool inside_dash(double s) const {
    double k;
    const uint32_t j = element_after(s, &k);
    if (j % 2 != 0) return false;
    return element_start(k, j) < s;
  }
  // A closed subpath whose dashes run on through its start point: a dash
  // covers both its beginning and its end (or the whole of it). Its start
  // point is then a join, with no caps.
  MPVG_HD bool wraps() const {
    double k;
    return element_after(0, &k) % 2 == 0 && element_before(len) % 2 == 0;
  }
  // Whether element (k, j) is one of the subpath's dash positions (SVG 2
  // painting.html#TermDashPositions): it ends after the start or is a
  // zero-length element at the very start of an unshifted pattern, and it
  // begins before the end.
  MPVG_HD bool counts(double k, double start, double end) const {
    if (!(start < len) && !(len == 0 && start <= 0)) return false;
    if (end > 0) return true;
    return offset == 0 && k == 0 && start == 0;
  }
};

MPVG_HD_INLINE DashPattern dash_pattern_of(const StrokeInput& in, const StrokeRecord& st, double len) {
  return {in.dashes + st.dash_first, in.dash_ends + st.dash_first, st.dash_count, st.dash_sum, st.dash_offset, len};
}

// Whether a subpath of length len is stroked solid: no pattern, or more
// dashes than kMaxDashes.
MPVG_HD_INLINE bool solid(const StrokeRecord& st, double len) {
  return st.dash_count == 0 || len / st.dash_sum * double(st.dash_count) > kMaxDashes;
}

MPVG_HD_INLINE JoinStyle join_style(const StrokeRecord& st) { return {st.h, st.miter_limit, st.tol, st.join, st.cap}; }

// ---------------------------------------------------------------- elements

// The measuring pass: the arc length of segment i, as the dash table
// measures it (ArcTable); 0 for undashed strokes, which need no lengths.
MPVG_HD_INLINE double stroke_measure(const StrokeInput& in, uint32_t i) {
  const Curve& c = in.segments[i].curve;
  if (in.strokes[in.subpaths[in.segments[i].subpath].stroke].dash_count == 0) return 0;
  if (c.is_line()) return length(c.p[1] - c.p[0]);
  return ArcTable(c).total();
}

// The direction of travel at parameter t.
MPVG_HD_INLINE Vec2 direction_at(const Curve& c, double t) {
  Vec2 d = t == 0 ? c.start_tangent() : (t == 1 ? c.end_tangent() : normalized(c.derivative(t)));
  if (d.x == 0 && d.y == 0) d = c.start_tangent();
  return d;
}

// Segment element i: the caps and dots of the dashes on it, to `out`, and
// the parts of it to build bodies for, to parts(t0, t1).
template <class Sink, class Parts>
MPVG_HD void stroke_segment(const StrokeInput& in, uint32_t i, Emitter<Sink>& out, Parts&& parts) {
  const StrokeSegment& seg = in.segments[i];
  const StrokeSubpath& sp = in.subpaths[seg.subpath];
  const StrokeRecord& st = in.strokes[sp.stroke];
  const Curve& c = seg.curve;
  const double len = in.sub_length[seg.subpath];
  if (solid(st, len)) {
    parts(0.0, 1.0);
    return;
  }
  const JoinStyle js = join_style(st);
  const DashPattern dp = dash_pattern_of(in, st, len);
  const bool last = seg.index + 1 == sp.segment_count;
  const double s0 = in.seg_start[i];
  const double s1 = last ? len : in.seg_start[i + 1];
  const bool wrap = (sp.flags & SUBPATH_CLOSED) && dp.wraps();
  const ArcTable table(c);
  auto param = [&](double s) {
    if (s <= s0) return 0.0;
    if (s >= s1) return 1.0;
    return table.param_at(s - s0);
  };
  // Start before the element s0 falls in, two elements of some length
  // back (and the zero-length ones among them: dots at s0) against
  // rounding: elements further back end before s0 and add nothing. Stop
  // past the segment's end.
  double k;
  uint32_t j = dp.element_after(s0, &k);
  for (uint32_t back = 0, long_ones = 0; back <= dp.n && long_ones < 2; back++) {
    if (j == 0) j = dp.n, k -= 1;
    j--;
    if (dp.d[j] > 0) long_ones++;
  }
  const double guard = (s1 - s0) / dp.sum * dp.n + 4.0 * dp.n + 8;
  for (double it = 0; it < guard; it++) {
    const double start = dp.element_start(k, j), end = start + dp.d[j];
    if (start > s1) break;
    if (j % 2 == 0 && dp.counts(k, start, end)) {
      const double b = dmax(start, 0.0), e = dmin(end, len);
      if (b == e) {
        // A zero-length dash: a dot, drawn by the segment it begins.
        if ((b >= s0 && b < s1) || (last && b == s1)) emit_dot(js, c.point(param(b)), direction_at(c, param(b)), out);
      } else {
        const double lo = dmax(b, s0), hi = dmin(e, s1);
        if (hi > lo) {
          const double t0 = param(lo), t1 = param(hi);
          const Curve part = c.sub(t0, t1);
          if (part.extent() > 0) {
            parts(t0, t1);
            const bool begins = b >= s0 && b < s1 && !(wrap && b == 0);
            const bool ends = e > s0 && e <= s1 && !(wrap && e == len);
            if (begins) emit_cap(js, part.start(), part.start_tangent(), false, out);
            if (ends) emit_cap(js, part.end(), part.end_tangent(), true, out);
          } else if (b >= s0 && b < s1) {
            emit_dot(js, c.point(t0), direction_at(c, t0), out);
          }
        }
      }
    }
    if (++j == dp.n) j = 0, k += 1;
  }
}

// The subpath of vertex v and v's index in it (binary search on first_vertex).
MPVG_HD_INLINE uint32_t vertex_subpath(const StrokeInput& in, uint32_t v) {
  uint32_t lo = 0, hi = in.nsubpaths;
  while (hi - lo > 1) {
    const uint32_t mid = (lo + hi) / 2;
    if (in.subpaths[mid].first_vertex <= v)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

// Element e: elements come per subpath, its segments then its vertices,
// so that outputs come grouped by stroke; the subpath is found by binary
// search on first_element.
struct ElementRef {
  bool vertex;
  uint32_t index;  // segment or vertex
  uint32_t stroke;
};
MPVG_HD_INLINE ElementRef element_of(const StrokeInput& in, uint32_t e) {
  uint32_t lo = 0, hi = in.nsubpaths;
  while (hi - lo > 1) {
    const uint32_t mid = (lo + hi) / 2;
    if (in.first_element[mid] <= e)
      lo = mid;
    else
      hi = mid;
  }
  const StrokeSubpath& sp = in.subpaths[lo];
  const uint32_t k = e - in.first_element[lo];
  if (k < sp.segment_count) return {false, sp.first_segment + k, sp.stroke};
  return {true, sp.first_vertex + (k - sp.segment_count), sp.stroke};
}

// Vertex element v.
template <class Sink>
MPVG_HD void stroke_vertex(const StrokeInput& in, uint32_t v, Emitter<Sink>& out) {
  const uint32_t spi = vertex_subpath(in, v);
  const StrokeSubpath& sp = in.subpaths[spi];
  const StrokeRecord& st = in.strokes[sp.stroke];
  const JoinStyle js = join_style(st);
  const uint32_t k = v - sp.first_vertex;
  const double len = in.sub_length[spi];
  const bool is_solid = solid(st, len);
  if (sp.flags & SUBPATH_ZERO_LENGTH) {
    // A dot, when the pattern is "on" at the point: an unshifted pattern
    // always starts with a dash, a shifted one where the offset falls.
    double per;
    if (is_solid || st.dash_offset == 0 || dash_pattern_of(in, st, 0).element_after(0, &per) % 2 == 0)
      emit_dot(js, sp.start, Vec2{1, 0}, out);
    return;
  }
  const uint32_t n = sp.segment_count;
  const StrokeSegment* seg = in.segments + sp.first_segment;
  const bool closed = (sp.flags & SUBPATH_CLOSED) != 0;
  if (!closed && (k == 0 || k == n)) {
    // The caps of an undashed open subpath (dashes' caps are their segments').
    if (!is_solid) return;
    if (k == 0)
      emit_cap(js, seg[0].curve.start(), seg[0].curve.start_tangent(), false, out);
    else
      emit_cap(js, seg[n - 1].curve.end(), seg[n - 1].curve.end_tangent(), true, out);
    return;
  }
  // A join between the segment ending here and the one starting here, when
  // the stroke runs through the vertex.
  const Curve& prev = seg[k == 0 ? n - 1 : k - 1].curve;
  const Curve& next = seg[k].curve;
  if (!is_solid) {
    const DashPattern dp = dash_pattern_of(in, st, len);
    if (k == 0 ? !dp.wraps() : !dp.inside_dash(in.seg_start[sp.first_segment + k])) return;
  }
  emit_join(js, next.start(), prev.end_tangent(), next.start_tangent(), end_curvature(prev, true),
            end_curvature(next, false), out);
}

// ---------------------------------------------------------------- body items

// The curve of a part, and the half width and tolerance of its stroke.
struct PartCurve {
  Curve c;
  double h, tol;
  uint32_t stroke;
};
MPVG_HD_INLINE PartCurve part_curve(const StrokeInput& in, const StrokePart& p) {
  const StrokeSegment& seg = in.segments[p.segment];
  const StrokeRecord& st = in.strokes[in.subpaths[seg.subpath].stroke];
  return {seg.curve.sub(p.t0, p.t1), st.h, st.tol, in.subpaths[seg.subpath].stroke};
}

// Fit items of a span: knot intervals times boundary roles.
MPVG_HD_INLINE uint32_t span_fit_items(const Knots& kn) { return static_cast<uint32_t>((kn.n - 1) * span_roles(kn.span.kind)); }
MPVG_HD_INLINE FitRef fit_ref(uint32_t span, int nroles, uint32_t k) {
  return {span, static_cast<uint16_t>(k / nroles), static_cast<uint16_t>(k % nroles)};
}

}  // namespace mpvg::stroking
