// Stage "subdivide" on the CPU: the four passes of §4.2 (split, segmented
// scan of windings, offset scan, scatter) over every cell of a level.
#include <numeric>

#include "core/cpu/cpu_stages.h"
#include "core/subdivision.h"

namespace mpvg {

TreeLevel subdivide_cpu(const TreeLevel& parent, const std::vector<AbstractSegment>& segments, uint32_t root_size,
                        bool root) {
  const uint32_t fanout = root ? 1u : 4u;
  const Entry* in = parent.entries.data();
  const size_t pairs = fanout * parent.entries.size();
  // Pair (entry i of cell k, child c) lives at fanout*begin + c*size + (i-begin):
  // each child's block lists the parent's entries in order.
  std::vector<uint32_t> flags(pairs);
  std::vector<WindSeg> wind(pairs);
  std::vector<uint32_t> count(pairs);
  TreeLevel out;
  out.cells.resize(fanout * parent.cells.size());
  std::vector<CellBox> boxes(out.cells.size());
  for (size_t k = 0; k < parent.cells.size(); k++) {
    const Cell& pc = parent.cells[k];
    for (uint32_t c = 0; c < fanout; c++) {
      Cell& cc = out.cells[fanout * k + c];
      cc.ix = root ? 0 : static_cast<uint16_t>(2 * pc.ix + (c & 1));
      cc.iy = root ? 0 : static_cast<uint16_t>(2 * pc.iy + (c >> 1));
      cc.level = root ? 0 : static_cast<uint16_t>(pc.level + 1);
      cc.pad = 0;
      boxes[fanout * k + c] = cell_box(cc.ix, cc.iy, cc.level, root_size);
    }
  }
  // Pass 1: split.
  for (size_t k = 0; k < parent.cells.size(); k++) {
    const Cell& pc = parent.cells[k];
    const uint32_t size = pc.end - pc.begin;
    for (uint32_t c = 0; c < fanout; c++) {
      const CellBox& box = boxes[fanout * k + c];
      const size_t base = fanout * size_t(pc.begin) + size_t(c) * size;
      for (uint32_t i = pc.begin; i < pc.end; i++) {
        int32_t w;
        const size_t j = base + (i - pc.begin);
        flags[j] = split_entry(in[i], segments.data(), box, &w);
        wind[j] = WindSeg{w, run_starts(in, i, pc.begin) ? 1u : 0u};
      }
    }
  }
  // Pass 2: consolidate windings per path run (segmented inclusive scan).
  std::inclusive_scan(wind.begin(), wind.end(), wind.begin(), SegmentedSum<int32_t>{});
  // Pass 3: output offsets (exclusive scan, one extra slot per non-zero run).
  for (size_t k = 0; k < parent.cells.size(); k++) {
    const Cell& pc = parent.cells[k];
    const uint32_t size = pc.end - pc.begin;
    for (uint32_t c = 0; c < fanout; c++) {
      const size_t base = fanout * size_t(pc.begin) + size_t(c) * size;
      for (uint32_t i = pc.begin; i < pc.end; i++) {
        const size_t j = base + (i - pc.begin);
        count[j] = split_output_count(flags[j], run_ends(in, i, pc.end), wind[j].value);
      }
    }
  }
  std::vector<uint32_t> offset(pairs + 1, 0);
  std::inclusive_scan(count.begin(), count.end(), offset.begin() + 1);
  out.entries.resize(offset[pairs]);
  // Pass 4: scatter; child cell ranges fall out of the offsets.
  for (size_t k = 0; k < parent.cells.size(); k++) {
    const Cell& pc = parent.cells[k];
    const uint32_t size = pc.end - pc.begin;
    for (uint32_t c = 0; c < fanout; c++) {
      const size_t base = fanout * size_t(pc.begin) + size_t(c) * size;
      Cell& cc = out.cells[fanout * k + c];
      cc.begin = offset[base];
      cc.end = offset[base + size];
      for (uint32_t i = pc.begin; i < pc.end; i++) {
        const size_t j = base + (i - pc.begin);
        split_scatter(in[i], flags[j], run_ends(in, i, pc.end), wind[j].value, segments.data(),
                      out.entries.data() + offset[j]);
      }
    }
  }
  return out;
}

}  // namespace mpvg
