// Filter primitives per pixel (Filter Effects Module Level 1, §9-§15),
// written once for both executors: cpu/filter.cpp runs them in loops,
// the CUDA executor in kernels. A primitive works on layers: premultiplied
// RGBA floats over the filter layer's pixels (frame/filter_layers.h), in
// the primitive's colour space (linearRGB or sRGB, premultiplied there).
//
// FilterOp is a primitive of core/filters/filter.h resolved to the layer's pixels:
// lengths scaled by the filter's transform to pixels, its subregion as a
// pixel box, colours premultiplied in its space, transfer tables and
// kernels as ranges of one float array. Pixels outside an op's box are
// transparent black in its result.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/paint/blend.h"
#include "core/hd.h"
#include "core/hd_math.h"
#include "core/paint/paint.h"
#include "core/output/srgb.h"

namespace mpvg {

enum FilterOpKind : uint32_t {  // core/filters/filter.h's FilterKind, same order
  FOP_BLEND = 0,
  FOP_COLOR_MATRIX,
  FOP_COMPONENT_TRANSFER,
  FOP_COMPOSITE,
  FOP_CONVOLVE_MATRIX,
  FOP_DIFFUSE_LIGHTING,
  FOP_DISPLACEMENT_MAP,
  FOP_DROP_SHADOW,
  FOP_FLOOD,
  FOP_GAUSSIAN_BLUR,
  FOP_IMAGE,
  FOP_MERGE,
  FOP_MORPHOLOGY,
  FOP_OFFSET,
  FOP_SPECULAR_LIGHTING,
  FOP_TILE,
  FOP_TURBULENCE,
};

enum FilterEdge : uint32_t { FEDGE_NONE = 0, FEDGE_DUPLICATE, FEDGE_WRAP, FEDGE_MIRROR };
enum FilterCompositeOp : uint32_t { FCOMP_OVER = 0, FCOMP_IN, FCOMP_OUT, FCOMP_ATOP, FCOMP_XOR, FCOMP_ARITHMETIC,
                                    FCOMP_LIGHTER };
enum FilterTransfer : uint32_t { FTRANSFER_IDENTITY = 0, FTRANSFER_TABLE, FTRANSFER_DISCRETE, FTRANSFER_LINEAR,
                                 FTRANSFER_GAMMA };

struct FilterBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1) in layer pixels
};

struct FilterOp {
  uint32_t kind = FOP_FLOOD;
  int32_t in = -1, in2 = -1;  // results, or core/filters/filter.h's FilterInput
  FilterBox box;
  uint32_t linear = 1;  // colour space: linearRGB (1) or sRGB (0)
  float color[4] = {0, 0, 0, 0};  // Flood, DropShadow: premultiplied in the op's space
  float dx = 0, dy = 0;           // Offset, DropShadow: whole pixels
  float std_x = 0, std_y = 0;     // GaussianBlur, DropShadow: pixels
  uint32_t edge = FEDGE_NONE;
  uint32_t mode = 0;              // Blend: BlendModeCode; Composite: FilterCompositeOp
  float k[4] = {0, 0, 0, 0};      // Composite arithmetic
  float matrix[20] = {1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0};
  // ComponentTransfer: per channel its type, table range in the op array,
  // and slope / intercept or amplitude / exponent / offset.
  uint32_t func[4] = {0, 0, 0, 0};
  uint32_t table_begin[4] = {0, 0, 0, 0}, table_size[4] = {0, 0, 0, 0};
  float fparam[4][3] = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  int rx = 0, ry = 0;             // Morphology: half the window's sides in pixels
  uint32_t dilate = 0;
  FilterBox tile;                 // Tile: the input's box
  uint32_t inputs_begin = 0, inputs_count = 0;  // Merge: nodes in the layer's input array, bottom first
  // Turbulence: layer pixels to the filter's user space (a b c d e f), the
  // base frequencies, octaves, the stitching tile (user space) and the
  // lattice in the layer's noise array (turbulence_init).
  double to_user[6] = {1, 0, 0, 1, 0, 0};
  double freq_x = 0, freq_y = 0;
  int octaves = 1;
  uint32_t fractal = 0, stitch = 0;
  double tile_user[4] = {0, 0, 0, 0};
  uint32_t noise_begin = 0;
  // ConvolveMatrix: order, kernel range in the layer's tables (as written,
  // row-major), divisor, bias, target, preserve_alpha.
  int order_x = 3, order_y = 3, target_x = 1, target_y = 1;
  uint32_t kernel_begin = 0, preserve_alpha = 0;
  float divisor = 1, bias = 0;
  // DisplacementMap: scale along x and y in pixels, channels 0..3.
  float scale_x = 0, scale_y = 0;
  uint32_t x_channel = 3, y_channel = 3;
  // Lighting: surface scale, constants, exponent; the light in layer
  // pixels (z scaled like lengths), its colour (straight, op's space).
  float surface_scale = 1, kd = 1, ks = 1, specular_exponent = 1;
  uint32_t light = 0;  // 0 none, 1 distant, 2 point, 3 spot
  float light_dir[3] = {0, 0, 1};        // Distant: unit vector to the light
  float light_pos[3] = {0, 0, 0}, light_at[3] = {0, 0, 0};
  float spot_exponent = 1, cone_cos = -2;  // cone_cos < -1: no cone
  // Image: index of the prepared layer image.
  uint32_t image = 0;
};

