// Stages "schedule", "sample" and "integrate" on the GPU (§5.3, non-warped
// scheduler). Cells are aligned to pixels, so a leaf's unit areas are the
// pixels it covers: the schedule is, per leaf, its number of batches of U
// unit areas, and a block takes one batch. The block streams the leaf's
// entries through shared memory in chunks of I while its S threads advance
// one sample each through the flat-clipping machine; the samples of a unit
// area are then summed on chip, in the same order as on the CPU, and the
// pixel is written once (no atomics: deterministic).
//
// Leaves without geometry have one colour everywhere: it is evaluated once
// per leaf and written to their pixels by a separate fill.
//
// Wider filters (integration.h): after a group of unit areas has been
// sampled, one thread per (unit area, covered pixel) computes the weighted
// sum and adds it to the pixel's fixed-point accumulators with 64-bit
// integer atomics (order-independent: deterministic). The accumulators are
// then normalised, prefiltered line by line for the cardinal B-spline (one
// thread per row, then per column, running the CPU's recursion), clamped and
// cropped.
#include <algorithm>

#include "core/sampling.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 256;

struct PixelRect {
  uint32_t x0, y0, w, h;
};

__device__ __forceinline__ PixelRect leaf_rect(const Cell& c, uint32_t root_size, int width, int height) {
  const uint32_t s = root_size >> c.level;
  const uint32_t x0 = c.ix * s, y0 = c.iy * s;
  const uint32_t x1 = min(x0 + s, static_cast<uint32_t>(width)), y1 = min(y0 + s, static_cast<uint32_t>(height));
  return PixelRect{x0, y0, x1 > x0 ? x1 - x0 : 0, y1 > y0 ? y1 - y0 : 0};
}

__device__ __forceinline__ float4 composite(float r, float g, float b, float a, const PaintRecord& bg) {
  const float under = 1.0f - a;
  return make_float4(r + under * bg.r, g + under * bg.g, b + under * bg.b, a + under * bg.a);
}

// Schedule: batches per leaf; uniform leaves get their colour instead.
__global__ void k_leaf_info(const Cell* leaves, size_t nleaves, const Entry* entries, SampleInputs in,
                            uint32_t root_size, int width, int height, uint32_t batch, uint32_t* batches,
                            float4* color) {
  const size_t l = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (l > nleaves) return;
  if (l == nleaves) {
    batches[l] = 0;
    return;
  }
  const Cell c = leaves[l];
  const PixelRect r = leaf_rect(c, root_size, width, height);
  const uint32_t npix = r.w * r.h;
  bool uniform = true;
  for (uint32_t i = c.begin; i < c.end && uniform; i++) uniform = !entry_is_geometry(entries[i]);
  if (uniform) {
    const Rgba4 col = sample_cell(in, c.begin, c.end, float(r.x0), float(r.y0));
    color[l] = make_float4(col.r, col.g, col.b, col.a);
    batches[l] = 0;
  } else {
    color[l] = make_float4(0.0f, 0.0f, 0.0f, -1.0f);  // a = -1: not uniform
    batches[l] = (npix + batch - 1) / batch;
  }
}

// Where a block's weighted sums go: directly to the pixel (box filter), or
// into the accumulators of the K x K pixels a unit area reaches.
struct Accumulate {
  unsigned long long* acc;  // null: direct
  const float* weights;     // [class][K*K][m]
  int support, class_mod, acc_w, acc_h;
};

