// Transparency groups and masks (core/paint/group.h) on the CPU pipeline against
// the reference compositor (a buffer per group, double precision), pruned
// against unpruned trees, and values worked out by hand; groups with the
// Porter-Duff operators (plus-lighter, source-atop, xor) the same ways.
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>

#include "cpu/cpu_stages.h"
#include "frame/encoding.h"
#include "frame/frame.h"
#include "tests/catch.h"
#include "tests/oracle.h"
#include "tests/probe_points.h"
#include "tests/random_groups.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"
#include "frame/scene_info.h"

using namespace mpvg;

namespace {

constexpr int kSize = 48;

using probe_points::BruteInside;
using probe_points::Probe;

Probe probe(const Scene& scene, const EncodedScene& enc, uint32_t seed, int count) {
  return probe_points::probe(scene, enc, seed, count, kSize);
}

TreeParams params(bool prune) {
  TreeParams t;
  t.min_segments = 4;
  t.prune = prune;
  return t;
}

// Random group scenes of seeds [first, last] rendered on the CPU against
// the reference compositor. Float against double: a colour goes through a
// few dozen compositing steps of a few roundings each (about 3e-7 is what
// 120 scenes show); color-dodge and color-burn divide by 1 - cs and cs,
// which could magnify float error near 1 and 0, clamped to [0, 1].
// Returns the samples compared; `groups` counts the scenes' groups.
size_t compare_with_reference(uint32_t first, uint32_t last, bool porter_duff, size_t& groups,
                              size_t* porter_duff_groups = nullptr) {
  constexpr double kTolerance = 1e-5;
  size_t compared = 0;
  double worst = 0;
  for (uint32_t seed = first; seed <= last; seed++) {
    const random_groups::GroupScene gs = random_groups::group_scene(seed, 4, kSize, porter_duff);
    groups += gs.scene.groups.size();
    if (porter_duff_groups)
      for (const Group& g : gs.scene.groups) *porter_duff_groups += g.blend >= BlendMode::PlusLighter ? 1 : 0;
    const EncodedScene enc = encode(gs.scene, Affine{}, Gamma::Srgb);
    const ShortcutTree tree = build_tree_cpu(enc, kSize, kSize, params(true));
    const Probe p = probe(gs.scene, enc, seed * 7, 60);
    reference::Compositor ref(p.points.size(), p.inside);
    const std::vector<reference::D4> want = ref.render(gs.root);
    for (size_t i = 0; i < p.points.size(); i++) {
      const Rgba4 got = sample_tree_cpu(tree, p.points[i].first, p.points[i].second);
      const double g[4] = {got.r, got.g, got.b, got.a};
      INFO("seed " << seed << " point (" << p.points[i].first << ", " << p.points[i].second << ")\n"
                   << dump(gs.scene));
      for (int k = 0; k < 4; k++) {
        worst = std::max(worst, std::fabs(g[k] - want[i][k]));
        REQUIRE(std::fabs(g[k] - want[i][k]) < kTolerance);
      }
      compared++;
    }
  }
  INFO("worst difference from the reference " << worst << " over " << compared << " samples");
  CHECK(worst < kTolerance);
  return compared;
}

// Random group scenes of seeds [first, last): pruned, unpruned and coarse-grid
// trees sample identically, and pruning removes at least a tenth of the
// leaf entries.
void compare_pruned(uint32_t first, uint32_t last, bool porter_duff) {
  size_t compared = 0, pruned = 0, unpruned = 0;
  for (uint32_t seed = first; seed < last; seed++) {
    const random_groups::GroupScene gs = random_groups::group_scene(seed, 4, kSize, porter_duff);
    const EncodedScene enc = encode(gs.scene, Affine{}, Gamma::Srgb);
    for (int max_depth : {0, 3, -1}) {
      TreeParams on = params(true), off = params(false);
      on.max_depth = off.max_depth = max_depth;
      TreeParams coarse = on;  // three levels of coarse grid, unpruned (core/tree/tree.h)
      coarse.grid_levels = 3;
      const ShortcutTree a = build_tree_cpu(enc, kSize, kSize, on);
      const ShortcutTree b = build_tree_cpu(enc, kSize, kSize, off);
      const ShortcutTree g = build_tree_cpu(enc, kSize, kSize, coarse);
      if (max_depth == -1) {
        pruned += a.leaf_entries.size();
        unpruned += b.leaf_entries.size();
      }
      const Probe p = probe(gs.scene, enc, seed, 40);
      for (const auto& [px, py] : p.points) {
        const Rgba4 x = sample_tree_cpu(a, px, py), y = sample_tree_cpu(b, px, py), z = sample_tree_cpu(g, px, py);
        INFO("seed " << seed << " depth " << max_depth << " point (" << px << ", " << py << "): " << x.r << " " << x.g
                      << " " << x.b << " " << x.a << " against " << y.r << " " << y.g << " " << y.b << " " << y.a
                      << "; with the coarse grid " << z.r << " " << z.g << " " << z.b << " " << z.a);
        REQUIRE(oracle::identical(x, y));
        REQUIRE(oracle::identical(z, y));
        compared++;
      }
    }
  }
  INFO("leaf entries: " << pruned << " pruned vs " << unpruned << " unpruned");
  CHECK(compared > 5000);
  CHECK(pruned * 10 < unpruned * 9);
}

}  // namespace

