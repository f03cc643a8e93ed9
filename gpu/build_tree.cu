// Building the tree on the GPU: abstraction, the root, then breadth first,
// level by level, subdivision and pruning -- the loop of
// cpu/build_tree.cpp, with every per-cell and per-entry step a kernel.
// Two drivers run the same kernels. Host-driven (a context's first build,
// and any frame that outgrew its pools), the host reads back a handful of
// counts per level to size the next one. Device-driven, every level's
// buffers come from pools sized ahead (DrivePlan: the most a build of
// this context needed per input segment, with a margin), every kernel
// reads its counts from the device (Count), the coarse grid is every
// root's own (in_root_grid, as a forest's), every level up to the depth
// cap is launched (empty ones exit at once), and the host reads the
// totals once, with the frame's first result (settle). A stage that would
// outgrow a pool raises DRIVE_OVERFLOW and empties the levels after it;
// the frame is then built again host-driven, so the tree is always the
// host-driven one.
#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "frame/forest.h"
#include "core/tree/subdivision.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 256;

// Which cells are subdivided, and the counts that place their entries: a
// warp per cell counts its geometry entries (entry_weight), 32 at a time,
// until they pass min_segments (only that is asked), so the cells' ranges
// are all it reads: a level's entry count is not needed before the counts
// come back (pruning leaves it on the device).
constexpr unsigned kDecideWarps = kBlock / 32;
// Cells from the count to the bound (thread ncells.n) count nothing, so
// that the scan's total is at the bound.
__global__ void k_decide(const Entry* e, const Cell* cells, Count ncells, bool may_subdivide, uint32_t min_segments,
                         const uint8_t* root_grid, LevelCounts* counts) {
  const size_t k = blockIdx.x * size_t(kDecideWarps) + threadIdx.x / 32;
  const uint32_t lane = threadIdx.x % 32;
  if (k > ncells.n) return;
  if (k >= ncells.get()) {
    if (lane == 0) counts[k] = LevelCounts{0, 0, 0, 0};
    return;
  }
  const Cell c = cells[k];
  const uint32_t size = c.end - c.begin;
  bool sub = may_subdivide && in_root_grid(c, root_grid);
  if (may_subdivide && !sub) {
    uint32_t weight = 0;
    for (uint32_t i = c.begin; i < c.end && weight <= min_segments; i += 32) {
      const bool geometry = i + lane < c.end && entry_weight(e[i + lane]);
      weight += __popc(__ballot_sync(__activemask(), geometry));
    }
    sub = weight > min_segments;
  }
  if (lane == 0) counts[k] = sub ? LevelCounts{1, size, 0, 0} : LevelCounts{0, 0, size, 1};
}

// Placement, one launch: every entry goes to its cell's slot in the next
// parent level or in the leaf stream (after the leaves of earlier levels),
// and every cell (threads below ncells) to the parent level or the leaves,
// with its node. n bounds the level's entries (pruning leaves their count
// on the device): the counts' totals, pos[ncells], give it. Driven
// (drive non-null), the leaf and node bases are the device's running
// totals, and a level that would outgrow the leaf or node pools raises
// the overflow flag instead.
struct PlacePools {
  size_t leaves, leaf_entries, nodes;
};
__global__ void k_place(const Entry* e, const uint32_t* entry_cell, size_t n, const Cell* cells, Count ncells,
                        const LevelCounts* pos, const LevelCounts* counts, Entry* parent, uint32_t* parent_cell,
                        Entry* leaf_entries, Cell* parent_cells, Cell* leaves, size_t leaf_base,
                        size_t leaf_entry_base, Node* nodes, size_t node_base, size_t child_base, uint32_t* drive,
                        PlacePools pools) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  const size_t nc = ncells.get();
  const LevelCounts tot = pos[nc];
  if (drive) {
    leaf_base = drive[DRIVE_LEAVES];
    leaf_entry_base = drive[DRIVE_LEAF_ENTRIES];
    node_base = drive[DRIVE_NODE_BASE];
    child_base = node_base + nc;
    if (leaf_base + tot.leaves > pools.leaves || leaf_entry_base + tot.leaf_entries > pools.leaf_entries ||
        child_base + 4 * size_t(tot.sub) > pools.nodes) {
      if (i == 0) atomicOr(&drive[DRIVE_OVERFLOW], 1u);
      return;
    }
  }
  if (i < n && i < size_t(tot.parent_entries) + tot.leaf_entries) {
    const uint32_t k = entry_cell[i];
    const uint32_t within = static_cast<uint32_t>(i) - cells[k].begin;
    if (counts[k].sub) {
      parent[pos[k].parent_entries + within] = e[i];
      parent_cell[pos[k].parent_entries + within] = pos[k].sub;
    } else {
      leaf_entries[leaf_entry_base + pos[k].leaf_entries + within] = e[i];
    }
  }
  const size_t k = i;
  if (k >= nc) return;
  Cell c = cells[k];
  const uint32_t size = c.end - c.begin;
  if (counts[k].sub) {
    c.begin = pos[k].parent_entries;
    c.end = c.begin + size;
    parent_cells[pos[k].sub] = c;
    nodes[node_base + k] = Node{static_cast<int32_t>(child_base + 4 * size_t(pos[k].sub)), 0};
  } else {
    c.begin = static_cast<uint32_t>(leaf_entry_base + pos[k].leaf_entries);
    c.end = c.begin + size;
    leaves[leaf_base + pos[k].leaves] = c;
    nodes[node_base + k] = Node{-1, static_cast<uint32_t>(leaf_base + pos[k].leaves)};
  }
}

