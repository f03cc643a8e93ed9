// Stroke-to-fill conversion: the stroke as a union of positively oriented
// pieces (see stroker.h for the overall contract).
//
// Bodies. A segment c(t) with unit tangent T(t), left normal n(t) = T
// rotated by +90° and signed curvature k(t) sweeps the normal segments
//   F(t, s) = c(t) + s n(t),   t in [0, 1], s in [-h, h]   (h = width / 2).
// With n' = -k |c'| T, the Jacobian of F is det[F_t, F_s] = |c'| (1 - s k).
// So the closed curve "offset s = -h forward, normal at t = 1, offset s = +h
// backward, normal at t = 0" winds +1 around every point it sweeps once,
// and more around points swept several times, as long as 1 - s k > 0 on the
// whole rectangle, i.e. as long as the radius of curvature 1/|k| exceeds h.
// Where it does not, the rectangle folds along the evolute s = 1/k(t) (the
// centres of curvature): past the fold the Jacobian is negative, and the
// naive outline winds -1 there, which would cancel other pieces (the inner
// offset's "swallowtail", the classic failure). We split the segment where
// |k| h = 1 and, where |k| h > 1, split the rectangle along s = 1/k: the part
// with 1 - s k >= 0 is traced as it is, the part with 1 - s k <= 0 is traced
// reversed. Both pieces are bounded by an offset and the evolute; each winds
// +1 (or more) everywhere it covers, and together they cover exactly the
// swept normals (Nehab 2020 uses evolutes in these regions for the same
// reason). Offsets and evolutes are fitted by quadratics through the
// tangent-line intersection at the ends, split until 7 interior samples lie
// within the tolerance.
//
// Segments are first split at cusps (zero speed: the normal flips), at
// inflections, where |k| h = 1, at extrema of k inside high-curvature spans
// (cusps of the evolute), and so that the tangent turns by at most 80° per
// fitted span.
//
// Joins and caps follow SVG 2 painting.html#LineJoin and #LineCaps. A round
// join or cap is a whole disk: it contains the SVG shape, and what it adds
// lies within half the width of the path, so the stroke stays the set of
// points within h of the path for round joins and caps, exactly.
//
// Pieces that share a normal segment (consecutive runs and segments, the
// joins between them, square caps) are emitted as one contour, a strip,
// which winds exactly as the sum of its pieces (see Stroker::contour):
// usually one contour per open subpath or dash, two per closed subpath, and
// one more per high-curvature run and per disk.
#include "stroker/stroker.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "stroker/curve.h"

namespace mpvg::stroke {

namespace {

constexpr double kPi = M_PI;

// ---------------------------------------------------------------- output

// A boundary element of a piece: a line p0 -> p2, a quadratic or a conic.
struct Piece {
  SegmentType type;
  Vec2 p0, p1, p2;
  double w = 1;
};
using Chain = std::vector<Piece>;

void reverse(Chain& c) {
  std::reverse(c.begin(), c.end());
  for (Piece& p : c) std::swap(p.p0, p.p2);
}

void append(Chain& to, const Chain& from) { to.insert(to.end(), from.begin(), from.end()); }

// The circular arc of centre o and radius r from angle a0 over `sweep`
// radians (positive: counter-clockwise), as conics of at most 90°. A conic
// with its middle control point where the end tangents meet and weight
// cos(half the angle) is exactly the arc.
Chain arc(Vec2 o, double r, double a0, double sweep) {
  Chain c;
  const int n = std::max(1, static_cast<int>(std::ceil(std::fabs(sweep) / (kPi / 2) - 1e-9)));
  const double d = sweep / n;
  const double w = std::cos(d / 2);
  auto at = [&](double a, double radius) { return Vec2{o.x + radius * std::cos(a), o.y + radius * std::sin(a)}; };
  for (int i = 0; i < n; i++) {
    const double s = a0 + i * d;
    c.push_back({SegmentType::RQuad, at(s, r), at(s + d / 2, r / w), at(s + d, r), w});
  }
  return c;
}

// Collects the pieces, each a closed contour, into the output path. A
// contour is only started by its first element of positive length, so that
// degenerate pieces leave nothing behind.
class Output {
 public:
  void begin(Vec2 p) {
    start_ = cur_ = p;
    pending_ = true;
  }
  void line(Vec2 p) {
    if (p == cur_) return;
    start_contour();
    path_.line_to(p);
    cur_ = p;
  }
  // Appends a chain, bridging a gap before each element with a line.
  void chain(const Chain& c) {
    for (const Piece& p : c) {
      line(p.p0);
      if (p.type == SegmentType::Line) {
        line(p.p2);
      } else if (p.p0 != p.p2 || p.p1 != p.p0) {
        start_contour();
        if (p.type == SegmentType::Quad)
          path_.quad_to(p.p1, p.p2);
        else
          path_.rquad_to(p.p1, p.p2, p.w);
        cur_ = p.p2;
      }
    }
  }
  void close() {
    if (!pending_) path_.close();
    pending_ = false;
  }

  // A closed chain as one contour.
  void contour(const Chain& c) {
    if (c.empty()) return;
    begin(c.front().p0);
    chain(c);
    close();
  }

  // A convex polygon, counter-clockwise whatever the order given, so that it
  // winds +1 inside; nothing when it has no area.
  void polygon(std::initializer_list<Vec2> pts) {
    const Vec2* p = pts.begin();
    const size_t n = pts.size();
    double area = 0;
    for (size_t i = 1; i + 1 < n; i++) area += cross(p[i] - p[0], p[i + 1] - p[0]);
    if (!(area != 0) || !std::isfinite(area)) return;
    if (area > 0) {
      begin(p[0]);
      for (size_t i = 1; i < n; i++) line(p[i]);
    } else {
      begin(p[n - 1]);
      for (size_t i = n - 1; i-- > 0;) line(p[i]);
    }
    close();
  }

  // A disk, counter-clockwise: four quarter conics.
  void disk(Vec2 o, double r) { contour(arc(o, r, 0, 2 * kPi)); }

  Path take() { return std::move(path_); }

 private:
  void start_contour() {
    if (!pending_) return;
    path_.move_to(start_);
    pending_ = false;
  }

