// Pruning (paper §4.3-4.4) and flat clipping (§5.2) on random scenes with
// random nested clip expressions:
//   - pruned and unpruned trees give bit-identical sample colours;
//   - the flat-clipping machine agrees with a recursive, stack-based
//     evaluation of the same scene expression with brute-force windings.
#include <algorithm>
#include <cmath>
#include <random>

#include "cpu/cpu_stages.h"
#include "frame/encoding.h"
#include "core/tree/flat_clipping.h"
#include "core/tree/pruning.h"
#include "core/sampling/sampling.h"
#include "tests/catch.h"
#include "tests/oracle.h"
#include "tests/random_scenes.h"
#include "frame/scene_info.h"

using namespace mpvg;

namespace {

constexpr int kSize = 64;

Scene random_clip_scene(uint32_t seed, int max_depth) { return random_scenes::clip_scene(seed, max_depth, kSize); }

// Recursive, stack-based evaluation of the scene stream (no short cuts):
// the reference semantics of §3.
struct Recursive {
  const Scene& scene;
  const EncodedScene& enc;
  const std::vector<int>& winding;
  size_t i = 0;
  Rgba4 color{0, 0, 0, 0};

  bool inside(uint32_t path) const { return path_inside(enc.paths[path].flags, winding[path]); }

  bool clip_union() {  // until '|' or ')'
    bool any = false;
    while (i < scene.stream.size()) {
      const Element& e = scene.stream[i];
      if (e.kind == ElementKind::Activate || e.kind == ElementKind::Pop) return any;
      i++;
      if (e.kind == ElementKind::Clip) {
        any = inside(e.path) || any;
      } else {  // nested clip-path: (clip-path* | clip-path*)
        const bool a = clip_union();
        i++;  // '|'
        const bool c = clip_union();
        i++;  // ')'
        any = (a && c) || any;
      }
    }
    return any;
  }

  void fill_list(bool draw) {  // until ')' or the end
    while (i < scene.stream.size()) {
      const Element& e = scene.stream[i];
      if (e.kind == ElementKind::Pop) return;
      i++;
      if (e.kind == ElementKind::Fill) {
        if (draw && inside(e.path)) {
          const PaintRecord& p = enc.paint->paints[enc.paths[e.path].paint];
          const float t = 1.0f - color.a;
          color = Rgba4{color.r + t * p.r, color.g + t * p.g, color.b + t * p.b, color.a + t * p.a};
        }
      } else {  // '(' clip-path* '|' fill* ')'
        const bool clip = clip_union();
        i++;  // '|'
        fill_list(draw && clip);
        i++;  // ')'
      }
    }
  }
};

Rgba4 tree_sample(const ShortcutTree& t, float px, float py) { return sample_tree_cpu(t, px, py); }

}  // namespace

TEST_CASE("flat clipping machine: hand-made streams", "[clip]") {
  // ( C1 | ... ) passes; ( C0 C1 | ) passes; ( (C1 | C0) | ) fails; ...
  // Drive the machine directly with delimiters and clip outcomes.
  FlatClip m = flat_clip_start();
  flat_clip_delimiter(m, ENTRY_PUSH);  // (
  flat_clip_pass(m);                   //   c1
  CHECK(m.state == FLAT_S);
  flat_clip_delimiter(m, ENTRY_PUSH);  //   ( skipped nested clip-path
  flat_clip_delimiter(m, ENTRY_ACTIVATE);
  flat_clip_delimiter(m, ENTRY_POP);
  CHECK(m.state == FLAT_S);
  flat_clip_delimiter(m, ENTRY_ACTIVATE);  // |
  CHECK(m.state == FLAT_P);                // the clip-path passed: draw its content
  flat_clip_delimiter(m, ENTRY_POP);
  CHECK(m.state == FLAT_P);
  CHECK(m.d == 0);

  m = flat_clip_start();
  flat_clip_delimiter(m, ENTRY_PUSH);      // (
  flat_clip_delimiter(m, ENTRY_PUSH);      //   ( nested clip-path
  flat_clip_pass(m);                       //     c1 in its clip section
  flat_clip_delimiter(m, ENTRY_ACTIVATE);  //     |
  CHECK(m.state == FLAT_P);                //     now its content section
  flat_clip_delimiter(m, ENTRY_POP);       //   ) content union failed: item false
  CHECK(m.state == FLAT_P);
  flat_clip_delimiter(m, ENTRY_ACTIVATE);  // | no item passed
  CHECK(m.state == FLAT_SA);
  flat_clip_delimiter(m, ENTRY_POP);
  CHECK(m.state == FLAT_P);

  m = flat_clip_start();
  flat_clip_delimiter(m, ENTRY_PUSH);      // (
  flat_clip_delimiter(m, ENTRY_PUSH);      //   (
  flat_clip_pass(m);                       //     c1
  flat_clip_delimiter(m, ENTRY_ACTIVATE);  //     |
  flat_clip_pass(m);                       //     c1 in the content section
  CHECK(m.state == FLAT_S);
  flat_clip_delimiter(m, ENTRY_POP);       //   ) the nested clip-path passed
  CHECK(m.state == FLAT_S);                //   so does the outer union
  CHECK(m.s == 1);
  flat_clip_delimiter(m, ENTRY_ACTIVATE);  // |
  CHECK(m.state == FLAT_P);
}

