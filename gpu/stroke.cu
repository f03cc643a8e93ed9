// Stage "stroke" on the GPU: one thread per segment measures it; a scan by
// subpath gives each segment's arc length from its subpath's start. Then,
// one thread per item, kind after kind: elements (each subpath's segments,
// then its vertices: caps, joins, dots, and the parts to build bodies
// for), parts (analysis and the ties of their contours), spans (knots),
// fit items (fitted boundary pieces). Each kind counts its output, an
// exclusive scan places it, and the same items write it. The segments are
// then grouped by path (a stable radix sort), as abstraction takes them.
// Totals come back a few at a time: four host round trips in all (five when
// a fit item makes more segments than its slots hold).
#include <algorithm>
#include <chrono>
#include <deque>

#include "core/error.h"
#include "stroker/stroke.h"
#include "gpu/gpu_backend.h"
#include "gpu/stroke.cuh"
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

__device__ SegmentSink sink_at(const StrokeInput& in, uint32_t stroke, InputSegment* out, uint32_t capacity) {
  const StrokeRecord& rec = in.strokes[stroke];
  return SegmentSink{out, capacity, rec.path, rec.xf, 0};
}

// Elements: their own segments (caps, joins, dots) and their parts.
__global__ void k_element_count(StrokeInput in, uint32_t* count, uint32_t* part_count) {
  const uint32_t nelem = in.nelements;
  const uint32_t e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e > nelem) return;
  if (e == nelem) {
    count[e] = part_count[e] = 0;
    return;
  }
  const ElementRef r = element_of(in, e);
  CountSink sink;
  Emitter<CountSink> out(sink);
  uint32_t parts = 0;
  if (r.vertex)
    stroke_vertex(in, r.index, out);
  else
    stroke_segment(in, r.index, out, [&](double, double) { parts++; });
  count[e] = sink.n;
  part_count[e] = parts;
}

__global__ void k_element_write(StrokeInput in, const uint32_t* offset, const uint32_t* part_offset,
                                InputSegment* segs, StrokePart* parts, uint32_t* mismatch) {
  const uint32_t nelem = in.nelements;
  const uint32_t e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e >= nelem) return;
  const ElementRef r = element_of(in, e);
  SegmentSink sink = sink_at(in, r.stroke, segs + offset[e], offset[e + 1] - offset[e]);
  Emitter<SegmentSink> out(sink);
  uint32_t np = 0;
  const uint32_t room = part_offset[e + 1] - part_offset[e];
  if (r.vertex)
    stroke_vertex(in, r.index, out);
  else
    stroke_segment(in, r.index, out, [&](double a, double z) {
      if (np < room) parts[part_offset[e] + np] = StrokePart{r.index, 0, a, z};
      np++;
    });
  if (sink.n != offset[e + 1] - offset[e] || np != room) atomicOr(mismatch, 1u);
}

// Items that write as they count: each keeps up to K segments in slots of
// its own (K = 12 for parts, 8 for fit items: in the bench inputs, parts
// make at most 11, fit items at most 6, and almost all 2 and 1) and counts
// them; after the scan they are copied into place, and only an item that
// made more is run again, straight into place. flags[1] and flags[2]
// count those parts and fit items.
constexpr uint32_t kPartSlots = 12, kFitSlots = 8;

__device__ SegmentSink slots_of(const StrokeInput& in, uint32_t stroke, InputSegment* slots, uint32_t item,
                                uint32_t k) {
  return sink_at(in, stroke, slots + size_t{item} * k, k);
}

// Copies item's n segments from its k slots to out; false when it made more
// than its slots hold.
__device__ bool place_from_slots(const InputSegment* slots, uint32_t item, uint32_t k, uint32_t n,
                                 InputSegment* out) {
  if (n > k) return false;
  for (uint32_t j = 0; j < n; j++) out[j] = slots[size_t{item} * k + j];
  return true;
}

