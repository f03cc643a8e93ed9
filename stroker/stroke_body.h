// Stage "stroke", bodies: the region a segment's normals sweep, as closed
// positively oriented contours, built by parts, spans and fit items (see
// "bodies" below; both executors).
//
// A segment c(t) with unit tangent T(t), left normal n(t) = T rotated by
// +90° and signed curvature k(t) sweeps the normal segments
//   F(t, s) = c(t) + s n(t),   t in [0, 1], s in [-h, h]   (h = width / 2).
// With n' = -k |c'| T, the Jacobian of F is det[F_t, F_s] = |c'| (1 - s k).
// So the closed curve "offset s = -h forward, normal at t = 1, offset s = +h
// backward, normal at t = 0" winds +1 around every point it sweeps once,
// and more around points swept several times, as long as 1 - s k > 0 on the
// whole rectangle, i.e. as long as the radius of curvature 1/|k| exceeds h.
// Where it does not, the rectangle folds along the evolute s = 1/k(t) (the
// centres of curvature): past the fold the Jacobian is negative, and the
// naive outline winds -1 there, which would cancel other pieces (the inner
// offset's "swallowtail", the classic failure). The segment is split where
// |k| h = 1 and, where |k| h > 1, the rectangle is split along s = 1/k: the
// part with 1 - s k >= 0 is traced as it is, the part with 1 - s k <= 0
// reversed. Both pieces are bounded by an offset and the evolute; each winds
// +1 (or more) everywhere it covers, and together they cover exactly the
// swept normals (Nehab 2020 uses evolutes in these regions for the same
// reason). Offsets and evolutes are fitted by quadratics through the
// tangent-line intersection at the ends, split until 7 interior samples lie
// within the tolerance.
//
// Segments are first split at cusps (zero speed: the normal flips, and a
// disk of the stroke width joins the two sides), at inflections, where
// |k| h = 1, at extrema of k inside high-curvature spans (cusps of the
// evolute), and so that the tangent turns by at most 80° per fitted span.
//
// Everything here runs in bounded memory without allocation: the breaks of
// a part and the knots of a span are fixed arrays, and the fitter walks its
// subdivision with an explicit stack whose every decision depends on the
// interval alone (a contour runs along one side forwards and the other
// backwards: the same pieces, reversed).
#pragma once
#include <cstdint>

#include "stroker/stroke_curve.h"
#include "stroker/stroke_output.h"

namespace mpvg::stroking {

// ---------------------------------------------------------------- boundaries

// The moving frame of a segment over one span [a, b] of its parameter: the
// unit tangent, with the values at the ends given (limits from inside the
// span at cusps and at coincident control points).
struct Frame {
  const Curve* c;
  double a, b;
  Vec2 ta, tb;

  MPVG_HD Vec2 tangent(double t) const {
    if (t == a) return ta;
    if (t == b) return tb;
    const Vec2 d = normalized(c->derivative(t));
    if (d.x != 0 || d.y != 0) return d;
    return normalized(c->point(dmin(b, t + 1e-9)) - c->point(dmax(a, t - 1e-9)));
  }
};

// A curve bounding a body piece: the offset at signed distance s, or the
// evolute c + n / k clamped to |1/k| <= h (only used where |k| h >= 1).
struct Boundary {
  Frame f;
  bool evolute = false;
  double s = 0;  // offset distance
  double h = 0;  // half width (evolute clamp)
  int side = 0;  // evolute: +1 centres of curvature on the left, -1 right

  // The point at t; *dir is a direction of its tangent line (offsets are
  // parallel to the path, the evolute is normal to it).
  MPVG_HD Vec2 point(double t, Vec2* dir) const {
    const Vec2 T = f.tangent(t), n = rot90(T);
    const Vec2 p = f.c->point(t);
    if (!evolute) {
      *dir = T;
      return p + s * n;
    }
    *dir = n;
    return p + radius(t) * n;
  }

