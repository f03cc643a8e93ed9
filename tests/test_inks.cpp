// Ink pages (core/inks/inks.h: passes of three inks, set_ink_blend's channel
// rules, overprint groups) on the CPU pipeline against the N-ink reference
// compositor (tests/reference_compositor.h, namespace inks: PDF's
// subtractive blending and compatible overprint in N channels at once,
// double precision), on random pages of 4, 5 and 7 inks and on values
// worked out by hand.
#include <cmath>
#include <map>
#include <random>
#include <string>

#include "cpu/cpu_stages.h"
#include "frame/encoding.h"
#include "core/inks/inks.h"
#include "tests/catch.h"
#include "tests/oracle.h"
#include "tests/probe_points.h"
#include "tests/random_inks.h"
#include "frame/scene_info.h"

using namespace mpvg;
using reference::inks::Ink;
using InkNode = reference::inks::Node;

namespace {

constexpr int kSize = 48;

using probe_points::BruteInside;
using probe_points::Probe;

Probe probe(const Scene& scene, const EncodedScene& enc, uint32_t seed, int count) {
  return probe_points::probe(scene, enc, seed, count, kSize);
}

ShortcutTree tree_of(const EncodedScene& enc) {
  TreeParams t;
  t.min_segments = 4;
  return build_tree_cpu(enc, kSize, kSize, t);
}

// Every pass of page `s` sampled at `points`: per point, N premultiplied
// inks and the alpha (which every pass must give alike).
std::vector<Ink> sample_passes(const random_inks::InkScene& s, const std::vector<std::pair<float, float>>& points) {
  std::vector<Ink> out(points.size(), Ink(s.ink_count + 1, -1.0));
  for (const InkPass& pass : ink_passes(s.ink_count)) {
    const Scene scene = random_inks::pass_scene(s, pass);
    const ShortcutTree tree = tree_of(encode(scene, Affine{}, Gamma::Srgb));
    for (size_t i = 0; i < points.size(); i++) {
      const Rgba4 got = sample_tree_cpu(tree, points[i].first, points[i].second);
      const float c[3] = {got.r, got.g, got.b};
      for (int k = 0; k < 3; k++)
        if (pass.inks[k] >= 0) out[i][pass.inks[k]] = c[k];
      if (out[i][s.ink_count] >= 0) {
        INFO("alpha differs between passes at point " << i);
        REQUIRE(std::fabs(out[i][s.ink_count] - got.a) < 1e-6);
      }
      out[i][s.ink_count] = got.a;
    }
  }
  return out;
}

std::string ink_string(const Ink& c) {
  std::string s;
  for (double v : c) s += std::to_string(v) + " ";
  return s;
}

}  // namespace

