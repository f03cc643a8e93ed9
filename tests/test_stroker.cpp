// Stroke tests: the output of the stroke stage (stroker/stroke.h, run by
// stroke_cpu on a one-stroke StrokeBatch), filled with the nonzero rule, is
// compared point by point with independent definitions of the stroke.
//
//   - Round joins and caps: a point is inside exactly when its distance to
//     the centreline is at most half the width. The distance comes from
//     dense sampling and golden-section refinement of the centreline,
//     evaluated here from the Bernstein forms; inside/outside of the output
//     from the brute-force winding oracle (tests/oracle.h) over the stage's
//     segments. Points within twice the tolerance of the true boundary are
//     skipped.
//   - Polylines with butt/square caps and miter/miter-clip/bevel joins: the
//     expected shape is the union of the convex pieces of SVG 2
//     painting.html#StrokeShape, computed directly.
//   - Dashes against arc length (measured here by chords, placed by the
//     dash positions of SVG 2 written out here), degenerate input, the
//     tolerance, transforms.
//
// These tests held the previous stroker (stroke_to_fill, removed) to the
// same definitions; the stage replaced it once the two agreed.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "stroker/stroke_input.h"
#include "tests/catch.h"
#include "tests/oracle.h"
#include "tests/random_paths.h"

using namespace mpvg;
using namespace mpvg::test;

namespace {

constexpr double kTol = 1.0 / 16;

using Segments = std::vector<InputSegment>;

// The stage's output for one stroke: fill geometry in the space `to_device`
// maps the path to, within `tolerance_px` of the exact outline there.
Segments stroke_of(const Path& path, const StrokeStyle& style, const Affine& to_device = {},
                   double tolerance_px = kTol) {
  StrokeBatch batch;
  batch.add(path, style, to_device, 0, tolerance_px);
  return stroke_cpu(batch, 1);
}

// ---------------------------------------------------------------- oracles

// Inside/outside of the stage's segments filled with the nonzero rule (they
// are in device space already, one path).
class Filled {
 public:
  explicit Filled(const Segments& segs) : windings_(std::make_unique<oracle::Windings>(segs, 1)) {}
  // nullopt within `band` of an output curve, where ray casting is
  // ambiguous. The oracle also declines points level with a curve's end
  // point; those are retried a hair (1e-5) higher, far below every margin
  // the tests leave around the true boundary.
  std::optional<bool> inside(Vec2 p, double band = 1e-7) const {
    for (int k = 0; k < 4; k++) {
      const auto w = windings_->at(p.x, p.y + k * 1e-5, band);
      if (w) return (*w)[0] != 0;
    }
    return std::nullopt;
  }

 private:
  std::unique_ptr<oracle::Windings> windings_;
};

// A centreline segment evaluated from its definition.
struct Seg {
  SegmentType type;
  Vec2 p[4];
  double w = 1;
  Vec2 at(double t) const {
    const double u = 1 - t;
    switch (type) {
      case SegmentType::Line: return u * p[0] + t * p[1];
      case SegmentType::Quad: return (u * u) * p[0] + (2 * u * t) * p[1] + (t * t) * p[2];
      case SegmentType::RQuad: {
        const double b0 = u * u, b1 = 2 * u * t * w, b2 = t * t;
        return (1 / (b0 + b1 + b2)) * (b0 * p[0] + b1 * p[1] + b2 * p[2]);
      }
      default:
        return (u * u * u) * p[0] + (3 * u * u * t) * p[1] + (3 * u * t * t) * p[2] + (t * t * t) * p[3];
    }
  }
};

// An output segment as a Seg.
Seg seg_of(const InputSegment& s) {
  Seg g;
  g.type = s.type == INPUT_LINE    ? SegmentType::Line
           : s.type == INPUT_QUAD  ? SegmentType::Quad
           : s.type == INPUT_RQUAD ? SegmentType::RQuad
                                   : SegmentType::Cubic;
  for (int i = 0; i <= segment_degree(g.type); i++) g.p[i] = {s.x[i], s.y[i]};
  if (g.type == SegmentType::RQuad) g.w = s.w;
  return g;
}

// The control points of output segments.
std::vector<Vec2> control_points(const Segments& segs) {
  std::vector<Vec2> out;
  for (const InputSegment& s : segs)
    for (int i = 0; i <= segment_degree(seg_of(s).type); i++) out.push_back({s.x[i], s.y[i]});
  return out;
}

size_t count_type(const Segments& segs, uint32_t type) {
  size_t n = 0;
  for (const InputSegment& s : segs) n += s.type == type;
  return n;
}

double norm(Vec2 v) { return std::hypot(v.x, v.y); }

// The segments of every contour of a path, in order, with the points of
// contours without segments ("M p Z").
struct PathSegs {
  std::vector<std::vector<Seg>> contours;
  std::vector<Vec2> points;

  explicit PathSegs(const Path& path) {
    for (const Path::Contour& c : path.contours()) {
      if (c.segment_count == 0) points.push_back(path.points()[c.start_point]);
      std::vector<Seg> segs;
      for (uint32_t k = 0; k < c.segment_count; k++) {
        const Path::Segment& s = path.segments()[c.first_segment + k];
        Seg g;
        g.type = s.type;
        for (int i = 0; i <= segment_degree(s.type); i++) g.p[i] = path.points()[s.first_point + i];
        if (s.type == SegmentType::RQuad) g.w = path.weights()[s.first_weight];
        segs.push_back(g);
      }
      contours.push_back(std::move(segs));
    }
  }
};

// A centreline: pieces of segments (a segment on [t0, t1]), and points.
struct Centreline {
  struct Piece {
    Seg s;
    double t0 = 0, t1 = 1;
  };
  std::vector<Piece> pieces;
  std::vector<Vec2> points;

  Centreline() = default;
  // The whole path.
  explicit Centreline(const Path& path) {
    const PathSegs ps(path);
    points = ps.points;
    for (const auto& c : ps.contours)
      for (const Seg& s : c) pieces.push_back({s, 0, 1});
  }

