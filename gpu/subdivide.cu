// Stage "subdivide" on the GPU: the four kernels of §4.2 over every cell of
// a level at once. Pairs (parent entry, child) are laid out so that each
// child's block lists its parent's entries in order (as on the CPU):
//   pair(i, c) = fanout * begin(k) + c * size(k) + (i - begin(k)).
#include <algorithm>

#include "core/subdivision.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 128;

__device__ __forceinline__ CellBox child_box(const Cell& pc, uint32_t c, bool root, uint32_t root_size) {
  if (root) return cell_box(0, 0, 0, root_size);
  return cell_box(static_cast<uint16_t>(2 * pc.ix + (c & 1)), static_cast<uint16_t>(2 * pc.iy + (c >> 1)),
                  static_cast<uint16_t>(pc.level + 1), root_size);
}

// Kernel 1: splits of one parent entry into each child cell.
__global__ void k_split(const Entry* entries, const uint32_t* entry_cell, size_t n, const Cell* cells,
                        const AbstractSegment* segments, uint32_t fanout, bool root, uint32_t root_size,
                        uint32_t* flags, Segmented<int32_t>* wind) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const Cell pc = cells[entry_cell[i]];
  const size_t size = pc.end - pc.begin;
  const Entry e = entries[i];
  const uint32_t head = run_starts(entries, static_cast<uint32_t>(i), pc.begin) ? 1u : 0u;
  for (uint32_t c = 0; c < fanout; c++) {
    const size_t j = fanout * size_t(pc.begin) + c * size + (i - pc.begin);
    int32_t w;
    flags[j] = split_entry(e, segments, child_box(pc, c, root, root_size), &w);
    wind[j] = Segmented<int32_t>{w, head};
  }
}

// Kernel 3 input: outputs of each pair, with room for one winding entry per
// path run whose consolidated winding is non-zero.
__global__ void k_count(const Entry* entries, const uint32_t* entry_cell, size_t n, const Cell* cells,
                        uint32_t fanout, const uint32_t* flags, const Segmented<int32_t>* wind, uint32_t* count,
                        size_t pairs, uint32_t* overflow) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  // Thread 0 also zeroes the item that ends the offsets' scan and the
  // scatter's overflow flag (launches saved: each costs the render thread
  // more than the work of a small kernel).
  if (i == 0) {
    count[pairs] = 0;
    *overflow = 0;
  }
  if (i >= n) return;
  const Cell pc = cells[entry_cell[i]];
  const size_t size = pc.end - pc.begin;
  const bool last = run_ends(entries, static_cast<uint32_t>(i), pc.end);
  for (uint32_t c = 0; c < fanout; c++) {
    const size_t j = fanout * size_t(pc.begin) + c * size + (i - pc.begin);
    count[j] = split_output_count(flags[j], last, wind[j].value);
  }
}

// Kernel 4: scatter into the child level, whose buffers hold `capacity`
// entries: a pair that would write past them raises the overflow flag.
// Threads below the parent level's cell count also write those cells'
// children (k_child_cells' work: a launch saved).
__device__ void child_cells(const Cell* cells, size_t k, uint32_t fanout, bool root, const uint32_t* offset,
                            Cell* out);

__global__ void k_scatter(const Entry* entries, const uint32_t* entry_cell, size_t n, const Cell* cells,
                          size_t ncells, bool root, const AbstractSegment* segments, uint32_t fanout,
                          const uint32_t* flags, const Segmented<int32_t>* wind, const uint32_t* offset,
                          const uint32_t* count, size_t capacity, Entry* out, uint32_t* out_cell, uint32_t* overflow,
                          Cell* out_cells) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < ncells) child_cells(cells, i, fanout, root, offset, out_cells);
  if (i >= n) return;
  const uint32_t k = entry_cell[i];
  const Cell pc = cells[k];
  const size_t size = pc.end - pc.begin;
  const Entry e = entries[i];
  const bool last = run_ends(entries, static_cast<uint32_t>(i), pc.end);
  for (uint32_t c = 0; c < fanout; c++) {
    const size_t j = fanout * size_t(pc.begin) + c * size + (i - pc.begin);
    const uint32_t o = offset[j];
    if (o + size_t(count[j]) > capacity) {
      atomicOr(overflow, 1u);
      continue;
    }
    const uint32_t m = split_scatter(e, flags[j], last, wind[j].value, segments, out + o);
    for (uint32_t t = 0; t < m; t++) out_cell[o + t] = fanout * k + c;
  }
}

