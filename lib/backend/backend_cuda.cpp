// The backend dispatcher of a build with CUDA.
#include <cuda_runtime.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>

#include "core/error.h"
#include "cpu/png_encode.h"
#include "frame/forest.h"
#include "frame/filter_layers.h"
#include "lib/backend/backend.h"
#include "gpu/cuda_util.h"
#include "gpu/filter.h"
#include "gpu/gpu_backend.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"
#include "frame/scene_info.h"

namespace mpvg {

bool cuda_available(std::string* why) {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess || n == 0) {
    if (why) *why = e != cudaSuccess ? std::string("no usable CUDA device (") + cudaGetErrorString(e) + ")"
                                     : std::string("no CUDA device");
    cudaGetLastError();  // clear the sticky error of a failed query
    return false;
  }
  return true;
}

namespace {

// Builds the tree of `enc` and renders it on ctx; `finish` renders (into
// whichever image it returns) and fills stats.
template <class Finish>
auto render_cuda(gpu::Context& ctx, const EncodedScene& enc, const RenderPlan& plan, const RenderOptions& o,
                 RenderStats& st, Finish&& finish) {
  st.backend = "cuda";
  const auto t_all = std::chrono::steady_clock::now();
  gpu::GpuTimes gt;
  gpu::GpuTimes* times = st.stage_times ? &gt : nullptr;
  ctx.build(enc, plan.frame.ua_w, plan.frame.ua_h, plan.tree, times, /*render_follows=*/true);
  auto img = finish(background_paint(o.background, o.gamma), times);
  st.stroke_ms += gt.stroke_ms;
  st.abstract_ms += gt.abstract_ms;
  st.subdivide_ms += gt.subdivide_ms;
  st.prune_ms += gt.prune_ms;
  st.schedule_ms += gt.schedule_ms;
  st.sample_ms += gt.sample_ms + gt.integrate_ms;
  st.samples += gt.samples;
  st.pixels += uint64_t(plan.frame.width) * uint64_t(plan.frame.height);
  st.total_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_all).count();
  st.input_segments = enc.input_segment_count;
  st.tree_bytes = ctx.tree_bytes();
  const gpu::Context::BuildCounts counts = ctx.build_counts();
  st.abstract_segments = counts.abstract_segments;
  st.depth = counts.depth;
  st.leaves = counts.leaves;
  st.leaf_entries = counts.leaf_entries;
  return img;
}

ImageF render_cuda(gpu::Context& ctx, const EncodedScene& enc, const RenderPlan& plan, const RenderOptions& o,
                   RenderStats& st) {
  return render_cuda(ctx, enc, plan, o, st, [&](const PaintRecord& bg, gpu::GpuTimes* gt) {
    return ctx.render(plan.integ, plan.frame, bg, gt);
  });
}

ImageF render_cuda(gpu::Context& ctx, const Scene& scene, const RenderOptions& options, RenderStats& st);

