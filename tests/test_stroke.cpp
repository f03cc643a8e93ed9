// Stage "stroke" (stroker/stroke.h) on the CPU executor, as a whole: its
// output is closed contours of finite segments for random centrelines under
// every join, cap, miter limit and dash pattern; degenerate subpaths give
// the dots and squares they should (rendered at 1x32 box against the shapes
// drawn as fills); outputs come grouped by stroke and do not depend on the
// number of threads; stroked scene elements render as their outlines
// filled. The brute-force oracles of the stroke's shape (distance to the
// centreline, SVG 2's convex pieces, dashes against arc length) are in
// test_stroker.cpp; until the stage replaced it, the previous stroker was
// held to the same coverage here.
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "frame/frame.h"
#include "stroker/stroke_input.h"
#include "tests/catch.h"
#include "tests/random_paths.h"
#include "tests/stroke_coverage.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"

using namespace mpvg;
using namespace mpvg::test;

namespace {

std::vector<InputSegment> stroke_of(const Path& path, const StrokeStyle& style, const Affine& xf) {
  StrokeBatch batch;
  batch.add(path, style, xf, 0);
  return stroke_cpu(batch, 1);
}

Vec2 start_of(const InputSegment& s) { return {s.x[0], s.y[0]}; }
Vec2 end_of(const InputSegment& s) {
  const int k = s.type == INPUT_LINE ? 1 : (s.type == INPUT_CUBIC ? 3 : 2);
  return {s.x[k], s.y[k]};
}

// The stage's segments chained into contours by their end points, which
// meet exactly, as a Path. Segments that form closed loops can always be
// chained into closed contours (from any start, a chain can only get stuck
// back where it began); false when one cannot: the output has a gap.
bool path_of(const std::vector<InputSegment>& segs, Path& out) {
  std::map<std::pair<double, double>, std::vector<size_t>> starting;
  for (size_t i = segs.size(); i-- > 0;) starting[{segs[i].x[0], segs[i].y[0]}].push_back(i);
  std::vector<bool> used(segs.size(), false);
  for (size_t first = 0; first < segs.size(); first++) {
    if (used[first]) continue;
    const Vec2 start = start_of(segs[first]);
    out.move_to(start);
    size_t i = first;
    while (true) {
      const InputSegment& s = segs[i];
      used[i] = true;
      if (s.type == INPUT_LINE) out.line_to({s.x[1], s.y[1]});
      if (s.type == INPUT_QUAD) out.quad_to({s.x[1], s.y[1]}, {s.x[2], s.y[2]});
      if (s.type == INPUT_RQUAD) out.rquad_to({s.x[1], s.y[1]}, {s.x[2], s.y[2]}, s.w);
      if (s.type == INPUT_CUBIC) out.cubic_to({s.x[1], s.y[1]}, {s.x[2], s.y[2]}, {s.x[3], s.y[3]});
      const Vec2 end = end_of(s);
      if (end == start) break;
      std::vector<size_t>& next = starting[{end.x, end.y}];
      while (!next.empty() && used[next.back()]) next.pop_back();
      if (next.empty()) return false;
      i = next.back();
    }
    out.close();
  }
  return true;
}

// What is wrong with an output, if anything: a non-finite coordinate or
// weight, a path id other than 0, a contour that does not close.
std::string defect(const std::vector<InputSegment>& segs) {
  for (const InputSegment& s : segs) {
    if (s.path != 0) return "path id " + std::to_string(s.path);
    if (s.type > INPUT_RQUAD) return "segment type " + std::to_string(s.type);
    if (!std::isfinite(s.w) || !(s.w > 0)) return "weight " + std::to_string(s.w);
    for (int k = 0; k < 3; k++)
      if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k])) return "non-finite coordinate";
  }
  Path p;
  if (!path_of(segs, p)) return "a contour does not close";
  return "";
}

struct Diff {
  int pixels = 0;  // differing by more than 1/255
  float max = 0;   // largest difference
  int worst_x = 0, worst_y = 0;
};

