// Filter effects (W3C Filter Effects Module Level 1) in the core scene: the
// one designed exception to "every sample's colour from flat data" (the
// paper's future work, §7: "filter effects on groups of paths").
//
// A filtered element is a FilterEffect: its content (the SourceGraphic) is
// a sub-scene in the parent's scene units, and a graph of primitives runs
// on it. The parent fills the filter region with PaintType::Filter, which
// the renderer resolves before encoding (frame/filter_layers.h): the source
// is rendered by the same pipeline into an offscreen layer at the output's
// resolution, the graph runs on that layer (core/filters/filter_primitives.h, per
// pixel on either executor), and the result re-enters the parent scene as
// a texture paint over the region, so that what comes after (clipping,
// masks, opacity, blending, groups) stays per sample.
//
// Everything here is resolved by the frontend: lengths are in the
// element's user space (primitiveUnits="objectBoundingBox" already applied),
// `xf` maps that space to scene units, every primitive has its subregion
// (the spec's defaults applied), its colour space (auto is linearRGB) and
// its inputs as indices. The layer is axis-aligned in output pixels: the
// region and subregions are taken as the pixel boxes of their transformed
// rectangles, and lengths are scaled by xf's scale along each axis (as
// resvg and Chromium do for transforms with rotation or skew).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "core/geometry/geometry.h"

namespace mpvg {

struct Scene;
struct Image;

// A rectangle [x, x + w) x [y, y + h) in user space; w or h <= 0 is empty.
struct FilterRect {
  double x = 0, y = 0, w = 0, h = 0;
};

// The bounds [x0, x1] x [y0, y1] of rectangle r mapped by m: a region or
// subregion as the axis-aligned box where its layer lies.
inline void filter_rect_bounds(const FilterRect& r, const Affine& m, double& x0, double& y0, double& x1,
                               double& y1) {
  const Vec2 c[4] = {m.apply({r.x, r.y}), m.apply({r.x + r.w, r.y}), m.apply({r.x, r.y + r.h}),
                     m.apply({r.x + r.w, r.y + r.h})};
  x0 = x1 = c[0].x;
  y0 = y1 = c[0].y;
  for (const Vec2& p : c) {
    x0 = p.x < x0 ? p.x : x0, x1 = p.x > x1 ? p.x : x1;
    y0 = p.y < y0 ? p.y : y0, y1 = p.y > y1 ? p.y : y1;
  }
}

enum class FilterKind : uint8_t {
  Blend,              // mode: in2 below, in above (core/paint/blend.h)
  ColorMatrix,        // matrix (values resolved to the 4 x 5 matrix)
  ComponentTransfer,  // funcs[4] (R, G, B, A)
  Composite,          // op, k1..k4: in over/in/out/atop/xor/arithmetic in2
  ConvolveMatrix,     // order, kernel, divisor, bias, target, edge mode, preserve_alpha
  DiffuseLighting,    // surface_scale, diffuse_constant, light, lighting_color
  DisplacementMap,    // scale, x_channel, y_channel: in displaced by in2
  DropShadow,         // dx, dy, std_dev, flood colour
  Flood,              // flood colour (straight, sRGB-encoded) and opacity
  GaussianBlur,       // std_dev, edge_mode
  Image,              // image + image_xf, or scene (an element reference)
  Merge,              // inputs: merge nodes, bottom first
  Morphology,         // op (erode / dilate), radius
  Offset,             // dx, dy
  SpecularLighting,   // surface_scale, specular_constant, specular_exponent, light, lighting_color
  Tile,               // in's subregion repeated over the primitive's
  Turbulence,         // base_frequency, num_octaves, seed, stitch_tiles, fractal_noise
};

// Inputs: >= 0 the result of an earlier primitive of the graph; otherwise
// one of these. BackgroundImage and BackgroundAlpha are transparent black;
// FillPaint and StrokePaint flood the layer with FilterEffect::fill_paint
// and stroke_paint. (The SVG frontend maps all four to SourceGraphic, as
// resvg's references show; the core keeps their meaning for frontends that
// have them.)
enum FilterInput : int32_t {
  FILTER_SOURCE_GRAPHIC = -1,
  FILTER_SOURCE_ALPHA = -2,
  FILTER_BACKGROUND_IMAGE = -3,
  FILTER_BACKGROUND_ALPHA = -4,
  FILTER_FILL_PAINT = -5,
  FILTER_STROKE_PAINT = -6,
};

enum class EdgeMode : uint8_t { None, Duplicate, Wrap, Mirror };
enum class CompositeOp : uint8_t { Over, In, Out, Atop, Xor, Arithmetic, Lighter };
enum class TransferType : uint8_t { Identity, Table, Discrete, Linear, Gamma };
enum class LightType : uint8_t { None, Distant, Point, Spot };

struct TransferFunction {
  TransferType type = TransferType::Identity;
  std::vector<float> table;  // Table, Discrete: tableValues
  float slope = 1, intercept = 0;                 // Linear
  float amplitude = 1, exponent = 1, offset = 0;  // Gamma
};

// A light source; positions in user space (z as well, scaled like lengths).
struct LightSource {
  LightType type = LightType::None;
  double azimuth = 0, elevation = 0;  // Distant, degrees
  double x = 0, y = 0, z = 0;         // Point, Spot
  double points_at_x = 0, points_at_y = 0, points_at_z = 0;  // Spot
  double specular_exponent = 1;       // Spot
  double limiting_cone_angle = 0;     // Spot, degrees; has_cone = false: none
  bool has_cone = false;
};

struct FilterPrimitive {
  FilterKind kind = FilterKind::Flood;
  int32_t in = FILTER_SOURCE_GRAPHIC, in2 = FILTER_SOURCE_GRAPHIC;
  std::vector<int32_t> inputs;  // Merge
  FilterRect subregion;         // user space, the spec's defaults resolved
  bool linear_rgb = true;       // color-interpolation-filters: linearRGB (auto) or sRGB

