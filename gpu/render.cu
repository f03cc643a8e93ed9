// Stages "schedule", "sample" and "integrate" on the GPU (§5.3, non-warped
// scheduler). Cells are aligned to pixels, so a leaf's unit areas are the
// pixels it covers: the schedule is, per leaf, its number of batches, each a
// tile of up to U unit areas (tw x th, tw = th or 2 th), and a block takes
// one batch. The block streams the leaf's entries through shared memory in
// chunks of I while its S threads advance one sample each through the
// flat-clipping machine; the samples of a unit area are then summed on chip,
// in the same order as on the CPU, and the pixel is written once (no
// atomics: deterministic).
//
// Leaves without geometry or position-dependent paints have one colour
// everywhere: it is evaluated once per leaf and written to their pixels by
// a separate fill.
//
// Wider filters (integration.h, Fig. 11): after a group of unit areas has
// been sampled, one thread per (unit area, covered pixel) computes the
// weighted sum and adds it, with 64-bit integer atomics, to fixed-point
// accumulators in shared memory that cover the batch's tile and its apron
// of K - 1 pixels; when the batch is done the tile goes to global memory
// with one atomic per pixel and channel (77 instead of 512 per 8 x 4 tile
// for K = 4). Integer sums do not depend on the order: deterministic, and
// equal to the CPU's. Unit areas of uniform leaves are gathered instead of
// scattered: the normalisation kernel adds, for each pixel, the flat colours
// of the uniform unit areas under its filter times their weight sums. The
// cardinal B-spline's prefilter then runs as a parallel recursive filter
// (Nehab et al. 2011): every line is cut into blocks filtered independently,
// the carries between blocks are propagated, and each block is corrected.
#include <algorithm>

#include "core/sampling/sampling.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 256;

struct PixelRect {
  uint32_t x0, y0, w, h;
};

// Where a root of the pass reads and writes: Context::Impl::RootPass, per
// tree root (by_root) and per pass slot (blockIdx.y of the per-pixel
// kernels, through pass_roots). Null tables: one root, the kernels'
// arguments.
__device__ __forceinline__ const RootPass* pass_of(const RootPass* by_root, const uint32_t* pass_roots) {
  return by_root + pass_roots[blockIdx.y];
}

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

// Schedule: batches per leaf of the root rendered (the others get none);
// uniform leaves (entry_varies) get their colour instead. Kinds:
// kUniformKinds of the scene's (groups or not).
template <uint32_t Kinds>
// Leaves from the count to its bound (a device-driven build not yet
// settled) and thread nleaves.n have no batches.
__global__ void k_leaf_info(const Cell* leaves, Count nleaves, const Entry* entries, SampleInputs in,
                            uint32_t root_size, int width, int height, uint32_t tile_w, uint32_t tile_h,
                            uint32_t root, uint32_t* batches, float4* color, const RootPass* by_root,
                            uint32_t pass_kinds, unsigned long long* samples) {
  const size_t l = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (l > nleaves.n) return;
  if (l >= nleaves.get()) {
    batches[l] = 0;
    return;
  }
  const Cell c = leaves[l];
  bool mine = c.root == root;
  if (by_root) {  // every root of the pass with this sampler's kinds
    const RootPass& p = by_root[c.root];
    mine = p.active && p.kinds == pass_kinds;
    width = p.ua_w, height = p.ua_h;
  }
  if (!mine) {
    batches[l] = 0;
    return;
  }
  const PixelRect r = leaf_rect(c, root_size, width, height);
  bool uniform = true;
  for (uint32_t i = c.begin; i < c.end && uniform; i++) uniform = !entry_varies(entries[i], in.paths);
  if (uniform) {
    // Uniform leaves hold no position-dependent paint, patterns included.
    const Rgba4 col = sample_cell<0, Kinds>(in, c.begin, c.end, float(r.x0), float(r.y0));
    color[l] = make_float4(col.r, col.g, col.b, col.a);
    batches[l] = 0;
    if (samples) atomicAdd(samples, 1ull);
  } else {
    color[l] = make_float4(0.0f, 0.0f, 0.0f, -1.0f);  // a = -1: not uniform
    batches[l] = ((r.w + tile_w - 1) / tile_w) * ((r.h + tile_h - 1) / tile_h);
  }
}

// Where a block's weighted sums go: directly to the pixel (box filter), or
// into the accumulators of the K x K pixels a unit area reaches.
struct Accumulate {
  unsigned long long* acc;  // null: direct
  const float* weights;     // [class][m][K*K]
  int support, class_mod, acc_w, acc_h;
  float4* ua_color;                // flat unit areas' colours (not direct)
  unsigned long long* samples;     // samples evaluated (--stats), or null
};