  Path path_;
  Vec2 start_, cur_;
  bool pending_ = false;
};

// ---------------------------------------------------------------- fitting

double dist_segment(Vec2 x, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double l2 = dot(ab, ab);
  const double u = l2 > 0 ? std::clamp(dot(x - a, ab) / l2, 0.0, 1.0) : 0.0;
  return length(x - (a + u * ab));
}

// Distance from x to the quadratic Bezier (p0, p1, p2), by Newton's method
// on dot(Q(u) - x, Q'(u)) = 0 from `guess`; when that does not land within
// `enough`, from the best of 9 samples as well. Any point of the curve
// gives an upper bound, so the result never underestimates.
double dist_quad(Vec2 x, Vec2 p0, Vec2 p1, Vec2 p2, double guess, double enough) {
  const Vec2 a = p0 - 2 * p1 + p2, b = p1 - p0;  // Q(u) = p0 + 2u b + u^2 a
  auto q = [&](double u) { return p0 + (2 * u) * b + (u * u) * a; };
  auto newton = [&](double u) {
    for (int it = 0; it < 6; it++) {
      const Vec2 r = q(u) - x, d1 = 2 * (b + u * a);
      const double f = dot(r, d1), fp = dot(d1, d1) + 2 * dot(r, a);
      if (!(fp > 0)) break;
      u = std::clamp(u - f / fp, 0.0, 1.0);
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
  return std::min({d, best, newton(best_u)});
}

// The moving frame of a segment over one span [a, b] of its parameter:
// the unit tangent, with the values at the ends given (they are limits from
// inside the span at cusps and at coincident control points).
struct Frame {
  const Curve* c;
  double a, b;
  Vec2 ta, tb;

  Vec2 tangent(double t) const {
    if (t == a) return ta;
    if (t == b) return tb;
    const Vec2 d = normalized(c->derivative(t));
    if (d.x != 0 || d.y != 0) return d;
    return normalized(c->point(std::min(b, t + 1e-9)) - c->point(std::max(a, t - 1e-9)));
  }
};

// A curve bounding a body piece: the offset at signed distance s, or the
// evolute c + n / k clamped to |1/k| <= h (only used where |k| h >= 1).
struct Boundary {
  Frame f;
  bool evolute = false;
  double s = 0;     // offset distance
  double h = 0;     // half width (evolute clamp)
  int side = 0;     // evolute: +1 centres of curvature on the left, -1 right

  // The point at t; *dir is a direction of its tangent line (offsets are
  // parallel to the path, the evolute is normal to it).
  Vec2 point(double t, Vec2* dir) const {
    const Vec2 T = f.tangent(t), n = rot90(T);
    const Vec2 p = f.c->point(t);
    if (!evolute) {
      if (dir) *dir = T;
      return p + s * n;
    }
    if (dir) *dir = n;
    return p + radius(t) * n;
  }

  // Signed radius of curvature |c'|^3 / (c' x c''), clamped to the span's
  // side and to h: it tends to 0 at cusps and is at most h in these spans.
  double radius(double t) const {
    Vec2 d1, d2;
    f.c->derivatives(t, &d1, &d2);
    const double sp = length(d1), cr = cross(d1, d2);
    if (!(sp > 0)) return 0;
    const double r = sp * sp * sp / cr;
    if (side > 0) return (cr > 0 && r < h) ? r : h;
    return (cr < 0 && r > -h) ? r : -h;
  }
};

// Quadratic approximation of a boundary, appended to a chain.
class Fitter {
 public:
  Fitter(const Boundary& g, double tol, Chain& out) : g_(g), tol_(tol), out_(out) {}

  void run(const std::vector<double>& knots) {
    calls_ = 0;
    Vec2 du;
    Vec2 pu = g_.point(knots[0], &du);
    for (size_t i = 0; i + 1 < knots.size(); i++) {
      Vec2 dv;
      const Vec2 pv = g_.point(knots[i + 1], &dv);
      piece(knots[i], knots[i + 1], pu, pv, du, dv, 0);
      pu = pv;
      du = dv;
    }
  }

 private:
  static constexpr int kMaxDepth = 48;
  // At most this many subdivisions per boundary: input that defeats the
  // fitter (rounding noise) ends in lines instead of an exponential search.
  static constexpr int kMaxCalls = 20000;
  int calls_ = 0;

  // Fits the boundary between knots or splits u..v. The boundary is a
  // convex arc here (its tangent turns one way, by less than 80°), so it
  // lies in the triangle of its chord and end tangents: the triangle's
  // height bounds its distance from the chord. Its deviation from a
  // quadratic is measured at 7 samples, which must be spread along the arc:
  // where the tangent turns within a tiny range of t (near-cusps), samples
  // uniform in t all fall at one end, which the even turning check detects.
  void piece(double u, double v, Vec2 pu, Vec2 pv, Vec2 du, Vec2 dv, int depth) {
    if (depth >= kMaxDepth || !(v - u > 1e-15) || ++calls_ > kMaxCalls) {
      out_.push_back({SegmentType::Line, pu, {}, pv});
      return;
    }
    Vec2 s[7], ds[7];
    for (int k = 0; k < 7; k++) s[k] = g_.point(u + (v - u) * (k + 1) / 8.0, &ds[k]);
    // The turn between samples, as sin of the angle (cheap, and a slight
    // underestimate: a near-cusp puts almost all of the turn in one step).
    auto step_turn = [](Vec2 a, Vec2 b) { return dot(a, b) > 0 ? std::fabs(cross(a, b)) : 1.0; };
    const double total = std::atan2(cross(du, dv), dot(du, dv));
    double step = step_turn(du, ds[0]);
    for (int k = 0; k < 6; k++) step = std::max(step, step_turn(ds[k], ds[k + 1]));
    step = std::max(step, step_turn(ds[6], dv));
    const bool even = step <= 0.4 * std::fabs(total) + 0.02;
    const Vec2 chord = pv - pu;
    const double len = length(chord);
    if (even) {
      // A line when the arc's triangle is flat: its height is at most
      // len * min(tan a, tan b) for the angles a, b of the end tangents
      // with the chord.
      auto tan_to_chord = [&](Vec2 d) {
        const double c = std::fabs(dot(d, chord));
        return c > 0 ? std::fabs(cross(d, chord)) / c : std::numeric_limits<double>::infinity();
      };
      const double height = len * std::min(tan_to_chord(du), tan_to_chord(dv));
      double err = 0;
      for (const Vec2& x : s) err = std::max(err, dist_segment(x, pu, pv));
      if (err <= tol_ && height <= tol_) {
        out_.push_back({SegmentType::Line, pu, {}, pv});
        return;
      }
      // The quadratic whose control point is where the end tangents meet.
      // It must run forwards along the chord, with a control polygon no
      // longer than twice the chord.
      const double den = cross(du, dv);
      if (std::fabs(den) > 1e-9) {
        const Vec2 p1 = pu + (cross(chord, dv) / den) * du;
        if (dot(p1 - pu, chord) > 0 && dot(pv - p1, chord) > 0 && length(p1 - pu) + length(pv - p1) <= 2 * len) {
          err = 0;
          for (int k = 0; k < 7 && err <= tol_; k++)
            err = std::max(err, dist_quad(s[k], pu, p1, pv, (k + 1) / 8.0, tol_));
          if (err <= tol_) {
            out_.push_back({SegmentType::Quad, pu, p1, pv});
            return;
          }
        }
      }
    }
    const double m = split(u, v, !even);
    Vec2 dm;
    const Vec2 pm = g_.point(m, &dm);
    piece(u, m, pu, pm, du, dm, depth + 1);
    piece(m, v, pm, pv, dm, dv, depth + 1);
  }

  // Where to split a piece that does not fit: where the tangent has turned
  // half way when it turns noticeably or unevenly in t (near-cusps turn
  // within a tiny range of t), else in the middle.
  double split(double u, double v, bool uneven) const {
    const Vec2 tu = g_.f.tangent(u), tv = g_.f.tangent(v);
    const double phi = std::atan2(cross(tu, tv), dot(tu, tv));
    if (!uneven && std::fabs(phi) < 0.35) return (u + v) / 2;
    if (phi == 0 || std::fabs(phi) > kPi - 1e-6) return (u + v) / 2;
    // The tangent turns one way from tu to tv: it has turned half way once
    // it is past their bisector.
    const Vec2 half = normalized(tu + tv);
    const double dir = phi > 0 ? 1 : -1;
    double lo = u, hi = v;
    for (int it = 0; it < 40; it++) {
      const double m = (lo + hi) / 2;
      if (dir * cross(half, g_.f.tangent(m)) < 0)
        lo = m;
      else
        hi = m;
    }
    const double m = (lo + hi) / 2;
    return (m > u && m < v) ? m : (u + v) / 2;
  }

  const Boundary& g_;
  double tol_;
  Chain& out_;
};

// ---------------------------------------------------------------- segment analysis

// A span of a segment's parameter with one kind of body: normal (|k| h < 1)
// or high curvature with the centres of curvature on the left (+1) or
// right (-1) within reach of the stroke.
struct Span {
  double a, b;
  Vec2 ta, tb;
  int kind;
  bool cusp_at_a = false;         // the normal flips at a: a new run begins
  std::vector<double> knots;      // a, ..., b: where the fitter starts pieces
};

struct Break {
  double t;
  bool cusp;
};

template <class F>
double bisect(double lo, double hi, F sign_at_lo_is, int iterations = 60) {
  for (int i = 0; i < iterations; i++) {
    const double m = (lo + hi) / 2;
    if (sign_at_lo_is(m))
      lo = m;
    else
      hi = m;
  }
  return (lo + hi) / 2;
}

// Minimum (or maximum, with sign -1) of f on [lo, hi] by golden-section search.
template <class F>
double golden(double lo, double hi, F f, double sign = 1) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = sign * f(x1), f2 = sign * f(x2);
  for (int i = 0; i < 80; i++) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - g * (hi - lo), f1 = sign * f(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + g * (hi - lo), f2 = sign * f(x2);
    }
  }
  return (lo + hi) / 2;
}

class Analysis {
 public:
  Analysis(const Curve& c, double h) : c_(c), h_(h) {}