__device__ void child_cells(const Cell* cells, size_t k, uint32_t fanout, bool root, const uint32_t* offset,
                            Cell* out) {
  const Cell pc = cells[k];
  const size_t size = pc.end - pc.begin;
  for (uint32_t c = 0; c < fanout; c++) {
    Cell cc;
    cc.begin = offset[fanout * size_t(pc.begin) + c * size];
    cc.end = offset[fanout * size_t(pc.begin) + (c + 1) * size];
    cc.ix = root ? 0 : static_cast<uint16_t>(2 * pc.ix + (c & 1));
    cc.iy = root ? 0 : static_cast<uint16_t>(2 * pc.iy + (c >> 1));
    cc.level = root ? 0 : static_cast<uint16_t>(pc.level + 1);
    cc.pad = 0;
    out[fanout * k + c] = cc;
  }
}

}  // namespace

void Context::Impl::subdivide(const DeviceLevel& from, DeviceLevel& to, bool root) {
  const uint32_t fanout = root ? 1u : 4u;
  const size_t n = from.nentries;
  const size_t pairs = fanout * n;
  uint32_t* flags = (u32[0].resize(pairs + 1), u32[0].data());
  uint32_t* count = (u32[1].resize(pairs + 1), u32[1].data());
  uint32_t* offset = (u32[2].resize(pairs + 1), u32[2].data());
  wind.resize(pairs + 1);
  overflow.resize(1);
  if (n == 0) {
    MPVG_CUDA(cudaMemsetAsync(count + pairs, 0, sizeof(uint32_t)));
    MPVG_CUDA(cudaMemsetAsync(overflow.data(), 0, sizeof(uint32_t)));
  } else {
    k_split<<<grid_for(n, kBlock), kBlock>>>(from.entries.data(), from.entry_cell.data(), n, from.cells.data(),
                                             segments.data(), fanout, root, root_size, flags, wind.data());
    launched();
    prim.inclusive_scan(wind.data(), wind.data(), SegmentedSum<int32_t>{}, pairs);
    k_count<<<grid_for(n, kBlock), kBlock>>>(from.entries.data(), from.entry_cell.data(), n, from.cells.data(),
                                             fanout, flags, wind.data(), count, pairs, overflow.data());
    launched();
  }
  prim.exclusive_sum(count, offset, pairs + 1);
  // Scatter into the capacity the child buffers already have (they only
  // grow, so after the first frame this rarely fails), then read the total
  // and the overflow flag (zeroed by k_count) in one round trip; on
  // overflow, grow and redo.
  const size_t estimate = std::max(to.entries.capacity(), 2 * pairs + 1024);
  to.entries.resize(estimate);
  to.entry_cell.resize(estimate);
  to.ncells = fanout * from.ncells;
  to.cells.resize(to.ncells);
  uint32_t total = 0, failed = 0;
  for (int attempt = 0;; attempt++) {
    if (attempt > 0) MPVG_CUDA(cudaMemsetAsync(overflow.data(), 0, sizeof(uint32_t)));
    if (n || from.ncells) {
      k_scatter<<<grid_for(std::max(n, from.ncells), kBlock), kBlock>>>(
          from.entries.data(), from.entry_cell.data(), n, from.cells.data(), from.ncells, root, segments.data(),
          fanout, flags, wind.data(), offset, count, to.entries.size(), to.entries.data(), to.entry_cell.data(),
          overflow.data(), to.cells.data());
      launched();
    }
    read_words({{offset + pairs, &total}, {overflow.data(), &failed}});
    if (!failed) break;
    if (attempt > 0) throw Error("subdivision overflowed its grown buffers");
    to.entries.resize(total);
    to.entry_cell.resize(total);
  }
  to.entries.resize(total);
  to.entry_cell.resize(total);
  to.nentries = total;
  to.bound = false;
}

}  // namespace mpvg::gpu