// Driven: after a level's placement, the running totals move past it and
// the parent level gets its counts (none once a pool has overflowed).
__global__ void k_advance(const LevelCounts* pos, Count ncells, uint32_t* parent_size, uint32_t* drive, uint32_t lv) {
  const uint32_t nc = static_cast<uint32_t>(ncells.get());
  const LevelCounts t = pos[nc];
  const bool over = drive[DRIVE_OVERFLOW] != 0;
  if (!over && nc) {
    const uint32_t exact = t.parent_entries + t.leaf_entries;  // the level's entries after pruning
    drive[DRIVE_LEAVES] += t.leaves;
    drive[DRIVE_LEAF_ENTRIES] += t.leaf_entries;
    drive[DRIVE_NODES] = drive[DRIVE_NODE_BASE] + nc + 4 * t.sub;
    drive[DRIVE_NODE_BASE] += nc;
    drive[DRIVE_DEPTH] = lv;
    drive[DRIVE_PEAK] = max(drive[DRIVE_PEAK], exact);
    drive[DRIVE_TOTAL] += exact;
  }
  parent_size[0] = over ? 0u : t.parent_entries;
  parent_size[1] = over ? 0u : t.sub;
}

// A level of the coarse grid (TreeParams::grid_levels): every cell is
// subdivided, cell k's children the next level's cells 4k .. 4k + 3.
__global__ void k_grid_nodes(Node* nodes, size_t node_base, size_t ncells, size_t child_base) {
  const size_t k = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (k < ncells) nodes[node_base + k] = Node{static_cast<int32_t>(child_base + 4 * k), 0};
}

TreeLevel download_level(const DeviceLevel& lv) {
  TreeLevel t;
  t.cells = lv.cells.download(lv.ncells);
  // A pruned level's entries end where its last cell's do.
  t.entries = lv.entries.download(lv.bound ? (t.cells.empty() ? 0 : t.cells.back().end) : lv.nentries);
  return t;
}

// A forest's grid levels per root (in_root_grid), from its top-level cell.
__global__ void k_root_grid(const Cell* cells, size_t nroots, int max_level, uint32_t min_segments, int grid_levels,
                            uint8_t* root_grid) {
  const size_t r = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (r >= nroots) return;
  root_grid[r] = static_cast<uint8_t>(grid_levels_for(cells[r].end - cells[r].begin, max_level, min_segments, grid_levels));
}

}  // namespace