Diff compare(const std::vector<float>& a, const std::vector<float>& b) {
  Diff d;
  for (int i = 0; i < kSize * kSize; i++) {
    const float e = std::fabs(a[i] - b[i]);
    if (e > 1.0f / 255) d.pixels++;
    if (e > d.max) d.max = e, d.worst_x = i % kSize, d.worst_y = i / kSize;
  }
  return d;
}

const char* join_name(LineJoin j) {
  static const char* names[] = {"miter", "miter-clip", "arcs", "round", "bevel"};
  return names[static_cast<int>(j)];
}
const char* cap_name(LineCap c) {
  static const char* names[] = {"butt", "round", "square"};
  return names[static_cast<int>(c)];
}

// Random transforms: scales, rotations and skews that keep the 0..100 box
// of random_path inside the image.
Affine random_view(std::mt19937& rng) {
  std::uniform_int_distribution<int> kind(0, 3);
  std::uniform_real_distribution<double> u(0, 1);
  const Affine fit = Affine::translate(8, 8) * Affine::scale(0.8, 0.8);
  switch (kind(rng)) {
    case 0: return fit;
    case 1: return fit * Affine::translate(50, 50) * Affine::rotate_degrees(360 * u(rng)) * Affine::translate(-50, -50);
    case 2: return Affine::translate(8, 8) * Affine::scale(0.8, 0.4 + 0.4 * u(rng));
    default: return fit * Affine::translate(50, 50) * Affine::skew_x_degrees(40 * u(rng) - 20) *
                    Affine::scale(0.7, 0.7) * Affine::translate(-50, -50);
  }
}

std::string describe(int iter, const StrokeStyle& st) {
  std::string s = "iteration " + std::to_string(iter) + " " + join_name(st.join) + "/" + cap_name(st.cap) +
                  " width " + std::to_string(st.width) + " miter limit " + std::to_string(st.miter_limit);
  if (!st.dashes.empty()) {
    s += " dashes";
    for (double x : st.dashes) s += " " + std::to_string(x);
    s += " offset " + std::to_string(st.dash_offset);
  }
  return s;
}

// Shapes to fill, all wound the same way so that nonzero is their union.
void add_disk(Path& p, Vec2 c, double r) { p.append(circle(c, r)); }
void add_box(Path& p, double x0, double y0, double x1, double y1) { p.append(Path::rectangle(x0, y0, x1, y1)); }

}  // namespace

TEST_CASE("stroke stage: random paths under every join, cap and miter limit give closed contours",
          "[stroke_stage]") {
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<double> width(0.5, 30), limit(0.5, 8);
  for (int iter = 0; iter < 60; iter++) {
    const Path path = random_path(rng, 1 + iter % 3);
    StrokeStyle st;
    st.width = width(rng);
    st.join = static_cast<LineJoin>(iter % 5);
    st.cap = static_cast<LineCap>((iter / 5) % 3);
    st.miter_limit = limit(rng);
    const std::vector<InputSegment> out = stroke_of(path, st, random_view(rng));
    INFO(describe(iter, st));
    CHECK(!out.empty());
    CHECK(defect(out) == "");
  }
}

TEST_CASE("stroke stage: dashes, offsets and closed subpaths give closed contours", "[stroke_stage][dash]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> width(0.5, 12), len(0, 25), off(-60, 60);
  std::uniform_int_distribution<int> count(1, 5);
  for (int iter = 0; iter < 60; iter++) {
    const Path path = random_path(rng, 1 + iter % 3);
    StrokeStyle st;
    st.width = width(rng);
    st.join = static_cast<LineJoin>(iter % 5);
    st.cap = static_cast<LineCap>((iter / 5) % 3);
    st.miter_limit = 4;
    const int n = count(rng);
    for (int k = 0; k < n; k++) st.dashes.push_back(iter % 7 == 3 && k == 0 ? 0.0 : len(rng));
    st.dash_offset = iter % 4 == 0 ? 0 : off(rng);
    const std::vector<InputSegment> out = stroke_of(path, st, random_view(rng));
    INFO(describe(iter, st));
    CHECK(defect(out) == "");
  }
}

