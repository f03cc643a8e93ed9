// Stage "stroke" on the GPU: one thread per segment measures it; a scan by
// subpath gives each segment's arc length from its subpath's start; one
// thread per element (each subpath's segments, then its vertices) counts
// its output, an exclusive scan places it, and the same element writes it.
#include <chrono>

#include "core/error.h"
#include "core/stroke.h"
#include "gpu/context.cuh"
#include "gpu/stroke.h"

namespace mpvg::gpu {

namespace {

using namespace stroking;

constexpr unsigned kBlock = 64;

__global__ void k_stroke_measure(StrokeInput in, double* length, uint32_t* key) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= in.nsegments) return;
  length[i] = stroke_measure(in, i);
  key[i] = in.segments[i].subpath;
}

// The length of each subpath, from its last segment's start and length.
__global__ void k_stroke_subpath_length(StrokeInput in, double* sub_length) {
  const uint32_t s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= in.nsubpaths) return;
  const StrokeSubpath& sp = in.subpaths[s];
  if (sp.segment_count == 0) {
    sub_length[s] = 0;
    return;
  }
  const uint32_t last = sp.first_segment + sp.segment_count - 1;
  sub_length[s] = in.seg_start[last] + in.seg_length[last];
}

// Element e: a segment or a vertex of the subpath whose range holds it.
struct ElementRef {
  bool vertex;
  uint32_t index;
  uint32_t stroke;
};
__device__ ElementRef element_of(const StrokeInput& in, const uint32_t* first_element, uint32_t e) {
  uint32_t lo = 0, hi = in.nsubpaths;
  while (hi - lo > 1) {
    const uint32_t mid = (lo + hi) / 2;
    if (first_element[mid] <= e) lo = mid; else hi = mid;
  }
  const StrokeSubpath& sp = in.subpaths[lo];
  const uint32_t k = e - first_element[lo];
  if (k < sp.segment_count) return {false, sp.first_segment + k, sp.stroke};
  return {true, sp.first_vertex + (k - sp.segment_count), sp.stroke};
}

__global__ void k_stroke_count(StrokeInput in, const uint32_t* first_element, uint32_t nelem, uint32_t* count) {
  const uint32_t e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e > nelem) return;
  if (e == nelem) {
    count[e] = 0;
    return;
  }
  const ElementRef r = element_of(in, first_element, e);
  CountSink sink;
  Emitter<CountSink> out(sink);
  if (r.vertex)
    stroke_vertex(in, r.index, out);
  else
    stroke_segment(in, r.index, out);
  count[e] = sink.n;
}

__global__ void k_stroke_write(StrokeInput in, const uint32_t* first_element, uint32_t nelem, const uint32_t* offset,
                               InputSegment* out_segments, uint32_t* mismatch) {
  const uint32_t e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e >= nelem) return;
  const ElementRef r = element_of(in, first_element, e);
  const StrokeRecord& rec = in.strokes[r.stroke];
  SegmentSink sink{out_segments + offset[e], offset[e + 1] - offset[e], rec.path, rec.xf, 0};
  Emitter<SegmentSink> out(sink);
  if (r.vertex)
    stroke_vertex(in, r.index, out);
  else
    stroke_segment(in, r.index, out);
  if (sink.n != offset[e + 1] - offset[e]) atomicOr(mismatch, 1u);
}

template <class T>
void upload(DeviceBuffer<T>& d, const std::vector<T>& h) {
  d.upload(h);
}

}  // namespace