// Parts: analysis (breaks kept), their own segments, their spans.
__global__ void k_part_slots(StrokeInput in, const StrokePart* parts, uint32_t nparts, Breaks* breaks,
                             InputSegment* slots, uint32_t* count, uint32_t* span_count, uint32_t* flags) {
  const uint32_t p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p > nparts) return;
  if (p == nparts) {
    count[p] = span_count[p] = 0;
    return;
  }
  const PartCurve pc = part_curve(in, parts[p]);
  Breaks br;
  const int n = analyse_part(pc.c, pc.h, br);
  breaks[p] = br;
  SegmentSink sink = slots_of(in, pc.stroke, slots, p, kPartSlots);
  emit_part(pc.c, pc.h, br, sink);
  count[p] = sink.n;
  span_count[p] = static_cast<uint32_t>(n);
  if (sink.n > kPartSlots) atomicAdd(&flags[1], 1u);
}

__global__ void k_part_place(StrokeInput in, const StrokePart* parts, uint32_t nparts, const Breaks* breaks,
                             const InputSegment* slots, const uint32_t* offset, const uint32_t* span_offset,
                             InputSegment* segs, SpanRef* spans, uint32_t* flags) {
  const uint32_t p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= nparts) return;
  for (uint32_t k = span_offset[p]; k < span_offset[p + 1]; k++) spans[k] = SpanRef{p, k - span_offset[p]};
  const uint32_t n = offset[p + 1] - offset[p];
  if (place_from_slots(slots, p, kPartSlots, n, segs + offset[p])) return;
  const PartCurve pc = part_curve(in, parts[p]);
  SegmentSink sink = sink_at(in, pc.stroke, segs + offset[p], n);
  emit_part(pc.c, pc.h, breaks[p], sink);
  if (sink.n != n) atomicOr(&flags[0], 1u);
}

// Spans: knots, and how many fit items.
__global__ void k_span_knots(StrokeInput in, const StrokePart* parts, const Breaks* breaks, const SpanRef* spans,
                             uint32_t nspans, Knots* knots, uint32_t* items) {
  const uint32_t s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s > nspans) return;
  if (s == nspans) {
    items[s] = 0;
    return;
  }
  const SpanRef sr = spans[s];
  const PartCurve pc = part_curve(in, parts[sr.part]);
  const Breaks& br = breaks[sr.part];
  Knots kn;
  span_knots(pc.c, pc.h, br, static_cast<int>(sr.index), kn);
  knots[s] = kn;
  items[s] = span_fit_items(kn);
}

__global__ void k_span_items(const Knots* knots, uint32_t nspans, const uint32_t* item_offset, FitRef* fits) {
  const uint32_t s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= nspans) return;
  const uint32_t n = item_offset[s + 1] - item_offset[s];
  const int roles = span_roles(knots[s].span.kind);
  for (uint32_t k = 0; k < n; k++) fits[item_offset[s] + k] = fit_ref(s, roles, k);
}

// Fit items: the fitted pieces of one boundary over one knot interval
// (written as counted, as parts are).
__global__ void k_fit_slots(StrokeInput in, const StrokePart* parts, const SpanRef* spans, const Knots* knots,
                            const FitRef* fits, uint32_t nfits, InputSegment* slots, uint32_t* count,
                            uint32_t* flags) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i > nfits) return;
  if (i == nfits) {
    count[i] = 0;
    return;
  }
  const FitRef f = fits[i];
  const PartCurve pc = part_curve(in, parts[spans[f.span].part]);
  SegmentSink sink = slots_of(in, pc.stroke, slots, i, kFitSlots);
  fit_item(pc.c, pc.h, pc.tol, knots[f.span], f.interval, f.role, sink);
  count[i] = sink.n;
  if (sink.n > kFitSlots) atomicAdd(&flags[2], 1u);
}

