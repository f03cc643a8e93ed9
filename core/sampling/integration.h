// Integration (paper §5.1): antialiasing filters of wide support with
// samples shared between the pixels whose filters overlap.
//
// The filter domain of a pixel is tiled by K x K unit areas (K = 1 for the
// box, 2 for the hat, 4 for the cubics). Every unit area of the image is
// sampled once, with the same pattern of m samples, and sends one weighted
// sum to each of the K x K pixels whose support covers it (Fig. 11):
//
//   c(p) = sum over unit areas A_j of p's support of
//          (1/m) sum_i f(sample_ji) psi(sample_ji - centre(p))          (27)
//
// so K^2 m samples reach each pixel at the cost of m per unit area: 4x4x32
// weighs 512 samples per pixel. Pixels keep one fixed-point sum per channel
// whatever the sample count; integer sums do not depend on the order in
// which unit areas arrive, so images are deterministic and the CPU and GPU
// agree bit for bit.
//
// Frames. For odd K (the box) a unit area is a pixel. For even K the pixel
// centres must sit on unit-area corners, so unit-area space is pixel space
// shifted by half a pixel. Pixels near the border need unit areas beyond the
// image (the illustration continues there), and the cardinal B-spline's
// recursive prefilter needs pixels beyond the border as well: it runs on an
// image padded by kCardinalPad pixels on every side, whose influence on the
// visible pixels (|z|^12, z = sqrt(3) - 2) is below 1e-6, so the result
// equals filtering the unbounded illustration.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>
#if defined(__SSE2__) && defined(__x86_64__) && !defined(__CUDA_ARCH__)
#include <emmintrin.h>  // to_fixed's cvtsd2si
#endif

#include "core/hd.h"

