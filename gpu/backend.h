// Backend choice at run time (--backend auto|cuda|cpu). Built in every
// configuration: without nvcc, the CUDA side reports itself unavailable and
// auto renders on the CPU.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/renderer.h"

namespace mpvg {

// Is a CUDA device usable? If not, *why says why (one line).
bool cuda_available(std::string* why = nullptr);

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
  explicit FrameRenderer(Backend backend);  // throws mpvg::Error for Cuda without a device
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  Backend backend() const;  // Cpu or Cuda
  const std::string& note() const;  // why Auto chose the CPU, or empty
  // scene = encode_for(s, options): the image in the integration colour space.
  ImageF render(const EncodedScene& scene, const RenderOptions& options, RenderStats* stats = nullptr);
  // The same image as to_rgba8(render(...), options.gamma) gives, byte for
  // byte; with CUDA converted on the device (a quarter of the copy back).
  // plan = plan_render(options), made once per frame by the caller. With
  // CUDA the result reuses storage's memory where it is large enough
  // (batches hand back the buffers of written pages).
  std::vector<uint8_t> render_rgba8(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                                    RenderStats* stats = nullptr, std::vector<uint8_t> storage = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mpvg
