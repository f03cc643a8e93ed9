// Stage "prune" on the GPU (§4.4), one round per level: depth by an
// inclusive scan, a sort by depth and one segmented scan to cross-link
// delimiters, every element marking the elimination array with atomic
// increments and decrements, an inclusive scan; with groups, rules 16, 19
// and 23 on what those marks leave (section counts, a sort by them, two
// prefix sums, two marking kernels: core/tree/pruning.h); then an exclusive
// scan and an order-preserving compaction.
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>
#include <thrust/iterator/transform_output_iterator.h>
#include <thrust/iterator/zip_iterator.h>
#include <thrust/tuple.h>

#include <algorithm>

#include "core/tree/pruning.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 256;

// Everything a round needs before its scans, in one launch (each launch
// costs the render thread 4-6 us of driver time, and a page's tree takes
// about a thousand of them: BENCHMARKS.md): each element's depth delta (or
// 0 without groups), its pruning term, its elimination count zeroed and
// its links unset, and (with groups) its index as the sort by depth's
// input. Thread n only zeroes the count the sweep's scan ends on; threads
// from the count to its bound (a driven frame) write the scans' identities.
__global__ void k_round_init(const Entry* e, const uint32_t* entry_cell, Count count, const Cell* cells,
                             const PathRecord* paths, bool groups, int32_t* depth, uint64_t* depth_section,
                             uint32_t* term, int32_t* elim, int32_t* elim2, uint32_t* open, uint32_t* bar,
                             uint32_t* close, uint32_t* first_c1, uint32_t* parent, uint32_t* index) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  const size_t n = count.get();
  if (i > count.n) return;
  if (i > n) {  // the sorts' padding (counted scans read nothing past n)
    if (groups && i < count.n) index[i] = static_cast<uint32_t>(i);
    return;
  }
  elim[i] = 0;
  if (groups) elim2[i] = 0;
  if (i == n) {
    if (groups && i < count.n) index[i] = static_cast<uint32_t>(i);
    return;
  }
  const Cell c = cells[entry_cell[i]];
  term[i] = prune_classify(e, static_cast<uint32_t>(i), c.begin, c.end, paths);
  if (!groups) {
    depth[i] = 0;
    return;
  }
  // Depth in the low word, section count in the high one: their sums are
  // never negative, so one 64-bit scan gives both (SplitDepthSection).
  depth_section[i] = static_cast<uint64_t>(static_cast<int64_t>(prune_depth_delta(e, static_cast<uint32_t>(i)))) +
                     (static_cast<uint64_t>(static_cast<int64_t>(prune_section_delta(e, static_cast<uint32_t>(i))))
                      << 32);
  open[i] = bar[i] = close[i] = first_c1[i] = parent[i] = ~0u;
  index[i] = static_cast<uint32_t>(i);
}

struct SplitDepthSection {
  __host__ __device__ thrust::tuple<int32_t, int32_t> operator()(uint64_t v) const {
    return thrust::make_tuple(static_cast<int32_t>(static_cast<uint32_t>(v)), static_cast<int32_t>(v >> 32));
  }
};

// The link scan's input at sorted position p (core/tree/pruning.h), read
// through a transform iterator instead of written by a kernel of its own.
// (Positions past a driven frame's count hold its padding, sorted last:
// no position before them reads theirs.)
struct LinkStart {
  const Entry* e;
  const uint32_t* sorted;
  const int32_t* depth;
  __host__ __device__ LinkSeg operator()(uint32_t p) const { return prune_link_start(e, sorted, depth, p); }
};

// Driven: the sort keys from the count to the bound above every real key.
__global__ void k_pad_keys(int32_t* key, Count n, int32_t pad) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n.n && i >= n.get()) key[i] = pad;
}

__global__ void k_link(const Entry* e, const uint32_t* sorted, const int32_t* depth, const LinkSeg* last, Count count,
                       uint32_t* open, uint32_t* bar, uint32_t* close, uint32_t* parent) {
  const size_t p = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  const size_t n = count.get();
  if (p < n)
    prune_link(e, sorted, depth, last, static_cast<uint32_t>(n), static_cast<uint32_t>(p), open, bar, close, parent);
}