TEST_CASE("stroke stage: degenerate subpaths and input", "[stroke_stage][degenerate]") {
  // Dots, squares along x and nothing for butt caps (SVG 2
  // painting.html#LineCaps), against those shapes drawn as fills.
  const Affine view = Affine::translate(10, 10);
  const double h = 4.5;
  Path p;
  p.move_to({20, 20});
  p.close();  // M p Z: a dot
  p.move_to({50, 20});
  p.line_to({50, 20});  // M p L p: a dot
  p.move_to({20, 50});
  p.line_to({20, 50});
  p.line_to({60, 50});  // a zero-length segment inside: nothing changes
  p.move_to({70, 70});  // a bare move: nothing
  for (int cap = 0; cap < 3; cap++) {
    StrokeStyle st;
    st.width = 2 * h;
    st.cap = static_cast<LineCap>(cap);
    auto dot = [&](Path& e, Vec2 c) {
      if (st.cap == LineCap::Round) add_disk(e, c, h);
      if (st.cap == LineCap::Square) add_box(e, c.x - h, c.y - h, c.x + h, c.y + h);
    };
    auto check = [&](const Path& expected, const char* what) {
      const std::vector<InputSegment> out = stroke_of(p, st, view);
      const Diff d = compare(coverage(out), expected.empty() ? coverage({}) : coverage(segments_of(expected, view)));
      INFO(what << " cap " << cap_name(st.cap) << ": " << d.pixels << " pixels differ, max " << d.max << " at ("
                << d.worst_x << ", " << d.worst_y << ")");
      CHECK(defect(out) == "");
      CHECK(d.pixels == 0);
    };
    Path solid;
    dot(solid, {20, 20});
    dot(solid, {50, 20});
    add_box(solid, 20, 50 - h, 60, 50 + h);
    dot(solid, {20, 50});
    dot(solid, {60, 50});
    check(solid, "solid");
    // Zero-length subpaths under dashes: a dot when the pattern is on there.
    // Zero-length dashes along the line from 0 (unshifted), or from 3
    // (offset 2), every 5, before its end.
    st.dashes = {0, 5};
    Path unshifted;
    dot(unshifted, {20, 20});
    dot(unshifted, {50, 20});
    for (double x = 20; x < 60; x += 5) dot(unshifted, {x, 50});
    check(unshifted, "dashes 0 5");
    st.dash_offset = 2;
    Path shifted;
    for (double x = 23; x < 60; x += 5) dot(shifted, {x, 50});
    check(shifted, "dashes 0 5 offset 2");
  }
  // Nothing, without throwing: zero, negative and non-finite widths, a
  // singular transform, non-finite points.
  Path line;
  line.move_to({0, 0});
  line.line_to({10, 10});
  StrokeBatch b;
  StrokeStyle st;
  for (double w : {0.0, -1.0, double(NAN), double(INFINITY)}) {
    st.width = w;
    CHECK_FALSE(b.add(line, st, Affine{}, 0));
  }
  st.width = 1;
  CHECK_FALSE(b.add(line, st, Affine::scale(0, 1), 0));
  Path bad;
  bad.move_to({0, NAN});
  bad.line_to({1, 1});
  CHECK_FALSE(b.add(bad, st, Affine{}, 0));
  CHECK(stroke_cpu(b).empty());
}