  // Signed radius of curvature |c'|^3 / (c' x c''), clamped to the span's
  // side and to h: it tends to 0 at cusps and is at most h in these spans.
  MPVG_HD double radius(double t) const {
    Vec2 d1, d2;
    f.c->derivatives(t, &d1, &d2);
    const double sp = length(d1), cr = cross(d1, d2);
    if (!(sp > 0)) return 0;
    const double r = sp * sp * sp / cr;
    if (side > 0) return (cr > 0 && r < h) ? r : h;
    return (cr < 0 && r > -h) ? r : -h;
  }
};

MPVG_HD_INLINE double dist_segment(Vec2 x, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double l2 = dot(ab, ab);
  const double u = l2 > 0 ? dclamp(dot(x - a, ab) / l2, 0.0, 1.0) : 0.0;
  return length(x - (a + u * ab));
}

// Distance from x to the quadratic Bezier (p0, p1, p2), by Newton's method
// on dot(Q(u) - x, Q'(u)) = 0 from `guess`; when that does not land within
// `enough`, from the best of 9 samples as well. Any point of the curve
// gives an upper bound, so the result never underestimates.
MPVG_HD_INLINE double dist_quad(Vec2 x, Vec2 p0, Vec2 p1, Vec2 p2, double guess, double enough) {
  const Vec2 a = p0 - 2 * p1 + p2, b = p1 - p0;  // Q(u) = p0 + 2u b + u^2 a
  auto q = [&](double u) { return p0 + (2 * u) * b + (u * u) * a; };
  auto newton = [&](double u) {
    for (int it = 0; it < 6; it++) {
      const Vec2 r = q(u) - x, d1 = 2 * (b + u * a);
      const double f = dot(r, d1), fp = dot(d1, d1) + 2 * dot(r, a);
      if (!(fp > 0)) break;
      u = dclamp(u - f / fp, 0.0, 1.0);
    }
    return length(q(u) - x);
  };
  const double d = newton(guess);
  if (d <= enough) return d;
  double best_u = 0, best = length(x - p0);
  for (int k = 1; k <= 8; k++) {
    const double u = k / 8.0, e = length(q(u) - x);
    if (e < best) best = e, best_u = u;
  }
  return dmin(dmin(d, best), newton(best_u));
}

// ---------------------------------------------------------------- fitting

// Deeper than this, a piece that still does not fit is a line: the fitter
// never makes more than 2^kFitDepth pieces per knot interval, and its
// pieces depend only on the interval, not on the order of the walk.
constexpr int kFitDepth = 16;

// Bisection of [lo, hi] where pred holds at lo and not at hi: `steps`
// halvings keep it so, and the middle of what is left is returned.
template <class Pred>
MPVG_HD_INLINE double bisect(double lo, double hi, int steps, Pred&& pred) {
  for (int it = 0; it < steps; it++) {
    const double m = (lo + hi) / 2;
    if (pred(m))
      lo = m;
    else
      hi = m;
  }
  return (lo + hi) / 2;
}

// Where to split a piece that does not fit: where the tangent has turned
// half way when it turns noticeably or unevenly in t (near-cusps turn
// within a tiny range of t), else in the middle.
MPVG_HD_INLINE double fit_split(const Boundary& g, double u, double v, bool uneven) {
  const Vec2 tu = g.f.tangent(u), tv = g.f.tangent(v);
  const double phi = atan2(cross(tu, tv), dot(tu, tv));
  if (!uneven && fabs(phi) < 0.35) return (u + v) / 2;
  if (phi == 0 || fabs(phi) > kPi - 1e-6) return (u + v) / 2;
  // The tangent turns one way from tu to tv: it has turned half way once
  // it is past their bisector.
  const Vec2 half = normalized(tu + tv);
  const double dir = phi > 0 ? 1 : -1;
  const double m = bisect(u, v, 40, [&](double x) { return dir * cross(half, g.f.tangent(x)) < 0; });
  return (m > u && m < v) ? m : (u + v) / 2;
}

// Fits the boundary on [u, v] or tells where to split it. The boundary is
// a convex arc here (its tangent turns one way, by less than 80°), so it
// lies in the triangle of its chord and end tangents: the triangle's
// height bounds its distance from the chord. Its deviation from a
// quadratic is measured at 7 samples, which must be spread along the arc:
// where the tangent turns within a tiny range of t (near-cusps), samples
// uniform in t all fall at one end, which the even turning check detects.
// Returns true with *out set when [u, v] is one piece, else false with
// *split set.
// pu, du and pv, dv are the boundary's points and tangent directions at u
// and v (g.point).
MPVG_HD_INLINE bool fit_piece(const Boundary& g, double tol, double u, double v, Vec2 pu, Vec2 du, Vec2 pv, Vec2 dv,
                              int depth, Piece* out, double* split) {
  if (depth >= kFitDepth || !(v - u > 1e-15)) {
    *out = {CURVE_LINE, pu, {}, pv};
    return true;
  }
  Vec2 s[7], ds[7];
  for (int k = 0; k < 7; k++) s[k] = g.point(u + (v - u) * (k + 1) / 8.0, &ds[k]);
  // The turn between samples, as sin of the angle (cheap, and a slight
  // underestimate: a near-cusp puts almost all of the turn in one step).
  auto step_turn = [](Vec2 a, Vec2 b) { return dot(a, b) > 0 ? fabs(cross(a, b)) : 1.0; };
  const double total = atan2(cross(du, dv), dot(du, dv));
  double step = step_turn(du, ds[0]);
  for (int k = 0; k < 6; k++) step = dmax(step, step_turn(ds[k], ds[k + 1]));
  step = dmax(step, step_turn(ds[6], dv));
  const bool even = step <= 0.4 * fabs(total) + 0.02;
  const Vec2 chord = pv - pu;
  const double len = length(chord);
  if (even) {
    // A line when the arc's triangle is flat: its height is at most
    // len * min(tan a, tan b) for the angles a, b of the end tangents with
    // the chord.
    auto tan_to_chord = [&](Vec2 d) {
      const double c = fabs(dot(d, chord));
      return c > 0 ? fabs(cross(d, chord)) / c : HUGE_VAL;
    };
    const double height = len * dmin(tan_to_chord(du), tan_to_chord(dv));
    double err = 0;
    for (int k = 0; k < 7; k++) err = dmax(err, dist_segment(s[k], pu, pv));
    if (err <= tol && height <= tol) {
      *out = {CURVE_LINE, pu, {}, pv};
      return true;
    }
    // The quadratic whose control point is where the end tangents meet. It
    // must run forwards along the chord, with a control polygon no longer
    // than twice the chord.
    const double den = cross(du, dv);
    if (fabs(den) > 1e-9) {
      const Vec2 p1 = pu + (cross(chord, dv) / den) * du;
      if (dot(p1 - pu, chord) > 0 && dot(pv - p1, chord) > 0 && length(p1 - pu) + length(pv - p1) <= 2 * len) {
        err = 0;
        for (int k = 0; k < 7 && err <= tol; k++) err = dmax(err, dist_quad(s[k], pu, p1, pv, (k + 1) / 8.0, tol));
        if (err <= tol) {
          *out = {CURVE_QUAD, pu, p1, pv};
          return true;
        }
      }
    }
  }
  *split = fit_split(g, u, v, !even);
  return false;
}

// The pieces of the boundary over [u, v] (each reversed when backwards),
// to the sink. The walk is depth first with an explicit stack; every
// decision depends on the interval alone.
// A line a -> b to the sink, unless it has no length.
template <class Sink>
MPVG_HD void emit_line(Sink& out, Vec2 a, Vec2 b) {
  if (!(a == b)) out.segment(CURVE_LINE, a, b, b, 1);
}

// A fitted piece to the sink (reversed when backwards), unless degenerate.
template <class Sink>
MPVG_HD void emit_piece(Sink& out, Piece q, bool backwards) {
  if (backwards) q = reversed(q);
  if (q.type == CURVE_LINE)
    emit_line(out, q.p0, q.p2);
  else if (q.p0 != q.p2 || q.p1 != q.p0)
    out.segment(q.type, q.p0, q.p1, q.p2, q.w);
}

template <class Sink>
MPVG_HD void fit_interval(const Boundary& g, double tol, double u, double v, bool backwards, Sink& out) {
  // Each node carries its ends' points, computed once where it was split
  // off (the same values g.point gives there: the pieces do not change).
  struct Node {
    double u, v;
    Vec2 pu, du, pv, dv;
    int depth;
  };
  Node stack[kFitDepth + 2];
  int top = 0;
  Node root{u, v, {}, {}, {}, {}, 0};
  root.pu = g.point(u, &root.du);
  root.pv = g.point(v, &root.dv);
  stack[top++] = root;
  while (top > 0) {
    const Node nd = stack[--top];
    Piece pc;
    double m = 0;
    if (fit_piece(g, tol, nd.u, nd.v, nd.pu, nd.du, nd.pv, nd.dv, nd.depth, &pc, &m)) {
      emit_piece(out, pc, backwards);
      continue;
    }
    Vec2 dm;
    const Vec2 pm = g.point(m, &dm);
    stack[top++] = {m, nd.v, pm, dm, nd.pv, nd.dv, nd.depth + 1};
    stack[top++] = {nd.u, m, nd.pu, nd.du, pm, dm, nd.depth + 1};
  }
}

// ---------------------------------------------------------------- analysis

MPVG_HD_INLINE double golden_min(const Curve& c, double lo, double hi, int what, double sign);

// c' x c'', zero where it is at the level of rounding (straight curves).
MPVG_HD_INLINE double curl(Vec2 d1, Vec2 d2) {
  const double cr = cross(d1, d2);
  return fabs(cr) <= 1e-12 * length(d1) * length(d2) ? 0 : cr;
}

// Golden-section search of the minimum of f on [lo, hi] (maximum with
// sign -1), for f the squared speed (what 0) or the radius of curvature
// |c'|^3 / (c' x c'') (what 1).
MPVG_HD_INLINE double golden_value(const Curve& c, double t, int what) {
  Vec2 d1, d2;
  c.derivatives(t, &d1, &d2);
  if (what == 0) return dot(d1, d1);
  const double s = length(d1);
  return s * s * s / cross(d1, d2);
}
MPVG_HD_INLINE double golden_min(const Curve& c, double lo, double hi, int what, double sign) {
  const double g = 0.6180339887498949;  // (sqrt(5) - 1) / 2
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = sign * golden_value(c, x1, what), f2 = sign * golden_value(c, x2, what);
  for (int i = 0; i < 80; i++) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - g * (hi - lo), f1 = sign * golden_value(c, x1, what);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + g * (hi - lo), f2 = sign * golden_value(c, x2, what);
    }
  }
  return (lo + hi) / 2;
}

