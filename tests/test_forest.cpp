// Forest frames (core/forest.h): several scenes built into one tree render,
// scene by scene, to the images they have alone, bit for bit; no cell of
// the forest holds another scene's elements.
#include <random>

#include "core/cpu/cpu_stages.h"
#include "core/forest.h"
#include "core/renderer.h"
#include "core/sampling.h"
#include "tests/catch.h"
#include "tests/random_forest.h"

using namespace mpvg;

namespace {

void check_forest(const RenderOptions& like, uint32_t seeds) {
  for (uint32_t seed = 1; seed <= seeds; seed++) {
    const std::vector<random_forest::Page> ps = random_forest::pages(seed, like);
    std::vector<RenderPlan> plans;
    std::vector<EncodedScene> encs;
    std::vector<ImageF> alone;
    for (const random_forest::Page& p : ps) {
      REQUIRE(same_frame_options(p.options, like));
      plans.push_back(plan_render(p.options));
      encs.push_back(encode_for(p.scene, plans.back(), p.options.gamma));
      alone.push_back(render_cpu(encs.back(), plans.back(), p.options));
    }
    std::vector<FrameScene> frame;
    for (size_t k = 0; k < ps.size(); k++) frame.push_back(FrameScene{&encs[k], &plans[k], nullptr});
    const std::vector<ImageF> together = render_forest_cpu(frame, like);
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
  std::vector<ForestScene> fs;
  std::vector<size_t> path_end;
  size_t paths = 0;
  for (const random_forest::Page& p : ps) {
    const RenderPlan plan = plan_render(p.options);
    EncodedScene enc = encode_for(p.scene, plan, p.options.gamma);
    paths += enc.paths.size();
    path_end.push_back(paths);
    fs.push_back(ForestScene{std::move(enc), plan.frame.ua_w, plan.frame.ua_h});
  }
  const EncodedScene forest = make_forest(std::move(fs));
  REQUIRE(forest.roots.size() == ps.size());
  REQUIRE(forest.paths.size() == paths);
  int w = 0, h = 0;
  forest_grid(forest, w, h);
  TreeParams params;
  params.keep_levels = true;
  const ShortcutTree tree = build_tree_cpu(forest, w, h, params);
  CHECK(tree.roots == ps.size());
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
  for (uint32_t r = 0; r < tree.roots; r++) {
    const SceneRoot& sr = forest.roots[r];
    for (int y = 0; y < sr.height; y += 3)
      for (int x = 0; x < sr.width; x += 3)
        REQUIRE(tree.leaves[tree_find_leaf(tree.nodes.data(), tree.root_size, x, y, r)].root == r);
  }
  CHECK_THROWS(make_forest(std::vector<ForestScene>(kMaxForestRoots + 1)));
}
