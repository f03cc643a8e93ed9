// Stage "subdivide" on the CPU: the passes of §4.2 (split; the segmented
// scan of windings and the offset scan as one scan, SplitScan; scatter)
// over every cell of a level, in batches of cells, a large level's batches
// on every core.
#include <algorithm>
#include <cstdint>
#include <numeric>

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

// One batch's passes 1 and 2.
struct Scratch {
  std::vector<uint32_t> flags;
  std::vector<SplitScan> scan;
  // Where pair j's outputs start: the outputs of the pairs before it.
  uint32_t offset(size_t j) const { return j ? scan[j - 1].count : 0u; }
};

struct Subdivision {
  const std::vector<Cell>& cells;
  const Entry* in;
  const std::vector<AbstractSegment>& segments;
  uint32_t fanout;
  std::vector<CellBox> boxes;

  // Passes 1 and 2 over cells k0 .. k1 - 1: the entries their children
  // get. Pair (entry i of cell k, child c) lives at
  // fanout*(begin-first) + c*size + (i-begin), first the batch's first
  // entry: each child's block lists the parent's entries in order (slots
  // between cells that are not subdivided count nothing).
  size_t count_batch(size_t k0, size_t k1, Scratch& sc) const {
    auto& [flags, scan] = sc;
    const uint32_t first = cells[k0].begin;
    const size_t pairs = fanout * size_t(cells[k1 - 1].end - first);
    flags.resize(pairs);
    scan.assign(pairs, SplitScan{0, 0, 0, 0});
    // Pass 1: split.
    for (size_t k = k0; k < k1; k++) {
      const Cell& pc = cells[k];
      for (uint32_t c = 0; c < fanout; c++) {
        const CellBox& box = boxes[fanout * k + c];
        for (uint32_t i = pc.begin; i < pc.end; i++) {
          int32_t w;
          const size_t j = pair(pc, first, c, i);
          flags[j] = split_entry(in[i], segments.data(), box, &w);
          scan[j] = split_scan_item(flags[j], w, run_starts(in, i, pc.begin), run_ends(in, i, pc.end));
        }
      }
    }
    // Pass 2: windings consolidated per path run and outputs counted, one
    // inclusive scan (core/tree/subdivision.h).
    std::inclusive_scan(scan.begin(), scan.end(), scan.begin(), SplitScanOp{});
    return pairs ? scan[pairs - 1].count : 0;
  }

  // Pass 3 after count_batch: scatter into out from `base`; child cell
  // ranges fall out of the offsets.
  void scatter_batch(size_t k0, size_t k1, size_t base, TreeLevel& out, const Scratch& sc) const {
    const auto& flags = sc.flags;
    const uint32_t first = cells[k0].begin;
    for (size_t k = k0; k < k1; k++) {
      const Cell& pc = cells[k];
      const uint32_t size = pc.end - pc.begin;
      for (uint32_t c = 0; c < fanout; c++) {
        const size_t j0 = pair(pc, first, c, pc.begin);
        Cell& cc = out.cells[fanout * k + c];
        cc.begin = static_cast<uint32_t>(base + sc.offset(j0));
        cc.end = static_cast<uint32_t>(base + sc.offset(j0 + size));
        for (uint32_t i = pc.begin; i < pc.end; i++) {
          const size_t j = j0 + (i - pc.begin);
          split_scatter(in[i], flags[j], run_ends(in, i, pc.end), sc.scan[j].last, segments.data(),
                        out.entries.data() + base + sc.offset(j));
        }
      }
    }
  }

  size_t pair(const Cell& pc, uint32_t first, uint32_t c, uint32_t i) const {
    return fanout * size_t(pc.begin - first) + size_t(c) * (pc.end - pc.begin) + (i - pc.begin);
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
  // up before its entries are made.
  if (span > max_entries / kMaxGrowth) {
    Scratch sc;
    size_t total = 0;
    for (size_t k0 = 0, k1; k0 < cells.size(); k0 = k1) {
      k1 = batch_end(cells, k0, cpu_batch_entries);
      total += sd.count_batch(k0, k1, sc);
    }
    if (total > max_entries) {
      if (overflow) *overflow = true;
      return TreeLevel{};
    }
    out.entries.reserve(total);
  }
  // Batches of at most cpu_batch_entries entries; a large level in at least
  // one batch per core. Groups of up to as many batches as cores, at most
  // cpu_batch_entries entries in all (a larger batch alone), count in
  // parallel, place their entries after the previous group's and scatter
  // in parallel (batches are independent: no cell spans two, and the output
  // depends on the cells alone). Scratch stays bounded as with one batch.
  const size_t cores = static_cast<size_t>(hardware_threads());
  const std::vector<size_t> starts = cell_batches(cells, span, cores);
  auto end_of = [&](size_t b) { return b + 1 < starts.size() ? starts[b + 1] : cells.size(); };
  std::vector<Scratch> scratch(std::min(cores, starts.size()));
  std::vector<size_t> base(scratch.size() + 1);
  for (size_t g = 0, m; g < starts.size(); g += m) {
    m = batch_group(cells, starts, g, cores);
    parallel_for(m, static_cast<int>(m),
                 [&](size_t b) { base[b + 1] = sd.count_batch(starts[g + b], end_of(g + b), scratch[b]); });
    base[0] = out.entries.size();
    for (size_t b = 0; b < m; b++) base[b + 1] += base[b];
    out.entries.resize(base[m]);
    parallel_for(m, static_cast<int>(m),
                 [&](size_t b) { sd.scatter_batch(starts[g + b], end_of(g + b), base[b], out, scratch[b]); });
  }
  return out;
}

}  // namespace mpvg