__global__ void k_fit_place(StrokeInput in, const StrokePart* parts, const SpanRef* spans, const Knots* knots,
                            const FitRef* fits, uint32_t nfits, const InputSegment* slots, const uint32_t* offset,
                            InputSegment* segs, uint32_t* flags) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= nfits) return;
  const uint32_t n = offset[i + 1] - offset[i];
  if (place_from_slots(slots, i, kFitSlots, n, segs + offset[i])) return;
  const FitRef f = fits[i];
  const PartCurve pc = part_curve(in, parts[spans[f.span].part]);
  SegmentSink sink = sink_at(in, pc.stroke, segs + offset[i], n);
  fit_item(pc.c, pc.h, pc.tol, knots[f.span], f.interval, f.role, sink);
  if (sink.n != n) atomicOr(&flags[0], 1u);
}

// Grouping by path: keys and a gather after a stable radix sort.
__global__ void k_path_keys(const InputSegment* segs, uint32_t n, uint32_t* keys, uint32_t* index) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  keys[i] = segs[i].path;
  index[i] = i;
}
// The first segment of each path in segments sorted by path (keys):
// the lower bound of p; n for p = npaths.
__global__ void k_path_first(const uint32_t* keys, uint32_t n, uint32_t npaths, uint32_t* first) {
  const uint32_t p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p > npaths) return;
  uint32_t lo = 0, hi = n;
  while (lo < hi) {
    const uint32_t mid = (lo + hi) / 2;
    if (keys[mid] < p) lo = mid + 1; else hi = mid;
  }
  first[p] = lo;
}

__global__ void k_gather(const InputSegment* segs, const uint32_t* index, uint32_t n, InputSegment* out) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) out[i] = segs[index[i]];
}

}  // namespace