TEST_CASE("flat clipping agrees with recursive evaluation", "[clip]") {
  size_t compared = 0;
  for (uint32_t seed = 1; seed <= 60; seed++) {
    const Scene scene = random_clip_scene(seed, 3);
    const EncodedScene enc = encode(scene, Affine{}, Gamma::Srgb);
    const oracle::Windings brute(enc.segments, scene.paths.size());
    TreeParams params;
    params.min_segments = 8;
    const ShortcutTree tree = build_tree_cpu(enc, kSize, kSize, params);
    std::mt19937 rng(seed * 31);
    std::uniform_real_distribution<float> coord(0.0f, float(kSize));
    for (int n = 0; n < 300; n++) {
      const float px = coord(rng), py = coord(rng);
      const auto w = brute.at(px, py, 1e-3);
      if (!w) continue;
      Recursive r{scene, enc, *w};
      r.fill_list(true);
      const Rgba4 got = tree_sample(tree, px, py);
      INFO("seed " << seed << " point (" << px << ", " << py << ")\n" << dump(scene));
      REQUIRE(std::fabs(got.r - r.color.r) < 1e-4f);
      REQUIRE(std::fabs(got.g - r.color.g) < 1e-4f);
      REQUIRE(std::fabs(got.b - r.color.b) < 1e-4f);
      REQUIRE(std::fabs(got.a - r.color.a) < 1e-4f);
      compared++;
    }
  }
  CHECK(compared > 15000);
}

TEST_CASE("pruned and unpruned trees give identical samples", "[prune]") {
  size_t compared = 0, pruned_entries = 0, unpruned_entries = 0;
  // Solid paints, then paints of every kind: opaque gradients and textures
  // occlude like opaque colours (rule 14), translucent ones and patterns
  // do not.
  for (uint32_t seed = 100; seed < 190; seed++) {
    const Scene scene = seed < 160 ? random_clip_scene(seed, 4) : random_scenes::clip_scene(seed, 4, kSize, true);
    const EncodedScene enc = encode(scene, Affine{}, Gamma::Srgb);
    const oracle::Windings brute(enc.segments, scene.paths.size());
    for (int max_depth : {0, 3, -1}) {
      TreeParams on, off;
      on.max_depth = off.max_depth = max_depth;
      on.min_segments = off.min_segments = 4;
      off.prune = false;
      const ShortcutTree a = build_tree_cpu(enc, kSize, kSize, on);
      const ShortcutTree b = build_tree_cpu(enc, kSize, kSize, off);
      // Three levels of coarse grid (core/tree/tree.h): not pruned, subdivided
      // whole; the first level pruned then meets what they left.
      TreeParams coarse = on;
      coarse.grid_levels = 3;
      const ShortcutTree g = build_tree_cpu(enc, kSize, kSize, coarse);
      if (max_depth == -1)  // levels 0-2: 1 + 4 + 16 nodes, all subdivided
        for (size_t k = 0; k < 21; k++) REQUIRE(g.nodes[k].child == static_cast<int32_t>(1 + 4 * k));
      if (max_depth == 0) {
        pruned_entries += a.leaf_entries.size();
        unpruned_entries += b.leaf_entries.size();
      }
      std::mt19937 rng(seed);
      std::uniform_real_distribution<float> coord(0.0f, float(kSize));
      for (int n = 0; n < 200; n++) {
        const float px = coord(rng), py = coord(rng);
        // Away from curves, both trees must agree exactly.
        if (!brute.at(px, py, 1e-3)) continue;
        const Rgba4 x = tree_sample(a, px, py), y = tree_sample(b, px, py), z = tree_sample(g, px, py);
        INFO("seed " << seed << " depth " << max_depth << " point (" << px << ", " << py << "): " << x.r << " " << x.g
                      << " " << x.b << " " << x.a << " against " << y.r << " " << y.g << " " << y.b << " " << y.a);
        REQUIRE(oracle::identical(x, y));
        INFO("with the coarse grid: " << z.r << " " << z.g << " " << z.b << " " << z.a);
        REQUIRE(oracle::identical(z, y));
        compared++;
      }
    }
  }
  INFO("root-only trees: " << pruned_entries << " entries pruned vs " << unpruned_entries << " unpruned");
  CHECK(compared > 37000);
  CHECK(pruned_entries < unpruned_entries);
}