__global__ void k_first_c1(const uint32_t* term, Count n, PruneLinks links, uint32_t* first_c1) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n.get() && term[i] == TERM_C1 && prune_c1_in_content(links, static_cast<uint32_t>(i)))
    atomicMin(&first_c1[links.open[i]], static_cast<uint32_t>(i));
}

__global__ void k_mark(const Entry* e, const uint32_t* entry_cell, Count n, const Cell* cells, const uint32_t* term,
                       PruneLinks links, int32_t* elim) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n.get()) return;
  auto add = [elim](uint32_t at, int32_t v) { atomicAdd(&elim[at], v); };
  const Cell c = cells[entry_cell[i]];
  prune_mark(e, term, links, static_cast<uint32_t>(i), c.begin, c.end, add);
}

// Rules 16, 19, 23 (core/tree/pruning.h): what shows at each position of the
// section order (0 past the end, where the exclusive scan ends), ...
struct Shows {
  const Entry* e;
  const int32_t* elim;
  const uint32_t* sorted;
  Count n;
  __host__ __device__ uint32_t operator()(uint32_t p) const {
    return p < n.get() ? prune_shows(e, elim, sorted[p]) : 0u;
  }
};

__global__ void k_empty(const Entry* e, const uint32_t* entry_cell, Count n, const Cell* cells, const int32_t* elim,
                        PruneLinks links, PruneShown shown, uint64_t* weight, int32_t* elim2) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  shown.n = static_cast<uint32_t>(n.get());
  if (i >= shown.n) return;
  auto add = [elim2](uint32_t at, int32_t v) { atomicAdd(&elim2[at], v); };
  weight[i] = prune_mark_empty(e, elim, links, shown, static_cast<uint32_t>(i), cells[entry_cell[i]].begin, add);
}

// ... the item weights in depth order ...
struct Weighs {
  const uint64_t* weight;
  const uint32_t* sorted;
  Count n;
  __host__ __device__ uint64_t operator()(uint32_t p) const {
    return p < n.get() ? weight[sorted[p]] : uint64_t{0};
  }
};

__global__ void k_unwrap(const Entry* e, Count n, const uint32_t* term, PruneLinks links, PruneItems items,
                         int32_t* elim2) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  items.n = static_cast<uint32_t>(n.get());
  if (i >= items.n) return;
  auto add = [elim2](uint32_t at, int32_t v) { atomicAdd(&elim2[at], v); };
  prune_mark_unwrap(e, term, links, items, static_cast<uint32_t>(i), add);
}

// An element survives when neither elimination count is positive (the
// second array only with groups).
struct Kept {
  const int32_t* elim;
  const int32_t* elim2;
  const uint32_t* entry_cell;
  const Cell* cells;
  const uint8_t* root_grid;  // a forest's cells inside their root's grid keep everything
  __host__ __device__ uint32_t operator()(uint32_t i) const {
    const size_t count = n.get();
    if (i >= count) return 0u;  // only completes the scan (and a driven frame's padding)
    if (root_grid && in_root_grid(cells[entry_cell[i]], root_grid)) return 1u;
    return elim[i] <= 0 && (!elim2 || elim2[i] <= 0) ? 1u : 0u;
  }
  Count n;
};

// The sweep, one launch: survivors to their slots (threads below n) and
// every cell's range renumbered (threads below ncells).
__global__ void k_compact(const Entry* e, const uint32_t* entry_cell, Count n, const uint32_t* kpos, Entry* out,
                          uint32_t* out_cell, Cell* cells, Count ncells) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n.get() && kpos[i + 1] != kpos[i]) {
    out[kpos[i]] = e[i];
    out_cell[kpos[i]] = entry_cell[i];
  }
  if (i < ncells.get()) {
    cells[i].begin = kpos[cells[i].begin];
    cells[i].end = kpos[cells[i].end];
  }
}