  std::vector<Span> spans() {
    find_breaks();
    std::vector<Span> out;
    for (size_t i = 0; i + 1 < breaks_.size(); i++) {
      Span sp;
      sp.a = breaks_[i].t;
      sp.b = breaks_[i + 1].t;
      sp.cusp_at_a = breaks_[i].cusp;
      sp.ta = end_tangent(sp.a, sp.b, breaks_[i].cusp, true);
      sp.tb = end_tangent(sp.b, sp.a, breaks_[i + 1].cusp, false);
      sp.kind = kind_at((sp.a + sp.b) / 2);
      sp.knots = knots(sp);
      out.push_back(std::move(sp));
    }
    return out;
  }

 private:
  static constexpr int kSamples = 48;

  // c' x c'', zero where it is at the level of rounding (straight curves).
  static double curl(Vec2 d1, Vec2 d2) {
    const double cr = cross(d1, d2);
    return std::fabs(cr) <= 1e-12 * length(d1) * length(d2) ? 0 : cr;
  }

  // (h |k| - 1) |c'|^3 = h |c' x c''| - |c'|^3: positive where |k| h > 1.
  // At the curve's ends the speed may vanish (coincident control points):
  // the value just inside stands for the limit there.
  double excess(double t) const {
    t = std::clamp(t, 1e-7, 1 - 1e-7);
    Vec2 d1, d2;
    c_.derivatives(t, &d1, &d2);
    const double sp = length(d1);
    return h_ * std::fabs(curl(d1, d2)) - sp * sp * sp;
  }

  int kind_at(double t) const {
    Vec2 d1, d2;
    c_.derivatives(t, &d1, &d2);
    const double sp = length(d1), cr = curl(d1, d2);
    if (!(h_ * std::fabs(cr) > sp * sp * sp)) return 0;
    return cr > 0 ? 1 : -1;
  }

  // Within this distance of a cusp (in t), c' is at the level of rounding
  // noise: its direction and the signs of c' x c'' are meaningless there.
  // Other breaks are not placed that close, and the tangents at a cusp come
  // from secants this long (see end_tangent).
  static constexpr double kCuspGuard = 1e-6;

  void add(double t, bool cusp) {
    if (!(t > 0 && t < 1)) return;
    if (!cusp)
      for (double c : cusps_)
        if (std::fabs(t - c) < kCuspGuard) return;
    if (cusp) cusps_.push_back(t);
    breaks_.push_back({t, cusp});
  }

  void find_breaks() {
    const double e = c_.extent();
    double ts[kSamples + 1];
    Vec2 d1[kSamples + 1], d2[kSamples + 1];
    double max_speed = 0;
    for (int i = 0; i <= kSamples; i++) {
      ts[i] = double(i) / kSamples;
      c_.derivatives(ts[i], &d1[i], &d2[i]);
      max_speed = std::max(max_speed, length(d1[i]));
    }
    // Speed minima: cusps where the speed vanishes (the tangent reverses),
    // and sharp near-cusps, where the tangent turns fast.
    auto speed2 = [&](double t) {
      const Vec2 d = c_.derivative(t);
      return dot(d, d);
    };
    for (int i = 1; i < kSamples; i++) {
      const double s0 = dot(d1[i - 1], d1[i - 1]), s1 = dot(d1[i], d1[i]), s2 = dot(d1[i + 1], d1[i + 1]);
      if (!(s1 <= s0 && s1 <= s2 && (s1 < s0 || s1 < s2))) continue;
      // Sampled this fast, the speed cannot drop near zero between samples.
      if (s1 > 0.0625 * max_speed * max_speed) continue;
      const double tm = golden(ts[i - 1], ts[i + 1], speed2);
      const double sp = std::sqrt(speed2(tm));
      if (sp <= 1e-10 * e)
        add(tm, true);
      else if (sp < 0.05 * max_speed)
        add(tm, false);
    }
    // Inflections: sign changes of c' x c'' (values at rounding level
    // count as zero, so straight curves have none).
    auto cr = [&](double t) {
      Vec2 a, b;
      c_.derivatives(t, &a, &b);
      return cross(a, b);
    };
    int last = -1;
    for (int i = 0; i <= kSamples; i++) {
      const double v = cross(d1[i], d2[i]);
      if (std::fabs(v) <= 1e-12 * length(d1[i]) * length(d2[i])) continue;
      if (last >= 0 && (v > 0) != (cross(d1[last], d2[last]) > 0)) {
        const bool lo_pos = cross(d1[last], d2[last]) > 0;
        add(bisect(ts[last], ts[i], [&](double t) { return (cr(t) > 0) == lo_pos; }), false);
      }
      last = i;
    }
    breaks_.push_back({0, false});
    breaks_.push_back({1, false});
    sort_breaks();
    // Where |k| h crosses 1, sampled on the uniform grid and at the breaks
    // so far (curvature peaks sit at near-cusps). Curvature is infinite at
    // a cusp, and near one only noise decides.
    auto near_cusp = [&](double t) {
      for (double c : cusps_)
        if (std::fabs(t - c) < kCuspGuard) return true;
      return false;
    };
    auto sample_high = [&](int i) {
      if (near_cusp(ts[i])) return true;
      if (i == 0 || i == kSamples) return excess(ts[i]) > 0;
      const double sp = length(d1[i]);
      return h_ * std::fabs(curl(d1[i], d2[i])) - sp * sp * sp > 0;
    };
    std::vector<std::pair<double, bool>> grid;  // (t, high), in order
    grid.reserve(kSamples + 1 + breaks_.size());
    size_t b = 0;
    auto push_breaks_before = [&](double t) {
      for (; b < breaks_.size() && breaks_[b].t < t; b++)
        grid.push_back({breaks_[b].t, breaks_[b].cusp || near_cusp(breaks_[b].t) || excess(breaks_[b].t) > 0});
    };
    for (int i = 0; i <= kSamples; i++) {
      push_breaks_before(ts[i]);
      grid.push_back({ts[i], sample_high(i)});
    }
    push_breaks_before(2);
    std::vector<double> crossings;
    for (size_t i = 0; i + 1 < grid.size(); i++) {
      const bool h0 = grid[i].second;
      if (h0 == grid[i + 1].second || !(grid[i + 1].first > grid[i].first)) continue;
      crossings.push_back(bisect(grid[i].first, grid[i + 1].first, [&](double t) { return (excess(t) > 0) == h0; }));
    }
    for (double t : crossings) add(t, false);
    sort_breaks();
  }