std::vector<InputSegment> stroke_gpu(const StrokeBatch& b, StrokeGpuTimes* times) {
  StrokeGpuTimes t;
  const auto w0 = std::chrono::steady_clock::now();
  DeviceBuffer<StrokeRecord> strokes;
  DeviceBuffer<StrokeSubpath> subpaths;
  DeviceBuffer<StrokeSegment> segments;
  DeviceBuffer<double> dashes, seg_length, seg_start, sub_length;
  DeviceBuffer<uint32_t> keys, first_element, count, offset, mismatch;
  upload(strokes, b.strokes);
  upload(subpaths, b.subpaths);
  upload(segments, b.segments);
  upload(dashes, b.dashes.empty() ? std::vector<double>{0.0} : b.dashes);
  std::vector<uint32_t> first(b.subpaths.size());
  uint32_t nelem = 0;
  for (size_t s = 0; s < b.subpaths.size(); s++) {
    first[s] = nelem;
    nelem += b.subpaths[s].segment_count + subpath_vertices(b.subpaths[s]);
  }
  upload(first_element, first.empty() ? std::vector<uint32_t>{0} : first);
  MPVG_CUDA(cudaDeviceSynchronize());
  t.upload_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count();

  const uint32_t nseg = static_cast<uint32_t>(b.segments.size()), nsub = static_cast<uint32_t>(b.subpaths.size());
  seg_length.resize(nseg + 1);
  seg_start.resize(nseg + 1);
  sub_length.resize(nsub + 1);
  keys.resize(nseg + 1);
  StrokeInput in{strokes.data(), subpaths.data(), segments.data(), dashes.data(), seg_length.data(),
                 seg_start.data(), sub_length.data(), static_cast<uint32_t>(b.strokes.size()), nsub, nseg,
                 b.nvertices};
  Primitives prim;
  cudaEvent_t ev[4];
  for (cudaEvent_t& e : ev) MPVG_CUDA(cudaEventCreate(&e));
  MPVG_CUDA(cudaEventRecord(ev[0]));
  if (nseg) {
    k_stroke_measure<<<grid_for(nseg, kBlock), kBlock>>>(in, seg_length.data(), keys.data());
    MPVG_LAUNCHED();
    t.launches++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::ExclusiveSumByKey(nullptr, bytes, keys.data(), seg_length.data(), seg_start.data(),
                                                 static_cast<int>(nseg)));
    DeviceBuffer<uint8_t> temp;
    temp.resize(bytes);
    MPVG_CUDA(cub::DeviceScan::ExclusiveSumByKey(temp.data(), bytes, keys.data(), seg_length.data(),
                                                 seg_start.data(), static_cast<int>(nseg)));
    MPVG_LAUNCHED();
    t.launches++;
  }
  if (nsub) {
    k_stroke_subpath_length<<<grid_for(nsub, kBlock), kBlock>>>(in, sub_length.data());
    MPVG_LAUNCHED();
    t.launches++;
  }
  MPVG_CUDA(cudaEventRecord(ev[1]));
  count.resize(nelem + 1);
  offset.resize(nelem + 1);
  k_stroke_count<<<grid_for(nelem + 1, kBlock), kBlock>>>(in, first_element.data(), nelem, count.data());
  MPVG_LAUNCHED();
    t.launches++;
  prim.exclusive_sum(count.data(), offset.data(), nelem + 1);
  MPVG_LAUNCHED();
    t.launches++;
  uint32_t total = 0;
  MPVG_CUDA(cudaMemcpy(&total, offset.data() + nelem, sizeof total, cudaMemcpyDeviceToHost));
  MPVG_CUDA(cudaEventRecord(ev[2]));
  DeviceBuffer<InputSegment> out;
  out.resize(total + 1);
  mismatch.resize(1);
  MPVG_CUDA(cudaMemset(mismatch.data(), 0, sizeof(uint32_t)));
  if (nelem) {
    k_stroke_write<<<grid_for(nelem, kBlock), kBlock>>>(in, first_element.data(), nelem, offset.data(), out.data(),
                                                        mismatch.data());
    MPVG_LAUNCHED();
    t.launches++;
  }
  MPVG_CUDA(cudaEventRecord(ev[3]));
  MPVG_CUDA(cudaEventSynchronize(ev[3]));
  float ms[3];
  for (int k = 0; k < 3; k++) MPVG_CUDA(cudaEventElapsedTime(&ms[k], ev[k], ev[k + 1]));
  for (cudaEvent_t& e : ev) MPVG_CUDA(cudaEventDestroy(e));
  t.measure_ms = ms[0];
  t.count_ms = ms[1];
  t.write_ms = ms[2];
  uint32_t bad = 0;
  MPVG_CUDA(cudaMemcpy(&bad, mismatch.data(), sizeof bad, cudaMemcpyDeviceToHost));
  if (bad) throw Error("stroke: an element wrote a different count than it counted (GPU)");
  std::vector<InputSegment> host(total);
  if (total) MPVG_CUDA(cudaMemcpy(host.data(), out.data(), total * sizeof(InputSegment), cudaMemcpyDeviceToHost));
  t.segments = total;
  if (times) *times = t;
  return host;
}

}  // namespace mpvg::gpu