  // Distance from q: the best of 512 samples per piece, each local minimum
  // of the samples refined by golden-section search. *interior tells
  // whether the nearest point lies inside a piece (away from its ends),
  // where q is on the segment's normal.
  double distance(Vec2 q, bool* interior = nullptr) const {
    double best = 1e300;
    bool inside_piece = false;
    auto consider = [&](double d, bool in) {
      if (d < best) {
        best = d;
        inside_piece = in;
      }
    };
    for (const Vec2& p : points) consider(norm(q - p), false);
    for (const Piece& pc : pieces) {
      const Seg& s = pc.s;
      const double t0 = pc.t0, t1 = pc.t1;
      auto in = [&](double t) { return t > t0 + 1e-6 && t < t1 - 1e-6; };
      if (s.type == SegmentType::Line) {
        const Vec2 ab = s.p[1] - s.p[0];
        const double l2 = dot(ab, ab);
        const double t = l2 > 0 ? std::clamp(dot(q - s.p[0], ab) / l2, t0, t1) : t0;
        consider(norm(q - s.at(t)), in(t));
        continue;
      }
      constexpr int n = 512;
      auto param = [&](int i) { return t0 + (t1 - t0) * i / n; };
      double d[n + 1];
      for (int i = 0; i <= n; i++) d[i] = norm(q - s.at(param(i)));
      for (int i = 0; i <= n; i++) {
        consider(d[i], in(param(i)));
        if ((i > 0 && d[i] > d[i - 1]) || (i < n && d[i] > d[i + 1])) continue;
        double lo = param(std::max(0, i - 1)), hi = param(std::min(n, i + 1));
        const double g = (std::sqrt(5.0) - 1) / 2;
        for (int k = 0; k < 80; k++) {
          const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
          if (norm(q - s.at(x1)) < norm(q - s.at(x2)))
            hi = x2;
          else
            lo = x1;
        }
        consider(norm(q - s.at((lo + hi) / 2)), in((lo + hi) / 2));
      }
    }
    if (interior) *interior = inside_piece;
    return best;
  }
};

// ---------------------------------------------------------------- dash oracle

using Intervals = std::vector<std::pair<double, double>>;

// The dash positions of SVG 2 painting.html#TermDashPositions for a subpath
// of length len and a valid pattern of even length: walking the pattern from
// minus the offset (a negative offset counts from the end of the pattern),
// every dash that reaches into the subpath, clamped to it; a zero-length
// dash only at the very start of an unshifted pattern.
Intervals dash_positions(double len, const std::vector<double>& pattern, double offset) {
  double sum = 0;
  for (double d : pattern) sum += d;
  offset = std::fmod(offset, sum);
  if (offset < 0) offset += sum;
  Intervals out;
  double pos = -offset;
  for (size_t i = 0; pos < len; i = (i + 1) % pattern.size()) {
    const double end = pos + pattern[i];
    if (i % 2 == 0 && (end > 0 || (end == 0 && pos == 0 && offset == 0)))
      out.push_back({std::max(pos, 0.0), std::min(end, len)});
    pos = end;
  }
  return out;
}

// Arc length along a path's contours, by the chords of 4096 samples per
// segment (independent of the stage's quadrature), and the centrelines of
// the dashes a pattern places on them.
struct Measured {
  struct Contour {
    std::vector<Seg> segs;
    std::vector<std::vector<double>> cum;  // per segment: arc length at t = i / kSamples
    double length = 0;
  };
  static constexpr int kSamples = 4096;
  std::vector<Contour> contours;

  explicit Measured(const Path& path) {
    const PathSegs ps(path);
    for (const auto& segs : ps.contours) {
      Contour c;
      c.segs = segs;
      for (const Seg& s : segs) {
        std::vector<double> cum(kSamples + 1);
        cum[0] = c.length;
        for (int i = 1; i <= kSamples; i++)
          cum[i] = cum[i - 1] + norm(s.at(double(i) / kSamples) - s.at(double(i - 1) / kSamples));
        c.length = cum.back();
        c.cum.push_back(std::move(cum));
      }
      contours.push_back(std::move(c));
    }
  }

  // The dashes of an open contour as a centreline: each dash's pieces of
  // the segments it runs along, zero-length dashes as points.
  Centreline dashes(size_t contour, const std::vector<double>& pattern, double offset) const {
    const Contour& c = contours[contour];
    Centreline out;
    for (const auto& [b, e] : dash_positions(c.length, pattern, offset)) {
      for (size_t k = 0; k < c.segs.size(); k++) {
        const std::vector<double>& cum = c.cum[k];
        if (b == e && b >= cum.front() && b <= cum.back()) {
          out.points.push_back(c.segs[k].at(param(cum, b)));
          break;
        }
        if (e <= cum.front() || b >= cum.back()) continue;
        out.pieces.push_back({c.segs[k], param(cum, b), param(cum, e)});
      }
    }
    return out;
  }