// ------------------------------------------------------------ colour

// A premultiplied pixel from one colour space to the other.
MPVG_HD_INLINE Rgba4 filter_convert(Rgba4 p, bool from_linear, bool to_linear) {
  if (from_linear == to_linear || !(p.a > 0.0f)) return p;
  float c[3] = {p.r / p.a, p.g / p.a, p.b / p.a};
  for (int i = 0; i < 3; i++) {
    float v = c[i] < 0.0f ? 0.0f : (c[i] > 1.0f ? 1.0f : c[i]);
    c[i] = (to_linear ? srgb_to_linear(v) : linear_to_srgb(v)) * p.a;
  }
  return Rgba4{c[0], c[1], c[2], p.a};
}

MPVG_HD_INLINE float filter_clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }

// A premultiplied pixel made valid: alpha in [0, 1], colour in [0, alpha].
MPVG_HD_INLINE Rgba4 filter_valid(Rgba4 p) {
  const float a = filter_clamp01(p.a);
  auto c = [a](float v) { return v < 0.0f ? 0.0f : (v > a ? a : v); };
  return Rgba4{c(p.r), c(p.g), c(p.b), a};
}

// ------------------------------------------------------------ pointwise

// feComposite (§15.12) of a (in) with b (in2), premultiplied.
MPVG_HD_INLINE Rgba4 filter_composite(const FilterOp& op, Rgba4 a, Rgba4 b) {
  float fa = 0, fb = 0;  // Porter-Duff: a * fa + b * fb
  switch (op.mode) {
    case FCOMP_OVER: fa = 1; fb = 1 - a.a; break;
    case FCOMP_IN: fa = b.a; fb = 0; break;
    case FCOMP_OUT: fa = 1 - b.a; fb = 0; break;
    case FCOMP_ATOP: fa = b.a; fb = 1 - a.a; break;
    case FCOMP_XOR: fa = 1 - b.a; fb = 1 - a.a; break;
    case FCOMP_LIGHTER: fa = 1; fb = 1; break;
    default: {  // arithmetic: k1 i1 i2 + k2 i1 + k3 i2 + k4, per premultiplied channel
      auto f = [&op](float i1, float i2) { return op.k[0] * i1 * i2 + op.k[1] * i1 + op.k[2] * i2 + op.k[3]; };
      return filter_valid(Rgba4{f(a.r, b.r), f(a.g, b.g), f(a.b, b.b), f(a.a, b.a)});
    }
  }
  return filter_valid(Rgba4{a.r * fa + b.r * fb, a.g * fa + b.g * fb, a.b * fa + b.b * fb, a.a * fa + b.a * fb});
}

// feColorMatrix (§15.10) on the straight colour.
MPVG_HD_INLINE Rgba4 filter_color_matrix(const FilterOp& op, Rgba4 p) {
  const float in[4] = {p.a > 0 ? p.r / p.a : 0, p.a > 0 ? p.g / p.a : 0, p.a > 0 ? p.b / p.a : 0, p.a};
  float out[4];
  for (int r = 0; r < 4; r++) {
    const float* m = op.matrix + 5 * r;
    out[r] = filter_clamp01(m[0] * in[0] + m[1] * in[1] + m[2] * in[2] + m[3] * in[3] + m[4]);
  }
  return Rgba4{out[0] * out[3], out[1] * out[3], out[2] * out[3], out[3]};
}

