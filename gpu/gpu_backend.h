// The CUDA executor of the pipeline (paper §4.2, §4.4, §5.3). The same
// per-element functions of core/ as the CPU executor, run by kernels; scans
// and compactions by CUB. Plain C++ interface: tests and tools compiled with
// g++ use it without seeing CUDA.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/output/image.h"
#include "frame/encoding.h"
#include "core/sampling/integration.h"
#include "core/output/png_encode.h"
#include "core/tree/tree.h"

namespace mpvg::gpu {

// GPU time per stage, from CUDA events, in milliseconds.
struct GpuTimes {
  double stroke_ms = 0, abstract_ms = 0, subdivide_ms = 0, prune_ms = 0, schedule_ms = 0, sample_ms = 0;
  double integrate_ms = 0;  // wide filters: normalisation, prefilter, output
  double png_ms = 0;        // the PNG stage on the device (render_png)
  uint64_t samples = 0;     // samples evaluated (adaptive sampling: core/sampling/sampling.h, unit_area_flat)
  double preprocess_ms() const { return stroke_ms + abstract_ms + subdivide_ms + prune_ms; }
  double render_ms() const { return schedule_ms + sample_ms + integrate_ms; }
};

// Kernel shape of the sampler (§5.3): threads per block (the paper's S, the
// samples in flight), entries streamed through shared memory per chunk (I),
// and unit areas per batch (U, a power of two: a batch is a tile of unit
// areas, 8 x 4 for 32). The paper used S = 128, I = 32, U = 32 on a GTX
// Titan; on an H200 S = 64 measured fastest (BENCHMARKS.md).
struct SamplerShape {
  int threads = 64;
  int chunk = 32;
  int batch = 32;
};

// Who drives a frame's tree build. Host: the host reads each level's
// counts back to size the next (a round trip per level). Device: the
// levels run from pools sized ahead, every kernel reading its counts on
// the device, the host waiting once, with the frame's first result; a
// frame that outgrows its pools is built again host-driven. Auto:
// device-driven from a context's second build, once its first has
// measured what the pools need. The default is Host: on the H200 the
// driven build measured slower (BENCHMARKS.md, issue 49). MPVG_GPU_DRIVE=host|device|auto
// overrides it (measurements).
enum class GpuDrive { Auto, Host, Device };

// Device state, reused across frames: buffers grow to the largest scene seen
// and are kept, so repeated frames measure the pipeline, not cudaMalloc.
class Context {
 public:
  Context();
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Uploads an encoded scene and builds its shortcut tree on the GPU. The
  // tree stays on the device; times, if given, receive per-stage GPU times.
  // render_follows: the caller renders the tree before `scene` goes away,
  // so that a device-driven build's counts come back with the render's
  // first read (one round trip fewer) and an overflow can build again.
  void build(const EncodedScene& scene, int width, int height, const TreeParams& params, GpuTimes* times = nullptr,
             bool render_follows = false);

  // As build(); returns the GPU time of the whole build, host round trips
  // between kernels included, in ms (events around it).
  double build_timed(const EncodedScene& scene, int width, int height, const TreeParams& params, GpuTimes* times);

  // The built tree as host arrays, levels included when params.keep_levels.
  ShortcutTree download_tree() const;

  // Renders the built tree (built over frame's unit-area grid): samples
  // every unit area with its class's pattern (integ.offsets), integrates as
  // integ says, composites over the background; returns the image in the
  // integration colour space. A forest's tree (frame/forest.h) renders one
  // root at a time, each over its own grid; every render below takes it.
  ImageF render(const Integration& integ, const IntegrationFrame& frame, const PaintRecord& background,
                GpuTimes* times = nullptr, uint32_t root = 0);
  // The box filter over the pixels the tree was built for.
  ImageF render(const std::vector<SampleOffset>& pattern, const PaintRecord& background, GpuTimes* times = nullptr);

  // Roots 0 .. frames.size() - 1 of a forest's tree rendered in one pass,
  // root k into images[k] on the device (frames[k].width x height
  // premultiplied RGBA floats): each the image render() gives that root,
  // the launches and host round trips of one frame for all of them.
  void render_roots_to_device(const Integration& integ, const std::vector<IntegrationFrame>& frames,
                              const PaintRecord& background, const std::vector<float*>& images);