// A segment's breaks: the ends, cusps, inflections and crossings of
// |k| h = 1, in order. Spans lie between consecutive breaks.
constexpr int kMaxBreaks = 40;

struct Breaks {
  double t[kMaxBreaks];
  bool cusp[kMaxBreaks];
  int n = 0;
};

class Analysis {
 public:
  MPVG_HD Analysis(const Curve& c, double h) : c_(c), h_(h) {}

  // The kind of body of a span: 0 normal (|k| h < 1), +1 / -1 high
  // curvature with the centres of curvature on the left / right.
  MPVG_HD int kind_at(double t) const {
    Vec2 d1, d2;
    c_.derivatives(t, &d1, &d2);
    const double sp = length(d1), cr = curl(d1, d2);
    if (!(h_ * fabs(cr) > sp * sp * sp)) return 0;
    return cr > 0 ? 1 : -1;
  }

  // The unit tangent at t, the limit from inside [t, other] (at_start) or
  // [other, t]: from the control points at the curve's ends, from a secant
  // at a cusp (where c' vanishes and flips), else from c'.
  MPVG_HD Vec2 end_tangent(double t, double other, bool cusp, bool at_start) const {
    if (t == 0) return c_.start_tangent();
    if (t == 1) return c_.end_tangent();
    const Vec2 d = normalized(c_.derivative(t));
    if (!cusp && (d.x != 0 || d.y != 0)) return d;
    const double delta = dmin(kCuspGuard, fabs(other - t) / 4);
    return at_start ? normalized(c_.point(t + delta) - c_.point(t)) : normalized(c_.point(t) - c_.point(t - delta));
  }

