// Stage "subdivide" on the GPU: the kernels of §4.2 over every cell of a
// level at once, the second and third as one scan (SplitScan). Pairs (parent entry, child) are laid out so that each
// child's block lists its parent's entries in order (as on the CPU):
//   pair(i, c) = fanout * begin(k) + c * size(k) + (i - begin(k)).
#include <algorithm>

#include "core/tree/subdivision.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 128;

__device__ __forceinline__ CellBox child_box(const Cell& pc, uint32_t c, bool root, uint32_t root_size) {
  if (root) return cell_box(0, 0, 0, root_size);
  return cell_box(static_cast<uint16_t>(2 * pc.ix + (c & 1)), static_cast<uint16_t>(2 * pc.iy + (c >> 1)),
                  static_cast<uint16_t>(pc.level + 1), root_size);
}

// Kernel 1: splits of one parent entry into each child cell, as items of
// the scan that consolidates windings and counts outputs (kernels 2 and 3
// of §4.2 in one: SplitScan, core/tree/subdivision.h). Thread 0 also writes the
// scan's leading identity (splits[0]: the scan goes to splits + 1, so that
// splits[j].count is pair j's offset) and zeroes the scatter's overflow
// flag (a device-driven frame's flag, overflow null, is never zeroed).
// With counts on the device (n only bounding the parent level's entries),
// threads past them write identity items (pad: a device scan over the
// bound follows; a counted one reads no padding): the pairs of the
// level's entries are the first fanout * n.get().
__global__ void k_split(const Entry* entries, const uint32_t* entry_cell, Count n, const Cell* cells,
                        const AbstractSegment* segments, uint32_t fanout, bool root, uint32_t root_size,
                        uint32_t* flags, SplitScan* items, SplitScan* splits, uint32_t* overflow, bool pad) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i == 0) {
    splits[0] = SplitScan{0, 0, 0, 0};
    if (overflow) *overflow = 0;
  }
  if (i >= n.n) return;
  if (i >= n.get()) {
    if (!pad) return;  // a counted scan reads no padding
    for (uint32_t c = 0; c < fanout; c++) items[fanout * i + c] = SplitScan{0, 0, 0, 0};
    return;
  }
  const Cell pc = cells[entry_cell[i]];
  const size_t size = pc.end - pc.begin;
  const Entry e = entries[i];
  const bool head = run_starts(entries, static_cast<uint32_t>(i), pc.begin);
  const bool last = run_ends(entries, static_cast<uint32_t>(i), pc.end);
  for (uint32_t c = 0; c < fanout; c++) {
    const size_t j = fanout * size_t(pc.begin) + c * size + (i - pc.begin);
    int32_t w;
    flags[j] = split_entry(e, segments, child_box(pc, c, root, root_size), &w);
    items[j] = split_scan_item(flags[j], w, head, last);
  }
}

// Scatter (kernel 4) into the child level, whose buffers hold `capacity`
// entries: a pair that would write past them raises the overflow flag.
// Threads below the parent level's cell count also write those cells'
// children (a launch saved), if the child level's `cells_capacity` holds
// them (a driven frame's k_child_size flags the level otherwise).
__device__ void child_cells(const Cell* cells, size_t k, uint32_t fanout, bool root, const SplitScan* splits,
                            Cell* out);

__global__ void k_scatter(const Entry* entries, const uint32_t* entry_cell, Count n_count, const Cell* cells,
                          Count cell_count, const LevelCounts* dev_counts, bool root, const AbstractSegment* segments,
                          uint32_t fanout, const uint32_t* flags, const SplitScan* splits, size_t capacity,
                          Entry* out, uint32_t* out_cell, uint32_t* overflow, Cell* out_cells,
                          size_t cells_capacity) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  size_t n = n_count.get(), ncells = cell_count.get();
  if (dev_counts) {  // n and ncells only bound them
    n = n < dev_counts->parent_entries ? n : dev_counts->parent_entries;
    ncells = ncells < dev_counts->sub ? ncells : dev_counts->sub;
  }
  if (i < ncells && fanout * ncells <= cells_capacity) child_cells(cells, i, fanout, root, splits, out_cells);
  if (i >= n) return;
  const uint32_t k = entry_cell[i];
  const Cell pc = cells[k];
  const size_t size = pc.end - pc.begin;
  const Entry e = entries[i];
  const bool last = run_ends(entries, static_cast<uint32_t>(i), pc.end);
  for (uint32_t c = 0; c < fanout; c++) {
    const size_t j = fanout * size_t(pc.begin) + c * size + (i - pc.begin);
    const uint32_t o = splits[j].count;
    if (size_t(splits[j + 1].count) > capacity) {
      atomicOr(overflow, 1u);
      continue;
    }
    const uint32_t m = split_scatter(e, flags[j], last, splits[j + 1].last, segments, out + o);
    for (uint32_t t = 0; t < m; t++) out_cell[o + t] = fanout * k + c;
  }
}