size_t StrokeStage::run(const StrokeBatch& b, DeviceBuffer<InputSegment>& out, size_t at, Primitives& prim,
                        HostWords& words, StrokeGpuTimes* times) {
  StrokeGpuTimes t;
  const auto w0 = std::chrono::steady_clock::now();
  // The centrelines through page-locked staging: copies queued, not waited for.
  const std::vector<double> no_dashes{0.0};
  const std::vector<uint32_t> no_elements{0};
  const std::vector<double>& dash_values = b.dashes.empty() ? no_dashes : b.dashes;
  const std::vector<double>& dash_end_values = b.dash_ends.empty() ? no_dashes : b.dash_ends;
  const std::vector<uint32_t>& element_starts = b.first_element.empty() ? no_elements : b.first_element;
  staging.begin(HostStaging::room(b.strokes.size() * sizeof(StrokeRecord)) +
                HostStaging::room(b.subpaths.size() * sizeof(StrokeSubpath)) +
                HostStaging::room(b.segments.size() * sizeof(StrokeSegment)) +
                HostStaging::room(dash_values.size() * sizeof(double)) +
                HostStaging::room(dash_end_values.size() * sizeof(double)) +
                HostStaging::room(element_starts.size() * sizeof(uint32_t)));
  staging.put(strokes, b.strokes);
  staging.put(subpaths, b.subpaths);
  staging.put(segments, b.segments);
  staging.put(dashes, dash_values);
  staging.put(dash_ends, dash_end_values);
  staging.put(first_element, element_starts);
  if (times) MPVG_CUDA(cudaStreamSynchronize(cudaStreamPerThread));
  t.upload_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count();

  const uint32_t nseg = static_cast<uint32_t>(b.segments.size()), nsub = static_cast<uint32_t>(b.subpaths.size());
  const uint32_t nelem = b.nelements;
  seg_length.resize(nseg + 1);
  seg_start.resize(nseg + 1);
  sub_length.resize(nsub + 1);
  keys.resize(nseg + 1);
  const StrokeInput in{strokes.data(),    subpaths.data(),      segments.data(),
                       dashes.data(),     dash_ends.data(),     seg_length.data(),    seg_start.data(),
                       sub_length.data(), first_element.data(), static_cast<uint32_t>(b.strokes.size()),
                       nsub,              nseg,                 nelem};
  // GPU times only when asked for (tools): a frame records no events. The
  // phases, and each kernel and scan within them (named slots).
  StageTimer phases(times != nullptr), kernels(times != nullptr);
  std::deque<std::pair<const char*, double>> slots;
  auto timed = [&](const char* name, auto f) {
    slots.push_back({name, 0.0});
    kernels.start(&slots.back().second);
    f();
    kernels.stop();
  };
  auto launch = [&](const char* name, auto kernel, uint32_t n, auto... args) {
    if (!n) return;
    timed(name, [&] { kernel<<<grid_for(n, kBlock), kBlock>>>(args...); });
    MPVG_LAUNCHED();
    t.launches++;
  };
  auto scan = [&](DeviceBuffer<uint32_t>& c, DeviceBuffer<uint32_t>& o, uint32_t n) {
    o.resize(n + 1);
    timed("scan", [&] { prim.exclusive_sum(c.data(), o.data(), n + 1); });
    t.launches++;
  };
  // Totals and flags, a few at a time in one round trip.
  auto read = [&](std::initializer_list<std::pair<const uint32_t*, uint32_t*>> list) {
    words.read(list);
    t.round_trips++;
  };

  phases.start(&t.measure_ms);
  launch("measure", k_stroke_measure, nseg, in, seg_length.data(), keys.data());
  if (nseg) {
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::ExclusiveSumByKey(nullptr, bytes, keys.data(), seg_length.data(), seg_start.data(),
                                                 static_cast<int>(nseg)));
    temp.resize(bytes);
    timed("scan by subpath", [&] {
      MPVG_CUDA(cub::DeviceScan::ExclusiveSumByKey(temp.data(), bytes, keys.data(), seg_length.data(),
                                                   seg_start.data(), static_cast<int>(nseg)));
    });
    t.launches++;
  }
  launch("subpath_length", k_stroke_subpath_length, nsub, in, sub_length.data());
  phases.stop();

  // Elements, then parts, spans and fit items; each kind counts, scans and
  // writes (parts and fit items write as they count, into slots). Output:
  // the elements' segments, the parts', the fit items'. Flags: 0 an item
  // wrote a different count than it counted, 1 and 2 the parts and the fit
  // items that overflowed their slots.
  phases.start(&t.count_ms);
  flags.resize(3);
  MPVG_CUDA(cudaMemsetAsync(flags.data(), 0, 3 * sizeof(uint32_t)));
  count.resize(nelem + 1);
  pcount.resize(nelem + 1);
  launch("element_count", k_element_count, nelem + 1, in, count.data(), pcount.data());
  scan(count, offset, nelem);
  scan(pcount, poffset, nelem);
  uint32_t a_total = 0, nparts = 0;
  read({{offset.data() + nelem, &a_total}, {poffset.data() + nelem, &nparts}});
  // Room for the elements' segments now; the others' are added as counted.
  out.grow_keep(at + a_total + 1);
  parts.resize(nparts + 1);
  launch("element_write", k_element_write, nelem, in, offset.data(), poffset.data(), out.data() + at, parts.data(),
         flags.data());

  breaks.resize(nparts + 1);
  count.resize(nparts + 1);
  scount.resize(nparts + 1);
  part_slots.resize(size_t{nparts} * kPartSlots + 1);
  launch("part_slots", k_part_slots, nparts + 1, in, parts.data(), nparts, breaks.data(), part_slots.data(),
         count.data(), scount.data(), flags.data());
  scan(count, offset, nparts);
  scan(scount, soffset, nparts);
  uint32_t b_total = 0, nspans = 0;
  read({{offset.data() + nparts, &b_total}, {soffset.data() + nparts, &nspans}});
  out.grow_keep(at + a_total + b_total + 1);
  spans.resize(nspans + 1);
  launch("part_place", k_part_place, nparts, in, parts.data(), nparts, breaks.data(), part_slots.data(),
         offset.data(), soffset.data(), out.data() + at + a_total, spans.data(), flags.data());

  knots.resize(nspans + 1);
  count.resize(nspans + 1);
  launch("span_knots", k_span_knots, nspans + 1, in, parts.data(), breaks.data(), spans.data(), nspans, knots.data(),
         count.data());
  scan(count, offset, nspans);
  uint32_t nfits = 0;
  read({{offset.data() + nspans, &nfits}});
  fits.resize(nfits + 1);
  launch("span_items", k_span_items, nspans, knots.data(), nspans, offset.data(), fits.data());
  count.resize(nfits + 1);
  fit_slots.resize(size_t{nfits} * kFitSlots + 1);
  launch("fit_slots", k_fit_slots, nfits + 1, in, parts.data(), spans.data(), knots.data(), fits.data(), nfits,
         fit_slots.data(), count.data(), flags.data());
  scan(count, offset, nfits);
  uint32_t c_total = 0, mismatch = 0, part_overflow = 0, fit_overflow = 0;
  read({{offset.data() + nfits, &c_total},
        {flags.data(), &mismatch},
        {flags.data() + 1, &part_overflow},
        {flags.data() + 2, &fit_overflow}});
  t.part_refits = part_overflow;
  t.fit_refits = fit_overflow;
  phases.stop();

  phases.start(&t.write_ms);
  const uint32_t total = a_total + b_total + c_total;
  out.grow_keep(at + total + 1);
  launch("fit_place", k_fit_place, nfits, in, parts.data(), spans.data(), knots.data(), fits.data(), nfits,
         fit_slots.data(), offset.data(), out.data() + at + a_total + b_total, flags.data());
  // Only a fit item run again can disagree now.
  if (fit_overflow && !mismatch) read({{flags.data(), &mismatch}});
  phases.stop();

  phases.collect();
  kernels.collect();
  t.kernels.assign(slots.begin(), slots.end());
  if (mismatch) throw Error("stroke: an item wrote a different count than it counted (GPU)");
  t.segments = total;
  if (times) *times = t;
  return total;
}

