#include "stroker/stroke_input.h"

#include <algorithm>
#include <cmath>

namespace mpvg {

static_assert(static_cast<uint32_t>(LineJoin::Miter) == stroking::JOIN_MITER &&
                  static_cast<uint32_t>(LineJoin::MiterClip) == stroking::JOIN_MITER_CLIP &&
                  static_cast<uint32_t>(LineJoin::Arcs) == stroking::JOIN_ARCS &&
                  static_cast<uint32_t>(LineJoin::Round) == stroking::JOIN_ROUND &&
                  static_cast<uint32_t>(LineJoin::Bevel) == stroking::JOIN_BEVEL,
              "LineJoin and the stroke stage's JOIN_* agree");
static_assert(static_cast<uint32_t>(LineCap::Butt) == stroking::CAP_BUTT &&
                  static_cast<uint32_t>(LineCap::Round) == stroking::CAP_ROUND &&
                  static_cast<uint32_t>(LineCap::Square) == stroking::CAP_SQUARE,
              "LineCap and the stroke stage's CAP_* agree");

namespace {

// The dash pattern that `dashes` describes (SVG 2 painting.html#StrokeDashing):
// false when a value is negative or not finite (no dashing, as for an empty
// list or one that sums to zero); else the list, repeated once when its
// length is odd.
bool pattern_of(const std::vector<double>& dashes, std::vector<double>& out) {
  double sum = 0;
  for (double d : dashes) {
    if (!(d >= 0) || !std::isfinite(d)) return false;
    sum += d;
  }
  if (!(sum > 0) || !std::isfinite(sum)) return false;
  out = dashes;
  if (out.size() % 2 == 1) out.insert(out.end(), dashes.begin(), dashes.end());
  return true;
}

bool finite_point(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

}  // namespace

bool StrokeBatch::add(const Path& path, const StrokeStyle& style, const Affine& to_pixels, uint32_t path_id,
                      double tolerance_px) {
  using namespace stroking;
  if (!(style.width > 0) || !std::isfinite(style.width)) return false;
  if (!to_pixels.invertible()) return false;
  // The largest singular value of the linear part: user-space errors grow
  // by at most this much in pixels.
  const Affine& m = to_pixels;
  const double p = m.a * m.a + m.b * m.b, q = m.c * m.c + m.d * m.d, r = m.a * m.c + m.b * m.d;
  const double sigma = std::sqrt((p + q + std::sqrt((p - q) * (p - q) + 4 * r * r)) / 2);
  if (!(sigma > 0) || !std::isfinite(sigma)) return false;

  StrokeRecord rec{};
  const double xf[6] = {m.a, m.b, m.c, m.d, m.e, m.f};
  std::copy(xf, xf + 6, rec.xf);
  rec.h = style.width / 2;
  rec.miter_limit = std::isfinite(style.miter_limit) ? std::max(1.0, style.miter_limit) : 1.0;
  rec.tol = std::max(tolerance_px, 1e-6) / sigma;
  rec.join = static_cast<uint32_t>(style.join);
  rec.cap = static_cast<uint32_t>(style.cap);
  rec.path = path_id;
  std::vector<double> pattern;
  if (pattern_of(style.dashes, pattern)) {
    double sum = 0;
    for (double d : pattern) sum += d;
    // A negative offset d counts from the end: sum - (|d| mod sum)
    // (SVG 2 painting.html#StrokeDashoffsetProperty).
    double off = std::isfinite(style.dash_offset) ? std::fmod(style.dash_offset, sum) : 0;
    if (off < 0) off += sum;
    if (!(off < sum)) off = 0;
    rec.dash_first = static_cast<uint32_t>(dashes.size());
    rec.dash_count = static_cast<uint32_t>(pattern.size());
    rec.dash_sum = sum;
    rec.dash_offset = off;
  }
  const uint32_t stroke_id = static_cast<uint32_t>(strokes.size());
  const size_t subpaths0 = subpaths.size(), segments0 = segments.size();

  const auto& pts = path.points();
  for (const Path::Contour& c : path.contours()) {
    StrokeSubpath sp{};
    sp.stroke = stroke_id;
    sp.first_segment = static_cast<uint32_t>(segments.size());
    sp.start = pts[c.start_point];
    bool ok = finite_point(sp.start);
    uint32_t kept = 0;
    for (uint32_t k = 0; k < c.segment_count && ok; k++) {
      const Path::Segment& s = path.segments()[c.first_segment + k];
      Curve cv;
      switch (s.type) {
        case SegmentType::Line: cv.type = CURVE_LINE; break;
        case SegmentType::Quad: cv.type = CURVE_QUAD; break;
        case SegmentType::RQuad: cv.type = CURVE_RQUAD; break;
        case SegmentType::Cubic: cv.type = CURVE_CUBIC; break;
        case SegmentType::RCubic: ok = false; break;  // no frontend makes them; encode() refuses them
      }
      if (!ok) break;
      for (int i = 0; i <= cv.degree(); i++) {
        cv.p[i] = pts[s.first_point + i];
        ok = ok && finite_point(cv.p[i]);
      }
      if (cv.type == CURVE_RQUAD) {
        cv.w = path.weights()[s.first_weight];
        ok = ok && std::isfinite(cv.w) && cv.w > 0;
      }
      if (ok && cv.extent() > 0) {
        segments.push_back({cv, static_cast<uint32_t>(subpaths.size()), kept});
        kept++;
      }
    }
    // A contour with a non-finite coordinate is left out whole.
    if (!ok) {
      segments.resize(sp.first_segment);
      continue;
    }
    sp.segment_count = kept;
    if (c.closed) sp.flags |= SUBPATH_CLOSED;
    if (kept == 0) {
      if (!(c.segment_count > 0 || c.closed)) continue;
      sp.flags |= SUBPATH_ZERO_LENGTH;
    }
    sp.first_vertex = nvertices;
    nvertices += subpath_vertices(sp);
    first_element.push_back(nelements);
    nelements += sp.segment_count + subpath_vertices(sp);
    subpaths.push_back(sp);
  }
  if (subpaths.size() == subpaths0) {
    segments.resize(segments0);
    return false;
  }
  dashes.insert(dashes.end(), pattern.begin(), pattern.end());
  double end = 0;
  for (double d : pattern) dash_ends.push_back(end += d);
  strokes.push_back(rec);
  return true;
}

Hairline hairline(double width, const Affine& to_device, double min_device_width) {
  const double scale = std::sqrt(std::fabs(to_device.det()));
  if (!(scale > 0) || !std::isfinite(scale) || !(min_device_width > 0)) return {width, 1};
  const double min_user = min_device_width / scale;
  if (!(width > 0)) return {min_user, 1};
  if (width >= min_user) return {width, 1};
  return {min_user, width / min_user};
}

}  // namespace mpvg
