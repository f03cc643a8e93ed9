// Stage "stroke" on the CPU: the per-item functions of stroker/stroke.h in
// loops, in the GPU's order: measuring (one task per segment), the scan of
// lengths per subpath, the elements (each subpath's segments, then its
// vertices), the parts of bodies, their spans, the fit items; each kind
// appends its segments in one pass. The output is grouped by path.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <iterator>

#include "core/parallel.h"
#include "cpu/cpu_stages.h"
#include "stroker/stroke_input.h"

namespace mpvg {

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

std::vector<InputSegment> stroke_cpu(const StrokeBatch& b, int threads, StrokeTimes* times, MemoryBudget* budget) {
  using namespace stroking;
  // Six parallel loops start their threads each: below a few thousand
  // elements (~1 ms on one thread) that costs more than it saves.
  constexpr uint32_t kParallelElements = 4096;
  if (b.nelements < kParallelElements) threads = 1;
  auto t0 = std::chrono::steady_clock::now();
  // What the stage holds is charged before it is made (each output list
  // once made: a chunk's worth past the budget at most), and all of it
  // given back on return.
  std::atomic<uint64_t> charged{0};
  struct GiveBack {
    MemoryBudget* budget;
    std::atomic<uint64_t>& bytes;
    ~GiveBack() {
      if (budget) budget->release(bytes.load());
    }
  } give_back{budget, charged};
  auto hold = [&](uint64_t bytes) {
    if (!budget) return;
    budget->charge(bytes, "the strokes' segments");
    charged += bytes;
  };
  const size_t nseg = b.segments.size(), nsub = b.subpaths.size();
  hold((2 * nseg + nsub) * sizeof(double));
  std::vector<double> seg_length(nseg), seg_start(nseg), sub_length(nsub);
  StrokeInput in{b.strokes.data(),        b.subpaths.data(),  b.segments.data(),
                 b.dashes.data(),         b.dash_ends.data(), seg_length.data(),  seg_start.data(),
                 sub_length.data(),       b.first_element.data(),
                 static_cast<uint32_t>(b.strokes.size()), static_cast<uint32_t>(nsub),
                 static_cast<uint32_t>(nseg), b.nelements};
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

  // Items of each kind in one pass: each chunk appends its segments to its
  // own list (the GPU counts first to place its writes; here lists grow),
  // and the lists are joined in order.
  struct VectorSink {
    std::vector<InputSegment>* out;
    uint32_t path;
    const double* xf;
    void segment(uint32_t type, Vec2 a, Vec2 b, Vec2 c, double w) {
      out->push_back(input_segment(type, a, b, c, w, path, xf));
    }
  };
  constexpr size_t kChunk = 32;
  auto chunked = [&](size_t n, auto item) {
    hold((n + kChunk - 1) / kChunk * sizeof(std::vector<InputSegment>));
    std::vector<std::vector<InputSegment>> lists((n + kChunk - 1) / kChunk);
    parallel_for(lists.size(), threads, [&](size_t c) {
      for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); i++) item(i, lists[c]);
      hold(lists[c].capacity() * sizeof(InputSegment));
    });
    return lists;
  };
  auto sink_for = [&](uint32_t stroke, std::vector<InputSegment>& list) {
    return VectorSink{&list, b.strokes[stroke].path, b.strokes[stroke].xf};
  };
  t0 = std::chrono::steady_clock::now();
  hold((b.nelements + kChunk - 1) / kChunk * sizeof(std::vector<StrokePart>));
  std::vector<std::vector<StrokePart>> part_lists((b.nelements + kChunk - 1) / kChunk);
  auto from_elements = chunked(b.nelements, [&](size_t i, std::vector<InputSegment>& list) {
    const ElementRef e = element_of(in, static_cast<uint32_t>(i));
    VectorSink sink = sink_for(e.stroke, list);
    Emitter<VectorSink> out(sink);
    if (e.vertex)
      stroke_vertex(in, e.index, out);
    else
      stroke_segment(in, e.index, out,
                     [&](double a, double z) { part_lists[i / kChunk].push_back({e.index, 0, a, z}); });
  });
  size_t nparts = 0;
  for (const auto& l : part_lists) nparts += l.size();
  // (The lists themselves, then their join, the breaks and span counts.)
  hold(nparts * (2 * sizeof(StrokePart) + sizeof(Breaks) + sizeof(int)));
  std::vector<StrokePart> parts;
  parts.reserve(nparts);
  for (const auto& l : part_lists) parts.insert(parts.end(), l.begin(), l.end());
  if (times) times->elements_ms += ms_since(t0);

  // Parts: analysis (breaks kept) and their own segments; then their spans.
  t0 = std::chrono::steady_clock::now();
  std::vector<Breaks> breaks(parts.size());
  std::vector<int> nspans(parts.size());
  auto from_parts = chunked(parts.size(), [&](size_t i, std::vector<InputSegment>& list) {
    const PartCurve pc = part_curve(in, parts[i]);
    nspans[i] = analyse_part(pc.c, pc.h, breaks[i]);
    VectorSink sink = sink_for(pc.stroke, list);
    emit_part(pc.c, pc.h, breaks[i], sink);
  });
  size_t nspan_total = 0;
  for (int k : nspans) nspan_total += size_t(std::max(k, 0));
  hold(nspan_total * (sizeof(SpanRef) + sizeof(Knots) + sizeof(uint32_t)));
  std::vector<SpanRef> spans;
  spans.reserve(nspan_total);
  for (size_t i = 0; i < parts.size(); i++)
    for (int k = 0; k < nspans[i]; k++) spans.push_back({static_cast<uint32_t>(i), static_cast<uint32_t>(k)});
  if (times) times->parts_ms += ms_since(t0);

  // Spans: knots; then the fit items.
  t0 = std::chrono::steady_clock::now();
  std::vector<Knots> knots(spans.size());
  std::vector<uint32_t> nitems(spans.size());
  parallel_for(spans.size(), threads, [&](size_t i) {
    const PartCurve pc = part_curve(in, parts[spans[i].part]);
    const Breaks& br = breaks[spans[i].part];
    span_knots(pc.c, pc.h, br, static_cast<int>(spans[i].index), knots[i]);
    nitems[i] = span_fit_items(knots[i]);
  });
  size_t nfits = 0;
  for (uint32_t k : nitems) nfits += k;
  hold(nfits * sizeof(FitRef));
  std::vector<FitRef> fits;
  fits.reserve(nfits);
  for (size_t i = 0; i < spans.size(); i++)
    for (uint32_t k = 0; k < nitems[i]; k++) fits.push_back(fit_ref(static_cast<uint32_t>(i), span_roles(knots[i].span.kind), k));
  auto from_fits = chunked(fits.size(), [&](size_t i, std::vector<InputSegment>& list) {
    const FitRef& f = fits[i];
    const SpanRef& sr = spans[f.span];
    const PartCurve pc = part_curve(in, parts[sr.part]);
    VectorSink sink = sink_for(pc.stroke, list);
    fit_item(pc.c, pc.h, pc.tol, knots[f.span], f.interval, f.role, sink);
  });
  if (times) times->fit_ms += ms_since(t0);

  // Elements' segments, parts', fit items', grouped by path (a counting
  // sort: each path's segments keep their order).
  std::vector<size_t> first;
  for (const auto* family : {&from_elements, &from_parts, &from_fits})
    for (const auto& l : *family)
      for (const InputSegment& s : l) {
        if (s.path + 1 >= first.size()) first.resize(s.path + 2, 0);
        first[s.path + 1]++;
      }
  for (size_t p = 1; p < first.size(); p++) first[p] += first[p - 1];
  const size_t total = first.empty() ? 0 : first.back();
  hold(total * sizeof(InputSegment));
  std::vector<InputSegment> out(total);
  for (const auto* family : {&from_elements, &from_parts, &from_fits})
    for (const auto& l : *family)
      for (const InputSegment& s : l) out[first[s.path]++] = s;
  return out;
}

std::vector<InputSegment> stroke_input_segments(const EncodedScene& scene, int threads, MemoryBudget* budget) {
  const std::vector<InputSegment> strokes = stroke_cpu(scene.strokes, threads, nullptr, budget);
  const BudgetCharge held(budget, strokes.size() * sizeof(InputSegment), "the strokes' segments");
  // Both lists are grouped by path, in increasing path order, and no path
  // is in both: a merge.
  charge(budget, (scene.segments.size() + strokes.size()) * sizeof(InputSegment), "the strokes' segments");
  std::vector<InputSegment> out;
  out.reserve(scene.segments.size() + strokes.size());
  std::merge(scene.segments.begin(), scene.segments.end(), strokes.begin(), strokes.end(), std::back_inserter(out),
             [](const InputSegment& a, const InputSegment& b) { return a.path < b.path; });
  return out;
}

}  // namespace mpvg
