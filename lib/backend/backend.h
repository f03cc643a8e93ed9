// Backend choice at run time (--backend auto|cuda|cpu). Built in every
// configuration: without nvcc, the CUDA side reports itself unavailable and
// auto renders on the CPU.
#pragma once
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "core/output/png_encode.h"
#include "frame/frame.h"
#include "cpu/cpu_frame.h"

namespace mpvg {

// Is a CUDA device usable? If not, *why says why (one line).
bool cuda_available(std::string* why = nullptr);
// How many CUDA devices are visible (0 without CUDA).
int cuda_device_count();

// Renders with options.backend: Cpu, Cuda (throws mpvg::Error when no device
// can be used), or Auto (CUDA when available, else the CPU, with a one-line
// note in stats->note).
ImageF render(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

// Renders frame after frame with one backend, keeping its state between
// them (the CUDA device buffers, which grow to the largest frame), as
// batches do. Auto is resolved once, at construction. Not thread-safe: one
// per rendering thread; scenes are encoded elsewhere (encode_for, any
// thread).
class FrameRenderer {
 public:
  // device: which CUDA device (0-based) its frames render on; each call
  // makes it current on the calling thread. Throws mpvg::Error for Cuda
  // without a device or with a device number out of range.
  explicit FrameRenderer(Backend backend, int device = 0);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  Backend backend() const;  // Cpu or Cuda
  int device() const;
  const std::string& note() const;  // why Auto chose the CPU, or empty
  // encode_for(scene, plan, options.gamma) with the scene's filter effects
  // rendered as layers by this renderer's executor (with CUDA: sources
  // rendered and graphs run on its device), warnings in stats.
  EncodedScene encode(const Scene& scene, const RenderPlan& plan, const RenderOptions& options,
                      RenderStats* stats = nullptr);
  // scene = encode_for(s, options): the image in the integration colour space.
  ImageF render(const EncodedScene& scene, const RenderOptions& options, RenderStats* stats = nullptr);
  // The same image as to_rgba8(render(...), options.gamma) gives, byte for
  // byte; with CUDA converted on the device (a quarter of the copy back).
  // plan = plan_render(options), made once per frame by the caller. With
  // CUDA the result reuses storage's memory where it is large enough
  // (batches hand back the buffers of written pages).
  std::vector<uint8_t> render_rgba8(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                                    RenderStats* stats = nullptr, std::vector<uint8_t> storage = {});

  // As render_rgba8(), the bytes left on the device (CUDA backend only;
  // mpvg::Error on the CPU) in memory of their own, freed with the last
  // copy of `data`; the render and the copy into it are finished.
  struct DeviceImage {
    std::shared_ptr<uint8_t> data;  // width x height RGBA rows, 4 bytes a pixel
    int width = 0, height = 0;
    int device = 0;  // the CUDA device it is on
  };
  DeviceImage render_rgba8_device(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                                  RenderStats* stats = nullptr);
  // A device image's bytes copied to the host (its consumers' check).
  static std::vector<uint8_t> download(const DeviceImage& image);
  // Device memory of `bytes` on `device` (cudaMalloc, freed with the last
  // copy), and a device image's bytes copied into device memory at `to`
  // (finished on return): a batch of images in one allocation.
  static std::shared_ptr<uint8_t> device_alloc(size_t bytes, int device);
  static void copy_on_device(const DeviceImage& image, uint8_t* to);

  // As render_rgba8(), the image filtered and deflated for a PNG by
  // core/output/png_encode.h's stages (compression level 1): with CUDA on the
  // device, so that only the compressed data is copied back; on the CPU by
  // their reference executor. The same bytes either way.
  png::ImageData render_png(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                            RenderStats* stats = nullptr);
  // As render_png(), the first half only: the image's PNG rows filtered
  // (core/output/png_filter.h), with CUDA on the device, so that only the
  // rows are copied back (a quarter fewer bytes than the RGBA codes of an
  // opaque image) and the CPU is left with deflate (png::encode_filtered:
  // the bytes png::encode_rgba8 gives). Reuses storage's memory as
  // render_rgba8 does.
  png::FilteredRows render_filtered(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                                    RenderStats* stats = nullptr, std::vector<uint8_t> storage = {});

  // Several scenes as one frame (a forest, frame/forest.h): one tree build
  // for all of them, then each rendered over its own grid, to the same
  // bytes render_rgba8 (render_filtered, render_png: as `kind` says)
  // gives it alone. options: the scenes' shared options
  // (same_frame_options); each scene's size and view are in its plan. As
  // render_rgba8, the 8-bit images (filtered rows) reuse the memory of
  // `storage`'s buffers, one per scene, where given.
  using Output = FrameOutput;
  std::vector<Output> render_forest(const std::vector<FrameScene>& scenes, const RenderOptions& options,
                                    FrameOutputKind kind,
                                    std::vector<std::vector<uint8_t>> storage = {});
  // Readies the first real frame: reserves device memory in the pool the
  // buffers come from (`pool_bytes`), and renders a small built-in scene
  // with `like`'s filter and samples so that the kernels a frame needs are
  // loaded and the scratch of the scans exists. Nothing on the CPU.
  void warm_up(const RenderOptions& like, size_t pool_bytes);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// CUDA's start-up (driver, context, kernel modules, a pool of device memory,
// a warm-up frame), begun on a thread of its own at program start, so that
// it overlaps reading, parsing and stroking (~250 ms on the GPU host, most of
// it the driver's). The thread is detached: a process that ends while it
// still runs must end with std::_Exit (after flushing its output), not
// exit(), whose static destructors would race with it.
class GpuStartup {
 public:
  // Starts unless `backend` is Cpu. `like` gives the warm-up frame's filter
  // and samples.
  GpuStartup(Backend backend, const RenderOptions& like);
  ~GpuStartup();
  GpuStartup(const GpuStartup&) = delete;
  GpuStartup& operator=(const GpuStartup&) = delete;

  bool started() const;  // false for Cpu
  bool done() const;     // finished, with a renderer or without
  double elapsed_ms() const;  // since construction
  double ready_ms() const;    // when it finished, since construction (after done())
  std::string phases() const; // after done(): "driver X ms, context Y ms, pool and warm-up frame Z ms"
  // Waits for it. The CUDA renderer, or nullptr with *why when there is no
  // usable device (or the start-up failed).
  std::unique_ptr<FrameRenderer> take(std::string* why);
  // Not needed after all (the CPU renders): the start-up stops before its
  // next phase, so that a context that was never made costs no teardown
  // when the process exits (~130 ms on the GPU host).
  void cancel();

 private:
  struct State;
  std::shared_ptr<State> state_;
  std::chrono::steady_clock::time_point t0_;
};

// --backend auto's cost model (lib/backend/cost_model.cpp; its constants are
// measurements, BENCHMARKS.md "End to end"): the CPU when it would finish
// before the GPU, counting what is left of CUDA's start-up.
struct CostInputs {
  size_t input_segments = 0;  // encode_for's count
  double unit_areas = 0;      // of the frame: ua_w * ua_h
  int samples = 32;           // per unit area
  int support = 1;            // filter support K: K^2 pixels take each sample
  size_t pixels = 0;          // of the output
  int cpu_threads = 1;        // the CPU backend's
  bool gpu_possible = false;  // a start-up is running or has given a device
  double gpu_wait_ms = 0;     // expected time until the device is ready
  // Teardown the process pays at exit for a context it would make only by
  // choosing CUDA (expected_gpu_teardown_ms() for a one-shot process whose
  // start-up has not made one yet; 0 otherwise).
  double gpu_teardown_ms = 0;
};
struct BackendChoice {
  Backend backend = Backend::Cpu;
  double cpu_ms = 0, gpu_ms = 0;  // the model's estimates
  std::string why;                // one line, for --stats
};
BackendChoice choose_backend(const CostInputs& in);
// Expected duration of CUDA's start-up when nothing is known of it yet, ms.
double expected_gpu_startup_ms();
// Expected time the driver takes to destroy a process's context at exit, ms.
double expected_gpu_teardown_ms();

}  // namespace mpvg
