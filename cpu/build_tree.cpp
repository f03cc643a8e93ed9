// Building the whole tree on the CPU: abstraction, the root, then breadth
// first, level by level, subdivision and pruning (paper §4.2).
#include <algorithm>
#include <chrono>

#include "cpu/cpu_stages.h"
#include "core/memory_budget.h"
#include "frame/forest.h"
#include "core/tree/subdivision.h"

namespace mpvg {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

uint32_t cell_weight(const TreeLevel& level, const Cell& c) {
  uint32_t w = 0;
  for (uint32_t i = c.begin; i < c.end; i++) w += entry_weight(level.entries[i]);
  return w;
}

}  // namespace

ShortcutTree build_tree_cpu(const EncodedScene& scene, int width, int height, const TreeParams& params,
                            BuildTimes* times, MemoryBudget* budget) {
  check_stop_rule(params);
  BuildTimes local;
  BuildTimes& t = times ? *times : local;
  ShortcutTree tree;
  tree.root_size = tree_root_size(width, height);
  tree.width = static_cast<uint32_t>(width);
  tree.height = static_cast<uint32_t>(height);
  tree.paths = scene.paths;
  tree.paint = scene.paint;
  // Pattern tiles' trees: built like any other, over their grids.
  TreeParams tile_params = params;
  tile_params.keep_levels = false;
  for (const EncodedTile& tile : scene.tiles)
    tree.tiles.push_back(build_tree_cpu(tile.scene, tile.width, tile.height, tile_params, &t, budget));

  auto t0 = std::chrono::steady_clock::now();
  std::vector<InputSegment> with_strokes;
  BudgetCharge strokes_held(budget);  // given back on return, with with_strokes
  if (!scene.strokes.empty()) {
    with_strokes = stroke_input_segments(scene, 0, budget);
    strokes_held.adopt((scene.segments.size() + with_strokes.size()) * sizeof(InputSegment));
    t.stroke_ms += ms_since(t0);
    t0 = std::chrono::steady_clock::now();
  }
  // The abstract segments: at least one an input segment, charged first;
  // the monotonic pieces past that once they are made.
  const std::vector<InputSegment>& input = scene.strokes.empty() ? scene.segments : with_strokes;
  charge(budget, input.size() * sizeof(AbstractSegment), "the abstract segments");
  tree.segments = abstract_cpu(input);
  if (tree.segments.size() > input.size())
    charge(budget, (tree.segments.size() - input.size()) * sizeof(AbstractSegment), "the abstract segments");
  t.abstract_ms += ms_since(t0);

  t0 = std::chrono::steady_clock::now();
  // One virtual cell per root (a forest's scenes, or the whole stream).
  TreeLevel virt;
  std::vector<uint32_t> at;
  virt.entries = initial_stream(scene, tree.segments, &at);
  tree.roots = scene_roots(scene, width, height);
  for (size_t r = 0; r < tree.roots.size(); r++)
    virt.cells.push_back(
        Cell{at[tree.roots[r].stream_begin], at[tree.roots[r].stream_end], 0, 0, 0, static_cast<uint16_t>(r)});
  auto level_bytes = [](const TreeLevel& l) {
    return uint64_t(l.entries.capacity()) * sizeof(Entry) + uint64_t(l.cells.capacity()) * sizeof(Cell);
  };
  BudgetCharge virt_held(budget, level_bytes(virt), "the tree's levels");
  TreeLevel level = subdivide_cpu(virt.cells, virt.entries.data(), tree.segments, tree.root_size, true);
  BudgetCharge level_held(budget, level_bytes(level), "the tree's levels");
  virt = TreeLevel{};
  virt_held.reset();
  t.subdivide_ms += ms_since(t0);
  const int max_level = tree_max_level(tree.root_size, params);
  // Levels [0, grid) are subdivided whole and not pruned (the coarse grid:
  // TreeParams::grid_levels); level `grid` is the first pruned. A forest's
  // roots have a grid each (in_root_grid).
  std::vector<uint8_t> root_grid;
  if (tree.roots.size() > 1)
    for (const Cell& c : level.cells)
      root_grid.push_back(static_cast<uint8_t>(tree_grid_levels(c.end - c.begin, max_level, params)));
  const uint8_t* rg = root_grid.empty() ? nullptr : root_grid.data();
  const int grid = rg ? 0 : tree_grid_levels(level.entries.size(), max_level, params);
  if (params.prune && grid == 0) {
    t0 = std::chrono::steady_clock::now();
    prune_cpu(level, tree.paths, rg);
    t.prune_ms += ms_since(t0);
  }

  size_t total_entries = level.entries.size();
  tree.nodes.assign(tree.roots.size(), Node{-1, 0});
  charge(budget, tree.nodes.capacity() * sizeof(Node), "the tree");
  uint32_t node_base = 0;  // node index of the current level's first cell
  for (int lv = 0;; lv++) {
    tree.depth = lv;
    tree.peak_level_entries = std::max(tree.peak_level_entries, level.entries.size());
    if (params.keep_levels) tree.levels.push_back(level);
    std::vector<char> sub(level.cells.size(), 0);
    size_t nsub = 0;
    if (lv < max_level) {
      for (size_t k = 0; k < level.cells.size(); k++) {
        sub[k] = lv < grid || in_root_grid(level.cells[k], rg) || cell_weight(level, level.cells[k]) > params.min_segments;
        nsub += sub[k] ? 1 : 0;
      }
    }
    TreeLevel child;
    BudgetCharge child_held(budget);
    if (nsub > 0) {
      t0 = std::chrono::steady_clock::now();
      // The cells to subdivide, their entries where they are.
      std::vector<Cell> parent;
      parent.reserve(nsub);
      for (size_t k = 0; k < level.cells.size(); k++)
        if (sub[k]) parent.push_back(level.cells[k]);
      bool over = total_entries >= params.max_entries;
      if (!over)
        child = subdivide_cpu(parent, level.entries.data(), tree.segments, tree.root_size, false,
                              params.max_entries - total_entries, &over);
      t.subdivide_ms += ms_since(t0);
      // (Made before it is charged: a level at most past the budget.)
      child_held = BudgetCharge(budget, level_bytes(child), "the tree's levels");
      if (over) {
        // Memory cap (criterion 1 of §4.1), found before the level's
        // entries are made: this level is the last, its cells coarser.
        nsub = 0;
        sub.assign(level.cells.size(), 0);
        tree.capped = true;
      }
    }
    // Nodes of this level's cells, leaves for those not subdivided. The
    // leaves' entries grow by exactly what this level adds (no doubling:
    // the old and new arrays are held together only while they move).
    const uint32_t child_base = node_base + static_cast<uint32_t>(level.cells.size());
    size_t leaf_add = 0, leaf_count = 0;
    for (size_t k = 0; k < level.cells.size(); k++)
      if (!sub[k]) leaf_add += level.cells[k].end - level.cells[k].begin, leaf_count++;
    const uint64_t old_bytes = tree.leaf_entries.capacity() * sizeof(Entry) + tree.leaves.capacity() * sizeof(Cell) +
                               tree.nodes.capacity() * sizeof(Node);
    const uint64_t new_bytes = (tree.leaf_entries.size() + leaf_add) * sizeof(Entry) +
                               (tree.leaves.size() + leaf_count) * sizeof(Cell) + (child_base + 4 * nsub) * sizeof(Node);
    charge(budget, new_bytes, "the tree");
    tree.leaf_entries.reserve(tree.leaf_entries.size() + leaf_add);
    tree.leaves.reserve(tree.leaves.size() + leaf_count);
    tree.nodes.reserve(child_base + 4 * nsub);
    if (budget) budget->release(old_bytes);
    tree.nodes.resize(child_base + 4 * nsub, Node{-1, 0});
    uint32_t m = 0;
    for (size_t k = 0; k < level.cells.size(); k++) {
      Node& node = tree.nodes[node_base + k];
      if (sub[k]) {
        node.child = static_cast<int32_t>(child_base + 4 * m++);
        continue;
      }
      Cell c = level.cells[k];
      node.child = -1;
      node.leaf = static_cast<uint32_t>(tree.leaves.size());
      const uint32_t b = static_cast<uint32_t>(tree.leaf_entries.size());
      tree.leaf_entries.insert(tree.leaf_entries.end(), level.entries.begin() + c.begin,
                               level.entries.begin() + c.end);
      c.begin = b;
      c.end = static_cast<uint32_t>(tree.leaf_entries.size());
      tree.leaves.push_back(c);
    }
    if (nsub == 0) break;
    if (params.prune && lv + 1 >= grid) {
      t0 = std::chrono::steady_clock::now();
      prune_cpu(child, tree.paths, rg);
      t.prune_ms += ms_since(t0);
    }
    total_entries += child.entries.size();
    node_base = child_base;
    level = std::move(child);
    level_held = std::move(child_held);
  }
  return tree;
}

}  // namespace mpvg