// Kinds: the paint kinds the scene uses (sampling.h); each mask is its own
// kernel, so that solid scenes keep the registers (and occupancy) of a
// solid-colour sampler.
template <uint32_t Kinds>
__global__ void k_sample(const Cell* leaves, uint32_t nleaves, const uint32_t* batch_start, SampleInputs in,
                         const SampleOffset* pattern, int n, int chunk, int tile_w, int tile_h, uint32_t root_size,
                         int width, int height, PaintRecord bg, float4* image, Accumulate a, const RootPass* by_root) {
  extern __shared__ __align__(16) unsigned char smem[];
  AbstractSegment* ss = reinterpret_cast<AbstractSegment*>(smem);
  Entry* se = reinterpret_cast<Entry*>(ss + chunk);
  float4* red = reinterpret_cast<float4*>(se + chunk + (chunk & 1));
  unsigned long long* tacc = reinterpret_cast<unsigned long long*>(red + blockDim.x);
  __shared__ uint32_t nwork;

  const uint32_t b = blockIdx.x;
  // The leaf of this batch: the last leaf whose batches start at or before it.
  uint32_t lo = 0, hi = nleaves;
  while (hi - lo > 1) {
    const uint32_t mid = (lo + hi) / 2;
    if (batch_start[mid] <= b) lo = mid; else hi = mid;
  }
  const Cell c = leaves[lo];
  if (by_root) {  // the leaf's root: its grids and buffers
    const RootPass& p = by_root[c.root];
    width = p.ua_w, height = p.ua_h;
    image = p.image;
    a.acc = a.acc ? p.acc : nullptr;
    a.ua_color = p.ua_color;
    a.acc_w = p.acc_w, a.acc_h = p.acc_h;
  }
  const PixelRect r = leaf_rect(c, root_size, width, height);
  // The batch's tile of unit areas within the leaf.
  const uint32_t bi = b - batch_start[lo], tiles_x = (r.w + tile_w - 1) / tile_w;
  const uint32_t ox = r.x0 + (bi % tiles_x) * tile_w, oy = r.y0 + (bi / tiles_x) * tile_h;
  const uint32_t tw = min(static_cast<uint32_t>(tile_w), r.x0 + r.w - ox);
  const uint32_t count = tw * min(static_cast<uint32_t>(tile_h), r.y0 + r.h - oy);

  const int tid = threadIdx.x;
  const int k = tid % n;             // sample of its unit area
  const int group = blockDim.x / n;  // unit areas in flight
  const int g = tid / n;
  const float w = box_weight(n);
  const int K = a.support;
  // Accumulators of the pixels the tile reaches: (tile_w + K - 1) x
  // (tile_h + K - 1), the first at (ox - K + 1, oy - K + 1).
  const int acc_tw = tile_w + K - 1, acc_tn = a.acc ? acc_tw * (tile_h + K - 1) * 4 : 0;
  for (int i = tid; i < acc_tn; i += blockDim.x) tacc[i] = 0;
  // Adaptive sampling (core/sampling/sampling.h, unit_area_flat): a flat unit area
  // takes one sample, on a thread of its own, and goes to its pixel or to
  // the unit-area colours the normalisation gathers; the others are listed
  // in `work` (in any order: every sum is order-free) for the sample groups.
  // A leaf whose stream fits in one chunk is loaded once, for the test and
  // for every group's samples.
  uint32_t* work = reinterpret_cast<uint32_t*>(tacc + acc_tn);
  const uint32_t stream = c.end - c.begin;
  const bool resident = stream <= static_cast<uint32_t>(chunk);
  if (resident)
    for (uint32_t t = tid; t < stream; t += blockDim.x) {
      const Entry e = in.entries[c.begin + t];
      se[t] = e;
      if (entry_kind(e) == ENTRY_SEGMENT) ss[t] = in.segments[e.data];
    }
  if (tid == 0) nwork = 0;
  __syncthreads();
  for (uint32_t u = tid; u < count; u += blockDim.x) {
    const uint32_t x = ox + u % tw, y = oy + u / tw;
    bool flat = true;
    if (resident) {
      for (uint32_t t = 0; t < stream && flat; t++) flat = !unit_area_spoils_flat(se[t], &ss[t], in.paths, x, y);
    } else {
      flat = unit_area_flat(in, c.begin, c.end, x, y);
    }
    if (flat) {
      const SampleOffset o = pattern[unit_area_class(x, y, a.class_mod) * n];
      const float fx = float(x) + o.x, fy = float(y) + o.y;
      SampleState<Kinds> fs = sample_start<Kinds>();
      if (resident)
        for (uint32_t t = 0; t < stream && !fs.done; t++) sample_step<0, Kinds>(fs, in, se[t], &ss[t], fx, fy);
      else
        for (uint32_t i = c.begin; i < c.end && !fs.done; i++) {
          const Entry e = in.entries[i];
          sample_step<0, Kinds>(fs, in, e, entry_segment(e, in.segments), fx, fy);
        }
      sample_finish_path<0, Kinds>(fs, in, fx, fy);
      const Rgba4 col = fs.color;
      if (a.acc) a.ua_color[size_t(y) * width + x] = make_float4(col.r, col.g, col.b, col.a);
      else image[size_t(y) * width + x] = composite(col.r, col.g, col.b, col.a, bg);
    } else {
      work[atomicAdd(&nwork, 1u)] = u;
    }
  }
  __syncthreads();
  const uint32_t nw = nwork;
  if (a.samples && tid == 0) atomicAdd(a.samples, static_cast<unsigned long long>(nw) * n + (count - nw));
  for (uint32_t p0 = 0; p0 < nw; p0 += group) {
    const uint32_t wi = p0 + g;
    const bool active = g < group && wi < nw;
    const uint32_t pix = active ? work[wi] : 0;
    const uint32_t x = ox + pix % tw, y = oy + pix / tw;
    const SampleOffset o = pattern[unit_area_class(x, y, a.class_mod) * n + k];  // the class's pattern
    const float sx = float(x) + o.x, sy = float(y) + o.y;
    SampleState<Kinds> st = sample_start<Kinds>();
    st.done = !active;
    for (uint32_t base = c.begin; base < c.end; base += chunk) {
      const uint32_t cnt = min(static_cast<uint32_t>(chunk), c.end - base);
      if (!resident) {
        __syncthreads();  // the previous chunk has been read by everyone
        for (uint32_t t = tid; t < cnt; t += blockDim.x) {
          const Entry e = in.entries[base + t];
          se[t] = e;
          if (entry_kind(e) == ENTRY_SEGMENT) ss[t] = in.segments[e.data];
        }
        __syncthreads();
      }
      for (uint32_t t = 0; t < cnt && !st.done; t++) sample_step<0, Kinds>(st, in, se[t], &ss[t], sx, sy);
      if (__syncthreads_and(st.done)) break;
    }
    if (active) sample_finish_path<0, Kinds>(st, in, sx, sy);
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
        if (p0 + gg >= nw) continue;
        const uint32_t upix = work[p0 + gg];
        const uint32_t ux = ox + upix % tw, uy = oy + upix / tw;
        float s4[4];
        integrate_unit_area(a.weights + size_t(unit_area_class(ux, uy, a.class_mod)) * n * targets + e, targets, 0.0f,
                            n, false, nullptr, reinterpret_cast<const float*>(&red[gg * n]), s4);
        // Pixel (ux - ex, uy - ey) at (ux - ox - ex + K - 1, ...) in the tile.
        unsigned long long* dst =
            tacc + ((int(uy - oy) - e / K + K - 1) * acc_tw + (int(ux - ox) - e % K + K - 1)) * 4;
        for (int ch = 0; ch < 4; ch++) atomicAdd(dst + ch, static_cast<unsigned long long>(to_fixed(s4[ch])));
      }
    }
    __syncthreads();  // red[] is rewritten by the next group
  }
  // The tile's sums to the global accumulators.
  for (int i = tid; i < acc_tn; i += blockDim.x) {
    const unsigned long long v = tacc[i];
    if (v == 0) continue;
    const int px = i / 4;
    const int ax = int(ox) - K + 1 + px % acc_tw, ay = int(oy) - K + 1 + px / acc_tw;
    if (ax < 0 || ay < 0 || ax >= a.acc_w || ay >= a.acc_h) continue;
    atomicAdd(a.acc + (size_t(ay) * a.acc_w + ax) * 4 + i % 4, v);
  }
}

