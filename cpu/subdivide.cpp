// Stage "subdivide" on the CPU: the passes of §4.2 (split; the segmented
// scan of windings and the offset scan; scatter), as one sequential pass
// over each batch of a level's cells, a large level's batches on every core.
#include <algorithm>
#include <cstdint>

#include "cpu/cpu_stages.h"
#include "core/parallel.h"
#include "core/tree/subdivision.h"

namespace mpvg {

size_t cpu_batch_entries = size_t(1) << 20;

size_t batch_end(const std::vector<Cell>& cells, size_t k0, size_t limit) {
  size_t k1 = k0 + 1;
  while (k1 < cells.size() && cells[k1].end - cells[k0].begin <= limit) k1++;
  return k1;
}

std::vector<size_t> cell_batches(const std::vector<Cell>& cells, size_t span, size_t cores) {
  constexpr size_t kParallelEntries = size_t(1) << 16;
  size_t limit = cpu_batch_entries;
  if (span >= kParallelEntries && cores > 1) limit = std::min(cpu_batch_entries, span) / cores + 1;
  std::vector<size_t> starts;
  for (size_t k0 = 0; k0 < cells.size(); k0 = batch_end(cells, k0, limit)) starts.push_back(k0);
  return starts;
}

size_t batch_group(const std::vector<Cell>& cells, const std::vector<size_t>& starts, size_t g, size_t cores) {
  auto entries = [&](size_t b) {
    const size_t k1 = b + 1 < starts.size() ? starts[b + 1] : cells.size();
    return size_t(cells[k1 - 1].end - cells[starts[b]].begin);
  };
  size_t m = 1, total = entries(g);
  while (m < cores && g + m < starts.size() && total + entries(g + m) <= cpu_batch_entries) total += entries(g + m++);
  return m;
}

namespace {

// An entry makes at most this many entries in its children: itself in each
// of four, and a shortcut entry for its run in each.
constexpr size_t kMaxGrowth = 8;

// Passes 1 to 3 of §4.2 as one pass over a batch of cells: each (parent
// entry, child) pair's outputs (split_scatter) written in the pairs' order
// -- cell by cell, child by child, entry by entry, as the scan of §4.2
// orders them -- with its path run's winding summed as the run goes. The
// scan computes the same sums and offsets in parallel (integer sums: the
// same in any order); on a core the pass needs neither its per-pair arrays
// nor a second reading of the split.
struct Subdivision {
  const std::vector<Cell>& cells;
  const Entry* in;
  const std::vector<AbstractSegment>& segments;
  uint32_t fanout;
  std::vector<CellBox> boxes;