namespace mpvg {

struct SampleOffset {
  float x, y;  // in [0, 1)^2, relative to the unit area's corner
};

enum class Filter : uint32_t { Box, Hat, BSpline, Cardinal, Mitchell, CatmullRom };
enum class PatternKind { Stratified, BlueNoise };

// Name <-> filter, for the command line ("box", "hat", "bspline",
// "cardinal", "mitchell", "catmull-rom").
bool parse_filter(const std::string& name, Filter* out);
const char* filter_name(Filter f);

// Support width in unit areas.
MPVG_HD_INLINE int filter_support(Filter f) {
  return f == Filter::Box ? 1 : (f == Filter::Hat ? 2 : 4);
}

// The 1D kernel phi; the 2D filter is psi(x, y) = phi(x) phi(y). Every phi
// integrates to 1 over its support.
MPVG_HD_INLINE float filter_kernel(Filter f, float x) {
  const float a = fabsf(x);
  switch (f) {
    case Filter::Box: return a < 0.5f ? 1.0f : 0.0f;
    case Filter::Hat: return a < 1.0f ? 1.0f - a : 0.0f;
    case Filter::BSpline:
    case Filter::Cardinal:  // the B-spline, then the prefilter
      if (a < 1.0f) return (4.0f - 6.0f * a * a + 3.0f * a * a * a) / 6.0f;
      if (a < 2.0f) {
        const float t = 2.0f - a;
        return t * t * t / 6.0f;
      }
      return 0.0f;
    default: {
      // Mitchell and Netravali's (B, C) cubics: (1/3, 1/3) and Catmull-Rom (0, 1/2).
      const float B = f == Filter::Mitchell ? 1.0f / 3.0f : 0.0f;
      const float C = f == Filter::Mitchell ? 1.0f / 3.0f : 0.5f;
      if (a < 1.0f)
        return ((12.0f - 9.0f * B - 6.0f * C) * a * a * a + (-18.0f + 12.0f * B + 6.0f * C) * a * a +
                (6.0f - 2.0f * B)) /
               6.0f;
      if (a < 2.0f)
        return ((-B - 6.0f * C) * a * a * a + (6.0f * B + 30.0f * C) * a * a + (-12.0f * B - 48.0f * C) * a +
                (8.0f * B + 24.0f * C)) /
               6.0f;
      return 0.0f;
    }
  }
}

constexpr int kCardinalPad = 12;

// Everything a backend needs to integrate one frame.
//
// Unit areas fall into K x K classes by their grid position (u mod K,
// v mod K), each with its own pattern. A pixel's K x K unit areas are one of
// each class, so the K^2 patterns together are what the pixel's filter
// integrates over: a single blue-noise tile of K^2 m samples (or, for
// stratified patterns, shifted copies whose rows and columns interleave)
// rather than K^2 copies of one m-sample pattern whose errors along an edge
// would add up.
struct Integration {
  Filter filter = Filter::Box;
  int support = 1;     // K
  int pad = 0;         // pixels of padding around the image (cardinal prefilter)
  int samples = 1;     // m, per unit area
  int classes = 1;     // K^2 for K > 1
  int class_mod = 1;   // K for K > 1: class of unit area (u, v) is unit_area_class(u, v, class_mod)
  std::vector<SampleOffset> offsets;  // [class][i]
  // weights[(class * m + i) * K^2 + ey * K + ex]: weight of sample i of a
  // unit area of that class for the accumulation pixel (ex, ey) unit areas
  // before it (see integration_frame). Targets vary fastest: the GPU's
  // threads for one unit area's K^2 pixels read neighbouring weights.
  std::vector<float> weights;
  std::vector<float> weight_sums;  // [class][target]: sum over i, for uniform cells
  std::vector<double> totals;      // [pixel class]: all weights reaching such a pixel
  bool prefilter = false;          // cardinal B-spline: run the recursive prefilter
};

// Class of unit area (u, v) and of accumulation pixel (a, b).
MPVG_HD_INLINE int unit_area_class(uint32_t u, uint32_t v, int K) { return int(v % K) * K + int(u % K); }

// Builds the classes' patterns and weight tables. With a pattern kind, blue
// noise uses the tile of K x K unit areas (core/sampling/blue_noise_tables.inc) whose
// unit areas are the classes: every pixel's support then holds the whole
// tile, K^2 m samples that are blue noise as one set; the seed applies a
// symmetry of the tile and a shift within unit areas. Stratified patterns,
// and the variant taking one pattern, give class (cx, cy) the pattern shifted
// by (cy, cx) / (K m). Throws mpvg::Error for blue noise of other than 8,
// 32 or 64 samples.
//
// odd_support: a filter of even support K integrates over K + 1 unit areas
// per side instead (the kernel is 0 on the extra ring), so that unit areas
// are pixels again: what aliased paths need (core/sampling/sampling.h). Blue-noise
// tiles exist for supports 1 to 5.
Integration make_integration(Filter f, PatternKind kind, int samples, uint32_t seed, bool odd_support = false);
Integration make_integration(Filter f, const std::vector<SampleOffset>& pattern, bool odd_support = false);
// The support in unit areas make_integration gives filter f.
int integration_support(Filter f, bool odd_support);

// The grids of a frame of width x height output pixels:
//   accumulation image  acc_w x acc_h = output + 2 pad
//   unit areas          ua_w x ua_h   = accumulation + K - 1
// Unit area (u, v) sends to accumulation pixels (u - ex, v - ey) for
// ex, ey in [0, K). to_unit_areas is the translation from output pixel
// coordinates to unit-area coordinates (added to x and y).
struct IntegrationFrame {
  int width, height;
  int acc_w, acc_h;
  int ua_w, ua_h;
  double to_unit_areas;
};
IntegrationFrame integration_frame(const Integration& integ, int width, int height);

// The pattern of a single unit area: blue noise (Balzer et al. 2009
// capacity-constrained point sets, latinised; 8, 32 or 64 samples; a
// non-zero seed applies a symmetry and a toroidal shift) or stratified
// (multi-jittered, any count). Throws mpvg::Error for blue noise of another
// count.
std::vector<SampleOffset> sample_pattern(PatternKind kind, int n, uint32_t seed);
std::vector<SampleOffset> stratified_pattern(int n, uint32_t seed);

// Box filter weight of a sample of the pixel's own unit area: 1/n each.
MPVG_HD_INLINE float box_weight(int n) { return 1.0f / static_cast<float>(n); }

// Fixed-point accumulation: 2^44 steps per unit; sums of up to 16 unit
// areas of magnitude below 2^15 fit in an int64 with room to spare.
constexpr double kFixedScale = 17592186044416.0;
// Rounded to nearest, ties to even (rint in the default rounding mode). On
// the x86 host one cvtsd2si, which rounds by that mode: without SSE4.1 rint
// is a sequence of its own, and to_fixed runs K x K x 4 times for every
// unit area. The same integer either way.
MPVG_HD_INLINE long long to_fixed(float v) {
#if defined(__SSE2__) && defined(__x86_64__) && !defined(__CUDA_ARCH__)
  return _mm_cvtsd_si64(_mm_set_sd(static_cast<double>(v) * kFixedScale));
#else
  return static_cast<long long>(rint(static_cast<double>(v) * kFixedScale));
#endif
}

// The weighted sum one unit area sends to one pixel: sum_i w[i stride]
// col[i] (4 channels per sample), in this order on both backends. A uniform
// cell's samples all have the colour flat: flat times the weights' sum.
MPVG_HD_INLINE void integrate_unit_area(const float* w, int stride, float wsum, int n, bool uniform,
                                        const float* flat, const float* col, float out[4]) {
  if (uniform) {
    for (int c = 0; c < 4; c++) out[c] = flat[c] * wsum;
    return;
  }
  for (int c = 0; c < 4; c++) out[c] = 0.0f;
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 4; c++) out[c] += w[i * stride] * col[i * 4 + c];
}