 private:
  // The parameter at arc length s along a segment's table (clamped to it).
  static double param(const std::vector<double>& cum, double s) {
    if (s <= cum.front()) return 0;
    if (s >= cum.back()) return 1;
    const size_t i = std::upper_bound(cum.begin(), cum.end(), s) - cum.begin() - 1;
    const double span = cum[i + 1] - cum[i];
    return (i + (span > 0 ? (s - cum[i]) / span : 0)) / kSamples;
  }
};

// ---------------------------------------------------------------- round oracle

struct Box {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  void add(Vec2 p) {
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
};

Box control_box(const Path& p) {
  Box b;
  for (const Vec2& q : p.points()) b.add(q);
  return b;
}

// Counts of agreement between the output and the round-stroke definition.
struct RoundCheck {
  int checked = 0, wrong = 0;
  std::string first_wrong;
};

// Random points around `path`: inside the output (nonzero) exactly when
// within h of the centreline.
RoundCheck check_round(const Path& path, double width, int npoints, std::mt19937& rng) {
  StrokeStyle st;
  st.width = width;
  st.join = LineJoin::Round;
  st.cap = LineCap::Round;
  const Filled filled(stroke_of(path, st));
  const Centreline line(path);
  const double h = width / 2;
  const Box b = control_box(path);
  std::uniform_real_distribution<double> ux(b.x0 - h * 1.2, b.x1 + h * 1.2), uy(b.y0 - h * 1.2, b.y1 + h * 1.2);
  // Half the points uniform around the path, half within reach of the
  // centreline, where holes would be.
  std::uniform_real_distribution<double> unit01(0, 1), angle(0, 2 * M_PI);
  auto near_line = [&]() {
    if (line.pieces.empty()) return Vec2{ux(rng), uy(rng)};
    const Seg& s = line.pieces[std::min(line.pieces.size() - 1, size_t(unit01(rng) * line.pieces.size()))].s;
    const double a = angle(rng), r = 1.2 * h * unit01(rng);
    return s.at(unit01(rng)) + Vec2{r * std::cos(a), r * std::sin(a)};
  };
  RoundCheck r;
  for (int i = 0; i < npoints; i++) {
    const Vec2 q = i % 2 ? near_line() : Vec2{ux(rng), uy(rng)};
    const double d = line.distance(q);
    if (std::fabs(d - h) < 2 * kTol) continue;
    const auto in = filled.inside(q);
    if (!in) continue;
    r.checked++;
    if (*in != (d < h)) {
      if (r.wrong++ == 0)
        r.first_wrong = "point (" + std::to_string(q.x) + ", " + std::to_string(q.y) + ") distance " +
                        std::to_string(d) + " half width " + std::to_string(h) + (*in ? " inside" : " outside");
    }
  }
  return r;
}

// ---------------------------------------------------------------- polygon oracle

using Poly = std::vector<Vec2>;

// Signed distance-like value of q for a convex polygon: the smallest
// distance to an edge line, positive inside (either orientation).
double convex_depth(const Poly& poly, Vec2 q) {
  double area = 0;
  for (size_t i = 0; i < poly.size(); i++) area += cross(poly[i], poly[(i + 1) % poly.size()]);
  if (area == 0) return -1e300;
  const double s = area > 0 ? 1 : -1;
  double depth = 1e300;
  for (size_t i = 0; i < poly.size(); i++) {
    const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const double l = norm(b - a);
    if (l == 0) continue;
    depth = std::min(depth, s * cross(b - a, q - a) / l);
  }
  return depth;
}

Vec2 left(Vec2 d) { return {-d.y, d.x}; }
Vec2 unit(Vec2 d) { return (1 / norm(d)) * d; }

// The stroke of a polyline as convex pieces (SVG 2 painting.html#StrokeShape):
// segment rectangles, outer join shapes, caps.
std::vector<Poly> polyline_stroke(const std::vector<Vec2>& v, bool closed, const StrokeStyle& st) {
  const double h = st.width / 2;
  std::vector<Poly> out;
  std::vector<std::pair<Vec2, Vec2>> segs;
  for (size_t i = 0; i + 1 < v.size(); i++)
    if (v[i] != v[i + 1]) segs.push_back({v[i], v[i + 1]});
  if (closed && v.back() != v.front()) segs.push_back({v.back(), v.front()});
  for (const auto& [a, b] : segs) {
    const Vec2 n = h * left(unit(b - a));
    out.push_back({a - n, b - n, b + n, a + n});
  }
  auto join = [&](Vec2 p, Vec2 t0, Vec2 t1) {
    const double tau = std::atan2(cross(t0, t1), dot(t0, t1));
    const double sgn = tau >= 0 ? -1 : 1;
    const Vec2 p1 = p + (sgn * h) * left(t0), p2 = p + (sgn * h) * left(t1);
    const double ch = std::cos(tau / 2);
    if (ch * std::max(1.0, st.miter_limit) >= 1 && st.join != LineJoin::Bevel) {
      const Vec2 b = unit((p1 - p) + (p2 - p));
      out.push_back({p, p1, p + (h / ch) * b, p2});
    } else if (st.join == LineJoin::MiterClip) {
      const double lambda = (st.miter_limit * h - h * ch) / std::sin(std::fabs(tau) / 2);
      out.push_back({p, p1, p1 + lambda * t0, p2 - lambda * t1, p2});
    } else {
      out.push_back({p, p1, p2});
    }
  };
  for (size_t i = 0; i + 1 < segs.size(); i++)
    join(segs[i].second, unit(segs[i].second - segs[i].first), unit(segs[i + 1].second - segs[i + 1].first));
  if (closed) {
    join(segs.back().second, unit(segs.back().second - segs.back().first),
         unit(segs.front().second - segs.front().first));
  } else if (st.cap == LineCap::Square) {
    auto cap = [&](Vec2 p, Vec2 t) {
      const Vec2 n = h * left(t), e = h * t;
      out.push_back({p - n, p + e - n, p + e + n, p + n});
    };
    cap(segs.front().first, -1.0 * unit(segs.front().second - segs.front().first));
    cap(segs.back().second, unit(segs.back().second - segs.back().first));
  }
  return out;
}

double union_depth(const std::vector<Poly>& polys, Vec2 q) {
  double d = -1e300;
  for (const Poly& p : polys) d = std::max(d, convex_depth(p, q));
  return d;
}

Path polyline_path(const std::vector<Vec2>& v, bool closed) {
  Path p;
  p.move_to(v[0]);
  for (size_t i = 1; i < v.size(); i++) p.line_to(v[i]);
  if (closed) p.close();
  return p;
}

// Wrong classifications of random points against the polygon union.
int check_polygons(const Segments& out, const std::vector<Poly>& expected, const Box& b, int n, std::mt19937& rng,
                   int* checked) {
  const Filled filled(out);
  std::uniform_real_distribution<double> ux(b.x0, b.x1), uy(b.y0, b.y1);
  int wrong = 0;
  for (int i = 0; i < n; i++) {
    const Vec2 q{ux(rng), uy(rng)};
    const double d = union_depth(expected, q);
    if (std::fabs(d) < kTol / 4) continue;
    const auto in = filled.inside(q);
    if (!in) continue;
    (*checked)++;
    if (*in != (d > 0)) wrong++;
  }
  return wrong;
}


// Whether two outputs are the same segments, bit for bit.
bool same(const Segments& a, const Segments& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); i++) {
    if (a[i].type != b[i].type || a[i].w != b[i].w) return false;
    for (int k = 0; k < 4; k++)
      if (a[i].x[k] != b[i].x[k] || a[i].y[k] != b[i].y[k]) return false;
  }
  return true;
}

}  // namespace

// ---------------------------------------------------------------- round joins and caps: exact oracle

TEST_CASE("stroke: round joins and caps are the points within h of random paths", "[stroke][oracle]") {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> width(1, 40);
  int checked = 0;
  for (int iter = 0; iter < 40; iter++) {
    const Path path = random_path(rng, 1 + iter % 3);
    const double w = width(rng);
    const RoundCheck r = check_round(path, w, 250, rng);
    INFO("path " << iter << " width " << w << ": " << r.first_wrong);
    CHECK(r.wrong == 0);
    checked += r.checked;
  }
  CHECK(checked > 5000);
}

TEST_CASE("stroke: each segment type alone, round", "[stroke][oracle]") {
  std::mt19937 rng(7);
  for (int type = 0; type < 4; type++) {
    for (int iter = 0; iter < 6; iter++) {
      Path p;
      p.move_to(rpt(rng));
      if (type == 0) p.line_to(rpt(rng));
      if (type == 1) p.quad_to(rpt(rng), rpt(rng));
      if (type == 2) p.rquad_to(rpt(rng), rpt(rng), 0.1 + 0.5 * iter);
      if (type == 3) p.cubic_to(rpt(rng), rpt(rng), rpt(rng));
      const double w = 2 + 9 * iter;
      const RoundCheck r = check_round(p, w, 300, rng);
      INFO("type " << type << " iter " << iter << ": " << r.first_wrong);
      CHECK(r.wrong == 0);
      CHECK(r.checked > 100);
    }
  }
}

TEST_CASE("stroke: radius of curvature below h, the inner offset folds", "[stroke][oracle]") {
  std::mt19937 rng(11);
  // A circle of radius 5 with width 30: a disk of radius 20, no hole.
  const Path c = circle({50, 50}, 5);
  const RoundCheck r = check_round(c, 30, 2000, rng);
  INFO(r.first_wrong);
  CHECK(r.wrong == 0);
  StrokeStyle st;
  st.width = 30;
  const Filled f(stroke_of(c, st));
  CHECK(f.inside({50.3, 50.2}) == true);
  CHECK(f.inside({50.5, 49.7}) == true);
  // Quarter arcs and tight parabolas, every join style.
  for (LineJoin j : {LineJoin::Miter, LineJoin::Bevel, LineJoin::Round}) {
    Path p;
    p.move_to({10, 50});
    p.quad_to({90, 52}, {10, 54});  // radius ~0.05 at the vertex
    st.join = j;
    st.width = 20;
    const Filled g(stroke_of(p, st));
    // Inside the swept normals around the vertex of the parabola.
    for (Vec2 q : {Vec2{50, 52}, Vec2{45, 45}, Vec2{45, 60}, Vec2{55, 52}})
      CHECK(g.inside(q) == true);
    CHECK(g.inside({65, 52}) == false);
  }
  const RoundCheck r2 = [&] {
    Path p;
    p.move_to({10, 50});
    p.quad_to({90, 52}, {10, 54});
    return check_round(p, 20, 2000, rng);
  }();
  INFO(r2.first_wrong);
  CHECK(r2.wrong == 0);
}