void Context::Impl::upload_paints(const PaintData& p) {
  paints.upload(p.paints);
  gradients.upload(p.gradients);
  ramp_t.upload(p.ramp_t);
  ramp_color.upload(p.ramp_color);
  textures.upload(p.textures);
  texture_levels.upload(p.levels);
  if (p.device_texels.empty()) {
    texels.upload(p.texels);
  } else {
    // Filter layers' texels stay on the device: copied in after the host's.
    texels.resize(p.texel_count());
    if (!p.texels.empty())
      MPVG_CUDA(cudaMemcpy(texels.data(), p.texels.data(), p.texels.size() * sizeof(Texel16), cudaMemcpyHostToDevice));
    for (const PaintData::DeviceTexels& d : p.device_texels)
      if (d.count)
        MPVG_CUDA(cudaMemcpyAsync(texels.data() + d.offset, d.src, d.count * sizeof(Texel16), cudaMemcpyDeviceToDevice,
                                  cudaStreamPerThread));
  }
  patterns.upload(p.patterns);
  groups.upload(p.groups);
  meshes.upload(p.meshes);
  mesh_triangles.upload(p.mesh_triangles);
  mesh_cells.upload(p.mesh_cells);
  mesh_items.upload(p.mesh_items);
}

void Context::Impl::stash_tile(TileTree& t) {
  auto copy = [](auto& dst, const auto& src, size_t n) {
    dst.resize(n);
    if (n) MPVG_CUDA(cudaMemcpyAsync(dst.data(), src.data(), n * sizeof(*src.data()), cudaMemcpyDeviceToDevice));
  };
  copy(t.segments, segments, nsegments);
  copy(t.paths, paths, npaths);
  copy(t.nodes, nodes, nnodes);
  copy(t.leaves, leaves, nleaves);
  copy(t.entries, leaf_entries, nleaf_entries);
  t.nsegments = nsegments;
  t.npaths = npaths;
  t.nnodes = nnodes;
  t.nleaves = nleaves;
  t.nentries = nleaf_entries;
  t.root_size = root_size;
  t.width = static_cast<uint32_t>(width);
  t.height = static_cast<uint32_t>(height);
}

void Context::Impl::build(const EncodedScene& scene, int w, int h, const TreeParams& params, GpuTimes* times,
                          bool render_follows) {
  check_stop_rule(params);
  // A driven build nobody rendered: its counts are not needed any more.
  pending = false;
  pending_scene = nullptr;
  const size_t launches0 = launches, syncs0 = syncs, calls0 = prim.calls;
  if (builds++ > 0) host_words.pin();  // a reused context
  host_paint = scene.paint ? scene.paint : std::make_shared<const PaintData>();
  upload_paints(*host_paint);
  // Tiles first: the working buffers end up holding the scene's tree.
  if (tiles.size() < scene.tiles.size()) tiles.resize(scene.tiles.size());
  ntiles = scene.tiles.size();
  TreeParams tile_params = params;
  tile_params.keep_levels = false;
  std::vector<TreeView> views;
  for (size_t k = 0; k < ntiles; k++) {
    const EncodedTile& tile = scene.tiles[k];
    build_tree(tile.scene, tile.width, tile.height, tile_params, times);
    TileTree& tt = tiles[k];
    stash_tile(tt);
    views.push_back(TreeView{tt.nodes.data(), tt.leaves.data(), tt.entries.data(), tt.segments.data(),
                             tt.paths.data(), tt.root_size, tt.width, tt.height, 0});
  }
  tile_views.upload(views);
  paint_view.upload(std::vector<PaintTables>{paint_tables()});
  last_driven = last_fallback = false;
  if (may_drive(scene, params) && build_tree_driven(scene, w, h, params, times)) {
    last_driven = pending = true;
    pending_scene = &scene;
    pending_w = w, pending_h = h;
    pending_params = params;
    pending_times = times;
    if (!render_follows) settle();
  } else {
    build_tree(scene, w, h, params, times);
    learn(scene);
  }
  build_launches = launches - launches0;
  build_syncs = syncs - syncs0;
  build_cub_calls = prim.calls - calls0;
}

bool Context::Impl::may_drive(const EncodedScene& scene, const TreeParams& params) const {
  if (drive_mode == GpuDrive::Host || !scene.tiles.empty() || params.keep_levels) return false;
  return drive_mode == GpuDrive::Device || plan.builds > 0;
}