// integrate_unit_area for all T pixels a unit area reaches at once, with
// the same operations per pixel (a loop order the CPU vectorises):
// out[t * 4 + c] = sum_i w[i T + t] col[i * 4 + c].
// Four pixels at a time, their sums held over the whole loop of samples
// (16 running sums: in registers, where the sample-major order loaded and
// stored every pixel's sums for every sample; the same additions in the
// same order for each pixel).
inline void integrate_unit_area_all(const float* __restrict__ w, int T, int n, const float* __restrict__ col,
                                    float* __restrict__ out) {
  int t0 = 0;
  for (; t0 + 4 <= T; t0 += 4) {
    float a[4][4] = {};
    for (int i = 0; i < n; i++) {
      const float* wi = w + i * T + t0;
      const float* ci = col + i * 4;
      for (int k = 0; k < 4; k++)
        for (int c = 0; c < 4; c++) a[k][c] += wi[k] * ci[c];
    }
    for (int k = 0; k < 4; k++)
      for (int c = 0; c < 4; c++) out[(t0 + k) * 4 + c] = a[k][c];
  }
  for (int t = t0; t < T; t++) {
    float a[4] = {};
    for (int i = 0; i < n; i++)
      for (int c = 0; c < 4; c++) a[c] += w[i * T + t] * col[i * 4 + c];
    for (int c = 0; c < 4; c++) out[t * 4 + c] = a[c];
  }
}

MPVG_HD_INLINE float fixed_to_float(long long v, double norm) {
  return static_cast<float>(static_cast<double>(v) / norm);
}

// The recursive prefilter that turns B-spline weights into cardinal ones
// (Unser et al. 1991): the inverse of the sampled B-spline [1/6, 4/6, 1/6]
// along a line, as a causal and an anticausal first-order recursion with pole
// z = sqrt(3) - 2, gain 6, and mirror boundaries:
//
//   causal      c[k] = x[k] + z c[k-1],        c[-1] = sum_{k>=1} z^(k-1) x[k]
//   anticausal  a[k] = z (a[k+1] - c[k]),      a[n-1] = z / (z^2 - 1) (c[n-1] + z c[n-2])
//   output      y[k] = 6 a[k]
//
// Both executors cut each line into kPrefilterBlocks blocks, run the
// recursions on every block from a zero carry, propagate the carries from
// block to block and correct each block by its carry times powers of z
// (Nehab et al. 2011, first-order case): the GPU runs the blocks in
// parallel, the CPU one after another, with the same operations in the same
// order, so that both round alike and give the same bits. (The plain
// recursion along the line rounds differently: images then differed by one
// level in 8 bits here and there; issue 32.) On a padded image the
// boundaries are kCardinalPad pixels away from anything visible.
constexpr float kCardinalPole = -0.267949192431122706f;  // sqrt(3) - 2
constexpr float kCardinalGain = 6.0f;
constexpr int kCardinalHorizon = 13;  // |z|^13 < 1e-7
constexpr int kPrefilterBlocks = 64;