__global__ void k_fill_uniform(const Node* nodes, uint32_t root_size, uint32_t root, int width, int height,
                               const float4* color, PaintRecord bg, float4* image, const RootPass* by_root,
                               const uint32_t* pass_roots) {
  if (by_root) {
    const RootPass& p = *pass_of(by_root, pass_roots);
    root = p.root, width = p.ua_w, height = p.ua_h, image = p.image;
  }
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= size_t(width) * height) return;
  const uint32_t x = static_cast<uint32_t>(i % width), y = static_cast<uint32_t>(i / width);
  const float4 c = color[tree_find_leaf(nodes, root_size, x, y, root)];
  if (c.w >= 0.0f) image[i] = composite(c.x, c.y, c.z, c.w, bg);
}

// Unit areas of uniform leaves send flat colour times the weights' sums.
// The flat colour of every unit area in a uniform leaf (a < 0 elsewhere).
__global__ void k_unit_area_color(const Node* nodes, uint32_t root_size, uint32_t root, int ua_w, int ua_h,
                                  const float4* color, float4* ua_color, const RootPass* by_root,
                                  const uint32_t* pass_roots) {
  if (by_root) {
    const RootPass& p = *pass_of(by_root, pass_roots);
    root = p.root, ua_w = p.ua_w, ua_h = p.ua_h, ua_color = p.ua_color;
  }
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= size_t(ua_w) * ua_h) return;
  const uint32_t ux = static_cast<uint32_t>(i % ua_w), uy = static_cast<uint32_t>(i / ua_w);
  ua_color[i] = color[tree_find_leaf(nodes, root_size, ux, uy, root)];
}