// Filter layers on the device (frame/filter_layers.h's FilterExecutor): the
// sources encoded (their own filters resolved by this executor first),
// those that can share a frame rendered as forest frames (frame/forest.h:
// one tree build for all, each root to the image it has alone), every
// root rendered straight into its layer's source plane on the device (a
// source alone: a frame of one root); then all the
// graphs batched (gpu/filter.h), the results left on the device as the
// textures' texels.
FilterExecutor cuda_filters(gpu::Context& ctx) {
  return FilterExecutor{[&ctx](std::vector<LayerJob>& jobs) {
    const FilterExecutor inner = cuda_filters(ctx);
    // MPVG_FILTER_TIMES=1: each call's parts on stderr, the device waited
    // for at each boundary (measurements only).
    static const bool timed = std::getenv("MPVG_FILTER_TIMES") != nullptr;
    auto t_mark = std::chrono::steady_clock::now();
    std::string times;
    auto lap = [&](const char* what) {
      if (!timed) return;
      cudaDeviceSynchronize();
      const auto now = std::chrono::steady_clock::now();
      times += std::string(" ") + what + " " +
               std::to_string(std::chrono::duration<double, std::milli>(now - t_mark).count()).substr(0, 6) + " ms";
      t_mark = now;
    };
    std::vector<size_t> live;
    for (size_t k = 0; k < jobs.size(); k++)
      if (jobs[k].layer.width > 0 && jobs[k].layer.height > 0) live.push_back(k);
    std::vector<RenderPlan> plans(jobs.size());
    std::vector<EncodedScene> encs(jobs.size());
    // (Encoding the sources on several threads measured slower: 9.5 ms
    // against 5.8 for 100 small ones, each encode spawning its own.)
    for (size_t k : live) {
      LayerJob& j = jobs[k];
      for (const LayerJob::Element& e : j.elements) {
        RenderStats ignored;
        ignored.stage_times = false;
        j.layer.images[e.image] = render_cuda(ctx, *e.scene, e.options, ignored);
      }
      plans[k] = plan_render(j.source_options);
      encs[k] = encode_for(*j.source, plans[k], j.source_options.gamma, nullptr, &inner);
    }
    lap("encode");
    // The sources' planes, one buffer.
    std::vector<size_t> offset(jobs.size(), 0);
    size_t total = 0;
    for (size_t k : live) offset[k] = total, total += size_t(jobs[k].layer.width) * jobs[k].layer.height * 4;
    gpu::DeviceBuffer<float> sources(std::max<size_t>(total, 4));
    const PaintRecord bg = background_paint(RGBA{0, 0, 0, 0}, live.empty() ? Gamma::Srgb : jobs[live[0]].source_options.gamma);
    // A source alone in its frame, rendered straight into its plane.
    auto alone = [&](size_t k) {
      const RenderPlan& p = plans[k];
      ctx.build(encs[k], p.frame.ua_w, p.frame.ua_h, p.tree);
      ctx.render_roots_to_device(p.integ, {p.frame}, bg, {sources.data() + offset[k]});
    };
    // Forests: sources with no device texels whose frames agree.
    std::vector<std::vector<size_t>> groups;
    for (size_t k : live) {
      const bool shareable = !encs[k].paint || encs[k].paint->device_texels.empty();
      std::vector<size_t>* g = nullptr;
      for (std::vector<size_t>& c : groups) {
        const size_t f = c.front();
        if (shareable && (!encs[f].paint || encs[f].paint->device_texels.empty()) && c.size() < kMaxForestRoots &&
            same_frame_options(jobs[f].source_options, jobs[k].source_options) && same_frame_grid(plans[f], plans[k])) {
          g = &c;
          break;
        }
      }
      if (g) g->push_back(k);
      else groups.push_back({k});
    }
    for (const std::vector<size_t>& g : groups) {
      if (g.size() == 1) {
        alone(g[0]);
        continue;
      }
      std::vector<FrameScene> fs;
      for (size_t k : g) fs.push_back(FrameScene{&encs[k], &plans[k], nullptr});
      int w = 0, h = 0;
      {
        const EncodedScene forest = forest_of(fs);
        forest_grid(forest, w, h);
        ctx.build(forest, w, h, plans[g[0]].tree);
      }
      lap("forest build");
      if (ctx.build_counts().capped) {  // one frame each, as a batch would
        for (size_t k : g) alone(k);
        continue;
      }
      // Every root at once, each into its layer's source plane.
      std::vector<IntegrationFrame> frames;
      std::vector<float*> images;
      for (size_t k : g) frames.push_back(plans[k].frame), images.push_back(sources.data() + offset[k]);
      ctx.render_roots_to_device(plans[g[0]].integ, frames, bg, images);
    }
    lap("renders");
    std::vector<const FilterLayer*> layers;
    std::vector<const float*> srcs;
    for (size_t k : live) layers.push_back(&jobs[k].layer), srcs.push_back(sources.data() + offset[k]);
    std::vector<std::shared_ptr<const Image>> out(jobs.size());
    if (live.empty()) return out;
    const std::vector<std::shared_ptr<const Image>> made =
        gpu::run_filters_cuda(layers, srcs, jobs[live[0]].source_options.gamma);
    for (size_t i = 0; i < live.size(); i++) out[live[i]] = made[i];
    lap("graphs");
    if (timed)
      std::fprintf(stderr, "filter layers: %zu in %zu frames:%s\n", live.size(), groups.size(), times.c_str());
    return out;
  }};
}

ImageF render_cuda(gpu::Context& ctx, const Scene& scene, const RenderOptions& options, RenderStats& st) {
  const auto t_all = std::chrono::steady_clock::now();
  RenderOptions o = options;
  o.aliased_paths = o.aliased_paths || has_aliased_paths(scene);
  const RenderPlan plan = plan_render(o);
  const FilterExecutor filters = cuda_filters(ctx);
  const EncodedScene enc = encode_for(scene, plan, o.gamma, &st, &filters);
  const double encode_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_all).count();
  ImageF img = render_cuda(ctx, enc, plan, o, st);
  st.total_ms += encode_ms;
  return img;
}

