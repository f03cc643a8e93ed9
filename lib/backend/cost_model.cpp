// --backend auto's cost model: which backend finishes a frame first,
// counting what is left of CUDA's start-up. Its constants are measurements
// (BENCHMARKS.md, "End to end (issue 12)"): per-thread CPU costs on the
// 2-core development machine and the GPU host's cores, GPU costs on an H100.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lib/backend/backend.h"

namespace mpvg {

namespace {

// CPU backend, fitted to the four bench inputs at 1024 px on the 2-core
// development machine and the GPU host's 16 cores (BENCHMARKS.md, "End to
// end (issue 12)"). The tree's build (abstract, subdivide, prune, schedule)
// barely gains from threads: per input segment and per unit area of the
// frame. Sampling and integration do, as threads^0.6 (2 threads: 1.5x one,
// 16: 5.3x): per sample, and per sample and target pixel of the filter
// (K^2: 16 for 4x4x32, which makes it ~6x 1x32). Wide filters add a fixed
// cost (the prefilter's passes) even to a tiny frame.
// Refitted in issue 50 (2-core machine, the four inputs at 1x32 and 4x4x32,
// least squares on relative error; BENCHMARKS.md "CPU executor, issue 50"):
// the per-sample costs fell with adaptive sampling (a flat unit area takes
// one sample: 6.4 evaluated a pixel on tiger at 4x4x32, not 32) and the
// integration's rework, 8 -> 2 ns a sample and 2.2 -> 0.73 ns a sample and
// target; the old constants predicted 2-5x the measured time. Within ~50 %
// of the measurements (the tree's cost is not linear in segments); the
// thread exponent is the GPU host's earlier fit, not measured again.
// Refitted again after the sample lanes, the one-pass subdivision and the
// 8-bit sink (the same eight frames, medians of three): 9000 -> 6900 ns an
// input segment, 2.0 -> 1.8 ns a sample, 0.73 -> 0.48 ns a sample and
// target; still within ~50 % (a segment's cost depends on its kind: tiger's
// 2,170 cubics take longer than reschart's 7,919 lines).
constexpr double kCpuFrameMs = 0.3;
constexpr double kCpuWideFilterMs = 2.5;
constexpr double kCpuSegmentNs = 6900;
constexpr double kCpuUnitAreaNs = 0.1;
constexpr double kCpuSampleNs = 1.8;
constexpr double kCpuSampleTargetNs = 0.48;
constexpr double kCpuThreadExponent = 0.6;
// CUDA backend on an H100, a warm context (the start-up's warm-up frame
// done): a frame's floor (launches, copies), per input segment, per sample,
// and the copy back of 8-bit pixels.
constexpr double kGpuFrameMs = 3.0;
constexpr double kGpuSegmentNs = 40;
constexpr double kGpuSampleNs = 0.05;
constexpr double kGpuPixelNs = 0.4;
// CUDA's start-up when nothing is known of it: driver and context, the
// memory pool, the warm-up frame (the GPU host: 254-268 ms).
constexpr double kGpuStartupMs = 260;
// The driver's teardown of a context when its process exits, even by
// _Exit: the external wall of svg2png minus its own wall and start on the
// GPU host, 120-140 ms.
constexpr double kGpuTeardownMs = 130;

}  // namespace

double expected_gpu_startup_ms() { return kGpuStartupMs; }
double expected_gpu_teardown_ms() { return kGpuTeardownMs; }

BackendChoice choose_backend(const CostInputs& in) {
  BackendChoice c;
  const double speedup = std::pow(std::max(1, in.cpu_threads), kCpuThreadExponent);
  const double samples = in.unit_areas * in.samples;
  const double targets = double(in.support) * in.support;
  c.cpu_ms = kCpuFrameMs + (in.support > 1 ? kCpuWideFilterMs : 0) +
             (in.input_segments * kCpuSegmentNs + in.unit_areas * kCpuUnitAreaNs) * 1e-6 +
             samples * (kCpuSampleNs + targets * kCpuSampleTargetNs) / speedup * 1e-6;
  char buf[256];
  if (!in.gpu_possible) {
    c.backend = Backend::Cpu;
    c.why = "no CUDA device";
    return c;
  }
  c.gpu_ms = std::max(0.0, in.gpu_wait_ms) + std::max(0.0, in.gpu_teardown_ms) + kGpuFrameMs +
             (in.input_segments * kGpuSegmentNs + samples * kGpuSampleNs + in.pixels * kGpuPixelNs) * 1e-6;
  c.backend = c.cpu_ms <= c.gpu_ms ? Backend::Cpu : Backend::Cuda;
  std::snprintf(buf, sizeof buf, "estimated %.1f ms on %d CPU threads, %.1f ms with CUDA (of which %.1f ms start-up left, %.1f ms "
                "teardown at exit)",
                c.cpu_ms, in.cpu_threads, c.gpu_ms, std::max(0.0, in.gpu_wait_ms), std::max(0.0, in.gpu_teardown_ms));
  c.why = buf;
  return c;
}

}  // namespace mpvg