// Per accumulation pixel: the atomics' sums plus the uniform unit areas of
// its support (each term rounded to fixed point exactly as if it had been
// scattered), normalised by the pixel class's total weight.
__global__ void k_normalize(const unsigned long long* acc, const float4* ua_color, int acc_w, int acc_h, int ua_w,
                            int K, int class_mod, const float* weight_sums, const double* totals, float4* out,
                            const RootPass* by_root, const uint32_t* pass_roots) {
  if (by_root) {
    const RootPass& p = *pass_of(by_root, pass_roots);
    acc = p.acc, ua_color = p.ua_color, acc_w = p.acc_w, acc_h = p.acc_h, ua_w = p.ua_w, out = p.buf;
  }
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= size_t(acc_w) * acc_h) return;
  const int ax = int(i % acc_w), ay = int(i / acc_w);
  long long sum[4];
  for (int ch = 0; ch < 4; ch++) sum[ch] = static_cast<long long>(acc[i * 4 + ch]);
  for (int e = 0; e < K * K; e++) {
    const int ux = ax + e % K, uy = ay + e / K;
    const float4 c = ua_color[size_t(uy) * ua_w + ux];
    if (c.w < 0.0f) continue;
    const float flat[4] = {c.x, c.y, c.z, c.w};
    float s4[4];
    integrate_unit_area(nullptr, 0, weight_sums[unit_area_class(ux, uy, class_mod) * K * K + e], 0, true, flat,
                        nullptr, s4);
    for (int ch = 0; ch < 4; ch++) sum[ch] += to_fixed(s4[ch]);
  }
  const double norm = kFixedScale * totals[unit_area_class(uint32_t(ax), uint32_t(ay), class_mod)];
  out[i] = make_float4(fixed_to_float(sum[0], norm), fixed_to_float(sum[1], norm), fixed_to_float(sum[2], norm),
                       fixed_to_float(sum[3], norm));
}

// The cardinal prefilter (core/sampling/integration.h) on `lines` lines of n float4
// pixels: pixel k of line l at data[l * line_stride + k * elem_stride]. A
// block takes kPrefilterLines lines (threadIdx.x), each cut into the
// prefilter's kPrefilterBlocks blocks (threadIdx.y): the steps of
// cardinal_prefilter_line, each block's on its own thread.
constexpr int kPrefilterLines = 8;