  // As render(), returning the image as straight 8-bit codes, 4 bytes per
  // pixel (core/output/rgba8.h; linear: the image was integrated in linear light),
  // converted on the device: a quarter of the float image is copied back.
  // The result reuses storage's memory where it is large enough (batches
  // hand back the buffers of written pages: fresh pages of memory cost a
  // page fault each while the copy fills them).
  std::vector<uint8_t> render_rgba8(const Integration& integ, const IntegrationFrame& frame,
                                    const PaintRecord& background, bool linear, GpuTimes* times = nullptr,
                                    std::vector<uint8_t> storage = {}, uint32_t root = 0);

  // As render_rgba8(), the codes left on the device in memory of their own
  // (cudaMalloc'd, freed with the last copy of the returned pointer), the
  // copy into it finished: for callers that hand the image on without a
  // round trip through the host (libmpvg's device bitmaps, DLPack).
  std::shared_ptr<uint8_t> render_rgba8_device(const Integration& integ, const IntegrationFrame& frame,
                                               const PaintRecord& background, bool linear, GpuTimes* times = nullptr,
                                               uint32_t root = 0);

  // As render_rgba8(), the image filtered and deflated on the device
  // (core/output/png_encode.h's stages, gpu/png_encode.cu): only the PNG's
  // compressed data is copied back; the same bytes as the CPU executor's
  // filter_image and deflate_zlib give.
  png::ImageData render_png(const Integration& integ, const IntegrationFrame& frame, const PaintRecord& background,
                            bool linear, GpuTimes* times = nullptr, uint32_t root = 0);

  // As render_png(), the first half only: the rows filtered on the device
  // (core/output/png_filter.h) and copied back, into storage's memory where
  // it is large enough, for the CPU to deflate (png::encode_filtered): the
  // same rows as the CPU executor's filter_image, a quarter fewer bytes
  // than the RGBA codes for an opaque image.
  png::FilteredRows render_filtered(const Integration& integ, const IntegrationFrame& frame,
                                    const PaintRecord& background, bool linear, GpuTimes* times = nullptr,
                                    std::vector<uint8_t> storage = {}, uint32_t root = 0);

  // As render(), leaving the image on the device (benchmarks); returns the
  // GPU time of the whole render, gaps between kernels included, in ms.
  double render_on_device(const Integration& integ, const IntegrationFrame& frame, const PaintRecord& background,
                          GpuTimes* times = nullptr);

  // Work issued by the last build: tree depth, kernel launches, CUB calls,
  // and host round trips (device-to-host reads that wait for the GPU); and
  // what it built: abstract segments, leaf cells, leaf entries.
  struct BuildCounts {
    int depth = 0;
    size_t launches = 0, cub_calls = 0, syncs = 0;
    size_t abstract_segments = 0, leaves = 0, leaf_entries = 0;
    bool capped = false;  // a level was not made (TreeParams::max_entries)
    bool driven = false;    // the device drove the build (GpuDrive) ...
    bool fallback = false;  // ... and it outgrew its pools: built again host-driven
  };
  BuildCounts build_counts() const;

  // GpuDrive; pool_scale: the margin of the pools over the most a build
  // of this context needed per input segment (1.5; below 1 forces
  // overflows, for tests).
  void set_drive(GpuDrive mode, double pool_scale = 1.5);
  // Host round trips and kernel launches since the context was made (a
  // frame's: the difference around it).
  size_t host_syncs() const;
  size_t kernel_launches() const;

  void set_sampler_shape(const SamplerShape& shape);
  size_t tree_bytes() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Name of the CUDA device in use, e.g. "NVIDIA H100 80GB HBM3".
std::string device_name();

// Device buffers come from the device's stream-ordered memory pool, which
// keeps what is freed (release threshold: never) for the next allocation:
// a buffer that grows, or a frame after a warm-up, does not map memory
// again. reserve_pool grows the pool by `bytes` at once (one mapping
// instead of one per buffer of the first frame).
void use_retaining_pool();
void reserve_pool(size_t bytes);

}  // namespace mpvg::gpu
