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

__global__ void k_sample(const Cell* leaves, uint32_t nleaves, const uint32_t* batch_start, SampleInputs in,
                         const SampleOffset* pattern, int n, int chunk, int batch, uint32_t root_size, int width,
                         int height, PaintRecord bg, float4* image) {
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
  for (uint32_t p0 = first; p0 < last; p0 += group) {
    const uint32_t pix = p0 + g;
    const bool active = g < group && pix < last;
    const uint32_t x = r.x0 + (active ? pix % r.w : 0), y = r.y0 + (active ? pix / r.w : 0);
    const float sx = float(x) + pattern[k].x, sy = float(y) + pattern[k].y;
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

}  // namespace

void Context::Impl::render(const std::vector<SampleOffset>& pat, const PaintRecord& bg, GpuTimes* times) {
  StageTimer timer(times != nullptr);
  GpuTimes local;
  GpuTimes& t = times ? *times : local;
  const int n = static_cast<int>(pat.size());
  if (n < 1 || shape.threads % n != 0 || n > shape.threads)
    throw Error("the CUDA sampler needs samples per pixel dividing " + std::to_string(shape.threads));
  pattern.upload(pat);
  image.resize(size_t(width) * height);
  const SampleInputs in{leaf_entries.data(), segments.data(), paths.data(), paints.data()};

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
                          sizeof(float4) * shape.threads;
    MPVG_CUDA(cudaFuncSetAttribute(k_sample, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(shared)));
    k_sample<<<total_batches, shape.threads, shared>>>(leaves.data(), static_cast<uint32_t>(nleaves),
                                                       leaf_batches.data(), in, pattern.data(), n, shape.chunk,
                                                       shape.batch, root_size, width, height, bg, image.data());
    launched();
  }
  const size_t npix = size_t(width) * height;
  k_fill_uniform<<<grid_for(npix, kBlock), kBlock>>>(nodes.data(), root_size, width, height, leaf_color.data(), bg,
                                                     image.data());
  launched();
  timer.stop();
  timer.collect();
}

}  // namespace mpvg::gpu
