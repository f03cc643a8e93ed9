// Device-side state of a gpu::Context and the CUB calls the stages share.
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

namespace mpvg::gpu {

class StrokeStage;  // gpu/stroke.cuh
class PngStage;     // gpu/png_encode.cuh

// Small results the host reads back. Once pinned (page-locked memory), the
// copies of several words are queued and one synchronization waits for all
// of them; before, each copy waits on its own (locking pages takes time a
// one-shot run would not earn back: the owner pins from its second frame).
class HostWords {
 public:
  static constexpr size_t kMax = 8;
  HostWords() = default;
  ~HostWords() {
    if (words_) cudaFreeHost(words_);
  }
  HostWords(const HostWords&) = delete;
  HostWords& operator=(const HostWords&) = delete;
  void pin() {
    if (!words_) MPVG_CUDA(cudaMallocHost(&words_, kMax * sizeof(uint32_t)));
  }
  // *host = *device for each pair (at most kMax), in one round trip.
  void read(std::initializer_list<std::pair<const uint32_t*, uint32_t*>> words) {
    if (!words_) {
      for (const auto& w : words) MPVG_CUDA(cudaMemcpy(w.second, w.first, sizeof(uint32_t), cudaMemcpyDeviceToHost));
      return;
    }
    size_t k = 0;
    for (const auto& w : words)
      MPVG_CUDA(cudaMemcpyAsync(words_ + k++, w.first, sizeof(uint32_t), cudaMemcpyDeviceToHost));
    MPVG_CUDA(cudaStreamSynchronize(0));
    k = 0;
    for (const auto& w : words) *w.second = words_[k++];
  }

 private:
  uint32_t* words_ = nullptr;
};

// Host memory the device copies from without waiting: page-locked, grown
// as needed and kept. begin() makes room for a set of arrays (waiting for
// copies still queued from it), put() copies one in and queues its upload;
// the caller's next round trip finds them done. Locking pages costs
// milliseconds per megabyte, which only a reused context earns back: the
// first set goes up the plain way (a copy that waits), later sets through
// the staging.
class HostStaging {
 public:
  HostStaging() = default;
  ~HostStaging() {
    if (p_) cudaFreeHost(p_);
  }
  HostStaging(const HostStaging&) = delete;
  HostStaging& operator=(const HostStaging&) = delete;

  static size_t room(size_t bytes) { return (bytes + 255) & ~size_t{255}; }
  void begin(size_t bytes) {
    used_ = 0;
    staged_ = sets_++ > 0;
    if (!staged_) return;
    MPVG_CUDA(cudaStreamSynchronize(0));
    if (bytes <= cap_) return;
    const size_t cap = std::max(bytes, cap_ + cap_ / 2);  // room for sets to vary
    if (p_) MPVG_CUDA(cudaFreeHost(p_));
    p_ = nullptr;
    cap_ = 0;
    MPVG_CUDA(cudaMallocHost(&p_, cap));
    cap_ = cap;
  }
  template <class T>
  void put(DeviceBuffer<T>& dst, const std::vector<T>& v) {
    if (!staged_) {
      dst.upload(v);
      return;
    }
    dst.resize(v.size());
    const size_t bytes = v.size() * sizeof(T);
    if (!bytes) return;
    if (used_ + room(bytes) > cap_) throw Error("staging: more bytes put than begin() made room for");
    std::memcpy(p_ + used_, v.data(), bytes);
    MPVG_CUDA(cudaMemcpyAsync(dst.data(), p_ + used_, bytes, cudaMemcpyHostToDevice));
    used_ += room(bytes);
  }

 private:
  unsigned char* p_ = nullptr;
  size_t cap_ = 0, used_ = 0, sets_ = 0;
  bool staged_ = false;
};

// The bits a radix sort needs for keys up to max_key (at least one).
inline int key_bits(uint64_t max_key) {
  int bits = 1;
  while (bits < 32 && (uint64_t{1} << bits) <= max_key) bits++;
  return bits;
}

// Scans, reductions and compactions through CUB, with one temporary buffer
// ("ask for the temp storage size first").
class Primitives {
 public:
  size_t calls = 0;  // CUB calls issued (each one to three kernels)

