// Paints evaluated per sample (core/paint/gradient.h, core/paint/texture.h,
// core/sampling/sampling.h) against references written from the definitions in
// double precision, independently of the encoder's normalisation:
//   - gradients: t from the geometry (the two-point conical gradient by
//     solving for every circle through the point, the sweep gradient by
//     the angle around its centre), spread, ramp with exact colour-space
//     conversions, for random parameters, every focal configuration, and
//     sweeps of any angles (backwards, past 360, negative, equal) through
//     the CPU renderer's sampler over a grid;
//   - textures: nearest, bilinear and Mitchell bicubic sums over texels for
//     every wrap mode, and minification of a checkerboard;
//   - patterns: a pattern rendered through its tile tree against the same
//     content tiled explicitly as clipped geometry, nested patterns too.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>

#include "cpu/cpu_stages.h"
#include "frame/encoding.h"
#include "core/error.h"
#include "core/sampling/integration.h"
#include "frame/frame.h"
#include "core/sampling/sampling.h"
#include "tests/catch.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"
#include "frame/scene_info.h"

using namespace mpvg;

namespace {

// ------------------------------------------------------------ references

struct C4 {
  double r, g, b, a;
};

double ref_srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double ref_linear_to_srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055; }

Vec2 apply_inverse(const Affine& m, Vec2 p) { return m.inverted().apply(p); }

// t of every circle of the two-point conical gradient through q, the
// largest valid one (radius >= 0, extension flags), or nothing. Solved in
// long double from |q - f - t (c - f)| = fr + t (r - fr).
std::optional<double> ref_radial_t(const Gradient& g, Vec2 q) {
  const long double cdx = g.center.x - g.focal.x, cdy = g.center.y - g.focal.y;
  const long double dr = g.radius - g.focal_radius, r0 = g.focal_radius;
  const long double px = q.x - g.focal.x, py = q.y - g.focal.y;
  const long double s = std::max({std::hypot(double(cdx), double(cdy)), std::fabs(g.focal_radius), std::fabs(g.radius)});
  long double a = cdx * cdx + cdy * cdy - dr * dr;
  const long double b = px * cdx + py * cdy + r0 * dr;
  const long double c = px * px + py * py - r0 * r0;
  // Tangent circles (a within rounding of 0) are the degenerate case, as the
  // encoder decides it (relative 1e-6).
  if (std::fabs(double(a / (s * s))) < 1e-6) a = 0;
  std::vector<long double> roots;
  if (a == 0) {
    if (b != 0) roots.push_back(c / (2 * b));
  } else {
    const long double disc = b * b - a * c;
    if (disc < 0) return std::nullopt;
    roots.push_back((b + std::sqrt(disc)) / a);
    roots.push_back((b - std::sqrt(disc)) / a);
  }
  std::sort(roots.begin(), roots.end(), std::greater<long double>());
  for (long double t : roots) {
    if (r0 + t * dr < 0) continue;
    if (g.spread == Spread::Pad && ((!g.extend_start && t < 0) || (!g.extend_end && t > 1))) continue;
    return double(t);
  }
  return std::nullopt;
}

// Straight colour of the ramp at t (already spread), in the output space.
C4 ref_ramp(const Gradient& g, double t, Gamma gamma) {
  const bool lin = g.interpolation == ColorSpace::LinearRgb;
  auto in = [&](const RGBA& c) {
    C4 r{c.r, c.g, c.b, c.a};
    if (lin) r = C4{ref_srgb_to_linear(r.r), ref_srgb_to_linear(r.g), ref_srgb_to_linear(r.b), r.a};
    return r;
  };
  C4 c;
  const auto& st = g.stops;
  if (t <= st.front().offset) {
    c = in(st.front().color);
  } else if (t >= st.back().offset) {
    c = in(st.back().color);
  } else {
    size_t i = 0;
    while (st[i + 1].offset <= t) i++;
    const double s = (t - st[i].offset) / (st[i + 1].offset - st[i].offset);
    const C4 a = in(st[i].color), b = in(st[i + 1].color);
    c = C4{a.r + s * (b.r - a.r), a.g + s * (b.g - a.g), a.b + s * (b.b - a.b), a.a + s * (b.a - a.a)};
  }
  const bool out_lin = gamma == Gamma::Linear;
  if (lin && !out_lin) c = C4{ref_linear_to_srgb(c.r), ref_linear_to_srgb(c.g), ref_linear_to_srgb(c.b), c.a};
  if (!lin && out_lin) c = C4{ref_srgb_to_linear(c.r), ref_srgb_to_linear(c.g), ref_srgb_to_linear(c.b), c.a};
  return c;
}

// A gradient's premultiplied colour at t: the spread (and a pad
// gradient's extend flags), then the ramp.
C4 ref_spread_color(const Gradient& g, double t, Gamma gamma) {
  switch (g.spread) {
    case Spread::Pad:
      if ((t < 0 && !g.extend_start) || (t > 1 && !g.extend_end)) return C4{0, 0, 0, 0};
      t = std::clamp(t, 0.0, 1.0);
      break;
    case Spread::Repeat: t -= std::floor(t); break;
    case Spread::Reflect: {
      const double m = std::fabs(t) - 2 * std::floor(std::fabs(t) / 2);
      t = m > 1 ? 2 - m : m;
      break;
    }
  }
  const C4 c = ref_ramp(g, t, gamma);
  return C4{c.r * c.a, c.g * c.a, c.b * c.a, c.a};
}

// Premultiplied colour of gradient g at pixel p (view maps scene units to
// pixels).
C4 ref_gradient(const Gradient& g, bool radial, const Affine& view, Vec2 p, Gamma gamma) {
  const Vec2 q = apply_inverse(view * g.xf, p);
  double t;
  if (radial) {
    const auto rt = ref_radial_t(g, q);
    if (!rt) return C4{0, 0, 0, 0};
    t = *rt;
  } else {
    const Vec2 d = g.p1 - g.p0;
    t = dot(q - g.p0, d) / dot(d, d);
  }
  return ref_spread_color(g, t, gamma);
}

double max_diff(const C4& a, const Rgba4& b) {
  return std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b), std::fabs(a.a - b.a)});
}
double max_diff(const C4& a, const C4& b) {
  return std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b), std::fabs(a.a - b.a)});
}

// ------------------------------------------------------------ scenes

Path rect(double x, double y, double w, double h) {
  Path p;
  p.move_to({x, y});
  p.line_to({x + w, y});
  p.line_to({x + w, y + h});
  p.line_to({x, y + h});
  p.close();
  return p;
}

// A scene of one rectangle covering [0, size)^2 filled with paint p.
Scene one_rect(double size, Paint p, const std::vector<Gradient>& gradients = {},
               const std::vector<Texture>& textures = {}, const std::vector<Pattern>& patterns = {}) {
  SceneBuilder b(size, size);
  for (const Gradient& g : gradients) b.add_gradient(g);
  for (const Texture& t : textures) b.add_texture(t);
  for (const Pattern& pt : patterns) b.add_pattern(pt);
  b.fill(b.add_geometry(rect(-1, -1, size + 2, size + 2)), Affine{}, FillRule::NonZero, p);
  return b.finish();
}