__device__ void child_cells(const Cell* cells, size_t k, uint32_t fanout, bool root, const SplitScan* splits,
                            Cell* out) {
  const Cell pc = cells[k];
  const size_t size = pc.end - pc.begin;
  for (uint32_t c = 0; c < fanout; c++) {
    Cell cc;
    cc.begin = splits[fanout * size_t(pc.begin) + c * size].count;
    cc.end = splits[fanout * size_t(pc.begin) + (c + 1) * size].count;
    cc.ix = root ? 0 : static_cast<uint16_t>(2 * pc.ix + (c & 1));
    cc.iy = root ? 0 : static_cast<uint16_t>(2 * pc.iy + (c >> 1));
    cc.level = root ? 0 : static_cast<uint16_t>(pc.level + 1);
    cc.root = pc.root;
    out[fanout * k + c] = cc;
  }
}

}  // namespace

void Context::Impl::subdivide_split(const DeviceLevel& from, Count n, uint32_t fanout, bool root, uint32_t* flags,
                                    uint32_t* zero_overflow, bool pad) {
  k_split<<<grid_for(n.n, kBlock), kBlock>>>(from.entries.data(), from.entry_cell.data(), n, from.cells.data(),
                                             segments.data(), fanout, root, root_size, flags, split_items.data(),
                                             splits.data(), zero_overflow, pad);
  launched();
}

void Context::Impl::subdivide_scatter(const DeviceLevel& from, Count n, Count ncells, const LevelCounts* counted,
                                      uint32_t fanout, bool root, const uint32_t* flags, DeviceLevel& to,
                                      uint32_t* overflow_flag) {
  if (n.n == 0 && ncells.n == 0) return;
  k_scatter<<<grid_for(std::max(n.n, ncells.n), kBlock), kBlock>>>(
      from.entries.data(), from.entry_cell.data(), n, from.cells.data(), ncells, counted, root, segments.data(),
      fanout, flags, splits.data(), to.entries.size(), to.entries.data(), to.entry_cell.data(), overflow_flag,
      to.cells.data(), to.cells.size());
  launched();
}

void Context::Impl::subdivide(const DeviceLevel& from, DeviceLevel& to, bool root, const LevelCounts* counted,
                              LevelCounts* tot) {
  const uint32_t fanout = root ? 1u : 4u;
  const size_t n = from.nentries;  // with `counted`, bounds of from's entries and cells
  const size_t pairs = fanout * n;
  uint32_t* flags = (u32[0].resize(pairs + 1), u32[0].data());
  split_items.resize(pairs + 1);
  splits.resize(pairs + 1);
  overflow.resize(1);
  if (n == 0) {
    MPVG_CUDA(cudaMemsetAsync(splits.data(), 0, sizeof(SplitScan)));
    MPVG_CUDA(cudaMemsetAsync(overflow.data(), 0, sizeof(uint32_t)));
  } else {
    subdivide_split(from, Count{n, counted ? &counted->parent_entries : nullptr}, fanout, root, flags,
                    overflow.data(), /*pad=*/true);
    // Windings consolidated and outputs counted in one scan, into splits[1 ..].
    prim.inclusive_scan(split_items.data(), splits.data() + 1, SplitScanOp{}, pairs);
  }
  // Scatter into the capacity the child buffers already have (they only
  // grow, so after the first frame this rarely fails), then read the total
  // and the overflow flag (zeroed by k_split) in one round trip; on
  // overflow, grow and redo.
  const size_t estimate = std::max(to.entries.capacity(), 2 * pairs + 1024);
  to.entries.resize(estimate);
  to.entry_cell.resize(estimate);
  to.ncells = fanout * from.ncells;
  to.cells.resize(to.ncells);
  to.driven = false;
  uint32_t total = 0, failed = 0;
  for (int attempt = 0;; attempt++) {
    if (attempt > 0) MPVG_CUDA(cudaMemsetAsync(overflow.data(), 0, sizeof(uint32_t)));
    subdivide_scatter(from, Count{n}, Count{from.ncells}, counted, fanout, root, flags, to, overflow.data());
    if (counted) {  // the level's counts come back with the total
      read_words({{&splits.data()[pairs].count, &total},
                  {overflow.data(), &failed},
                  {&counted->sub, &tot->sub},
                  {&counted->parent_entries, &tot->parent_entries},
                  {&counted->leaf_entries, &tot->leaf_entries},
                  {&counted->leaves, &tot->leaves}});
      to.ncells = fanout * size_t(tot->sub);
    } else {
      read_words({{&splits.data()[pairs].count, &total}, {overflow.data(), &failed}});
    }
    if (!failed) break;
    if (attempt > 0) throw Error("subdivision overflowed its grown buffers");
    to.entries.resize(total);
    to.entry_cell.resize(total);
  }
  to.entries.resize(total);
  to.entry_cell.resize(total);
  to.nentries = total;
  to.bound = false;
  most_entries = std::max(most_entries, size_t(total));
  most_cells = std::max(most_cells, to.ncells);
}

}  // namespace mpvg::gpu