TEST_CASE("inks: passes of random pages agree with the N-ink reference compositor", "[inks]") {
  // Float against double, as in test_groups (a few dozen roundings a value).
  constexpr double kTolerance = 1e-5;
  size_t compared = 0, groups = 0, overprints = 0, fragile = 0, failed_fragile = 0;
  double worst = 0;
  const int ink_counts[] = {4, 5, 7};
  for (uint32_t seed = 1; seed <= 300; seed++) {
    const int n = ink_counts[seed % 3];
    const random_inks::InkScene page = random_inks::ink_scene(seed, n, 4, kSize);
    const std::vector<InkPass> passes = ink_passes(n);
    REQUIRE(passes.size() == size_t((n + 2) / 3));
    const Scene first = random_inks::pass_scene(page, passes[0]);
    for (const InkPass& pass : passes) {
      const Scene sc = random_inks::pass_scene(page, pass);
      groups += sc.groups.size();
      for (const Group& g : sc.groups)
        for (ChannelRule r : g.channels) overprints += r == ChannelRule::Backdrop && g.blend == BlendMode::Normal;
    }
    const EncodedScene enc = encode(first, Affine{}, Gamma::Srgb);
    const Probe p = probe(first, enc, seed * 7, 60);
    reference::inks::Compositor ref(p.points.size(), n, p.inside);
    const std::vector<Ink> want = ref.render(page.root);
    const std::vector<Ink> got = sample_passes(page, p.points);
    for (size_t i = 0; i < p.points.size(); i++) {
      // Over the paper: inks as they are, alpha 1 (both sides alike); the
      // alpha before it compared too.
      const Ink w = reference::inks::over_paper(want[i]), g = reference::inks::over_paper(got[i]);
      INFO("seed " << seed << ", " << n << " inks, point (" << p.points[i].first << ", " << p.points[i].second
                   << ")\nwant " << ink_string(want[i]) << "\ngot  " << ink_string(got[i]) << "\n"
                   << dump(first));
      double e = std::fabs(got[i][n] - want[i][n]);
      for (int k = 0; k <= n; k++) e = std::max(e, std::fabs(g[k] - w[k]));
      if (ref.ill_conditioned()[i]) {
        fragile++;
        failed_fragile += e >= kTolerance;
        continue;
      }
      worst = std::max(worst, e);
      CHECK(e < kTolerance);
      compared++;
    }
  }
  INFO("worst difference " << worst << " over " << compared << " samples, " << groups << " groups, " << overprints
                            << " overprint groups; " << fragile << " samples ill-conditioned, " << failed_fragile
                            << " of them different");
  CHECK(worst < kTolerance);
  // Points where a blend met its function's discontinuity (Hue and
  // Saturation at a grey, color-dodge and color-burn at their corners) are
  // left out: float noise of 1e-7 (a backdrop removed from a result, say)
  // can put the implementation on the other side of the jump. Few, and
  // nearly all of them equal anyway (3000 seeds: 2 of 4422 differ).
  CHECK(fragile * 20 < compared);
  CHECK(failed_fragile * 100 <= fragile);
  CHECK(compared > 6000);
  CHECK(groups > 500);
  CHECK(overprints > 100);
}

namespace {

// Hand-made pages: rectangles, ink values, painted masks and groups.
struct Hand {
  random_inks::InkScene page;
  explicit Hand(int n) {
    page.ink_count = n;
    page.size = 40;
    page.root.kind = InkNode::Transparency;
  }
  std::vector<std::unique_ptr<InkNode>>* into = &page.root.children;

  // A box of ink values `inks` (others 0), painting `painted` (empty: all).
  void box(double x0, double y0, double x1, double y1, std::map<int, double> inks, double alpha = 1,
           std::vector<int> painted = {}, bool painted_listed = false) {
    auto n = std::make_unique<InkNode>();
    n->kind = InkNode::Fill;
    page.geometries.push_back(oracle::rect(x0, y0, x1, y1));
    n->geometry = static_cast<uint32_t>(page.geometries.size() - 1);
    n->inks.assign(page.ink_count, 0.0);
    for (auto [k, v] : inks) n->inks[k] = v;
    n->alpha = alpha;
    if (painted_listed) {
      n->painted.assign(page.ink_count, false);
      for (int k : painted) n->painted[k] = true;
    }
    into->push_back(std::move(n));
  }
  void paper() { box(-5, -5, 45, 45, {}); }
  // A group around what `body` adds.
  template <class F>
  void group(Group g, F body) {
    auto n = std::make_unique<InkNode>();
    n->kind = InkNode::Transparency;
    n->group = g;
    auto* saved = into;
    into = &n->children;
    body();
    into = saved;
    into->push_back(std::move(n));
  }

  // The implementation's and the reference's result at (x, y), over paper.
  std::pair<Ink, Ink> at(float x, float y) {
    std::vector<std::pair<float, float>> pts{{x, y}};
    const Scene first = random_inks::pass_scene(page, ink_passes(page.ink_count)[0]);
    const EncodedScene enc = encode(first, Affine{}, Gamma::Srgb);
    BruteInside inside;
    for (uint32_t id = 0; id < first.paths.size(); id++) inside.path_of[first.paths[id].geometry] = id;
    const oracle::Windings brute(enc.segments, first.paths.size());
    auto w = brute.at(x, y, 1e-3);
    REQUIRE(w);
    inside.windings.push_back(*w);
    reference::inks::Compositor ref(1, page.ink_count, inside);
    return {reference::inks::over_paper(sample_passes(page, pts)[0]),
            reference::inks::over_paper(ref.render(page.root)[0])};
  }
};

// Both the implementation and the reference give `want` (ink -> value) at
// (x, y); unnamed inks: the two agree.
void check(Hand& h, float x, float y, std::map<int, double> want) {
  const auto [got, ref] = h.at(x, y);
  INFO("at (" << x << ", " << y << "): got " << ink_string(got) << "; reference " << ink_string(ref));
  for (int k = 0; k <= h.page.ink_count; k++) CHECK(got[k] == Approx(ref[k]).margin(1e-5));
  for (auto [k, v] : want) {
    CHECK(got[k] == Approx(v).margin(1e-5));
    CHECK(ref[k] == Approx(v).margin(1e-9));
  }
}

constexpr int C = 0, M = 1, Y = 2, K = 3, S1 = 4;

}  // namespace