  void sort_breaks() {
    std::sort(breaks_.begin(), breaks_.end(), [](const Break& x, const Break& y) { return x.t < y.t; });
    std::vector<Break> out;
    for (const Break& b : breaks_) {
      if (!out.empty() && b.t - out.back().t <= 1e-12) {
        out.back().cusp = out.back().cusp || b.cusp;
        if (b.t == 1) out.back().t = 1;
        continue;
      }
      out.push_back(b);
    }
    // The ends stay exactly 0 and 1.
    out.front().t = 0;
    out.front().cusp = false;
    out.back().t = 1;
    out.back().cusp = false;
    breaks_ = out;
  }

  // The unit tangent at t, the limit from inside [t, other] (at_start) or
  // [other, t]: from the control points at the curve's ends, from a secant
  // at a cusp (where c' vanishes and flips), else from c'.
  Vec2 end_tangent(double t, double other, bool cusp, bool at_start) const {
    if (t == 0) return c_.start_tangent();
    if (t == 1) return c_.end_tangent();
    const Vec2 d = normalized(c_.derivative(t));
    if (!cusp && (d.x != 0 || d.y != 0)) return d;
    const double delta = std::min(kCuspGuard, std::fabs(other - t) / 4);
    return at_start ? normalized(c_.point(t + delta) - c_.point(t)) : normalized(c_.point(t) - c_.point(t - delta));
  }

  // Knots of a span: its ends, the cusps of the evolute in high-curvature
  // spans (extrema of the radius of curvature), and points that keep the
  // tangent's turn below 80° between knots.
  std::vector<double> knots(const Span& sp) const {
    std::vector<double> k{sp.a, sp.b};
    const Frame f{&c_, sp.a, sp.b, sp.ta, sp.tb};
    constexpr int n = 16;
    double t[n + 1];
    for (int i = 0; i <= n; i++) t[i] = sp.a + (sp.b - sp.a) * i / n;
    t[n] = sp.b;
    if (sp.kind != 0) {
      auto rho = [&](double x) {
        Vec2 d1, d2;
        c_.derivatives(x, &d1, &d2);
        const double s = length(d1);
        return s * s * s / cross(d1, d2);
      };
      double r[n + 1];
      for (int i = 0; i <= n; i++) r[i] = rho(t[i]);
      for (int i = 1; i < n; i++) {
        const bool is_max = r[i] > r[i - 1] && r[i] >= r[i + 1];
        const bool is_min = r[i] < r[i - 1] && r[i] <= r[i + 1];
        if ((is_max || is_min) && std::isfinite(r[i]))
          k.push_back(golden(t[i - 1], t[i + 1], rho, is_max ? -1 : 1));
      }
    }
    // Turning: the tangent turns one way inside a span (spans end at
    // inflections and cusps); accumulate it, and split every ~75°.
    Vec2 T[n + 1];
    for (int i = 0; i <= n; i++) T[i] = f.tangent(t[i]);
    Vec2 d1, d2;
    c_.derivatives((sp.a + sp.b) / 2, &d1, &d2);
    const double dir = cross(d1, d2) >= 0 ? 1 : -1;
    auto turn = [&](Vec2 x, Vec2 y) {
      double a = std::atan2(cross(x, y), dot(x, y));
      if (a * dir < 0 && std::fabs(a) > 1e-9) a += dir * 2 * kPi;
      return a;
    };
    double acc[n + 1];
    acc[0] = 0;
    for (int i = 0; i < n; i++) acc[i + 1] = acc[i] + turn(T[i], T[i + 1]);
    const double total = std::fabs(acc[n]);
    constexpr double kMaxTurn = 75 * kPi / 180;
    if (total > kMaxTurn * 1.07) {
      const int m = static_cast<int>(std::ceil(total / kMaxTurn));
      for (int j = 1; j < m; j++) {
        const double target = acc[n] * j / m;
        int i = 0;
        while (i < n - 1 && std::fabs(acc[i + 1]) < std::fabs(target)) i++;
        const double local = target - acc[i];
        k.push_back(bisect(t[i], t[i + 1],
                           [&](double x) { return std::fabs(turn(T[i], f.tangent(x))) < std::fabs(local); }));
      }
    }
    std::sort(k.begin(), k.end());
    std::vector<double> out;
    for (double x : k)
      if (out.empty() || x - out.back() > 1e-12) out.push_back(x);
    out.front() = sp.a;
    if (out.back() != sp.b) {
      if (out.size() > 1 && sp.b - out.back() <= 1e-12)
        out.back() = sp.b;
      else
        out.push_back(sp.b);
    }
    return out;
  }

  const Curve& c_;
  double h_;
  std::vector<Break> breaks_;
  std::vector<double> cusps_;
};

// ---------------------------------------------------------------- curvature at the ends

// Signed curvature at an end of a segment (lines: 0); NaN where the speed
// vanishes (coincident control points: infinite curvature).
double end_curvature(const Curve& c, bool at_end) {
  if (c.is_line()) return 0;
  Vec2 d1, d2;
  c.derivatives(at_end ? 1 : 0, &d1, &d2);
  const double sp = length(d1);
  if (!(sp > 1e-12 * c.extent())) return std::numeric_limits<double>::quiet_NaN();
  return cross(d1, d2) / (sp * sp * sp);
}

// ---------------------------------------------------------------- the stroker

class Stroker {
 public:
  Stroker(const Style& st, double tol) : st_(st), h_(st.width / 2), tol_(tol) {
    miter_limit_ = std::isfinite(st.miter_limit) ? std::max(1.0, st.miter_limit) : 1.0;
  }

  // A solid open or closed subpath of non-degenerate curves.
  //
  // Pieces that meet along a whole normal segment are merged into one
  // contour, a strip: the runs of the bodies (of a high-curvature run, the
  // part traced as it is), the joins between them and square caps. Winding numbers add over closed chains,
  // so the contour that runs along the pieces' boundaries, leaving out the
  // edges two pieces share (traced once each way), winds exactly as the sum
  // of the pieces: merging changes no winding number anywhere, it only
  // saves segments. At a join the outer side runs through the join shape
  // and the inner side through the vertex itself, the two edges that the
  // bodies' end normals and the join shape leave there. Of a high-curvature
  // run, the part traced reversed stays a contour of its own; cusps end the
  // strip.
  void contour(const std::vector<Curve>& cs, bool closed) {
    std::vector<std::vector<Unit>> units(cs.size());
    for (size_t i = 0; i < cs.size(); i++) body(cs[i], units[i]);
    bool whole = true;  // one strip runs through the whole subpath
    for (size_t i = 0; i < cs.size(); i++) {
      for (const Unit& u : units[i]) {
        if (!u.merge) {
          finish_strip({});
          whole = false;
          continue;
        }
        if (!strip_.open) {
          const bool at_start = i == 0 && &u == &units[0].front();
          open_strip(at_start && !closed ? cap_path(cs[0].start(), cs[0].start_tangent(), false)
                                         : std::vector<Vec2>{});
        }
        append(strip_.right, u.right);
        append(strip_.left, u.left);
      }
      if (i + 1 < cs.size()) join(cs[i], cs[i + 1], units[i + 1].front().merge);
    }
    if (closed) {
      const bool loops = whole && strip_.open;
      join(cs.back(), cs.front(), loops);
      if (loops) {
        // The outer and inner boundaries closed on themselves.
        strip_.open = false;
        out_.contour(strip_.right);
        reverse(strip_.left);
        out_.contour(strip_.left);
      }
      finish_strip({});
      return;
    }
    const Curve& first = cs.front();
    const Curve& last = cs.back();
    if (!units.front().front().merge) cap(first.start(), first.start_tangent(), false);
    if (strip_.open)
      finish_strip(cap_path(last.end(), last.end_tangent(), true));
    else
      cap(last.end(), last.end_tangent(), true);
    if (st_.cap == Cap::Round) {
      if (units.front().front().merge) out_.disk(first.start(), h_);
      if (units.back().back().merge) out_.disk(last.end(), h_);
    }
  }

