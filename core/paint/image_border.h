// The image's border. The output is a window onto the plane: the unit
// areas of a margin around it (the filter's radius, and the cardinal
// prefilter's padding) are sampled like any other, so content that crosses
// the border is filtered as it would be in a larger image cropped to this
// one (core/sampling/integration.h).
//
// A path's straight edge that lies on the border is different: it is where
// the drawing stops there, a background the size of the canvas, a page's
// clip to its box, an image that fills the view. Filtered as a window, such
// content would fade over the filter's radius into the empty margin, and
// every icon and page would have a translucent frame where browsers and
// coverage renderers give opaque edges. So the encoder pushes each such
// edge out past the frame's edge: the edge a -> b becomes a -> a' -> b' ->
// b, a' and b' the points of the frame's edge beyond a and b (the frame's
// corner where a or b is a corner of the image). Everything added lies in
// the margin, so no sample inside the image sees a difference; what lies
// on the canvas side of the edge continues through the margin, and what
// lies outside it (content beyond the border that stops there) no longer
// reaches in.
//
// Curves whose control points all lie on one border line are such edges
// too. A point is on a line when within kBorderTolerance of it: transforms
// of integer-sized documents to integer pixel sizes round a little.
#pragma once
#include <cmath>
#include <vector>

#include "core/geometry/abstraction.h"

namespace mpvg {

constexpr double kBorderTolerance = 1.0 / 1024.0;

// In the coordinates the encoder works in (unit areas): the image is
// [x0, x1) x [y0, y1), the frame sampled around it [fx0, fx1) x [fy0, fy1).
// Unset (the default): no edge is pushed out (pattern tiles, offscreen
// grids).
struct ImageBorder {
  bool set = false;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double fx0 = 0, fy0 = 0, fx1 = 0, fy1 = 0;
};

namespace border_detail {

enum Side { kNone, kLeft, kRight, kTop, kBottom };

inline bool near(double a, double b) { return std::fabs(a - b) <= kBorderTolerance; }

// The index of s's last control point (its end point).
inline int last_point(const InputSegment& s) {
  return s.type == INPUT_LINE ? 1 : (s.type == INPUT_CUBIC ? 3 : 2);
}

// The border line all of s's control points lie on, if any.
inline Side side_of(const ImageBorder& b, const InputSegment& s) {
  const int n = last_point(s) + 1;
  auto all = [&](const double* v, double at) {
    for (int i = 0; i < n; i++)
      if (!near(v[i], at)) return false;
    return true;
  };
  if (all(s.x, b.x0)) return kLeft;
  if (all(s.x, b.x1)) return kRight;
  if (all(s.y, b.y0)) return kTop;
  if (all(s.y, b.y1)) return kBottom;
  return kNone;
}

// Where point (x, y) on side `side` goes: one unit area past the frame's
// edge, or past its corner where (x, y) is a corner of the image.
inline void push_out(const ImageBorder& b, Side side, double x, double y, double* ox, double* oy) {
  const double l = b.fx0 - 1, r = b.fx1 + 1, t = b.fy0 - 1, d = b.fy1 + 1;
  *ox = x, *oy = y;
  if (side == kLeft || side == kRight) {
    *ox = side == kLeft ? l : r;
    if (near(y, b.y0)) *oy = t;
    if (near(y, b.y1)) *oy = d;
  } else {
    *oy = side == kTop ? t : d;
    if (near(x, b.x0)) *ox = l;
    if (near(x, b.x1)) *ox = r;
  }
}

inline InputSegment line(uint32_t path, double x0, double y0, double x1, double y1) {
  InputSegment s{};
  s.type = INPUT_LINE;
  s.path = path;
  s.w = 1.0;
  s.x[0] = x0, s.y[0] = y0, s.x[1] = x1, s.y[1] = y1;
  return s;
}

}  // namespace border_detail

// Pushes out the border edges among segs[first, end) (one or more closed
// contours). Returns how many edges it pushed out.
inline size_t push_out_border_edges(const ImageBorder& b, std::vector<InputSegment>& segs, size_t first) {
  using namespace border_detail;
  if (!b.set) return 0;
  size_t found = 0;
  for (size_t i = first; i < segs.size(); i++)
    if (side_of(b, segs[i]) != kNone) found++;
  if (found == 0) return 0;
  std::vector<InputSegment> out;
  out.reserve(segs.size() - first + 2 * found);
  for (size_t i = first; i < segs.size(); i++) {
    const InputSegment& s = segs[i];
    const Side side = side_of(b, s);
    if (side == kNone) {
      out.push_back(s);
      continue;
    }
    const int last = last_point(s);
    const double ax = s.x[0], ay = s.y[0], bx = s.x[last], by = s.y[last];
    double pax, pay, pbx, pby;
    push_out(b, side, ax, ay, &pax, &pay);
    push_out(b, side, bx, by, &pbx, &pby);
    out.push_back(line(s.path, ax, ay, pax, pay));
    out.push_back(line(s.path, pax, pay, pbx, pby));
    out.push_back(line(s.path, pbx, pby, bx, by));
  }
  segs.resize(first);
  segs.insert(segs.end(), out.begin(), out.end());
  return found;
}

}  // namespace mpvg
