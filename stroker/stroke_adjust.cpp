// Stroke adjustment and thin-line snapping (stroker/stroke_adjust.h).
#include "stroker/stroke_adjust.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace mpvg {

namespace {

// Within this many pixels a line counts as horizontal or vertical.
constexpr double kAxisEps = 1e-3;

// A contour of lines only, each horizontal or vertical in device space.
bool rectilinear(const Path& path, const Path::Contour& c, const std::vector<Vec2>& dev) {
  if (c.segment_count == 0) return false;
  for (uint32_t k = c.first_segment; k < c.first_segment + c.segment_count; k++) {
    const Path::Segment& s = path.segments()[k];
    if (s.type != SegmentType::Line) return false;
    const Vec2 a = dev[s.first_point], b = dev[s.first_point + 1];
    if (std::fabs(a.x - b.x) > kAxisEps && std::fabs(a.y - b.y) > kAxisEps) return false;
  }
  return true;
}

// The contour's points (start, then each line's end) after `snap` moved
// them in device space, as a closed or open polyline in user space.
template <class Snap>
Path rebuild(const Path& path, size_t i, const std::vector<Vec2>& dev, const Affine& from_device, Snap&& snap) {
  const Path::Contour& c = path.contours()[i];
  std::vector<uint32_t> idx{c.start_point};
  for (uint32_t k = c.first_segment; k < c.first_segment + c.segment_count; k++)
    idx.push_back(path.segments()[k].first_point + 1);
  std::vector<Vec2> pts;
  for (uint32_t j : idx) pts.push_back(dev[j]);
  snap(pts);
  Path out;
  out.move_to(from_device.apply(pts[0]));
  for (size_t j = 1; j < pts.size(); j++) out.line_to(from_device.apply(pts[j]));
  if (c.closed) out.close();
  return out;
}

template <class Snap>
Path adjust(const Path& path, const Affine& to_device, Snap&& snap) {
  std::vector<Vec2> dev;
  dev.reserve(path.points().size());
  for (const Vec2& p : path.points()) dev.push_back(to_device.apply(p));
  const Affine from_device = to_device.inverted();
  Path out;
  for (size_t i = 0; i < path.contours().size(); i++) {
    const Path::Contour& c = path.contours()[i];
    out.append(rectilinear(path, c, dev) ? rebuild(path, i, dev, from_device, snap) : path.contour_path(i));
  }
  return out;
}

double uniform_scale(const Affine& m) { return std::sqrt(std::fabs(m.det())); }

}  // namespace

bool grid_aligned(const Affine& m) {
  if (!m.invertible()) return false;
  const double s = uniform_scale(m), tol = 1e-9 * s;
  const bool straight = std::fabs(m.b) <= tol && std::fabs(m.c) <= tol && std::fabs(std::fabs(m.a) - std::fabs(m.d)) <= tol;
  const bool quarter = std::fabs(m.a) <= tol && std::fabs(m.d) <= tol && std::fabs(std::fabs(m.b) - std::fabs(m.c)) <= tol;
  return straight || quarter;
}

Path adjust_stroke(const Path& centreline, double* width, const Affine& to_device) {
  const double scale = uniform_scale(to_device);
  if (!(scale > 0) || !std::isfinite(scale)) return centreline;
  const double pixels = *width * scale;
  if (!grid_aligned(to_device)) {
    if (pixels < 1) *width = 1 / scale;
    return centreline;
  }
  const double n = std::max(1.0, std::floor(pixels + 0.5));
  *width = n / scale;
  const bool odd = std::fmod(n, 2.0) == 1.0;
  auto centre = [odd](double v) { return odd ? std::floor(v) + 0.5 : std::floor(v + 0.5); };
  return adjust(centreline, to_device, [&](std::vector<Vec2>& p) {
    // A point on a horizontal line has its y centred, on a vertical line
    // its x (a corner both).
    std::vector<Vec2> q = p;
    for (size_t j = 0; j + 1 < p.size(); j++) {
      const bool horizontal = std::fabs(p[j].y - p[j + 1].y) <= kAxisEps;
      const bool vertical = std::fabs(p[j].x - p[j + 1].x) <= kAxisEps;
      if (horizontal) q[j].y = q[j + 1].y = centre(0.5 * (p[j].y + p[j + 1].y));
      if (vertical) q[j].x = q[j + 1].x = centre(0.5 * (p[j].x + p[j + 1].x));
    }
    // A contour that ends where it starts: the first and last point are
    // one corner, moved by the lines on both sides of it.
    if (p.size() > 2 && p.front() == p.back()) {
      if (q.back().x != p.back().x) q.front().x = q.back().x;
      if (q.back().y != p.back().y) q.front().y = q.back().y;
      if (q.front().x != p.front().x) q.back().x = q.front().x;
      if (q.front().y != p.front().y) q.back().y = q.front().y;
    }
    p = q;
  });
}

Path adjust_fill(const Path& geometry, const Affine& to_device) {
  if (!grid_aligned(to_device)) return geometry;
  return adjust(geometry, to_device, [](std::vector<Vec2>& p) {
    // One axis at a time: round to boundaries; a span of two values that
    // collapses keeps the pixel nearest its middle.
    auto axis = [&p](double Vec2::*v) {
      double lo = INFINITY, hi = -INFINITY;
      for (const Vec2& q : p) {
        lo = std::min(lo, q.*v);
        hi = std::max(hi, q.*v);
      }
      bool two = true;
      for (const Vec2& q : p) two = two && (q.*v == lo || q.*v == hi);
      const double rlo = std::floor(lo + 0.5), rhi = std::floor(hi + 0.5);
      if (two && hi > lo && rlo == rhi) {
        const double first = std::floor(0.5 * (lo + hi));
        for (Vec2& q : p) q.*v = q.*v == lo ? first : first + 1;
        return;
      }
      for (Vec2& q : p) q.*v = std::floor(q.*v + 0.5);
    };
    axis(&Vec2::x);
    axis(&Vec2::y);
  });
}

}  // namespace mpvg