  // A zero-length subpath or dash at p, its caps oriented along dir
  // (SVG 2 painting.html#LineCaps: a dot or a square; nothing for butt).
  void dot_caps(Vec2 p, Vec2 dir) {
    if (st_.cap == Cap::Round) {
      out_.disk(p, h_);
    } else if (st_.cap == Cap::Square) {
      const Vec2 t = h_ * dir, n = rot90(t);
      out_.polygon({p - t - n, p + t - n, p + t + n, p - t + n});
    }
  }

  Path take() { return out_.take(); }

 private:
  // A part of a segment's body in path order: a run of spans, which joins
  // the strip (its two sides, forwards), or a marker where the strip must
  // end (a cusp).
  struct Unit {
    bool merge = false;
    Chain right, left;
  };

  void body(const Curve& c, std::vector<Unit>& units) {
    if (c.is_line()) {
      const Vec2 n = h_ * rot90(normalized(c.p[1] - c.p[0]));
      Unit u;
      u.merge = true;
      u.right.push_back({SegmentType::Line, c.p[0] - n, {}, c.p[1] - n});
      u.left.push_back({SegmentType::Line, c.p[0] + n, {}, c.p[1] + n});
      units.push_back(std::move(u));
      return;
    }
    const std::vector<Span> spans = Analysis(c, h_).spans();
    // Runs of spans with the same kind and no cusp between them share their
    // pieces: the boundaries are continuous across their ends.
    size_t i = 0;
    while (i < spans.size()) {
      size_t j = i + 1;
      while (j < spans.size() && spans[j].kind == spans[i].kind && !spans[j].cusp_at_a) j++;
      // A cusp: the normal flips, the strip cannot continue; a disk joins
      // the two sides continuously.
      if (i > 0 && spans[i].cusp_at_a) {
        units.push_back({});
        out_.disk(c.point(spans[i].a), h_);
      }
      run(c, spans, i, j, units);
      i = j;
    }
  }

  Chain fit(const Curve& c, const std::vector<Span>& spans, size_t i, size_t j, bool evolute, double s) {
    Chain ch;
    for (size_t k = i; k < j; k++) {
      const Span& sp = spans[k];
      Boundary g;
      g.f = {&c, sp.a, sp.b, sp.ta, sp.tb};
      g.evolute = evolute;
      g.s = s;
      g.h = h_;
      g.side = sp.kind;
      Fitter(g, 0.75 * tol_, ch).run(sp.knots);
    }
    return ch;
  }

  // The pieces of spans [i, j) of one kind (see the top of this file). The
  // part with 1 - s k >= 0 joins the strip: for a normal run the offsets at
  // -h and +h, for a high-curvature run one offset and the evolute (the
  // evolute meets the normal segment at both ends of the run, so the strip's
  // sides stay connected along the normals). The part with 1 - s k <= 0 is
  // a contour of its own, traced reversed.
  void run(const Curve& c, const std::vector<Span>& spans, size_t i, size_t j, std::vector<Unit>& units) {
    const int kind = spans[i].kind;
    Chain right = fit(c, spans, i, j, false, -h_);
    Chain left = fit(c, spans, i, j, false, h_);
    if (kind == 0) {
      units.push_back({true, std::move(right), std::move(left)});
      return;
    }
    Chain ev = fit(c, spans, i, j, true, 0);
    if (kind > 0) {
      // Centres of curvature on the left: s in [-h, 1/k] joins the strip
      // (right offset; evolute on the left side); s in [1/k, h] is apart.
      Chain minus = left;
      Chain ev_back = ev;
      reverse(ev_back);
      append(minus, ev_back);
      out_.contour(minus);
      units.push_back({true, std::move(right), std::move(ev)});
    } else {
      // Centres on the right: s in [1/k, h] joins the strip (evolute on the
      // right side; left offset); s in [-h, 1/k] is apart.
      Chain minus = ev;
      reverse(right);
      append(minus, right);
      out_.contour(minus);
      units.push_back({true, std::move(ev), std::move(left)});
    }
  }

  // The line join shape (SVG 2 painting.html#TermLineJoinShape) at the end
  // of `prev`, where `next` starts. With `merge`, the open strip goes on
  // into `next`: the join's outer edges and the inner detour through the
  // vertex become part of it. Otherwise the strip ends and the join is a
  // contour of its own. Parts that do not fit a strip are always apart: a
  // round join's disk, an arcs join's region, the inner bevel between
  // curves.
  void join(const Curve& prev, const Curve& next, bool merge) {
    merge = merge && strip_.open;
    const Vec2 p = next.start();
    const Vec2 t0 = prev.end_tangent(), t1 = next.start_tangent();
    const double cr = cross(t0, t1), dt = dot(t0, t1);
    const double tau = std::atan2(cr, dt);  // the turn, in (-pi, pi]
    // The outer side of the turn (a half-turn counts as a left turn).
    const double sgn = tau >= 0 ? -1 : 1;
    const Vec2 n0 = rot90(t0), n1 = rot90(t1);
    const Vec2 p1 = p + (sgn * h_) * n0, p2 = p + (sgn * h_) * n1;  // outer
    const Vec2 q1 = p - (sgn * h_) * n0, q2 = p - (sgn * h_) * n1;  // inner
    // Nehab 2020: between curves, the inner side can show a gap that the
    // bodies do not fill. A body covers the inner wedge between the two end
    // normals unless it folds there (its centre of curvature on the inner
    // side, closer than h); where both fold, the inner bevel closes the gap.
    const bool fold0 = folds_inside(end_curvature(prev, true), -sgn);
    const bool fold1 = folds_inside(end_curvature(next, false), -sgn);
    // Nearly straight on: the offsets meet within a fraction of the
    // tolerance, and their ends are joined directly. Inside, that adds a
    // negative sliver, which both bodies cover when neither folds.
    const bool straight = dt > 0 && h_ * std::fabs(tau) <= tol_ / 8;
    std::vector<Vec2> outer{p1};
    if (!straight) {
      if (st_.join == Join::Round) out_.disk(p, h_);
      if (st_.join != Join::Round && fold0 && fold1) out_.polygon({p, q1, q2});
      switch (st_.join) {
        case Join::Miter:
        case Join::MiterClip: miter(p, p1, p2, t0, t1, tau, st_.join == Join::MiterClip, outer); break;
        case Join::Arcs:
          if (!arcs(p, p1, p2, t0, t1, tau, sgn, end_curvature(prev, true), end_curvature(next, false)))
            miter(p, p1, p2, t0, t1, tau, true, outer);
          break;
        default: break;  // bevel; a round join's bevel is inside its disk
      }
    }
    outer.push_back(p2);
    if (!merge) {
      finish_strip({});
      if (!straight && st_.join != Join::Round) {
        if (outer.size() == 2) out_.polygon({p, p1, p2});
        if (outer.size() == 3) out_.polygon({p, outer[0], outer[1], outer[2]});
        if (outer.size() == 4) out_.polygon({p, outer[0], outer[1], outer[2], outer[3]});
      }
      return;
    }
    Chain& o = sgn < 0 ? strip_.right : strip_.left;
    Chain& in = sgn < 0 ? strip_.left : strip_.right;
    for (size_t k = 0; k + 1 < outer.size(); k++) o.push_back({SegmentType::Line, outer[k], {}, outer[k + 1]});
    if (straight && !fold0 && !fold1) {
      in.push_back({SegmentType::Line, q1, {}, q2});
    } else {
      in.push_back({SegmentType::Line, q1, {}, p});
      in.push_back({SegmentType::Line, p, {}, q2});
    }
  }

