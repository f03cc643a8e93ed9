// The built shortcut tree as host arrays: what the CPU builder produces, what
// the GPU builder's results are compared against, and what samplers read.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/geometry/abstract_segment.h"
#include "core/paint/paint_data.h"
#include "core/tree/shortcut_tree.h"

namespace mpvg {

// TreeParams::min_segments left to the renderer: plan_render resolves it
// from the samples per unit area (stop_rule); the builders take it resolved.
constexpr uint32_t kStopFromSamples = 0xffffffffu;

// Stopping criteria (paper §4.1).
struct TreeParams {
  // Subdivide cells with more geometry entries than this.
  uint32_t min_segments = kStopFromSamples;
  int max_depth = -1;           // deepest level; -1: down to 1-pixel cells
  // Cap on all levels' entries together (memory): a level that would pass
  // it is not made (the CPU counts it before making it), and its parent's
  // cells stay leaves, coarser. RenderOptions::memory_budget lowers it.
  size_t max_entries = size_t(1) << 27;
  bool prune = true;
  // Levels subdivided whole, without deciding or pruning: the coarse grid
  // of 4^k cells that starts the tree (the paper's future work, §7), k
  // levels of decisions, pruning rounds and their round trips saved. -1:
  // from the scene's density (tree_grid_levels).
  int grid_levels = -1;
  bool keep_levels = false;     // keep every level after pruning (tests, backend comparison)
};

// The stopping rule, auto-tuned from the sample cost (the paper's future
// work, §7): a leaf of n entries costs its samples times n tests, a
// subdivision a fixed cost per cell on either executor, so the threshold
// falls as the samples per unit area rise. Measured on both executors over
// the bench inputs (BENCHMARKS.md, "The stopping rule"): at 32 samples one
// entry is best (render 6-46 % faster than the paper's 4, the build no
// slower), at 8 samples 4-8. The rule depends on the options only, never on
// the executor, so that both build the same tree and give the same bytes.
inline uint32_t stop_rule(int samples) {
  const int m = 32 / (samples > 0 ? samples : 1);
  return static_cast<uint32_t>(m > 1 ? m : 1);
}
inline TreeParams resolve_stop_rule(TreeParams p, int samples) {
  if (p.min_segments == kStopFromSamples) p.min_segments = stop_rule(samples);
  return p;
}
// The builders' check (a TreeParams straight from RenderOptions has no rule yet).
inline void check_stop_rule(const TreeParams& p) {
  if (p.min_segments == kStopFromSamples)
    throw std::invalid_argument("TreeParams::min_segments unresolved: build with RenderPlan::tree (resolve_stop_rule)");
}

// One level of the tree during construction: its cells and their streams.
struct TreeLevel {
  std::vector<Cell> cells;
  std::vector<Entry> entries;
};

// One scene of a forest frame (frame/forest.h): its elements in the stream,
// the grid of unit areas it is rendered over, and the sampler
// specialisations its own paints need (sampler_kinds without and with
// aliasing): a scene renders with its own, as in a frame of its own, not
// with the forest's (a page of text next to one with patterns would take
// the slowest).
struct SceneRoot {
  uint32_t stream_begin = 0, stream_end = 0;
  int width = 0, height = 0;
  uint32_t kinds[2] = {0, 0};
};

struct ShortcutTree {
  uint32_t root_size = 1;  // power of two, >= image width and height
  std::vector<SceneRoot> roots;  // the tree's scenes (frame/forest.h): nodes 0 .. roots.size() - 1
  int depth = 0;           // deepest level that has cells
  std::vector<AbstractSegment> segments;
  std::vector<PathRecord> paths;
  std::shared_ptr<const PaintData> paint;  // shared with the tiles' trees
  std::vector<ShortcutTree> tiles;  // pattern tiles' trees (EncodedScene::tiles), top-level tree only
  uint32_t width = 0, height = 0;   // the grid of unit areas the tree was built over
  std::vector<Node> nodes;          // node 0 is the root
  std::vector<Cell> leaves;         // begin/end index leaf_entries
  std::vector<Entry> leaf_entries;
  std::vector<TreeLevel> levels;    // TreeParams::keep_levels only
  size_t peak_level_entries = 0;    // largest level, for memory reports
  bool capped = false;              // a level was not made: TreeParams::max_entries

  // Bytes of what sampling needs: segments, nodes, leaves and their
  // entries, paths, the tiles' trees, and the paint tables.
  size_t memory_bytes() const {
    size_t n = segments.size() * sizeof(AbstractSegment) + nodes.size() * sizeof(Node) +
               leaves.size() * sizeof(Cell) + leaf_entries.size() * sizeof(Entry) + paths.size() * sizeof(PathRecord);
    for (const ShortcutTree& t : tiles) n += t.memory_bytes();
    if (paint) n += paint->bytes();
    return n;
  }

  // The tree as a sampler reads it.
  TreeView view() const {
    return TreeView{nodes.data(),    leaves.data(), leaf_entries.data(), segments.data(),
                    paths.data(),    root_size,     width,               height,
                    0};
  }
};

// Smallest power of two that is at least max(width, height), and at least 1.
inline uint32_t tree_root_size(int width, int height) {
  const uint32_t m = static_cast<uint32_t>(width > height ? width : height);
  uint32_t s = 1;
  while (s < m) s <<= 1;
  return s;
}

// Deepest level allowed: cells of one pixel, or params.max_depth if smaller.
inline int tree_max_level(uint32_t root_size, const TreeParams& p) {
  int lv = 0;
  while ((root_size >> lv) > 1) lv++;
  return (p.max_depth >= 0 && p.max_depth < lv) ? p.max_depth : lv;
}

// Levels of the coarse grid (TreeParams::grid_levels) for a scene whose
// top level holds `entries` entries: level l is subdivided whole while its
// 4^l cells would average kGridCellFactor times min_segments geometry
// entries or more, so that most of them would be subdivided anyway (tiger
// at 1024 px: 3 levels; the density rule subdivides 2 of 4, 6 of 8 and 19
// of 24 cells at levels 1-3, the image covering a quarter of its 2048 px
// root square). Cells the grid subdivides that the rule would not have
// are cheap: their children hold as few entries.
constexpr size_t kGridCellFactor = 64;
MPVG_HD_INLINE int grid_levels_for(size_t entries, int max_level, uint32_t min_segments, int grid_levels) {
  int k = grid_levels;
  if (k < 0) {
    const size_t per_cell = kGridCellFactor * (min_segments > 0 ? min_segments : 1);
    k = 0;
    while (k < 16 && (entries >> (2 * k)) >= per_cell) k++;
  }
  return k < max_level ? k : max_level;
}
inline int tree_grid_levels(size_t entries, int max_level, const TreeParams& p) {
  return grid_levels_for(entries, max_level, p.min_segments, p.grid_levels);
}

// A forest (frame/forest.h) cannot subdivide whole levels: each root has the
// coarse grid of its own scene, root_grid[r] levels (tree_grid_levels of
// its own top level), so that its tree is the one a frame of its own
// builds. Its cells inside that grid are subdivided whatever they hold and
// not pruned (root_grid null: a single scene, whose grid is whole levels).
MPVG_HD_INLINE bool in_root_grid(const Cell& c, const uint8_t* root_grid) {
  return root_grid != nullptr && c.level < root_grid[c.root];
}

}  // namespace mpvg
