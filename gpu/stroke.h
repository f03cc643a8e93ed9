// Stage "stroke" on the GPU (stroker/stroke.h, one thread per element): the
// centreline goes up, the fill geometry is built on the device. Plain C++
// interface for tools and tests; the frame's own use of the stage goes
// through gpu::Context.
#pragma once
#include <cstddef>
#include <utility>
#include <vector>

#include "core/geometry/abstraction.h"
#include "stroker/stroke_input.h"

namespace mpvg::gpu {

struct StrokeGpuTimes {
  double upload_ms = 0;   // host to device (wall clock)
  double measure_ms = 0;  // lengths and their scan (GPU time, events)
  double count_ms = 0;    // counting pass and its scan
  double write_ms = 0;    // writing pass
  double device_ms() const { return measure_ms + count_ms + write_ms; }
  size_t segments = 0;    // output segments
  size_t launches = 0;    // kernels and CUB calls
  size_t round_trips = 0; // device-to-host reads that wait for the GPU
  // Parts and fit items run again (more segments than their slots hold).
  size_t part_refits = 0, fit_refits = 0;
  // GPU time of each kernel and scan, in order (events around each).
  std::vector<std::pair<const char*, double>> kernels;
};

// Expands a batch on the current device and copies the segments back (for
// tests and tools: in a frame they stay on the device). With repeats > 1
// the stage runs that many times on the same buffers, as frame after frame
// does, and *times tells of the fastest run.
std::vector<InputSegment> stroke_gpu(const StrokeBatch& batch, StrokeGpuTimes* times = nullptr, int repeats = 1);

}  // namespace mpvg::gpu
