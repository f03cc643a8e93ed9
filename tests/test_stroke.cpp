// Stage "stroke" (core/stroke.h) on the CPU executor against the stroker it
// replaces (stroker/, the oracle until the tree keeps one stroker): for
// random centrelines under every join, cap, miter limit and dash pattern,
// both outputs are rendered at 1x32 box and their per-pixel coverage
// compared.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/renderer.h"
#include "core/stroke_input.h"
#include "stroker/stroker.h"
#include "tests/catch.h"
#include "tests/random_paths.h"
#include "tests/stroke_coverage.h"

using namespace mpvg;
using namespace mpvg::test;
namespace sk = mpvg::stroke;

namespace {

StrokeStyle style_of(const sk::Style& s) {
  StrokeStyle o;
  o.width = s.width;
  o.join = static_cast<LineJoin>(s.join);
  o.cap = static_cast<LineCap>(s.cap);
  o.miter_limit = s.miter_limit;
  o.dashes = s.dashes;
  o.dash_offset = s.dash_offset;
  return o;
}

struct Diff {
  int pixels = 0;      // differing by more than 1/255
  float max = 0;       // largest difference
  int worst_x = 0, worst_y = 0;
};

// The old stroker's and the stage's coverage of one stroke.
Diff compare(const Path& path, const sk::Style& style, const Affine& xf) {
  const Path old_fill = sk::stroke_to_fill(path, style, xf);
  StrokeBatch batch;
  batch.add(path, style_of(style), xf, 0);
  const std::vector<InputSegment> segs = stroke_cpu(batch, 1);
  const std::vector<float> a = coverage(old_fill.empty() ? std::vector<InputSegment>{} : segments_of(old_fill, xf)),
                           b = coverage(segs);
  Diff d;
  for (int i = 0; i < kSize * kSize; i++) {
    const float e = std::fabs(a[i] - b[i]);
    if (e > 1.0f / 255) d.pixels++;
    if (e > d.max) d.max = e, d.worst_x = i % kSize, d.worst_y = i / kSize;
  }
  return d;
}

const char* join_name(sk::Join j) {
  static const char* names[] = {"miter", "miter-clip", "arcs", "round", "bevel"};
  return names[static_cast<int>(j)];
}
const char* cap_name(sk::Cap c) {
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

std::string describe(int iter, const sk::Style& st, const Diff& d) {
  std::string s = "iteration " + std::to_string(iter) + " " + join_name(st.join) + "/" + cap_name(st.cap) +
                  " width " + std::to_string(st.width) + " miter limit " + std::to_string(st.miter_limit);
  if (!st.dashes.empty()) {
    s += " dashes";
    for (double x : st.dashes) s += " " + std::to_string(x);
    s += " offset " + std::to_string(st.dash_offset);
  }
  s += ": " + std::to_string(d.pixels) + " pixels differ, max " + std::to_string(d.max) + " at (" +
       std::to_string(d.worst_x) + ", " + std::to_string(d.worst_y) + ")";
  return s;
}

}  // namespace

TEST_CASE("stroke stage: random paths under every join, cap and miter limit agree with the stroker",
          "[stroke_stage][oracle]") {
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<double> width(0.5, 30), limit(0.5, 8);
  int total_pixels = 0;
  float worst = 0;
  for (int iter = 0; iter < 60; iter++) {
    const Path path = random_path(rng, 1 + iter % 3);
    sk::Style st;
    st.width = width(rng);
    st.join = static_cast<sk::Join>(iter % 5);
    st.cap = static_cast<sk::Cap>((iter / 5) % 3);
    st.miter_limit = limit(rng);
    const Affine view = random_view(rng);
    const Diff d = compare(path, st, view);
    INFO(describe(iter, st, d));
    total_pixels += d.pixels;
    worst = std::max(worst, d.max);
    CHECK(d.pixels <= 2);
    CHECK(d.max <= 2.0f / 32 + 1e-6f);
  }
  // Over all of them, the two agree on all but a handful of pixels, each
  // by at most a sample or two (rounding that moves an edge across one).
  WARN("random strokes: " << total_pixels << " pixels differ by more than 1/255, largest difference " << worst);
  CHECK(total_pixels <= 20);
}

TEST_CASE("stroke stage: dashes, offsets and closed subpaths agree with the stroker", "[stroke_stage][oracle][dash]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> width(0.5, 12), len(0, 25), off(-60, 60);
  std::uniform_int_distribution<int> count(1, 5);
  int total_pixels = 0;
  for (int iter = 0; iter < 60; iter++) {
    const Path path = random_path(rng, 1 + iter % 3);
    sk::Style st;
    st.width = width(rng);
    st.join = static_cast<sk::Join>(iter % 5);
    st.cap = static_cast<sk::Cap>((iter / 5) % 3);
    st.miter_limit = 4;
    const int n = count(rng);
    for (int k = 0; k < n; k++) st.dashes.push_back(iter % 7 == 3 && k == 0 ? 0.0 : len(rng));
    st.dash_offset = iter % 4 == 0 ? 0 : off(rng);
    const Diff d = compare(path, st, random_view(rng));
    INFO(describe(iter, st, d));
    total_pixels += d.pixels;
    CHECK(d.pixels <= 2);
    CHECK(d.max <= 2.0f / 32 + 1e-6f);
  }
  CHECK(total_pixels <= 20);
}

TEST_CASE("stroke stage: degenerate subpaths and input", "[stroke_stage][degenerate]") {
  const Affine view = Affine::translate(10, 10);
  for (int cap = 0; cap < 3; cap++) {
    sk::Style st;
    st.width = 9;
    st.cap = static_cast<sk::Cap>(cap);
    Path p;
    p.move_to({20, 20});
    p.close();  // M p Z: a dot
    p.move_to({50, 20});
    p.line_to({50, 20});  // M p L p: a dot
    p.move_to({20, 50});
    p.line_to({20, 50});
    p.line_to({60, 50});  // a zero-length segment inside: nothing changes
    p.move_to({70, 70});  // a bare move: nothing
    const Diff d = compare(p, st, view);
    INFO(describe(0, st, d));
    CHECK(d.pixels == 0);
    // Zero-length subpaths under dashes: a dot when the pattern is on there.
    st.dashes = {0, 5};
    CHECK(compare(p, st, view).pixels == 0);
    st.dash_offset = 2;
    CHECK(compare(p, st, view).pixels == 0);
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
// stage when the scene is rendered, against the same scene with the old
// stroker's fills, inside clip groups and transparency groups, with
// transforms: the images agree on every pixel.
TEST_CASE("stroke stage: stroked scene elements render as the stroker's fills", "[stroke_stage][scene]") {
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
    std::mt19937 shapes(static_cast<uint32_t>(iter));
    for (int k = 0; k < 4; k++) {
      const Path centre = random_path(rng, 1 + k % 2);
      sk::Style st;
      st.width = width(rng);
      st.join = static_cast<sk::Join>((iter + k) % 5);
      st.cap = static_cast<sk::Cap>(k % 3);
      if (k == 3) st.dashes = {6, 3, 1, 3};
      const Affine xf = Affine::translate(50, 50) * Affine::rotate_degrees(90 * u(rng)) *
                        Affine::scale(0.8, 0.6 + 0.4 * u(rng)) * Affine::translate(-50, -50);
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
          b.stroke(b.add_geometry(centre), xf, style_of(st), p);
        else
          b.fill(b.add_geometry(sk::stroke_to_fill(centre, st, view * xf)), xf, FillRule::NonZero, p);
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