// by_root: each pass slot's accumulation image (blockIdx.y), its rows
// (columns: false) or its columns.
__global__ void k_prefilter_lines(float4* data, int lines, int n, size_t line_stride, size_t elem_stride,
                                  const RootPass* by_root, const uint32_t* pass_roots, bool rows) {
  if (by_root) {
    const RootPass& p = *pass_of(by_root, pass_roots);
    data = p.buf;
    lines = rows ? p.acc_h : p.acc_w;
    n = rows ? p.acc_w : p.acc_h;
    line_stride = rows ? size_t(p.acc_w) : 1;
    elem_stride = rows ? 1 : size_t(p.acc_w);
  }
  __shared__ float4 carry[kPrefilterBlocks][kPrefilterLines];
  __shared__ PrefilterBlock blocks[kPrefilterBlocks];
  const int tx = threadIdx.x, j = threadIdx.y;
  const int line = blockIdx.x * kPrefilterLines + tx;
  const bool live = line < lines && n >= 2;
  float4* d = data + (live ? size_t(line) * line_stride : 0);
  const size_t s = elem_stride;
  if (tx == 0) blocks[j] = prefilter_block(n, j);
  const float4 zero = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
  // The boundary carry c[-1], from the input before any block overwrites it.
  float4 c0 = zero;
  if (live && j == 0) {
    const float* f = reinterpret_cast<const float*>(d);
    const int s4 = static_cast<int>(elem_stride * 4);
    c0 = make_float4(cardinal_causal_carry(f, n, s4), cardinal_causal_carry(f + 1, n, s4),
                     cardinal_causal_carry(f + 2, n, s4), cardinal_causal_carry(f + 3, n, s4));
  }
  __syncthreads();
  const PrefilterBlock b = blocks[j];
  auto carry_of = [&](int k) -> float4& { return carry[k][tx]; };
  auto block_of = [&](int k) { return blocks[k]; };
  // 1-3. Causal.
  carry[j][tx] = live ? prefilter_causal_block(d, s, b, zero) : zero;
  __syncthreads();
  if (j == 0) prefilter_carries(carry_of, block_of, c0, false);
  __syncthreads();
  if (live) prefilter_causal_correct(d, s, b, carry[j][tx]);
  __syncthreads();
  // 4-6. Anticausal; the block ending the line starts from the boundary
  // value, read before other blocks overwrite c[n-2].
  const bool tail = live && b.end > b.start && b.end == n;
  const float4 a0 = tail ? cardinal_anticausal_start(d[(n - 1) * s], d[(n - 2) * s]) : zero;
  __syncthreads();
  carry[j][tx] = live ? prefilter_anticausal_block(d, s, b, tail, a0) : zero;
  __syncthreads();
  if (j == 0) prefilter_carries(carry_of, block_of, zero, true);
  __syncthreads();
  if (live) prefilter_anticausal_correct(d, s, b, carry[j][tx]);
}

__global__ void k_output(const float* buf, int acc_w, int pad, int width, int height, PaintRecord bg, float4* image,
                         const RootPass* by_root, const uint32_t* pass_roots) {
  if (by_root) {
    const RootPass& p = *pass_of(by_root, pass_roots);
    buf = reinterpret_cast<const float*>(p.buf), acc_w = p.acc_w, width = p.out_w, height = p.out_h, image = p.image;
  }
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= size_t(width) * height) return;
  const size_t x = i % width, y = i / width;
  float p[4];
  const float* q = buf + ((y + pad) * acc_w + x + pad) * 4;
  for (int c = 0; c < 4; c++) p[c] = q[c];
  clamp_premultiplied(p);
  image[i] = composite(p[0], p[1], p[2], p[3], bg);
}

// A block's threads for n samples per unit area (whole unit areas, as many
// as fit in the shape's threads), and the tile of unit areas a batch is:
// U = 2^b unit areas as 2^ceil(b/2) x 2^floor(b/2).
struct SamplerGrid {
  int threads, tile_w, tile_h;
};
SamplerGrid sampler_grid(const SamplerShape& shape, int n) {
  const int threads = n <= shape.threads ? n * (shape.threads / n) : n;
  if (n < 1 || threads > 1024) throw Error("the CUDA sampler takes 1 to 1024 samples per unit area");
  int log_batch = 0;
  while ((2 << log_batch) <= shape.batch) log_batch++;
  const int tile_w = 1 << ((log_batch + 1) / 2);
  return SamplerGrid{threads, tile_w, (1 << log_batch) / tile_w};
}

// The sampler over `total` batches (one block each), specialised for
// `kinds`, its shared memory sized for the shape and, under a wide filter,
// the accumulators of a tile and its apron.
void launch_sampler(Context::Impl& m, uint32_t kinds, uint32_t total, int threads, bool direct, const Integration& integ,
                    int tile_w, int tile_h, const SampleInputs& in, int width, int height, const PaintRecord& bg,
                    float4* image, const Accumulate& a, const RootPass* by_root) {
  const int K = integ.support;
  const SamplerShape& sh = m.shape;
  const size_t shared = sizeof(AbstractSegment) * sh.chunk + sizeof(Entry) * (sh.chunk + (sh.chunk & 1)) +
                        sizeof(float4) * threads +
                        (direct ? 0 : sizeof(unsigned long long) * 4 * (tile_w + K - 1) * (tile_h + K - 1)) +
                        sizeof(uint32_t) * tile_w * tile_h;  // the work list
  auto launch = [&](auto kernel) {
    MPVG_CUDA(cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(shared)));
    kernel<<<total, threads, shared>>>(m.leaves.data(), static_cast<uint32_t>(m.nleaves), m.leaf_batches.data(), in,
                                       m.pattern.data(), integ.samples, sh.chunk, tile_w, tile_h, m.root_size, width,
                                       height, bg, image, a, by_root);
  };
  with_sampler_kinds(kinds, [&](auto k) { launch(k_sample<decltype(k)::value>); });
  m.launched();
}

}  // namespace