// The premultiplied colour of paint 0 of an encoded scene at (px, py),
// evaluated as the sampler does.
struct Evaluator {
  EncodedScene enc;
  std::vector<TreeView> tiles;
  PaintTables tables;
  explicit Evaluator(EncodedScene e) : enc(std::move(e)) { tables = enc.paint->view(tiles.data()); }
  Rgba4 at(float px, float py) const { return paint_at(tables, 0, px, py); }
};

RGBA random_color(std::mt19937& rng, bool opaque) {
  std::uniform_real_distribution<float> u(0, 1);
  return RGBA{u(rng), u(rng), u(rng), opaque ? 1.0f : u(rng)};
}

std::vector<ColorStop> random_stops(std::mt19937& rng, int n, bool opaque) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<ColorStop> s;
  for (int i = 0; i < n; i++) s.push_back({u(rng), random_color(rng, opaque)});
  std::sort(s.begin(), s.end(), [](const ColorStop& a, const ColorStop& b) { return a.offset < b.offset; });
  if (n > 2) s[1].offset = s[2].offset;  // a hard step
  return s;
}

Affine random_affine(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  return Affine::translate(50 + 20 * u(rng), 50 + 20 * u(rng)) * Affine::rotate_degrees(180 * u(rng)) *
         Affine::scale(1 + 0.5 * u(rng), 1 + 0.5 * u(rng)) * Affine::skew_x_degrees(20 * u(rng));
}

// Compares a gradient's evaluation with the reference at random pixels,
// skipping points within 0.02 px of a discontinuity of the reference (the
// edge of a cone, a repeat's seam, a hard step), where float and double
// may legitimately fall on different sides. Returns the points compared.
int compare_gradient(const Gradient& g, bool radial, const Affine& view, Gamma gamma, std::mt19937& rng,
                     int points) {
  Paint p;
  p.type = radial ? PaintType::RadialGradient : PaintType::LinearGradient;
  p.index = 0;
  const Evaluator ev(encode(one_rect(100, p, {g}), view, gamma));
  std::uniform_real_distribution<double> u(0, 200);
  int compared = 0;
  double worst = 0;
  for (int i = 0; i < points; i++) {
    const Vec2 q{u(rng), u(rng)};
    const C4 ref = ref_gradient(g, radial, view, q, gamma);
    bool edge = false;
    for (Vec2 d : {Vec2{0.02, 0}, Vec2{-0.02, 0}, Vec2{0, 0.02}, Vec2{0, -0.02}})
      edge = edge || max_diff(ref, ref_gradient(g, radial, view, q + d, gamma)) > 0.01;
    if (edge) continue;
    compared++;
    const Rgba4 got = ev.at(float(q.x), float(q.y));
    const double d = max_diff(ref, got);
    worst = std::max(worst, d);
    if (d > 1.0 / 512) {
      INFO("at (" << q.x << ", " << q.y << ") ref " << ref.r << " " << ref.g << " " << ref.b << " " << ref.a << " got "
                  << got.r << " " << got.g << " " << got.b << " " << got.a);
      CHECK(d <= 1.0 / 512);
    }
  }
  INFO("worst difference " << worst);
  CHECK(worst <= 1.0 / 512);
  return compared;
}

}  // namespace

TEST_CASE("linear gradients match the closed form: spreads, colour spaces, extension", "[paint][gradient]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-40, 40);
  int compared = 0, total = 0;
  for (Spread spread : {Spread::Pad, Spread::Reflect, Spread::Repeat})
    for (ColorSpace cs : {ColorSpace::Srgb, ColorSpace::LinearRgb})
      for (Gamma gamma : {Gamma::Srgb, Gamma::Linear})
        for (int k = 0; k < 4; k++) {
          Gradient g;
          g.xf = random_affine(rng);
          g.p0 = {u(rng), u(rng)};
          g.p1 = {u(rng), u(rng)};
          g.stops = random_stops(rng, 1 + k, k % 2 == 0);
          g.spread = spread;
          g.interpolation = cs;
          g.extend_start = k != 1;
          g.extend_end = k != 2;
          const Affine view = Affine::scale(2, 2);
          compared += compare_gradient(g, false, view, gamma, rng, 400);
          total += 400;
        }
  INFO(compared << " of " << total << " points away from discontinuities");
  CHECK(compared > total * 9 / 10);
}

TEST_CASE("radial gradients match the two-point conical closed form in every focal configuration",
          "[paint][gradient]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  enum Config { Inside, OnCircle, Outside, FocalRadius, StartLarger, Cylinder, Concentric, NoExtend };
  int compared = 0, total = 0;
  for (int config = Inside; config <= NoExtend; config++)
    for (Spread spread : {Spread::Pad, Spread::Reflect, Spread::Repeat})
      for (int k = 0; k < 3; k++) {
        INFO("config " << config << " spread " << int(spread) << " case " << k);
        Gradient g;
        g.xf = random_affine(rng);
        g.center = {20 * u(rng) - 10, 20 * u(rng) - 10};
        g.radius = 10 + 30 * u(rng);
        const double ang = 2 * M_PI * u(rng);
        const Vec2 dir{std::cos(ang), std::sin(ang)};
        switch (config) {
          case Inside: g.focal = g.center + (0.8 * g.radius * u(rng)) * dir; break;
          case OnCircle: g.focal = g.center + g.radius * dir; break;
          case Outside: g.focal = g.center + (g.radius * (1.2 + 2 * u(rng))) * dir; break;
          case FocalRadius:
            g.focal = g.center + (0.3 * g.radius * u(rng)) * dir;
            g.focal_radius = 0.5 * g.radius * u(rng);
            break;
          case StartLarger:
            g.focal = g.center + (0.5 * g.radius * u(rng)) * dir;
            g.focal_radius = g.radius * (1.2 + u(rng));
            break;
          case Cylinder:
            g.focal = g.center + (2 * g.radius * u(rng)) * dir;
            g.focal_radius = g.radius;
            break;
          case Concentric:
            g.focal = g.center;
            g.focal_radius = 0.3 * g.radius;
            break;
          case NoExtend:
            g.focal = g.center + (2 * g.radius * u(rng)) * dir;
            g.focal_radius = 0.4 * g.radius;
            g.extend_start = k != 0;
            g.extend_end = k == 0;
            break;
        }
        g.stops = random_stops(rng, 2 + k, k != 1);
        g.spread = spread;
        g.interpolation = k == 2 ? ColorSpace::LinearRgb : ColorSpace::Srgb;
        compared += compare_gradient(g, true, Affine::scale(2, 2), k == 1 ? Gamma::Linear : Gamma::Srgb, rng, 400);
        total += 400;
      }
  INFO(compared << " of " << total << " points away from discontinuities");
  CHECK(compared > total * 8 / 10);
}