__global__ void k_sample(const Cell* leaves, uint32_t nleaves, const uint32_t* batch_start, SampleInputs in,
                         const SampleOffset* pattern, int n, int chunk, int batch, uint32_t root_size, int width,
                         int height, PaintRecord bg, float4* image, Accumulate a) {
  extern __shared__ __align__(16) unsigned char smem[];
  AbstractSegment* ss = reinterpret_cast<AbstractSegment*>(smem);
  Entry* se = reinterpret_cast<Entry*>(ss + chunk);
  float4* red = reinterpret_cast<float4*>(se + chunk + (chunk & 1));

  // The leaf of this batch: the last leaf whose batches start at or before it.
  const uint32_t b = blockIdx.x;
  uint32_t lo = 0, hi = nleaves;
  while (hi - lo > 1) {
    const uint32_t mid = (lo + hi) / 2;
    if (batch_start[mid] <= b) lo = mid; else hi = mid;
  }
  const Cell c = leaves[lo];
  const PixelRect r = leaf_rect(c, root_size, width, height);
  const uint32_t npix = r.w * r.h;
  const uint32_t first = (b - batch_start[lo]) * static_cast<uint32_t>(batch);
  const uint32_t last = min(first + static_cast<uint32_t>(batch), npix);

  const int tid = threadIdx.x;
  const int k = tid % n;             // sample of its unit area
  const int group = blockDim.x / n;  // unit areas in flight
  const int g = tid / n;
  const float w = box_weight(n);
  const int K = a.support;
  for (uint32_t p0 = first; p0 < last; p0 += group) {
    const uint32_t pix = p0 + g;
    const bool active = g < group && pix < last;
    const uint32_t x = r.x0 + (active ? pix % r.w : 0), y = r.y0 + (active ? pix / r.w : 0);
    const SampleOffset o = pattern[unit_area_class(x, y, a.class_mod) * n + k];  // the class's pattern
    const float sx = float(x) + o.x, sy = float(y) + o.y;
    SampleState st = sample_start();
    st.done = !active;
    for (uint32_t base = c.begin; base < c.end; base += chunk) {
      const uint32_t cnt = min(static_cast<uint32_t>(chunk), c.end - base);
      __syncthreads();  // the previous chunk has been read by everyone
      for (uint32_t t = tid; t < cnt; t += blockDim.x) {
        const Entry e = in.entries[base + t];
        se[t] = e;
        if (entry_kind(e) == ENTRY_SEGMENT) ss[t] = in.segments[e.data];
      }
      __syncthreads();
      for (uint32_t t = 0; t < cnt && !st.done; t++) sample_step(st, in, se[t], &ss[t], sx, sy);
      if (__syncthreads_and(st.done)) break;
    }
    if (active) sample_finish_path(st, in, sx, sy);
    red[tid] = make_float4(st.color.r, st.color.g, st.color.b, st.color.a);
    __syncthreads();
    if (!a.acc) {
      if (active && k == 0) {
        // Integration: the unit area's samples, summed in the CPU's order.
        float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int q = 0; q < n; q++) {
          const float4 v = red[g * n + q];
          acc[0] += v.x;
          acc[1] += v.y;
          acc[2] += v.z;
          acc[3] += v.w;
        }
        image[size_t(y) * width + x] = composite(acc[0] * w, acc[1] * w, acc[2] * w, acc[3] * w, bg);
      }
    } else {
      // One thread per (unit area of the group, pixel it reaches).
      const int targets = K * K;
      for (int t = tid; t < group * targets; t += blockDim.x) {
        const int gg = t / targets, e = t % targets;
        const uint32_t upix = p0 + gg;
        if (upix >= last) continue;
        const uint32_t ux = r.x0 + upix % r.w, uy = r.y0 + upix / r.w;
        const int ax = int(ux) - e % K, ay = int(uy) - e / K;
        if (ax < 0 || ay < 0 || ax >= a.acc_w || ay >= a.acc_h) continue;
        float s4[4];
        integrate_unit_area(a.weights + (size_t(unit_area_class(ux, uy, a.class_mod)) * targets + e) * n, 0.0f, n, false,
                            nullptr, reinterpret_cast<const float*>(&red[gg * n]), s4);
        unsigned long long* dst = a.acc + (size_t(ay) * a.acc_w + ax) * 4;
        for (int ch = 0; ch < 4; ch++) atomicAdd(dst + ch, static_cast<unsigned long long>(to_fixed(s4[ch])));
      }
    }
    __syncthreads();  // red[] is rewritten by the next group
  }
}