// c[-1] of a line of n >= 2 samples (x[k] at data[k * stride]), truncated
// at the horizon.
MPVG_HD_INLINE float cardinal_causal_carry(const float* data, int n, int stride) {
  const float z = kCardinalPole;
  const int horizon = n < kCardinalHorizon ? n : kCardinalHorizon;
  float sum = 0.0f, zk = 1.0f;
  for (int k = 1; k < horizon; k++) {
    sum += zk * data[k * stride];
    zk *= z;
  }
  return sum;
}

// The prefilter's values: one channel (float, the CPU) or four (float4,
// the GPU), each channel with the same operations, rounded twice (the
// build keeps compilers from contracting a x + y).
MPVG_HD_INLINE float lane_axpy(float a, float x, float y) { return a * x + y; }
MPVG_HD_INLINE float lane_scale(float a, float x) { return a * x; }
MPVG_HD_INLINE float lane_sub(float x, float y) { return x - y; }
// The CPU's four channels of one pixel, stepped together (SSE on x86):
// each channel's operations are the float ones above.
struct Lane4 {
  float v[4];
};
inline Lane4 lane_axpy(float a, Lane4 x, Lane4 y) {
  Lane4 r;
  for (int c = 0; c < 4; c++) r.v[c] = a * x.v[c] + y.v[c];
  return r;
}
inline Lane4 lane_scale(float a, Lane4 x) {
  Lane4 r;
  for (int c = 0; c < 4; c++) r.v[c] = a * x.v[c];
  return r;
}
inline Lane4 lane_sub(Lane4 x, Lane4 y) {
  Lane4 r;
  for (int c = 0; c < 4; c++) r.v[c] = x.v[c] - y.v[c];
  return r;
}
#if defined(__CUDACC__)
MPVG_HD_INLINE float4 lane_axpy(float a, float4 x, float4 y) {
  return make_float4(a * x.x + y.x, a * x.y + y.y, a * x.z + y.z, a * x.w + y.w);
}
MPVG_HD_INLINE float4 lane_scale(float a, float4 x) { return make_float4(a * x.x, a * x.y, a * x.z, a * x.w); }
MPVG_HD_INLINE float4 lane_sub(float4 x, float4 y) { return make_float4(x.x - y.x, x.y - y.y, x.z - y.z, x.w - y.w); }
#endif

// a[n-1] from the causal outputs c[n-1], c[n-2].
template <class V>
MPVG_HD_INLINE V cardinal_anticausal_start(V c_last, V c_before) {
  const float z = kCardinalPole;
  return lane_scale(z / (z * z - 1.0f), lane_axpy(z, c_before, c_last));
}

// Block j of a line of n samples: [start, end), and z^(end - start).
struct PrefilterBlock {
  int start, end;
  float zpow;
};
MPVG_HD_INLINE PrefilterBlock prefilter_block(int n, int j) {
  const int L = (n + kPrefilterBlocks - 1) / kPrefilterBlocks;
  PrefilterBlock b;
  b.start = j * L < n ? j * L : n;
  b.end = b.start + L < n ? b.start + L : n;
  b.zpow = 1.0f;
  for (int k = b.start; k < b.end; k++) b.zpow *= kCardinalPole;
  return b;
}

// 1. The causal recursion over a block from a zero carry (d[k * s] is
// sample k); returns its last value.
template <class V>
MPVG_HD_INLINE V prefilter_causal_block(V* d, size_t s, PrefilterBlock b, V y) {
  for (int k = b.start; k < b.end; k++) d[k * s] = y = lane_axpy(kCardinalPole, y, d[k * s]);
  return y;
}