ImageF render_cuda(const Scene& scene, const RenderOptions& options, RenderStats& st) {
  gpu::Context ctx;
  return render_cuda(ctx, scene, options, st);
}

}  // namespace

ImageF render(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
  RenderStats local;
  local.stage_times = false;  // nobody reads them
  RenderStats& st = stats ? *stats : local;
  if (options.backend == Backend::Cpu) return render_cpu(scene, options, &st);
  std::string why;
  if (!cuda_available(&why)) {
    if (options.backend == Backend::Cuda) throw ResourceError("CUDA backend unavailable: " + why);
    ImageF img = render_cpu(scene, options, &st);
    st.note = why + "; rendered on the CPU";
    return img;
  }
  return render_cuda(scene, options, st);
}

int cuda_device_count() {
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) {
    cudaGetLastError();
    return 0;
  }
  return n;
}

struct FrameRenderer::Impl {
  Backend backend = Backend::Cpu;
  int device = 0;
  std::string note;
  std::unique_ptr<gpu::Context> ctx;
};

FrameRenderer::FrameRenderer(Backend backend, int device) : impl_(std::make_unique<Impl>()) {
  if (backend == Backend::Cpu) return;
  std::string why;
  if (!cuda_available(&why)) {
    if (backend == Backend::Cuda) throw ResourceError("CUDA backend unavailable: " + why);
    impl_->note = why + "; rendered on the CPU";
    return;
  }
  impl_->backend = Backend::Cuda;
  // How a host thread waits for the device (before the context exists):
  // MPVG_CUDA_SYNC=spin|yield|block, for measurements; the driver's
  // default otherwise (it spins while the process has fewer contexts than
  // cores, taking a core from the CPU stages of a pipeline per waiting
  // thread).
  static std::once_flag once;
  std::call_once(once, [] {
    const char* sync = std::getenv("MPVG_CUDA_SYNC");
    const std::string mode = sync ? sync : "";
    const unsigned flags = mode == "spin"    ? cudaDeviceScheduleSpin
                           : mode == "yield" ? cudaDeviceScheduleYield
                           : mode == "block" ? cudaDeviceScheduleBlockingSync
                                             : cudaDeviceScheduleAuto;
    if (flags != cudaDeviceScheduleAuto) cudaSetDeviceFlags(flags);
  });
  if (device < 0 || device >= cuda_device_count())
    throw Error("no CUDA device " + std::to_string(device) + " (" + std::to_string(cuda_device_count()) +
                " visible)");
  impl_->device = device;
  if (cudaSetDevice(device) != cudaSuccess) throw Error("cannot use CUDA device " + std::to_string(device));
  impl_->ctx = std::make_unique<gpu::Context>();
}
FrameRenderer::~FrameRenderer() {
  // The buffers go back to their own device's pool.
  if (impl_ && impl_->ctx) cudaSetDevice(impl_->device);
}
Backend FrameRenderer::backend() const { return impl_->backend; }
int FrameRenderer::device() const { return impl_->device; }
const std::string& FrameRenderer::note() const { return impl_->note; }

EncodedScene FrameRenderer::encode(const Scene& scene, const RenderPlan& plan, const RenderOptions& options,
                                   RenderStats* stats) {
  if (impl_->backend == Backend::Cpu || !has_filters(scene)) return encode_for(scene, plan, options.gamma, stats);
  cudaSetDevice(impl_->device);
  const FilterExecutor filters = cuda_filters(*impl_->ctx);
  return encode_for(scene, plan, options.gamma, stats, &filters);
}

ImageF FrameRenderer::render(const EncodedScene& scene, const RenderOptions& options, RenderStats* stats) {
  RenderStats local;
  local.stage_times = false;  // nobody reads them
  RenderStats& st = stats ? *stats : local;
  st.note = impl_->note;
  if (impl_->backend == Backend::Cpu) return render_cpu(scene, options, &st);
  cudaSetDevice(impl_->device);
  return render_cuda(*impl_->ctx, scene, plan_render(options), options, st);
}