// Driven: the level's count after the sweep.
__global__ void k_pruned_size(const uint32_t* kpos, Count n, uint32_t* size) { size[0] = kpos[n.get()]; }

}  // namespace

void Context::Impl::prune(DeviceLevel& lv) {
  // One round (core/tree/pruning.h). Without clip groups or transparency groups
  // only rules 12 and 14 (at the top level) apply, and there is no depth to
  // scan. Driven (lv.driven), n is the level's bound and its count is on the
  // device: every launch and scan runs over the bound, the positions past
  // the count write the scans' identities, and the sorts' keys there sort
  // last.
  const size_t n = lv.nentries;
  if (n == 0) return;
  const Count cn = lv.entry_count();
  const unsigned grid = grid_for(n, kBlock);
  const Entry* e = lv.entries.data();
  int32_t* depth = (i32[0].resize(n), i32[0].data());
  int32_t* elim = (i32[1].resize(n + 1), i32[1].data());
  uint32_t* open = (u32[0].resize(n), u32[0].data());
  uint32_t* bar = (u32[1].resize(n), u32[1].data());
  uint32_t* close = (u32[2].resize(n), u32[2].data());
  uint32_t* term = (u32[3].resize(n + 1), u32[3].data());
  uint32_t* first_c1 = (u32[4].resize(n + 1), u32[4].data());
  uint32_t* parent_of = (u32[5].resize(n), u32[5].data());

  const bool groups = scene_depth > 0;
  uint32_t* index = groups ? (by_depth[2].resize(n), by_depth[2].data()) : nullptr;
  uint64_t* packed = groups ? (depth_section.resize(n), depth_section.data()) : nullptr;
  int32_t* sec = groups ? (section.resize(n), section.data()) : nullptr;
  int32_t* elim_b = groups ? (elim2.resize(n + 1), elim2.data()) : nullptr;
  k_round_init<<<grid_for(n + 1, kBlock), kBlock>>>(e, lv.entry_cell.data(), cn, lv.cells.data(), paths.data(),
                                                     groups, depth, packed, term, elim, elim_b, open, bar, close,
                                                     first_c1, parent_of, index);
  launched();
  // Driven, the padding's key sorts after every depth and section count.
  const int32_t pad = scene_depth + 1;
  const int bits = key_bits(static_cast<uint64_t>(lv.driven ? pad : scene_depth));
  uint32_t* sorted = nullptr;
  if (groups) {
    // Depths and section counts in one scan; then cross-links over all
    // depths at once (core/tree/pruning.h): a stable sort by depth, one
    // segmented scan, then each element's links.
    const auto split = thrust::make_transform_output_iterator(thrust::make_zip_iterator(depth, sec),
                                                              SplitDepthSection{});
    if (lv.driven) prim.counted_inclusive(packed, split, Plus{}, uint64_t{0}, cn);
    else prim.inclusive_sum(packed, split, n);
    if (lv.driven) {
      k_pad_keys<<<grid, kBlock>>>(depth, cn, pad);
      launched();
      k_pad_keys<<<grid, kBlock>>>(sec, cn, pad);
      launched();
    }
    sorted = (by_depth[0].resize(n), by_depth[0].data());
    uint32_t* sorted_depth = (by_depth[1].resize(n), by_depth[1].data());
    prim.sort_pairs(reinterpret_cast<const uint32_t*>(depth), sorted_depth, index, sorted, n, bits);
    link.resize(n);
    const auto start = thrust::make_transform_iterator(thrust::counting_iterator<uint32_t>(0), LinkStart{e, sorted, depth});
    if (lv.driven) prim.counted_inclusive(start, link.data(), SegmentedMax<uint32_t>{}, LinkSeg{0, 0}, cn);
    else prim.inclusive_scan(start, link.data(), SegmentedMax<uint32_t>{}, n);
    k_link<<<grid, kBlock>>>(e, sorted, depth, link.data(), cn, open, bar, close, parent_of);
    launched();
  }
  const PruneLinks links{depth, open, bar, close, first_c1, parent_of};
  if (groups) {
    k_first_c1<<<grid, kBlock>>>(term, cn, links, first_c1);
    launched();
  }
  k_mark<<<grid, kBlock>>>(e, lv.entry_cell.data(), cn, lv.cells.data(), term, links, elim);
  launched();
  if (lv.driven) prim.counted_inclusive(elim, elim, Plus{}, int32_t{0}, cn.and_one());
  else prim.inclusive_sum(elim, elim, n + 1);

  if (groups) {
    // Rules 16 and 19, then 23, on what those marks leave.
    uint32_t* by_sec = (by_section[0].resize(n), by_section[0].data());
    uint32_t* by_sec_keys = (by_section[1].resize(n), by_section[1].data());
    prim.sort_pairs(reinterpret_cast<const uint32_t*>(sec), by_sec_keys, index, by_sec, n, bits);
    uint32_t* shown_before = (shown.resize(n + 1), shown.data());
    const auto shows = thrust::make_transform_iterator(thrust::counting_iterator<uint32_t>(0),
                                                       Shows{e, elim, by_sec, cn});
    if (lv.driven) prim.counted_exclusive(shows, shown_before, Plus{}, uint32_t{0}, cn.and_one());
    else prim.exclusive_sum(shows, shown_before, n + 1);
    uint64_t* w = (weight.resize(n), weight.data());
    k_empty<<<grid, kBlock>>>(e, lv.entry_cell.data(), cn, lv.cells.data(), elim, links,
                              PruneShown{sec, by_sec, shown_before, static_cast<uint32_t>(n)}, w, elim_b);
    launched();
    uint64_t* item_sums = (items.resize(n + 1), items.data());
    const auto weighs = thrust::make_transform_iterator(thrust::counting_iterator<uint32_t>(0),
                                                        Weighs{w, sorted, cn});
    if (lv.driven) prim.counted_exclusive(weighs, item_sums, Plus{}, uint64_t{0}, cn.and_one());
    else prim.exclusive_sum(weighs, item_sums, n + 1);
    k_unwrap<<<grid, kBlock>>>(e, cn, term, links, PruneItems{sorted, item_sums, static_cast<uint32_t>(n)}, elim_b);
    launched();
    if (lv.driven) prim.counted_inclusive(elim_b, elim_b, Plus{}, int32_t{0}, cn.and_one());
    else prim.inclusive_sum(elim_b, elim_b, n + 1);
  }

  // Sweep: the exclusive scan of the keep flags gives every survivor its
  // slot and every cell its new range (item n only completes the scan).
  uint32_t* kpos = term;
  const auto keep = thrust::make_transform_iterator(thrust::counting_iterator<uint32_t>(0), Kept{elim, elim_b, lv.entry_cell.data(), lv.cells.data(), grid_of_root, cn});
  if (lv.driven) prim.counted_exclusive(keep, kpos, Plus{}, uint32_t{0}, cn.and_one());
  else prim.exclusive_sum(keep, kpos, n + 1);
  // No round trip: the survivors' count stays on the device, n bounds it,
  // and the level's counts bring it back (build_tree.cu).
  DeviceLevel& out = parent;  // scratch level
  out.entries.resize(n);
  out.entry_cell.resize(n);
  k_compact<<<grid_for(std::max(n, lv.ncells), kBlock), kBlock>>>(e, lv.entry_cell.data(), cn, kpos,
                                                                   out.entries.data(), out.entry_cell.data(),
                                                                   lv.cells.data(), lv.cell_count());
  launched();
  lv.entries.swap(out.entries);
  lv.entry_cell.swap(out.entry_cell);
  if (lv.driven) {
    k_pruned_size<<<1, 1>>>(kpos, cn, lv.size.data());
    launched();
  } else {
    lv.bound = true;
  }
}

}  // namespace mpvg::gpu
