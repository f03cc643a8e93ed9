// Device-side state of a gpu::Context (the CUB calls and host words the
// stages share: gpu/primitives.cuh).
#pragma once
#include <cub/cub.cuh>

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <utility>
#include <vector>

#include "core/geometry/abstraction.h"
#include "core/error.h"
#include "core/paint/paint.h"
#include "core/paint/paint_data.h"
#include "core/output/png_encode.h"
#include "core/output/rgba8.h"
#include "core/scan.h"
#include "core/tree/shortcut_tree.h"
#include "core/tree/subdivision.h"
#include "core/sampling/integration.h"
#include "core/tree/tree.h"
#include "gpu/cuda_util.h"
#include "gpu/gpu_backend.h"
#include "gpu/primitives.cuh"

namespace mpvg::gpu {

class StrokeStage;  // gpu/stroke.cuh
class PngStage;     // gpu/png_encode.cuh

// An element count a kernel is launched over: exact on the host (dev
// null), or, in a frame the device drives (build_tree.cu), a bound the host
// sized the launch and the buffers to, with the exact count at *dev.

// One tree level on the device: cells, their entries, and each entry's cell.
struct DeviceLevel {
  DeviceBuffer<Cell> cells;
  DeviceBuffer<Entry> entries;
  DeviceBuffer<uint32_t> entry_cell;
  size_t ncells = 0, nentries = 0;
  // nentries is only a bound: pruning leaves the count of its survivors on
  // the device, and the level's counts (build_tree.cu) bring it back.
  bool bound = false;
  // A device-driven frame: nentries and ncells are bounds, the counts
  // themselves at size[0] and size[1].
  DeviceBuffer<uint32_t> size;
  bool driven = false;
  Count entry_count() const { return Count{nentries, driven ? size.data() : nullptr}; }
  Count cell_count() const { return Count{ncells, driven ? size.data() + 1 : nullptr}; }
};

// The words of a device-driven build (build_tree.cu): the overflow flag
// every stage raises instead of writing past a pool, and the totals the
// host reads once, with the frame's first result.
enum DriveWord : uint32_t {
  DRIVE_OVERFLOW,      // a pool was too small (or the memory cap was hit): the frame runs again, host-driven
  DRIVE_SEGMENTS,      // abstract segments
  DRIVE_LEAVES,        // leaves placed so far
  DRIVE_LEAF_ENTRIES,  // their entries
  DRIVE_NODE_BASE,     // the current level's first node
  DRIVE_NODES,         // nodes made so far
  DRIVE_DEPTH,         // deepest level with cells
  DRIVE_PEAK,          // most entries of a level after pruning (ShortcutTree::peak_level_entries)
  DRIVE_TOTAL,         // entries of all levels so far, after pruning (TreeParams::max_entries)
  DRIVE_MOST_ENTRIES,  // most entries any level's buffer held (the pools' bound)
  DRIVE_MOST_CELLS,    // most cells of a level
  DRIVE_WORDS
};

// The pools of a device-driven build: per input segment, the most any
// build of the context needed (learn), with a margin (scale), and never
// more than 2 scale times the most any needed at all (a scene of few
// segments and many entries must not size the pools of a large one).
struct DrivePlan {
  enum { SEGMENTS, ENTRIES, CELLS, LEAVES, LEAF_ENTRIES, NODES, KINDS };
  double per_input[KINDS] = {};
  size_t most[KINDS] = {};
  size_t builds = 0;   // builds it has learnt from
  double scale = 1.5;  // margin over the most seen (tests shrink it to force overflows)
  void learn(size_t ninput, const size_t (&v)[KINDS]) {
    const double d = double(std::max<size_t>(ninput, 1));
    for (int k = 0; k < KINDS; k++) {
      per_input[k] = std::max(per_input[k], v[k] / d);
      most[k] = std::max(most[k], v[k]);
    }
    builds++;
  }
  size_t bound(int kind, size_t ninput) const {
    const double by_input = scale * per_input[kind] * double(ninput), cap = 2 * scale * double(most[kind]);
    return static_cast<size_t>(std::min(by_input, cap)) + (scale >= 1 ? 1024 : 16);
  }
};

// Four counters scanned together when a level is split into subdivided
// cells and leaves.
struct LevelCounts {
  uint32_t sub, parent_entries, leaf_entries, leaves;
};
struct LevelCountsAdd {
  __host__ __device__ LevelCounts operator()(LevelCounts a, LevelCounts b) const {
    return LevelCounts{a.sub + b.sub, a.parent_entries + b.parent_entries, a.leaf_entries + b.leaf_entries,
                       a.leaves + b.leaves};
  }
};

// A root of a forest rendered with others in one pass (Impl::render_roots):
// its grids and where its buffers are; the kernels of gpu/render.cu read it
// by tree root (the leaves') or by pass slot (blockIdx.y).
struct RootPass {
  int ua_w, ua_h;    // unit areas
  int acc_w, acc_h;  // accumulation pixels
  int out_w, out_h;  // output pixels
  uint32_t root, active, kinds;
  float4* image;
  unsigned long long* acc;
  float4* ua_color;
  float4* buf;
};

struct Context::Impl {
  Primitives prim;
  // Scene.
  DeviceBuffer<InputSegment> input;
  DeviceBuffer<PathRecord> paths;
  DeviceBuffer<Entry> placeholders;      // encoding's stream, one SEGMENT placeholder per path
  DeviceBuffer<uint32_t> path_input;     // first input segment of each path (npaths + 1)
  DeviceBuffer<AbstractSegment> segments;
  size_t npaths = 0, nsegments = 0;
  std::unique_ptr<StrokeStage> stroke_stage;  // made for the first scene with strokes
  size_t ninput = 0;                          // input segments, strokes' included
  int32_t scene_depth = 0;  // deepest nesting of clip groups and transparency groups in the scene
  // Tree under construction and built.
  DeviceLevel level, parent, child;
  DeviceBuffer<Node> nodes;
  DeviceBuffer<Cell> leaves;
  DeviceBuffer<Entry> leaf_entries;
  size_t nnodes = 0, nleaves = 0, nleaf_entries = 0;
  uint32_t root_size = 1;
  int depth = 0;
  size_t peak_level_entries = 0;
  std::vector<TreeLevel> kept_levels;  // TreeParams::keep_levels
  std::vector<PathRecord> host_paths;
  // Paint tables, uploaded once per frame (build), and the pattern tiles'
  // trees, built by the same stages before the scene's own and copied aside.
  struct TileTree {
    DeviceBuffer<AbstractSegment> segments;
    DeviceBuffer<PathRecord> paths;
    DeviceBuffer<Node> nodes;
    DeviceBuffer<Cell> leaves;
    DeviceBuffer<Entry> entries;
    size_t nsegments = 0, npaths = 0, nnodes = 0, nleaves = 0, nentries = 0;
    uint32_t root_size = 1, width = 0, height = 0;
  };
  std::vector<TileTree> tiles;
  size_t ntiles = 0;
  DeviceBuffer<TreeView> tile_views;
  DeviceBuffer<PaintRecord> paints;
  DeviceBuffer<GradientRecord> gradients;
  DeviceBuffer<float> ramp_t;
  DeviceBuffer<Rgba4> ramp_color;
  DeviceBuffer<TextureRecord> textures;
  DeviceBuffer<TextureLevel> texture_levels;
  DeviceBuffer<Texel16> texels;
  DeviceBuffer<PatternRecord> patterns;
  DeviceBuffer<GroupRecord> groups;
  DeviceBuffer<MeshRecord> meshes;
  DeviceBuffer<MeshTriangle> mesh_triangles;
  DeviceBuffer<uint32_t> mesh_cells, mesh_items;
  DeviceBuffer<PaintTables> paint_view;  // one element: paint_tables(), for SampleInputs::paint
  std::shared_ptr<const PaintData> host_paint;
  PaintTables paint_tables() const {
    return PaintTables{paints.data(),   gradients.data(),      ramp_t.data(), ramp_color.data(), textures.data(),
                       texture_levels.data(), texels.data(), patterns.data(), tile_views.data(),
                       groups.data(), meshes.data(), mesh_triangles.data(), mesh_cells.data(),
                       mesh_items.data()};
  }
  // Scratch.
  DeviceBuffer<uint32_t> u32[6];
  DeviceBuffer<int32_t> i32[2];
  DeviceBuffer<SplitScan> split_items, splits;  // subdivide: the split's scan, in and out
  DeviceBuffer<Segmented<uint32_t>> link;
  DeviceBuffer<uint32_t> by_depth[3];  // prune: indices sorted by depth, their depths, the sort's input
  // prune, rules 16, 19, 23 (core/tree/pruning.h): depth and section deltas
  // packed for one scan, section counts, indices sorted by them and their
  // counts, survivors before each sorted position, item weights and their
  // sums in depth order, the second elimination array.
  DeviceBuffer<uint64_t> depth_section, weight, items;
  DeviceBuffer<int32_t> section, elim2;
  DeviceBuffer<uint32_t> by_section[2], shown;
  DeviceBuffer<LevelCounts> counts;
  DeviceBuffer<uint32_t> scalar;  // small results read back by the host
  // Rendering.
  DeviceBuffer<RootPass> pass_table;  // render_roots: per tree root
  DeviceBuffer<uint32_t> pass_slots;  // ... and the roots of its per-pixel launches
  DeviceBuffer<SampleOffset> pattern;
  DeviceBuffer<float4> image;
  DeviceBuffer<float4> leaf_color;
  DeviceBuffer<float4> ua_color;  // wide filters: flat colour per unit area, a < 0 where not uniform
  DeviceBuffer<uint32_t> leaf_batches;  // exclusive scan of batches per leaf
  DeviceBuffer<float> weights, weight_sums, buf;
  DeviceBuffer<double> totals;
  DeviceBuffer<unsigned long long> acc;  // fixed-point accumulators, 4 per pixel
  DeviceBuffer<unsigned long long> sample_count;  // samples evaluated by the last render (timed renders only)
  DeviceBuffer<SrgbCodeTable> srgb_table;  // core/output/rgba8.h's, uploaded on first use
  DeviceBuffer<uint32_t> rgba8;            // the image as 8-bit codes (rgba8.cu)
  // The codes in memory of their own, handed out (rgba8.cu).
  std::shared_ptr<uint8_t> device_rgba8(bool linear);
  std::unique_ptr<PngStage> png_stage;     // made for the first render_png or render_filtered
  int out_width = 0, out_height = 0;
  SamplerShape shape;
  int width = 0, height = 0;
  // The built tree's roots (frame/forest.h): one per scene of a forest,
  // each over its own grid; root_stream holds their stream ranges.
  std::vector<SceneRoot> roots;
  DeviceBuffer<uint32_t> root_stream;
  DeviceBuffer<uint8_t> root_grid;
  const uint8_t* grid_of_root = nullptr;  // a forest's root_grid (core/tree/tree.h, in_root_grid); null for one scene
  bool capped = false;                    // the last tree hit TreeParams::max_entries