std::vector<uint8_t> FrameRenderer::render_rgba8(const EncodedScene& scene, const RenderPlan& plan,
                                                const RenderOptions& options, RenderStats* stats,
                                                std::vector<uint8_t> storage) {
  RenderStats local;
  local.stage_times = false;  // nobody reads them
  RenderStats& st = stats ? *stats : local;
  st.note = impl_->note;
  if (impl_->backend == Backend::Cpu) return render_cpu_rgba8(scene, plan, options, &st);
  cudaSetDevice(impl_->device);
  gpu::Context& ctx = *impl_->ctx;
  return render_cuda(ctx, scene, plan, options, st, [&](const PaintRecord& bg, gpu::GpuTimes* gt) {
    return ctx.render_rgba8(plan.integ, plan.frame, bg, options.gamma == Gamma::Linear, gt, std::move(storage));
  });
}

FrameRenderer::DeviceImage FrameRenderer::render_rgba8_device(const EncodedScene& scene, const RenderPlan& plan,
                                                              const RenderOptions& options, RenderStats* stats) {
  if (impl_->backend == Backend::Cpu) throw UnsupportedError("device output needs the CUDA backend (rendering on the CPU)");
  RenderStats local;
  local.stage_times = false;  // nobody reads them
  RenderStats& st = stats ? *stats : local;
  st.note = impl_->note;
  cudaSetDevice(impl_->device);
  gpu::Context& ctx = *impl_->ctx;
  DeviceImage out;
  out.data = render_cuda(ctx, scene, plan, options, st, [&](const PaintRecord& bg, gpu::GpuTimes* gt) {
    return ctx.render_rgba8_device(plan.integ, plan.frame, bg, options.gamma == Gamma::Linear, gt);
  });
  out.width = options.width;
  out.height = options.height;
  out.device = impl_->device;
  return out;
}

std::shared_ptr<uint8_t> FrameRenderer::device_alloc(size_t bytes, int device) {
  cudaSetDevice(device);
  void* p = nullptr;
  if (cudaMalloc(&p, bytes ? bytes : 4) != cudaSuccess) throw ResourceError("out of device memory for a batch of images");
  return std::shared_ptr<uint8_t>(static_cast<uint8_t*>(p), [](uint8_t* q) { cudaFree(q); });
}

void FrameRenderer::copy_on_device(const DeviceImage& image, uint8_t* to) {
  const size_t bytes = size_t(image.width) * image.height * 4;
  cudaSetDevice(image.device);
  if (bytes && (cudaMemcpyAsync(to, image.data.get(), bytes, cudaMemcpyDeviceToDevice, cudaStreamPerThread) != cudaSuccess ||
                cudaStreamSynchronize(cudaStreamPerThread) != cudaSuccess))
    throw Error("cannot copy a device image");
}

std::vector<uint8_t> FrameRenderer::download(const DeviceImage& image) {
  std::vector<uint8_t> out(size_t(image.width) * image.height * 4);
  if (!out.empty()) {
    cudaSetDevice(image.device);
    if (cudaMemcpy(out.data(), image.data.get(), out.size(), cudaMemcpyDeviceToHost) != cudaSuccess)
      throw Error("cannot copy a device image to the host");
  }
  return out;
}

png::ImageData FrameRenderer::render_png(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                                         RenderStats* stats) {
  RenderStats local;
  local.stage_times = false;  // nobody reads them
  RenderStats& st = stats ? *stats : local;
  st.note = impl_->note;
  if (impl_->backend == Backend::Cpu) {
    const std::vector<uint8_t> rgba8 = render_cpu_rgba8(scene, plan, options, &st);
    const auto t0 = std::chrono::steady_clock::now();
    png::ImageData data = png::compress_rgba8(rgba8.data(), plan.frame.width, plan.frame.height);
    st.png_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return data;
  }
  cudaSetDevice(impl_->device);
  gpu::Context& ctx = *impl_->ctx;
  return render_cuda(ctx, scene, plan, options, st, [&](const PaintRecord& bg, gpu::GpuTimes* gt) {
    png::ImageData data = ctx.render_png(plan.integ, plan.frame, bg, options.gamma == Gamma::Linear, gt);
    if (gt) st.png_ms += gt->png_ms;
    return data;
  });
}