TEST_CASE("stroke stage: outputs are grouped by stroke, the same on any number of threads", "[stroke_stage]") {
  std::mt19937 rng(3);
  StrokeBatch b;
  StrokeStyle st;
  st.width = 4;
  st.dashes = {3, 2};
  for (uint32_t id = 0; id < 8; id++) {
    st.join = static_cast<LineJoin>(id % 5);
    st.cap = static_cast<LineCap>(id % 3);
    REQUIRE(b.add(random_path(rng, 2), st, Affine{}, id * 10));
  }
  const std::vector<InputSegment> out = stroke_cpu(b, 2);
  REQUIRE_FALSE(out.empty());
  // Paths in the order strokes were added, each one run of segments.
  for (size_t i = 1; i < out.size(); i++) CHECK(out[i].path >= out[i - 1].path);
  // The same output on one thread and on several.
  const std::vector<InputSegment> one = stroke_cpu(b, 1);
  REQUIRE(one.size() == out.size());
  for (size_t i = 0; i < out.size(); i++) {
    CHECK(one[i].x[0] == out[i].x[0]);
    CHECK(one[i].y[2] == out[i].y[2]);
  }
}

// Scenes: strokes as scene elements (SceneBuilder::stroke), built by the
// stage when the scene is rendered, against the same scene with the stage's
// outlines of them as fills, inside clip groups and transparency groups,
// with transforms: the images agree on every pixel.
TEST_CASE("stroke stage: stroked scene elements render as their outlines filled", "[stroke_stage][scene]") {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> width(0.5, 15), u(0, 1);
  for (int iter = 0; iter < 12; iter++) {
    SceneBuilder with(120, 120), without(120, 120);
    const Affine view = Affine::scale(1.2, 1.2);
    auto both = [&](auto f) {
      f(with, true);
      f(without, false);
    };
    both([&](SceneBuilder& b, bool) {
      const uint32_t bg = b.add_geometry(Path::rectangle(0, 0, 100, 100));
      Paint p;
      p.color = RGBA{0.9f, 0.9f, 0.8f, 1};
      b.fill(bg, Affine{}, FillRule::NonZero, p);
    });
    for (int k = 0; k < 4; k++) {
      const Path centre = random_path(rng, 1 + k % 2);
      StrokeStyle st;
      st.width = width(rng);
      st.join = static_cast<LineJoin>((iter + k) % 5);
      st.cap = static_cast<LineCap>(k % 3);
      if (k == 3) st.dashes = {6, 3, 1, 3};
      const Affine xf = Affine::translate(50, 50) * Affine::rotate_degrees(90 * u(rng)) *
                        Affine::scale(0.8, 0.6 + 0.4 * u(rng)) * Affine::translate(-50, -50);
      // The outline in pixels, as the scene's stroke is built; filled with
      // the view undone.
      Path outline;
      REQUIRE(path_of(stroke_of(centre, st, view * xf), outline));
      Paint p;
      p.color = RGBA{float(u(rng)), float(u(rng)), float(u(rng)), 0.7f};
      const bool grouped = k == 1, clipped = k == 2;
      both([&](SceneBuilder& b, bool stage) {
        if (clipped) {
          b.push();
          b.clip(b.add_geometry(Path::rectangle(10, 10, 90, 70)), Affine{}, FillRule::NonZero);
          b.activate();
        }
        if (grouped) {
          Group g;
          g.opacity = 0.6f;
          b.begin_group(g);
        }
        if (stage)
          b.stroke(b.add_geometry(centre), xf, st, p);
        else
          b.fill(b.add_geometry(outline), view.inverted(), FillRule::NonZero, p);
        if (grouped) b.end_group();
        if (clipped) b.pop();
      });
    }
    const Scene a = with.finish(), b = without.finish();
    REQUIRE(a.strokes.size() == 4);
    RenderOptions o;
    o.width = o.height = 120;
    o.view = view;
    o.samples = 32;
    o.filter = Filter::Box;
    o.backend = Backend::Cpu;
    const ImageF ia = render_cpu(a, o), ib = render_cpu(b, o);
    int differ = 0;
    for (size_t i = 0; i < ia.rgba.size(); i++) differ += std::fabs(ia.rgba[i] - ib.rgba[i]) > 1.0f / 255;
    INFO("iteration " << iter);
    CHECK(differ == 0);
  }
}