  // Device-driven builds (build_tree.cu): after the first build of a
  // context, a frame's levels run from pools sized ahead (plan), every
  // kernel reading its counts from the device, and the host reads the
  // counts once, with the frame's first result (settle()); a frame that
  // outgrew its pools is built again the host-driven way.
  GpuDrive drive_mode = GpuDrive::Host;  // measured slower driven (BENCHMARKS.md): not the default yet
  DrivePlan plan;
  DeviceBuffer<uint32_t> drive;  // DriveWord
  bool pending = false;          // a driven build whose counts the host has not read
  bool last_driven = false, last_fallback = false;
  size_t most_entries = 0, most_cells = 0;  // of a host-driven build, for the plan
  // What a pending build needs to run again host-driven.
  const EncodedScene* pending_scene = nullptr;
  int pending_w = 0, pending_h = 0;
  TreeParams pending_params;
  GpuTimes* pending_times = nullptr;
  size_t fallbacks = 0;
  bool may_drive(const EncodedScene& scene, const TreeParams& params) const;
  void learn(const EncodedScene& scene);  // the plan, from a host-driven build's counts
  // The driven tree, launched: false if the pools cannot be sized (the
  // host-driven build runs instead).
  bool build_tree_driven(const EncodedScene& scene, int w, int h, const TreeParams& params, GpuTimes* times);
  // Reads a pending build's counts (with `extra` words, in the same round
  // trip); false if it overflowed, in which case the tree has been built
  // again host-driven.
  bool settle(std::initializer_list<HostWords::Word> extra = {});