TEST_CASE("inks by hand: overprint keeps the ink below, a knockout fill removes it", "[inks]") {
  for (bool overprint : {true, false}) {
    Hand h(4);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 1}});  // a cyan background
    // Black text with OPM 1: its CMYK colour paints only K, non-zero.
    h.box(10, 10, 30, 30, {{K, 1}}, 1, {K}, overprint);
    INFO((overprint ? "overprint" : "knockout"));
    check(h, 20, 20, {{C, overprint ? 1.0 : 0.0}, {M, 0}, {K, 1}});
    check(h, 5, 5, {{C, 1}, {K, 0}});
  }
  {  // Translucent overprint: the unpainted ink stays whole, the painted one composites.
    Hand h(5);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 0.6}, {S1, 0.4}});
    h.box(10, 10, 30, 30, {{K, 0.8}, {S1, 0.9}}, 0.5, {K, S1}, true);
    check(h, 20, 20, {{C, 0.6}, {K, 0.4}, {S1, 0.5 * 0.9 + 0.5 * 0.4}});
  }
  {  // A fill painting nothing changes no ink (over transparency it adds alpha, no ink).
    Hand h(4);
    h.box(0, 0, 40, 40, {{M, 0.7}}, 0.5);
    h.box(10, 10, 30, 30, {}, 1, {}, true);
    check(h, 20, 20, {{M, 0.35}, {C, 0}, {K, 0}});
    check(h, 5, 5, {{M, 0.35}});
  }
}

TEST_CASE("inks by hand: separable modes are subtractive, on spots too", "[inks]") {
  auto two = [](BlendMode mode) {
    Hand h(5);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 0.5}, {S1, 0.5}});
    Group g;
    g.blend = mode;
    h.group(g, [&] { h.box(10, 10, 30, 30, {{C, 0.5}, {S1, 0.5}}); });
    return h;
  };
  {  // Multiply darkens: 1 - (1 - 0.5)(1 - 0.5).
    Hand h = two(BlendMode::Multiply);
    check(h, 20, 20, {{C, 0.75}, {S1, 0.75}, {M, 0}, {K, 0}});
    check(h, 5, 5, {{C, 0.5}, {S1, 0.5}});
  }
  {  // Screen lightens: 1 - (0.5 + 0.5 - 0.25).
    Hand h = two(BlendMode::Screen);
    check(h, 20, 20, {{C, 0.25}, {S1, 0.25}, {M, 0}});
  }
  {  // Darken keeps more ink (the darker), lighten less.
    Hand h(4);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 0.3}, {M, 0.8}});
    Group g;
    g.blend = BlendMode::Darken;
    h.group(g, [&] { h.box(10, 10, 30, 30, {{C, 0.6}, {M, 0.2}}); });
    check(h, 20, 20, {{C, 0.6}, {M, 0.8}});
  }
  {  // Multiply over the paper inside the page: the source itself; over
     // transparency (no paper fill) likewise.
    for (bool paper : {true, false}) {
      Hand h(4);
      if (paper) h.paper();
      Group g;
      g.blend = BlendMode::Multiply;
      h.group(g, [&] { h.box(10, 10, 30, 30, {{Y, 0.4}}); });
      check(h, 20, 20, {{Y, 0.4}, {C, 0}});
    }
  }
}