namespace {

// ------------------------------------------------------------ sweep gradients

// The sweep gradient straight from its definition (core/scene.h, Gradient),
// in double: the angle of the point in gradient space around the centre,
// from +x towards +y in [0, 360) (0 at the centre), t by the angles, the
// spread, then the ramp. Premultiplied; nothing painted is transparent.
C4 ref_sweep(const Gradient& g, const Affine& view, Vec2 p, Gamma gamma) {
  const Vec2 q = apply_inverse(view * g.xf, p);
  const double dx = q.x - g.center.x, dy = q.y - g.center.y;
  double theta = dx == 0 && dy == 0 ? 0 : std::atan2(dy, dx) * (180 / M_PI);
  if (theta < 0) theta += 360;
  const double span = g.end_angle - g.start_angle;
  double t;
  if (span == 0) {
    if (g.spread != Spread::Pad) return C4{0, 0, 0, 0};
    t = theta < g.start_angle ? -INFINITY : INFINITY;  // the step: first stop before, last from it on
  } else {
    t = (theta - g.start_angle) / span;
  }
  return ref_spread_color(g, t, gamma);
}

struct SweepResult {
  int compared = 0, skipped = 0;
  double worst = 0;
};

// The CPU renderer's samples (its tree and sampler) of a square filled with
// sweep gradient g, against the reference on a grid of 100 x 100 points of
// a 200 x 200 pixel image. Points where the reference jumps by more than
// 0.01 within 0.02 px (the seam where the angle wraps, the ends of a pad
// range, repeat seams, hard steps, the centre), and points within 0.05 px
// of the centre (where float positions leave the angle undecided), are
// skipped.
SweepResult compare_sweep(const Gradient& g, const Affine& view, Gamma gamma, double tolerance) {
  Paint p;
  p.type = PaintType::SweepGradient;
  const Scene scene = one_rect(100, p, {g});
  const EncodedScene enc = encode(scene, view, gamma);
  TreeParams tp;
  tp.min_segments = 4;
  const ShortcutTree tree = build_tree_cpu(enc, 200, 200, tp);
  const Vec2 centre = (view * g.xf).apply(g.center);
  SweepResult r;
  for (int j = 0; j < 100; j++)
    for (int i = 0; i < 100; i++) {
      const Vec2 q{2 * i + 0.37, 2 * j + 1.61};
      const C4 ref = ref_sweep(g, view, q, gamma);
      bool edge = std::hypot(q.x - centre.x, q.y - centre.y) < 0.05;
      for (Vec2 d : {Vec2{0.02, 0}, Vec2{-0.02, 0}, Vec2{0, 0.02}, Vec2{0, -0.02}})
        edge = edge || max_diff(ref, ref_sweep(g, view, q + d, gamma)) > 0.01;
      if (edge) {
        r.skipped++;
        continue;
      }
      const Rgba4 got = sample_tree_cpu(tree, float(q.x), float(q.y));
      const double d = max_diff(ref, got);
      r.worst = std::max(r.worst, d);
      r.compared++;
      if (d > tolerance) {
        INFO("at (" << q.x << ", " << q.y << ") ref " << ref.r << " " << ref.g << " " << ref.b << " " << ref.a
                    << " got " << got.r << " " << got.g << " " << got.b << " " << got.a);
        CHECK(d <= tolerance);
      }
    }
  return r;
}

}  // namespace

TEST_CASE("sweep gradients match their definition: angles, spreads, extension, transforms, hard stops",
          "[paint][gradient][sweep]") {
  // Float angles (atan2f, about 4e-5 degrees) over spans of 20 degrees or
  // more move t by less than 1e-5; the ramp's knots are within 1/4096.
  constexpr double kTolerance = 1.0 / 1024;
  struct Angles {
    double start, end;
  };
  const Angles angles[] = {
      {0, 360},      // the full turn
      {90, 180},     // a quarter: pad extends both ways
      {270, 45},     // start > end: runs backwards
      {-90, 630},    // negative start, a span of two turns: t only in [0.125, 0.625)
      {-720, -700},  // far negative, narrow: t from 36 to 54, wrapped by repeat and reflect
      {400, 380},    // backwards past 360: every angle lies before the start (t > 1)
      {30, 30},      // equal: a pad step, nothing for repeat and reflect
  };
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  const std::vector<ColorStop> hard = {{0, RGBA{1, 0, 0, 1}},   {0.5, RGBA{1, 1, 0, 1}},
                                       {0.5, RGBA{0, 0, 1, 0.5f}}, {0.75, RGBA{0, 1, 0, 1}},
                                       {0.75, RGBA{1, 0, 1, 1}}, {1, RGBA{0, 1, 1, 0.2f}}};
  int compared = 0, total = 0, configs = 0;
  double worst = 0;
  for (int c = 0; c < 4; c++)  // where the centre lies, and how gradient space maps
    for (const Angles& a : angles)
      for (Spread spread : {Spread::Pad, Spread::Reflect, Spread::Repeat})
        for (int k = 0; k < 3; k++) {
          Gradient g;
          switch (c) {
            case 0: g.center = {50.3, 41.7}; break;  // inside, identity
            case 1:                                  // inside, skewed and scaled unevenly
              g.center = {10, 20};
              g.xf = Affine::translate(30, 55) * Affine::skew_x_degrees(25) * Affine::scale(1.5, 0.7);
              break;
            case 2:  // y flipped (a y-up space: counter-clockwise on screen)
              g.center = {-20.5, 30.25};
              g.xf = Affine::translate(80, 100) * Affine::scale(1, -1);
              break;
            case 3:  // outside the square, rotated and mirrored
              g.center = {0, 0};
              g.xf = Affine::translate(-15, 120) * Affine::rotate_degrees(33) * Affine::scale(-1.2, 0.9);
              break;
          }
          g.start_angle = a.start;
          g.end_angle = a.end;
          g.spread = spread;
          g.stops = k == 0 ? hard : random_stops(rng, 2 + k, k == 1);
          g.interpolation = k == 2 ? ColorSpace::LinearRgb : ColorSpace::Srgb;
          // Pad: every combination of the extend flags over the cases.
          g.extend_start = spread != Spread::Pad || (c + k) % 3 != 1;
          g.extend_end = spread != Spread::Pad || (c + k) % 4 != 2;
          const Gamma gamma = k == 1 ? Gamma::Linear : Gamma::Srgb;
          INFO("centre case " << c << " angles " << a.start << " " << a.end << " spread " << int(spread) << " stops "
                              << k);
          const SweepResult r = compare_sweep(g, Affine::scale(2, 2), gamma, kTolerance);
          compared += r.compared;
          total += r.compared + r.skipped;
          worst = std::max(worst, r.worst);
          configs++;
        }
  INFO(compared << " of " << total << " points away from discontinuities over " << configs
                << " gradients; worst difference " << worst);
  CHECK(worst <= kTolerance);
  CHECK(compared > total * 8 / 10);
}

