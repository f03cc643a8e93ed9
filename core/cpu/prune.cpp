// Stage "prune" on the CPU: mark-and-sweep rounds of §4.4 until a round
// eliminates nothing. Cross-links come from the depth scan and one segmented
// scan per depth, exactly as on the GPU.
#include <algorithm>
#include <numeric>

#include "core/cpu/cpu_stages.h"
#include "core/pruning.h"

namespace mpvg {

namespace {

// One round; returns whether anything was eliminated.
bool prune_round(TreeLevel& level, const std::vector<PathRecord>& paths) {
  const size_t n = level.entries.size();
  if (n == 0) return false;
  const Entry* e = level.entries.data();
  std::vector<uint32_t> cell_of(n);
  for (size_t k = 0; k < level.cells.size(); k++)
    for (uint32_t i = level.cells[k].begin; i < level.cells[k].end; i++) cell_of[i] = static_cast<uint32_t>(k);

  // Depth of every element.
  std::vector<int32_t> depth(n);
  for (size_t i = 0; i < n; i++) depth[i] = prune_depth_delta(e, static_cast<uint32_t>(i));
  std::inclusive_scan(depth.begin(), depth.end(), depth.begin());
  const int32_t max_depth = *std::max_element(depth.begin(), depth.end());

  // Cross-links, one segmented scan per depth.
  std::vector<uint32_t> open(n, ~0u), bar(n, ~0u), close(n, ~0u), parent(n, ~0u);
  std::vector<LinkSeg> link(n);
  for (int32_t d = 1; d <= max_depth; d++) {
    for (size_t i = 0; i < n; i++)
      link[i] = LinkSeg{1u, (entry_opens(e[i]) && depth[i] == d) ? 1u : 0u};
    std::inclusive_scan(link.begin(), link.end(), link.begin(), SegmentedSum<uint32_t>{});
    for (size_t i = 0; i < n; i++) {
      // A '(' or '{' one level deeper lies in the nearest '(' or '{' of depth d.
      if (depth[i] == d + 1 && entry_opens(e[i])) parent[i] = static_cast<uint32_t>(i) - (link[i].value - 1);
      if (depth[i] != d) continue;
      const uint32_t o = static_cast<uint32_t>(i) - (link[i].value - 1);
      open[i] = o;
      const uint32_t k = entry_kind(e[i]);
      if (k == ENTRY_ACTIVATE) bar[o] = static_cast<uint32_t>(i);
      if (entry_closes(e[i])) close[o] = static_cast<uint32_t>(i);
    }
  }

  // Terminals, and the first C1 of every content section.
  std::vector<uint32_t> term(n);
  for (size_t i = 0; i < n; i++) {
    const Cell& c = level.cells[cell_of[i]];
    term[i] = prune_classify(e, static_cast<uint32_t>(i), c.begin, c.end, paths.data());
  }
  std::vector<uint32_t> first_c1(n, ~0u);
  const PruneLinks links{depth.data(), open.data(), bar.data(), close.data(), first_c1.data(), parent.data()};
  for (size_t i = 0; i < n; i++)
    if (term[i] == TERM_C1 && prune_c1_in_content(links, static_cast<uint32_t>(i)))
      first_c1[open[i]] = std::min(first_c1[open[i]], static_cast<uint32_t>(i));

  // Mark.
  std::vector<int32_t> elim(n + 1, 0);
  auto add = [&](uint32_t at, int32_t v) { elim[at] += v; };
  for (size_t i = 0; i < n; i++)
    prune_mark(e, term.data(), links, static_cast<uint32_t>(i), level.cells[cell_of[i]].begin,
               level.cells[cell_of[i]].end, add);

  // Sweep.
  std::inclusive_scan(elim.begin(), elim.end(), elim.begin());
  std::vector<uint32_t> kept_before(n + 1, 0);
  for (size_t i = 0; i < n; i++) kept_before[i + 1] = kept_before[i] + (elim[i] <= 0 ? 1u : 0u);
  if (kept_before[n] == n) return false;
  std::vector<Entry> out;
  out.reserve(kept_before[n]);
  for (size_t i = 0; i < n; i++)
    if (elim[i] <= 0) out.push_back(e[i]);
  for (Cell& c : level.cells) {
    c.begin = kept_before[c.begin];
    c.end = kept_before[c.end];
  }
  level.entries.swap(out);
  return true;
}

}  // namespace

int prune_cpu(TreeLevel& level, const std::vector<PathRecord>& paths) {
  int rounds = 0;
  while (prune_round(level, paths)) rounds++;
  return rounds;
}

}  // namespace mpvg