// One channel of feComponentTransfer (§15.11).
MPVG_HD_INLINE float filter_transfer(const FilterOp& op, int ch, float c, const float* tables) {
  const float* v = tables + op.table_begin[ch];
  const uint32_t n = op.table_size[ch];
  switch (op.func[ch]) {
    case FTRANSFER_TABLE: {
      if (n == 0) return c;
      if (n == 1) return v[0];
      const float s = c * static_cast<float>(n - 1);
      uint32_t k = s <= 0.0f ? 0 : static_cast<uint32_t>(s);
      if (k >= n - 1) k = n - 2;
      return v[k] + (s - static_cast<float>(k)) * (v[k + 1] - v[k]);
    }
    case FTRANSFER_DISCRETE: {
      if (n == 0) return c;
      const float s = c * static_cast<float>(n);
      uint32_t k = s <= 0.0f ? 0 : static_cast<uint32_t>(s);
      if (k >= n) k = n - 1;
      return v[k];
    }
    case FTRANSFER_LINEAR: return op.fparam[ch][0] * c + op.fparam[ch][1];
    case FTRANSFER_GAMMA: return op.fparam[ch][0] * hd_powf(c, op.fparam[ch][1]) + op.fparam[ch][2];
    default: return c;
  }
}

MPVG_HD_INLINE Rgba4 filter_component_transfer(const FilterOp& op, Rgba4 p, const float* tables) {
  const float in[4] = {p.a > 0 ? p.r / p.a : 0, p.a > 0 ? p.g / p.a : 0, p.a > 0 ? p.b / p.a : 0, p.a};
  float out[4];
  for (int c = 0; c < 4; c++) out[c] = filter_clamp01(filter_transfer(op, c, filter_clamp01(in[c]), tables));
  return Rgba4{out[0] * out[3], out[1] * out[3], out[2] * out[3], out[3]};
}

// feBlend (§15.9): in over in2 with the mode (core/paint/blend.h).
MPVG_HD_INLINE Rgba4 filter_blend(const FilterOp& op, Rgba4 in, Rgba4 in2) {
  return filter_valid(blend_over(op.mode, in2, in));
}

// ------------------------------------------------------------ neighbourhoods

// A layer pixel under an edge mode; transparent outside with `none`.
MPVG_HD_INLINE int filter_edge_index(int i, int lo, int hi, uint32_t edge) {
  const int n = hi - lo;
  if (n <= 0) return -1;
  if (i >= lo && i < hi) return i;
  switch (edge) {
    case FEDGE_DUPLICATE: return i < lo ? lo : hi - 1;
    case FEDGE_WRAP: {
      int m = (i - lo) % n;
      return lo + (m < 0 ? m + n : m);
    }
    case FEDGE_MIRROR: {
      int m = (i - lo) % (2 * n);
      if (m < 0) m += 2 * n;
      return lo + (m < n ? m : 2 * n - 1 - m);
    }
    default: return -1;
  }
}

MPVG_HD_INLINE Rgba4 filter_read(const float* layer, int width, int x, int y) {
  const float* p = layer + 4 * (static_cast<size_t>(y) * width + x);
  return Rgba4{p[0], p[1], p[2], p[3]};
}

// Box sums in fixed point, 2^40 steps a unit: integer sums are exact, so a
// window summed pixel by pixel (the GPU's thread a pixel) and a running sum
// along the line (the CPU's, O(1) a pixel) give the same bits.
constexpr double kBoxFixed = 1099511627776.0;
MPVG_HD_INLINE long long box_fixed(float v) { return static_cast<long long>(rint(static_cast<double>(v) * kBoxFixed)); }
MPVG_HD_INLINE float box_mean(long long sum, int size) {
  return static_cast<float>(static_cast<double>(sum) / kBoxFixed / static_cast<double>(size));
}