TEST_CASE("sweep gradients by hand: direction, the centre, the step of equal angles", "[paint][gradient][sweep]") {
  Gradient g;
  g.center = {50, 50};
  g.stops = {{0, RGBA{1, 0, 0, 1}}, {1, RGBA{0, 0, 1, 1}}};
  Paint p;
  p.type = PaintType::SweepGradient;
  auto at = [&](const Gradient& gr, float x, float y) {
    const Evaluator ev(encode(one_rect(100, p, {gr}), Affine{}, Gamma::Srgb));
    return ev.at(x, y);
  };
  // From +x towards +y (down on screen): a quarter turn at (50, 60).
  CHECK(at(g, 60, 50.001f).r == Approx(1).margin(1e-4));   // just past 0: red
  CHECK(at(g, 60, 49.999f).b == Approx(1).margin(1e-4));   // just before 360: blue
  const Rgba4 quarter = at(g, 50, 60);
  CHECK(quarter.r == Approx(0.75).margin(1e-5));
  CHECK(quarter.b == Approx(0.25).margin(1e-5));
  CHECK(at(g, 40, 50).r == Approx(0.5).margin(1e-5));
  // The centre itself has angle 0.
  CHECK(at(g, 50, 50).r == 1);
  // Backwards: from 90 down to 0.
  Gradient back = g;
  back.start_angle = 90;
  back.end_angle = 0;
  CHECK(at(back, 50, 60).r == Approx(1).margin(1e-5));
  CHECK(at(back, 60, 50.001f).b == Approx(1).margin(1e-3));
  const Rgba4 mid = at(back, 60, 60);  // 45 degrees
  CHECK(mid.r == Approx(0.5).margin(1e-5));
  // Equal angles with pad: the first stop before 90, the last from 90 on;
  // either side dropped by its extend flag.
  Gradient step = g;
  step.start_angle = step.end_angle = 90;
  CHECK(at(step, 60, 55).r == 1);  // about 27 degrees
  CHECK(at(step, 40, 55).b == 1);  // about 153 degrees
  CHECK(at(step, 40, 45).b == 1);  // about 207 degrees
  step.extend_start = false;
  CHECK(at(step, 60, 55).a == 0);
  CHECK(at(step, 40, 55).b == 1);
  // ... and nothing with repeat or reflect.
  for (Spread sp : {Spread::Repeat, Spread::Reflect}) {
    Gradient none = g;
    none.start_angle = none.end_angle = 90;
    none.spread = sp;
    CHECK(at(none, 60, 55).a == 0);
    CHECK(at(none, 40, 55).a == 0);
  }
  // The y flip in xf makes the sweep counter-clockwise on screen: a quarter
  // turn lands at (50, 40).
  Gradient up = g;
  up.center = {0, 0};
  up.xf = Affine::translate(50, 50) * Affine::scale(1, -1);
  const Rgba4 ccw = at(up, 50, 40);
  CHECK(ccw.r == Approx(0.75).margin(1e-5));
  CHECK(ccw.b == Approx(0.25).margin(1e-5));
}

TEST_CASE("sweep gradients mark paths opaque only where every angle gets an opaque colour", "[paint][gradient][sweep]") {
  auto flags = [](Spread spread, double start, double end, bool ext_start, bool ext_end, float alpha) {
    Gradient g;
    g.center = {30, 60};
    g.start_angle = start;
    g.end_angle = end;
    g.spread = spread;
    g.extend_start = ext_start;
    g.extend_end = ext_end;
    g.stops = {{0, RGBA{1, 0, 0, 1}}, {1, RGBA{0, 0, 1, alpha}}};
    Paint p;
    p.type = PaintType::SweepGradient;
    const EncodedScene e = encode(one_rect(100, p, {g}), Affine{}, Gamma::Srgb);
    return std::make_pair(e.paths[0].flags, e.paint->paints[0].kind);
  };
  auto opaque = [&](Spread spread, double start, double end, bool es, bool ee, float alpha) {
    return (flags(spread, start, end, es, ee, alpha).first & PATH_OPAQUE) != 0;
  };
  CHECK(opaque(Spread::Pad, 0, 360, true, true, 1));
  CHECK(opaque(Spread::Pad, 90, 120, true, true, 1));
  CHECK(opaque(Spread::Pad, 45, 45, true, true, 1));  // the step covers both sides
  CHECK(opaque(Spread::Repeat, 10, 50, false, false, 1));
  CHECK(opaque(Spread::Reflect, 50, 10, true, true, 1));
  CHECK_FALSE(opaque(Spread::Pad, 90, 120, false, true, 1));
  CHECK_FALSE(opaque(Spread::Pad, 90, 120, true, false, 1));
  CHECK_FALSE(opaque(Spread::Pad, 0, 360, true, true, 0.5f));
  // Equal angles with repeat or reflect paint nothing: a transparent solid.
  for (Spread sp : {Spread::Repeat, Spread::Reflect}) {
    const auto [f, kind] = flags(sp, 45, 45, true, true, 1);
    CHECK((f & PATH_OPAQUE) == 0);
    CHECK(kind == PAINT_SOLID);
  }
  CHECK(flags(Spread::Pad, 0, 360, true, true, 1).second == PAINT_SWEEP);
  CHECK((flags(Spread::Pad, 0, 360, true, true, 1).first & PATH_VARYING) != 0);
}

TEST_CASE("sweep gradients in dumps, appended scenes and SceneBuilder's checks", "[paint][gradient][sweep]") {
  Gradient g;
  g.center = {5, 6};
  g.start_angle = 30;
  g.end_angle = -45.5;
  g.spread = Spread::Repeat;
  g.stops = {{0, RGBA{1, 0, 0, 1}}, {1, RGBA{0, 0, 1, 1}}};
  Paint p;
  p.type = PaintType::SweepGradient;
  const Scene s = one_rect(10, p, {g});
  const std::string text = dump(s);
  CHECK(text.find("sweep 0 opacity 1") != std::string::npos);
  CHECK(text.find(" repeat srgb sweep 30 -45.5") != std::string::npos);
  // Default angles add nothing to a gradient's line (dumps of scenes
  // without sweeps stay as they were).
  Gradient plain = g;
  plain.start_angle = 0;
  plain.end_angle = 360;
  const std::string plain_text = dump(one_rect(10, p, {plain}));
  const size_t line = plain_text.find("gradient 0 ");
  REQUIRE(line != std::string::npos);
  CHECK(plain_text.substr(line, plain_text.find('\n', line) - line).find("sweep") == std::string::npos);
  // Appended elsewhere, the paint stays a sweep with its angles, its
  // transform composed.
  SceneBuilder b(20, 20);
  b.append(s, Affine::translate(3, 4));
  const Scene a = b.finish();
  REQUIRE(a.paints.size() == 1);
  CHECK(a.paints[0].type == PaintType::SweepGradient);
  CHECK(a.gradients[0].start_angle == 30);
  CHECK(a.gradients[0].end_angle == -45.5);
  CHECK(a.gradients[0].xf.e == 3);
  // Non-finite angles are refused.
  SceneBuilder bad(10, 10);
  Gradient nan = g;
  nan.end_angle = std::nan("");
  CHECK_THROWS_AS(bad.add_gradient(nan), Error);
}

