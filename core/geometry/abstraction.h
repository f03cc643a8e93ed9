// Abstraction (paper §3.1-3.2): one input segment in pixel space becomes
// monotonic, implicit abstract segments. Written once for both executors:
// the CPU loops over input segments, the GPU runs one thread per segment.
//
//   1. Monotonization (§3.1): split where x'(t) = 0 or y'(t) = 0; cubics
//      also at inflections and at the double point (§3.2), so that every
//      piece is convex and C, the intersection of its end tangents, lies in
//      its bounding box. The roots come from Blinn's robust quadratic solver
//      (quadratic.h). The pieces' control points come from the blossom
//      (Ramshaw's multiaffine form) of the whole segment, evaluated with
//      (1-t)a + tb so that t = 0 and t = 1 reproduce the endpoints exactly
//      and neighbouring pieces share their endpoints bit for bit.
//   2. Implicitization (§3.2): the implicit equation of each piece's curve,
//      from the Bezout resultant of its Bernstein form (Sederberg):
//        conic  f = l21 l10 - l20^2
//        cubic  f = | l32  l31        l30 |
//                   | l31  l30 + l21  l20 |
//                   | l30  l20        l10 |
//      with l_ij(p) = C(n,i) C(n,j) w_i w_j det[p 1; P_i 1; P_j 1]. It is
//      expanded into a cubic polynomial in (p - P0), normalised so that f is
//      about the signed distance to the curve near it and f > 0 on the left.
//      Double precision throughout, floats only in the stored record.
//
// Pieces that are flat to within kFlatTolerance pixels become lines; pieces
// whose endpoints round to the same float point vanish.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/geometry/abstract_segment.h"
#include "core/hd.h"
#include "core/geometry/quadratic.h"

