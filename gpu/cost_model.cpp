// --backend auto's cost model: which backend finishes a frame first,
// counting what is left of CUDA's start-up. Its constants are measurements
// (BENCHMARKS.md, "End to end (issue 12)"): per-thread CPU costs on the
// 2-core development machine and the GPU host's cores, GPU costs on an H100.
#include <algorithm>
#include <cstdio>

#include "gpu/backend.h"

namespace mpvg {

namespace {

// CPU backend, per thread: a fixed cost per frame, per input segment (the
// tree's build), per sample (sampling a unit area), per weighted sample
// (integration over the filter's K^2 pixels), in ns.
constexpr double kCpuFrameMs = 0.3;
constexpr double kCpuSegmentNs = 2500;
constexpr double kCpuSampleNs = 12;
constexpr double kCpuWeightNs = 1.5;
// CUDA backend: the launch floor of a frame (~1 000 launches), per input
// segment, per sample, and the copy back of 8-bit pixels, in ns.
constexpr double kGpuFrameMs = 3.0;
constexpr double kGpuSegmentNs = 30;
constexpr double kGpuSampleNs = 0.05;
constexpr double kGpuPixelNs = 0.4;
// CUDA's start-up when nothing is known of it: driver and context, module
// loading, the warm-up frame (the GPU host: ~250 ms).
constexpr double kGpuStartupMs = 250;

}  // namespace

double expected_gpu_startup_ms() { return kGpuStartupMs; }

BackendChoice choose_backend(const CostInputs& in) {
  BackendChoice c;
  const double threads = std::max(1, in.cpu_threads);
  const double samples = in.unit_areas * in.samples;
  c.cpu_ms = kCpuFrameMs + (in.input_segments * kCpuSegmentNs + samples * kCpuSampleNs +
                            samples * in.support * in.support * kCpuWeightNs) /
                               threads * 1e-6;
  char buf[256];
  if (!in.gpu_possible) {
    c.backend = Backend::Cpu;
    c.why = "no CUDA device";
    return c;
  }
  c.gpu_ms = std::max(0.0, in.gpu_wait_ms) + kGpuFrameMs +
             (in.input_segments * kGpuSegmentNs + samples * kGpuSampleNs + in.pixels * kGpuPixelNs) * 1e-6;
  c.backend = c.cpu_ms <= c.gpu_ms ? Backend::Cpu : Backend::Cuda;
  std::snprintf(buf, sizeof buf, "estimated %.1f ms on %d CPU threads, %.1f ms with CUDA (of which %.1f ms start-up left)",
                c.cpu_ms, in.cpu_threads, c.gpu_ms, std::max(0.0, in.gpu_wait_ms));
  c.why = buf;
  return c;
}

}  // namespace mpvg