// One pass of a box blur of `size` pixels along x (horizontal) or y, whose
// window starts `lead` pixels before the output pixel: the spec's three
// box blurs approximating a Gaussian (§15.17) for d >= 2. Reads within box
// (the input's extent; outside it, transparent or by the edge mode).
MPVG_HD_INLINE Rgba4 filter_box_pass(const float* in, int width, const FilterBox& box, int x, int y, bool horizontal,
                                     int size, int lead, uint32_t edge) {
  long long acc[4] = {0, 0, 0, 0};
  for (int k = 0; k < size; k++) {
    int sx = x, sy = y;
    if (horizontal) sx = filter_edge_index(x - lead + k, box.x0, box.x1, edge);
    else sy = filter_edge_index(y - lead + k, box.y0, box.y1, edge);
    if (sx < 0 || sy < 0) continue;
    const Rgba4 p = filter_read(in, width, sx, sy);
    acc[0] += box_fixed(p.r);
    acc[1] += box_fixed(p.g);
    acc[2] += box_fixed(p.b);
    acc[3] += box_fixed(p.a);
  }
  return Rgba4{box_mean(acc[0], size), box_mean(acc[1], size), box_mean(acc[2], size), box_mean(acc[3], size)};
}

// One pass of an exact Gaussian (std dev < 2 pixels), radius ceil(3 std),
// weights normalised over the window.
MPVG_HD_INLINE Rgba4 filter_gauss_pass(const float* in, int width, const FilterBox& box, int x, int y,
                                       bool horizontal, float std_dev, uint32_t edge) {
  const int r = static_cast<int>(ceilf(3.0f * std_dev));
  Rgba4 acc{0, 0, 0, 0};
  float wsum = 0;
  for (int k = -r; k <= r; k++) {
    const float w = hd_expf(-0.5f * static_cast<float>(k * k) / (std_dev * std_dev));
    wsum += w;
    int sx = x, sy = y;
    if (horizontal) sx = filter_edge_index(x + k, box.x0, box.x1, edge);
    else sy = filter_edge_index(y + k, box.y0, box.y1, edge);
    if (sx < 0 || sy < 0) continue;
    const Rgba4 p = filter_read(in, width, sx, sy);
    acc.r += w * p.r;
    acc.g += w * p.g;
    acc.b += w * p.b;
    acc.a += w * p.a;
  }
  const float s = 1.0f / wsum;
  return Rgba4{acc.r * s, acc.g * s, acc.b * s, acc.a * s};
}

// The box sizes of the three passes for standard deviation s (§15.17):
// d = floor(s * 3 sqrt(2 pi) / 4 + 0.5); d odd: three boxes of d centred;
// d even: two of d, the first's window one pixel to the left, the second
// to the right, then one of d + 1 centred. lead[i]: pixels before the
// output pixel in pass i's window.
MPVG_HD_INLINE int filter_box_sizes(float s, int size[3], int lead[3]) {
  const int d = static_cast<int>(floorf(s * 3.0f * sqrtf(2.0f * 3.14159265358979f) / 4.0f + 0.5f));
  if (d % 2 == 1) {
    for (int i = 0; i < 3; i++) {
      size[i] = d;
      lead[i] = d / 2;
    }
  } else {
    size[0] = size[1] = d;
    lead[0] = d / 2;
    lead[1] = d / 2 - 1;
    size[2] = d + 1;
    lead[2] = d / 2;
  }
  return d;
}

// The passes of a separable blur by standard deviations sx, sy (pixels):
// per axis with s > 0, three box passes (d >= 2) or one exact Gaussian,
// the edge mode on its first pass (later ones read the whole layer).
struct FilterBlurPass {
  bool horizontal, boxes;
  int size, lead;
  float s;
  uint32_t edge;
};
MPVG_HD_INLINE int filter_blur_passes(float sx, float sy, uint32_t edge, FilterBlurPass out[6]) {
  int n = 0;
  for (int axis = 0; axis < 2; axis++) {
    const float s = axis == 0 ? sx : sy;
    if (!(s > 0.0f)) continue;
    int size[3], lead[3];
    const bool boxes = s >= 2.0f && filter_box_sizes(s, size, lead) > 0;
    for (int pass = 0; pass < (boxes ? 3 : 1); pass++)
      out[n++] = FilterBlurPass{axis == 0, boxes, boxes ? size[pass] : 0, boxes ? lead[pass] : 0, s,
                                pass == 0 ? edge : FEDGE_NONE};
  }
  return n;
}