  MPVG_HD void find_breaks(Breaks& br) {
    br.n = 0;
    ncusps_ = 0;
    const double e = c_.extent();
    // The derivatives on the uniform grid, once.
    Sample smp[kSamples + 1];
    double max_speed = 0;
    for (int i = 0; i <= kSamples; i++) {
      Vec2 d1, d2;
      c_.derivatives(t_of(i), &d1, &d2);
      smp[i] = {dot(d1, d1), cross(d1, d2), length(d1), length(d2)};
      max_speed = dmax(max_speed, smp[i].len1);
    }
    // The searches below are listed first (sample bit masks) and then run
    // one after another: on the GPU, the threads of a warp then run their
    // k-th searches together instead of each at its own sample.
    // Speed minima: cusps where the speed vanishes (the tangent reverses),
    // and sharp near-cusps, where the tangent turns fast.
    uint64_t minima = 0;
    for (int i = 1; i < kSamples; i++) {
      const double s0 = smp[i - 1].speed2, s1 = smp[i].speed2, s2 = smp[i + 1].speed2;
      // Sampled this fast, the speed cannot drop near zero between samples.
      if (s1 <= s0 && s1 <= s2 && (s1 < s0 || s1 < s2) && !(s1 > 0.0625 * max_speed * max_speed))
        minima |= uint64_t{1} << i;
    }
    for (; minima; minima &= minima - 1) {
      const int i = lowest_bit(minima);
      const double tm = golden_min(c_, t_of(i - 1), t_of(i + 1), 0, 1);
      const double sp = sqrt(speed2(tm));
      if (sp <= 1e-10 * e)
        add(br, tm, true);
      else if (sp < 0.05 * max_speed)
        add(br, tm, false);
    }
    // Inflections: sign changes of c' x c'' (values at rounding level count
    // as zero, so straight curves have none), between a sample and the
    // previous one that counts.
    {
      uint64_t counted = 0, changes = 0;
      int last = -1;
      bool last_pos = false;
      for (int i = 0; i <= kSamples; i++) {
        const double v = smp[i].cr;
        if (fabs(v) <= 1e-12 * smp[i].len1 * smp[i].len2) continue;
        if (last >= 0 && (v > 0) != last_pos) changes |= uint64_t{1} << i;
        counted |= uint64_t{1} << i;
        last = i;
        last_pos = v > 0;
      }
      for (; changes; changes &= changes - 1) {
        const int i = lowest_bit(changes);
        const int prev = highest_bit(counted & ((uint64_t{1} << i) - 1));
        const bool prev_pos = smp[prev].cr > 0;
        add(br, bisect(t_of(prev), t_of(i), 60, [&](double m) { return (cross_at(m) > 0) == prev_pos; }), false);
      }
    }
    push(br, 0, false);
    push(br, 1, false);
    sort_breaks(br);
    // Where |k| h crosses 1, sampled on the uniform grid and at the breaks
    // so far (curvature peaks sit at near-cusps), merged in order.
    // Curvature is infinite at a cusp, and near one only noise decides.
    // The intervals are listed first and then searched (see above).
    double cross_lo[kMaxBreaks], cross_hi[kMaxBreaks];
    uint64_t cross_from_high = 0;
    int ncross = 0;
    {
      int b = 0;
      bool have = false;
      double prev_t = 0;
      bool prev_high = false;
      auto visit = [&](double t, bool high) {
        if (have && high != prev_high && t > prev_t && ncross < kMaxBreaks) {
          if (prev_high) cross_from_high |= uint64_t{1} << ncross;
          cross_lo[ncross] = prev_t;
          cross_hi[ncross++] = t;
        }
        have = true;
        prev_t = t;
        prev_high = high;
      };
      for (int i = 0; i <= kSamples + 1; i++) {
        const double ti = i <= kSamples ? t_of(i) : 2;
        for (; b < br.n && br.t[b] < ti; b++)
          visit(br.t[b], br.cusp[b] || near_cusp(br.t[b]) || excess(br.t[b]) > 0);
        if (i <= kSamples) visit(ti, sample_high(i, smp[i]));
      }
    }
    for (int k = 0; k < ncross; k++) {
      const bool h0 = (cross_from_high >> k) & 1;
      cross_lo[k] = bisect(cross_lo[k], cross_hi[k], 60, [&](double m) { return (excess(m) > 0) == h0; });
    }
    for (int k = 0; k < ncross; k++) add(br, cross_lo[k], false);
    sort_breaks(br);
  }

