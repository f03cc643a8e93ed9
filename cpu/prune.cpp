// Stage "prune" on the CPU: one mark-and-sweep round of §4.4 per level.
// Cross-links come from the depth scan, a sort by depth and one segmented
// scan, exactly as on the GPU.
#include <algorithm>
#include <numeric>

#include "cpu/cpu_stages.h"
#include "core/parallel.h"
#include "core/tree/pruning.h"

namespace mpvg {

namespace {

// One round over a batch of cells, k0 .. k1 - 1 (cpu_batch_entries): a
// cell's stream is balanced, so depths and cross-links never leave it, and
// the round's dozen per-entry arrays (about 60 bytes an entry) grow with
// the batch, not the level. The entries kept are appended to `kept` and
// the cells' ranges set to where they landed there. Returns whether
// anything was eliminated.
bool prune_batch(TreeLevel& level, size_t k0, size_t k1, const std::vector<PathRecord>& paths,
                 std::vector<Entry>& kept, const uint8_t* root_grid) {
  const uint32_t first = level.cells[k0].begin;
  const size_t n = level.cells[k1 - 1].end - first;
  const Entry* e = level.entries.data() + first;
  auto begin_of = [&](size_t k) { return level.cells[k].begin - first; };
  auto end_of = [&](size_t k) { return level.cells[k].end - first; };
  std::vector<uint32_t> cell_of(n);
  for (size_t k = k0; k < k1; k++)
    for (uint32_t i = begin_of(k); i < end_of(k); i++) cell_of[i] = static_cast<uint32_t>(k);

  // Depth of every element.
  std::vector<int32_t> depth(n);
  for (size_t i = 0; i < n; i++) depth[i] = prune_depth_delta(e, static_cast<uint32_t>(i));
  std::inclusive_scan(depth.begin(), depth.end(), depth.begin());
  const int32_t max_depth = n ? *std::max_element(depth.begin(), depth.end()) : 0;

  // Cross-links over all depths at once (core/tree/pruning.h): the elements
  // sorted stably by depth (a counting sort), a segmented max-scan, then
  // each element's links.
  std::vector<uint32_t> open(n, ~0u), bar(n, ~0u), close(n, ~0u), parent(n, ~0u), sorted;
  if (max_depth > 0) {
    std::vector<uint32_t> at(static_cast<size_t>(max_depth) + 2, 0);
    sorted.resize(n);
    for (size_t i = 0; i < n; i++) at[depth[i] + 1]++;
    for (size_t d = 1; d < at.size(); d++) at[d] += at[d - 1];
    for (size_t i = 0; i < n; i++) sorted[at[depth[i]]++] = static_cast<uint32_t>(i);
    std::vector<LinkSeg> last(n);
    for (size_t p = 0; p < n; p++) last[p] = prune_link_start(e, sorted.data(), depth.data(), static_cast<uint32_t>(p));
    std::inclusive_scan(last.begin(), last.end(), last.begin(), SegmentedMax<uint32_t>{});
    for (size_t p = 0; p < n; p++)
      prune_link(e, sorted.data(), depth.data(), last.data(), static_cast<uint32_t>(n), static_cast<uint32_t>(p),
                 open.data(), bar.data(), close.data(), parent.data());
  }

  // Terminals, and the first C1 of every content section.
  std::vector<uint32_t> term(n);
  for (size_t i = 0; i < n; i++)
    term[i] = prune_classify(e, static_cast<uint32_t>(i), begin_of(cell_of[i]), end_of(cell_of[i]), paths.data());
  std::vector<uint32_t> first_c1(n, ~0u);
  const PruneLinks links{depth.data(), open.data(), bar.data(), close.data(), first_c1.data(), parent.data()};
  for (size_t i = 0; i < n; i++)
    if (term[i] == TERM_C1 && prune_c1_in_content(links, static_cast<uint32_t>(i)))
      first_c1[open[i]] = std::min(first_c1[open[i]], static_cast<uint32_t>(i));

  // Mark.
  std::vector<int32_t> elim(n + 1, 0);
  auto add = [&](uint32_t at, int32_t v) { elim[at] += v; };
  for (size_t i = 0; i < n; i++)
    prune_mark(e, term.data(), links, static_cast<uint32_t>(i), begin_of(cell_of[i]), end_of(cell_of[i]), add);

  std::inclusive_scan(elim.begin(), elim.end(), elim.begin());

  // Rules 16, 19 and 23 on what those marks leave (core/tree/pruning.h), into a
  // second elimination array: section counts, the elements sorted by them
  // (a counting sort), the survivors' prefix sum in that order; then the
  // items' prefix sum in the order of depths.
  std::vector<int32_t> elim2(n + 1, 0);
  if (max_depth > 0) {
    std::vector<int32_t> section(n);
    for (size_t i = 0; i < n; i++) section[i] = prune_section_delta(e, static_cast<uint32_t>(i));
    std::inclusive_scan(section.begin(), section.end(), section.begin());
    const int32_t max_section = *std::max_element(section.begin(), section.end());
    std::vector<uint32_t> at(static_cast<size_t>(max_section) + 2, 0), by_section(n), shown(n + 1, 0);
    for (size_t i = 0; i < n; i++) at[section[i] + 1]++;
    for (size_t d = 1; d < at.size(); d++) at[d] += at[d - 1];
    for (size_t i = 0; i < n; i++) by_section[at[section[i]]++] = static_cast<uint32_t>(i);
    for (size_t p = 0; p < n; p++) shown[p + 1] = shown[p] + prune_shows(e, elim.data(), by_section[p]);
    const PruneShown s{section.data(), by_section.data(), shown.data(), static_cast<uint32_t>(n)};
    auto add2 = [&](uint32_t at, int32_t v) { elim2[at] += v; };
    std::vector<uint64_t> weight(n);
    for (size_t i = 0; i < n; i++)
      weight[i] = prune_mark_empty(e, elim.data(), links, s, static_cast<uint32_t>(i), begin_of(cell_of[i]), add2);
    std::vector<uint64_t> items(n + 1, 0);
    for (size_t p = 0; p < n; p++) items[p + 1] = items[p] + weight[sorted[p]];
    const PruneItems it{sorted.data(), items.data(), static_cast<uint32_t>(n)};
    for (size_t i = 0; i < n; i++) prune_mark_unwrap(e, term.data(), links, it, static_cast<uint32_t>(i), add2);
    std::inclusive_scan(elim2.begin(), elim2.end(), elim2.begin());
  }

  // Sweep (a forest's cells inside their root's grid keep everything).
  std::vector<char> keep(n);
  for (size_t i = 0; i < n; i++) keep[i] = elim[i] <= 0 && elim2[i] <= 0;
  if (root_grid)
    for (size_t k = k0; k < k1; k++)
      if (in_root_grid(level.cells[k], root_grid)) std::fill(keep.begin() + begin_of(k), keep.begin() + end_of(k), 1);
  std::vector<uint32_t> kept_before(n + 1, 0);
  for (size_t i = 0; i < n; i++) kept_before[i + 1] = kept_before[i] + (keep[i] ? 1u : 0u);
  const uint32_t base = static_cast<uint32_t>(kept.size());
  for (size_t i = 0; i < n; i++)
    if (keep[i]) kept.push_back(e[i]);
  for (size_t k = k0; k < k1; k++) {
    Cell& c = level.cells[k];
    const uint32_t b = begin_of(k), en = end_of(k);
    c.begin = base + kept_before[b];
    c.end = base + kept_before[en];
  }
  return kept_before[n] != n;
}

// One round over the whole level; returns whether anything was eliminated.
// Batches of cells (cell_batches) are pruned a group at a time in parallel
// (batch_group), each into a list of its own with its cells' ranges counted
// from the list's start; the lists are then joined in order and the ranges
// moved by what precedes them.
bool prune_round(TreeLevel& level, const std::vector<PathRecord>& paths, const uint8_t* root_grid) {
  if (level.entries.empty()) return false;
  const size_t cores = static_cast<size_t>(hardware_threads());
  const std::vector<size_t> starts = cell_batches(level.cells, level.entries.size(), cores);
  auto end_of = [&](size_t b) { return b + 1 < starts.size() ? starts[b + 1] : level.cells.size(); };
  std::vector<std::vector<Entry>> kept(starts.size());
  std::vector<char> pruned(starts.size(), 0);
  for (size_t g = 0, m; g < starts.size(); g += m) {  // scratch bounded as with one batch
    m = batch_group(level.cells, starts, g, cores);
    parallel_for(m, static_cast<int>(m), [&](size_t b) {
      pruned[g + b] = prune_batch(level, starts[g + b], end_of(g + b), paths, kept[g + b], root_grid);
    });
  }
  size_t total = 0;
  for (size_t b = 0; b < starts.size(); b++) {
    for (size_t k = starts[b]; k < end_of(b); k++) {
      level.cells[k].begin += static_cast<uint32_t>(total);
      level.cells[k].end += static_cast<uint32_t>(total);
    }
    total += kept[b].size();
  }
  if (std::find(pruned.begin(), pruned.end(), 1) == pruned.end()) return false;
  // Joined in place: a batch's survivors land at or before where its
  // entries were, so only entries already done are overwritten; each list
  // is freed once copied (peak memory: the level and its survivors, as
  // when one list grew).
  size_t at = 0;
  for (std::vector<Entry>& k : kept) {
    std::copy(k.begin(), k.end(), level.entries.begin() + static_cast<std::ptrdiff_t>(at));
    at += k.size();
    std::vector<Entry>().swap(k);
  }
  level.entries.resize(total);
  return true;
}

}  // namespace

bool prune_cpu(TreeLevel& level, const std::vector<PathRecord>& paths, const uint8_t* root_grid) {
  return prune_round(level, paths, root_grid);
}

}  // namespace mpvg