TEST_CASE("a sweep gradient in a forest frame renders as it does alone", "[paint][gradient][sweep]") {
  // The second scene's gradient records sit after the first's in the
  // merged tables (frame/forest.cpp): its paint's index must follow them.
  Gradient lin;
  lin.p0 = {0, 0};
  lin.p1 = {64, 0};
  lin.stops = {{0, RGBA{0, 1, 0, 1}}, {1, RGBA{1, 1, 0, 1}}};
  Paint pl;
  pl.type = PaintType::LinearGradient;
  Gradient sw;
  sw.center = {30, 35};
  sw.start_angle = 20;
  sw.end_angle = 250;
  sw.spread = Spread::Reflect;
  sw.stops = {{0, RGBA{1, 0, 0, 1}}, {0.5, RGBA{0, 0, 1, 0.5f}}, {1, RGBA{1, 1, 1, 1}}};
  Paint ps;
  ps.type = PaintType::SweepGradient;
  const Scene a = one_rect(64, pl, {lin}), b = one_rect(64, ps, {sw});
  RenderOptions o;
  o.width = o.height = 64;
  o.samples = 8;
  o.backend = Backend::Cpu;
  const RenderPlan plan = plan_render(o);
  const EncodedScene ea = encode_for(a, plan, o.gamma), eb = encode_for(b, plan, o.gamma);
  const std::vector<ImageF> together = render_forest_cpu({{&ea, &plan}, {&eb, &plan}}, o);
  REQUIRE(together.size() == 2);
  CHECK(together[0].rgba == render_cpu(ea, plan, o).rgba);
  CHECK(together[1].rgba == render_cpu(eb, plan, o).rgba);
}

TEST_CASE("degenerate gradients paint nothing, single stops paint one colour", "[paint][gradient]") {
  Gradient g;
  g.stops = {{0.5, RGBA{1, 0, 0, 1}}};
  g.p0 = g.p1 = {10, 10};
  Paint p;
  p.type = PaintType::LinearGradient;
  const Evaluator zero(encode(one_rect(100, p, {g}), Affine{}, Gamma::Srgb));
  CHECK(zero.at(5, 5).a == 0);
  g.p1 = {20, 10};
  const Evaluator one(encode(one_rect(100, p, {g}), Affine{}, Gamma::Srgb));
  for (float x : {0.0f, 15.0f, 99.0f}) {
    const Rgba4 c = one.at(x, 3);
    CHECK(c.r == 1);
    CHECK(c.g == 0);
    CHECK(c.a == 1);
  }
  // Equal circles at one place: no circle reaches anything but the rim.
  g.focal = g.center = {50, 50};
  g.focal_radius = g.radius = 10;
  p.type = PaintType::RadialGradient;
  const Evaluator same(encode(one_rect(100, p, {g}), Affine{}, Gamma::Srgb));
  CHECK(same.at(50, 50).a == 0);
  CHECK(same.at(90, 50).a == 0);
}

TEST_CASE("radial gradients mark paths opaque only when their circles sweep the whole plane", "[paint][gradient]") {
  // Opaque stops; the start circle strictly inside the end circle sweeps
  // everything, internally tangent circles (the focal point on the end
  // circle) only a half plane, which must not occlude what lies beneath.
  auto opaque = [](Vec2 focal, double focal_radius) {
    Gradient g;
    g.stops = {{0, RGBA{1, 0, 0, 1}}, {1, RGBA{0, 0, 1, 1}}};
    g.center = {70, 50};
    g.radius = 40;
    g.focal = focal;
    g.focal_radius = focal_radius;
    Paint p;
    p.type = PaintType::RadialGradient;
    return (encode(one_rect(100, p, {g}), Affine{}, Gamma::Srgb).paths[0].flags & PATH_OPAQUE) != 0;
  };
  CHECK(opaque({70, 50}, 0));
  CHECK(opaque({40, 50}, 0));
  CHECK(opaque({60, 50}, 20));
  CHECK_FALSE(opaque({30, 50}, 0));   // on the end circle
  CHECK_FALSE(opaque({50, 50}, 20));  // tangent from inside, with a focal radius
  CHECK_FALSE(opaque({20, 50}, 0));   // outside
  CHECK_FALSE(opaque({70, 50}, 40));  // equal circles
}

TEST_CASE("ramps: exact knots stay within 1/4096, lookup tables are an option", "[paint][gradient]") {
  // Interpolated in sRGB, integrated in linear light: the encoder adds knots.
  Gradient g;
  g.p0 = {0, 0};
  g.p1 = {1000, 0};
  g.stops = {{0, RGBA{0, 0.2f, 1, 1}}, {0.3, RGBA{1, 1, 0, 0.5f}}, {1, RGBA{0.1f, 0, 0.4f, 1}}};
  Paint p;
  p.type = PaintType::LinearGradient;
  const Scene s = one_rect(1000, p, {g});
  for (int lut : {0, 256, 1024}) {
    INFO("ramp_lut " << lut);
    EncodeOptions o;
    o.ramp_lut = lut;
    const Evaluator ev(encode(s, Affine{}, Gamma::Linear, o));
    double worst = 0;
    for (int x = 0; x < 1000; x++) worst = std::max(worst, max_diff(ref_gradient(g, false, Affine{}, {x + 0.5, 0}, Gamma::Linear), ev.at(x + 0.5f, 0)));
    CHECK(worst <= (lut == 0 ? 1.0 / 4096 + 1e-6 : 1.0 / 255));
    if (lut == 0) CHECK(ev.enc.paint->ramp_t.size() > 3);
    if (lut > 0) CHECK(ev.enc.paint->ramp_t.size() == size_t(lut));
  }
}