  // Whether a body with curvature k at the join folds on the side `inner`
  // (+1 left, -1 right); NaN stands for the infinite curvature of a
  // vanishing speed, of either sign.
  bool folds_inside(double k, double inner) const { return std::isnan(k) || k * inner * h_ >= 1; }

  // Miter: the bevel plus the triangle up to where the outer edges meet,
  // when miter length / width = 1 / cos(tau / 2) is within the limit, else
  // the bevel alone, or (miter-clip) the miter clipped by the line
  // perpendicular to the bisector at miter_limit * h from p. Appends the
  // outer corners between p1 and p2 to `outer`.
  void miter(Vec2 p, Vec2 p1, Vec2 p2, Vec2 t0, Vec2 t1, double tau, bool clip, std::vector<Vec2>& outer) {
    const double ch = std::cos(tau / 2), sh = std::sin(std::fabs(tau) / 2);
    if (ch * miter_limit_ >= 1) {
      outer.push_back(p + (h_ / ch) * normalized((p1 - p) + (p2 - p)));
      return;
    }
    if (!clip) return;
    // Distance along each outer edge from p1 (p2) to the clip line.
    const double lambda = (miter_limit_ * h_ - h_ * ch) / sh;
    outer.push_back(p1 + lambda * t0);
    outer.push_back(p2 - lambda * t1);
  }

  // The strip being built: offsets at -h (right) and +h (left) forwards,
  // and the way from the left chain's start to the right one's (a square
  // cap, or nothing: the normal).
  struct Strip {
    bool open = false;
    Chain right, left;
    std::vector<Vec2> start;
  };

  void open_strip(std::vector<Vec2> start) {
    strip_.open = true;
    strip_.right.clear();
    strip_.left.clear();
    strip_.start = std::move(start);
  }

  // Emits the open strip as one contour: right chain, `end` (from the right
  // chain's end to the left chain's), left chain backwards, start.
  void finish_strip(const std::vector<Vec2>& end) {
    if (!strip_.open) return;
    strip_.open = false;
    out_.begin(strip_.right.front().p0);
    out_.chain(strip_.right);
    for (const Vec2& q : end) out_.line(q);
    reverse(strip_.left);
    out_.chain(strip_.left);
    for (const Vec2& q : strip_.start) out_.line(q);
    out_.close();
  }

  // One outer edge extended past the join: a circle (centre, radius) or,
  // for zero curvature, a line (through a point, along a direction).
  struct Edge {
    bool line;
    Vec2 o;
    double r;
    Vec2 q, d;
  };

  // Arcs (SVG 2): the outer edges are extended by the circles with their
  // curvature at the join (lines by lines) to their intersection nearest to
  // p, and the region bounded by p, the extensions and p is clipped at the
  // miter limit like miter-clip. False when the construction does not apply
  // (both edges straight, no intersection, infinite curvature, an outer
  // edge that folds back at the join): the caller falls back to miter-clip.
  bool arcs(Vec2 p, Vec2 p1, Vec2 p2, Vec2 t0, Vec2 t1, double tau, double sgn, double k0, double k1) {
    if (!std::isfinite(k0) || !std::isfinite(k1)) return false;
    if (k0 == 0 && k1 == 0) return false;
    const double s = sgn * h_;  // the outer edge is the offset at s
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
        e.r = std::fabs(1 / k - s);
      }
      return e;
    };
    const Edge e0 = edge(k0, n0, p1, t0), e1 = edge(k1, n1, p2, t1);
    // Intersections of the two extensions.
    std::vector<Vec2> xs;
    auto line_circle = [&](const Edge& l, const Edge& c) {
      const Vec2 m = l.q - c.o;
      const double bq = dot(l.d, m), cq = dot(m, m) - c.r * c.r, disc = bq * bq - cq;
      if (disc < 0) return;
      const double sq = std::sqrt(disc);
      xs.push_back(l.q + (-bq - sq) * l.d);
      xs.push_back(l.q + (-bq + sq) * l.d);
    };
    if (e0.line) {
      line_circle(e0, e1);
    } else if (e1.line) {
      line_circle(e1, e0);
    } else {
      const Vec2 dv = e1.o - e0.o;
      const double d = length(dv);
      if (!(d > 0) || d > e0.r + e1.r || d < std::fabs(e0.r - e1.r)) return false;
      const double a = (e0.r * e0.r - e1.r * e1.r + d * d) / (2 * d);
      const double y = std::sqrt(std::max(0.0, e0.r * e0.r - a * a));
      const Vec2 u = (1 / d) * dv, base = e0.o + a * u;
      xs.push_back(base + y * rot90(u));
      xs.push_back(base - y * rot90(u));
    }
    if (xs.empty()) return false;
    Vec2 x = xs[0];
    for (const Vec2& c : xs)
      if (length(c - p) < length(x - p)) x = c;

    // The boundary p -> p1 -> (extension 0) -> x -> (extension 1) -> p2 -> p,
    // as lines and arcs with a parameter in [0, 1] each.
    struct Elem {
      bool line;
      Vec2 a, b;                // line
      Vec2 o;                   // arc
      double r, a0, sweep;
      Vec2 at(double u) const {
        if (line) return a + u * (b - a);
        const double th = a0 + u * sweep;
        return {o.x + r * std::cos(th), o.y + r * std::sin(th)};
      }
    };
    auto mod2pi = [](double a) {
      a = std::fmod(a, 2 * kPi);
      return a < 0 ? a + 2 * kPi : a;
    };
    std::vector<Elem> elems;
    elems.push_back({true, p, p1, {}, 0, 0, 0});
    auto extension = [&](const Edge& e, Vec2 from, Vec2 to, Vec2 t, bool forwards) {
      if (e.line) {
        // Along t from p1 (forwards), or arriving along t at p2.
        if (dot(to - from, t) < 0) return false;
        elems.push_back({true, from, to, {}, 0, 0, 0});
        return true;
      }
      // Turning like the edge at its end point (p1 or p2).
      const Vec2 rim = forwards ? from : to;
      const bool ccw = cross(rim - e.o, t) > 0;
      const double a_from = std::atan2(from.y - e.o.y, from.x - e.o.x);
      const double a_to = std::atan2(to.y - e.o.y, to.x - e.o.x);
      const double sweep = ccw ? mod2pi(a_to - a_from) : -mod2pi(a_from - a_to);
      if (std::fabs(sweep) > kPi) return false;
      elems.push_back({false, {}, {}, e.o, e.r, a_from, sweep});
      return true;
    };
    if (!extension(e0, p1, x, t0, true) || !extension(e1, x, p2, t1, false)) return false;
    elems.push_back({true, p2, p, {}, 0, 0, 0});

