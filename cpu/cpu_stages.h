// The CPU executor: each stage runs the per-element functions of core/ in
// loops (threaded where it pays), with std algorithms for the scans. The
// CUDA executor (gpu/) runs the same functions with the same stage names.
#pragma once
#include <cstdint>
#include <vector>

#include "frame/encoding.h"
#include "core/sampling/integration.h"
#include "core/memory_budget.h"
#include "core/output/image.h"
#include "core/tree/tree.h"

namespace mpvg {

// abstract: one input segment at a time, order preserved.
std::vector<AbstractSegment> abstract_cpu(const std::vector<InputSegment>& input);

// The stream before the root exists: delimiters, and each path's abstract
// segments as SEGMENT entries (expanding the encoding's placeholders).
std::vector<Entry> initial_stream(const EncodedScene& scene, const std::vector<AbstractSegment>& segments,
                                  std::vector<uint32_t>* at = nullptr);

// Entries a batch of cells spans at most in subdivide_cpu and prune_cpu,
// whose per-pair and per-entry arrays grow with it (1 << 20: ~80 MB); a
// cell's stream is balanced, so batches are independent, and run on every
// core (a level of 65,536 entries or more is cut into at least one batch
// per core). Tests set it small to run many batches.
extern size_t cpu_batch_entries;

// Batches of a level's cells for subdivide_cpu and prune_cpu. batch_end:
// the end of the batch starting at cell k0, cells up to `limit` entries in
// all (a larger cell alone). cell_batches: the first cell of each batch of
// a level of `span` entries: batches of cpu_batch_entries, and from 65,536
// entries on, of at most a core's share of min(span, cpu_batch_entries).
// batch_group: how many batches from batch g run at once: up to `cores`,
// at most cpu_batch_entries entries in all (a larger batch alone).
size_t batch_end(const std::vector<Cell>& cells, size_t k0, size_t limit);
std::vector<size_t> cell_batches(const std::vector<Cell>& cells, size_t span, size_t cores);
size_t batch_group(const std::vector<Cell>& cells, const std::vector<size_t>& starts, size_t g, size_t cores);

// subdivide: the passes of §4.2, as one pass per batch of cells, over
// `cells` of a level (entries
// indexes their ranges; cells in ascending order, not necessarily
// adjacent), a batch of cells at a time. With root set, the one cell is
// the virtual cell holding the initial stream and the only child is the
// root cell. A level that would hold more than max_entries entries is not
// made: an empty level is returned and *overflow set.
TreeLevel subdivide_cpu(const std::vector<Cell>& cells, const Entry* entries,
                        const std::vector<AbstractSegment>& segments, uint32_t root_size, bool root,
                        size_t max_entries = SIZE_MAX, bool* overflow = nullptr);

// prune: one mark-and-sweep round (§4.4; core/tree/pruning.h). Its rules for
// what lists hold act on what its other rules leave, so one round reaches
// what rounds until nothing changes would but for rare chains (a clip
// section or mask emptied by the round; the next level's round takes
// those). Returns whether anything was eliminated.
// root_grid: a forest's cells in_root_grid are left as they are.
bool prune_cpu(TreeLevel& level, const std::vector<PathRecord>& paths, const uint8_t* root_grid = nullptr);

struct BuildTimes {
  double stroke_ms = 0, abstract_ms = 0, subdivide_ms = 0, prune_ms = 0;
};

// stroke: the scene's fills' input segments with its strokes' (stroke_cpu)
// added, grouped by path, as abstraction takes them.
// The result is charged to `budget` (the caller gives it back).
std::vector<InputSegment> stroke_input_segments(const EncodedScene& scene, int threads = 0,
                                                MemoryBudget* budget = nullptr);

// The whole tree: abstraction, root, then level by level subdivision and
// pruning until the stopping criteria hold everywhere. A forest's (scene.
// roots, frame/forest.h) has one root per scene; width x height is then
// forest_grid's.
// What the build holds is charged to `budget` (if any): its scratch while
// it runs, the tree's arrays for as long as the budget lives.
ShortcutTree build_tree_cpu(const EncodedScene& scene, int width, int height, const TreeParams& params,
                            BuildTimes* times = nullptr, MemoryBudget* budget = nullptr);


struct RenderTimes {
  double schedule_ms = 0, sample_ms = 0;
  uint64_t samples = 0;  // samples evaluated (adaptive sampling: core/sampling/sampling.h, unit_area_flat)
};

// schedule + sample + integrate: every unit area of frame is sampled with
// its class's pattern (integ.offsets) in the leaf that holds it, integrated
// as integ says (integration.h) and composited over background
// (premultiplied). The tree must have been built over the frame's unit-area
// grid. threads = 0: all cores. In a forest, the scene of root `root`,
// over its own grid.
ImageF render_tree_cpu(const ShortcutTree& tree, const Integration& integ, const IntegrationFrame& frame,
                       const PaintRecord& background, int threads, RenderTimes* times = nullptr,
                       uint32_t root = 0);

// The same frame as 8-bit codes (what to_rgba8 gives of render_tree_cpu's
// image, without the float image).
std::vector<uint8_t> render_tree_cpu_rgba8(const ShortcutTree& tree, const Integration& integ,
                                           const IntegrationFrame& frame, const PaintRecord& background, Gamma gamma,
                                           int threads, RenderTimes* times = nullptr, uint32_t root = 0);

// The colour of one sample at (px, py), straight from the tree (tests and
// tools): premultiplied, in the integration colour space, no background.
Rgba4 sample_tree_cpu(const ShortcutTree& tree, float px, float py, uint32_t root = 0);

// The colours of the n samples (px[k], py[k]) of leaf `leaf` of the tree
// by the sampler specialisation `kinds` (sampler_kinds), taken both as the
// renders take them, together (sample_cell_lanes), and one by one
// (sample_cell): test_sample_lanes compares them bit for bit.
void sample_leaf_cpu(const ShortcutTree& tree, uint32_t leaf, uint32_t kinds, const float* px, const float* py, int n,
                     Rgba4* together, Rgba4* one_by_one);

// The box filter over width x height pixels (the tree built over them).
ImageF render_tree_cpu(const ShortcutTree& tree, int width, int height, const std::vector<SampleOffset>& pattern,
                       const PaintRecord& background, int threads, RenderTimes* times = nullptr);

}  // namespace mpvg
