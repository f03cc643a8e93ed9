// Stage "stroke" on the CPU: the per-element functions of core/stroke.h in
// loops. Measuring is one task per segment; the scan of lengths runs per
// subpath; elements (each subpath's segments, then its vertices, so that
// the output comes grouped by stroke) append their segments in one pass.
#include <algorithm>
#include <chrono>

#include "core/parallel.h"
#include "core/stroke_input.h"

namespace mpvg {

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

std::vector<InputSegment> stroke_cpu(const StrokeBatch& b, int threads, StrokeTimes* times) {
  using namespace stroking;
  auto t0 = std::chrono::steady_clock::now();
  const size_t nseg = b.segments.size(), nsub = b.subpaths.size();
  std::vector<double> seg_length(nseg), seg_start(nseg), sub_length(nsub);
  StrokeInput in{b.strokes.data(),     b.subpaths.data(),  b.segments.data(),
                 b.dashes.data(),      seg_length.data(),  seg_start.data(),
                 sub_length.data(),    static_cast<uint32_t>(b.strokes.size()),
                 static_cast<uint32_t>(nsub), static_cast<uint32_t>(nseg), b.nvertices};
  parallel_for(nseg, threads, [&](size_t i) { seg_length[i] = stroke_measure(in, static_cast<uint32_t>(i)); });
  for (size_t s = 0; s < nsub; s++) {
    const StrokeSubpath& sp = b.subpaths[s];
    double acc = 0;
    for (uint32_t k = 0; k < sp.segment_count; k++) {
      seg_start[sp.first_segment + k] = acc;
      acc += seg_length[sp.first_segment + k];
    }
    sub_length[s] = acc;
  }
  if (times) times->measure_ms += ms_since(t0);

  // Elements in output order: per subpath, its segments, then its vertices.
  struct Element {
    bool vertex;
    uint32_t index;
  };
  std::vector<Element> elems;
  elems.reserve(nseg + b.nvertices);
  for (const StrokeSubpath& sp : b.subpaths) {
    for (uint32_t k = 0; k < sp.segment_count; k++) elems.push_back({false, sp.first_segment + k});
    for (uint32_t k = 0; k < subpath_vertices(sp); k++) elems.push_back({true, sp.first_vertex + k});
  }
  // One pass: each chunk of elements appends to its own list (the GPU
  // counts first to place its writes; here lists grow), then the lists are
  // joined in order.
  struct VectorSink {
    std::vector<InputSegment>* out;
    uint32_t path;
    const double* xf;
    void segment(uint32_t type, Vec2 a, Vec2 b, Vec2 c, double w) {
      out->push_back(input_segment(type, a, b, c, w, path, xf));
    }
  };
  t0 = std::chrono::steady_clock::now();
  constexpr size_t kChunk = 32;
  std::vector<std::vector<InputSegment>> parts((elems.size() + kChunk - 1) / kChunk);
  parallel_for(parts.size(), threads, [&](size_t c) {
    for (size_t i = c * kChunk; i < std::min(elems.size(), (c + 1) * kChunk); i++) {
      const Element& e = elems[i];
      const uint32_t stroke =
          e.vertex ? b.subpaths[vertex_subpath(in, e.index)].stroke : b.subpaths[b.segments[e.index].subpath].stroke;
      const StrokeRecord& rec = b.strokes[stroke];
      VectorSink sink{&parts[c], rec.path, rec.xf};
      Emitter<VectorSink> out(sink);
      if (e.vertex)
        stroke_vertex(in, e.index, out);
      else
        stroke_segment(in, e.index, out);
    }
  });
  size_t total = 0;
  for (const auto& p : parts) total += p.size();
  std::vector<InputSegment> out;
  out.reserve(total);
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  if (times) times->write_ms += ms_since(t0);
  return out;
}

}  // namespace mpvg