TEST_CASE("a full-width 16-bit gradient has no step larger than one 8-bit level", "[paint][gradient]") {
  for (Gamma gamma : {Gamma::Srgb, Gamma::Linear})
    for (int lut : {0, 256}) {
      INFO("gamma " << (gamma == Gamma::Srgb ? "srgb" : "linear") << " ramp_lut " << lut);
      const int W = 2048;
      Gradient g;
      g.p0 = {0, 0};
      g.p1 = {double(W), 0};
      g.stops = {{0, RGBA{0, 0, 0, 1}}, {1, RGBA{1, 1, 1, 1}}};
      Paint p;
      p.type = PaintType::LinearGradient;
      SceneBuilder b(W, 4);
      b.add_gradient(g);
      b.fill(b.add_geometry(rect(-1, -1, W + 2, 6)), Affine{}, FillRule::NonZero, p);
      const Scene s = b.finish();
      // The pipeline itself, as svg2png runs it (encode options through
      // the tree: the lookup table variant is encoded by hand).
      RenderOptions o;
      o.width = W;
      o.height = 4;
      o.gamma = gamma;
      o.samples = 8;
      o.backend = Backend::Cpu;
      const RenderPlan plan = plan_render(o);
      EncodeOptions eo;
      eo.ramp_lut = lut;
      const ShortcutTree tree = build_tree_cpu(encode(s, plan.view, gamma, eo), W, 4, plan.tree);
      const ImageF img = render_tree_cpu(tree, plan.integ, plan.frame, background_paint(RGBA{0, 0, 0, 0}, gamma), 0);
      const std::vector<uint16_t> px = to_rgba16(img, gamma);
      int worst = 0;
      bool monotone = true;
      for (int x = 1; x < W; x++)
        for (int c = 0; c < 3; c++) {
          const int d = int(px[size_t(W + x) * 4 + c]) - int(px[size_t(W + x - 1) * 4 + c]);
          worst = std::max(worst, std::abs(d));
          monotone = monotone && d >= 0;
        }
      INFO("largest step " << worst << " / 65535");
      CHECK(worst <= 257);
      CHECK(monotone);
    }
}

namespace {

// ------------------------------------------------------------ textures

std::shared_ptr<Image> random_image(std::mt19937& rng, int w, int h) {
  auto im = std::make_shared<Image>();
  im->width = w;
  im->height = h;
  im->rgba8.resize(size_t(w) * h * 4);
  std::uniform_int_distribution<int> u(0, 255);
  for (size_t i = 0; i < im->rgba8.size(); i++) im->rgba8[i] = static_cast<uint8_t>(u(rng));
  return im;
}

// Premultiplied texel (i, j) in the output space, or transparent outside a
// decal texture.
C4 ref_texel(const Image& im, int i, int j, TextureWrap wx, TextureWrap wy, Gamma gamma) {
  auto wrap = [](int k, int n, TextureWrap m) {
    if (m == TextureWrap::Repeat) return ((k % n) + n) % n;
    if (m == TextureWrap::Decal) return (k < 0 || k >= n) ? -1 : k;
    return std::clamp(k, 0, n - 1);
  };
  const int x = wrap(i, im.width, wx), y = wrap(j, im.height, wy);
  if (x < 0 || y < 0) return C4{0, 0, 0, 0};
  const uint8_t* p = &im.rgba8[(size_t(y) * im.width + x) * 4];
  auto ch = [&](int k) {
    const double v = p[k] / 255.0;
    return gamma == Gamma::Linear ? ref_srgb_to_linear(v) : v;
  };
  const double a = p[3] / 255.0;
  return C4{ch(0) * a, ch(1) * a, ch(2) * a, a};
}

// The texture's reconstruction at texel-space point (u, v) as a sum of
// texels times a separable kernel centred on the texel centres.
C4 ref_texture(const Texture& t, Vec2 q, Gamma gamma) {
  const Image& im = *t.image;
  if (t.filter == TextureFilter::Nearest)
    return ref_texel(im, int(std::floor(q.x)), int(std::floor(q.y)), t.wrap_x, t.wrap_y, gamma);
  const int support = t.filter == TextureFilter::Bilinear ? 1 : 2;
  auto kernel = [&](double d) {
    return t.filter == TextureFilter::Bilinear ? std::max(0.0, 1 - std::fabs(d))
                                               : double(filter_kernel(Filter::Mitchell, float(d)));
  };
  C4 acc{0, 0, 0, 0};
  const int i0 = int(std::floor(q.x - 0.5)), j0 = int(std::floor(q.y - 0.5));
  for (int j = j0 - support + 1; j <= j0 + support; j++)
    for (int i = i0 - support + 1; i <= i0 + support; i++) {
      const double w = kernel(q.x - (i + 0.5)) * kernel(q.y - (j + 0.5));
      const C4 c = ref_texel(im, i, j, t.wrap_x, t.wrap_y, gamma);
      acc = C4{acc.r + w * c.r, acc.g + w * c.g, acc.b + w * c.b, acc.a + w * c.a};
    }
  acc.a = std::clamp(acc.a, 0.0, 1.0);
  acc.r = std::clamp(acc.r, 0.0, acc.a);
  acc.g = std::clamp(acc.g, 0.0, acc.a);
  acc.b = std::clamp(acc.b, 0.0, acc.a);
  return acc;
}

}  // namespace

TEST_CASE("texture lookups match direct sums over texels: filters and wrap modes", "[paint][texture]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 100);
  for (TextureFilter f : {TextureFilter::Nearest, TextureFilter::Bilinear, TextureFilter::Bicubic})
    for (TextureWrap w : {TextureWrap::Clamp, TextureWrap::Repeat, TextureWrap::Decal})
      for (Gamma gamma : {Gamma::Srgb, Gamma::Linear}) {
        INFO("filter " << int(f) << " wrap " << int(w) << " gamma " << int(gamma));
        Texture t;
        t.image = random_image(rng, 7, 5);
        // Magnified about 6x, rotated: no minification.
        t.xf = Affine::translate(30, 20) * Affine::rotate_degrees(17) * Affine::scale(6, 5.5);
        t.filter = f;
        t.wrap_x = w;
        t.wrap_y = w == TextureWrap::Repeat ? TextureWrap::Clamp : w;
        Paint p;
        p.type = PaintType::Texture;
        const Evaluator ev(encode(one_rect(100, p, {}, {t}), Affine{}, gamma));
        double worst = 0;
        for (int i = 0; i < 2000; i++) {
          const Vec2 q{u(rng), u(rng)};
          const Vec2 tq = apply_inverse(t.xf, q);
          // Nearest lookups jump at texel edges: keep away from them.
          if (f == TextureFilter::Nearest &&
              (std::fabs(tq.x - std::round(tq.x)) < 1e-3 || std::fabs(tq.y - std::round(tq.y)) < 1e-3))
            continue;
          worst = std::max(worst, max_diff(ref_texture(t, tq, gamma), ev.at(float(q.x), float(q.y))));
        }
        // Texels are stored at 16 bits; float arithmetic on top.
        CHECK(worst <= 1.0 / 2048);
      }
}