  template <class In, class Out>
  void exclusive_sum(In in, Out out, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::ExclusiveSum(temp(bytes), bytes, in, out, static_cast<int>(n)));
  }
  template <class In, class Out>
  void inclusive_sum(In in, Out out, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::InclusiveSum(nullptr, bytes, in, out, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::InclusiveSum(temp(bytes), bytes, in, out, static_cast<int>(n)));
  }
  template <class In, class Out, class Op>
  void inclusive_scan(In in, Out out, Op op, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::InclusiveScan(nullptr, bytes, in, out, op, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::InclusiveScan(temp(bytes), bytes, in, out, op, static_cast<int>(n)));
  }
  template <class In, class Out, class Op, class T>
  void exclusive_scan(In in, Out out, Op op, T init, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::ExclusiveScan(nullptr, bytes, in, out, op, init, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::ExclusiveScan(temp(bytes), bytes, in, out, op, init, static_cast<int>(n)));
  }
  // Stable: equal keys keep their order. Only keys' bits [0, bits) count
  // (key_bits).
  template <class K, class V>
  void sort_pairs(const K* keys_in, K* keys_out, const V* values_in, V* values_out, size_t n, int bits) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys_in, keys_out, values_in, values_out,
                                              static_cast<int>(n), 0, bits));
    MPVG_CUDA(cub::DeviceRadixSort::SortPairs(temp(bytes), bytes, keys_in, keys_out, values_in, values_out,
                                              static_cast<int>(n), 0, bits));
  }
  template <class In, class Out>
  void reduce_max(In in, Out out, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceReduce::Max(nullptr, bytes, in, out, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceReduce::Max(temp(bytes), bytes, in, out, static_cast<int>(n)));
  }

 private:
  void* temp(size_t bytes) {
    temp_.resize(bytes);
    return temp_.data();
  }
  DeviceBuffer<uint8_t> temp_;
};

// One tree level on the device: cells, their entries, and each entry's cell.
struct DeviceLevel {
  DeviceBuffer<Cell> cells;
  DeviceBuffer<Entry> entries;
  DeviceBuffer<uint32_t> entry_cell;
  size_t ncells = 0, nentries = 0;
  // nentries is only a bound: pruning leaves the count of its survivors on
  // the device, and the level's counts (build_tree.cu) bring it back.
  bool bound = false;
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
  std::unique_ptr<PngStage> png_stage;     // made for the first render_png
  int out_width = 0, out_height = 0;
  SamplerShape shape;
  int width = 0, height = 0;
  // The built tree's roots (core/tree/forest.h): one per scene of a forest,
  // each over its own grid; root_stream holds their stream ranges.
  std::vector<SceneRoot> roots;
  DeviceBuffer<uint32_t> root_stream;
  DeviceBuffer<uint8_t> root_grid;
  const uint8_t* grid_of_root = nullptr;  // a forest's root_grid (core/tree/tree.h, in_root_grid); null for one scene
  bool capped = false;                    // the last tree hit TreeParams::max_entries

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
  // `counted`: the device's counts of the level `from` was placed from,
  // from's entry and cell counts only bounds; they come back into *tot
  // with the subdivision's total, in one round trip.
  void subdivide(const DeviceLevel& from, DeviceLevel& to, bool root, const LevelCounts* counted = nullptr,
                 LevelCounts* tot = nullptr);
  void prune(DeviceLevel& lv);
  // The whole frame's trees: paint tables uploaded, tiles built and put
  // aside, then the scene's tree.
  void build(const EncodedScene& scene, int width, int height, const TreeParams& params, GpuTimes* times);
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
};

}  // namespace mpvg::gpu