  // Cells k0 .. k1 - 1 into `list` (it grows as needed), their children's
  // ranges in out.cells counted from the list's start. A cell's entries
  // are split for all its children first, so that each segment is read
  // once, not once per child (the segments are read in the stream's order,
  // scattered over an array larger than the caches). Returns the entries
  // written.
  // Without Write, only counts the entries (list and out unused).
  template <bool Write>
  size_t split_batch(size_t k0, size_t k1, std::vector<Entry>* list, TreeLevel* out) const {
    constexpr size_t kMaxOutputs = 4;  // a pair writes at most: itself, two shortcuts, a winding
    std::vector<uint8_t> flags;
    std::vector<int32_t> wind;
    size_t used = 0;
    for (size_t k = k0; k < k1; k++) {
      const Cell& pc = cells[k];
      const uint32_t size = pc.end - pc.begin;
      const CellBox* box = &boxes[fanout * k];
      flags.resize(size_t(fanout) * size);
      wind.resize(size_t(fanout) * size);
      for (uint32_t i = 0; i < size; i++)
        for (uint32_t c = 0; c < fanout; c++)
          flags[c * size + i] = static_cast<uint8_t>(split_entry(in[pc.begin + i], segments.data(), box[c],
                                                                 &wind[c * size + i]));
      for (uint32_t c = 0; c < fanout; c++) {
        if constexpr (Write) out->cells[fanout * k + c].begin = static_cast<uint32_t>(used);
        int32_t run = 0;
        for (uint32_t i = pc.begin; i < pc.end; i++) {
          const size_t j = c * size + (i - pc.begin);
          run = run_starts(in, i, pc.begin) ? wind[j] : run + wind[j];
          if constexpr (Write) {
            if (list->size() < used + kMaxOutputs) list->resize(std::max(2 * list->size(), used + 4096));
            used += split_scatter(in[i], flags[j], run_ends(in, i, pc.end), run, segments.data(), list->data() + used);
          } else {
            used += split_output_count(flags[j], run_ends(in, i, pc.end), run);
          }
        }
        if constexpr (Write) out->cells[fanout * k + c].end = static_cast<uint32_t>(used);
      }
    }
    return used;
  }
};

}  // namespace

TreeLevel subdivide_cpu(const std::vector<Cell>& cells, const Entry* entries,
                        const std::vector<AbstractSegment>& segments, uint32_t root_size, bool root,
                        size_t max_entries, bool* overflow) {
  if (overflow) *overflow = false;
  Subdivision sd{cells, entries, segments, root ? 1u : 4u, {}};
  TreeLevel out;
  out.cells.resize(sd.fanout * cells.size());
  sd.boxes.resize(out.cells.size());
  size_t span = 0;
  for (size_t k = 0; k < cells.size(); k++) {
    const Cell& pc = cells[k];
    span += pc.end - pc.begin;
    for (uint32_t c = 0; c < sd.fanout; c++) {
      Cell& cc = out.cells[sd.fanout * k + c];
      cc.ix = root ? 0 : static_cast<uint16_t>(2 * pc.ix + (c & 1));
      cc.iy = root ? 0 : static_cast<uint16_t>(2 * pc.iy + (c >> 1));
      cc.level = root ? 0 : static_cast<uint16_t>(pc.level + 1);
      cc.root = pc.root;
      sd.boxes[sd.fanout * k + c] = cell_box(cc.ix, cc.iy, cc.level, root_size);
    }
  }
  // A level that might pass the cap is counted first, so that it is given
  // up before its entries are made, and its list is made at its size (no
  // copy of a growing list: the old and new arrays at once).
  const size_t cores = static_cast<size_t>(hardware_threads());
  const std::vector<size_t> starts = cell_batches(cells, span, cores);
  auto end_of = [&](size_t b) { return b + 1 < starts.size() ? starts[b + 1] : cells.size(); };
  if (span > max_entries / kMaxGrowth) {
    std::vector<size_t> counts(starts.size());
    parallel_for(starts.size(), static_cast<int>(cores),
                 [&](size_t b) { counts[b] = sd.split_batch<false>(starts[b], end_of(b), nullptr, nullptr); });
    size_t total = 0;
    for (size_t c : counts) total += c;
    if (total > max_entries) {
      if (overflow) *overflow = true;
      return TreeLevel{};
    }
    out.entries.reserve(total);
  }
  // Batches of at most cpu_batch_entries entries; a large level in at least
  // one batch per core. Groups of up to as many batches as cores, at most
  // cpu_batch_entries entries in all (a larger batch alone), split in
  // parallel, each into a list of its own (batches are independent: no cell
  // spans two, and the output depends on the cells alone); the lists are
  // then placed after the previous group's, and their cells' ranges moved
  // there.
  std::vector<std::vector<Entry>> lists(std::min(cores, starts.size()));
  std::vector<size_t> base(lists.size() + 1);
  for (size_t g = 0, m; g < starts.size(); g += m) {
    m = batch_group(cells, starts, g, cores);
    parallel_for(m, static_cast<int>(m),
                 [&](size_t b) { base[b + 1] = sd.split_batch<true>(starts[g + b], end_of(g + b), &lists[b], &out); });
    base[0] = out.entries.size();
    for (size_t b = 0; b < m; b++) base[b + 1] += base[b];
    if (base[m] > max_entries) {
      if (overflow) *overflow = true;
      return TreeLevel{};
    }
    out.entries.resize(base[m]);
    parallel_for(m, static_cast<int>(m), [&](size_t b) {
      std::copy_n(lists[b].data(), base[b + 1] - base[b], out.entries.data() + base[b]);
      for (size_t k = starts[g + b]; k < end_of(g + b); k++)
        for (uint32_t c = 0; c < sd.fanout; c++) {
          Cell& cc = out.cells[sd.fanout * k + c];
          cc.begin += static_cast<uint32_t>(base[b]);
          cc.end += static_cast<uint32_t>(base[b]);
        }
    });
  }
  return out;
}

}  // namespace mpvg