  // The host copies of what the last render uploaded of its integration
  // (pattern, weights): a forest's roots and a run of frames with the same
  // options upload them once.
  std::vector<SampleOffset> pattern_host;
  std::vector<float> weights_host, weight_sums_host;
  std::vector<double> totals_host;
  template <class T>
  void upload_changed(DeviceBuffer<T>& dst, std::vector<T>& host, const std::vector<T>& v) {
    if (dst.size() == v.size() && host.size() == v.size() &&
        (v.empty() || std::memcmp(host.data(), v.data(), v.size() * sizeof(T)) == 0))
      return;
    dst.upload(v);
    host = v;
  }

  // Host round trips and launches, per build (reported by the benchmark).
  size_t launches = 0, syncs = 0;
  size_t build_launches = 0, build_cub_calls = 0, build_syncs = 0;  // of the last build
  void launched() {
    MPVG_LAUNCHED();
    launches++;
  }
  uint32_t read_u32(const uint32_t* p) {
    uint32_t v = 0;
    MPVG_CUDA(cudaMemcpy(&v, p, sizeof v, cudaMemcpyDeviceToHost));
    syncs++;
    return v;
  }
  // Reads several device words in one round trip.
  void read_words(std::initializer_list<std::pair<const uint32_t*, uint32_t*>> words) {
    host_words.read(words);
    syncs++;
  }
  HostWords host_words;
  HostStaging staging;  // uploads that need not wait
  size_t builds = 0;
  // GPU-side allocation failure flag: a kernel that would write past its
  // output's capacity sets it and writes nothing; the host grows the buffer
  // and runs the kernel again.
  DeviceBuffer<uint32_t> overflow;