void Context::Impl::render(const Integration& integ, const IntegrationFrame& frame, const PaintRecord& bg,
                           GpuTimes* times, uint32_t root) {
  const std::vector<SampleOffset>& pat = integ.offsets;
  StageTimer timer(times != nullptr);
  GpuTimes local;
  GpuTimes& t = times ? *times : local;
  const SamplerGrid sg = sampler_grid(shape, integ.samples);
  const int threads = sg.threads, tile_w = sg.tile_w, tile_h = sg.tile_h;
  if (root >= roots.size()) throw Error("render of a root the built tree does not have");
  // The root's own grid (a forest's tree is built over the largest).
  const int width = roots[root].width, height = roots[root].height;
  if (frame.ua_w != width || frame.ua_h != height) throw Error("render frame does not match the built tree");
  const bool direct = integ.support == 1 && integ.pad == 0;
  upload_changed(pattern, pattern_host, pat);
  out_width = frame.width;
  out_height = frame.height;
  image.resize(size_t(frame.width) * frame.height);
  const SampleInputs in{leaf_entries.data(), segments.data(), paths.data(), paint_view.data()};
  Accumulate acc_args{nullptr, nullptr, integ.support, integ.class_mod, frame.acc_w, frame.acc_h, nullptr, nullptr};
  if (times) {  // samples evaluated, for --stats
    sample_count.resize(1);
    MPVG_CUDA(cudaMemsetAsync(sample_count.data(), 0, sizeof(unsigned long long)));
    acc_args.samples = sample_count.data();
  }
  const size_t nacc = size_t(frame.acc_w) * frame.acc_h * 4;
  if (!direct) {
    upload_changed(weights, weights_host, integ.weights);
    upload_changed(weight_sums, weight_sums_host, integ.weight_sums);
    upload_changed(totals, totals_host, integ.totals);
    acc.resize(nacc);
    MPVG_CUDA(cudaMemsetAsync(acc.data(), 0, nacc * sizeof(unsigned long long)));
    acc_args.acc = acc.data();
    acc_args.weights = weights.data();
  }

  timer.start(&t.schedule_ms);
  // A device-driven build not yet settled: nleaves is a bound, the count
  // on the device; it comes back with the batches' total, one round trip.
  const bool deferred = pending;
  const Count leaf_count{nleaves, deferred ? drive.data() + DRIVE_LEAVES : nullptr};
  const size_t L = nleaves;
  leaf_batches.resize(L + 1);
  leaf_color.resize(L + 1);
  uint32_t* nb = (u32[0].resize(L + 1), u32[0].data());
  const uint32_t kinds = roots[root].kinds[integ.support % 2 == 1];  // the root's own (core/tree/tree.h, SceneRoot)
  auto leaf_info = (kinds & SAMPLE_GROUPS) ? k_leaf_info<SAMPLE_GROUPS> : k_leaf_info<PAINTS_SOLID>;
  leaf_info<<<grid_for(L + 1, kBlock), kBlock>>>(leaves.data(), leaf_count, leaf_entries.data(), in, root_size, width,
                                                 height, static_cast<uint32_t>(tile_w), static_cast<uint32_t>(tile_h),
                                                 root, nb, leaf_color.data(), nullptr, 0, acc_args.samples);
  launched();
  prim.exclusive_sum(nb, leaf_batches.data(), L + 1);
  uint32_t total_batches = 0;
  if (deferred) {
    if (!settle({{leaf_batches.data() + L, &total_batches}})) {
      // Outgrew its pools: built again host-driven; render that tree.
      timer.stop();
      timer.collect();
      render(integ, frame, bg, times, root);
      return;
    }
  } else {
    total_batches = read_u32(leaf_batches.data() + nleaves);
  }
  const size_t nua = size_t(width) * height;
  timer.stop();

  timer.start(&t.sample_ms);
  if (!direct) {  // before the sampler, which adds the flat unit areas' colours
    ua_color.resize(nua);
    k_unit_area_color<<<grid_for(nua, kBlock), kBlock>>>(nodes.data(), root_size, root, width, height,
                                                         leaf_color.data(), ua_color.data(), nullptr, nullptr);
    launched();
    acc_args.ua_color = ua_color.data();
  }
  if (total_batches) {
    launch_sampler(*this, kinds, total_batches, threads, direct, integ, tile_w, tile_h, in, width, height, bg,
                   image.data(), acc_args, nullptr);
  }
  if (direct) {
    k_fill_uniform<<<grid_for(nua, kBlock), kBlock>>>(nodes.data(), root_size, root, width, height,
                                                      leaf_color.data(), bg, image.data(), nullptr, nullptr);
    launched();
  }
  timer.stop();

  if (!direct) {
    timer.start(&t.integrate_ms);
    buf.resize(nacc);
    const size_t npacc = size_t(frame.acc_w) * frame.acc_h;
    k_normalize<<<grid_for(npacc, kBlock), kBlock>>>(acc.data(), ua_color.data(), frame.acc_w, frame.acc_h, width,
                                                      integ.support, integ.class_mod, weight_sums.data(),
                                                      totals.data(), reinterpret_cast<float4*>(buf.data()), nullptr,
                                                      nullptr);
    launched();
    if (integ.prefilter) {
      const dim3 block(kPrefilterLines, kPrefilterBlocks);
      float4* b4 = reinterpret_cast<float4*>(buf.data());
      // Rows, then columns, as on the CPU.
      k_prefilter_lines<<<grid_for(frame.acc_h, kPrefilterLines), block>>>(b4, frame.acc_h, frame.acc_w,
                                                                            size_t(frame.acc_w), 1, nullptr, nullptr,
                                                                            true);
      launched();
      k_prefilter_lines<<<grid_for(frame.acc_w, kPrefilterLines), block>>>(b4, frame.acc_w, frame.acc_h, 1,
                                                                            size_t(frame.acc_w), nullptr, nullptr,
                                                                            false);
      launched();
    }
    const size_t npix = size_t(frame.width) * frame.height;
    k_output<<<grid_for(npix, kBlock), kBlock>>>(buf.data(), frame.acc_w, integ.pad, frame.width, frame.height, bg,
                                                 image.data(), nullptr, nullptr);
    launched();
    timer.stop();
  }
  timer.collect();
  if (times) {
    unsigned long long n = 0;
    MPVG_CUDA(cudaMemcpy(&n, sample_count.data(), sizeof n, cudaMemcpyDeviceToHost));
    times->samples += n;
  }
}

