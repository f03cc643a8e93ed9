// The stroke stage's device side (gpu/stroke.cu): buffers kept across
// frames by gpu::Context, and the grouping of input segments by path.
#pragma once
#include "stroker/stroke.h"
#include "stroker/stroke_input.h"
#include "gpu/primitives.cuh"
#include "gpu/stroke.h"

namespace mpvg::gpu {

class StrokeStage {
 public:
  // Expands `batch` on the device, appending its segments (in pixels) to
  // out[at, at + n), growing `out` and keeping out[0, at); returns n. The
  // segments are not grouped by path. Totals come back through `words`.
  size_t run(const StrokeBatch& batch, DeviceBuffer<InputSegment>& out, size_t at, Primitives& prim,
             HostWords& words, StrokeGpuTimes* times = nullptr);

 private:
  DeviceBuffer<stroking::StrokeRecord> strokes;
  DeviceBuffer<stroking::StrokeSubpath> subpaths;
  DeviceBuffer<stroking::StrokeSegment> segments;
  DeviceBuffer<double> dashes, dash_ends, seg_length, seg_start, sub_length;
  DeviceBuffer<uint32_t> keys, first_element, count, offset, flags;
  DeviceBuffer<uint32_t> pcount, poffset, scount, soffset;
  DeviceBuffer<stroking::StrokePart> parts;
  DeviceBuffer<stroking::Breaks> breaks;
  DeviceBuffer<stroking::SpanRef> spans;
  DeviceBuffer<stroking::Knots> knots;
  DeviceBuffer<stroking::FitRef> fits;
  DeviceBuffer<InputSegment> part_slots, fit_slots;  // a few segments per part, per fit item
  HostStaging staging;
  DeviceBuffer<uint8_t> temp;
};

// Sorts segs[0, n) by path, stably (each path's segments keep their
// order), and writes path_input: the first segment of each path (npaths + 1
// entries, the last n).
void group_by_path(DeviceBuffer<InputSegment>& segs, size_t n, size_t npaths, DeviceBuffer<uint32_t>& path_input,
                   Primitives& prim);

}  // namespace mpvg::gpu
