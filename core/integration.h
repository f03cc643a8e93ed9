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
// noise uses the tile of K x K unit areas (core/blue_noise_tables.inc) whose
// unit areas are the classes: every pixel's support then holds the whole
// tile, K^2 m samples that are blue noise as one set; the seed applies a
// symmetry of the tile and a shift within unit areas. Stratified patterns,
// and the variant taking one pattern, give class (cx, cy) the pattern shifted
// by (cy, cx) / (K m). Throws mpvg::Error for blue noise of other than 8,
// 32 or 64 samples.
//
// odd_support: a filter of even support K integrates over K + 1 unit areas
// per side instead (the kernel is 0 on the extra ring), so that unit areas
// are pixels again: what aliased paths need (core/sampling.h). Blue-noise
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
MPVG_HD_INLINE long long to_fixed(float v) { return static_cast<long long>(rint(static_cast<double>(v) * kFixedScale)); }

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
inline void integrate_unit_area_all(const float* __restrict__ w, int T, int n, const float* __restrict__ col,
                                    float* __restrict__ out) {
  for (int t = 0; t < T * 4; t++) out[t] = 0.0f;
  for (int i = 0; i < n; i++) {
    const float* wi = w + i * T;
    const float c0 = col[i * 4], c1 = col[i * 4 + 1], c2 = col[i * 4 + 2], c3 = col[i * 4 + 3];
    for (int t = 0; t < T; t++) {
      const float wt = wi[t];
      out[t * 4] += wt * c0;
      out[t * 4 + 1] += wt * c1;
      out[t * 4 + 2] += wt * c2;
      out[t * 4 + 3] += wt * c3;
    }
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
// The CPU runs the recursions along each line; the GPU cuts lines into
// blocks, runs them on every block from a zero carry, propagates the carries
// between blocks and corrects each block by the carry times powers of z
// (Nehab et al. 2011). Both use the pieces below. On a padded image the
// boundaries are kCardinalPad pixels away from anything visible.
constexpr float kCardinalPole = -0.267949192431122706f;  // sqrt(3) - 2
constexpr float kCardinalGain = 6.0f;
constexpr int kCardinalHorizon = 13;  // |z|^13 < 1e-7

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

// a[n-1] from the causal outputs c[n-1], c[n-2].
MPVG_HD_INLINE float cardinal_anticausal_start(float c_last, float c_before) {
  const float z = kCardinalPole;
  return (z / (z * z - 1.0f)) * (c_last + z * c_before);
}

// The whole prefilter on one line of n samples of 4 channels, `stride`
// floats apart (the CPU's executor).
MPVG_HD_INLINE void cardinal_prefilter_line(float* data, int n, int stride) {
  const float z = kCardinalPole;
  if (n < 2) return;
  for (int c = 0; c < 4; c++) {
    float* d = data + c;
    float carry = cardinal_causal_carry(d, n, stride);
    for (int k = 0; k < n; k++) carry = d[k * stride] += z * carry;
    float next = cardinal_anticausal_start(d[(n - 1) * stride], d[(n - 2) * stride]);
    d[(n - 1) * stride] = kCardinalGain * next;
    for (int k = n - 2; k >= 0; k--) {
      next = z * (next - d[k * stride]);
      d[k * stride] = kCardinalGain * next;
    }
  }
}

// A premultiplied pixel made valid after filters with negative lobes:
// alpha in [0, 1], colour in [0, alpha].
MPVG_HD_INLINE void clamp_premultiplied(float* p) {
  p[3] = fminf(1.0f, fmaxf(0.0f, p[3]));
  for (int c = 0; c < 3; c++) p[c] = fminf(p[3], fmaxf(0.0f, p[c]));
}

}  // namespace mpvg