// 2. and 5. The carries from block to block: carry(j) holds block j's own
// last value (causal) or first value (anticausal) and becomes the carry
// into it; `in` is the line's boundary carry. Causal carries go up from
// block 0, anticausal ones down from the last block.
template <class V, class Carry, class Block>
MPVG_HD_INLINE void prefilter_carries(Carry carry, Block block, V in, bool anticausal) {
  for (int i = 0; i < kPrefilterBlocks; i++) {
    const int j = anticausal ? kPrefilterBlocks - 1 - i : i;
    const V own = carry(j);
    carry(j) = in;
    in = lane_axpy(block(j).zpow, in, own);
  }
}

// 3. c[k] += z^(k - start + 1) carry.
template <class V>
MPVG_HD_INLINE void prefilter_causal_correct(V* d, size_t s, PrefilterBlock b, V f) {
  for (int k = b.start; k < b.end; k++) {
    f = lane_scale(kCardinalPole, f);
    d[k * s] = lane_axpy(1.0f, f, d[k * s]);
  }
}

// 4. The anticausal recursion over a block from a zero carry, or, for the
// block ending the line (tail), from the boundary value a (read before any
// block changed the causal outputs); returns its first value.
template <class V>
MPVG_HD_INLINE V prefilter_anticausal_block(V* d, size_t s, PrefilterBlock b, bool tail, V a) {
  int k = b.end - 1;
  if (tail) d[size_t(k--) * s] = a;
  for (; k >= b.start; k--) d[k * s] = a = lane_scale(kCardinalPole, lane_sub(a, d[k * s]));
  return a;
}

// 6. a[k] += z^(end - k) carry, and the gain.
template <class V>
MPVG_HD_INLINE void prefilter_anticausal_correct(V* d, size_t s, PrefilterBlock b, V f) {
  for (int k = b.end - 1; k >= b.start; k--) {
    f = lane_scale(kCardinalPole, f);
    d[k * s] = lane_scale(kCardinalGain, lane_axpy(1.0f, f, d[k * s]));
  }
}

// The whole prefilter on one line of n samples of 4 channels, `stride`
// floats apart (a multiple of 4): the blocks one after another, the four
// channels of a pixel together (the CPU's executor).
inline void cardinal_prefilter_line(float* data, int n, int stride) {
  if (n < 2) return;
  PrefilterBlock blocks[kPrefilterBlocks];
  for (int j = 0; j < kPrefilterBlocks; j++) blocks[j] = prefilter_block(n, j);
  static_assert(sizeof(Lane4) == 4 * sizeof(float), "a pixel's four channels");
  Lane4* d = reinterpret_cast<Lane4*>(data);
  const size_t s = static_cast<size_t>(stride / 4);
  Lane4 carry[kPrefilterBlocks];
  auto carry_of = [&](int j) -> Lane4& { return carry[j]; };
  auto block_of = [&](int j) { return blocks[j]; };
  const Lane4 zero{{0.0f, 0.0f, 0.0f, 0.0f}};
  Lane4 c0;
  for (int c = 0; c < 4; c++) c0.v[c] = cardinal_causal_carry(data + c, n, stride);
  for (int j = 0; j < kPrefilterBlocks; j++) carry[j] = prefilter_causal_block(d, s, blocks[j], zero);
  prefilter_carries(carry_of, block_of, c0, false);
  for (int j = 0; j < kPrefilterBlocks; j++) prefilter_causal_correct(d, s, blocks[j], carry[j]);
  const Lane4 a0 = cardinal_anticausal_start(d[(n - 1) * s], d[(n - 2) * s]);
  for (int j = 0; j < kPrefilterBlocks; j++) {
    const bool tail = blocks[j].end > blocks[j].start && blocks[j].end == n;
    carry[j] = prefilter_anticausal_block(d, s, blocks[j], tail, tail ? a0 : zero);
  }
  prefilter_carries(carry_of, block_of, zero, true);
  for (int j = 0; j < kPrefilterBlocks; j++) prefilter_anticausal_correct(d, s, blocks[j], carry[j]);
}

// A premultiplied pixel made valid after filters with negative lobes:
// alpha in [0, 1], colour in [0, alpha].
MPVG_HD_INLINE void clamp_premultiplied(float* p) {
  p[3] = fminf(1.0f, fmaxf(0.0f, p[3]));
  for (int c = 0; c < 3; c++) p[c] = fminf(p[3], fmaxf(0.0f, p[c]));
}

}  // namespace mpvg