TEST_CASE("stroke: cusps and inflections inside cubics", "[stroke][oracle]") {
  std::mt19937 rng(3);
  // Exact cusp, near-cusps on both sides, and an inflection.
  for (double e : {0.0, 1e-9, 1e-5, 0.01, 0.5}) {
    Path p;
    p.move_to({20, 20});
    cusp_cubic(p, {60, 0}, {0, 50});
    Path q;
    q.move_to({20, 20});
    const Vec2 p3 = p.points()[3] + Vec2{e, -e};
    q.cubic_to(p.points()[1], p.points()[2], p3);
    for (double w : {4.0, 25.0}) {
      const RoundCheck r = check_round(q, w, 1500, rng);
      INFO("perturbation " << e << " width " << w << ": " << r.first_wrong);
      CHECK(r.wrong == 0);
    }
  }
  // With butt caps and miter joins, the cusp is still filled (no hole at
  // the cusp point, where the normal flips).
  Path p;
  p.move_to({20, 20});
  cusp_cubic(p, {60, 0}, {0, 50});
  const Vec2 cusp = Seg{SegmentType::Cubic, {p.points()[0], p.points()[1], p.points()[2], p.points()[3]}}.at(0.5);
  StrokeStyle st;
  st.width = 10;
  const Filled f(stroke_of(p, st));
  for (double a = 0; a < 6.28; a += 0.5) CHECK(f.inside(cusp + Vec2{3 * std::cos(a), 3 * std::sin(a)}) == true);
  // An S-curve (inflection) with a moderate width.
  Path s;
  s.move_to({0, 0});
  s.cubic_to({100, 0}, {0, 100}, {100, 100});
  const RoundCheck r = check_round(s, 12, 2000, rng);
  INFO(r.first_wrong);
  CHECK(r.wrong == 0);
}

TEST_CASE("stroke: multiple subpaths and closed contours, round", "[stroke][oracle]") {
  std::mt19937 rng(5);
  Path p;
  p.move_to({10, 10});
  p.cubic_to({80, 0}, {90, 90}, {20, 60});
  p.close();
  p.move_to({60, 20});
  p.rquad_to({90, 20}, {90, 50}, 0.3);
  p.line_to({60, 80});
  p.move_to({5, 90});
  p.quad_to({50, 40}, {95, 90});
  p.close();
  const RoundCheck r = check_round(p, 9, 3000, rng);
  INFO(r.first_wrong);
  CHECK(r.wrong == 0);
}

TEST_CASE("stroke: other joins and caps on curves hold the swept normals and stay within their reach",
          "[stroke][oracle]") {
  // Every point within h of the centreline whose nearest point is inside a
  // segment lies on that segment's normal: inside for every join and cap.
  // Nothing lies farther than the joins and caps reach: h sqrt 2 for square
  // caps, miter_limit * h for miters, and for clipped miters the corners on
  // the clip line, at most h + lambda from the vertex with lambda (along
  // an outer edge) below miter_limit * h / sqrt(1 - 1 / miter_limit^2).
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> width(1, 30);
  int checked_in = 0, checked_out = 0, wrong = 0;
  for (int iter = 0; iter < 40; iter++) {
    const Path path = random_path(rng, 1 + iter % 2);
    StrokeStyle st;
    st.width = width(rng);
    st.join = std::array<LineJoin, 4>{LineJoin::Miter, LineJoin::MiterClip, LineJoin::Bevel, LineJoin::Arcs}[iter % 4];
    st.cap = iter % 3 ? LineCap::Square : LineCap::Butt;
    const Filled f(stroke_of(path, st));
    const Centreline line(path);
    const double h = st.width / 2;
    const double ml = st.miter_limit;
    const double join_reach = st.join == LineJoin::Bevel   ? 1.0
                              : st.join == LineJoin::Miter ? ml
                                                           : 1 + ml / std::sqrt(1 - 1 / (ml * ml));
    const double reach = h * std::max(st.cap == LineCap::Square ? M_SQRT2 : 1.0, join_reach);
    const Box b = control_box(path);
    std::uniform_real_distribution<double> ux(b.x0 - reach, b.x1 + reach), uy(b.y0 - reach, b.y1 + reach);
    int w = 0;
    for (int i = 0; i < 400; i++) {
      const Vec2 q{ux(rng), uy(rng)};
      bool interior = false;
      const double d = line.distance(q, &interior);
      const bool must_in = interior && d < h - 2 * kTol, must_out = d > reach + 2 * kTol;
      if (!must_in && !must_out) continue;
      const auto in = f.inside(q);
      if (!in) continue;
      (must_in ? checked_in : checked_out)++;
      w += *in != must_in;
    }
    INFO("path " << iter << " join " << int(st.join) << " cap " << int(st.cap) << " width " << st.width);
    CHECK(w == 0);
    wrong += w;
  }
  CHECK(wrong == 0);
  CHECK(checked_in > 2000);
  CHECK(checked_out > 2000);
}

// ---------------------------------------------------------------- polylines: butt/square caps, miter/bevel joins

TEST_CASE("stroke: polylines with miter, miter-clip and bevel joins, butt and square caps", "[stroke][polygon]") {
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> nv(2, 7);
  std::uniform_real_distribution<double> width(1, 25), limit(1, 10);
  std::bernoulli_distribution coin(0.5), rare(0.15);
  int checked = 0, wrong = 0;
  for (int iter = 0; iter < 120; iter++) {
    std::vector<Vec2> v;
    const int n = nv(rng);
    for (int i = 0; i < n; i++) {
      Vec2 q = rpt(rng);
      // Short segments and exact reversals.
      if (!v.empty() && rare(rng)) q = v.back() + Vec2{0.3, -0.2};
      if (v.size() >= 2 && rare(rng)) q = v[v.size() - 2];
      v.push_back(q);
    }
    const bool closed = n > 2 && coin(rng);
    StrokeStyle st;
    st.width = width(rng);
    st.miter_limit = limit(rng);
    st.join = std::array<LineJoin, 3>{LineJoin::Miter, LineJoin::MiterClip, LineJoin::Bevel}[iter % 3];
    st.cap = coin(rng) ? LineCap::Butt : LineCap::Square;
    const Segments out = stroke_of(polyline_path(v, closed), st);
    const std::vector<Poly> expected = polyline_stroke(v, closed, st);
    Box b;
    for (const Poly& p : expected)
      for (const Vec2& q : p) b.add(q);
    int c = 0;
    const int w = check_polygons(out, expected, b, 200, rng, &c);
    INFO("polyline " << iter << " join " << int(st.join) << " cap " << int(st.cap) << " closed " << closed);
    CHECK(w == 0);
    wrong += w;
    checked += c;
    // Lines stay lines.
    CHECK(count_type(out, INPUT_QUAD) == 0);
    CHECK(count_type(out, INPUT_RQUAD) == 0);
  }
  CHECK(checked > 10000);
  CHECK(wrong == 0);
}