  // Knots of span [a, b] (of `kind`): its ends, the cusps of the evolute in
  // high-curvature spans (extrema of the radius of curvature), and points
  // that keep the tangent's turn below 80° between knots. Returns the count.
  static constexpr int kMaxKnots = 32;
  MPVG_HD int knots(double a, double b, Vec2 ta, Vec2 tb, int kind, double* k) const {
    int nk = 0;
    k[nk++] = a;
    k[nk++] = b;
    const Frame f{&c_, a, b, ta, tb};
    constexpr int n = 16;
    double t[n + 1];
    for (int i = 0; i <= n; i++) t[i] = a + (b - a) * i / n;
    t[n] = b;
    if (kind != 0) {
      // Listed first, then searched (as in find_breaks).
      double r[n + 1];
      for (int i = 0; i <= n; i++) r[i] = golden_value(c_, t[i], 1);
      uint32_t extrema = 0, maxima = 0;
      for (int i = 1; i < n; i++) {
        const bool is_max = r[i] > r[i - 1] && r[i] >= r[i + 1];
        const bool is_min = r[i] < r[i - 1] && r[i] <= r[i + 1];
        if ((is_max || is_min) && finite(r[i])) extrema |= 1u << i;
        if (is_max) maxima |= 1u << i;
      }
      for (; extrema && nk < kMaxKnots; extrema &= extrema - 1) {
        const int i = lowest_bit(extrema);
        k[nk++] = golden_min(c_, t[i - 1], t[i + 1], 1, (maxima >> i) & 1 ? -1 : 1);
      }
    }
    // Turning: the tangent turns one way inside a span (spans end at
    // inflections and cusps); accumulate it, and split every ~75°.
    Vec2 d1, d2;
    c_.derivatives((a + b) / 2, &d1, &d2);
    const double dir = cross(d1, d2) >= 0 ? 1 : -1;
    auto turn = [&](Vec2 x, Vec2 y) {
      double an = atan2(cross(x, y), dot(x, y));
      if (an * dir < 0 && fabs(an) > 1e-9) an += dir * 2 * kPi;
      return an;
    };
    double acc[n + 1];
    Vec2 T[n + 1];
    for (int i = 0; i <= n; i++) T[i] = f.tangent(t[i]);
    acc[0] = 0;
    for (int i = 0; i < n; i++) acc[i + 1] = acc[i] + turn(T[i], T[i + 1]);
    const double total = fabs(acc[n]);
    const double max_turn = 75 * kPi / 180;
    if (total > max_turn * 1.07) {
      const int m = static_cast<int>(ceil(total / max_turn));
      for (int j = 1; j < m && nk < kMaxKnots; j++) {
        const double target = acc[n] * j / m;
        int i = 0;
        while (i < n - 1 && fabs(acc[i + 1]) < fabs(target)) i++;
        const double local = target - acc[i];
        k[nk++] = bisect(t[i], t[i + 1], 60, [&](double x) { return fabs(turn(T[i], f.tangent(x))) < fabs(local); });
      }
    }
    // Sorted (insertion sort: few knots), duplicates removed, ends exact.
    for (int i = 1; i < nk; i++) {
      const double x = k[i];
      int j = i - 1;
      while (j >= 0 && k[j] > x) k[j + 1] = k[j], j--;
      k[j + 1] = x;
    }
    int m = 0;
    for (int i = 0; i < nk; i++)
      if (m == 0 || k[i] - k[m - 1] > 1e-12) k[m++] = k[i];
    k[0] = a;
    if (k[m - 1] != b) {
      if (m > 1 && b - k[m - 1] <= 1e-12)
        k[m - 1] = b;
      else
        k[m++] = b;
    }
    return m;
  }