    // Clip by the half-plane dot(q - p, b) <= miter_limit * h.
    const Vec2 b = std::fabs(tau) < kPi - 1e-9 ? normalized((p1 - p) + (p2 - p)) : t0;
    const double lim = miter_limit_ * h_;
    auto inside = [&](Vec2 q) { return dot(q - p, b) <= lim; };
    Chain out;
    for (const Elem& e : elems) {
      std::vector<double> us{0, 1};
      if (e.line) {
        const double f0 = dot(e.a - p, b) - lim, f1 = dot(e.b - p, b) - lim;
        if ((f0 < 0) != (f1 < 0) && f0 != f1) us.push_back(f0 / (f0 - f1));
      } else {
        // dot(o - p, b) + r cos(theta - beta) = lim.
        const double kc = (lim - dot(e.o - p, b)) / e.r;
        if (std::fabs(kc) < 1) {
          const double beta = std::atan2(b.y, b.x), ac = std::acos(kc);
          for (double th : {beta + ac, beta - ac}) {
            // The parameter of th on this arc, if it lies on it.
            const double rel = e.sweep >= 0 ? mod2pi(th - e.a0) : -mod2pi(e.a0 - th);
            const double u = rel / e.sweep;
            if (u > 0 && u < 1) us.push_back(u);
          }
        }
      }
      std::sort(us.begin(), us.end());
      for (size_t k = 0; k + 1 < us.size(); k++) {
        const double ua = us[k], ub = us[k + 1];
        if (!(ub > ua) || !inside(e.at((ua + ub) / 2))) continue;
        if (e.line) {
          out.push_back({SegmentType::Line, e.at(ua), {}, e.at(ub)});
        } else {
          Chain a = arc(e.o, e.r, e.a0 + ua * e.sweep, (ub - ua) * e.sweep);
          // Pin the arc's ends to the boundary points so that the chain
          // stays connected exactly.
          a.front().p0 = e.at(ua);
          a.back().p2 = e.at(ub);
          append(out, a);
        }
      }
    }
    // Left turns (outer edges on the right) run counter-clockwise.
    if (sgn > 0) reverse(out);
    out_.contour(out);
    return true;
  }

  // The square cap (SVG 2 painting.html#TermCapShape) as part of a strip:
  // at the end, from p - h n around p + h t to p + h n; at the start, from
  // p + h n around p - h t to p - h n. The strip's sides may end elsewhere
  // on the normal (at the evolute): the path starts and ends on the normal's
  // ends so that the lines to them run along it. Nothing for butt and round
  // caps (a round cap is a disk of its own).
  std::vector<Vec2> cap_path(Vec2 p, Vec2 t, bool at_end) const {
    if (st_.cap != Cap::Square) return {};
    const Vec2 n = h_ * rot90(t), e = h_ * t;
    if (at_end) return {p - n, p - n + e, p + n + e, p + n};
    return {p + n, p + n - e, p - n - e, p - n};
  }

  // The cap shape at an end of an open subpath or dash, as a contour of its
  // own; t is the direction of travel there.
  void cap(Vec2 p, Vec2 t, bool at_end) {
    if (st_.cap == Cap::Round) {
      out_.disk(p, h_);
    } else if (st_.cap == Cap::Square) {
      const Vec2 n = h_ * rot90(t), e = (at_end ? h_ : -h_) * t;
      out_.polygon({p - n, p + e - n, p + e + n, p + n});
    }
  }

  const Style& st_;
  double h_, tol_;
  double miter_limit_;
  Output out_;
  Strip strip_;
};

// ---------------------------------------------------------------- input and dashing

// Subpaths of a Path as curves, zero-length segments left out.
struct Subpath {
  std::vector<Curve> curves;
  bool closed = false;
  bool zero_length = false;  // had segments (or "M p Z") but no length: caps only
  Vec2 start;
};

bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

std::vector<Subpath> subpaths(const Path& path) {
  std::vector<Subpath> out;
  const auto& pts = path.points();
  for (const Path::Contour& c : path.contours()) {
    Subpath sp;
    sp.closed = c.closed;
    sp.start = pts[c.start_point];
    bool ok = finite(sp.start);
    for (uint32_t k = 0; k < c.segment_count && ok; k++) {
      const Path::Segment& s = path.segments()[c.first_segment + k];
      Curve cv;
      cv.type = s.type;
      if (s.type == SegmentType::RCubic) {
        // No frontend produces rational cubics and encode() refuses them:
        // their contour is left out.
        ok = false;
        break;
      }
      for (int i = 0; i <= cv.degree(); i++) {
        cv.p[i] = pts[s.first_point + i];
        ok = ok && finite(cv.p[i]);
      }
      if (s.type == SegmentType::RQuad) {
        cv.w = path.weights()[s.first_weight];
        ok = ok && std::isfinite(cv.w) && cv.w > 0;
      }
      if (ok && cv.extent() > 0) sp.curves.push_back(cv);
    }
    // A contour with a non-finite coordinate is left out whole.
    if (!ok) continue;
    sp.zero_length = sp.curves.empty() && (c.segment_count > 0 || c.closed);
    if (!sp.curves.empty() || sp.zero_length) out.push_back(std::move(sp));
  }
  return out;
}

// A subpath measured by arc length.
class Measured {
 public:
  explicit Measured(const std::vector<Curve>& cs) : curves_(cs) {
    cum_.push_back(0);
    for (const Curve& c : curves_) {
      tables_.emplace_back(c);
      cum_.push_back(cum_.back() + tables_.back().total());
    }
  }
  double length() const { return cum_.back(); }

  // The curve and parameter at arc length s; at a vertex, the start of the
  // next curve (prefer_next) or the end of the previous one.
  std::pair<size_t, double> locate(double s, bool prefer_next) const {
    const size_t n = curves_.size();
    if (s <= 0) return {0, 0};
    if (s >= length()) return {n - 1, 1};
    size_t i = static_cast<size_t>(std::upper_bound(cum_.begin(), cum_.end(), s) - cum_.begin()) - 1;
    i = std::min(i, n - 1);
    if (!prefer_next && s == cum_[i] && i > 0) return {i - 1, 1};
    return {i, tables_[i].param_at(s - cum_[i])};
  }

  // The curves between arc lengths s0 < s1.
  std::vector<Curve> extract(double s0, double s1) const {
    const auto [i0, t0] = locate(s0, true);
    const auto [i1, t1] = locate(s1, false);
    std::vector<Curve> out;
    auto push = [&](const Curve& c) {
      if (c.extent() > 0) out.push_back(c);
    };
    if (i0 == i1) {
      if (t1 > t0) push(curves_[i0].sub(t0, t1));
    } else {
      if (t0 < 1) push(curves_[i0].sub(t0, 1));
      for (size_t i = i0 + 1; i < i1; i++) push(curves_[i]);
      if (t1 > 0) push(curves_[i1].sub(0, t1));
    }
    return out;
  }

  // The point and direction of travel at arc length s.
  std::pair<Vec2, Vec2> frame(double s) const {
    const auto [i, t] = locate(s, true);
    const Curve& c = curves_[i];
    Vec2 d = t == 0 ? c.start_tangent() : t == 1 ? c.end_tangent() : normalized(c.derivative(t));
    if (d.x == 0 && d.y == 0) d = c.start_tangent();
    return {c.point(t), d};
  }

 private:
  const std::vector<Curve>& curves_;
  std::vector<ArcLengthTable> tables_;
  std::vector<double> cum_;
};

// More dashes than this in one subpath are not drawn as dashes: the stroke
// is drawn solid instead (Skia applies the same kind of limit).
constexpr double kMaxDashes = 1e6;