TEST_CASE("stroke: miter limit switches to bevel at 1/sin(theta/2)", "[stroke][polygon]") {
  // Interior angle 60°: miter ratio 1/sin(30°) = 2.
  const double h = 5;
  const Vec2 p{50, 50};
  std::vector<Vec2> v{{0, 50}, p, p + 50 * Vec2{-std::cos(M_PI / 3), std::sin(M_PI / 3)}};
  // The miter tip lies 2h from p along the outer bisector.
  const Vec2 bis = unit(unit(p - v[0]) - unit(v[2] - p));
  StrokeStyle st;
  st.width = 2 * h;
  st.miter_limit = 2.01;
  const Filled miter(stroke_of(polyline_path(v, false), st));
  CHECK(miter.inside(p + (2 * h - 0.1) * bis) == true);
  CHECK(miter.inside(p + (2 * h + 0.1) * bis) == false);
  st.miter_limit = 1.99;
  const Filled bevel(stroke_of(polyline_path(v, false), st));
  CHECK(bevel.inside(p + (2 * h - 0.1) * bis) == false);
  CHECK(bevel.inside(p + (0.5 * h - 0.1) * bis) == true);
  st.join = LineJoin::MiterClip;
  const Filled clip(stroke_of(polyline_path(v, false), st));
  // Clipped at miter_limit * h = 9.95 from p.
  CHECK(clip.inside(p + 9.8 * bis) == true);
  CHECK(clip.inside(p + 10.1 * bis) == false);
}

// ---------------------------------------------------------------- degenerate input

TEST_CASE("stroke: zero-length subpaths draw dots and squares along x, butt nothing", "[stroke][degenerate]") {
  for (int form = 0; form < 3; form++) {
    Path p;
    p.move_to({10, 20});
    if (form == 1) p.line_to({10, 20});
    if (form == 2) p.cubic_to({10, 20}, {10, 20}, {10, 20});
    p.close();
    StrokeStyle st;
    st.width = 8;
    st.cap = LineCap::Butt;
    CHECK(stroke_of(p, st).empty());
    st.cap = LineCap::Round;
    const Filled dot(stroke_of(p, st));
    CHECK(dot.inside({13.5, 20}) == true);
    CHECK(dot.inside({12.7, 22.7}) == true);
    CHECK(dot.inside({13, 23.1}) == false);
    st.cap = LineCap::Square;
    const Filled square(stroke_of(p, st));
    CHECK(square.inside({13.9, 23.9}) == true);
    CHECK(square.inside({6.1, 16.1}) == true);
    CHECK(square.inside({14.1, 20}) == false);
    CHECK(square.inside({10, 24.1}) == false);
  }
  // A lone moveto is not a zero-length subpath: nothing.
  Path lone;
  lone.move_to({5, 5});
  StrokeStyle st;
  st.cap = LineCap::Round;
  CHECK(stroke_of(lone, st).empty());
}

TEST_CASE("stroke: zero-length segments inside a subpath change nothing", "[stroke][degenerate]") {
  std::mt19937 rng(1);
  Path a, b;
  a.move_to({10, 10});
  a.line_to({60, 10});
  a.cubic_to({80, 10}, {80, 40}, {60, 60});
  b.move_to({10, 10});
  b.line_to({10, 10});
  b.line_to({60, 10});
  b.quad_to({60, 10}, {60, 10});
  b.cubic_to({80, 10}, {80, 40}, {60, 60});
  b.line_to({60, 60});
  for (LineJoin j : {LineJoin::Miter, LineJoin::Round, LineJoin::Bevel}) {
    StrokeStyle st;
    st.width = 12;
    st.join = j;
    st.cap = LineCap::Square;
    const Filled fa(stroke_of(a, st)), fb(stroke_of(b, st));
    for (int i = 0; i < 500; i++) {
      const Vec2 q = rpt(rng, 0, 90);
      const auto ia = fa.inside(q, 1e-4), ib = fb.inside(q, 1e-4);
      if (ia && ib) CHECK(*ia == *ib);
    }
  }
}

TEST_CASE("stroke: coincident control points", "[stroke][degenerate]") {
  std::mt19937 rng(2);
  // A straight cubic with P0 = P1 and P2 = P3 strokes like the line.
  Path c;
  c.move_to({10, 10});
  c.cubic_to({10, 10}, {90, 70}, {90, 70});
  StrokeStyle st;
  st.width = 10;
  st.cap = LineCap::Square;
  const std::vector<Poly> expected = polyline_stroke({{10, 10}, {90, 70}}, false, st);
  int checked = 0;
  CHECK(check_polygons(stroke_of(c, st), expected, {0, 0, 100, 80}, 2000, rng, &checked) == 0);
  CHECK(checked > 1500);
  // Curved cubics with one pair of coincident points, and a conic with its
  // control point on an end point.
  for (int k = 0; k < 3; k++) {
    Path p;
    p.move_to({10, 10});
    if (k == 0) p.cubic_to({10, 10}, {90, 10}, {90, 80});
    if (k == 1) p.cubic_to({50, 90}, {90, 10}, {90, 10});
    if (k == 2) p.rquad_to({10, 10}, {90, 80}, 2);
    const RoundCheck r = check_round(p, 14, 1500, rng);
    INFO(k << ": " << r.first_wrong);
    CHECK(r.wrong == 0);
  }
}

TEST_CASE("stroke: 180-degree turns", "[stroke][degenerate]") {
  const std::vector<Vec2> v{{10, 50}, {80, 50}, {10, 50}};
  StrokeStyle st;
  st.width = 10;
  for (LineJoin j : {LineJoin::Miter, LineJoin::Bevel}) {
    st.join = j;
    const Filled f(stroke_of(polyline_path(v, false), st));
    CHECK(f.inside({79, 54}) == true);
    CHECK(f.inside({81, 50}) == false);  // miter: infinitely long, so bevel
  }
  st.join = LineJoin::Round;
  const Filled r(stroke_of(polyline_path(v, false), st));
  CHECK(r.inside({84.9, 50}) == true);
  CHECK(r.inside({85.1, 50}) == false);
  // Miter-clip keeps its limit: the clipped miter extends miter_limit * h.
  st.join = LineJoin::MiterClip;
  st.miter_limit = 3;
  const Filled mc(stroke_of(polyline_path(v, false), st));
  CHECK(mc.inside({94.8, 53}) == true);
  CHECK(mc.inside({95.2, 50}) == false);
  // A quadratic whose control point lies beyond its end: it turns back
  // within the segment (a cusp of a collinear curve).
  std::mt19937 rng(4);
  Path q;
  q.move_to({10, 50});
  q.quad_to({90, 50}, {40, 50});
  const RoundCheck rc = check_round(q, 10, 1500, rng);
  INFO(rc.first_wrong);
  CHECK(rc.wrong == 0);
}

TEST_CASE("stroke: nearly collinear curves have no spikes", "[stroke][degenerate]") {
  // Joins between almost-parallel pieces with a large miter limit stay
  // within the miter ratio of the almost-straight angle.
  Path p;
  p.move_to({0, 0});
  p.line_to({50, 0.001});
  p.cubic_to({60, 0.002}, {70, 0.0025}, {100, 0.004});
  p.quad_to({120, 0.005}, {140, 0});
  StrokeStyle st;
  st.width = 10;
  st.miter_limit = 100;
  const Segments out = stroke_of(p, st);
  for (const Vec2& q : control_points(out)) CHECK(std::fabs(q.y) < 5.2);
  std::mt19937 rng(6);
  const RoundCheck r = check_round(p, 10, 1000, rng);
  CHECK(r.wrong == 0);
}