// Cross-links over all depths at once (core/tree/pruning.h: a stable sort by
// depth, a segmented max-scan, each element's links), against a stack walk
// of the stream: every element's group opening, each opening's '|' and ')',
// and each opening's enclosing group, on the streams of random scenes
// nested up to 6 deep, one scene after another as cells follow each other
// in a level.
TEST_CASE("pruning cross-links: one pass over all depths equals a stack walk", "[prune]") {
  std::vector<Entry> e;
  for (uint32_t seed = 300; seed < 340; seed++) {
    const EncodedScene enc = encode(random_scenes::clip_scene(seed, 2 + seed % 5, kSize), Affine{}, Gamma::Srgb);
    e.insert(e.end(), enc.stream.begin(), enc.stream.end());
  }
  const size_t n = e.size();
  std::vector<uint32_t> want_open(n, ~0u), want_bar(n, ~0u), want_close(n, ~0u), want_parent(n, ~0u), stack;
  for (uint32_t i = 0; i < n; i++) {
    if (entry_opens(e[i])) {
      if (!stack.empty()) want_parent[i] = stack.back();
      stack.push_back(i);
    }
    if (stack.empty()) continue;
    const uint32_t o = stack.back();
    want_open[i] = o;
    if (entry_kind(e[i]) == ENTRY_ACTIVATE) want_bar[o] = i;
    if (entry_closes(e[i])) {
      want_close[o] = i;
      stack.pop_back();
    }
  }
  REQUIRE(stack.empty());

  std::vector<int32_t> depth(n);
  int32_t max_depth = 0, acc = 0;
  for (uint32_t i = 0; i < n; i++) max_depth = std::max(max_depth, depth[i] = acc += prune_depth_delta(e.data(), i));
  REQUIRE(max_depth >= 4);
  std::vector<uint32_t> sorted(n);
  for (uint32_t i = 0; i < n; i++) sorted[i] = i;
  std::stable_sort(sorted.begin(), sorted.end(), [&](uint32_t a, uint32_t b) { return depth[a] < depth[b]; });
  std::vector<LinkSeg> last(n);
  for (uint32_t p = 0; p < n; p++) last[p] = prune_link_start(e.data(), sorted.data(), depth.data(), p);
  for (size_t p = 1; p < n; p++) last[p] = SegmentedMax<uint32_t>{}(last[p - 1], last[p]);
  std::vector<uint32_t> open(n, ~0u), bar(n, ~0u), close(n, ~0u), parent(n, ~0u);
  for (uint32_t p = 0; p < n; p++)
    prune_link(e.data(), sorted.data(), depth.data(), last.data(), static_cast<uint32_t>(n), p, open.data(),
               bar.data(), close.data(), parent.data());
  size_t nested = 0;
  for (uint32_t i = 0; i < n; i++) {
    INFO("element " << i << " of " << n << ", depth " << depth[i]);
    REQUIRE(open[i] == want_open[i]);
    REQUIRE(bar[i] == want_bar[i]);
    REQUIRE(close[i] == want_close[i]);
    REQUIRE(parent[i] == want_parent[i]);
    nested += parent[i] != ~0u;
  }
  CHECK(nested > 100);
}