TEST_CASE("groups and masks agree with the reference compositor", "[groups]") {
  size_t groups = 0;
  const size_t compared = compare_with_reference(1, 120, false, groups);
  CHECK(groups > 300);
  CHECK(compared > 5000);
}

TEST_CASE("groups with Porter-Duff operators agree with the reference compositor", "[groups][porter-duff]") {
  // The same scenes' kind with plus-lighter, source-atop and xor among the
  // groups' modes: over nothing, over partly transparent backdrops, inside
  // knockout and non-isolated groups, masked.
  size_t groups = 0, porter_duff = 0;
  const size_t compared = compare_with_reference(1001, 1120, true, groups, &porter_duff);
  CHECK(groups > 300);
  CHECK(porter_duff > 60);
  CHECK(compared > 5000);
}

TEST_CASE("groups: pruned and unpruned trees give identical samples", "[groups][prune]") {
  compare_pruned(200, 280, false);
}

TEST_CASE("groups with Porter-Duff operators: pruned and unpruned trees give identical samples",
          "[groups][prune][porter-duff]") {
  compare_pruned(1200, 1280, true);
}

namespace {

void fill_box(SceneBuilder& b, double x0, double y0, double x1, double y1, RGBA c) {
  Paint p;
  p.color = c;
  b.fill(b.add_geometry(oracle::rect(x0, y0, x1, y1)), Affine{}, FillRule::NonZero, p);
}

// Premultiplied colours of a 40 x 40 render with one sample per pixel: the
// squares here cover whole pixels, so where in its pixel the sample falls
// does not matter.
struct Rendered {
  ImageF im;
  explicit Rendered(const Scene& s) {
    RenderOptions o;
    o.width = o.height = 40;
    o.samples = 1;
    o.backend = Backend::Cpu;
    im = render_cpu(s, o);
  }
  std::array<float, 4> at(int x, int y) const {
    const float* p = &im.rgba[(size_t(y) * 40 + x) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
};

void check_pixel(const Rendered& r, int x, int y, std::array<float, 4> want) {
  const auto got = r.at(x, y);
  INFO("pixel (" << x << ", " << y << ") " << got[0] << " " << got[1] << " " << got[2] << " " << got[3]);
  for (int k = 0; k < 4; k++) CHECK(got[k] == Approx(want[k]).margin(1e-5));
}

}  // namespace

TEST_CASE("groups by hand: opacity once, blend modes, isolation, knockout", "[groups]") {
  {  // Two opaque squares in a 50 % group: 50 % in the overlap too, not 75 %.
    SceneBuilder b(40, 40);
    Group g;
    g.opacity = 0.5f;
    b.begin_group(g);
    fill_box(b, 0, 0, 25, 25, {1, 0, 0, 1});
    fill_box(b, 15, 15, 40, 40, {0, 0, 1, 1});
    b.end_group();
    const Rendered r(b.finish());
    check_pixel(r, 5, 5, {0.5f, 0, 0, 0.5f});
    check_pixel(r, 20, 20, {0, 0, 0.5f, 0.5f});
    check_pixel(r, 5, 35, {0, 0, 0, 0});
  }
  {  // Multiply: yellow x cyan = green where they meet; the backdrop elsewhere.
    SceneBuilder b(40, 40);
    fill_box(b, 0, 0, 40, 40, {1, 1, 0, 1});
    Group g;
    g.blend = BlendMode::Multiply;
    b.begin_group(g);
    fill_box(b, 10, 10, 30, 30, {0, 1, 1, 1});
    b.end_group();
    const Rendered r(b.finish());
    check_pixel(r, 5, 5, {1, 1, 0, 1});
    check_pixel(r, 20, 20, {0, 1, 0, 1});
  }
  {  // A multiply child sees grey through a non-isolated group, nothing through an isolated one.
    for (bool isolated : {true, false}) {
      SceneBuilder b(40, 40);
      fill_box(b, 0, 0, 40, 40, {0.5f, 0.5f, 0.5f, 1});
      Group g;
      g.isolated = isolated;
      g.opacity = 0.999f;  // a group that stays one
      b.begin_group(g);
      Group m;
      m.blend = BlendMode::Multiply;
      b.begin_group(m);
      fill_box(b, 0, 0, 40, 40, {1, 0, 0, 1});
      b.end_group();
      b.end_group();
      const Rendered r(b.finish());
      // Non-isolated: red x grey = (0.5, 0, 0) over grey. Isolated: red alone in
      // the group (multiply onto transparency is the source), then over grey.
      const float k = 0.999f;
      if (isolated)
        check_pixel(r, 20, 20, {k * 1 + (1 - k) * 0.5f, (1 - k) * 0.5f, (1 - k) * 0.5f, 1});
      else
        check_pixel(r, 20, 20, {0.5f, (1 - k) * 0.5f, (1 - k) * 0.5f, 1});
    }
  }
  {  // Knockout: the top square replaces the bottom one where they meet, even translucent.
    SceneBuilder b(40, 40);
    Group g;
    g.knockout = true;
    b.begin_group(g);
    fill_box(b, 0, 0, 25, 25, {1, 0, 0, 1});
    fill_box(b, 15, 15, 40, 40, {0, 0, 1, 0.5f});
    b.end_group();
    const Rendered r(b.finish());
    check_pixel(r, 5, 5, {1, 0, 0, 1});
    check_pixel(r, 20, 20, {0, 0, 0.5f, 0.5f});
  }
}

TEST_CASE("Porter-Duff groups by hand: over a backdrop, over nothing, partly transparent, knockout",
          "[groups][porter-duff]") {
  // Opaque red over the top half; the group's content is blue at 50 % over
  // the left half. (5, 5): both; (5, 30): the group over nothing; (30, 5):
  // the backdrop alone, which a bounded operator leaves; (30, 30): nothing.
  auto scene = [](BlendMode mode, float opacity) {
    SceneBuilder b(40, 40);
    fill_box(b, 0, 0, 40, 20, {1, 0, 0, 1});
    Group g;
    g.blend = mode;
    g.opacity = opacity;
    b.begin_group(g);
    fill_box(b, 0, 0, 20, 40, {0, 0, 1, 0.5f});
    b.end_group();
    return b.finish();
  };
  {  // source-atop: cs ab + cb (1 - as) where the backdrop is, nothing elsewhere.
    const Scene s = scene(BlendMode::SourceAtop, 1);
    // The top level meets its backdrop: it runs back to front inside a group.
    REQUIRE(s.groups.size() == 2);
    CHECK(s.groups[1].back_to_front);
    const Rendered r(s);
    check_pixel(r, 5, 5, {0.5f, 0, 0.5f, 1});
    check_pixel(r, 5, 30, {0, 0, 0, 0});
    check_pixel(r, 30, 5, {1, 0, 0, 1});
    check_pixel(r, 30, 30, {0, 0, 0, 0});
  }
  {  // xor: red's share (1 - as) where both are, alpha 0.5 + 1 - 2 x 0.5.
    const Rendered r(scene(BlendMode::Xor, 1));
    check_pixel(r, 5, 5, {0.5f, 0, 0, 0.5f});
    check_pixel(r, 5, 30, {0, 0, 0.5f, 0.5f});
    check_pixel(r, 30, 5, {1, 0, 0, 1});
    check_pixel(r, 30, 30, {0, 0, 0, 0});
  }
  {  // plus-lighter: the sum, clamped.
    const Rendered r(scene(BlendMode::PlusLighter, 1));
    check_pixel(r, 5, 5, {1, 0, 0.5f, 1});
    check_pixel(r, 5, 30, {0, 0, 0.5f, 0.5f});
    check_pixel(r, 30, 5, {1, 0, 0, 1});
  }
  {  // The group's opacity scales its result first: xor with blue at 25 %.
    const Rendered r(scene(BlendMode::Xor, 0.5f));
    check_pixel(r, 5, 5, {0.75f, 0, 0, 0.75f});
    check_pixel(r, 5, 30, {0, 0, 0.25f, 0.25f});
  }
  {  // In an isolated group of its own, source-atop sees only what the group
     // holds: over nothing it paints nothing, whatever lies outside.
    SceneBuilder b(40, 40);
    fill_box(b, 0, 0, 40, 40, {0, 1, 0, 1});
    Group outer;
    outer.opacity = 0.999f;  // a group that stays one
    b.begin_group(outer);
    fill_box(b, 0, 0, 40, 20, {1, 0, 0, 1});
    Group atop;
    atop.blend = BlendMode::SourceAtop;
    b.begin_group(atop);
    fill_box(b, 0, 0, 20, 40, {0, 0, 1, 1});
    b.end_group();
    b.end_group();
    const Rendered r(b.finish());
    const float k = 0.999f;
    check_pixel(r, 5, 5, {0, 1 - k, k, 1});       // blue atop red, over green
    check_pixel(r, 5, 30, {0, 1, 0, 1});          // atop nothing: green shows
    check_pixel(r, 30, 5, {k, 1 - k, 0, 1});
  }
  // An isolated knockout group of red, then blue in a group of `mode`.
  auto knockout = [](BlendMode mode, float blue_alpha) {
    SceneBuilder b(40, 40);
    Group ko;
    ko.knockout = true;
    b.begin_group(ko);
    fill_box(b, 0, 0, 40, 20, {1, 0, 0, 1});
    Group g;
    g.blend = mode;
    b.begin_group(g);
    fill_box(b, 0, 0, 20, 40, {0, 0, 1, blue_alpha});
    b.end_group();
    b.end_group();
    return b.finish();
  };
  {  // Each element is composited onto transparency: a source-atop
     // element there is nothing, and knocks out the red below it. Its list
     // must run back to front for that.
    const Scene s = knockout(BlendMode::SourceAtop, 1);
    CHECK(s.groups[0].back_to_front);
    const Rendered r(s);
    check_pixel(r, 5, 5, {0, 0, 0, 0});
    check_pixel(r, 30, 5, {1, 0, 0, 1});
    check_pixel(r, 5, 30, {0, 0, 0, 0});
  }
  {  // ... whereas xor and plus-lighter onto transparency are the source:
     // that knockout list keeps running front to back.
    const Scene s = knockout(BlendMode::Xor, 0.5f);
    CHECK_FALSE(s.groups[0].back_to_front);
    const Rendered r(s);
    check_pixel(r, 5, 5, {0, 0, 0.5f, 0.5f});
    check_pixel(r, 30, 5, {1, 0, 0, 1});
  }
  // Their names, in dumps and for frontends.
  CHECK(std::string(blend_mode_name(BlendMode::PlusLighter)) == "plus-lighter");
  CHECK(std::string(blend_mode_name(BlendMode::SourceAtop)) == "source-atop");
  CHECK(std::string(blend_mode_name(BlendMode::Xor)) == "xor");
  // Past the last mode: refused.
  SceneBuilder b(10, 10);
  Group bad;
  bad.blend = static_cast<BlendMode>(static_cast<int>(BlendMode::Xor) + 1);
  CHECK_THROWS(b.begin_group(bad));
}

TEST_CASE("masks by hand: luminance, alpha, backdrop, mask on mask, empty masks", "[groups]") {
  auto masked = [](MaskType type, RGBA backdrop, bool nested, bool empty) {
    SceneBuilder b(40, 40);
    Group g;
    b.begin_group(g);
    Group m;
    m.mask = type;
    m.backdrop = backdrop;
    b.begin_group(m);
    if (nested) {  // the mask's own alpha mask: only its left half
      Group n;
      n.mask = MaskType::Alpha;
      b.begin_group(n);
      fill_box(b, 0, 0, 20, 40, {0, 0, 0, 1});
      b.end_group();
    }
    if (!empty) {
      fill_box(b, 0, 0, 40, 20, {1, 1, 1, 1});       // white, top
      fill_box(b, 0, 20, 40, 40, {1, 1, 1, 0.5f});   // half-transparent white, bottom
    }
    b.end_group();
    fill_box(b, 0, 0, 40, 40, {0, 1, 0, 1});
    b.end_group();
    return Rendered(b.finish());
  };
  const RGBA none{0, 0, 0, 0};
  {
    const Rendered r = masked(MaskType::Luminance, none, false, false);
    check_pixel(r, 30, 5, {0, 1, 0, 1});
    check_pixel(r, 30, 30, {0, 0.5f, 0, 0.5f});
  }
  {  // Alpha ignores colour; a luminance mask over an opaque grey backdrop sees grey where it is empty.
    const Rendered a = masked(MaskType::Alpha, none, false, false);
    check_pixel(a, 30, 30, {0, 0.5f, 0, 0.5f});
    const Rendered g = masked(MaskType::Luminance, {0.5f, 0.5f, 0.5f, 1}, false, true);
    check_pixel(g, 30, 30, {0, 0.5f, 0, 0.5f});
    const Rendered e = masked(MaskType::Luminance, none, false, true);
    check_pixel(e, 30, 30, {0, 0, 0, 0});
  }
  {  // The mask's own mask keeps only its left half.
    const Rendered r = masked(MaskType::Luminance, none, true, false);
    check_pixel(r, 5, 5, {0, 1, 0, 1});
    check_pixel(r, 30, 5, {0, 0, 0, 0});
    check_pixel(r, 5, 30, {0, 0.5f, 0, 0.5f});
  }
}

TEST_CASE("groups past the stack's depth: flattened, opacity folded into their content, one count", "[groups]") {
  // 16 groups of 0.9 keep their stack; 8 more are flattened into the 16th's
  // list. One square inside: folding is exact, 0.9^24 of red over blue.
  for (int depth : {16, 24}) {
    SceneBuilder b(40, 40);
    fill_box(b, 0, 0, 40, 40, {0, 0, 1, 1});
    Group g;
    g.opacity = 0.9f;
    for (int i = 0; i < depth; i++) b.begin_group(g);
    fill_box(b, 10, 10, 30, 30, {1, 0, 0, 1});
    for (int i = 0; i < depth; i++) b.end_group();
    const Scene s = b.finish();
    CHECK(b.flattened_groups() == size_t(std::max(0, depth - kMaxGroupDepth)));
    const Rendered r(s);
    float a = 1;
    for (int i = 0; i < depth; i++) a *= 0.9f;
    check_pixel(r, 20, 20, {a, 0, 1 - a, 1});
    check_pixel(r, 5, 5, {0, 0, 1, 1});
  }
  {  // Inside the 16th group: a group with a mask (the mask would be the
     // 18th level: dropped, the content unmasked) and a multiply group
     // (the 17th: drawn normally, opacity kept).
    SceneBuilder b(40, 40);
    fill_box(b, 0, 0, 40, 40, {0, 0, 1, 1});
    Group g;
    g.opacity = 0.999f;  // groups that stay groups
    for (int i = 0; i < kMaxGroupDepth - 1; i++) b.begin_group(g);
    Group masked;
    masked.opacity = 0.5f;
    b.begin_group(masked);
    Group mask;
    mask.mask = MaskType::Alpha;
    b.begin_group(mask);
    b.end_group();  // an empty mask: would hide everything
    fill_box(b, 0, 0, 20, 40, {1, 0, 0, 1});
    Group multiply;
    multiply.blend = BlendMode::Multiply;
    multiply.opacity = 0.5f;
    b.begin_group(multiply);
    fill_box(b, 20, 0, 40, 40, {0, 1, 0, 1});
    b.end_group();
    b.end_group();
    for (int i = 0; i < kMaxGroupDepth - 1; i++) b.end_group();
    const Scene s = b.finish();
    CHECK(b.flattened_groups() == 2);
    const Rendered r(s);
    float k = 1;
    for (int i = 0; i < kMaxGroupDepth - 1; i++) k *= 0.999f;
    // Left: red at 0.5 over blue, through groups of k. Right: green at
    // 0.5 x 0.5 (normal, not multiply) over blue.
    check_pixel(r, 5, 20, {0.5f * k, 0, 1 - 0.5f * k, 1});
    check_pixel(r, 35, 20, {0, 0.25f * k, 1 - 0.25f * k, 1});
  }
}

TEST_CASE("groups: the CPU tree is the same built and pruned a few cells at a time", "[groups][prune]") {
  // subdivide_cpu and prune_cpu work through a level in batches of cells
  // (cpu_batch_entries, ~1 M entries); batches of a few entries must build
  // the same tree, leaf for leaf.
  const size_t saved = cpu_batch_entries;
  size_t compared = 0;
  for (uint32_t seed = 300; seed < 330; seed++) {
    const random_groups::GroupScene gs = random_groups::group_scene(seed, 4, kSize);
    const EncodedScene enc = encode(gs.scene, Affine{}, Gamma::Srgb);
    cpu_batch_entries = size_t(1) << 20;
    const ShortcutTree whole = build_tree_cpu(enc, kSize, kSize, params(true));
    cpu_batch_entries = 1 + seed % 7;
    const ShortcutTree batched = build_tree_cpu(enc, kSize, kSize, params(true));
    cpu_batch_entries = saved;
    REQUIRE(batched.nodes.size() == whole.nodes.size());
    REQUIRE(batched.leaves.size() == whole.leaves.size());
    REQUIRE(batched.leaf_entries.size() == whole.leaf_entries.size());
    for (size_t i = 0; i < whole.leaf_entries.size(); i++) {
      REQUIRE(batched.leaf_entries[i].head == whole.leaf_entries[i].head);
      REQUIRE(batched.leaf_entries[i].data == whole.leaf_entries[i].data);
    }
    for (size_t i = 0; i < whole.leaves.size(); i++) {
      REQUIRE(batched.leaves[i].begin == whole.leaves[i].begin);
      REQUIRE(batched.leaves[i].end == whole.leaves[i].end);
    }
    compared += whole.leaf_entries.size();
  }
  CHECK(compared > 10000);
}

TEST_CASE("tree cap: a level past TreeParams::max_entries is not made, its parent's cells stay leaves",
          "[groups][tree]") {
  const random_groups::GroupScene gs = random_groups::group_scene(7, 4, kSize);
  const EncodedScene enc = encode(gs.scene, Affine{}, Gamma::Srgb);
  const ShortcutTree full = build_tree_cpu(enc, kSize, kSize, params(true));
  TreeParams capped = params(true);
  capped.max_entries = full.leaf_entries.size();  // less than all levels together
  const ShortcutTree coarse = build_tree_cpu(enc, kSize, kSize, capped);
  CHECK(coarse.depth < full.depth);
  // The same samples: the tree only accelerates.
  const Probe p = probe(gs.scene, enc, 7, 200);
  for (const auto& [px, py] : p.points) REQUIRE(oracle::identical(sample_tree_cpu(coarse, px, py), sample_tree_cpu(full, px, py)));
}