 private:
  static constexpr int kSamples = 48;
  // Within this distance of a cusp (in t), c' is at the level of rounding
  // noise: its direction and the signs of c' x c'' are meaningless there.
  // Other breaks are not placed that close, and the tangents at a cusp come
  // from secants this long (see end_tangent).
  static constexpr double kCuspGuard = 1e-6;
  static constexpr int kMaxCusps = 8;
  struct Sample {
    double speed2, cr, len1, len2;  // |c'|^2, c' x c'', |c'|, |c''|
  };

  MPVG_HD static double t_of(int i) { return double(i) / kSamples; }
  MPVG_HD double speed2(double t) const {
    const Vec2 d = c_.derivative(t);
    return dot(d, d);
  }
  MPVG_HD double cross_at(double t) const {
    Vec2 a, b;
    c_.derivatives(t, &a, &b);
    return cross(a, b);
  }
  // (h |k| - 1) |c'|^3 = h |c' x c''| - |c'|^3: positive where |k| h > 1.
  // At the curve's ends the speed may vanish (coincident control points):
  // the value just inside stands for the limit there.
  MPVG_HD double excess(double t) const {
    t = dclamp(t, 1e-7, 1 - 1e-7);
    Vec2 d1, d2;
    c_.derivatives(t, &d1, &d2);
    const double sp = length(d1);
    return h_ * fabs(curl(d1, d2)) - sp * sp * sp;
  }
  MPVG_HD bool near_cusp(double t) const {
    for (int i = 0; i < ncusps_; i++)
      if (fabs(t - cusps_[i]) < kCuspGuard) return true;
    return false;
  }
  MPVG_HD bool sample_high(int i, const Sample& sm) const {
    const double t = t_of(i);
    if (near_cusp(t)) return true;
    if (i == 0 || i == kSamples) return excess(t) > 0;
    const double cr = fabs(sm.cr) <= 1e-12 * sm.len1 * sm.len2 ? 0 : sm.cr;
    return h_ * fabs(cr) - sm.len1 * sm.len1 * sm.len1 > 0;
  }
  MPVG_HD void push(Breaks& br, double t, bool cusp) const {
    if (br.n < kMaxBreaks) {
      br.t[br.n] = t;
      br.cusp[br.n] = cusp;
      br.n++;
    }
  }
  // An interior break; breaks other than cusps keep away from cusps. Room
  // is kept for the two ends.
  MPVG_HD void add(Breaks& br, double t, bool cusp) {
    if (!(t > 0 && t < 1)) return;
    if (!cusp && near_cusp(t)) return;
    if (br.n >= kMaxBreaks - 2) return;
    if (cusp && ncusps_ < kMaxCusps) cusps_[ncusps_++] = t;
    push(br, t, cusp);
  }
  MPVG_HD static void sort_breaks(Breaks& br) {
    for (int i = 1; i < br.n; i++) {
      const double x = br.t[i];
      const bool cx = br.cusp[i];
      int j = i - 1;
      while (j >= 0 && br.t[j] > x) {
        br.t[j + 1] = br.t[j];
        br.cusp[j + 1] = br.cusp[j];
        j--;
      }
      br.t[j + 1] = x;
      br.cusp[j + 1] = cx;
    }
    int m = 0;
    for (int i = 0; i < br.n; i++) {
      if (m > 0 && br.t[i] - br.t[m - 1] <= 1e-12) {
        br.cusp[m - 1] = br.cusp[m - 1] || br.cusp[i];
        if (br.t[i] == 1) br.t[m - 1] = 1;
        continue;
      }
      br.t[m] = br.t[i];
      br.cusp[m] = br.cusp[i];
      m++;
    }
    br.n = m;
    // The ends stay exactly 0 and 1.
    br.t[0] = 0;
    br.cusp[0] = false;
    br.t[m - 1] = 1;
    br.cusp[m - 1] = false;
  }