namespace mpvg {

// Flat input segment in pixel space (encoding, abstraction.cpp). type is a
// SegmentType; rational cubics never get here.
struct InputSegment {
  uint32_t type;
  uint32_t path;
  double w;        // RQuad: weight of the middle control point
  double x[4], y[4];
};
static_assert(sizeof(InputSegment) == 80, "InputSegment is an 80-byte record shared by CPU and GPU");

enum : uint32_t { INPUT_LINE = 0, INPUT_QUAD = 1, INPUT_RQUAD = 2, INPUT_CUBIC = 3 };

// 2 extrema in x, 2 in y, 2 inflections, 2 parameters of the double point.
constexpr int kMaxSplits = 8;
constexpr int kMaxPieces = kMaxSplits + 1;

// Curves whose control polygon stays this close to the chord are lines.
constexpr double kFlatTolerance = 1.0 / 4096.0;

namespace abstraction_detail {

struct P2 {
  double x, y;
};

MPVG_HD_INLINE P2 mix(P2 a, P2 b, double t) { return P2{(1.0 - t) * a.x + t * b.x, (1.0 - t) * a.y + t * b.y}; }
MPVG_HD_INLINE double cross2(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }
MPVG_HD_INLINE P2 sub(P2 a, P2 b) { return P2{a.x - b.x, a.y - b.y}; }
MPVG_HD_INLINE double len(P2 a) { return sqrt(a.x * a.x + a.y * a.y); }

// Homogeneous point for conics: (w x, w y, w).
struct Hp {
  double x, y, w;
};
MPVG_HD_INLINE Hp mixh(Hp a, Hp b, double t) {
  return Hp{(1.0 - t) * a.x + t * b.x, (1.0 - t) * a.y + t * b.y, (1.0 - t) * a.w + t * b.w};
}

// Cubic polynomial in (dx, dy): coefficients of
// 1, dx, dy, dx^2, dx dy, dy^2, dx^3, dx^2 dy, dx dy^2, dy^3.
struct Poly {
  double c[10];
};

struct Lin {
  double a, b, c;  // a dx + b dy + c
};

MPVG_HD_INLINE Lin lin_add(Lin p, Lin q) { return Lin{p.a + q.a, p.b + q.b, p.c + q.c}; }

// l(p) = k det[p 1; Pi 1; Pj 1], Pi and Pj relative to the local origin.
MPVG_HD_INLINE Lin line_det(P2 pi, P2 pj, double k) {
  return Lin{k * (pi.y - pj.y), k * (pj.x - pi.x), k * (pi.x * pj.y - pj.x * pi.y)};
}

MPVG_HD_INLINE void poly_zero(Poly& p) {
  for (int i = 0; i < 10; i++) p.c[i] = 0.0;
}

// q += s * (l * m): product of two affine forms (degree 2).
MPVG_HD_INLINE void poly_add_ll(Poly& q, Lin l, Lin m, double s) {
  q.c[0] += s * (l.c * m.c);
  q.c[1] += s * (l.a * m.c + l.c * m.a);
  q.c[2] += s * (l.b * m.c + l.c * m.b);
  q.c[3] += s * (l.a * m.a);
  q.c[4] += s * (l.a * m.b + l.b * m.a);
  q.c[5] += s * (l.b * m.b);
}

// q += s * (l * m * n) (degree 3).
MPVG_HD_INLINE void poly_add_lll(Poly& q, Lin l, Lin m, Lin n, double s) {
  // (l m) as a quadratic, then times n.
  const double q0 = l.c * m.c, qx = l.a * m.c + l.c * m.a, qy = l.b * m.c + l.c * m.b;
  const double qxx = l.a * m.a, qxy = l.a * m.b + l.b * m.a, qyy = l.b * m.b;
  q.c[0] += s * (q0 * n.c);
  q.c[1] += s * (q0 * n.a + qx * n.c);
  q.c[2] += s * (q0 * n.b + qy * n.c);
  q.c[3] += s * (qx * n.a + qxx * n.c);
  q.c[4] += s * (qx * n.b + qy * n.a + qxy * n.c);
  q.c[5] += s * (qy * n.b + qyy * n.c);
  q.c[6] += s * (qxx * n.a);
  q.c[7] += s * (qxx * n.b + qxy * n.a);
  q.c[8] += s * (qxy * n.b + qyy * n.a);
  q.c[9] += s * (qyy * n.b);
}

MPVG_HD_INLINE double poly_eval(const Poly& p, double dx, double dy) {
  return p.c[0] + dy * (p.c[2] + dy * (p.c[5] + dy * p.c[9])) +
         dx * (p.c[1] + dy * (p.c[4] + dy * p.c[8]) + dx * (p.c[3] + dy * p.c[7] + dx * p.c[6]));
}

MPVG_HD_INLINE void poly_grad(const Poly& p, double dx, double dy, double& gx, double& gy) {
  gx = p.c[1] + 2.0 * p.c[3] * dx + p.c[4] * dy + 3.0 * p.c[6] * dx * dx + 2.0 * p.c[7] * dx * dy + p.c[8] * dy * dy;
  gy = p.c[2] + p.c[4] * dx + 2.0 * p.c[5] * dy + p.c[7] * dx * dx + 2.0 * p.c[8] * dx * dy + 3.0 * p.c[9] * dy * dy;
}

// Adds the roots of a t^2 - 2 b t + c in (0, 1) to ts.
MPVG_HD_INLINE void add_roots(double a, double b, double c, double* ts, int& n) {
  double r[2];
  const int k = solve_quadratic(a, b, c, r);
  for (int i = 0; i < k; i++)
    if (r[i] > 0.0 && r[i] < 1.0 && n < kMaxSplits) ts[n++] = r[i];
}

// Roots of the derivative of a Bernstein polynomial with coefficients
// c0..c3 (cubic) or c0..c2 (quadratic): the derivative's Bernstein form is
// d0 (1-t)^2 + 2 d1 t (1-t) + d2 t^2 = (d0 - 2 d1 + d2) t^2 - 2 (d0 - d1) t + d0.
MPVG_HD_INLINE void add_cubic_extrema(double c0, double c1, double c2, double c3, double* ts, int& n) {
  const double d0 = c1 - c0, d1 = c2 - c1, d2 = c3 - c2;
  add_roots(d0 - 2.0 * d1 + d2, d0 - d1, d0, ts, n);
}

// The implicit equation of a whole input segment, from the Bezout resultant
// of its Bernstein form, in the frame u = (p - o) * scale that maps its
// control polygon into [-1, 1]^2. Computing it once for the whole curve
// (rather than from a piece's own control points) keeps it well conditioned:
// a short piece is nearly a parabola, and the resultant of a nearly
// degree-elevated Bezier form is a nearly vanishing determinant.
struct Implicit {
  Poly f;
  double ox, oy, scale;
};

MPVG_HD_INLINE void implicit_of(const P2* c, int degree, double w, Implicit& im) {
  im.ox = c[0].x;
  im.oy = c[0].y;
  double ext = 0.0;
  for (int i = 1; i <= degree; i++) {
    const double ex = fabs(c[i].x - im.ox), ey = fabs(c[i].y - im.oy);
    ext = ex > ext ? ex : ext;
    ext = ey > ext ? ey : ext;
  }
  im.scale = ext > 0.0 ? 1.0 / ext : 1.0;
  P2 lq[4];
  for (int i = 0; i <= degree; i++) lq[i] = P2{(c[i].x - im.ox) * im.scale, (c[i].y - im.oy) * im.scale};
  poly_zero(im.f);
  if (degree == 3) {
    // A cubic whose t^3 coefficient vanishes (to 1e-9 of its size) is a
    // degree-elevated quadratic: its cubic resultant is identically zero.
    // Use the quadratic's, through Q1 = (3 P1 - P0)/2 = (3 P2 - P3)/2.
    const P2 a{-lq[0].x + 3.0 * lq[1].x - 3.0 * lq[2].x + lq[3].x, -lq[0].y + 3.0 * lq[1].y - 3.0 * lq[2].y + lq[3].y};
    if (len(a) < 1e-9) {
      lq[1] = P2{0.25 * (3.0 * lq[1].x - lq[0].x + 3.0 * lq[2].x - lq[3].x),
                 0.25 * (3.0 * lq[1].y - lq[0].y + 3.0 * lq[2].y - lq[3].y)};
      lq[2] = lq[3];
      degree = 2;
      w = 1.0;
    }
  }
  if (degree == 2) {
    const Lin l21 = line_det(lq[2], lq[1], 2.0 * w);
    const Lin l20 = line_det(lq[2], lq[0], 1.0);
    const Lin l10 = line_det(lq[1], lq[0], 2.0 * w);
    poly_add_ll(im.f, l21, l10, 1.0);
    poly_add_ll(im.f, l20, l20, -1.0);
  } else if (degree == 3) {
    const Lin l32 = line_det(lq[3], lq[2], 3.0);
    const Lin l31 = line_det(lq[3], lq[1], 3.0);
    const Lin l30 = line_det(lq[3], lq[0], 1.0);
    const Lin l21 = line_det(lq[2], lq[1], 9.0);
    const Lin l20 = line_det(lq[2], lq[0], 3.0);
    const Lin l10 = line_det(lq[1], lq[0], 3.0);
    const Lin m11 = lin_add(l30, l21);
    // Cofactor expansion along the first row.
    poly_add_lll(im.f, l32, m11, l10, 1.0);
    poly_add_lll(im.f, l32, l20, l20, -1.0);
    poly_add_lll(im.f, l31, l31, l10, -1.0);
    poly_add_lll(im.f, l31, l20, l30, 1.0);
    poly_add_lll(im.f, l30, l31, l20, 1.0);
    poly_add_lll(im.f, l30, m11, l30, -1.0);
  }
}

// Exponents (b0, bc, b1) of the 10 cubic monomials, in AbstractSegment::k order.
MPVG_HD_INLINE int tri_index(int e0, int ec, int e1) {
  // b0^3, b0^2 bc, b0^2 b1, b0 bc^2, b0 bc b1, b0 b1^2, bc^3, bc^2 b1, bc b1^2, b1^3:
  // the monomials of b0^e0 come after those of higher powers of b0, the
  // (4 - e0)(5 - e0)/2 of lower ones and b0's own counted down by bc's
  // power (a table of them, made on every call, was a tenth of the
  // abstraction's instructions on the CPU).
  (void)e1;
  return (4 - e0) * (5 - e0) / 2 - 1 - ec;
}

// The whole curve's implicit written as a homogeneous cubic in the
// barycentric coordinates (b0, bc, b1) of triangle (v0, vc, v1): substitute
// p = b0 v0 + bc vc + b1 v1 and homogenise lower-degree terms with
// (b0 + bc + b1) = 1.
MPVG_HD_INLINE void implicit_in_triangle(const Implicit& im, P2 v0, P2 vc, P2 v1, double out[10]) {
  const double lx[3] = {(v0.x - im.ox) * im.scale, (vc.x - im.ox) * im.scale, (v1.x - im.ox) * im.scale};
  const double ly[3] = {(v0.y - im.oy) * im.scale, (vc.y - im.oy) * im.scale, (v1.y - im.oy) * im.scale};
  const double one[3] = {1.0, 1.0, 1.0};
  const int ex[10] = {0, 1, 0, 2, 1, 0, 3, 2, 1, 0};
  const int ey[10] = {0, 0, 1, 0, 1, 2, 0, 1, 2, 3};
  for (int i = 0; i < 10; i++) out[i] = 0.0;
  for (int m = 0; m < 10; m++) {
    if (im.f.c[m] == 0.0) continue;
    const double* forms[3];
    int n = 0;
    for (int k = 0; k < ex[m]; k++) forms[n++] = lx;
    for (int k = 0; k < ey[m]; k++) forms[n++] = ly;
    while (n < 3) forms[n++] = one;
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++)
        for (int c = 0; c < 3; c++) {
          int e[3] = {0, 0, 0};
          e[a]++;
          e[b]++;
          e[c]++;
          out[tri_index(e[0], e[1], e[2])] += im.f.c[m] * forms[0][a] * forms[1][b] * forms[2][c];
        }
  }
}

// Emits one monotonic piece given by its control points (degree 1..3) and
// the implicit of its whole curve. Returns 1 if a piece was written, 0 if it
// vanished.
MPVG_HD_INLINE int emit_piece(const P2* q, int degree, double w, const Implicit* im, uint32_t path, double ta,
                              double tb, AbstractSegment* out) {
  AbstractSegment s;
  s.x0 = float(q[0].x);
  s.y0 = float(q[0].y);
  s.x1 = float(q[degree].x);
  s.y1 = float(q[degree].y);
  s.flags = ABSTRACT_LINE;
  s.path = path;
  s.cx = s.x0;
  s.cy = s.y0;
  for (int i = 0; i < 10; i++) s.k[i] = 0.0f;
  s.t0 = float(ta);
  s.t1 = float(tb);
  if (s.x0 == s.x1 && s.y0 == s.y1) return 0;
  if (!out) return 1;  // counting: every piece that does not vanish is written
  if (degree == 1 || s.x0 == s.x1 || s.y0 == s.y1) {
    // Monotonic pieces with equal endpoint x (or y) are straight.
    if (out) *out = s;
    return 1;
  }
  const P2 p0 = q[0], p3 = q[degree];
  const P2 chord = sub(p3, p0);
  const double chord_len = len(chord);
  // Flatness: a bound on the curve's distance from its chord. A conic with
  // equal end weights is farthest at t = 1/2, at w / (1 + w) of its control
  // point's distance; a cubic stays within 3/4 of its farthest control point.
  double flat = 0.0;
  for (int i = 1; i < degree; i++) {
    const double dist = fabs(cross2(chord, sub(q[i], p0))) / chord_len;
    flat = dist > flat ? dist : flat;
  }
  flat *= (degree == 2) ? w / (1.0 + w) : 0.75;
  if (!(flat > kFlatTolerance)) {
    if (out) *out = s;
    return 1;
  }
  // Apex C: intersection of the end tangents.
  P2 t0 = sub(q[1], p0);
  if (len(t0) <= 1e-12 * chord_len) t0 = sub(q[degree - 1], p0);
  P2 t1 = sub(p3, q[degree - 1]);
  if (len(t1) <= 1e-12 * chord_len) t1 = sub(p3, q[1]);
  const double den = cross2(t0, t1);
  if (!(fabs(den) > 1e-12 * len(t0) * len(t1))) {
    if (out) *out = s;
    return 1;
  }
  const double sc = cross2(sub(p3, p0), t1) / den;
  P2 apex{p0.x + sc * t0.x, p0.y + sc * t0.y};
  // C lies in the bounding box in exact arithmetic (§3.2); clamp rounding.
  const double bx0 = p0.x < p3.x ? p0.x : p3.x, bx1 = p0.x < p3.x ? p3.x : p0.x;
  const double by0 = p0.y < p3.y ? p0.y : p3.y, by1 = p0.y < p3.y ? p3.y : p0.y;
  apex.x = apex.x < bx0 ? bx0 : (apex.x > bx1 ? bx1 : apex.x);
  apex.y = apex.y < by0 ? by0 : (apex.y > by1 ? by1 : apex.y);

  s.cx = float(apex.x);
  s.cy = float(apex.y);
  // Triangle coordinates as the sampler computes them, from the stored
  // floats: b0 = cross(P1 - C, p - C), bc = chord, b1 = cross(C - P0, p - P0).
  const double fx0 = s.x0, fy0 = s.y0, fx1 = s.x1, fy1 = s.y1, fcx = s.cx, fcy = s.cy;
  auto tri_b0 = [&](double px, double py) { return (fx1 - fcx) * (py - fcy) - (fy1 - fcy) * (px - fcx); };
  auto tri_bc = [&](double px, double py) { return (py - fy0) * (fx1 - fx0) - (px - fx0) * (fy1 - fy0); };
  auto tri_b1 = [&](double px, double py) { return (fcx - fx0) * (py - fy0) - (fcy - fy0) * (px - fx0); };
  const double n0 = tri_b0(fx0, fy0), nc = tri_bc(fcx, fcy), n1 = tri_b1(fx1, fy1);
  if (!(fabs(n0) > 0.0 && fabs(nc) > 0.0 && fabs(n1) > 0.0)) {
    s.cx = s.x0;
    s.cy = s.y0;
    if (out) *out = s;
    return 1;
  }
  // Coefficients on the normalised barycentrics, then on the raw ones.
  double k[10];
  for (int i = 0; i < 10; i++) k[i] = 0.0;
  if (degree == 2) {
    // Conic in its own triangle: b_C^2 - 4 w^2 b_0 b_1 (barycentric form of
    // the rational quadratic, exact).
    k[0] = 1.0 / (nc * nc);
    k[1] = -4.0 * w * w / (n0 * n1);
  } else {
    implicit_in_triangle(*im, P2{fx0, fy0}, P2{fcx, fcy}, P2{fx1, fy1}, k);
    double pw0[4] = {1.0, n0, n0 * n0, n0 * n0 * n0}, pwc[4] = {1.0, nc, nc * nc, nc * nc * nc};
    double pw1[4] = {1.0, n1, n1 * n1, n1 * n1 * n1};
    for (int e0 = 0; e0 <= 3; e0++)
      for (int ec = 0; ec + e0 <= 3; ec++) {
        const int e1 = 3 - e0 - ec;
        k[tri_index(e0, ec, e1)] /= pw0[e0] * pwc[ec] * pw1[e1];
      }
  }
  double kmax = 0.0;
  for (int i = 0; i < 10; i++) kmax = fabs(k[i]) > kmax ? fabs(k[i]) : kmax;
  // Orientation: a point beyond the curve on its bulge side, halfway from the
  // curve's midpoint to C, is left of the curve iff the bulge is left.
  P2 mid;
  if (degree == 2) {
    const double wm = 0.5 + 0.5 * w;
    mid = P2{(0.25 * q[0].x + 0.5 * w * q[1].x + 0.25 * q[2].x) / wm,
             (0.25 * q[0].y + 0.5 * w * q[1].y + 0.25 * q[2].y) / wm};
  } else {
    mid = P2{0.125 * q[0].x + 0.375 * q[1].x + 0.375 * q[2].x + 0.125 * q[3].x,
             0.125 * q[0].y + 0.375 * q[1].y + 0.375 * q[2].y + 0.125 * q[3].y};
  }
  const double rx = 0.5 * (mid.x + fcx), ry = 0.5 * (mid.y + fcy);
  const double b0 = tri_b0(rx, ry), bc = tri_bc(rx, ry), b1 = tri_b1(rx, ry);
  double fref;
  if (degree == 2) {
    fref = k[0] * bc * bc + k[1] * b0 * b1;
  } else {
    fref = b0 * (b0 * (k[0] * b0 + k[1] * bc + k[2] * b1) + bc * (k[3] * bc + k[4] * b1) + k[5] * b1 * b1) +
           bc * (bc * (k[6] * bc + k[7] * b1) + k[8] * b1 * b1) + k[9] * b1 * b1 * b1;
  }
  if (!(kmax > 0.0) || !(kmax < 1e300) || !(fabs(fref) > 0.0)) {
    s.cx = s.x0;
    s.cy = s.y0;
    if (out) *out = s;
    return 1;
  }
  // Bulge side: which side of the chord the apex lies on ("left" = smaller x
  // at the same y, as in abstract_chord).
  const bool bulge_left = (fy1 > fy0) ? nc > 0.0 : nc < 0.0;
  const double norm = (((fref > 0.0) == bulge_left) ? 1.0 : -1.0) / kmax;
  for (int i = 0; i < 10; i++) s.k[i] = float(k[i] * norm);
  s.flags = (degree == 2 ? ABSTRACT_QUAD : ABSTRACT_CUBIC) | (bulge_left ? ABSTRACT_BULGE_LEFT : 0u) |
            (n1 > 0.0 ? ABSTRACT_TRI_POSITIVE : 0u);
  if (out) *out = s;
  return 1;
}

MPVG_HD_INLINE void sort_splits(double* ts, int& n) {
  for (int i = 1; i < n; i++) {
    const double v = ts[i];
    int j = i - 1;
    while (j >= 0 && ts[j] > v) {
      ts[j + 1] = ts[j];
      j--;
    }
    ts[j + 1] = v;
  }
  int m = 0;
  for (int i = 0; i < n; i++)
    if (m == 0 || ts[i] != ts[m - 1]) ts[m++] = ts[i];
  n = m;
}

}  // namespace abstraction_detail