TEST_CASE("texture tint and opacity multiply the texels; opaque images mark their paths opaque", "[paint][texture]") {
  auto im = std::make_shared<Image>();
  im->width = im->height = 2;
  im->rgba8 = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  Texture t;
  t.image = im;
  t.xf = Affine::scale(50, 50);
  t.filter = TextureFilter::Nearest;
  Paint p;
  p.type = PaintType::Texture;
  const EncodedScene opaque = encode(one_rect(100, p, {}, {t}), Affine{}, Gamma::Srgb);
  CHECK((opaque.paths[0].flags & PATH_OPAQUE) != 0);
  CHECK((opaque.paths[0].flags & PATH_VARYING) != 0);
  t.tint = RGBA{1, 0.5f, 1, 1};
  p.opacity = 0.5f;
  const Evaluator ev(encode(one_rect(100, p, {}, {t}), Affine{}, Gamma::Srgb));
  CHECK((ev.enc.paths[0].flags & PATH_OPAQUE) == 0);
  const Rgba4 white = ev.at(75, 75);
  CHECK(white.r == Approx(0.5f));
  CHECK(white.g == Approx(0.25f));
  CHECK(white.a == Approx(0.5f));
  t.wrap_x = TextureWrap::Decal;
  p.opacity = 1;
  t.tint = RGBA{1, 1, 1, 1};
  CHECK((encode(one_rect(100, p, {}, {t}), Affine{}, Gamma::Srgb).paths[0].flags & PATH_OPAQUE) == 0);
}

TEST_CASE("a minified checkerboard comes out grey, without moire", "[paint][texture]") {
  // 512 x 512 texels of alternating black and white, shown 8 times smaller
  // and rotated: 8 texels per pixel, far above what 32 samples resolve.
  auto im = std::make_shared<Image>();
  im->width = im->height = 512;
  im->rgba8.resize(512 * 512 * 4);
  for (int y = 0; y < 512; y++)
    for (int x = 0; x < 512; x++) {
      const uint8_t v = ((x + y) & 1) ? 255 : 0;
      uint8_t* q = &im->rgba8[(size_t(y) * 512 + x) * 4];
      q[0] = q[1] = q[2] = v;
      q[3] = 255;
    }
  for (Gamma gamma : {Gamma::Srgb, Gamma::Linear})
    for (double angle : {0.0, 23.0}) {
      INFO("gamma " << int(gamma) << " angle " << angle);
      Texture t;
      t.image = im;
      t.wrap_x = t.wrap_y = TextureWrap::Repeat;
      t.xf = Affine::rotate_degrees(angle) * Affine::scale(1.0 / 8, 1.0 / 8);
      Paint p;
      p.type = PaintType::Texture;
      RenderOptions o;
      o.width = o.height = 48;
      o.gamma = gamma;
      o.backend = Backend::Cpu;
      const ImageF img = render_cpu(one_rect(48, p, {}, {t}), o);
      const std::vector<uint8_t> px = to_rgba8(img, gamma);
      // Half the light in linear light is 188 in sRGB; half the sRGB value
      // is 128 when integration happens on sRGB values.
      const int grey = gamma == Gamma::Linear ? 188 : 128;
      int worst = 0;
      for (size_t i = 0; i < px.size(); i += 4) worst = std::max(worst, std::abs(int(px[i]) - grey));
      INFO("largest deviation from grey " << worst << " / 255");
      CHECK(worst <= 4);
      // Without mip levels the same render aliases: the test can fail.
      const RenderPlan plan = plan_render(o);
      EncodedScene enc = encode(one_rect(48, p, {}, {t}), plan.view, gamma);
      auto pd = std::make_shared<PaintData>(*enc.paint);
      pd->textures[0].lod_level = 0;
      pd->textures[0].lod_frac = 0;
      enc.paint = pd;
      const ImageF aliased = render_tree_cpu(build_tree_cpu(enc, 48, 48, plan.tree), plan.integ, plan.frame,
                                             background_paint(RGBA{0, 0, 0, 0}, gamma), 0);
      const std::vector<uint8_t> ap = to_rgba8(aliased, gamma);
      int aliased_worst = 0;
      for (size_t i = 0; i < ap.size(); i += 4) aliased_worst = std::max(aliased_worst, std::abs(int(ap[i]) - grey));
      INFO("without mip levels " << aliased_worst);
      CHECK(aliased_worst > 4 * worst);
    }
}

namespace {

// ------------------------------------------------------------ patterns

Path ellipse(double cx, double cy, double rx, double ry) {
  Path p;
  const double w = std::sqrt(0.5);
  p.move_to({cx + rx, cy});
  p.rquad_to({cx + rx, cy + ry}, {cx, cy + ry}, w);
  p.rquad_to({cx - rx, cy + ry}, {cx - rx, cy}, w);
  p.rquad_to({cx - rx, cy - ry}, {cx, cy - ry}, w);
  p.rquad_to({cx + rx, cy - ry}, {cx + rx, cy}, w);
  p.close();
  return p;
}

Paint solid(float r, float g, float b, float a = 1) {
  Paint p;
  p.color = RGBA{r, g, b, a};
  return p;
}

// A 20 x 15 tile: a circle crossing the tile's right edge, a translucent
// triangle, and optionally a rectangle painted with `inner`.
std::shared_ptr<Scene> tile_scene(const Pattern* inner) {
  SceneBuilder b(20, 15);
  b.fill(b.add_geometry(ellipse(17, 7, 6, 5)), Affine{}, FillRule::NonZero, solid(0.9f, 0.2f, 0.1f));
  Path tri;
  tri.move_to({2, 2});
  tri.line_to({12, 4});
  tri.cubic_to({8, 8}, {6, 16}, {3, 13});
  tri.close();
  b.fill(b.add_geometry(tri), Affine{}, FillRule::NonZero, solid(0.1f, 0.3f, 0.9f, 0.7f));
  if (inner) {
    Paint p;
    p.type = PaintType::Pattern;
    p.index = b.add_pattern(*inner);
    b.fill(b.add_geometry(rect(4, 6, 9, 7)), Affine{}, FillRule::EvenOdd, p);
  }
  return std::make_shared<Scene>(b.finish());
}

// Adds the content of `scene` mapped by `xf` to b, in painter's order, with
// every pattern fill expanded into copies of its tile, each clipped to its
// cell and to the path it fills, over the cells that reach [0, size)^2.
void add_explicit(SceneBuilder& b, const Scene& scene, const Affine& xf, double size) {
  for (auto it = scene.stream.rbegin(); it != scene.stream.rend(); ++it) {
    const ScenePath& sp = scene.paths[it->path];
    const uint32_t geom = b.add_geometry(scene.geometries[sp.geometry]);
    const Paint& paint = scene.paints[sp.paint];
    if (paint.type != PaintType::Pattern) {
      b.fill(geom, xf * sp.xf, sp.rule, paint);
      continue;
    }
    const Pattern& pat = scene.patterns[paint.index];
    const Scene& tile = *pat.tile;
    const Affine to_out = xf * pat.xf;
    const Affine inv = to_out.inverted();
    double i0 = 1e9, i1 = -1e9, j0 = 1e9, j1 = -1e9;
    for (Vec2 c : {Vec2{0, 0}, Vec2{size, 0}, Vec2{0, size}, Vec2{size, size}}) {
      const Vec2 q = inv.apply(c);
      i0 = std::min(i0, std::floor(q.x / tile.width));
      i1 = std::max(i1, std::floor(q.x / tile.width));
      j0 = std::min(j0, std::floor(q.y / tile.height));
      j1 = std::max(j1, std::floor(q.y / tile.height));
    }
    b.push();
    b.clip(geom, xf * sp.xf, sp.rule);
    b.activate();
    const uint32_t cell = b.add_geometry(rect(0, 0, tile.width, tile.height));
    for (double j = j0; j <= j1; j++)
      for (double i = i0; i <= i1; i++) {
        const Affine at = to_out * Affine::translate(i * tile.width, j * tile.height);
        b.push();
        b.clip(cell, at, FillRule::NonZero);
        b.activate();
        add_explicit(b, tile, at, size);
        b.pop();
      }
    b.pop();
  }
}

ImageF render_box(const Scene& s, int size) {
  RenderOptions o;
  o.width = o.height = size;
  o.backend = Backend::Cpu;
  o.samples = 32;
  return render_cpu(s, o);
}

}  // namespace

