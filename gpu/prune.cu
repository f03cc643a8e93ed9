// Stage "prune" on the GPU (§4.4): depth by an inclusive scan, one segmented
// scan per depth to cross-link delimiters, every element marking the
// elimination array with atomic increments and decrements, an inclusive scan,
// and an order-preserving compaction; repeated until nothing changes.
#include <thrust/iterator/transform_iterator.h>

#include "core/pruning.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 256;

__global__ void k_depth_delta(const Entry* e, size_t n, int32_t* depth) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n) depth[i] = prune_depth_delta(e, static_cast<uint32_t>(i));
}

__global__ void k_link_init(const Entry* e, const int32_t* depth, size_t n, int32_t d, Segmented<uint32_t>* link) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n) link[i] = Segmented<uint32_t>{1u, (entry_opens(e[i]) && depth[i] == d) ? 1u : 0u};
}

__global__ void k_link_apply(const Entry* e, const int32_t* depth, size_t n, int32_t d,
                             const Segmented<uint32_t>* link, uint32_t* open, uint32_t* bar, uint32_t* close,
                             uint32_t* parent) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  // A '(' or '{' one level deeper lies in the nearest '(' or '{' of depth d.
  if (depth[i] == d + 1 && entry_opens(e[i])) parent[i] = static_cast<uint32_t>(i) - (link[i].value - 1);
  if (depth[i] != d) return;
  const uint32_t o = static_cast<uint32_t>(i) - (link[i].value - 1);
  open[i] = o;
  const uint32_t k = entry_kind(e[i]);
  if (k == ENTRY_ACTIVATE) bar[o] = static_cast<uint32_t>(i);
  if (entry_closes(e[i])) close[o] = static_cast<uint32_t>(i);
}

__global__ void k_classify(const Entry* e, const uint32_t* entry_cell, size_t n, const Cell* cells,
                           const PathRecord* paths, uint32_t* term) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const Cell c = cells[entry_cell[i]];
  term[i] = prune_classify(e, static_cast<uint32_t>(i), c.begin, c.end, paths);
}

__global__ void k_first_c1(const uint32_t* term, size_t n, PruneLinks links, uint32_t* first_c1) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n && term[i] == TERM_C1 && prune_c1_in_content(links, static_cast<uint32_t>(i)))
    atomicMin(&first_c1[links.open[i]], static_cast<uint32_t>(i));
}

__global__ void k_mark(const Entry* e, const uint32_t* entry_cell, size_t n, const Cell* cells, const uint32_t* term,
                       PruneLinks links, int32_t* elim) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  auto add = [elim](uint32_t at, int32_t v) { atomicAdd(&elim[at], v); };
  const Cell c = cells[entry_cell[i]];
  prune_mark(e, term, links, static_cast<uint32_t>(i), c.begin, c.end, add);
}

// An element survives when its elimination count is not positive.
struct Kept {
  __host__ __device__ uint32_t operator()(int32_t elim) const { return elim <= 0 ? 1u : 0u; }
};

__global__ void k_compact(const Entry* e, const uint32_t* entry_cell, size_t n, const int32_t* elim,
                          const uint32_t* kpos, Entry* out, uint32_t* out_cell) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n && elim[i] <= 0) {
    out[kpos[i]] = e[i];
    out_cell[kpos[i]] = entry_cell[i];
  }
}

__global__ void k_cells_remap(Cell* cells, size_t ncells, const uint32_t* kpos) {
  const size_t k = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (k >= ncells) return;
  cells[k].begin = kpos[cells[k].begin];
  cells[k].end = kpos[cells[k].end];
}

}  // namespace

int Context::Impl::prune(DeviceLevel& lv) {
  // Without clip groups or transparency groups only rules 12 and 14 (at the
  // top level) apply; they depend on nothing another elimination can
  // change, so one round reaches the fixpoint, and there is no depth to
  // scan. With groups, the scene's nesting depth bounds every cell's: no
  // read-back is needed to know how many link scans to run.
  int rounds = 0;
  for (;;) {
    const size_t n = lv.nentries;
    if (n == 0) return rounds;
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

    if (scene_depth == 0) {
      MPVG_CUDA(cudaMemsetAsync(depth, 0, n * sizeof(int32_t)));
    } else {
      k_depth_delta<<<grid, kBlock>>>(e, n, depth);
      launched();
      prim.inclusive_sum(depth, depth, n);
      MPVG_CUDA(cudaMemsetAsync(open, 0xff, n * sizeof(uint32_t)));
      MPVG_CUDA(cudaMemsetAsync(bar, 0xff, n * sizeof(uint32_t)));
      MPVG_CUDA(cudaMemsetAsync(close, 0xff, n * sizeof(uint32_t)));
      MPVG_CUDA(cudaMemsetAsync(parent_of, 0xff, n * sizeof(uint32_t)));
      link.resize(n);
      for (int32_t d = 1; d <= scene_depth; d++) {
        k_link_init<<<grid, kBlock>>>(e, depth, n, d, link.data());
        launched();
        prim.inclusive_scan(link.data(), link.data(), SegmentedSum<uint32_t>{}, n);
        k_link_apply<<<grid, kBlock>>>(e, depth, n, d, link.data(), open, bar, close, parent_of);
        launched();
      }
    }

    k_classify<<<grid, kBlock>>>(e, lv.entry_cell.data(), n, lv.cells.data(), paths.data(), term);
    launched();
    const PruneLinks links{depth, open, bar, close, first_c1, parent_of};
    if (scene_depth > 0) {
      MPVG_CUDA(cudaMemsetAsync(first_c1, 0xff, n * sizeof(uint32_t)));
      k_first_c1<<<grid, kBlock>>>(term, n, links, first_c1);
      launched();
    }
    MPVG_CUDA(cudaMemsetAsync(elim, 0, (n + 1) * sizeof(int32_t)));
    k_mark<<<grid, kBlock>>>(e, lv.entry_cell.data(), n, lv.cells.data(), term, links, elim);
    launched();
    prim.inclusive_sum(elim, elim, n + 1);

    // Sweep: the exclusive scan of the keep flags gives every survivor its
    // slot and every cell its new range (item n only completes the scan).
    uint32_t* kpos = term;
    prim.exclusive_sum(thrust::make_transform_iterator(elim, Kept{}), kpos, n + 1);
    const size_t kept = read_u32(kpos + n);
    if (kept == n) return rounds;
    rounds++;
    DeviceLevel& out = parent;  // scratch level
    out.entries.resize(kept);
    out.entry_cell.resize(kept);
    k_compact<<<grid, kBlock>>>(e, lv.entry_cell.data(), n, elim, kpos, out.entries.data(), out.entry_cell.data());
    launched();
    k_cells_remap<<<grid_for(lv.ncells, kBlock), kBlock>>>(lv.cells.data(), lv.ncells, kpos);
    launched();
    lv.entries.swap(out.entries);
    lv.entry_cell.swap(out.entry_cell);
    lv.nentries = kept;
    if (scene_depth == 0) return rounds;
  }
}

}  // namespace mpvg::gpu
