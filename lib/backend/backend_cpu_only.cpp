// The backend dispatcher of a build without CUDA.
#include "core/error.h"
#include "cpu/png_encode.h"
#include "lib/backend/backend.h"
#include "cpu/cpu_frame.h"

namespace mpvg {

bool cuda_available(std::string* why) {
  if (why) *why = "mpvg was built without CUDA";
  return false;
}

ImageF render(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
  if (options.backend == Backend::Cuda) throw UnsupportedError("CUDA backend unavailable: mpvg was built without CUDA");
  ImageF img = render_cpu(scene, options, stats);
  if (stats && options.backend == Backend::Auto) stats->note = "no CUDA backend in this build; rendered on the CPU";
  return img;
}

int cuda_device_count() { return 0; }

struct FrameRenderer::Impl {
  std::string note;
};

FrameRenderer::FrameRenderer(Backend backend, int) : impl_(std::make_unique<Impl>()) {
  if (backend == Backend::Cuda) throw UnsupportedError("CUDA backend unavailable: mpvg was built without CUDA");
  if (backend == Backend::Auto) impl_->note = "no CUDA backend in this build; rendered on the CPU";
}
FrameRenderer::~FrameRenderer() = default;
Backend FrameRenderer::backend() const { return Backend::Cpu; }
int FrameRenderer::device() const { return 0; }
const std::string& FrameRenderer::note() const { return impl_->note; }
EncodedScene FrameRenderer::encode(const Scene& scene, const RenderPlan& plan, const RenderOptions& options,
                                   RenderStats* stats) {
  return encode_for(scene, plan, options.gamma, stats);
}

ImageF FrameRenderer::render(const EncodedScene& scene, const RenderOptions& options, RenderStats* stats) {
  ImageF img = render_cpu(scene, options, stats);
  if (stats) stats->note = impl_->note;
  return img;
}

FrameRenderer::DeviceImage FrameRenderer::render_rgba8_device(const EncodedScene&, const RenderPlan&,
                                                              const RenderOptions&, RenderStats*) {
  throw UnsupportedError("device output needs the CUDA backend (this build has none)");
}

std::shared_ptr<uint8_t> FrameRenderer::device_alloc(size_t, int) {
  throw UnsupportedError("device output needs the CUDA backend (this build has none)");
}

void FrameRenderer::copy_on_device(const DeviceImage&, uint8_t*) {
  throw UnsupportedError("device output needs the CUDA backend (this build has none)");
}

std::vector<uint8_t> FrameRenderer::download(const DeviceImage&) {
  throw UnsupportedError("device output needs the CUDA backend (this build has none)");
}

std::vector<uint8_t> FrameRenderer::render_rgba8(const EncodedScene& scene, const RenderPlan& plan,
                                                const RenderOptions& options, RenderStats* stats,
                                                std::vector<uint8_t> /*storage*/) {
  std::vector<uint8_t> out = render_cpu_rgba8(scene, plan, options, stats);
  if (stats) stats->note = impl_->note;
  return out;
}

png::ImageData FrameRenderer::render_png(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                                         RenderStats* stats) {
  RenderStats local;
  RenderStats& st = stats ? *stats : local;
  const std::vector<uint8_t> rgba8 = render_cpu_rgba8(scene, plan, options, &st);
  st.note = impl_->note;
  const auto t0 = std::chrono::steady_clock::now();
  png::ImageData data = png::compress_rgba8(rgba8.data(), plan.frame.width, plan.frame.height);
  st.png_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return data;
}

png::FilteredRows FrameRenderer::render_filtered(const EncodedScene& scene, const RenderPlan& plan,
                                                 const RenderOptions& options, RenderStats* stats,
                                                 std::vector<uint8_t> storage) {
  const std::vector<uint8_t> rgba8 = render_cpu_rgba8(scene, plan, options, stats);
  png::FilteredRows rows = filter_rows_cpu(rgba8.data(), plan.frame.width, plan.frame.height, stats, std::move(storage));
  if (stats) stats->note = impl_->note;
  return rows;
}

std::vector<FrameRenderer::Output> FrameRenderer::render_forest(const std::vector<FrameScene>& scenes,
                                                               const RenderOptions& options, FrameOutputKind kind,
                                                               std::vector<std::vector<uint8_t>> storage) {
  (void)storage;
  std::vector<Output> out = render_forest_cpu_8bit(scenes, options, kind);
  for (const FrameScene& s : scenes)
    if (s.stats) s.stats->note = impl_->note;
  return out;
}

void FrameRenderer::warm_up(const RenderOptions&, size_t) {}

struct GpuStartup::State {};

GpuStartup::GpuStartup(Backend, const RenderOptions&) : t0_(std::chrono::steady_clock::now()) {}
GpuStartup::~GpuStartup() = default;
bool GpuStartup::started() const { return false; }
bool GpuStartup::done() const { return true; }
double GpuStartup::elapsed_ms() const {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count();
}
double GpuStartup::ready_ms() const { return 0; }
std::string GpuStartup::phases() const { return {}; }
void GpuStartup::cancel() {}
std::unique_ptr<FrameRenderer> GpuStartup::take(std::string* why) {
  if (why) *why = "mpvg was built without CUDA";
  return nullptr;
}

}  // namespace mpvg
