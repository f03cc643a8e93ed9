// gpu::Context: the host-facing side of the CUDA executor.
#include "gpu/context.cuh"
#include "gpu/png_encode.cuh"
#include "gpu/stroke.cuh"

#include <cstdlib>
#include <mutex>
#include <string>

namespace mpvg::gpu {

Context::Context() : impl_(std::make_unique<Impl>()) {
  use_retaining_pool();
  if (const char* d = std::getenv("MPVG_GPU_DRIVE")) {
    const std::string v = d;
    if (v == "host") impl_->drive_mode = GpuDrive::Host;
    else if (v == "device") impl_->drive_mode = GpuDrive::Device;
    else if (v != "auto" && !v.empty()) throw Error("MPVG_GPU_DRIVE: expected host, device or auto, not '" + v + "'");
  }
}
Context::~Context() = default;

void Context::build(const EncodedScene& scene, int width, int height, const TreeParams& params, GpuTimes* times,
                    bool render_follows) {
  if (scene.segments.size() >= (size_t(1) << 31)) throw Error("scene too large for the CUDA backend");
  impl_->build(scene, width, height, params, times, render_follows);
}

void Context::set_drive(GpuDrive mode, double pool_scale) {
  if (!(pool_scale > 0)) throw Error("set_drive: the pools' scale must be positive");
  impl_->drive_mode = mode;
  impl_->plan.scale = pool_scale;
}

size_t Context::host_syncs() const { return impl_->syncs; }
size_t Context::kernel_launches() const { return impl_->launches; }

namespace {

// GPU time of a host call that issues work on the default stream.
template <class F>
double timed(F&& f) {
  cudaEvent_t a, b;
  MPVG_CUDA(cudaEventCreate(&a));
  MPVG_CUDA(cudaEventCreate(&b));
  MPVG_CUDA(cudaEventRecord(a));
  f();
  MPVG_CUDA(cudaEventRecord(b));
  MPVG_CUDA(cudaEventSynchronize(b));
  float ms = 0;
  MPVG_CUDA(cudaEventElapsedTime(&ms, a, b));
  cudaEventDestroy(a);
  cudaEventDestroy(b);
  return ms;
}

}  // namespace

double Context::build_timed(const EncodedScene& scene, int width, int height, const TreeParams& params,
                            GpuTimes* times) {
  return timed([&] { build(scene, width, height, params, times); });
}

double Context::render_on_device(const Integration& integ, const IntegrationFrame& frame,
                                 const PaintRecord& background, GpuTimes* times) {
  return timed([&] { impl_->render(integ, frame, background, times); });
}

ShortcutTree Context::download_tree() const {
  impl_->settle();
  const Impl& m = *impl_;
  ShortcutTree t;
  t.root_size = m.root_size;
  t.roots = m.roots;
  t.depth = m.depth;
  t.segments = m.segments.download(m.nsegments);
  t.width = static_cast<uint32_t>(m.width);
  t.height = static_cast<uint32_t>(m.height);
  t.paths = m.host_paths;
  t.paint = m.host_paint;
  for (size_t k = 0; k < m.ntiles; k++) {
    const Impl::TileTree& tt = m.tiles[k];
    ShortcutTree tile;
    tile.root_size = tt.root_size;
    tile.width = tt.width;
    tile.height = tt.height;
    tile.segments = tt.segments.download(tt.nsegments);
    tile.paths = tt.paths.download(tt.npaths);
    tile.nodes = tt.nodes.download(tt.nnodes);
    tile.leaves = tt.leaves.download(tt.nleaves);
    tile.leaf_entries = tt.entries.download(tt.nentries);
    tile.paint = m.host_paint;
    t.tiles.push_back(std::move(tile));
  }
  t.nodes = m.nodes.download(m.nnodes);
  t.leaves = m.leaves.download(m.nleaves);
  t.leaf_entries = m.leaf_entries.download(m.nleaf_entries);
  t.levels = m.kept_levels;
  t.peak_level_entries = m.peak_level_entries;
  t.capped = m.capped;
  return t;
}

ImageF Context::render(const std::vector<SampleOffset>& pattern, const PaintRecord& background, GpuTimes* times) {
  const Integration box = make_integration(Filter::Box, pattern);
  return render(box, integration_frame(box, impl_->width, impl_->height), background, times);
}

ImageF Context::render(const Integration& integ, const IntegrationFrame& frame, const PaintRecord& background,
                       GpuTimes* times, uint32_t root) {
  impl_->render(integ, frame, background, times, root);
  ImageF img;
  img.width = impl_->out_width;
  img.height = impl_->out_height;
  img.rgba.resize(size_t(img.width) * img.height * 4);
  MPVG_CUDA(cudaMemcpy(img.rgba.data(), impl_->image.data(), img.rgba.size() * sizeof(float), cudaMemcpyDeviceToHost));
  impl_->syncs++;
  return img;
}

void Context::render_roots_to_device(const Integration& integ, const std::vector<IntegrationFrame>& frames,
                                     const PaintRecord& background, const std::vector<float*>& images) {
  impl_->render_roots(integ, frames, background, images);
}

std::vector<uint8_t> Context::render_rgba8(const Integration& integ, const IntegrationFrame& frame,
                                          const PaintRecord& background, bool linear, GpuTimes* times,
                                          std::vector<uint8_t> storage, uint32_t root) {
  impl_->render(integ, frame, background, times, root);
  return impl_->download_rgba8(linear, std::move(storage));
}

std::shared_ptr<uint8_t> Context::render_rgba8_device(const Integration& integ, const IntegrationFrame& frame,
                                                      const PaintRecord& background, bool linear, GpuTimes* times,
                                                      uint32_t root) {
  impl_->render(integ, frame, background, times, root);
  return impl_->device_rgba8(linear);
}

png::ImageData Context::render_png(const Integration& integ, const IntegrationFrame& frame,
                                  const PaintRecord& background, bool linear, GpuTimes* times, uint32_t root) {
  impl_->render(integ, frame, background, times, root);
  StageTimer timer(times != nullptr);
  timer.start(times ? &times->png_ms : nullptr);
  png::ImageData data = impl_->download_png(linear);
  timer.stop();
  timer.collect();
  return data;
}

png::FilteredRows Context::render_filtered(const Integration& integ, const IntegrationFrame& frame,
                                           const PaintRecord& background, bool linear, GpuTimes* times,
                                           std::vector<uint8_t> storage, uint32_t root) {
  impl_->render(integ, frame, background, times, root);
  StageTimer timer(times != nullptr);
  timer.start(times ? &times->png_ms : nullptr);
  png::FilteredRows rows = impl_->download_filtered(linear, std::move(storage));
  timer.stop();
  timer.collect();
  return rows;
}

Context::BuildCounts Context::build_counts() const {
  impl_->settle();
  const Impl& m = *impl_;
  return BuildCounts{m.depth,   m.build_launches, m.build_cub_calls, m.build_syncs, m.nsegments,    m.nleaves,
                     m.nleaf_entries, m.capped,   m.last_driven,     m.last_fallback};
}

void Context::set_sampler_shape(const SamplerShape& shape) {
  if (shape.threads < 32 || shape.threads > 1024 || shape.threads % 32 || shape.chunk < 1 || shape.batch < 1 ||
      (shape.batch & (shape.batch - 1)) != 0)
    throw Error("invalid sampler shape");
  impl_->shape = shape;
}

size_t Context::tree_bytes() const {
  impl_->settle();
  const Impl& m = *impl_;
  size_t n = m.nsegments * sizeof(AbstractSegment) + m.nnodes * sizeof(Node) + m.nleaves * sizeof(Cell) +
             m.nleaf_entries * sizeof(Entry) + m.host_paths.size() * sizeof(PathRecord);
  for (size_t k = 0; k < m.ntiles; k++) {
    const Impl::TileTree& tt = m.tiles[k];
    n += tt.nsegments * sizeof(AbstractSegment) + tt.nnodes * sizeof(Node) + tt.nleaves * sizeof(Cell) +
         tt.nentries * sizeof(Entry) + tt.npaths * sizeof(PathRecord);
  }
  if (m.host_paint) n += m.host_paint->bytes();
  return n;
}

void use_retaining_pool() {
  // Once per device (the calling thread's current one).
  static std::mutex mutex;
  static std::vector<bool> done;
  int dev = 0;
  MPVG_CUDA(cudaGetDevice(&dev));
  std::lock_guard<std::mutex> lock(mutex);
  if (size_t(dev) < done.size() && done[dev]) return;
  cudaMemPool_t pool;
  MPVG_CUDA(cudaDeviceGetDefaultMemPool(&pool, dev));
  uint64_t never = UINT64_MAX;
  MPVG_CUDA(cudaMemPoolSetAttribute(pool, cudaMemPoolAttrReleaseThreshold, &never));
  if (done.size() <= size_t(dev)) done.resize(dev + 1);
  done[dev] = true;
}

void reserve_pool(size_t bytes) {
  use_retaining_pool();
  if (bytes == 0) return;
  void* p = nullptr;
  MPVG_CUDA(cudaMallocAsync(&p, bytes, cudaStreamPerThread));
  MPVG_CUDA(cudaFreeAsync(p, cudaStreamPerThread));
  MPVG_CUDA(cudaStreamSynchronize(cudaStreamPerThread));
}

std::string device_name() {
  int dev = 0;
  MPVG_CUDA(cudaGetDevice(&dev));
  cudaDeviceProp p{};
  MPVG_CUDA(cudaGetDeviceProperties(&p, dev));
  return p.name;
}

png::ImageData Context::Impl::download_png(bool linear) {
  convert_rgba8(linear);
  if (!png_stage) png_stage = std::make_unique<PngStage>();
  png::ImageData data = png_stage->run(rgba8.data(), out_width, out_height);
  launches += png_stage->launches;
  syncs += png_stage->syncs;
  return data;
}

png::FilteredRows Context::Impl::download_filtered(bool linear, std::vector<uint8_t> storage) {
  convert_rgba8(linear);
  if (!png_stage) png_stage = std::make_unique<PngStage>();
  png::FilteredRows rows = png_stage->filter(rgba8.data(), out_width, out_height, std::move(storage));
  launches += png_stage->launches;
  syncs += png_stage->syncs;
  return rows;
}

}  // namespace mpvg::gpu