// feMorphology (§15.20): the per-channel minimum (erode) or maximum
// (dilate) of the premultiplied pixels over the spec's 2 rx x 2 ry window,
// [x - rx, x + rx - 1] (its target the pixel at half the width, as
// resvg has it), transparent black outside the input's box; a radius of 0
// leaves that axis alone.
MPVG_HD_INLINE Rgba4 filter_morphology(const FilterOp& op, const float* in, int width, const FilterBox& box, int x,
                                       int y) {
  const float init = op.dilate ? 0.0f : 1.0f;
  float m[4] = {init, init, init, init};
  const int y1 = op.ry > 0 ? y + op.ry - 1 : y, x1 = op.rx > 0 ? x + op.rx - 1 : x;
  for (int j = y - op.ry; j <= y1; j++)
    for (int i = x - op.rx; i <= x1; i++) {
      float p[4] = {0, 0, 0, 0};
      if (i >= box.x0 && i < box.x1 && j >= box.y0 && j < box.y1) {
        const Rgba4 q = filter_read(in, width, i, j);
        p[0] = q.r, p[1] = q.g, p[2] = q.b, p[3] = q.a;
      }
      for (int c = 0; c < 4; c++) m[c] = op.dilate ? (p[c] > m[c] ? p[c] : m[c]) : (p[c] < m[c] ? p[c] : m[c]);
    }
  return Rgba4{m[0], m[1], m[2], m[3]};
}

// ------------------------------------------------------------ feConvolveMatrix

// §15.13: the kernel rotated by 180 degrees over the input (edge mode on
// its box), divided, biased; with preserveAlpha on straight colours and
// the input's alpha kept. Clamping as resvg and Chromium do.
MPVG_HD_INLINE Rgba4 filter_convolve(const FilterOp& op, const float* in, int width, const FilterBox& box,
                                     const float* kernel, int x, int y) {
  float sum[4] = {0, 0, 0, 0};
  const int n = op.order_x * op.order_y;
  for (int i = 0; i < op.order_y; i++)
    for (int j = 0; j < op.order_x; j++) {
      const int sx = filter_edge_index(x - op.target_x + j, box.x0, box.x1, op.edge);
      const int sy = filter_edge_index(y - op.target_y + i, box.y0, box.y1, op.edge);
      if (sx < 0 || sy < 0) continue;
      Rgba4 p = filter_read(in, width, sx, sy);
      if (op.preserve_alpha && p.a > 0) p = Rgba4{p.r / p.a, p.g / p.a, p.b / p.a, p.a};
      const float k = kernel[n - 1 - (i * op.order_x + j)];
      sum[0] += k * p.r, sum[1] += k * p.g, sum[2] += k * p.b, sum[3] += k * p.a;
    }
  float a;
  if (op.preserve_alpha) {
    const bool inside = x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1;
    a = inside ? filter_read(in, width, x, y).a : 0.0f;
  } else {
    a = sum[3] / op.divisor + op.bias;
  }
  const float ba = filter_clamp01(a);
  float c[3];
  for (int i = 0; i < 3; i++) {
    const float v = sum[i] / op.divisor + op.bias * a;
    c[i] = op.preserve_alpha ? filter_clamp01(v) * ba : (v < 0 ? 0 : (v > ba ? ba : v));
  }
  return Rgba4{c[0], c[1], c[2], ba};
}

// ------------------------------------------------------------ feDisplacementMap

// §15.15: in displaced by in2's channels (straight values), nearest pixel.
MPVG_HD_INLINE Rgba4 filter_displace(const FilterOp& op, const float* in, const FilterBox& in_box,
                                     const float* map, const FilterBox& map_box, int width, int x, int y) {
  float m[4] = {0, 0, 0, 0};
  if (x >= map_box.x0 && x < map_box.x1 && y >= map_box.y0 && y < map_box.y1) {
    const Rgba4 p = filter_read(map, width, x, y);
    m[3] = p.a;
    if (p.a > 0) m[0] = p.r / p.a, m[1] = p.g / p.a, m[2] = p.b / p.a;
  }
  const float ox = op.scale_x * (m[op.x_channel & 3] - 0.5f), oy = op.scale_y * (m[op.y_channel & 3] - 0.5f);
  const int sx = static_cast<int>(floorf(static_cast<float>(x) + ox + 0.5f));
  const int sy = static_cast<int>(floorf(static_cast<float>(y) + oy + 0.5f));
  if (sx < in_box.x0 || sx >= in_box.x1 || sy < in_box.y0 || sy >= in_box.y1) return Rgba4{0, 0, 0, 0};
  return filter_read(in, width, sx, sy);
}

// ------------------------------------------------------------ lighting