void group_by_path(DeviceBuffer<InputSegment>& segs, size_t n, size_t npaths, DeviceBuffer<uint32_t>& path_input,
                   Primitives& prim) {
  DeviceBuffer<uint32_t> keys_in, keys_out, idx_in, idx_out;  // from the retaining pool
  DeviceBuffer<InputSegment> grouped;
  keys_in.resize(n + 1);
  keys_out.resize(n + 1);
  idx_in.resize(n + 1);
  idx_out.resize(n + 1);
  grouped.resize(n + 1);
  if (n) {
    k_path_keys<<<grid_for(n, kBlock), kBlock>>>(segs.data(), static_cast<uint32_t>(n), keys_in.data(), idx_in.data());
    MPVG_LAUNCHED();
    // Paths are below npaths: only their bits are sorted on.
    prim.sort_pairs(keys_in.data(), keys_out.data(), idx_in.data(), idx_out.data(), n,
                    key_bits(npaths > 0 ? npaths - 1 : 0));
    k_gather<<<grid_for(n, kBlock), kBlock>>>(segs.data(), idx_out.data(), static_cast<uint32_t>(n), grouped.data());
    MPVG_LAUNCHED();
    segs.swap(grouped);
  }
  path_input.resize(npaths + 1);
  k_path_first<<<grid_for(npaths + 1, kBlock), kBlock>>>(keys_out.data(), static_cast<uint32_t>(n),
                                                         static_cast<uint32_t>(npaths), path_input.data());
  MPVG_LAUNCHED();
}

std::vector<InputSegment> stroke_gpu(const StrokeBatch& b, StrokeGpuTimes* times, int repeats) {
  use_retaining_pool();
  StrokeStage stage;
  Primitives prim;
  HostWords words;
  if (repeats > 1) words.pin();
  DeviceBuffer<InputSegment> out;
  size_t n = 0;
  for (int r = 0; r < std::max(1, repeats); r++) {
    StrokeGpuTimes t;
    n = stage.run(b, out, 0, prim, words, times ? &t : nullptr);
    if (times && (r == 0 || t.device_ms() < times->device_ms())) *times = t;
  }
  uint32_t npaths = 0;
  for (const StrokeRecord& r : b.strokes) npaths = std::max(npaths, r.path + 1);
  DeviceBuffer<uint32_t> first;
  group_by_path(out, n, npaths, first, prim);
  return out.download(n);
}

}  // namespace mpvg::gpu