TEST_CASE("inks by hand: non-separable modes: C, M, Y as RGB, K and spots by rule", "[inks]") {
  // Backdrop: grey C = M = Y = 0.4, K 0.3, spot 0.2; source: C 0.6, K 0.7, spot 0.9.
  auto page = [](BlendMode mode) {
    Hand h(5);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 0.4}, {M, 0.4}, {Y, 0.4}, {K, 0.3}, {S1, 0.2}});
    Group g;
    g.blend = mode;
    h.group(g, [&] { h.box(10, 10, 30, 30, {{C, 0.6}, {K, 0.7}, {S1, 0.9}}); });
    return h;
  };
  {  // Luminosity: K of the source; the grey takes the source's luminosity:
     // 1 - (0.3 x 0.4 + 0.59 + 0.11) = 0.18 of each of C, M, Y.
    Hand h = page(BlendMode::Luminosity);
    check(h, 20, 20, {{C, 0.18}, {M, 0.18}, {Y, 0.18}, {K, 0.7}, {S1, 0.9}});
  }
  {  // Hue: K of the backdrop; a grey has no saturation, so it stays grey;
     // the spot: Normal, the source's value.
    Hand h = page(BlendMode::Hue);
    check(h, 20, 20, {{C, 0.4}, {M, 0.4}, {Y, 0.4}, {K, 0.3}, {S1, 0.9}});
  }
  {  // Hue with a source of no ink (white, no saturation): grey of the
     // backdrop's luminosity 0.3 x 0.6 + 0.59 + 0.11 = 0.88, K the backdrop's.
    Hand h(4);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 0.4}, {K, 0.3}});
    Group g;
    g.blend = BlendMode::Hue;
    h.group(g, [&] { h.box(10, 10, 30, 30, {}); });
    check(h, 20, 20, {{C, 0.12}, {M, 0.12}, {Y, 0.12}, {K, 0.3}});
  }
  for (BlendMode mode : {BlendMode::Saturation, BlendMode::Color}) {
    Hand h = page(mode);
    check(h, 20, 20, {{K, 0.3}, {S1, 0.9}});
  }
  {  // Translucent: K = (1 - as) Kb + as Kb under hue: unchanged; the spot source-over.
    Hand h(5);
    h.paper();
    h.box(0, 0, 40, 40, {{K, 0.3}, {S1, 0.2}});
    Group g;
    g.blend = BlendMode::Hue;
    h.group(g, [&] { h.box(10, 10, 30, 30, {{K, 0.7}, {S1, 0.9}}, 0.5); });
    check(h, 20, 20, {{K, 0.3}, {S1, 0.55}});
  }
}

TEST_CASE("inks by hand: overprint inside knockout groups", "[inks]") {
  // Cyan below; a knockout group of magenta (paints every ink), then black
  // overprinting (paints K only) across part of it.
  for (bool isolated : {false, true}) {
    Hand h(4);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 1}});
    Group ko;
    ko.knockout = true;
    ko.isolated = isolated;
    h.group(ko, [&] {
      h.box(0, 0, 25, 40, {{M, 0.6}});
      h.box(15, 0, 40, 40, {{K, 1}}, 1, {K}, true);
    });
    INFO((isolated ? "isolated" : "non-isolated"));
    check(h, 5, 20, {{C, 0}, {M, 0.6}, {K, 0}});  // magenta alone knocks cyan out
    // Both: the black meets the group's initial backdrop, not the magenta:
    // magenta is knocked out; cyan stays where the backdrop is the page's
    // (non-isolated), not in an isolated group (whose backdrop is empty).
    check(h, 20, 20, {{C, isolated ? 0.0 : 1.0}, {M, 0}, {K, 1}});
    check(h, 35, 20, {{C, isolated ? 0.0 : 1.0}, {M, 0}, {K, 1}});
  }
  {  // Translucent black overprinting in a non-isolated knockout group: the
     // magenta below it is knocked out, K composites onto the initial backdrop.
    Hand h(4);
    h.paper();
    h.box(0, 0, 40, 40, {{C, 0.5}, {K, 0.2}});
    Group ko;
    ko.knockout = true;
    ko.isolated = false;
    h.group(ko, [&] {
      h.box(0, 0, 40, 40, {{M, 0.6}});
      h.box(10, 10, 30, 30, {{K, 1}}, 0.5, {K}, true);
    });
    check(h, 20, 20, {{C, 0.5}, {M, 0}, {K, 0.6}});
  }
}