  const Curve& c_;
  double h_;
  double cusps_[kMaxCusps];
  int ncusps_ = 0;
};

// ---------------------------------------------------------------- bodies

// A body is built by three kinds of work items, each independent of the
// others of its kind, so that a long curve is spread over many threads:
//   - the part (one per segment, or per dash's part of it): its analysis
//     (the breaks, stored), and what ties its boundaries into closed
//     contours: the normals at the ends of each run, the lines (almost
//     always of zero length, then nothing) between spans inside a run, and
//     a disk at each cusp; a line's body is its rectangle, here;
//   - the span (between consecutive breaks): its knots, stored;
//   - the fit item (a knot interval of a span, and a boundary role): the
//     fitted pieces of one boundary over that interval.
// A run of spans of one kind with no cusp between them is one or two closed
// contours, "boundary X forwards, boundary Y backwards": a normal run the
// right offset and the left offset; a high-curvature run the part with
// 1 - s k >= 0 (an offset and the evolute) and, traced reversed, the part
// with 1 - s k <= 0 (the other offset and the evolute). Pieces of a
// boundary meet exactly (the same function at the same parameter), so the
// contours close however their pieces are spread.

// One span of a curve, between breaks i and i + 1.
struct Span {
  double a, b;
  Vec2 ta, tb;
  int kind;
};

MPVG_HD_INLINE Span span_of(const Analysis& an, const Breaks& br, int i) {
  Span sp;
  sp.a = br.t[i];
  sp.b = br.t[i + 1];
  sp.ta = an.end_tangent(sp.a, sp.b, br.cusp[i], true);
  sp.tb = an.end_tangent(sp.b, sp.a, br.cusp[i + 1], false);
  sp.kind = an.kind_at((sp.a + sp.b) / 2);
  return sp;
}

// Boundary roles of a span of `kind`: 2 for a normal span (the contour's
// X and Y), 4 for a high-curvature one (two contours).
MPVG_HD_INLINE int span_roles(int kind) { return kind == 0 ? 2 : 4; }

struct Role {
  bool evolute;
  double s;  // offset distance (offsets)
  bool backwards;
};
MPVG_HD_INLINE Role span_role(int kind, int r, double h) {
  if (kind == 0) return r == 0 ? Role{false, -h, false} : Role{false, h, true};
  if (kind > 0) {
    // Centres of curvature on the left: s in [1/k, h] apart (left offset,
    // evolute); s in [-h, 1/k] as it is (right offset, evolute).
    switch (r) {
      case 0: return {false, h, false};
      case 1: return {true, 0, true};
      case 2: return {false, -h, false};
      default: return {true, 0, true};
    }
  }
  // Centres on the right: s in [-h, 1/k] apart (evolute, right offset);
  // s in [1/k, h] as it is (evolute, left offset).
  switch (r) {
    case 0: return {true, 0, false};
    case 1: return {false, -h, true};
    case 2: return {true, 0, false};
    default: return {false, h, true};
  }
}