// The surface normal's x and y at (x, y) from the alpha of the input
// (§15.14's Sobel kernels): the difference of the columns (rows) beside
// the pixel, weighted 1 2 1 over the rows (columns) inside the box; at
// the box's edges the pixel's own column stands in for the missing one.
// Every kernel of the spec's table is 2 / (distance x weights) of that.
MPVG_HD_INLINE void filter_normal(const float* in, int width, const FilterBox& box, float surface, int x, int y,
                                  float& nx, float& ny) {
  auto A = [&](int i, int j) { return filter_read(in, width, i, j).a; };
  const int xl = x > box.x0 ? x - 1 : x, xr = x < box.x1 - 1 ? x + 1 : x;
  const int yt = y > box.y0 ? y - 1 : y, yb = y < box.y1 - 1 ? y + 1 : y;
  float sx = 0, wx = 0, sy = 0, wy = 0;
  for (int d = -1; d <= 1; d++) {
    const float k = d == 0 ? 2.0f : 1.0f;
    if (y + d >= box.y0 && y + d < box.y1) sx += k * (A(xr, y + d) - A(xl, y + d)), wx += k;
    if (x + d >= box.x0 && x + d < box.x1) sy += k * (A(x + d, yb) - A(x + d, yt)), wy += k;
  }
  nx = xr > xl ? -surface * 2.0f * sx / (static_cast<float>(xr - xl) * wx) : 0.0f;
  ny = yb > yt ? -surface * 2.0f * sy / (static_cast<float>(yb - yt) * wy) : 0.0f;
}