void Context::Impl::learn(const EncodedScene& scene) {
  (void)scene;
  if (!capped) plan.learn(ninput, {nsegments, most_entries, most_cells, nleaves, nleaf_entries, nnodes});
}

bool Context::Impl::settle(std::initializer_list<HostWords::Word> extra) {
  if (!pending) {
    if (extra.size()) read_words(extra);
    return true;
  }
  pending = false;
  uint32_t w[DRIVE_WORDS] = {};
  std::vector<HostWords::Word> words(extra.begin(), extra.end());
  for (uint32_t k = 0; k < DRIVE_WORDS; k++) words.push_back({drive.data() + k, &w[k]});
  host_words.read(words.data(), words.size());
  syncs++;
  if (w[DRIVE_OVERFLOW]) {
    // Outgrew a pool (or met the memory cap): the host-driven build, whose
    // counts grow the plan.
    last_fallback = true;
    fallbacks++;
    const EncodedScene& scene = *pending_scene;
    pending_scene = nullptr;
    build_tree(scene, pending_w, pending_h, pending_params, pending_times);
    learn(scene);
    return false;
  }
  pending_scene = nullptr;
  nsegments = w[DRIVE_SEGMENTS];
  nleaves = w[DRIVE_LEAVES];
  nleaf_entries = w[DRIVE_LEAF_ENTRIES];
  nnodes = w[DRIVE_NODES];
  depth = static_cast<int>(w[DRIVE_DEPTH]);
  peak_level_entries = w[DRIVE_PEAK];
  capped = false;
  segments.resize(nsegments);
  leaves.resize(nleaves);
  leaf_entries.resize(nleaf_entries);
  nodes.resize(nnodes);
  plan.learn(ninput, {nsegments, w[DRIVE_MOST_ENTRIES], w[DRIVE_MOST_CELLS], nleaves, nleaf_entries, nnodes});
  return true;
}

namespace {

// Driven: the counts of a level made by the root's subdivision or a
// level's (splits' total, its parent's cells times the fanout), or none
// once a pool has overflowed or the memory cap is passed.
__global__ void k_child_size(const SplitScan* splits, Count pairs, Count parent_cells, uint32_t fanout,
                             size_t pool_entries, size_t pool_cells, size_t max_entries, uint32_t* size,
                             uint32_t* drive) {
  const uint32_t n = splits[pairs.get()].count;
  const size_t nc = fanout * parent_cells.get();
  const bool over = drive[DRIVE_OVERFLOW] || n > pool_entries || nc > pool_cells ||
                    size_t(drive[DRIVE_TOTAL]) + n > max_entries;
  if (over) drive[DRIVE_OVERFLOW] = 1;
  size[0] = over ? 0u : n;
  size[1] = over ? 0u : static_cast<uint32_t>(nc);
  drive[DRIVE_MOST_ENTRIES] = max(drive[DRIVE_MOST_ENTRIES], n);
  drive[DRIVE_MOST_CELLS] = max(drive[DRIVE_MOST_CELLS], static_cast<uint32_t>(nc));
}

}  // namespace

void Context::Impl::subdivide_driven(const DeviceLevel& from, DeviceLevel& to, bool root, size_t to_entries,
                                     size_t to_cells, const TreeParams& params) {
  const uint32_t fanout = root ? 1u : 4u;
  const Count n = from.entry_count();
  const size_t pairs = fanout * n.n;
  uint32_t* flags = (u32[0].resize(pairs + 1), u32[0].data());
  split_items.resize(pairs + 1);
  splits.resize(pairs + 1);
  if (n.n == 0) {
    MPVG_CUDA(cudaMemsetAsync(splits.data(), 0, sizeof(SplitScan)));
  } else {
    subdivide_split(from, n, fanout, root, flags, nullptr, /*pad=*/false);
    prim.counted_inclusive(split_items.data(), splits.data() + 1, SplitScanOp{}, SplitScan{0, 0, 0, 0},
                           n.times(fanout));
  }
  to.entries.resize(to_entries);
  to.entry_cell.resize(to_entries);
  to.cells.resize(to_cells);
  to.size.resize(2);
  to.nentries = to_entries;
  to.ncells = to_cells;
  to.driven = true;
  to.bound = false;
  subdivide_scatter(from, n, from.cell_count(), nullptr, fanout, root, flags, to, drive.data() + DRIVE_OVERFLOW);
  k_child_size<<<1, 1>>>(splits.data(), n.times(fanout), from.cell_count(), fanout, to_entries, to_cells,
                         root ? ~size_t{0} : params.max_entries, to.size.data(), drive.data());
  launched();
}