TEST_CASE("stroke: huge and tiny widths", "[stroke][degenerate]") {
  Path p;
  p.move_to({0, 0});
  p.cubic_to({10, 0}, {10, 10}, {0, 10});
  p.line_to({5, 5});
  StrokeStyle st;
  st.width = 1e5;
  st.join = LineJoin::Round;
  st.cap = LineCap::Round;
  const Segments big = stroke_of(p, st);
  for (const Vec2& q : control_points(big)) {
    REQUIRE(std::isfinite(q.x));
    CHECK(norm(q) < 5e4 * 1.5 + 20);
  }
  const Filled fb(big);
  CHECK(fb.inside({4.3, 6.1}, 1e-3) == true);
  CHECK(fb.inside({40000, 3000}, 1e-3) == true);
  CHECK(fb.inside({60000, 0}, 1e-3) == false);
  std::mt19937 rng(8);
  const RoundCheck r = check_round(p, 200, 1000, rng);
  CHECK(r.wrong == 0);
  // Tiny: every output point stays within h + tolerance of the centreline.
  st.width = 1e-6;
  st.join = LineJoin::Miter;
  st.cap = LineCap::Butt;
  const Segments tiny = stroke_of(p, st);
  CHECK(!tiny.empty());
  const Centreline c(p);
  for (const InputSegment& s : tiny)
    for (double t = 0; t <= 1; t += 0.25) CHECK(c.distance(seg_of(s).at(t)) < kTol);
}

TEST_CASE("stroke: non-invertible transforms and invalid input give nothing, without throwing",
          "[stroke][degenerate]") {
  Path p;
  p.move_to({0, 0});
  p.quad_to({10, 0}, {10, 10});
  StrokeStyle st;
  st.width = 2;
  CHECK(stroke_of(p, st, Affine::scale(0, 1)).empty());
  CHECK(stroke_of(p, st, Affine{1, 2, 2, 4, 0, 0}).empty());
  CHECK(stroke_of(p, st, Affine{NAN, 0, 0, 1, 0, 0}).empty());
  st.width = -1;
  CHECK(stroke_of(p, st).empty());
  st.width = NAN;
  CHECK(stroke_of(p, st).empty());
  st.width = 2;
  st.miter_limit = NAN;
  st.dashes = {NAN, 1};
  st.dash_offset = INFINITY;
  CHECK(!stroke_of(p, st).empty());
  // A contour with a non-finite point is skipped; the others are stroked.
  Path q;
  q.move_to({0, 0});
  q.line_to({INFINITY, 0});
  q.move_to({0, 10});
  q.line_to({10, 10});
  const Segments out = stroke_of(q, StrokeStyle{});
  CHECK(!out.empty());
  for (const Vec2& v : control_points(out)) CHECK((std::isfinite(v.x) && std::isfinite(v.y)));
}

// ---------------------------------------------------------------- transforms and tolerance

TEST_CASE("stroke: strokes are computed in user space, then transformed", "[stroke][transform]") {
  std::mt19937 rng(12);
  const Path p = random_path(rng, 2);
  for (const Affine& m : {Affine::scale(3, 0.5), Affine{1, 0.4, -0.8, 1.5, 10, 20}, Affine::rotate_degrees(30)}) {
    StrokeStyle st;
    st.width = 8;
    st.join = LineJoin::Round;
    st.cap = LineCap::Round;
    // The stage's output is in device space already.
    const Filled f(stroke_of(p, st, m));
    const Centreline c(p);
    // Device points, classified by the distance of their preimage.
    const double det = m.det();
    const Affine inv{m.d / det, -m.b / det, -m.c / det, m.a / det, (m.c * m.f - m.d * m.e) / det,
                     (m.b * m.e - m.a * m.f) / det};
    Box b;
    for (const Vec2& q : p.points()) b.add(m.apply(q));
    std::uniform_real_distribution<double> ux(b.x0 - 20, b.x1 + 20), uy(b.y0 - 20, b.y1 + 20);
    // The output is within kTol device pixels of the exact outline, so
    // within kTol / sigma_min user units.
    const double pp = m.a * m.a + m.b * m.b, qq = m.c * m.c + m.d * m.d, rr = m.a * m.c + m.b * m.d;
    const double sigma_min = std::sqrt((pp + qq - std::sqrt((pp - qq) * (pp - qq) + 4 * rr * rr)) / 2);
    int checked = 0, wrong = 0;
    for (int i = 0; i < 1500; i++) {
      const Vec2 q{ux(rng), uy(rng)};
      const double d = c.distance(inv.apply(q));
      if (std::fabs(d - 4) < 2 * kTol / sigma_min) continue;
      const auto in = f.inside(q);
      if (!in) continue;
      checked++;
      wrong += *in != (d < 4);
    }
    CHECK(wrong == 0);
    CHECK(checked > 800);
  }
}

TEST_CASE("stroke: offsets are quadratics within 1/16 device pixel of the true offset", "[stroke][tolerance]") {
  // One segment at a time (near joins the inner side lies within h of the
  // neighbour), with radius of curvature above h everywhere: every
  // quadratic of the output lies on an offset at distance h.
  const double h = 3;
  for (int k = 0; k < 2; k++) {
    Path p;
    p.move_to({0, 0});
    if (k == 0) p.cubic_to({40, -10}, {80, 30}, {100, 60});
    if (k == 1) p.rquad_to({20, 40}, {60, 30}, 0.8);
    const Centreline c(p);
    for (double scale : {0.5, 1.0, 4.0, 16.0}) {
      StrokeStyle st;
      st.width = 2 * h;
      const Segments out = stroke_of(p, st, Affine::scale(scale, scale), kTol);
      double worst = 0;
      size_t quads = 0;
      for (const InputSegment& s : out) {
        if (s.type != INPUT_QUAD) continue;
        quads++;
        // Back to user space, where the offset lies at distance h.
        const Seg g = seg_of(s);
        for (int i = 0; i <= 16; i++) {
          const Vec2 x = (1 / scale) * g.at(i / 16.0);
          worst = std::max(worst, std::fabs(c.distance(x) - h) * scale);
        }
      }
      INFO("segment " << k << " scale " << scale << ": " << quads << " quadratics, worst " << worst << " px");
      CHECK(worst <= kTol);
      CHECK(quads > 0);
      // Curves, not polylines: a handful of quadratics per offset, and the
      // only lines are the two ends of the body.
      CHECK(quads < 50);
      CHECK(count_type(out, INPUT_LINE) <= 2);
    }
  }
}

TEST_CASE("stroke: round joins and caps are exact conics", "[stroke]") {
  StrokeStyle st;
  st.width = 10;
  st.join = LineJoin::Round;
  st.cap = LineCap::Round;
  const Segments out = stroke_of(polyline_path({{0, 0}, {50, 0}, {50, 50}}, false), st);
  CHECK(count_type(out, INPUT_RQUAD) == 12);  // three disks of four quarter conics
  for (const InputSegment& s : out) {
    if (s.type != INPUT_RQUAD) continue;
    CHECK(s.w == Approx(M_SQRT1_2));
    // Every point of the conic lies on a circle of radius 5 around a vertex.
    const Seg g = seg_of(s);
    for (double t = 0; t <= 1; t += 0.125) {
      double d = 1e300;
      for (Vec2 c : {Vec2{0, 0}, Vec2{50, 0}, Vec2{50, 50}}) d = std::min(d, std::fabs(norm(g.at(t) - c) - 5));
      CHECK(d < 1e-9);
    }
  }
}