__global__ void k_fill_uniform(const Node* nodes, uint32_t root_size, int width, int height, const float4* color,
                               PaintRecord bg, float4* image) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= size_t(width) * height) return;
  const uint32_t x = static_cast<uint32_t>(i % width), y = static_cast<uint32_t>(i / width);
  const float4 c = color[tree_find_leaf(nodes, root_size, x, y)];
  if (c.w >= 0.0f) image[i] = composite(c.x, c.y, c.z, c.w, bg);
}

// Unit areas of uniform leaves send flat colour times the weights' sums.
__global__ void k_accumulate_uniform(const Node* nodes, uint32_t root_size, int ua_w, int ua_h, const float4* color,
                                     const float* weight_sums, Accumulate a) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= size_t(ua_w) * ua_h) return;
  const uint32_t ux = static_cast<uint32_t>(i % ua_w), uy = static_cast<uint32_t>(i / ua_w);
  const float4 c = color[tree_find_leaf(nodes, root_size, ux, uy)];
  if (c.w < 0.0f) return;
  const float flat[4] = {c.x, c.y, c.z, c.w};
  const int K = a.support, cls = unit_area_class(ux, uy, a.class_mod);
  for (int e = 0; e < K * K; e++) {
    const int ax = int(ux) - e % K, ay = int(uy) - e / K;
    if (ax < 0 || ay < 0 || ax >= a.acc_w || ay >= a.acc_h) continue;
    float s4[4];
    integrate_unit_area(nullptr, weight_sums[cls * K * K + e], 0, true, flat, nullptr, s4);
    unsigned long long* dst = a.acc + (size_t(ay) * a.acc_w + ax) * 4;
    for (int ch = 0; ch < 4; ch++) atomicAdd(dst + ch, static_cast<unsigned long long>(to_fixed(s4[ch])));
  }
}

__global__ void k_normalize(const unsigned long long* acc, size_t n, int acc_w, int class_mod, const double* totals,
                            float* out) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const size_t px = i / 4;
  const int pc = unit_area_class(uint32_t(px % acc_w), uint32_t(px / acc_w), class_mod);
  out[i] = fixed_to_float(static_cast<long long>(acc[i]), kFixedScale * totals[pc]);
}

__global__ void k_prefilter_rows(float* buf, int w, int h) {
  const int y = blockIdx.x * blockDim.x + threadIdx.x;
  if (y < h) cardinal_prefilter_line(buf + size_t(y) * w * 4, w, 4);
}

__global__ void k_prefilter_cols(float* buf, int w, int h) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x;
  if (x < w) cardinal_prefilter_line(buf + size_t(x) * 4, h, w * 4);
}

__global__ void k_output(const float* buf, int acc_w, int pad, int width, int height, PaintRecord bg, float4* image) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= size_t(width) * height) return;
  const size_t x = i % width, y = i / width;
  float p[4];
  const float* q = buf + ((y + pad) * acc_w + x + pad) * 4;
  for (int c = 0; c < 4; c++) p[c] = q[c];
  clamp_premultiplied(p);
  image[i] = composite(p[0], p[1], p[2], p[3], bg);
}

}  // namespace