MPVG_HD_INLINE Boundary boundary_of(const Curve& c, const Span& sp, const Role& role, double h) {
  Boundary g;
  g.f = {&c, sp.a, sp.b, sp.ta, sp.tb};
  g.evolute = role.evolute;
  g.s = role.s;
  g.h = h;
  g.side = sp.kind;
  return g;
}

// The part's analysis: its breaks (none for a line). Returns its spans.
MPVG_HD_INLINE int analyse_part(const Curve& c, double h, Breaks& br) {
  if (c.is_line()) {
    br.n = 0;
    return 0;
  }
  Analysis(c, h).find_breaks(br);
  return br.n - 1;
}

// The part item's own output: a line's rectangle, or the ties of the runs
// (see above) and the disks at cusps.
template <class Sink>
MPVG_HD void emit_part(const Curve& c, double h, const Breaks& br, Sink& sink) {
  if (c.is_line()) {
    const Vec2 n = h * rot90(normalized(c.p[1] - c.p[0]));
    const Vec2 q[4] = {c.p[0] - n, c.p[1] - n, c.p[1] + n, c.p[0] + n};
    for (int k = 0; k < 4; k++) emit_line(sink, q[k], q[(k + 1) % 4]);
    return;
  }
  const Analysis an(c, h);
  const int nspans = br.n - 1;
  int i = 0;
  while (i < nspans) {
    const int kind = an.kind_at((br.t[i] + br.t[i + 1]) / 2);
    int j = i + 1;
    while (j < nspans && !br.cusp[j] && an.kind_at((br.t[j] + br.t[j + 1]) / 2) == kind) j++;
    if (i > 0 && br.cusp[i]) {
      Emitter<Sink> out(sink);
      out.disk(c.point(br.t[i]), h);
    }
    const Span first = span_of(an, br, i), last = span_of(an, br, j - 1);
    for (int q = 0; q < span_roles(kind) / 2; q++) {
      const Role rx = span_role(kind, 2 * q, h), ry = span_role(kind, 2 * q + 1, h);
      Vec2 d;
      const Vec2 xa = boundary_of(c, first, rx, h).point(first.a, &d);
      const Vec2 xb = boundary_of(c, last, rx, h).point(last.b, &d);
      const Vec2 ya = boundary_of(c, first, ry, h).point(first.a, &d);
      const Vec2 yb = boundary_of(c, last, ry, h).point(last.b, &d);
      emit_line(sink, xb, yb);  // the normal at the run's end
      emit_line(sink, ya, xa);  // and at its start
      // Between spans of the run: X forwards, Y backwards.
      for (int k = i; k + 1 < j; k++) {
        const Span s0 = span_of(an, br, k), s1 = span_of(an, br, k + 1);
        const Vec2 x0 = boundary_of(c, s0, rx, h).point(s0.b, &d), x1 = boundary_of(c, s1, rx, h).point(s1.a, &d);
        const Vec2 y0 = boundary_of(c, s0, ry, h).point(s0.b, &d), y1 = boundary_of(c, s1, ry, h).point(s1.a, &d);
        emit_line(sink, x0, x1);
        emit_line(sink, y1, y0);
      }
    }
    i = j;
  }
}

// The span item: span i of a part with its knots (Analysis::knots).
struct Knots {
  Span span;
  double k[Analysis::kMaxKnots];
  int n = 0;
};
MPVG_HD_INLINE void span_knots(const Curve& c, double h, const Breaks& br, int i, Knots& out) {
  const Analysis an(c, h);
  const Span sp = span_of(an, br, i);
  out.span = sp;
  out.n = an.knots(sp.a, sp.b, sp.ta, sp.tb, sp.kind, out.k);
}

// The fit item: boundary `role` of span i over knot interval x, fitted to
// 3/4 of the tolerance.
template <class Sink>
MPVG_HD void fit_item(const Curve& c, double h, double tol, const Knots& kn, int x, int role, Sink& sink) {
  const Role r = span_role(kn.span.kind, role, h);
  const Boundary g = boundary_of(c, kn.span, r, h);
  fit_interval(g, 0.75 * tol, kn.k[x], kn.k[x + 1], r.backwards, sink);
}

}  // namespace mpvg::stroking
