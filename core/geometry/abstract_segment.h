// Abstract segments (paper §3, Fig. 2-4): monotonic pieces of the input
// segments, queried for their bounding box, orientation, and for the side of
// the piece on which a point lies. The side query is all the pipeline ever
// asks of geometry: the sampler uses it for horizontal rays (winding
// numbers), the subdivision for the corners of cells. No intersection is ever
// computed.
//
// A piece runs from (x0,y0) to (x1,y1); being monotonic in x and y, its
// bounding box is spanned by these endpoints. Over its y-range it is the graph
// of a monotonic function x = X(y) (a horizontal piece has no graph and never
// crosses a horizontal ray).
//
// side(p), for p.y within [min(y0,y1), max(y0,y1)], answers
//   +1  p is strictly left of the piece   (X(p.y) > p.x)
//    0  p is on the piece
//   -1  p is strictly right of the piece  (X(p.y) < p.x)
// exactly at the endpoints' heights, for bounding-box decisions and for
// vertical lines, and up to float rounding near the curve otherwise (Fig. 3):
//   0. at the height of an endpoint, compare with that endpoint's x;
//   1. left of the bounding box: left; right of it: right;
//   2. otherwise compare with the diagonal (chord) from start to end. A
//      curved piece bulges to one side of its chord (it is convex: cubics
//      are split at inflections). On the other side of the chord, or on it,
//      the answer is the opposite of the bulge side;
//   3. on the bulge side, inside the test region, triangle P0 C P1 (§3.2,
//      C the intersection of the end tangents), the sign of the implicit
//      function decides. Outside the triangle the point is beyond the curve,
//      on its bulge side. (The paper tests quadratics in the larger triangle
//      Q0 B1 Q2; here the tangent edges are needed anyway to evaluate the
//      implicit, so every curve uses P0 C P1.)
//
// The implicit function of a curved piece is the implicit equation of its
// curve written in the barycentric coordinates of its own test triangle
// P0 C P1 (C the intersection of the end tangents, §3.2). The triangle's edge
// functions -- the chord, and the tangent lines P0-C and C-P1 -- are
// affine, as in the paper's (k s)^2 - (l s)(m s) forms, and are what the
// triangle test computes anyway:
//   bc(p)  chord function (zero on P0 P1)       ~ barycentric of C
//   b1(p)  cross(C - P0, p - P0) (zero on P0 C) ~ barycentric of P1
//   b0(p)  cross(P1 - C, p - C)  (zero on C P1) ~ barycentric of P0
// A conic piece is exactly  k0 bc^2 + k1 b0 b1  (b_C^2 - 4 w^2 b_0 b_1); a
// cubic piece is a homogeneous cubic in (b0, bc, b1) with 10 coefficients.
// Inside the triangle these coordinates are bounded and the polynomial has no
// large cancelling terms, so float evaluation stays accurate (a monomial
// expansion in x and y does not: a near-square quadratic form expanded into
// monomials loses most of its digits). Coefficients are scaled at lowering so
// that f > 0 means left.
#pragma once
#include <cstdint>

#include "core/hd.h"