// ---------------------------------------------------------------- dashing

TEST_CASE("dash: pattern validation", "[stroke][dash]") {
  // An odd list is the list repeated once; an empty list, one that sums to
  // zero, and one with a negative or non-finite value draw the stroke solid
  // (SVG 2 painting.html#StrokeDashing): the same segments, bit for bit.
  Path p;
  p.move_to({10, 10});
  p.cubic_to({90, 0}, {100, 80}, {30, 70});
  p.line_to({20, 20});
  StrokeStyle st;
  st.width = 4;
  st.cap = LineCap::Square;
  const Segments solid = stroke_of(p, st);
  REQUIRE(!solid.empty());
  auto dashed = [&](std::vector<double> d) {
    st.dashes = std::move(d);
    return stroke_of(p, st);
  };
  CHECK(same(dashed({0, 0, 0}), solid));
  CHECK(same(dashed({4, -1}), solid));
  CHECK(same(dashed({NAN}), solid));
  CHECK(same(dashed({INFINITY, 1}), solid));
  CHECK(same(dashed({5}), dashed({5, 5})));
  CHECK(same(dashed({5, 3, 2}), dashed({5, 3, 2, 5, 3, 2})));
  CHECK(!same(dashed({5}), solid));
  CHECK(!same(dashed({4, 1}), solid));
  CHECK(!same(dashed({5, 3, 2}), dashed({5, 3})));
}

namespace {

// Points half a unit off the centreline of a horizontal line from (0, 0) to
// (len, 0), dashed with width 2, against the dash positions `expected`: with
// butt caps inside exactly the dashes of positive length, with square caps
// inside every dash extended by h = 1 at both ends (zero-length ones are
// squares). Points within 1e-3 of an expected edge are skipped.
void check_dash_positions(double len, const std::vector<double>& pattern, double offset, const Intervals& expected) {
  const Path line = polyline_path({{0, 0}, {len, 0}}, false);
  StrokeStyle st;
  st.width = 2;
  st.dashes = pattern;
  st.dash_offset = offset;
  for (LineCap cap : {LineCap::Butt, LineCap::Square}) {
    st.cap = cap;
    const double ext = cap == LineCap::Square ? 1 : 0;
    const Filled f(stroke_of(line, st));
    int checked = 0, wrong = 0;
    std::string first_wrong;
    for (double x = -2.0025; x < len + 2; x += 0.005) {
      bool in = false, near = false;
      for (const auto& [b, e] : expected) {
        if (cap == LineCap::Butt && !(e > b)) continue;
        in = in || (x > b - ext && x < e + ext);
        near = near || std::fabs(x - (b - ext)) < 1e-3 || std::fabs(x - (e + ext)) < 1e-3;
      }
      if (near) continue;
      const auto got = f.inside({x, 0.5});
      if (!got) continue;
      checked++;
      if (*got != in && wrong++ == 0) first_wrong = "at " + std::to_string(x) + (*got ? " inside" : " outside");
    }
    INFO("length " << len << " offset " << offset << " cap " << int(cap) << ": " << first_wrong);
    CHECK(wrong == 0);
    CHECK(checked > 150 * len);
  }
}

}  // namespace

TEST_CASE("dash: positions, offsets negative and larger than the pattern", "[stroke][dash]") {
  check_dash_positions(40, {10, 5}, 0, {{0, 10}, {15, 25}, {30, 40}});
  check_dash_positions(40, {10, 5}, 3, {{0, 7}, {12, 22}, {27, 37}});
  // -3 is 15 - 3 = 12 into the pattern: in the gap, 3 to go.
  check_dash_positions(40, {10, 5}, -3, {{3, 13}, {18, 28}, {33, 40}});
  check_dash_positions(40, {10, 5}, 12 + 15 * 100, {{3, 13}, {18, 28}, {33, 40}});
  check_dash_positions(40, {10, 5}, -3 - 15 * 7, {{3, 13}, {18, 28}, {33, 40}});
  // An offset at the end of a dash starts in the gap.
  check_dash_positions(40, {10, 5}, 10, {{5, 15}, {20, 30}, {35, 40}});
  // Zero-length dashes.
  check_dash_positions(50, {0, 20}, 0, {{0, 0}, {20, 20}, {40, 40}});
  // A dash pattern longer than the path.
  check_dash_positions(10, {100, 5}, 0, {{0, 10}});
  // The reference the other dash tests use agrees with these.
  CHECK(dash_positions(40, {10, 5}, -3) == Intervals{{3, 13}, {18, 28}, {33, 40}});
  CHECK(dash_positions(40, {10, 5}, 10) == Intervals{{5, 15}, {20, 30}, {35, 40}});
  CHECK(dash_positions(50, {0, 20}, 0) == Intervals{{0, 0}, {20, 20}, {40, 40}});
}

TEST_CASE("dash: dashes follow arc length across segments", "[stroke][dash]") {
  // A circle of radius 50 from (150, 100), four conics: the stage measures
  // it (its dash table, stroker/stroke_curve.h) as 2 pi 50.
  const Vec2 o{100, 100};
  const Path c = circle(o, 50);
  StrokeBatch batch;
  REQUIRE(batch.add(c, StrokeStyle{}, Affine{}, 0));
  double len = 0;
  for (const auto& s : batch.segments) len += stroking::ArcTable(s.curve).total();
  CHECK(len == Approx(2 * M_PI * 50).epsilon(1e-10));
  // Dashes 10 on, 20 off, butt caps, width 2: each dash ends on the normal
  // at its arc length, so the output's radial lines (the dashes' ends) lie
  // at the angles of the dash positions.
  StrokeStyle st;
  st.width = 2;
  st.dashes = {10, 20};
  const Segments out = stroke_of(c, st);
  std::vector<double> ends;
  for (const InputSegment& s : out) {
    if (s.type != INPUT_LINE) continue;
    const Vec2 a = Vec2{s.x[0], s.y[0]} - o, b = Vec2{s.x[1], s.y[1]} - o;
    if (std::fabs(cross(a, b)) > 1e-9 * norm(a) * norm(b) || dot(a, b) <= 0) continue;  // not radial
    if (std::fabs(norm(a) - norm(b)) < 1e-3) continue;
    double angle = std::atan2(a.y + b.y, a.x + b.x);
    if (angle < -1e-9) angle += 2 * M_PI;
    const double s_end = 50 * std::max(angle, 0.0);
    // A dash over a joint of two conics is a part on each, whose bodies
    // end there too: not a dash's end.
    const double quarter = M_PI / 2 * 50;
    const double joint = std::round(s_end / quarter);
    if (joint >= 1 && joint <= 3 && std::fabs(s_end - quarter * joint) < 1e-6) continue;
    if (std::none_of(ends.begin(), ends.end(), [&](double e) { return std::fabs(e - s_end) < 1e-6; }))
      ends.push_back(s_end);
  }
  std::sort(ends.begin(), ends.end());
  std::vector<double> expected;
  for (const auto& [b, e] : dash_positions(2 * M_PI * 50, {10, 20}, 0)) expected.insert(expected.end(), {b, e});
  REQUIRE(ends.size() == expected.size());
  for (size_t i = 0; i < ends.size(); i++) {
    INFO("dash end " << i);
    CHECK(std::fabs(ends[i] - expected[i]) < 1e-8);
  }
  // Across a corner: a square of side 100, dashes of 30 every 50 from
  // offset 10; the dash from 90 to 120 turns the corner at (100, 0), with
  // the miter join there, and ends 20 down the second side.
  const Path sq = polyline_path({{0, 0}, {100, 0}, {100, 100}, {0, 100}}, false);
  st.width = 6;
  st.dashes = {30, 20};
  st.dash_offset = 10;
  const Filled corner(stroke_of(sq, st));
  CHECK(corner.inside({90.5, 0}) == true);
  CHECK(corner.inside({89.5, 0}) == false);
  CHECK(corner.inside({102, -2}) == true);
  CHECK(corner.inside({100, 19.5}) == true);
  CHECK(corner.inside({100, 20.5}) == false);
  // A dash that starts exactly at a vertex starts on the next segment: no
  // join there.
  st.dash_offset = 0;
  const Filled at_vertex(stroke_of(sq, st));
  CHECK(at_vertex.inside({102, -2}) == false);
  CHECK(at_vertex.inside({100, 0.5}) == true);
  CHECK(at_vertex.inside({95, 1}) == false);
}