// One round of pruning on hand-made streams of one cell: rules 16, 19 and
// 23 act on what the round's other rules leave, so nested groups that the
// round empties go at once, deepest first in effect, and a group left with
// one item dissolves in the same round.
TEST_CASE("pruning: one round empties and dissolves nested groups", "[prune]") {
  // Paths: 0 a fill outside the cell (F0), 1 and 3 translucent fills that
  // cover it (kept as they are), 2 a clip path covering the cell (C1), 4 a
  // clip path crossing it (a segment: undecided).
  // 5 an opaque fill of a mask that makes it 1, covering the cell.
  const std::vector<PathRecord> paths{{0, 0}, {0, 0}, {PATH_CLIP, 0}, {0, 0}, {PATH_CLIP, 0},
                                      {PATH_OPAQUE | PATH_MASK_FULL, 0}};
  const Entry f0 = make_entry(ENTRY_WINDING, 0, 0), p1 = make_entry(ENTRY_WINDING, 1, 1),
              c1 = make_entry(ENTRY_WINDING, 2, 1), p3 = make_entry(ENTRY_WINDING, 3, 1),
              c4 = make_entry(ENTRY_SEGMENT, 4, 0), m5 = make_entry(ENTRY_WINDING, 5, 1);
  const uint32_t dissolves = GROUP_ENTRY_SOLID | GROUP_ENTRY_DISSOLVES | GROUP_ENTRY_NORMAL;
  const uint32_t keeps = GROUP_ENTRY_NORMAL;  // translucent: never dissolves
  uint32_t id = 0;
  auto group = [&](uint32_t bits, std::vector<Entry> content) {
    std::vector<Entry> s{make_entry(ENTRY_GROUP, bits, id)};
    s.insert(s.end(), content.begin(), content.end());
    s.push_back(make_entry(ENTRY_GROUP, bits | GROUP_ENTRY_END, id++));
    return s;
  };
  auto clip = [](std::vector<Entry> section, std::vector<Entry> content) {
    std::vector<Entry> s{make_entry(ENTRY_PUSH, 0, 0)};
    s.insert(s.end(), section.begin(), section.end());
    s.push_back(make_entry(ENTRY_ACTIVATE, 0, 0));
    s.insert(s.end(), content.begin(), content.end());
    s.push_back(make_entry(ENTRY_POP, 0, 0));
    return s;
  };
  auto cat = [](std::vector<std::vector<Entry>> parts) {
    std::vector<Entry> s;
    for (auto& p : parts) s.insert(s.end(), p.begin(), p.end());
    return s;
  };
  auto round = [&](const std::vector<Entry>& s) {
    TreeLevel level;
    level.entries = s;
    level.cells.push_back(Cell{0, static_cast<uint32_t>(s.size()), 0, 0, 0, 0});
    prune_cpu(level, paths);
    REQUIRE(level.cells[0].begin == 0);
    REQUIRE(level.cells[0].end == level.entries.size());
    return level.entries;
  };
  auto same = [](const std::vector<Entry>& a, const std::vector<Entry>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); i++)
      if (a[i].head != b[i].head || a[i].data != b[i].data) return false;
    return true;
  };

  // {{{F0}}} P1 -> P1, whatever the groups.
  CHECK(same(round(cat({group(keeps, group(keeps, group(keeps, {f0}))), {p1}})), {p1}));
  // {{P1} {F0}} -> P1: the empty group goes, the two others dissolve.
  CHECK(same(round(group(dissolves, cat({group(dissolves, {p1}), group(dissolves, {f0})}))), {p1}));
  // Translucent outer group: {{P1} {F0}} -> {P1}.
  const std::vector<Entry> kept = round(group(keeps, cat({group(dissolves, {p1}), group(dissolves, {f0})})));
  REQUIRE(kept.size() == 3);
  CHECK(same({kept[1]}, {p1}));
  CHECK(entry_is_group_begin(kept[0]));
  // A clip group whose content the round empties: (C4 | {{F0}}) -> e.
  CHECK(round(clip({c4}, group(dissolves, group(keeps, {f0})))).empty());
  // Two items stay two: rule 17 dissolves the clip group, the group it
  // leaves in holds P1 and P3, and stays.
  const std::vector<Entry> two = round(group(dissolves, clip({c1}, {p1, p3})));
  REQUIRE(two.size() == 4);
  CHECK(same({two[1], two[2]}, {p1, p3}));
  // A mask that is 1 in the cell, inside its region's clip, goes with the
  // clip (rules 17, 21), and its group dissolves (23): {{(C1 | M)} P1} -> P1.
  CHECK(same(round(group(dissolves, cat({group(GROUP_ENTRY_MASK, clip({c1}, {m5})), {p1}}))), {p1}));
  // {A {F0}} with A one path: the empty group goes and the outer dissolves.
  CHECK(same(round(cat({{p3}, group(dissolves, cat({{p1}, group(keeps, {f0})}))})), {p3, p1}));
}
