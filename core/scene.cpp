#include "core/scene.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/error.h"
#include "core/paint/group.h"

namespace mpvg {

// ---------------------------------------------------------------- Path

void Path::ensure_contour() {
  if (points_.empty()) throw Error("path segment without a current point");
  if (!open_contour_) {
    // A segment after close() starts a new contour at the current point.
    Contour c;
    c.first_segment = static_cast<uint32_t>(segments_.size());
    c.start_point = static_cast<uint32_t>(points_.size() - 1);
    contours_.push_back(c);
    open_contour_ = true;
  }
}

void Path::move_to(Vec2 p) {
  points_.push_back(p);
  Contour c;
  c.first_segment = static_cast<uint32_t>(segments_.size());
  c.start_point = static_cast<uint32_t>(points_.size() - 1);
  contours_.push_back(c);
  open_contour_ = true;
}

void Path::add_segment(SegmentType t, uint32_t first_weight) {
  const uint32_t deg = static_cast<uint32_t>(segment_degree(t));
  Segment s{t, static_cast<uint32_t>(points_.size() - 1 - deg), first_weight};
  segments_.push_back(s);
  contours_.back().segment_count++;
}

void Path::line_to(Vec2 p) {
  ensure_contour();
  points_.push_back(p);
  add_segment(SegmentType::Line, 0);
}

void Path::quad_to(Vec2 p1, Vec2 p2) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  add_segment(SegmentType::Quad, 0);
}

void Path::rquad_to(Vec2 p1, Vec2 p2, double w) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  weights_.push_back(w);
  add_segment(SegmentType::RQuad, static_cast<uint32_t>(weights_.size() - 1));
}

void Path::cubic_to(Vec2 p1, Vec2 p2, Vec2 p3) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  points_.push_back(p3);
  add_segment(SegmentType::Cubic, 0);
}

void Path::rcubic_to(Vec2 p1, Vec2 p2, Vec2 p3, double w0, double w1, double w2, double w3) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  points_.push_back(p3);
  const uint32_t first = static_cast<uint32_t>(weights_.size());
  weights_.insert(weights_.end(), {w0, w1, w2, w3});
  add_segment(SegmentType::RCubic, first);
}

void Path::close() {
  if (!open_contour_ || contours_.empty()) return;
  Contour& c = contours_.back();
  const Vec2 start = points_[c.start_point];
  if (c.segment_count > 0 && points_.back() != start) line_to(start);
  c.closed = true;
  open_contour_ = false;
}

Path Path::contour_path(size_t i) const {
  const Contour& c = contours_.at(i);
  Path out;
  out.move_to(points_[c.start_point]);
  for (uint32_t k = c.first_segment; k < c.first_segment + c.segment_count; k++) {
    const Segment& s = segments_[k];
    const Vec2* p = &points_[s.first_point];
    const double* w = weights_.data() + s.first_weight;
    switch (s.type) {
      case SegmentType::Line: out.line_to(p[1]); break;
      case SegmentType::Quad: out.quad_to(p[1], p[2]); break;
      case SegmentType::RQuad: out.rquad_to(p[1], p[2], w[0]); break;
      case SegmentType::Cubic: out.cubic_to(p[1], p[2], p[3]); break;
      case SegmentType::RCubic: out.rcubic_to(p[1], p[2], p[3], w[0], w[1], w[2], w[3]); break;
    }
  }
  if (c.closed) out.close();
  return out;
}

Path Path::rectangle(double x0, double y0, double x1, double y1) {
  Path p;
  p.move_to({x0, y0});
  p.line_to({x1, y0});
  p.line_to({x1, y1});
  p.line_to({x0, y1});
  p.close();
  return p;
}

Path Path::transformed(const Affine& m) const {
  Path out = *this;
  for (Vec2& p : out.points_) p = m.apply(p);
  return out;
}

void Path::append(const Path& other) {
  const auto np = static_cast<uint32_t>(points_.size());
  const auto nw = static_cast<uint32_t>(weights_.size());
  const auto ns = static_cast<uint32_t>(segments_.size());
  points_.insert(points_.end(), other.points_.begin(), other.points_.end());
  weights_.insert(weights_.end(), other.weights_.begin(), other.weights_.end());
  for (Segment s : other.segments_) {
    s.first_point += np;
    if (s.type == SegmentType::RQuad || s.type == SegmentType::RCubic) s.first_weight += nw;
    segments_.push_back(s);
  }
  for (Contour c : other.contours_) {
    c.first_segment += ns;
    c.start_point += np;
    contours_.push_back(c);
  }
  if (!other.contours_.empty()) open_contour_ = other.open_contour_;
}

size_t path_bytes(const Path& p) {
  // (Capacities: what the arrays hold, grown by doubling.)
  return sizeof(Path) + p.points().capacity() * sizeof(Vec2) + p.weights().capacity() * sizeof(double) +
         p.segments().capacity() * sizeof(Path::Segment) + p.contours().capacity() * sizeof(Path::Contour);
}

const char* blend_mode_name(BlendMode m) {
  static const char* const names[] = {"normal",       "multiply",    "screen",     "overlay",    "darken",
                                      "lighten",      "color-dodge", "color-burn", "hard-light", "soft-light",
                                      "difference",   "exclusion",   "hue",        "saturation", "color",
                                      "luminosity",   "plus-lighter", "source-atop", "xor"};
  static_assert(sizeof names / sizeof names[0] == static_cast<size_t>(BlendMode::Xor) + 1, "a name per mode");
  const auto i = static_cast<size_t>(m);
  return i < sizeof names / sizeof names[0] ? names[i] : "?";
}

}  // namespace mpvg