TEST_CASE("dash: closed contours start at their first point; a dash through it continues", "[stroke][dash]") {
  const Path sq = polyline_path({{0, 0}, {100, 0}, {100, 100}, {0, 100}}, true);
  StrokeStyle st;
  st.dashes = {30, 20};
  st.dash_offset = 10;  // dashes [0, 20], [40, 70], ..., [390, 400]
  // Along the perimeter, butt caps: inside exactly the dashes.
  st.width = 2;
  const Intervals dashes = dash_positions(400, {30, 20}, 10);
  REQUIRE(dashes.size() == 9);
  {
    const Filled f(stroke_of(sq, st));
    auto at = [](double s) {
      if (s < 100) return Vec2{s, 0};
      if (s < 200) return Vec2{100, s - 100};
      if (s < 300) return Vec2{300 - s, 100};
      return Vec2{0, 400 - s};
    };
    int checked = 0, wrong = 0;
    for (double s = 0.25; s < 400; s += 0.5) {
      bool in = false, near = false;
      for (const auto& [b, e] : dashes) {
        in = in || (s > b && s < e);
        near = near || std::fabs(s - b) < 0.5 || std::fabs(s - e) < 0.5;
      }
      // Half a unit off the centreline, away from the dashes' ends and the
      // corners' joins.
      if (near || std::fmod(s + 1.5, 100) < 3) continue;
      const auto got = f.inside(at(s) + Vec2{0.3, 0.4});
      if (!got) continue;
      checked++;
      wrong += *got != in;
    }
    CHECK(wrong == 0);
    CHECK(checked > 700);
  }
  // The last dash and the first are one: a join at the start point (miter:
  // the corner is square) and no caps there. With bevel joins and round
  // caps the corner is cut, where a cap would round it.
  st.width = 6;
  const Filled f(stroke_of(sq, st));
  CHECK(f.inside({-2.9, -2.9}) == true);
  st.join = LineJoin::Bevel;
  st.cap = LineCap::Round;
  const Filled bevel(stroke_of(sq, st));
  CHECK(bevel.inside({-1, -1}) == true);
  CHECK(bevel.inside({-2, -2}) == false);
  // Offset 0: the pattern starts at the first point, with a cap there.
  st.dash_offset = 0;
  const Filled capped(stroke_of(sq, st));
  CHECK(capped.inside({-2, -2}) == true);
  st.join = LineJoin::Miter;
  st.cap = LineCap::Butt;
  const Filled g(stroke_of(sq, st));
  CHECK(g.inside({1, 2}) == true);
  CHECK(g.inside({-1, -2}) == false);
}

TEST_CASE("dash: zero-length dashes carry round and square caps", "[stroke][dash]") {
  const Path line = polyline_path({{0, 0}, {100, 100}}, false);
  StrokeStyle st;
  st.width = 6;
  st.dashes = {0, 20 * M_SQRT2};
  st.cap = LineCap::Butt;
  CHECK(stroke_of(line, st).empty());
  st.cap = LineCap::Round;
  const Filled r(stroke_of(line, st));
  for (double x : {0.0, 20.0, 40.0, 60.0, 80.0}) {
    CHECK(r.inside({x + 2, x - 2}) == true);
    CHECK(r.inside({x + 10, x + 10}) == false);
  }
  st.cap = LineCap::Square;
  const Filled s(stroke_of(line, st));
  // Squares of side 6 turned 45° with the line: a corner reaches 3 sqrt 2
  // along the axes, while axis-aligned corners (3, 3) are outside.
  CHECK(s.inside({20 + 4.1, 20}) == true);
  CHECK(s.inside({20 + 2.9, 20 + 2.9}) == false);
}

TEST_CASE("dash: dashed round strokes are the union of their dashes' swept disks", "[stroke][dash][oracle]") {
  std::mt19937 rng(31);
  Path p;
  p.move_to({10, 10});
  p.cubic_to({90, 0}, {100, 80}, {30, 70});
  p.quad_to({0, 60}, {50, 40});
  StrokeStyle st;
  st.width = 8;
  st.join = LineJoin::Round;
  st.cap = LineCap::Round;
  st.dashes = {17, 9, 5};
  st.dash_offset = -4;
  const Filled f(stroke_of(p, st));
  const Centreline dashes = Measured(p).dashes(0, {17, 9, 5, 17, 9, 5}, -4);
  CHECK(dashes.pieces.size() >= 6);
  int checked = 0, wrong = 0;
  for (int i = 0; i < 3000; i++) {
    const Vec2 q = rpt(rng, -5, 110);
    const double d = dashes.distance(q);
    if (std::fabs(d - 4) < 2 * kTol) continue;
    const auto in = f.inside(q);
    if (!in) continue;
    checked++;
    wrong += *in != (d < 4);
  }
  CHECK(wrong == 0);
  CHECK(checked > 2500);
}

// ---------------------------------------------------------------- hairlines

TEST_CASE("stroke: hairlines keep their ink", "[stroke][hairline]") {
  const Hairline a = hairline(0.25, Affine{}, 1);
  CHECK(a.width == 1);
  CHECK(a.opacity == 0.25);
  const Hairline b = hairline(2, Affine::scale(0.25, 0.25), 1);
  CHECK(b.width == 4);
  CHECK(b.opacity == 0.5);
  const Hairline c = hairline(3, Affine::scale(2, 2), 1);
  CHECK(c.width == 3);
  CHECK(c.opacity == 1);
  // Width 0 (PDF): the thinnest visible line, at full opacity.
  const Hairline d = hairline(0, Affine::scale(4, 4), 1);
  CHECK(d.width == 0.25);
  CHECK(d.opacity == 1);
}