void Context::Impl::build_tree(const EncodedScene& scene, int w, int h, const TreeParams& params, GpuTimes* times) {
  StageTimer timer(times != nullptr);
  GpuTimes local;
  GpuTimes& t = times ? *times : local;
  width = w;
  height = h;
  root_size = tree_root_size(w, h);
  roots = scene_roots(scene, w, h);
  {
    std::vector<uint32_t> rs;
    for (const SceneRoot& r : roots) rs.insert(rs.end(), {r.stream_begin, r.stream_end});
    root_stream.upload(rs);
  }
  kept_levels.clear();
  host_paths = scene.paths;
  peak_level_entries = 0;
  most_entries = most_cells = 0;
  level.driven = parent.driven = child.driven = false;

  if (!scene.strokes.empty()) {
    timer.start(&t.stroke_ms);
    stroke(scene);
    timer.stop();
  }
  timer.start(&t.abstract_ms);
  abstract(scene);
  timer.stop();

  timer.start(&t.subdivide_ms);
  subdivide(level, child, true);
  timer.stop();
  std::swap(level, child);
  const int max_level = tree_max_level(root_size, params);
  // Levels [0, grid) are subdivided whole and not pruned (the coarse grid:
  // core/tree/tree.h); level `grid` is the first pruned. A forest's roots have a
  // grid each, from their own top-level cells (in_root_grid).
  grid_of_root = nullptr;
  if (roots.size() > 1) {
    root_grid.resize(roots.size());
    k_root_grid<<<grid_for(roots.size(), kBlock), kBlock>>>(level.cells.data(), roots.size(), max_level,
                                                            params.min_segments, params.grid_levels, root_grid.data());
    launched();
    grid_of_root = root_grid.data();
  }
  const int grid = grid_of_root ? 0 : tree_grid_levels(level.nentries, max_level, params);
  capped = false;
  if (params.prune && grid == 0) {
    timer.start(&t.prune_ms);
    prune(level);
    timer.stop();
  }

  size_t total_entries = level.nentries;
  nnodes = roots.size();  // nodes 0 .. roots - 1: the roots
  nodes.grow_keep(nnodes);
  nleaves = 0;
  nleaf_entries = 0;
  size_t node_base = 0;
  for (int lv = 0;; lv++) {
    depth = lv;
    if (!level.bound) peak_level_entries = std::max(peak_level_entries, level.nentries);
    if (params.keep_levels) kept_levels.push_back(download_level(level));
    const size_t ncells = level.ncells;
    if (lv < grid) {
      // The coarse grid: no weights, no decisions, no placement; the
      // level's entries are the parent level as they are.
      timer.start(&t.subdivide_ms);
      const size_t child_base = node_base + ncells;
      nodes.grow_keep(child_base + 4 * ncells);
      k_grid_nodes<<<grid_for(ncells, kBlock), kBlock>>>(nodes.data(), node_base, ncells, child_base);
      launched();
      subdivide(level, child, false);
      timer.stop();
      if (total_entries + child.nentries <= params.max_entries) {
        nnodes = child_base + 4 * ncells;
        if (params.prune && lv + 1 >= grid) {
          timer.start(&t.prune_ms);
          prune(child);
          timer.stop();
        }
        total_entries += child.nentries;
        node_base = child_base;
        std::swap(level, child);
        continue;
      }
      // Memory cap: this level's cells become leaves, as below.
      capped = true;
    }
    counts.resize(2 * (ncells + 1));
    LevelCounts* cnt = counts.data();
    LevelCounts* pos = counts.data() + ncells + 1;

    timer.start(&t.subdivide_ms);
    bool may_subdivide = lv < max_level && lv >= grid;
    LevelCounts tot{};
    size_t child_entries = 0;
    for (int attempt = 0; attempt < 2; attempt++) {
      k_decide<<<grid_for(ncells + 1, kDecideWarps), kBlock>>>(level.entries.data(), level.cells.data(),
                                                               Count{ncells}, may_subdivide, params.min_segments, grid_of_root,
                                                               cnt);
      launched();
      prim.exclusive_scan(cnt, pos, LevelCountsAdd{}, LevelCounts{0, 0, 0, 0}, ncells + 1);
      // Place entries (subdivided cells into the parent level, the others
      // into the leaf stream) and subdivide before the counts come back:
      // buffers sized by the level's entries and cells, which bound them;
      // the counts return with the subdivision's total, one round trip.
      parent.entries.resize(level.nentries);
      parent.entry_cell.resize(level.nentries);
      parent.cells.resize(ncells);
      parent.nentries = level.nentries;
      parent.ncells = ncells;
      leaf_entries.grow_keep(nleaf_entries + level.nentries);
      leaves.grow_keep(nleaves + ncells);
      const size_t child_base = node_base + ncells;
      nodes.grow_keep(child_base + 4 * ncells);
      k_place<<<grid_for(std::max(level.nentries, ncells), kBlock), kBlock>>>(
          level.entries.data(), level.entry_cell.data(), level.nentries, level.cells.data(), Count{ncells}, pos, cnt,
          parent.entries.data(), parent.entry_cell.data(), leaf_entries.data(), parent.cells.data(), leaves.data(),
          nleaves, nleaf_entries, nodes.data(), node_base, child_base, nullptr, PlacePools{});
      launched();
      if (may_subdivide) {
        subdivide(parent, child, false, pos + ncells, &tot);
      } else {
        read_words({{&pos[ncells].sub, &tot.sub},
                    {&pos[ncells].parent_entries, &tot.parent_entries},
                    {&pos[ncells].leaf_entries, &tot.leaf_entries},
                    {&pos[ncells].leaves, &tot.leaves}});
      }
      parent.nentries = tot.parent_entries;
      parent.ncells = tot.sub;
      if (level.bound) {  // the count pruning left on the device
        const size_t exact = size_t(tot.parent_entries) + tot.leaf_entries;
        total_entries -= level.nentries - exact;
        level.nentries = exact;
        level.bound = false;
        peak_level_entries = std::max(peak_level_entries, exact);
      }
      if (tot.sub == 0) break;
      child_entries = child.nentries;
      if (total_entries + child_entries <= params.max_entries) break;
      // Memory cap (criterion 1 of §4.1): this level is the last; redo the
      // placement with every cell a leaf.
      may_subdivide = false;
      capped = true;
    }
    timer.stop();
    nleaves += tot.leaves;
    nleaf_entries += tot.leaf_entries;
    nnodes = node_base + ncells + 4 * size_t(tot.sub);
    if (tot.sub == 0) break;
    if (params.prune) {
      timer.start(&t.prune_ms);
      prune(child);
      timer.stop();
    }
    total_entries += child.nentries;
    node_base += ncells;
    std::swap(level, child);
  }
  timer.collect();
}