namespace mpvg {

enum AbstractType : uint32_t {
  ABSTRACT_LINE = 0,
  ABSTRACT_QUAD = 1,   // integral or rational quadratic
  ABSTRACT_CUBIC = 2,  // integral cubic
};

// flags layout:
//   bits 0-1  AbstractType
//   bit  3    ABSTRACT_BULGE_LEFT: the curve lies left of its chord
//   bit  4    ABSTRACT_TRI_POSITIVE: triangle P0 C P1 is positively oriented,
//             so b0 and b1 are positive inside it
enum : uint32_t {
  ABSTRACT_TYPE_MASK = 3u,
  ABSTRACT_BULGE_LEFT = 1u << 3,
  ABSTRACT_TRI_POSITIVE = 1u << 4,
};

struct alignas(16) AbstractSegment {
  float x0, y0, x1, y1;  // start and end, in pixel space
  uint32_t flags;
  uint32_t path;         // path instance (stream order)
  float cx, cy;          // apex C of the test triangle
  // Implicit coefficients. Conic: f = k[0] bc^2 + k[1] b0 b1. Cubic:
  // monomials b0^3, b0^2 bc, b0^2 b1, b0 bc^2, b0 bc b1, b0 b1^2, bc^3,
  // bc^2 b1, bc b1^2, b1^3.
  float k[10];
  float t0, t1;          // parameter range of the piece within its input segment
};
static_assert(sizeof(AbstractSegment) == 80, "AbstractSegment is an 80-byte record shared by CPU and GPU");

MPVG_HD_INLINE uint32_t abstract_type(const AbstractSegment& s) { return s.flags & ABSTRACT_TYPE_MASK; }
MPVG_HD_INLINE bool abstract_horizontal(const AbstractSegment& s) { return s.y0 == s.y1; }
MPVG_HD_INLINE int abstract_direction(const AbstractSegment& s) { return s.y1 > s.y0 ? 1 : -1; }
MPVG_HD_INLINE float abstract_ymin(const AbstractSegment& s) { return s.y0 < s.y1 ? s.y0 : s.y1; }
MPVG_HD_INLINE float abstract_ymax(const AbstractSegment& s) { return s.y0 < s.y1 ? s.y1 : s.y0; }
MPVG_HD_INLINE float abstract_xmin(const AbstractSegment& s) { return s.x0 < s.x1 ? s.x0 : s.x1; }
MPVG_HD_INLINE float abstract_xmax(const AbstractSegment& s) { return s.x0 < s.x1 ? s.x1 : s.x0; }
// X(y) increases with y (the piece runs south-west to north-east or back).
MPVG_HD_INLINE bool abstract_increasing(const AbstractSegment& s) {
  return (s.x1 >= s.x0) == (s.y1 >= s.y0);
}

// Chord function: > 0 on one side of the line through the endpoints, 0 on
// it (exactly at both endpoints: the two products are then the same floats
// in the same order, and nothing is contracted into an FMA).
MPVG_HD_INLINE float abstract_chord_raw(const AbstractSegment& s, float px, float py) {
  return (py - s.y0) * (s.x1 - s.x0) - (px - s.x0) * (s.y1 - s.y0);
}

// Chord test: > 0 when p is left of the chord (smaller x at the same y).
MPVG_HD_INLINE float abstract_chord(const AbstractSegment& s, float px, float py) {
  const float d = abstract_chord_raw(s, px, py);
  return s.y1 > s.y0 ? d : -d;
}

// The implicit in triangle coordinates (see the top of this file), of a
// conic piece and of a cubic one from its coefficients k.
MPVG_HD_ALWAYS_INLINE float abstract_implicit_quad(const float* k, float b0, float bc, float b1) {
  return k[0] * bc * bc + k[1] * b0 * b1;
}
MPVG_HD_ALWAYS_INLINE float abstract_implicit_cubic(const float* k, float b0, float bc, float b1) {
  return b0 * (b0 * (k[0] * b0 + k[1] * bc + k[2] * b1) + bc * (k[3] * bc + k[4] * b1) + k[5] * b1 * b1) +
         bc * (bc * (k[6] * bc + k[7] * b1) + k[8] * b1 * b1) + k[9] * b1 * b1 * b1;
}
MPVG_HD_INLINE float abstract_implicit_tri(const AbstractSegment& s, float b0, float bc, float b1) {
  if (abstract_type(s) == ABSTRACT_QUAD) return abstract_implicit_quad(s.k, b0, bc, b1);
  return abstract_implicit_cubic(s.k, b0, bc, b1);
}

MPVG_HD_INLINE float abstract_tri_b1(const AbstractSegment& s, float px, float py) {
  return (s.cx - s.x0) * (py - s.y0) - (s.cy - s.y0) * (px - s.x0);
}
MPVG_HD_INLINE float abstract_tri_b0(const AbstractSegment& s, float px, float py) {
  return (s.x1 - s.cx) * (py - s.cy) - (s.y1 - s.cy) * (px - s.cx);
}

// The implicit function at p (curved pieces only).
MPVG_HD_INLINE float abstract_implicit(const AbstractSegment& s, float px, float py) {
  return abstract_implicit_tri(s, abstract_tri_b0(s, px, py), abstract_chord_raw(s, px, py),
                               abstract_tri_b1(s, px, py));
}

// +1 when px < x, -1 when px > x, 0 when equal.
MPVG_HD_ALWAYS_INLINE int abstract_side_of(float px, float x) { return int(px < x) - int(px > x); }

// c ? a : b as a mask: gcc vectorises a loop of these where it will not
// if-convert the conditional (of float comparisons) in the loop's body.
MPVG_HD_ALWAYS_INLINE int select_int(bool c, int a, int b) {
  const int m = -static_cast<int>(c);
  return (a & m) | (b & ~m);
}

// side(p) and the ray test of a line piece: the decisions of abstract_side
// and abstract_ray_winding below, in the same order of precedence, written
// as selects from values of the piece taken once, so that a loop over
// samples vectorises (the CPU's sample lanes, sampling.h). The chord is
// abstract_chord's: the same operations on the same floats, its sign
// flipped for a downward piece. On a vertical piece every p is at or
// beyond xmin or xmax, and a point on its line is on it (0).
struct LineTest {
  float x0, y0, x1, y1, dx, dy, xmin, xmax, lo, hi;
  bool up;  // y1 > y0
  MPVG_HD_ALWAYS_INLINE explicit LineTest(const AbstractSegment& s)
      : x0(s.x0), y0(s.y0), x1(s.x1), y1(s.y1), dx(s.x1 - s.x0), dy(s.y1 - s.y0), xmin(abstract_xmin(s)),
        xmax(abstract_xmax(s)), lo(s.y1 > s.y0 ? s.y0 : s.y1), hi(s.y1 > s.y0 ? s.y1 : s.y0), up(s.y1 > s.y0) {}
  // abstract_chord_raw.
  MPVG_HD_ALWAYS_INLINE float chord(float px, float py) const { return (py - y0) * dx - (px - x0) * dy; }
  // The decisions every piece takes first, at an endpoint's height and
  // outside the x-range, over `inner`, the decision elsewhere.
  MPVG_HD_ALWAYS_INLINE int bounded(float px, float py, int inner) const {
    int r = select_int(px >= xmax, -1, inner);
    r = select_int(px <= xmin, 1 - (int(px == xmin) & int(px == xmax)), r);
    r = select_int(py == y1, abstract_side_of(px, x1), r);
    return select_int(py == y0, abstract_side_of(px, x0), r);
  }
  // abstract_side's precondition.
  MPVG_HD_ALWAYS_INLINE int side(float px, float py) const {
    const float d = chord(px, py);
    const int c = int(d > 0.0f) - int(d < 0.0f);
    return bounded(px, py, select_int(up, c, -c));
  }
  // abstract_ray_winding: the half-open y-range, then the side.
  MPVG_HD_ALWAYS_INLINE int winding(float px, float py) const { return crossing(py, side(px, py)); }
  MPVG_HD_ALWAYS_INLINE int crossing(float py, int side) const {
    const int crosses = int(!(py < lo)) & int(!(py >= hi)) & int(side > 0);
    return select_int(up, crosses, -crosses);
  }
};

// The same for a curved piece of type Type (ABSTRACT_QUAD or _CUBIC): the
// decisions of abstract_side's curve case, the chord, the bulge side,
// triangle P0 C P1 and the implicit, each computed for every point (their
// floats as abstract_side computes them) and selected in abstract_side's
// order. abstract_side itself takes them one by one, returning early: the
// subdivision and the GPU ask one point at a time. test_sample_lanes checks
// that both decide alike.
template <uint32_t Type>
struct CurveTest {
  LineTest line;
  float cx, cy, c0x, c0y, c1x, c1y;
  float k[Type == ABSTRACT_QUAD ? 2 : 10];
  bool bulge_left, positive;
  MPVG_HD_ALWAYS_INLINE explicit CurveTest(const AbstractSegment& s)
      : line(s), cx(s.cx), cy(s.cy), c0x(s.cx - s.x0), c0y(s.cy - s.y0), c1x(s.x1 - s.cx), c1y(s.y1 - s.cy),
        bulge_left((s.flags & ABSTRACT_BULGE_LEFT) != 0), positive((s.flags & ABSTRACT_TRI_POSITIVE) != 0) {
    for (int i = 0; i < int(sizeof k / sizeof k[0]); i++) k[i] = s.k[i];
  }
  MPVG_HD_ALWAYS_INLINE int side(float px, float py) const {
    const float d = line.chord(px, py);
    const int c = int(d > 0.0f) - int(d < 0.0f);
    const int chord = select_int(line.up, c, -c);  // abstract_chord's sign
    const int on_bulge_side = select_int(bulge_left, int(chord > 0), int(chord < 0));
    const float b0 = c1x * (py - cy) - c1y * (px - cx);             // abstract_tri_b0
    const float b1 = c0x * (py - line.y0) - c0y * (px - line.x0);  // abstract_tri_b1
    const int outside = select_int(positive, int(b0 < 0.0f) | int(b1 < 0.0f), int(b0 > 0.0f) | int(b1 > 0.0f));
    const float f = Type == ABSTRACT_QUAD ? abstract_implicit_quad(k, b0, d, b1) : abstract_implicit_cubic(k, b0, d, b1);
    const int bulge = select_int(bulge_left, 1, -1);
    int r = int(f > 0.0f) - int(f < 0.0f);
    r = select_int(outside != 0, bulge, r);
    r = select_int(on_bulge_side == 0, -bulge, r);
    return line.bounded(px, py, r);
  }
  MPVG_HD_ALWAYS_INLINE int winding(float px, float py) const { return line.crossing(py, side(px, py)); }
};

// side(p) as specified at the top of this file. Precondition: p.y lies in
// the closed y-range of the piece; the piece is not horizontal.
MPVG_HD_INLINE int abstract_side(const AbstractSegment& s, float px, float py) {
  const uint32_t type = abstract_type(s);
  if (type == ABSTRACT_LINE) return LineTest(s).side(px, py);
  const float xmin = abstract_xmin(s), xmax = abstract_xmax(s);
  if (xmin == xmax) return abstract_side_of(px, xmin);  // vertical
  // At an endpoint's height X is that endpoint's x: decide exactly. These are
  // the heights at which subdivision tests a piece whose end lies in a cell,
  // often beside a horizontal tangent (pieces end at y-extrema), where an
  // implicit test could not tell the sides apart.
  if (py == s.y0) return abstract_side_of(px, s.x0);
  if (py == s.y1) return abstract_side_of(px, s.x1);
  // Elsewhere X(y) lies strictly inside (xmin, xmax).
  if (px <= xmin) return 1;
  if (px >= xmax) return -1;
  const float d = abstract_chord(s, px, py);
  const bool bulge_left = (s.flags & ABSTRACT_BULGE_LEFT) != 0;
  const bool on_bulge_side = bulge_left ? d > 0.0f : d < 0.0f;
  // On the chord, or beyond it from the bulge, a point is on the far side of
  // the curve (only the endpoints, handled above, touch both).
  if (!on_bulge_side) return bulge_left ? -1 : 1;
  // Inside triangle P0 C P1 the implicit decides; beyond its tangent edges
  // the point is beyond the curve, on its bulge side.
  const float b0 = abstract_tri_b0(s, px, py), b1 = abstract_tri_b1(s, px, py);
  const bool positive = (s.flags & ABSTRACT_TRI_POSITIVE) != 0;
  if (positive ? (b0 < 0.0f || b1 < 0.0f) : (b0 > 0.0f || b1 > 0.0f)) return bulge_left ? 1 : -1;
  const float f = abstract_implicit_tri(s, b0, abstract_chord_raw(s, px, py), b1);
  return f > 0.0f ? 1 : (f < 0.0f ? -1 : 0);
}

// Does the horizontal ray from p towards +x cross the piece? The y-range is
// half-open, so a ray through a shared vertex counts it once, and horizontal
// pieces never count. Returns the winding increment: +1 upward, -1 downward.
// A line piece's test is LineTest's; a curve's returns as early as it can.
MPVG_HD_INLINE int abstract_ray_winding(const AbstractSegment& s, float px, float py) {
  if (abstract_type(s) == ABSTRACT_LINE) return LineTest(s).winding(px, py);
  if (s.y1 > s.y0) {
    if (py < s.y0 || py >= s.y1) return 0;
    return abstract_side(s, px, py) > 0 ? 1 : 0;
  }
  if (py < s.y1 || py >= s.y0) return 0;
  return abstract_side(s, px, py) > 0 ? -1 : 0;
}

}  // namespace mpvg