// feDiffuseLighting / feSpecularLighting (§15.14, §15.22) at (x, y).
MPVG_HD_INLINE Rgba4 filter_lighting(const FilterOp& op, const float* in, int width, const FilterBox& box, int x,
                                     int y) {
  const bool inside = x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1;
  float nx = 0, ny = 0;
  if (inside) filter_normal(in, width, box, op.surface_scale, x, y, nx, ny);
  float n[3] = {nx, ny, 1.0f};
  const float nl = sqrtf(n[0] * n[0] + n[1] * n[1] + 1.0f);
  n[0] /= nl, n[1] /= nl, n[2] /= nl;
  const float z = inside ? op.surface_scale * filter_read(in, width, x, y).a : 0.0f;
  float L[3] = {op.light_dir[0], op.light_dir[1], op.light_dir[2]};
  float lc[3] = {op.color[0], op.color[1], op.color[2]};
  if (op.light >= 2) {
    L[0] = op.light_pos[0] - static_cast<float>(x), L[1] = op.light_pos[1] - static_cast<float>(y);
    L[2] = op.light_pos[2] - z;
    const float len = sqrtf(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
    if (len > 0) L[0] /= len, L[1] /= len, L[2] /= len;
    if (op.light == 3) {
      float S[3] = {op.light_at[0] - op.light_pos[0], op.light_at[1] - op.light_pos[1], op.light_at[2] - op.light_pos[2]};
      const float sl = sqrtf(S[0] * S[0] + S[1] * S[1] + S[2] * S[2]);
      if (sl > 0) S[0] /= sl, S[1] /= sl, S[2] /= sl;
      const float minus_ls = -(L[0] * S[0] + L[1] * S[1] + L[2] * S[2]);
      float f = 0;
      if (minus_ls > 0 && minus_ls >= op.cone_cos) f = hd_powf(minus_ls, op.spot_exponent);
      lc[0] *= f, lc[1] *= f, lc[2] *= f;
    }
  } else if (op.light == 0) {
    lc[0] = lc[1] = lc[2] = 0;
  }
  float k;
  float a = 1.0f;
  if (op.kind == FOP_DIFFUSE_LIGHTING) {
    k = op.kd * (n[0] * L[0] + n[1] * L[1] + n[2] * L[2]);
  } else {
    float h[3] = {L[0], L[1], L[2] + 1.0f};
    const float hl = sqrtf(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    const float nh = hl > 0 ? (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) / hl : 0.0f;
    k = op.ks * hd_powf(nh > 0 ? nh : 0.0f, op.specular_exponent);
  }
  float c[3];
  for (int i = 0; i < 3; i++) c[i] = filter_clamp01(k * lc[i]);
  if (op.kind == FOP_SPECULAR_LIGHTING) {
    a = c[0] > c[1] ? c[0] : c[1];
    a = a > c[2] ? a : c[2];
    return Rgba4{c[0], c[1], c[2], a};  // colour <= alpha: already premultiplied
  }
  return Rgba4{c[0], c[1], c[2], a};
}

// ------------------------------------------------------------ feTurbulence

// The spec's reference implementation (§15.23), in double as written
// there, so that both executors give its values: a lattice of
// kNoiseSize + kNoiseSize + 2 selectors then 4 x (2 kNoiseSize + 2) x 2
// gradients, set up from the seed on the host (turbulence_init).
constexpr int kNoiseSize = 0x100;
constexpr int kNoiseLattice = kNoiseSize + kNoiseSize + 2;
constexpr int kNoiseDoubles = kNoiseLattice + 4 * kNoiseLattice * 2;

inline long turbulence_random(long seed) {
  const long m = 2147483647, a = 16807, q = 127773, r = 2836;
  long result = a * (seed % q) - r * (seed / q);
  if (result <= 0) result += m;
  return result;
}

// out: kNoiseDoubles values.
inline void turbulence_init(long seed, double* out) {
  const long m = 2147483647;
  if (seed <= 0) seed = -(seed % (m - 1)) + 1;
  if (seed > m - 1) seed = m - 1;
  int lattice[kNoiseLattice];
  double* grad = out + kNoiseLattice;  // grad[(k * kNoiseLattice + i) * 2 + j]
  int i = 0;
  for (int k = 0; k < 4; k++) {
    for (i = 0; i < kNoiseSize; i++) {
      lattice[i] = i;
      for (int j = 0; j < 2; j++)
        grad[(k * kNoiseLattice + i) * 2 + j] =
            static_cast<double>(((seed = turbulence_random(seed)) % (kNoiseSize + kNoiseSize)) - kNoiseSize) / kNoiseSize;
      double* g = grad + (k * kNoiseLattice + i) * 2;
      const double s = std::sqrt(g[0] * g[0] + g[1] * g[1]);
      g[0] /= s;
      g[1] /= s;
    }
  }
  while (--i) {
    const int k = lattice[i];
    const int j = static_cast<int>((seed = turbulence_random(seed)) % kNoiseSize);
    lattice[i] = lattice[j];
    lattice[j] = k;
  }
  for (i = 0; i < kNoiseSize + 2; i++) {
    lattice[kNoiseSize + i] = lattice[i];
    for (int k = 0; k < 4; k++)
      for (int j = 0; j < 2; j++)
        grad[(k * kNoiseLattice + kNoiseSize + i) * 2 + j] = grad[(k * kNoiseLattice + i) * 2 + j];
  }
  for (i = 0; i < kNoiseLattice; i++) out[i] = lattice[i];
}

struct TurbulenceStitch {
  int width, height, wrap_x, wrap_y;
};

MPVG_HD_INLINE double turbulence_noise2(const double* noise, int channel, double vx, double vy,
                                        const TurbulenceStitch* st) {
  const int BM = 0xff, N = 0x1000;
  const double* lat = noise;
  const double* grad = noise + kNoiseLattice + channel * kNoiseLattice * 2;
  // Lattice points are masked after stitching (as Filter Effects 1 and
  // resvg have it; SVG 1.1's code masked first, which never stitches).
  double t = vx + N;
  long bx0 = static_cast<long>(t), bx1 = bx0 + 1;
  const double rx0 = t - static_cast<long>(t), rx1 = rx0 - 1.0;
  t = vy + N;
  long by0 = static_cast<long>(t), by1 = by0 + 1;
  const double ry0 = t - static_cast<long>(t), ry1 = ry0 - 1.0;
  if (st) {
    if (bx0 >= st->wrap_x) bx0 -= st->width;
    if (bx1 >= st->wrap_x) bx1 -= st->width;
    if (by0 >= st->wrap_y) by0 -= st->height;
    if (by1 >= st->wrap_y) by1 -= st->height;
  }
  bx0 &= BM, bx1 &= BM, by0 &= BM, by1 &= BM;
  const long i = static_cast<long>(lat[bx0]), j = static_cast<long>(lat[bx1]);
  const int b00 = static_cast<int>(lat[i + by0]), b10 = static_cast<int>(lat[j + by0]);
  const int b01 = static_cast<int>(lat[i + by1]), b11 = static_cast<int>(lat[j + by1]);
  const double sx = rx0 * rx0 * (3.0 - 2.0 * rx0), sy = ry0 * ry0 * (3.0 - 2.0 * ry0);
  const double* q = grad + 2 * b00;
  double u = rx0 * q[0] + ry0 * q[1];
  q = grad + 2 * b10;
  double v = rx1 * q[0] + ry0 * q[1];
  const double a = u + sx * (v - u);
  q = grad + 2 * b01;
  u = rx0 * q[0] + ry1 * q[1];
  q = grad + 2 * b11;
  v = rx1 * q[0] + ry1 * q[1];
  const double b = u + sx * (v - u);
  return a + sy * (b - a);
}

// The turbulence sum of one channel at user-space point (px, py).
MPVG_HD_INLINE double turbulence_sum(const FilterOp& op, const double* noise, int channel, double px, double py) {
  double fx = op.freq_x, fy = op.freq_y;
  TurbulenceStitch st{0, 0, 0, 0};
  const bool stitch = op.stitch != 0;
  const double tx = op.tile_user[0], ty = op.tile_user[1], tw = op.tile_user[2], th = op.tile_user[3];
  if (stitch) {
    if (fx != 0.0) {
      const double lo = floor(tw * fx) / tw, hi = ceil(tw * fx) / tw;
      fx = (fx / lo < hi / fx) ? lo : hi;
    }
    if (fy != 0.0) {
      const double lo = floor(th * fy) / th, hi = ceil(th * fy) / th;
      fy = (fy / lo < hi / fy) ? lo : hi;
    }
    st.width = static_cast<int>(tw * fx + 0.5);
    st.wrap_x = static_cast<int>(tx * fx + 0x1000 + st.width);
    st.height = static_cast<int>(th * fy + 0.5);
    st.wrap_y = static_cast<int>(ty * fy + 0x1000 + st.height);
  }
  double sum = 0, vx = px * fx, vy = py * fy, ratio = 1;
  for (int o = 0; o < op.octaves; o++) {
    const double n = turbulence_noise2(noise, channel, vx, vy, stitch ? &st : nullptr);
    sum += (op.fractal ? n : fabs(n)) / ratio;
    vx *= 2, vy *= 2, ratio *= 2;
    if (stitch) {
      st.width *= 2;
      st.wrap_x = 2 * st.wrap_x - 0x1000;
      st.height *= 2;
      st.wrap_y = 2 * st.wrap_y - 0x1000;
    }
  }
  return sum;
}

// feTurbulence at layer pixel (x, y): the four channels (straight, in the
// op's colour space), premultiplied.
MPVG_HD_INLINE Rgba4 filter_turbulence(const FilterOp& op, const double* noise, int x, int y) {
  const double* m = op.to_user;
  const double px = m[0] * x + m[2] * y + m[4], py = m[1] * x + m[3] * y + m[5];
  float c[4];
  for (int ch = 0; ch < 4; ch++) {
    double v = turbulence_sum(op, noise, ch, px, py);
    if (op.fractal) v = (v + 1.0) / 2.0;
    c[ch] = filter_clamp01(static_cast<float>(v));
  }
  return Rgba4{c[0] * c[3], c[1] * c[3], c[2] * c[3], c[3]};
}

// ------------------------------------------------------------ result

// A graph's result pixel (premultiplied, in linear light when
// result_linear) as the texel that paints it (frame/filter_layers.h):
// straight sRGB rounded to 16 bits, then premultiplied in the integration
// space (linear light when integ_linear) and rounded again, the encoder's
// conversion of a 16-bit image (frame/encoding.cpp, base_level). Rounding
// is half up: every value is non-negative and below 2^23.
MPVG_HD_INLINE Texel16 filter_texel(Rgba4 p, bool result_linear, bool integ_linear) {
  p = filter_valid(p);
  const float rgb[3] = {p.r, p.g, p.b};
  const float a = floorf(p.a * 65535.0f + 0.5f) / 65535.0f;
  uint16_t q[3];
  for (int c = 0; c < 3; c++) {
    float v = p.a > 0.0f ? rgb[c] / p.a : 0.0f;
    v = filter_clamp01(result_linear ? linear_to_srgb(filter_clamp01(v)) : v);
    float s = floorf(v * 65535.0f + 0.5f) / 65535.0f;  // straight sRGB, 16 bits
    if (integ_linear) s = srgb_to_linear(s);
    q[c] = static_cast<uint16_t>(floorf(filter_clamp01(s * a) * 65535.0f + 0.5f));
  }
  return Texel16{q[0], q[1], q[2], static_cast<uint16_t>(floorf(a * 65535.0f + 0.5f))};
}

}  // namespace mpvg
