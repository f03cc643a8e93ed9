// Stage "stroke", joins and caps (SVG 2 painting.html#LineJoin and
// #LineCaps), one thread per vertex or end, as closed positively oriented
// contours (both executors).
//
// A round join or cap is a whole disk: it contains the SVG shape, and what
// it adds lies within half the width of the path, so the stroke stays the
// set of points within h of the path for round joins and caps, exactly.
// Other joins are convex polygons on the vertex (bevel, miter, miter-clip)
// or, for arcs, the region bounded by the vertex and the outer edges'
// osculating circles, clipped at the miter limit.
#pragma once
#include <cstdint>

#include "stroker/stroke_curve.h"
#include "stroker/stroke_output.h"

namespace mpvg::stroking {

enum : uint32_t { JOIN_MITER = 0, JOIN_MITER_CLIP = 1, JOIN_ARCS = 2, JOIN_ROUND = 3, JOIN_BEVEL = 4 };
enum : uint32_t { CAP_BUTT = 0, CAP_ROUND = 1, CAP_SQUARE = 2 };

// What joins and caps need of a stroke's style, in user units.
struct JoinStyle {
  double h;            // half width
  double miter_limit;  // at least 1
  double tol;          // tolerance
  uint32_t join, cap;
};

// Signed curvature at an end of a segment (lines: 0); NaN where the speed
// vanishes (coincident control points: infinite curvature).
MPVG_HD_INLINE double end_curvature(const Curve& c, bool at_end) {
  if (c.is_line()) return 0;
  Vec2 d1, d2;
  c.derivatives(at_end ? 1 : 0, &d1, &d2);
  const double sp = length(d1);
  if (!(sp > 1e-12 * c.extent())) return NAN;
  return cross(d1, d2) / (sp * sp * sp);
}

// The cap shape at an end of an open subpath or dash; t is the direction
// of travel there. Nothing for butt caps.
template <class Sink>
MPVG_HD void emit_cap(const JoinStyle& st, Vec2 p, Vec2 t, bool at_end, Emitter<Sink>& out) {
  if (st.cap == CAP_ROUND) {
    out.disk(p, st.h);
  } else if (st.cap == CAP_SQUARE) {
    const Vec2 n = st.h * rot90(t), e = (at_end ? st.h : -st.h) * t;
    const Vec2 q[4] = {p - n, p + e - n, p + e + n, p + n};
    out.polygon(q, 4);
  }
}

// A zero-length subpath or dash at p, its caps oriented along dir
// (SVG 2 painting.html#LineCaps: a dot or a square; nothing for butt).
template <class Sink>
MPVG_HD void emit_dot(const JoinStyle& st, Vec2 p, Vec2 dir, Emitter<Sink>& out) {
  if (st.cap == CAP_ROUND) {
    out.disk(p, st.h);
  } else if (st.cap == CAP_SQUARE) {
    const Vec2 t = st.h * dir, n = rot90(t);
    const Vec2 q[4] = {p - t - n, p + t - n, p + t + n, p - t + n};
    out.polygon(q, 4);
  }
}

namespace join_detail {

// One outer edge extended past the join: a circle (centre, radius) or, for
// zero curvature, a line (through a point, along a direction).
struct Edge {
  bool line;
  Vec2 o;
  double r;
  Vec2 q, d;
};

// An element of the arcs join's boundary: a line a -> b or an arc, with a
// parameter in [0, 1].
struct Elem {
  bool line;
  Vec2 a, b;  // line
  Vec2 o;     // arc
  double r, a0, sweep;
  MPVG_HD Vec2 at(double u) const {
    if (line) return a + u * (b - a);
    const double th = a0 + u * sweep;
    return {o.x + r * cos(th), o.y + r * sin(th)};
  }
};

MPVG_HD_INLINE double mod2pi(double a) {
  a = fmod(a, 2 * kPi);
  return a < 0 ? a + 2 * kPi : a;
}

}  // namespace join_detail

// Arcs (SVG 2): the outer edges are extended by the circles with their
// curvature at the join (lines by lines) to their intersection nearest to
// p, and the region bounded by p, the extensions and p is clipped at the
// miter limit like miter-clip. False when the construction does not apply
// (both edges straight, no intersection, infinite curvature, an outer edge
// that folds back at the join): the caller falls back to miter-clip.
template <class Sink>
MPVG_HD bool emit_arcs(const JoinStyle& st, Vec2 p, Vec2 p1, Vec2 p2, Vec2 t0, Vec2 t1, double tau, double sgn,
                       double k0, double k1, Emitter<Sink>& out) {
  using namespace join_detail;
  const double h = st.h;
  if (!finite(k0) || !finite(k1)) return false;
  if (k0 == 0 && k1 == 0) return false;
  const double s = sgn * h;  // the outer edge is the offset at s
  if (1 - s * k0 <= 0 || 1 - s * k1 <= 0) return false;
  const Vec2 n0 = rot90(t0), n1 = rot90(t1);
  auto edge = [&](double k, Vec2 n, Vec2 at, Vec2 t) {
    Edge e{};
    if (k == 0) {
      e.line = true;
      e.q = at;
      e.d = t;
    } else {
      e.o = p + (1 / k) * n;
      e.r = fabs(1 / k - s);
    }
    return e;
  };
  const Edge e0 = edge(k0, n0, p1, t0), e1 = edge(k1, n1, p2, t1);
  // Intersections of the two extensions.
  Vec2 xs[2];
  int nx = 0;
  auto line_circle = [&](const Edge& l, const Edge& c) {
    const Vec2 m = l.q - c.o;
    const double bq = dot(l.d, m), cq = dot(m, m) - c.r * c.r, disc = bq * bq - cq;
    if (disc < 0) return;
    const double sq = sqrt(disc);
    xs[nx++] = l.q + (-bq - sq) * l.d;
    xs[nx++] = l.q + (-bq + sq) * l.d;
  };
  if (e0.line) {
    line_circle(e0, e1);
  } else if (e1.line) {
    line_circle(e1, e0);
  } else {
    const Vec2 dv = e1.o - e0.o;
    const double d = length(dv);
    if (!(d > 0) || d > e0.r + e1.r || d < fabs(e0.r - e1.r)) return false;
    const double a = (e0.r * e0.r - e1.r * e1.r + d * d) / (2 * d);
    const double y = sqrt(dmax(0.0, e0.r * e0.r - a * a));
    const Vec2 u = (1 / d) * dv, base = e0.o + a * u;
    xs[nx++] = base + y * rot90(u);
    xs[nx++] = base - y * rot90(u);
  }
  if (nx == 0) return false;
  Vec2 x = xs[0];
  for (int i = 0; i < nx; i++)
    if (length(xs[i] - p) < length(x - p)) x = xs[i];

  // The boundary p -> p1 -> (extension 0) -> x -> (extension 1) -> p2 -> p.
  Elem elems[4];
  int ne = 0;
  elems[ne++] = {true, p, p1, {}, 0, 0, 0};
  auto extension = [&](const Edge& e, Vec2 from, Vec2 to, Vec2 t, bool forwards) {
    if (e.line) {
      // Along t from p1 (forwards), or arriving along t at p2.
      if (dot(to - from, t) < 0) return false;
      elems[ne++] = {true, from, to, {}, 0, 0, 0};
      return true;
    }
    // Turning like the edge at its end point (p1 or p2).
    const Vec2 rim = forwards ? from : to;
    const bool ccw = cross(rim - e.o, t) > 0;
    const double a_from = atan2(from.y - e.o.y, from.x - e.o.x);
    const double a_to = atan2(to.y - e.o.y, to.x - e.o.x);
    const double sweep = ccw ? mod2pi(a_to - a_from) : -mod2pi(a_from - a_to);
    if (fabs(sweep) > kPi) return false;
    elems[ne++] = {false, {}, {}, e.o, e.r, a_from, sweep};
    return true;
  };
  if (!extension(e0, p1, x, t0, true) || !extension(e1, x, p2, t1, false)) return false;
  elems[ne++] = {true, p2, p, {}, 0, 0, 0};

  // Clip by the half-plane dot(q - p, b) <= miter_limit * h. The clipped
  // boundary is at most 4 elements of 3 parts, arcs of at most two conics.
  const Vec2 b = fabs(tau) < kPi - 1e-9 ? normalized((p1 - p) + (p2 - p)) : t0;
  const double lim = st.miter_limit * h;
  Piece pieces[32];
  int np = 0;
  for (int ei = 0; ei < ne; ei++) {
    const Elem& e = elems[ei];
    double us[4] = {0, 1, 0, 0};
    int nu = 2;
    if (e.line) {
      const double f0 = dot(e.a - p, b) - lim, f1 = dot(e.b - p, b) - lim;
      if ((f0 < 0) != (f1 < 0) && f0 != f1) us[nu++] = f0 / (f0 - f1);
    } else {
      // dot(o - p, b) + r cos(theta - beta) = lim.
      const double kc = (lim - dot(e.o - p, b)) / e.r;
      if (fabs(kc) < 1) {
        const double beta = atan2(b.y, b.x), ac = acos(kc);
        const double ths[2] = {beta + ac, beta - ac};
        for (int q = 0; q < 2; q++) {
          // The parameter of th on this arc, if it lies on it.
          const double rel = e.sweep >= 0 ? mod2pi(ths[q] - e.a0) : -mod2pi(e.a0 - ths[q]);
          const double u = rel / e.sweep;
          if (u > 0 && u < 1) us[nu++] = u;
        }
      }
    }
    for (int i = 1; i < nu; i++) {
      const double v = us[i];
      int j = i - 1;
      while (j >= 0 && us[j] > v) us[j + 1] = us[j], j--;
      us[j + 1] = v;
    }
    for (int k = 0; k + 1 < nu; k++) {
      const double ua = us[k], ub = us[k + 1];
      if (!(ub > ua) || !(dot(e.at((ua + ub) / 2) - p, b) <= lim)) continue;
      if (e.line) {
        if (np < 32) pieces[np++] = {CURVE_LINE, e.at(ua), {}, e.at(ub)};
        continue;
      }
      // The arc as conics of at most 90°, its ends pinned to the boundary
      // points so that the chain stays connected exactly.
      const double sweep = (ub - ua) * e.sweep, a0 = e.a0 + ua * e.sweep;
      int n = static_cast<int>(ceil(fabs(sweep) / (kPi / 2) - 1e-9));
      if (n < 1) n = 1;
      const double d = sweep / n, w = cos(d / 2);
      for (int q = 0; q < n && np < 32; q++) {
        Piece pc = Emitter<Sink>::arc_piece(e.o, e.r, a0 + q * d, d, w);
        if (q == 0) pc.p0 = e.at(ua);
        if (q == n - 1) pc.p2 = e.at(ub);
        pieces[np++] = pc;
      }
    }
  }
  if (np == 0) return true;
  // Left turns (outer edges on the right) run counter-clockwise.
  if (sgn > 0) {
    out.begin(pieces[np - 1].p2);
    for (int i = np; i-- > 0;) out.piece(reversed(pieces[i]));
  } else {
    out.begin(pieces[0].p0);
    for (int i = 0; i < np; i++) out.piece(pieces[i]);
  }
  out.close();
  return true;
}

// The line join shape (SVG 2 painting.html#TermLineJoinShape) at vertex p
// between a segment arriving along t0 with curvature k0 at its end and one
// leaving along t1 with curvature k1 at its start (NaN: infinite).
//
// Nehab 2020: between curves, the inner side can show a gap that the
// bodies do not fill. A body covers the inner wedge between the two end
// normals unless it folds there (its centre of curvature on the inner side,
// closer than h); where both fold, the inner bevel closes the gap.
template <class Sink>
MPVG_HD void emit_join(const JoinStyle& st, Vec2 p, Vec2 t0, Vec2 t1, double k0, double k1, Emitter<Sink>& out) {
  const double h = st.h;
  const double cr = cross(t0, t1), dt = dot(t0, t1);
  const double tau = atan2(cr, dt);  // the turn, in (-pi, pi]
  // The outer side of the turn (a half-turn counts as a left turn).
  const double sgn = tau >= 0 ? -1 : 1;
  // Nearly straight on: the offsets meet within a fraction of the
  // tolerance, and the bodies alone are the stroke.
  if (dt > 0 && h * fabs(tau) <= st.tol / 8) return;
  const Vec2 n0 = rot90(t0), n1 = rot90(t1);
  const Vec2 p1 = p + (sgn * h) * n0, p2 = p + (sgn * h) * n1;  // outer
  const Vec2 q1 = p - (sgn * h) * n0, q2 = p - (sgn * h) * n1;  // inner
  auto folds_inside = [&](double k, double inner) { return k != k || k * inner * h >= 1; };
  if (st.join == JOIN_ROUND) {
    out.disk(p, h);
    return;
  }
  if (folds_inside(k0, -sgn) && folds_inside(k1, -sgn)) {
    const Vec2 tri[3] = {p, q1, q2};
    out.polygon(tri, 3);
  }
  Vec2 outer[5];
  int no = 0;
  outer[no++] = p;
  outer[no++] = p1;
  // Miter: the bevel plus the triangle up to where the outer edges meet,
  // when miter length / width = 1 / cos(tau / 2) is within the limit, else
  // the bevel alone, or (miter-clip) the miter clipped by the line
  // perpendicular to the bisector at miter_limit * h from p.
  auto miter = [&](bool clip) {
    const double ch = cos(tau / 2), sh = sin(fabs(tau) / 2);
    if (ch * st.miter_limit >= 1) {
      outer[no++] = p + (h / ch) * normalized((p1 - p) + (p2 - p));
      return;
    }
    if (!clip) return;
    // Distance along each outer edge from p1 (p2) to the clip line.
    const double lambda = (st.miter_limit * h - h * ch) / sh;
    outer[no++] = p1 + lambda * t0;
    outer[no++] = p2 - lambda * t1;
  };
  switch (st.join) {
    case JOIN_MITER: miter(false); break;
    case JOIN_MITER_CLIP: miter(true); break;
    case JOIN_ARCS:
      if (!emit_arcs(st, p, p1, p2, t0, t1, tau, sgn, k0, k1, out)) miter(true);
      break;
    default: break;  // bevel
  }
  outer[no++] = p2;
  out.polygon(outer, no);
}

}  // namespace mpvg::stroking