TEST_CASE("a pattern through its tile tree equals its content tiled as clipped geometry", "[paint][pattern]") {
  const Pattern inner{tile_scene(nullptr), Affine::translate(1, 2) * Affine::rotate_degrees(-30) * Affine::scale(0.35, 0.35)};
  for (int nested = 0; nested < 2; nested++) {
    INFO((nested ? "pattern of pattern" : "one pattern"));
    const Pattern outer{tile_scene(nested ? &inner : nullptr),
                        Affine::translate(3, 4) * Affine::rotate_degrees(20) * Affine::scale(1.7, 1.3)};
    // The pattern fills a disc over the image.
    SceneBuilder b(96, 96);
    b.fill(b.add_geometry(rect(0, 0, 96, 96)), Affine{}, FillRule::NonZero, solid(1, 1, 0.8f));
    Paint p;
    p.type = PaintType::Pattern;
    p.index = b.add_pattern(outer);
    b.fill(b.add_geometry(ellipse(48, 48, 45, 40)), Affine{}, FillRule::NonZero, p);
    const Scene with_pattern = b.finish();
    SceneBuilder e(96, 96);
    add_explicit(e, with_pattern, Affine{}, 96);
    const Scene explicit_scene = e.finish();

    const ImageF a = render_box(with_pattern, 96), x = render_box(explicit_scene, 96);
    // Same samples, same geometry: only float rounding of positions mapped
    // into the tile can move a sample across an edge (1/32 of a pixel).
    int off = 0;
    double worst = 0;
    for (size_t i = 0; i < a.rgba.size(); i++) {
      const double d = std::fabs(a.rgba[i] - x.rgba[i]);
      worst = std::max(worst, d);
      if (d > 1.0 / 255) off++;
    }
    INFO("channels off by more than 1/255: " << off << ", largest difference " << worst);
    CHECK(off <= 4);
    CHECK(worst <= 1.5 / 32);
    if (nested) {
      const EncodedScene enc = encode(with_pattern, Affine{}, Gamma::Srgb);
      CHECK(enc.tiles.size() == 2);
    }
  }
}

TEST_CASE("a tile is encoded once per scale it is drawn at, however many paints use it", "[paint][pattern]") {
  const std::shared_ptr<Scene> tile = tile_scene(nullptr);
  SceneBuilder b(96, 96);
  b.fill(b.add_geometry(rect(0, 0, 96, 96)), Affine{}, FillRule::NonZero, solid(1, 1, 0.8f));
  // Three patterns differing only by translation share a tile; a fourth at
  // another scale needs its own.
  const Affine base = Affine::rotate_degrees(15) * Affine::scale(1.5, 1.5);
  const Affine placements[] = {base, Affine::translate(3.25, 1) * base, Affine::translate(-7, 2.5) * base,
                               Affine::scale(0.5, 0.5) * base};
  for (int i = 0; i < 4; i++) {
    Paint p;
    p.type = PaintType::Pattern;
    p.index = b.add_pattern(Pattern{tile, placements[i]});
    b.fill(b.add_geometry(rect(24 * i, 0, 24 * i + 20, 96)), Affine{}, FillRule::NonZero, p);
  }
  const Scene with_patterns = b.finish();
  CHECK(encode(with_patterns, Affine{}, Gamma::Srgb).tiles.size() == 2);
  CHECK(encode(with_patterns, Affine::scale(2, 2), Gamma::Srgb).tiles.size() == 2);
  // Each use still samples its tile at its own placement.
  SceneBuilder e(96, 96);
  add_explicit(e, with_patterns, Affine{}, 96);
  const ImageF a = render_box(with_patterns, 96), x = render_box(e.finish(), 96);
  int off = 0;
  for (size_t i = 0; i < a.rgba.size(); i++) off += std::fabs(a.rgba[i] - x.rgba[i]) > 1.0 / 255;
  INFO("channels off by more than 1/255: " << off);
  CHECK(off <= 4);
}

TEST_CASE("patterns nested deeper than the limit are an error", "[paint][pattern]") {
  std::shared_ptr<Scene> tile = tile_scene(nullptr);
  for (int depth = 1; depth <= kMaxPatternDepth + 1; depth++) {
    const Pattern p{tile, Affine::scale(0.5, 0.5)};
    tile = tile_scene(&p);
    const Scene s = one_rect(50, Paint{PaintType::Pattern, RGBA{}, 1, 0}, {}, {}, {Pattern{tile, Affine{}}});
    // The scene holds depth + 1 nested tiles.
    if (depth + 1 <= kMaxPatternDepth) {
      CHECK_NOTHROW(encode(s, Affine{}, Gamma::Srgb));
    } else {
      try {
        encode(s, Affine{}, Gamma::Srgb);
        FAIL("no error");
      } catch (const Error& e) {
        CHECK(std::string(e.what()) == "patterns nested more than 4 deep");
      }
    }
  }
}

TEST_CASE("tile grids follow the tile's size on screen, within bounds", "[paint][pattern]") {
  const std::shared_ptr<Scene> tile = tile_scene(nullptr);
  auto grid_of = [&](const Affine& xf, const Affine& view) {
    const EncodedScene enc =
        encode(one_rect(100, Paint{PaintType::Pattern, RGBA{}, 1, 0}, {}, {}, {Pattern{tile, xf}}), view, Gamma::Srgb);
    return std::make_pair(enc.tiles.at(0).width, enc.tiles.at(0).height);
  };
  CHECK(grid_of(Affine::scale(2, 3), Affine{}) == std::make_pair(40, 45));
  CHECK(grid_of(Affine::scale(2, 3), Affine::scale(0.5, 0.5)) == std::make_pair(20, 23));
  CHECK(grid_of(Affine::scale(0.01, 0.01), Affine{}) == std::make_pair(kMinTileGrid, kMinTileGrid));
  CHECK(grid_of(Affine::scale(1000, 1000), Affine{}) == std::make_pair(kMaxTileGrid, kMaxTileGrid));
}