  // Stages (abstract.cu, subdivide.cu, prune.cu, build_tree.cu, render.cu).
  void stroke(const EncodedScene& scene);  // before abstract(), for scenes with strokes
  void abstract(const EncodedScene& scene);
  void abstract_upload(const EncodedScene& scene);  // the scene's arrays, to the device
  // The same, device-driven: segments and level 0 sized to the bounds.
  void abstract_driven(const EncodedScene& scene, size_t max_segments, size_t max_entries);
  // `counted`: the device's counts of the level `from` was placed from,
  // from's entry and cell counts only bounds; they come back into *tot
  // with the subdivision's total, in one round trip.
  void subdivide(const DeviceLevel& from, DeviceLevel& to, bool root, const LevelCounts* counted = nullptr,
                 LevelCounts* tot = nullptr);
  // The same, device-driven: to's bounds (entries, cells) given, its counts
  // left on the device.
  void subdivide_split(const DeviceLevel& from, Count n, uint32_t fanout, bool root, uint32_t* flags,
                       uint32_t* zero_overflow, bool pad);
  void subdivide_scatter(const DeviceLevel& from, Count n, Count ncells, const LevelCounts* counted, uint32_t fanout,
                         bool root, const uint32_t* flags, DeviceLevel& to, uint32_t* overflow_flag);
  void subdivide_driven(const DeviceLevel& from, DeviceLevel& to, bool root, size_t to_entries, size_t to_cells,
                        const TreeParams& params);
  void prune(DeviceLevel& lv);
  // The whole frame's trees: paint tables uploaded, tiles built and put
  // aside, then the scene's tree.
  void build(const EncodedScene& scene, int width, int height, const TreeParams& params, GpuTimes* times,
             bool render_follows = false);
  // One tree (the scene's or a tile's) into the working buffers.
  void build_tree(const EncodedScene& scene, int width, int height, const TreeParams& params, GpuTimes* times);
  void upload_paints(const PaintData& p);
  void stash_tile(TileTree& t);
  // Renders root `root` of the built tree (0: a frame of one scene).
  // Roots 0 .. frames.size() - 1 of a forest's tree, each into images[k]
  // (frames[k].width x height premultiplied float4s on the device), in one
  // pass: one schedule and sampler launch per sampler specialisation, the
  // per-pixel kernels over all roots at once (blockIdx.y the root); each
  // image the one render() gives its root.
  void render_roots(const Integration& integ, const std::vector<IntegrationFrame>& frames, const PaintRecord& background,
                    const std::vector<float*>& images);
  void render(const Integration& integ, const IntegrationFrame& frame, const PaintRecord& background,
              GpuTimes* times, uint32_t root = 0);
  // The rendered image as straight 8-bit codes (core/output/rgba8.h) in rgba8.
  void convert_rgba8(bool linear);
  // ... copied back.
  std::vector<uint8_t> download_rgba8(bool linear, std::vector<uint8_t> storage);
  // ... filtered and deflated on the device (png_encode.cu): the PNG's
  // channels and IDAT stream, copied back.
  png::ImageData download_png(bool linear);
  // ... filtered on the device, the rows copied back (into storage).
  png::FilteredRows download_filtered(bool linear, std::vector<uint8_t> storage);
};

}  // namespace mpvg::gpu
