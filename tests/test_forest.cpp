// Forest frames (frame/forest.h): several scenes built into one tree render,
// scene by scene, to the images they have alone, bit for bit; no cell of
// the forest holds another scene's elements.
#include <random>

#include "cpu/cpu_stages.h"
#include "frame/forest.h"
#include "frame/frame.h"
#include "core/sampling/sampling.h"
#include "tests/catch.h"
#include "tests/random_forest.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"

using namespace mpvg;

namespace {

void check_forest(const RenderOptions& like, uint32_t seeds) {
  for (uint32_t seed = 1; seed <= seeds; seed++) {
    const std::vector<random_forest::Page> ps = random_forest::pages(seed, like);
    for (const random_forest::Page& p : ps) REQUIRE(same_frame_options(p.options, like));
    const random_forest::Encoded e = random_forest::encoded(ps);
    std::vector<ImageF> alone;
    for (size_t k = 0; k < ps.size(); k++) alone.push_back(render_cpu(e.scenes[k], e.plans[k], ps[k].options));
    const std::vector<ImageF> together = render_forest_cpu(e.frame, like);
    REQUIRE(together.size() == ps.size());
    for (size_t k = 0; k < ps.size(); k++) {
      INFO("seed " << seed << ", scene " << k);
      REQUIRE(together[k].width == alone[k].width);
      REQUIRE(together[k].height == alone[k].height);
      size_t differ = 0;
      for (size_t i = 0; i < alone[k].rgba.size(); i++) differ += together[k].rgba[i] != alone[k].rgba[i];
      CHECK(differ == 0);
    }
  }
}

}  // namespace

TEST_CASE("forest: each scene renders as it does alone, bit for bit (box, 32 samples)", "[forest]") {
  RenderOptions o;
  o.threads = 2;
  check_forest(o, 6);
}

TEST_CASE("forest: the same with a wide filter, aliased paths and no coarse grid", "[forest]") {
  RenderOptions o;
  o.threads = 2;
  o.samples = 8;
  o.filter = Filter::Cardinal;
  o.aliased_paths = true;
  check_forest(o, 3);
  o.filter = Filter::Box;
  o.samples = 32;
  o.aliased_paths = false;
  o.tree.grid_levels = 0;
  check_forest(o, 3);
}

TEST_CASE("forest: every cell holds its own scene's elements only, every root reaches its leaves", "[forest]") {
  RenderOptions like;
  const std::vector<random_forest::Page> ps = random_forest::pages(7, like);
  std::vector<EncodedScene> encs;
  std::vector<ForestScene> fs;
  std::vector<size_t> path_end;
  size_t paths = 0;
  encs.reserve(ps.size());
  for (const random_forest::Page& p : ps) {
    const RenderPlan plan = plan_render(p.options);
    encs.push_back(encode_for(p.scene, plan, p.options.gamma));
    paths += encs.back().paths.size();
    path_end.push_back(paths);
    fs.push_back(ForestScene{&encs.back(), plan.frame.ua_w, plan.frame.ua_h});
  }
  const EncodedScene forest = make_forest(fs);
  REQUIRE(forest.roots.size() == ps.size());
  REQUIRE(forest.paths.size() == paths);
  int w = 0, h = 0;
  forest_grid(forest, w, h);
  TreeParams params;
  params.min_segments = stop_rule(32);
  params.keep_levels = true;
  const ShortcutTree tree = build_tree_cpu(forest, w, h, params);
  CHECK(tree.roots.size() == ps.size());
  auto owner = [&](uint32_t path) {
    size_t r = 0;
    while (path >= path_end[r]) r++;
    return r;
  };
  size_t checked = 0;
  for (const TreeLevel& level : tree.levels)
    for (const Cell& c : level.cells)
      for (uint32_t i = c.begin; i < c.end; i++) {
        const Entry e = level.entries[i];
        if (entry_is_delimiter(e)) continue;
        REQUIRE(owner(entry_path(e)) == c.root);
        checked++;
      }
  CHECK(checked > 1000);
  // Root r's leaves are the ones found from node r.
  for (uint32_t r = 0; r < tree.roots.size(); r++) {
    const SceneRoot& sr = forest.roots[r];
    for (int y = 0; y < sr.height; y += 3)
      for (int x = 0; x < sr.width; x += 3)
        REQUIRE(tree.leaves[tree_find_leaf(tree.nodes.data(), tree.root_size, x, y, r)].root == r);
  }
  CHECK_THROWS(make_forest(std::vector<ForestScene>(kMaxForestRoots + 1)));
}