png::FilteredRows FrameRenderer::render_filtered(const EncodedScene& scene, const RenderPlan& plan,
                                                 const RenderOptions& options, RenderStats* stats,
                                                 std::vector<uint8_t> storage) {
  RenderStats local;
  local.stage_times = false;  // nobody reads them
  RenderStats& st = stats ? *stats : local;
  st.note = impl_->note;
  if (impl_->backend == Backend::Cpu) {
    const std::vector<uint8_t> rgba8 = render_cpu_rgba8(scene, plan, options, &st);
    return filter_rows_cpu(rgba8.data(), plan.frame.width, plan.frame.height, &st, std::move(storage));
  }
  cudaSetDevice(impl_->device);
  gpu::Context& ctx = *impl_->ctx;
  return render_cuda(ctx, scene, plan, options, st, [&](const PaintRecord& bg, gpu::GpuTimes* gt) {
    png::FilteredRows rows =
        ctx.render_filtered(plan.integ, plan.frame, bg, options.gamma == Gamma::Linear, gt, std::move(storage));
    if (gt) st.png_ms += gt->png_ms;
    return rows;
  });
}

std::vector<FrameRenderer::Output> FrameRenderer::render_forest(const std::vector<FrameScene>& scenes,
                                                               const RenderOptions& options, FrameOutputKind kind,
                                                               std::vector<std::vector<uint8_t>> storage) {
  if (impl_->backend == Backend::Cpu) {
    std::vector<Output> out = render_forest_cpu_8bit(scenes, options, kind);
    for (const FrameScene& s : scenes)
      if (s.stats) s.stats->note = impl_->note;
    return out;
  }
  cudaSetDevice(impl_->device);
  gpu::Context& ctx = *impl_->ctx;
  const auto t_all = std::chrono::steady_clock::now();
  int w = 0, h = 0;
  gpu::GpuTimes gt;
  const bool timed = !scenes.empty() && scenes[0].stats && scenes[0].stats->stage_times;
  {
    const EncodedScene forest = forest_of(scenes);
    forest_grid(forest, w, h);
    ctx.build(forest, w, h, resolve_stop_rule(options.tree, options.samples), timed ? &gt : nullptr);
  }
  const double share = 1.0 / std::max<size_t>(1, scenes.size());
  const double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_all).count();
  const gpu::Context::BuildCounts counts = ctx.build_counts();
  if (counts.capped) throw Error(kForestCapped);
  const PaintRecord bg = background_paint(options.background, options.gamma);
  const bool linear = options.gamma == Gamma::Linear;
  std::vector<Output> out(scenes.size());
  for (size_t k = 0; k < scenes.size(); k++) {
    const auto t0 = std::chrono::steady_clock::now();
    const RenderPlan& plan = *scenes[k].plan;
    const uint32_t root = static_cast<uint32_t>(k);
    gpu::GpuTimes rt;
    gpu::GpuTimes* rtp = timed ? &rt : nullptr;
    std::vector<uint8_t> mine = k < storage.size() ? std::move(storage[k]) : std::vector<uint8_t>{};
    if (kind == FrameOutputKind::Png) out[k].png = ctx.render_png(plan.integ, plan.frame, bg, linear, rtp, root);
    else if (kind == FrameOutputKind::Filtered)
      out[k].filtered = ctx.render_filtered(plan.integ, plan.frame, bg, linear, rtp, std::move(mine), root);
    else
      out[k].rgba8 = ctx.render_rgba8(plan.integ, plan.frame, bg, linear, rtp, std::move(mine), root);
    if (!scenes[k].stats) continue;
    RenderStats& st = *scenes[k].stats;
    st.backend = "cuda";
    st.note = impl_->note;
    st.stroke_ms += gt.stroke_ms * share;
    st.abstract_ms += gt.abstract_ms * share;
    st.subdivide_ms += gt.subdivide_ms * share;
    st.prune_ms += gt.prune_ms * share;
    st.schedule_ms += rt.schedule_ms;
    st.sample_ms += rt.sample_ms + rt.integrate_ms;
    st.samples += rt.samples;
    st.pixels += uint64_t(plan.frame.width) * uint64_t(plan.frame.height);
    st.png_ms += rt.png_ms;
    st.total_ms +=
        build_ms * share + std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    st.input_segments = scenes[k].scene->input_segment_count;
    st.tree_bytes = ctx.tree_bytes();
    st.abstract_segments = static_cast<size_t>(counts.abstract_segments * share);
    st.depth = counts.depth;
    st.leaves = static_cast<size_t>(counts.leaves * share);
    st.leaf_entries = static_cast<size_t>(counts.leaf_entries * share);
  }
  return out;
}