  // Flood, DropShadow (flood-color, flood-opacity); lighting-color in
  // `color` for the lighting primitives.
  float color[4] = {0, 0, 0, 1};  // straight alpha, sRGB-encoded
  double dx = 0, dy = 0;           // Offset, DropShadow: user units
  double std_dev_x = 0, std_dev_y = 0;  // GaussianBlur, DropShadow: user units
  EdgeMode edge_mode = EdgeMode::None;  // GaussianBlur (initial none), ConvolveMatrix (initial duplicate)
  uint8_t blend_mode = 0;              // Blend: BlendModeCode (core/paint/blend.h)
  CompositeOp op = CompositeOp::Over;  // Composite
  double k[4] = {0, 0, 0, 0};          // Composite arithmetic
  float matrix[20] = {1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0};  // ColorMatrix, row-major
  TransferFunction funcs[4];           // ComponentTransfer: R, G, B, A
  bool dilate = false;                 // Morphology: erode (false) or dilate
  double radius_x = 0, radius_y = 0;   // Morphology: user units
  // ConvolveMatrix: order_x x order_y kernel, row-major as written.
  int order_x = 3, order_y = 3;
  std::vector<float> kernel;
  double divisor = 1, bias = 0;
  int target_x = 1, target_y = 1;
  bool preserve_alpha = false;
  // DisplacementMap: scale in user units; channels 0..3 = R, G, B, A.
  double scale = 0;
  uint8_t x_channel = 3, y_channel = 3;
  // Lighting.
  double surface_scale = 1, diffuse_constant = 1, specular_constant = 1, specular_exponent = 1;
  LightSource light;
  // Turbulence: base frequencies in user space (1 / user units).
  double base_frequency_x = 0, base_frequency_y = 0;
  int num_octaves = 1;
  double seed = 0;
  bool stitch_tiles = false;
  bool fractal_noise = false;  // type="fractalNoise" (else turbulence)
  // Image: a raster placed by image_xf (image pixels to user space), or an
  // element rendered like a use of it (scene, in user space).
  std::shared_ptr<const mpvg::Image> image;
  Affine image_xf;
  bool image_pixelated = false;  // image-rendering asks for the nearest texel (else bilinear)
  std::shared_ptr<const Scene> scene;
};

// A filtered element. Its parent fills `region` (mapped by xf) with a
// Paint of type Filter whose index is this effect's.
struct FilterEffect {
  std::shared_ptr<const Scene> source;  // SourceGraphic, in the parent's scene units
  Affine xf;                            // the filter's user space to scene units
  FilterRect region;                    // filter region, user space
  std::vector<FilterPrimitive> primitives;  // the result is the last one's
  // FillPaint / StrokePaint colours (straight, sRGB-encoded; alpha 0: none).
  float fill_paint[4] = {0, 0, 0, 0}, stroke_paint[4] = {0, 0, 0, 0};
};

// Filters nest (an element inside a filtered element's content), at most
// this deep; deeper ones are drawn unfiltered by the frontend.
constexpr int kMaxFilterDepth = 16;

}  // namespace mpvg