TEST_CASE("forest: each root's leaves are those of the scene's own tree", "[forest]") {
  // The shape of a scene's tree (its coarse grid, pruning, decisions) is
  // its own in a forest: root r's leaves, in order, have the cells and
  // entry counts of the tree built for the scene alone.
  size_t leaves = 0;
  for (uint32_t seed = 1; seed <= 4; seed++)
    for (int grid : {-1, 2}) {
      RenderOptions like;
      like.tree.grid_levels = grid;
      const std::vector<random_forest::Page> ps = random_forest::pages(seed, like);
      std::vector<EncodedScene> encs;
      std::vector<ForestScene> fs;
      std::vector<ShortcutTree> alone;
      encs.reserve(ps.size());
      for (const random_forest::Page& p : ps) {
        const RenderPlan plan = plan_render(p.options);
        encs.push_back(encode_for(p.scene, plan, p.options.gamma));
        alone.push_back(build_tree_cpu(encs.back(), plan.frame.ua_w, plan.frame.ua_h, plan.tree));
        fs.push_back(ForestScene{&encs.back(), plan.frame.ua_w, plan.frame.ua_h});
      }
      const EncodedScene forest = make_forest(fs);
      int w = 0, h = 0;
      forest_grid(forest, w, h);
      const ShortcutTree tree = build_tree_cpu(forest, w, h, resolve_stop_rule(like.tree, like.samples));
      for (uint32_t r = 0; r < ps.size(); r++) {
        INFO("seed " << seed << ", grid " << grid << ", root " << r);
        std::vector<Cell> mine;
        for (const Cell& c : tree.leaves)
          if (c.root == r) mine.push_back(c);
        REQUIRE(mine.size() == alone[r].leaves.size());
        for (size_t k = 0; k < mine.size(); k++) {
          const Cell &a = mine[k], &b = alone[r].leaves[k];
          REQUIRE((a.ix == b.ix && a.iy == b.iy && a.level == b.level && a.end - a.begin == b.end - b.begin));
        }
        leaves += mine.size();
      }
    }
  CHECK(leaves > 5000);
}

TEST_CASE("forest: empty scenes and a forest of one", "[forest]") {
  RenderOptions o;
  o.width = o.height = 60;
  o.background = RGBA{0.2f, 0.4f, 0.6f, 1};
  const RenderPlan plan = plan_render(o);
  const Scene empty = SceneBuilder(60, 60).finish();
  const Scene full = random_scenes::clip_scene(11, 2, 60, true);
  const EncodedScene e0 = encode_for(empty, plan, o.gamma), e1 = encode_for(full, plan, o.gamma);
  for (const std::vector<const EncodedScene*>& order :
       {std::vector<const EncodedScene*>{&e0, &e1, &e0}, {&e1}, {&e0}}) {
    std::vector<FrameScene> frame;
    for (const EncodedScene* e : order) frame.push_back(FrameScene{e, &plan, nullptr});
    const std::vector<ImageF> together = render_forest_cpu(frame, o);
    REQUIRE(together.size() == order.size());
    for (size_t k = 0; k < order.size(); k++) CHECK(together[k].rgba == render_cpu(*order[k], plan, o).rgba);
  }
}

TEST_CASE("forest: scenes whose root squares differ are refused, not rendered differently", "[forest]") {
  RenderOptions a, b;
  a.width = a.height = 100;  // root square 128
  b.width = b.height = 200;  // 256
  const RenderPlan pa = plan_render(a), pb = plan_render(b);
  CHECK(!same_frame_grid(pa, pb));
  CHECK(same_frame_grid(pa, plan_render(RenderOptions{a})));
  const Scene s = random_scenes::clip_scene(5, 2, 100);
  const EncodedScene ea = encode_for(s, pa, a.gamma), eb = encode_for(s, pb, b.gamma);
  CHECK_THROWS(render_forest_cpu({FrameScene{&ea, &pa, nullptr}, FrameScene{&eb, &pb, nullptr}}, a));
}

TEST_CASE("forest: a forest over the entry cap is refused (its scenes' trees would be coarser)", "[forest]") {
  RenderOptions like;
  like.tree.max_entries = 3000;
  const random_forest::Encoded e = random_forest::encoded(random_forest::pages(3, like));
  CHECK_THROWS_WITH(render_forest_cpu(e.frame, like), kForestCapped);
}