void FrameRenderer::warm_up(const RenderOptions& like, size_t pool_bytes) {
  if (impl_->backend != Backend::Cuda) return;
  cudaSetDevice(impl_->device);
  gpu::reserve_pool(pool_bytes);
  // A filled shape with lines and a curve, a clip and an even-odd fill:
  // abstraction, subdivision, pruning, the tree and the solid sampler; and
  // a dashed stroke of a curve: every kernel of the stroke stage (parts,
  // spans, fit items, the grouping by path).
  SceneBuilder b(64, 64);
  Path shape = Path::rectangle(4, 4, 60, 36);
  shape.move_to({8, 60});
  shape.quad_to({32, 20}, {56, 60});
  shape.close();
  b.push();
  b.clip(b.add_geometry(Path::rectangle(0, 0, 48, 64)), Affine{}, FillRule::NonZero);
  b.activate();
  Paint paint;
  paint.color = RGBA{0.2f, 0.4f, 0.8f, 1};
  b.fill(b.add_geometry(shape), Affine{}, FillRule::EvenOdd, paint);
  b.pop();
  Path curve;
  curve.move_to({6, 50});
  curve.cubic_to({20, 10}, {44, 90}, {58, 50});
  StrokeStyle stroke;
  stroke.width = 3;
  stroke.join = LineJoin::Round;
  stroke.dashes = {9, 3};
  b.stroke(b.add_geometry(curve), Affine{}, stroke, paint);
  const Scene scene = b.finish();
  RenderOptions o = like;
  o.width = o.height = 64;
  o.view = Affine{};
  o.backend = Backend::Cuda;
  const RenderPlan plan = plan_render(o);
  render_rgba8(encode_for(scene, plan, o.gamma), plan, o);
}

struct GpuStartup::State {
  std::atomic<bool> cancelled{false};
  std::mutex mutex;
  std::condition_variable cv;
  bool done = false;
  double ready_ms = 0;
  std::unique_ptr<FrameRenderer> renderer;
  std::string why;
  std::string phases;
};

// Device memory the start-up reserves for the first frame: the bench inputs
// at 1024 px with 4x4x32 take 20-90 MB of buffers (BENCHMARKS.md).
constexpr size_t kStartupPoolBytes = size_t(128) << 20;

GpuStartup::GpuStartup(Backend backend, const RenderOptions& like) : t0_(std::chrono::steady_clock::now()) {
  if (backend == Backend::Cpu) return;
  state_ = std::make_shared<State>();
  std::thread([state = state_, like, t0 = t0_] {
    std::unique_ptr<FrameRenderer> renderer;
    std::string why;
    char phases[160] = "";
    try {
      using Clock = std::chrono::steady_clock;
      auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
      };
      const auto t_begin = Clock::now();
      if (cuda_available(&why) && !state->cancelled) {
        const auto t_driver = Clock::now();
        renderer = std::make_unique<FrameRenderer>(Backend::Cuda);
        const auto t_context = Clock::now();
        if (!state->cancelled) renderer->warm_up(like, kStartupPoolBytes);
        const auto t_warm = Clock::now();
        std::snprintf(phases, sizeof phases, "driver %.1f ms, context %.1f ms, pool and warm-up frame %.1f ms",
                      ms(t_begin, t_driver), ms(t_driver, t_context), ms(t_context, t_warm));
      }
      if (state->cancelled && why.empty()) why = "CUDA start-up cancelled";
    } catch (const std::exception& e) {
      renderer.reset();
      why = std::string("CUDA start-up failed: ") + e.what();
    }
    std::lock_guard<std::mutex> lock(state->mutex);
    state->renderer = std::move(renderer);
    state->why = std::move(why);
    state->phases = phases;
    state->ready_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    state->done = true;
    state->cv.notify_all();
  }).detach();
}

GpuStartup::~GpuStartup() = default;

bool GpuStartup::started() const { return state_ != nullptr; }

bool GpuStartup::done() const {
  if (!state_) return true;
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->done;
}

double GpuStartup::elapsed_ms() const {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count();
}

void GpuStartup::cancel() {
  if (state_) state_->cancelled = true;
}

std::string GpuStartup::phases() const {
  if (!state_) return {};
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->phases;
}

double GpuStartup::ready_ms() const {
  if (!state_) return 0;
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->ready_ms;
}

std::unique_ptr<FrameRenderer> GpuStartup::take(std::string* why) {
  if (!state_) {
    if (why) *why = "the CPU backend was asked for";
    return nullptr;
  }
  std::unique_lock<std::mutex> lock(state_->mutex);
  state_->cv.wait(lock, [&] { return state_->done; });
  if (!state_->renderer && why) *why = state_->why;
  return std::move(state_->renderer);
}

}  // namespace mpvg