bool Context::Impl::build_tree_driven(const EncodedScene& scene, int w, int h, const TreeParams& params,
                                      GpuTimes* times) {
  StageTimer timer(times != nullptr);
  GpuTimes local;
  GpuTimes& t = times ? *times : local;
  width = w;
  height = h;
  root_size = tree_root_size(w, h);
  roots = scene_roots(scene, w, h);
  {
    std::vector<uint32_t> rs;
    for (const SceneRoot& r : roots) rs.insert(rs.end(), {r.stream_begin, r.stream_end});
    root_stream.upload(rs);
  }
  kept_levels.clear();
  host_paths = scene.paths;
  const size_t nroots = roots.size();
  const size_t nin0 = scene.segments.size();
  // Pools from the plan. A scene whose pools would pass the memory cap, or
  // a plan that would make them huge, goes the host-driven way.
  auto pools_fit = [&](size_t nin) {
    const size_t e = plan.bound(DrivePlan::ENTRIES, nin);
    return e <= params.max_entries && e < (size_t(1) << 31) / 4;
  };
  if (!pools_fit(nin0)) return false;
  drive.resize(DRIVE_WORDS);
  MPVG_CUDA(cudaMemsetAsync(drive.data(), 0, DRIVE_WORDS * sizeof(uint32_t)));
  if (!scene.strokes.empty()) {  // host-driven still: its counts come back
    timer.start(&t.stroke_ms);
    stroke(scene);
    timer.stop();
  }
  const size_t nin = scene.strokes.empty() ? nin0 : ninput;
  const size_t E = plan.bound(DrivePlan::ENTRIES, nin), C = std::max(plan.bound(DrivePlan::CELLS, nin), nroots);
  const size_t S = plan.bound(DrivePlan::SEGMENTS, nin), L = plan.bound(DrivePlan::LEAVES, nin);
  const size_t LE = plan.bound(DrivePlan::LEAF_ENTRIES, nin);
  const size_t N = std::max(plan.bound(DrivePlan::NODES, nin), nroots);
  timer.start(&t.abstract_ms);
  abstract_driven(scene, S, E);
  timer.stop();
  timer.start(&t.subdivide_ms);
  subdivide_driven(level, child, true, E, nroots, params);
  timer.stop();
  std::swap(level, child);
  const int max_level = tree_max_level(root_size, params);
  // Every root's coarse grid its own, from its top-level cell (as a
  // forest's): the level loop needs no count from the host.
  root_grid.resize(nroots);
  k_root_grid<<<grid_for(nroots, kBlock), kBlock>>>(level.cells.data(), nroots, max_level, params.min_segments,
                                                   params.grid_levels, root_grid.data());
  launched();
  grid_of_root = root_grid.data();
  capped = false;
  if (params.prune) {
    timer.start(&t.prune_ms);
    prune(level);
    timer.stop();
  }
  nodes.resize(N);
  leaves.resize(L);
  leaf_entries.resize(LE);
  nnodes = N, nleaves = L, nleaf_entries = LE;  // bounds until settle()
  parent.size.resize(2);
  size_t cells_bound = nroots;  // level lv's cells: nroots 4^lv at most, and C
  for (int lv = 0; lv <= max_level; lv++) {
    const size_t ncells = level.ncells;
    counts.resize(2 * (ncells + 1));
    LevelCounts* cnt = counts.data();
    LevelCounts* pos = counts.data() + ncells + 1;
    timer.start(&t.subdivide_ms);
    const bool may_subdivide = lv < max_level;
    k_decide<<<grid_for(ncells + 1, kDecideWarps), kBlock>>>(level.entries.data(), level.cells.data(),
                                                             level.cell_count(), may_subdivide, params.min_segments,
                                                             grid_of_root, cnt);
    launched();
    prim.counted_exclusive(cnt, pos, LevelCountsAdd{}, LevelCounts{0, 0, 0, 0}, level.cell_count().and_one());
    parent.entries.resize(level.nentries);
    parent.entry_cell.resize(level.nentries);
    parent.cells.resize(ncells);
    parent.nentries = level.nentries;
    parent.ncells = ncells;
    parent.driven = true;
    parent.bound = false;
    k_place<<<grid_for(std::max(level.nentries, ncells), kBlock), kBlock>>>(
        level.entries.data(), level.entry_cell.data(), level.nentries, level.cells.data(), level.cell_count(), pos,
        cnt, parent.entries.data(), parent.entry_cell.data(), leaf_entries.data(), parent.cells.data(),
        leaves.data(), 0, 0, nodes.data(), 0, 0, drive.data(), PlacePools{L, LE, N});
    launched();
    k_advance<<<1, 1>>>(pos, level.cell_count(), parent.size.data(), drive.data(), static_cast<uint32_t>(lv));
    launched();
    if (!may_subdivide) {
      timer.stop();
      break;
    }
    cells_bound = std::min(C, 4 * cells_bound);
    subdivide_driven(parent, child, false, E, cells_bound, params);
    timer.stop();
    if (params.prune) {
      timer.start(&t.prune_ms);
      prune(child);
      timer.stop();
    }
    std::swap(level, child);
  }
  timer.collect();
  return true;
}

}  // namespace mpvg::gpu