// Calls solid(curves, closed) for every run of stroke and dot(point, dir)
// for every zero-length dash of a dashed subpath.
template <class Solid, class Dot>
void for_each_dash(const Subpath& sp, const std::vector<double>& pattern, double offset, Solid solid, Dot dot) {
  if (sp.zero_length) {
    // Length zero: one zero-length dash at the point when the pattern is
    // "on" there.
    if (!dash_positions(0, pattern, offset).empty()) dot(sp.start, Vec2{1, 0});
    return;
  }
  const Measured m(sp.curves);
  const double len = m.length();
  double sum = 0;
  for (double d : pattern) sum += d;
  if (len / sum * double(pattern.size()) > kMaxDashes) {
    solid(sp.curves, sp.closed);
    return;
  }
  std::vector<Interval> pos = dash_positions(len, pattern, offset);
  if (pos.empty()) return;
  if (sp.closed && pos.size() == 1 && pos[0].begin <= 0 && pos[0].end >= len) {
    solid(sp.curves, true);
    return;
  }
  // A dash through the start point of a closed subpath continues across
  // it, with a join there (resvg, Skia): the last dash runs on into the
  // first.
  const bool wraps = sp.closed && pos.size() >= 2 && pos.front().begin <= 0 && pos.front().end > 0 &&
                     pos.back().end >= len * (1 - 1e-12) && pos.back().end > pos.back().begin;
  const size_t first = wraps ? 1 : 0, last = wraps ? pos.size() - 1 : pos.size();
  for (size_t i = first; i < last; i++) {
    const Interval& d = pos[i];
    if (d.end > d.begin) {
      const std::vector<Curve> cs = m.extract(d.begin, d.end);
      if (!cs.empty()) {
        solid(cs, false);
        continue;
      }
    }
    const auto [p, dir] = m.frame(d.begin);
    dot(p, dir);
  }
  if (wraps) {
    std::vector<Curve> wrap = m.extract(pos.back().begin, len);
    const std::vector<Curve> head = m.extract(0, pos.front().end);
    wrap.insert(wrap.end(), head.begin(), head.end());
    if (!wrap.empty()) solid(wrap, false);
  }
}

void append_curve(Path& out, const Curve& c) {
  switch (c.type) {
    case SegmentType::Line: out.line_to(c.p[1]); break;
    case SegmentType::Quad: out.quad_to(c.p[1], c.p[2]); break;
    case SegmentType::RQuad: out.rquad_to(c.p[1], c.p[2], c.w); break;
    default: out.cubic_to(c.p[1], c.p[2], c.p[3]); break;
  }
}

}  // namespace

// ---------------------------------------------------------------- public API

std::optional<std::vector<double>> dash_pattern(const std::vector<double>& dashes) {
  double sum = 0;
  for (double d : dashes) {
    if (!(d >= 0) || !std::isfinite(d)) return std::nullopt;
    sum += d;
  }
  if (!(sum > 0) || !std::isfinite(sum)) return std::vector<double>{};
  std::vector<double> out = dashes;
  if (out.size() % 2 == 1) out.insert(out.end(), dashes.begin(), dashes.end());
  return out;
}

std::vector<Interval> dash_positions(double length, const std::vector<double>& pattern, double offset) {
  std::vector<Interval> out;
  const size_t n = pattern.size();
  double sum = 0;
  for (double d : pattern) sum += d;
  if (n == 0 || !(sum > 0) || !std::isfinite(sum)) {
    out.push_back({0, length});
    return out;
  }
  if (!std::isfinite(offset)) offset = 0;
  // A negative offset d counts from the end: sum - (|d| mod sum)
  // (SVG 2 painting.html#StrokeDashoffsetProperty).
  offset = std::fmod(offset, sum);
  if (offset < 0) offset += sum;
  // The dash or gap that the offset falls in. At a boundary the element
  // that ends there is over; with offset 0, the pattern starts at its
  // first element even when that is a zero-length dash.
  size_t index = 0;
  double acc = 0;
  for (size_t k = 0; k < n && offset > 0 && acc + pattern[index] <= offset; k++) {
    acc += pattern[index];
    index = (index + 1) % n;
  }
  double pos = std::min(std::max(acc + pattern[index] - offset, 0.0), length);
  if (index % 2 == 0) out.push_back({0, pos});
  while (pos < length) {
    index = (index + 1) % n;
    const double d = std::min(pattern[index], length - pos);
    if (index % 2 == 0) out.push_back({pos, pos + d});
    pos += d;
  }
  return out;
}

std::vector<double> contour_lengths(const Path& path) {
  std::vector<double> out;
  for (const Subpath& sp : subpaths(path)) {
    double l = 0;
    for (const Curve& c : sp.curves) l += arc_length(c);
    out.push_back(l);
  }
  return out;
}

Path dash_path(const Path& path, const Style& style) {
  Path out;
  const auto pattern = dash_pattern(style.dashes);
  for (const Subpath& sp : subpaths(path)) {
    auto emit = [&](const std::vector<Curve>& cs, bool closed) {
      out.move_to(cs.front().start());
      for (const Curve& c : cs) append_curve(out, c);
      if (closed) out.close();
    };
    if (sp.zero_length) continue;
    if (!pattern || pattern->empty())
      emit(sp.curves, sp.closed);
    else
      for_each_dash(sp, *pattern, style.dash_offset, emit, [](Vec2, Vec2) {});
  }
  return out;
}

Path stroke_to_fill(const Path& path, const Style& style, const Affine& to_device, double tolerance_px) {
  if (!(style.width > 0) || !std::isfinite(style.width)) return {};
  const double m[6] = {to_device.a, to_device.b, to_device.c, to_device.d, to_device.e, to_device.f};
  for (double v : m)
    if (!std::isfinite(v)) return {};
  const double det = to_device.det();
  if (!(std::fabs(det) > 0) || !std::isfinite(det)) return {};
  // The largest singular value of the linear part: user-space errors grow
  // by at most this much in device space.
  const double p = to_device.a * to_device.a + to_device.b * to_device.b;
  const double q = to_device.c * to_device.c + to_device.d * to_device.d;
  const double r = to_device.a * to_device.c + to_device.b * to_device.d;
  const double sigma = std::sqrt((p + q + std::sqrt((p - q) * (p - q) + 4 * r * r)) / 2);
  if (!(sigma > 0) || !std::isfinite(sigma)) return {};
  const double tol = std::max(tolerance_px, 1e-6) / sigma;

  const auto pattern = dash_pattern(style.dashes);
  const bool dashed = pattern && !pattern->empty();
  Stroker s(style, tol);
  for (const Subpath& sp : subpaths(path)) {
    if (!dashed) {
      if (sp.zero_length)
        s.dot_caps(sp.start, Vec2{1, 0});
      else
        s.contour(sp.curves, sp.closed);
      continue;
    }
    for_each_dash(
        sp, *pattern, style.dash_offset, [&](const std::vector<Curve>& cs, bool closed) { s.contour(cs, closed); },
        [&](Vec2 pt, Vec2 dir) { s.dot_caps(pt, dir); });
  }
  return s.take();
}

Hairline hairline(double width, const Affine& to_device, double min_device_width) {
  const double scale = std::sqrt(std::fabs(to_device.det()));
  if (!(scale > 0) || !std::isfinite(scale) || !(min_device_width > 0)) return {width, 1};
  const double min_user = min_device_width / scale;
  if (!(width > 0)) return {min_user, 1};
  if (width >= min_user) return {width, 1};
  return {min_user, width / min_user};
}

Path transformed(const Path& path, const Affine& m) {
  Path out;
  const auto& pts = path.points();
  for (const Path::Contour& c : path.contours()) {
    out.move_to(m.apply(pts[c.start_point]));
    for (uint32_t k = 0; k < c.segment_count; k++) {
      const Path::Segment& s = path.segments()[c.first_segment + k];
      const Vec2* p = &pts[s.first_point];
      switch (s.type) {
        case SegmentType::Line: out.line_to(m.apply(p[1])); break;
        case SegmentType::Quad: out.quad_to(m.apply(p[1]), m.apply(p[2])); break;
        case SegmentType::RQuad: out.rquad_to(m.apply(p[1]), m.apply(p[2]), path.weights()[s.first_weight]); break;
        case SegmentType::Cubic: out.cubic_to(m.apply(p[1]), m.apply(p[2]), m.apply(p[3])); break;
        case SegmentType::RCubic: {
          const double* w = &path.weights()[s.first_weight];
          out.rcubic_to(m.apply(p[1]), m.apply(p[2]), m.apply(p[3]), w[0], w[1], w[2], w[3]);
          break;
        }
      }
    }
    if (c.closed) out.close();
  }
  return out;
}

}  // namespace mpvg::stroke