void Context::Impl::render(const Integration& integ, const IntegrationFrame& frame, const PaintRecord& bg,
                           GpuTimes* times) {
  const std::vector<SampleOffset>& pat = integ.offsets;
  StageTimer timer(times != nullptr);
  GpuTimes local;
  GpuTimes& t = times ? *times : local;
  const int n = integ.samples;
  // A block holds whole unit areas: as many as fit in the shape's threads.
  const int threads = n <= shape.threads ? n * (shape.threads / n) : n;
  if (n < 1 || threads > 1024) throw Error("the CUDA sampler takes 1 to 1024 samples per unit area");
  if (frame.ua_w != width || frame.ua_h != height) throw Error("render frame does not match the built tree");
  const bool direct = integ.support == 1 && integ.pad == 0;
  pattern.upload(pat);
  out_width = frame.width;
  out_height = frame.height;
  image.resize(size_t(frame.width) * frame.height);
  const SampleInputs in{leaf_entries.data(), segments.data(), paths.data(), paints.data()};
  Accumulate acc_args{nullptr, nullptr, integ.support, integ.class_mod, frame.acc_w, frame.acc_h};
  const size_t nacc = size_t(frame.acc_w) * frame.acc_h * 4;
  if (!direct) {
    weights.upload(integ.weights);
    weight_sums.upload(integ.weight_sums);
    totals.upload(integ.totals);
    acc.resize(nacc);
    MPVG_CUDA(cudaMemsetAsync(acc.data(), 0, nacc * sizeof(unsigned long long)));
    acc_args.acc = acc.data();
    acc_args.weights = weights.data();
  }

  timer.start(&t.schedule_ms);
  leaf_batches.resize(nleaves + 1);
  leaf_color.resize(nleaves + 1);
  uint32_t* nb = (u32[0].resize(nleaves + 1), u32[0].data());
  k_leaf_info<<<grid_for(nleaves + 1, kBlock), kBlock>>>(leaves.data(), nleaves, leaf_entries.data(), in, root_size,
                                                         width, height, static_cast<uint32_t>(shape.batch), nb,
                                                         leaf_color.data());
  launched();
  prim.exclusive_sum(nb, leaf_batches.data(), nleaves + 1);
  const uint32_t total_batches = read_u32(leaf_batches.data() + nleaves);
  timer.stop();

  timer.start(&t.sample_ms);
  if (total_batches) {
    const size_t shared = sizeof(AbstractSegment) * shape.chunk + sizeof(Entry) * (shape.chunk + (shape.chunk & 1)) +
                          sizeof(float4) * threads;
    MPVG_CUDA(cudaFuncSetAttribute(k_sample, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(shared)));
    k_sample<<<total_batches, threads, shared>>>(leaves.data(), static_cast<uint32_t>(nleaves),
                                                       leaf_batches.data(), in, pattern.data(), n, shape.chunk,
                                                       shape.batch, root_size, width, height, bg, image.data(),
                                                       acc_args);
    launched();
  }
  const size_t nua = size_t(width) * height;
  if (direct) {
    k_fill_uniform<<<grid_for(nua, kBlock), kBlock>>>(nodes.data(), root_size, width, height, leaf_color.data(), bg,
                                                      image.data());
    launched();
  } else {
    k_accumulate_uniform<<<grid_for(nua, kBlock), kBlock>>>(nodes.data(), root_size, width, height,
                                                            leaf_color.data(), weight_sums.data(), acc_args);
    launched();
  }
  timer.stop();

  if (!direct) {
    timer.start(&t.integrate_ms);
    buf.resize(nacc);
    k_normalize<<<grid_for(nacc, kBlock), kBlock>>>(acc.data(), nacc, frame.acc_w, integ.class_mod, totals.data(),
                                                     buf.data());
    launched();
    if (integ.prefilter) {
      k_prefilter_rows<<<grid_for(frame.acc_h, 64), 64>>>(buf.data(), frame.acc_w, frame.acc_h);
      launched();
      k_prefilter_cols<<<grid_for(frame.acc_w, 64), 64>>>(buf.data(), frame.acc_w, frame.acc_h);
      launched();
    }
    const size_t npix = size_t(frame.width) * frame.height;
    k_output<<<grid_for(npix, kBlock), kBlock>>>(buf.data(), frame.acc_w, integ.pad, frame.width, frame.height, bg,
                                                 image.data());
    launched();
    timer.stop();
  }
  timer.collect();
}

}  // namespace mpvg::gpu
