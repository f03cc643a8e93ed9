// Stage "stroke", the output side: every element of a stroke (a segment's
// body, a join, a cap) emits closed contours through an Emitter, which
// bridges gaps with lines, leaves out degenerate pieces and closes each
// contour, and hands the segments to a sink: CountSink for the counting
// pass, SegmentSink for the writing pass (stroker/stroke.h).
#pragma once
#include <cstdint>

#include "core/geometry/abstraction.h"
#include "stroker/stroke_curve.h"

namespace mpvg::stroking {

// A boundary element of a piece: a line p0 -> p2, a quadratic or a conic.
struct Piece {
  uint32_t type;  // CURVE_LINE, CURVE_QUAD or CURVE_RQUAD
  Vec2 p0, p1, p2;
  double w = 1;
};

MPVG_HD_INLINE Piece reversed(Piece q) {
  const Vec2 t = q.p0;
  q.p0 = q.p2;
  q.p2 = t;
  return q;
}

// Counts segments (the first pass of every element).
struct CountSink {
  uint32_t n = 0;
  MPVG_HD void segment(uint32_t, Vec2, Vec2, Vec2, double) { n++; }
};

// A segment as the abstraction stage's input: mapped from user space to
// pixels by xf (a b c d e f, as Affine), tagged with the output path.
MPVG_HD_INLINE InputSegment input_segment(uint32_t type, Vec2 a, Vec2 b, Vec2 c, double w, uint32_t path,
                                          const double* xf) {
  auto map = [&](Vec2 p) { return Vec2{xf[0] * p.x + xf[2] * p.y + xf[4], xf[1] * p.x + xf[3] * p.y + xf[5]}; };
  InputSegment s{};
  s.type = type;
  s.path = path;
  s.w = type == CURVE_RQUAD ? w : 1.0;
  const Vec2 q0 = map(a), q1 = map(b);
  s.x[0] = q0.x, s.y[0] = q0.y, s.x[1] = q1.x, s.y[1] = q1.y;
  if (type != CURVE_LINE) {
    const Vec2 q2 = map(c);
    s.x[2] = q2.x, s.y[2] = q2.y;
  }
  return s;
}

// Writes segments at out[0, capacity) (the counting pass sized it; writes
// past it are counted but dropped, and the caller compares n).
struct SegmentSink {
  InputSegment* out;
  uint32_t capacity;
  uint32_t path;
  const double* xf;
  uint32_t n = 0;

  MPVG_HD void segment(uint32_t type, Vec2 a, Vec2 b, Vec2 c, double w) {
    if (n < capacity) out[n] = input_segment(type, a, b, c, w, path, xf);
    n++;
  }
};

// Builds closed contours from pieces, one at a time: bridges gaps with
// lines, leaves out pieces of no length (a contour of degenerate pieces
// leaves nothing) and closes each contour back to where it began.
template <class Sink>
class Emitter {
 public:
  MPVG_HD explicit Emitter(Sink& sink) : sink_(sink) {}

  MPVG_HD void begin(Vec2 p) {
    start_ = cur_ = p;
    open_ = false;
  }
  MPVG_HD void line(Vec2 p) {
    if (p == cur_) return;
    open_ = true;
    sink_.segment(CURVE_LINE, cur_, p, p, 1);
    cur_ = p;
  }
  // A piece, bridging a gap before it with a line.
  MPVG_HD void piece(const Piece& q) {
    line(q.p0);
    if (q.type == CURVE_LINE) {
      line(q.p2);
    } else if (q.p0 != q.p2 || q.p1 != q.p0) {
      open_ = true;
      sink_.segment(q.type, cur_, q.p1, q.p2, q.w);
      cur_ = q.p2;
    }
  }
  MPVG_HD void close() {
    if (open_) line(start_);
    open_ = false;
  }

  // A convex polygon, counter-clockwise whatever the order given, so that
  // it winds +1 inside; nothing when it has no area.
  MPVG_HD void polygon(const Vec2* p, int n) {
    double area = 0;
    for (int i = 1; i + 1 < n; i++) area += cross(p[i] - p[0], p[i + 1] - p[0]);
    if (!(area != 0) || !finite(area)) return;
    if (area > 0) {
      begin(p[0]);
      for (int i = 1; i < n; i++) line(p[i]);
    } else {
      begin(p[n - 1]);
      for (int i = n - 1; i-- > 0;) line(p[i]);
    }
    close();
  }

  // The circular arc of centre o and radius r from angle a0 over `sweep`
  // radians (positive: counter-clockwise), as conics of at most 90°. A
  // conic with its middle control point where the end tangents meet and
  // weight cos(half the angle) is exactly the arc. Appended to the contour.
  MPVG_HD void arc(Vec2 o, double r, double a0, double sweep) {
    int n = static_cast<int>(ceil(fabs(sweep) / (kPi / 2) - 1e-9));
    if (n < 1) n = 1;
    const double d = sweep / n;
    const double w = cos(d / 2);
    for (int i = 0; i < n; i++) piece(arc_piece(o, r, a0 + i * d, d, w));
  }
  MPVG_HD static Piece arc_piece(Vec2 o, double r, double s, double d, double w) {
    return {CURVE_RQUAD, Vec2{o.x + r * cos(s), o.y + r * sin(s)},
            Vec2{o.x + r / w * cos(s + d / 2), o.y + r / w * sin(s + d / 2)},
            Vec2{o.x + r * cos(s + d), o.y + r * sin(s + d)}, w};
  }

  // A disk, counter-clockwise: four quarter conics.
  MPVG_HD void disk(Vec2 o, double r) {
    begin(Vec2{o.x + r, o.y});
    arc(o, r, 0, 2 * kPi);
    close();
  }

 private:
  Sink& sink_;
  Vec2 start_, cur_;
  bool open_ = false;  // a segment of the contour has been emitted
};

}  // namespace mpvg::stroking