namespace {

// DashPattern's searches as the pattern's definition reads: running sums
// over the elements in order.
uint32_t after_by_scan(const std::vector<double>& d, double sum, double offset, double s, double* k) {
  const double q = s + offset;
  double per = std::floor(q / sum);
  double r = q - per * sum;
  if (r >= sum) r -= sum, per += 1;
  if (r < 0) r += sum, per -= 1;
  double c = 0;
  for (uint32_t j = 0; j < d.size(); j++) {
    if (r < c + d[j]) {
      *k = per;
      return j;
    }
    c += d[j];
  }
  *k = per + 1;
  return 0;
}

uint32_t before_by_scan(const std::vector<double>& d, double sum, double offset, double s) {
  const double q = s + offset;
  double r = q - std::ceil(q / sum - 1) * sum;
  if (r <= 0) r += sum;
  if (r > sum) r -= sum;
  double c = 0;
  for (uint32_t j = 0; j < d.size(); j++) {
    if (r <= c + d[j] && d[j] > 0) return j;
    c += d[j];
  }
  return static_cast<uint32_t>(d.size() - 1);
}

}  // namespace

TEST_CASE("dash patterns: binary searches on the running sums find what a scan finds", "[stroke_stage][dash]") {
  std::mt19937 rng(45);
  std::uniform_real_distribution<double> u(0, 1);
  int compared = 0;
  for (int t = 0; t < 300; t++) {
    // Even lengths, some zero, some tiny, some repeated.
    const int n = 2 * (1 + static_cast<int>(u(rng) * 20));
    std::vector<double> d(n);
    for (double& x : d) {
      const double r = u(rng);
      x = r < 0.25 ? 0 : r < 0.3 ? 1e-12 : r < 0.4 ? 0.5 : 10 * u(rng);
    }
    d[0] = std::max(d[0], 0.1);  // a pattern of some length
    std::vector<double> e;
    double sum = 0;
    for (double x : d) e.push_back(sum += x);
    const double offset = u(rng) * sum;
    const stroking::DashPattern dp{d.data(), e.data(), static_cast<uint32_t>(n), sum, offset, 100};
    for (int i = 0; i < 200; i++) {
      // Points anywhere, and exactly on element boundaries.
      const double s = i % 2 ? (u(rng) * 4 - 1) * sum : 2 * sum + dp.cum(static_cast<uint32_t>(u(rng) * n)) - offset;
      double k1 = 0, k2 = 0;
      const uint32_t a1 = dp.element_after(s, &k1), a2 = after_by_scan(d, sum, offset, s, &k2);
      INFO("pattern " << t << " at " << s);
      REQUIRE(a1 == a2);
      REQUIRE(k1 == k2);
      REQUIRE(dp.element_before(s) == before_by_scan(d, sum, offset, s));
      compared++;
    }
  }
  CHECK(compared == 60000);
}

TEST_CASE("dash patterns: a 200,000-element pattern strokes to what its dashes are", "[stroke_stage][dash]") {
  // Dashes of 0.001 and gaps of 0.001 over a 20-unit line: 10,000 dashes
  // of the 100,000 pattern periods' first elements reach the line (the
  // pattern is 200 long), each a rectangle of butt caps.
  Path p;
  p.move_to({0, 0});
  p.line_to({20, 0});
  StrokeStyle st;
  st.width = 1;
  st.dashes.assign(200000, 0.001);
  const std::vector<InputSegment> out = stroke_of(p, st, Affine::scale(10, 10));
  double lo = 1e9, hi = -1e9;
  for (const InputSegment& s : out) {
    lo = std::min(lo, s.x[0]);
    hi = std::max(hi, s.x[0]);
  }
  CHECK(lo >= -1e-9);
  CHECK(hi <= 200 + 1e-9);
  // Each dash is a closed contour of four lines.
  CHECK(out.size() == 4 * 10000);
}