// Lowers one input segment. Writes up to kMaxPieces abstract segments to out
// (out may be null to only count them) and returns how many.
MPVG_HD_INLINE int abstract_input_segment(const InputSegment& in, AbstractSegment* out) {
  using namespace abstraction_detail;
  const uint32_t path = in.path;
  if (in.type == INPUT_LINE) {
    const P2 q[2] = {{in.x[0], in.y[0]}, {in.x[1], in.y[1]}};
    return emit_piece(q, 1, 1.0, nullptr, path, 0.0, 1.0, out);
  }
  double ts[kMaxSplits];
  int n = 0;
  int count = 0;
  if (in.type == INPUT_QUAD || in.type == INPUT_RQUAD) {
    // An integral quadratic is the conic with w = 1: W(t) = 1 and the
    // homogeneous blossom below is the plain one.
    const double w = in.type == INPUT_QUAD ? 1.0 : in.w;
    // x'(t) = 0 for x(t) = X(t)/W(t): X'W - XW' is the quadratic
    // 2[w (x1-x0) (1-t)^2 + (x2-x0) t (1-t) + w (x2-x1) t^2].
    for (int axis = 0; axis < 2; axis++) {
      const double* c = axis == 0 ? in.x : in.y;
      const double e0 = w * (c[1] - c[0]), e1 = 0.5 * (c[2] - c[0]), e2 = w * (c[2] - c[1]);
      add_roots(e0 - 2.0 * e1 + e2, e0 - e1, e0, ts, n);
    }
    sort_splits(ts, n);
    const Hp h0{in.x[0], in.y[0], 1.0}, h1{w * in.x[1], w * in.y[1], w}, h2{in.x[2], in.y[2], 1.0};
    const P2 cp[3] = {{in.x[0], in.y[0]}, {in.x[1], in.y[1]}, {in.x[2], in.y[2]}};
    Implicit im{};  // (left unset by a count)
    if (out) implicit_of(cp, 2, w, im);  // (a count needs the pieces' ends only)
    double ta = 0.0;
    for (int i = 0; i <= n; i++) {
      const double tb = i < n ? ts[i] : 1.0;
      const Hp a = mixh(mixh(h0, h1, ta), mixh(h1, h2, ta), ta);
      const Hp m = mixh(mixh(h0, h1, ta), mixh(h1, h2, ta), tb);
      const Hp b = mixh(mixh(h0, h1, tb), mixh(h1, h2, tb), tb);
      // Back to standard form (end weights 1): w' = w_m / sqrt(w_a w_b).
      P2 q[3];
      q[0] = (ta == 0.0) ? P2{in.x[0], in.y[0]} : P2{a.x / a.w, a.y / a.w};
      q[1] = P2{m.x / m.w, m.y / m.w};
      q[2] = (tb == 1.0) ? P2{in.x[2], in.y[2]} : P2{b.x / b.w, b.y / b.w};
      const double wp = m.w / sqrt(a.w * b.w);
      count += emit_piece(q, 2, wp, &im, path, ta, tb, out ? out + count : nullptr);
      ta = tb;
    }
    return count;
  }
  // Integral cubic. Power basis P(t) = A t^3 + B t^2 + C t + D.
  const P2 c0{in.x[0], in.y[0]}, c1{in.x[1], in.y[1]}, c2{in.x[2], in.y[2]}, c3{in.x[3], in.y[3]};
  const P2 A{-c0.x + 3.0 * c1.x - 3.0 * c2.x + c3.x, -c0.y + 3.0 * c1.y - 3.0 * c2.y + c3.y};
  const P2 B{3.0 * c0.x - 6.0 * c1.x + 3.0 * c2.x, 3.0 * c0.y - 6.0 * c1.y + 3.0 * c2.y};
  const P2 C{3.0 * (c1.x - c0.x), 3.0 * (c1.y - c0.y)};
  add_cubic_extrema(c0.x, c1.x, c2.x, c3.x, ts, n);
  add_cubic_extrema(c0.y, c1.y, c2.y, c3.y, ts, n);
  // Inflections: cross(P', P'') = -6 (A x B) t^2 + 6 (C x A) t + 2 (C x B) = 0.
  const double axb = cross2(A, B), cxa = cross2(C, A), cxb = cross2(C, B);
  add_roots(-6.0 * axb, -3.0 * cxa, 2.0 * cxb, ts, n);
  // Double point: P(t1) = P(t2), t1 != t2. With s = t1 + t2, p = t1 t2:
  // A (s^2 - p) + B s + C = 0, so s = -(A x C)/(A x B) and p follows from
  // the component along A. t1, t2 solve t^2 - s t + p = 0.
  const double aa = A.x * A.x + A.y * A.y;
  if (axb != 0.0 && aa > 0.0) {
    const double sum = -cross2(A, C) / axb;
    const P2 r{B.x * sum + C.x, B.y * sum + C.y};
    const double prod = sum * sum + (r.x * A.x + r.y * A.y) / aa;
    if (sum * sum - 4.0 * prod > 0.0) add_roots(1.0, 0.5 * sum, prod, ts, n);
  }
  sort_splits(ts, n);
  const P2 cp[4] = {c0, c1, c2, c3};
  Implicit im{};  // (left unset by a count)
  if (out) implicit_of(cp, 3, 1.0, im);  // (a count needs the pieces' ends only)
  double ta = 0.0;
  for (int i = 0; i <= n; i++) {
    const double tb = i < n ? ts[i] : 1.0;
    // Blossom b(u, v, w): de Casteljau with a different parameter per level.
    P2 q[4];
    const double pars[4][3] = {{ta, ta, ta}, {ta, ta, tb}, {ta, tb, tb}, {tb, tb, tb}};
    for (int k = 0; k < 4; k++) {
      const P2 l1a = mix(c0, c1, pars[k][0]), l1b = mix(c1, c2, pars[k][0]), l1c = mix(c2, c3, pars[k][0]);
      const P2 l2a = mix(l1a, l1b, pars[k][1]), l2b = mix(l1b, l1c, pars[k][1]);
      q[k] = mix(l2a, l2b, pars[k][2]);
    }
    count += emit_piece(q, 3, 1.0, &im, path, ta, tb, out ? out + count : nullptr);
    ta = tb;
  }
  return count;
}

}  // namespace mpvg