void Context::Impl::render_roots(const Integration& integ, const std::vector<IntegrationFrame>& frames,
                                 const PaintRecord& bg, const std::vector<float*>& images) {
  const SamplerGrid sg = sampler_grid(shape, integ.samples);
  const int threads = sg.threads, tile_w = sg.tile_w, tile_h = sg.tile_h;
  if (frames.size() > roots.size() || images.size() != frames.size())
    throw Error("render of roots the built tree does not have");
  if (frames.empty()) return;
  settle();
  const bool direct = integ.support == 1 && integ.pad == 0;
  const bool odd = integ.support % 2 == 1;
  upload_changed(pattern, pattern_host, integ.offsets);
  if (!direct) {
    upload_changed(weights, weights_host, integ.weights);
    upload_changed(weight_sums, weight_sums_host, integ.weight_sums);
    upload_changed(totals, totals_host, integ.totals);
  }
  // Each root's grids, and its share of the accumulators, the unit-area
  // colours and the accumulation image.
  size_t nacc = 0, nua = 0, max_ua = 0, max_acc = 0, max_out = 0, max_lines = 0;
  for (size_t k = 0; k < frames.size(); k++) {
    const IntegrationFrame& f = frames[k];
    if (f.ua_w != roots[k].width || f.ua_h != roots[k].height) throw Error("render frame does not match the built tree");
    nacc += size_t(f.acc_w) * f.acc_h, nua += size_t(f.ua_w) * f.ua_h;
    max_ua = std::max(max_ua, size_t(f.ua_w) * f.ua_h);
    max_acc = std::max(max_acc, size_t(f.acc_w) * f.acc_h);
    max_out = std::max(max_out, size_t(f.width) * f.height);
    max_lines = std::max<size_t>(max_lines, std::max(f.acc_w, f.acc_h));
  }
  if (!direct) {
    acc.resize(nacc * 4);
    MPVG_CUDA(cudaMemsetAsync(acc.data(), 0, nacc * 4 * sizeof(unsigned long long)));
    ua_color.resize(nua);
    buf.resize(nacc * 4);
  }
  std::vector<RootPass> table(roots.size(), RootPass{});
  std::vector<uint32_t> slots(frames.size());
  std::vector<uint32_t> kinds_seen;
  size_t at_acc = 0, at_ua = 0;
  for (size_t k = 0; k < frames.size(); k++) {
    const IntegrationFrame& f = frames[k];
    RootPass& p = table[k];
    p.ua_w = f.ua_w, p.ua_h = f.ua_h, p.acc_w = f.acc_w, p.acc_h = f.acc_h, p.out_w = f.width, p.out_h = f.height;
    p.root = static_cast<uint32_t>(k);
    p.active = 1;
    p.kinds = roots[k].kinds[odd];
    p.image = reinterpret_cast<float4*>(images[k]);
    if (!direct) {
      p.acc = acc.data() + at_acc * 4;
      p.buf = reinterpret_cast<float4*>(buf.data()) + at_acc;
      p.ua_color = ua_color.data() + at_ua;
    }
    at_acc += size_t(f.acc_w) * f.acc_h, at_ua += size_t(f.ua_w) * f.ua_h;
    slots[k] = static_cast<uint32_t>(k);
    if (std::find(kinds_seen.begin(), kinds_seen.end(), p.kinds) == kinds_seen.end()) kinds_seen.push_back(p.kinds);
  }
  pass_table.upload(table);
  pass_slots.upload(slots);
  const RootPass* by_root = pass_table.data();
  const uint32_t* pass_roots = pass_slots.data();
  const unsigned nslots = static_cast<unsigned>(frames.size());
  const SampleInputs in{leaf_entries.data(), segments.data(), paths.data(), paint_view.data()};
  Accumulate acc_args{nullptr, direct ? nullptr : weights.data(), integ.support, integ.class_mod, 0, 0, nullptr, nullptr};
  if (!direct) acc_args.acc = acc.data();  // non-null: accumulate (each root's own, from the table)
  leaf_batches.resize(nleaves + 1);
  leaf_color.resize(nleaves + 1);
  uint32_t* nb = (u32[0].resize(nleaves + 1), u32[0].data());
  // One schedule and one sampler launch per sampler specialisation (each
  // root keeps its own, as alone: SceneRoot::kinds). The unit-area colours
  // come from every leaf's colour before any sampler adds its flat unit
  // areas: with several specialisations, a first round of schedules gives
  // all colours and each sampler's round schedules its batches again.
  auto leaf_info_pass = [&](uint32_t kinds) {
    auto leaf_info = (kinds & SAMPLE_GROUPS) ? k_leaf_info<SAMPLE_GROUPS> : k_leaf_info<PAINTS_SOLID>;
    leaf_info<<<grid_for(nleaves + 1, kBlock), kBlock>>>(leaves.data(), Count{nleaves}, leaf_entries.data(), in, root_size, 0,
                                                         0, static_cast<uint32_t>(tile_w),
                                                         static_cast<uint32_t>(tile_h), 0, nb, leaf_color.data(),
                                                         by_root, kinds, nullptr);
    launched();
  };
  const bool rounds = kinds_seen.size() > 1;
  if (rounds)
    for (const uint32_t kinds : kinds_seen) leaf_info_pass(kinds);
  else
    leaf_info_pass(kinds_seen.front());
  if (!direct) {
    k_unit_area_color<<<dim3(grid_for(max_ua, kBlock), nslots), kBlock>>>(nodes.data(), root_size, 0, 0, 0,
                                                                         leaf_color.data(), nullptr, by_root,
                                                                         pass_roots);
    launched();
  }
  for (const uint32_t kinds : kinds_seen) {
    if (rounds) leaf_info_pass(kinds);
    prim.exclusive_sum(nb, leaf_batches.data(), nleaves + 1);
    const uint32_t total_batches = read_u32(leaf_batches.data() + nleaves);
    if (!total_batches) continue;
    launch_sampler(*this, kinds, total_batches, threads, direct, integ, tile_w, tile_h, in, 0, 0, bg, nullptr, acc_args,
                   by_root);
  }
  if (direct) {
    k_fill_uniform<<<dim3(grid_for(max_ua, kBlock), nslots), kBlock>>>(nodes.data(), root_size, 0, 0, 0,
                                                                      leaf_color.data(), bg, nullptr, by_root,
                                                                      pass_roots);
    launched();
    return;
  }
  k_normalize<<<dim3(grid_for(max_acc, kBlock), nslots), kBlock>>>(nullptr, nullptr, 0, 0, 0, integ.support,
                                                                  integ.class_mod, weight_sums.data(), totals.data(),
                                                                  nullptr, by_root, pass_roots);
  launched();
  if (integ.prefilter) {
    const dim3 block(kPrefilterLines, kPrefilterBlocks);
    const dim3 grid(grid_for(max_lines, kPrefilterLines), nslots);
    k_prefilter_lines<<<grid, block>>>(nullptr, 0, 0, 0, 0, by_root, pass_roots, true);
    launched();
    k_prefilter_lines<<<grid, block>>>(nullptr, 0, 0, 0, 0, by_root, pass_roots, false);
    launched();
  }
  k_output<<<dim3(grid_for(max_out, kBlock), nslots), kBlock>>>(nullptr, 0, integ.pad, 0, 0, bg, nullptr, by_root,
                                                               pass_roots);
  launched();
}

}  // namespace mpvg::gpu
