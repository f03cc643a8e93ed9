// The scene model (paper §3).
//
// A scene is a stream of elements described by the grammar
//
//   scene     -> fill*                        (the dummy root push/pop is implicit)
//   fill      -> F | ( clip-path* | fill* ) | { mask? fill* }
//   mask      -> { fill* }                    (a group whose Group::mask is set)
//   clip-path -> C | ( clip-path* | clip-path* )
//
// where F is a filled path, C a clip test, and '(' '|' ')' are push, activate
// and pop. A clip-path area is the union of the clip-paths before its '|';
// nesting is intersection. '{' '}' begin and end a transparency group
// (core/paint/group.h): its content is composited on its own, then the result,
// times its opacity and its mask, onto what lies below it with its blend
// mode. A mask is a group whose result becomes a coverage value (luminance
// or alpha) that multiplies the group it is the first content of.
//
// The stream is stored top-most first, so that samples can be blended front
// to back and stop once opaque; only the fill lists of groups that must be
// evaluated back to front (blend modes other than normal meet their
// backdrop there, Group::back_to_front) are stored in painter's order.
//
// Frontends never write the stream directly: they use SceneBuilder
// (frame/scene_builder.h), which takes content in painter's (back-to-front)
// order, checks the grammar, decides which groups run back to front, and
// reverses every other fill* list when it finishes.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/filters/filter.h"
#include "core/geometry/geometry.h"
#include "core/memory_budget.h"
#include "core/paint/paint.h"

namespace mpvg {

enum class SegmentType : uint8_t {
  Line,    // 2 control points
  Quad,    // integral quadratic, 3 control points
  RQuad,   // rational quadratic (conic), 3 control points + weight of the middle one
  Cubic,   // integral cubic, 4 control points
  RCubic,  // rational cubic: representable, rejected by abstraction (paper §2)
};

inline int segment_degree(SegmentType t) {
  switch (t) {
    case SegmentType::Line: return 1;
    case SegmentType::Quad:
    case SegmentType::RQuad: return 2;
    default: return 3;
  }
}

enum class FillRule : uint8_t { NonZero, EvenOdd };

// Path geometry in user space: a list of contours, each a chain of segments
// sharing endpoints. Segment i of a contour uses points[first_point ..
// first_point + degree]; the next segment starts at its last point.
class Path {
 public:
  struct Segment {
    SegmentType type;
    uint32_t first_point;
    uint32_t first_weight;  // index into weights (RQuad: 1, RCubic: 4), or 0
  };
  struct Contour {
    uint32_t first_segment = 0;
    uint32_t segment_count = 0;
    uint32_t start_point = 0;
    bool closed = false;  // an explicit close ('Z'); fills close every contour anyway
  };

  void move_to(Vec2 p);
  void line_to(Vec2 p);
  void quad_to(Vec2 p1, Vec2 p2);
  void rquad_to(Vec2 p1, Vec2 p2, double w);
  void cubic_to(Vec2 p1, Vec2 p2, Vec2 p3);
  void rcubic_to(Vec2 p1, Vec2 p2, Vec2 p3, double w0, double w1, double w2, double w3);
  void close();

  bool empty() const { return segments_.empty(); }
  Vec2 current_point() const { return points_.empty() ? Vec2{} : points_.back(); }
  bool has_current_point() const { return !points_.empty(); }

  const std::vector<Vec2>& points() const { return points_; }
  const std::vector<double>& weights() const { return weights_; }
  const std::vector<Segment>& segments() const { return segments_; }
  const std::vector<Contour>& contours() const { return contours_; }

  // Contour i alone, as a path of its own (the same commands replayed).
  Path contour_path(size_t i) const;
  // The rectangle [x0, x1] x [y0, y1], one closed contour from (x0, y0).
  static Path rectangle(double x0, double y0, double x1, double y1);
  // Appends the contours of `other`, as if its commands followed ours.
  void append(const Path& other);
  // The same commands with every point mapped by m (affine maps keep the
  // rational weights).
  Path transformed(const Affine& m) const;

 private:
  void ensure_contour();
  void add_segment(SegmentType t, uint32_t first_weight);

  std::vector<Vec2> points_;
  std::vector<double> weights_;
  std::vector<Segment> segments_;
  std::vector<Contour> contours_;
  bool open_contour_ = false;
};

// Straight (non-premultiplied) RGBA with sRGB-encoded components in [0, 1].
struct RGBA {
  float r = 0, g = 0, b = 0, a = 1;
};

// ------------------------------------------------------------------ paints
//
// Every paint is evaluated per sample (core/paint/paint.h), at the sample's
// position, on both executors. Geometry of a paint lives in its own space;
// its transform maps that space to scene units (not to the path's user
// space: a paint can be placed independently of the path it fills, as PDF's
// shadings and patterns are).

// Filter: the result of a filter effect (core/filters/filter.h) over its region,
// which the renderer resolves into a Texture before encoding.
// SweepGradient comes last: the other values keep their numbers.
enum class PaintType : uint8_t { Solid, LinearGradient, RadialGradient, Texture, Pattern, Mesh, Filter, SweepGradient };

// What a colour ramp does with t outside [0, 1].
enum class Spread : uint8_t { Pad, Reflect, Repeat };

// The space colours of a ramp are interpolated in (SVG color-interpolation).
enum class ColorSpace : uint8_t { Srgb, LinearRgb };

struct ColorStop {
  double offset = 0;  // position along the ramp, non-decreasing from stop to stop
  RGBA color;         // straight alpha, sRGB-encoded
};

// A gradient: t from the geometry, then a colour from the ramp.
//
// Linear: t = 0 on the line through p0 perpendicular to p1 - p0, t = 1
// through p1.
//
// Radial, the general two-point conical gradient of canvas and of PDF's
// type-3 shadings: the circles C(t) with centre focal + t (center - focal)
// and radius focal_radius + t (radius - focal_radius), from the start
// (focal) circle at t = 0 to the end circle at t = 1. A point takes the
// largest t whose circle passes through it with a radius >= 0 (and, with an
// extend flag off, t within [0, 1]); a point no such circle reaches is not
// painted. Any placement is allowed: the focal circle inside, on or outside
// the end circle, focal_radius > 0, equal radii (a cylinder).
//
// Sweep (conic; COLR v1's PaintSweepGradient): the angle of a point p of
// gradient space around `center`,
//   theta = atan2(p.y - center.y, p.x - center.x), in degrees, measured from
//           +x towards +y and taken in [0, 360) (the centre itself: 0),
// gives t = (theta - start_angle) / (end_angle - start_angle). Any angles
// are allowed (start > end runs backwards; a span beyond 360 reaches only
// part of the ramp). A counter-clockwise sweep in a y-up space is the y
// flip in xf. Equal angles: with Pad, theta < start_angle takes the first
// stop's colour and theta >= start_angle the last's (a hard step, the
// extend flags applying to either side); with Reflect or Repeat nothing is
// painted.
//
// Stops: at least one; offsets non-decreasing (equal offsets make a hard
// step). Colours between stops are interpolated with straight alpha in
// `interpolation`'s space; t below the first stop takes its colour, above
// the last the last's. spread maps t outside [0, 1] first; with Pad, an
// extend flag that is off leaves t < 0 (extend_start) or t > 1 (extend_end)
// unpainted, as PDF's Extend array does.
struct Gradient {
  Affine xf;  // gradient space to scene units
  Vec2 p0, p1;
  Vec2 focal, center;
  double focal_radius = 0, radius = 0;
  double start_angle = 0, end_angle = 360;  // sweep, degrees
  std::vector<ColorStop> stops;
  Spread spread = Spread::Pad;
  ColorSpace interpolation = ColorSpace::Srgb;
  bool extend_start = true, extend_end = true;
};

// An RGBA raster: straight alpha, sRGB-encoded, row-major, top row first,
// 8 or 16 bits per channel (only the vector of that depth is used).
// Texels an executor made for one frame (a filter layer's result,
// frame/filter_layers.h): premultiplied, already in that frame's integration
// colour space, one level (they map texel for pixel, never minified). On
// the host (`host`), or in device memory (`device`, kept by `owner`),
// which only a frame of the same executor and device can read.
struct ExecutorTexels {
  std::vector<Texel16> host;
  const Texel16* device = nullptr;
  std::shared_ptr<const void> owner;
};

struct Image {
  int width = 0, height = 0;
  int bits = 8;
  std::vector<uint8_t> rgba8;
  std::vector<uint16_t> rgba16;
  std::shared_ptr<const ExecutorTexels> texels;  // instead of rgba8 / rgba16 when set
};

enum class TextureFilter : uint8_t { Nearest, Bilinear, Bicubic };
// Outside the image: the edge texels extended, the image repeated, or
// nothing (transparent).
enum class TextureWrap : uint8_t { Clamp, Repeat, Decal };

// An image as a paint. Magnification uses `filter`; minification reads
// pre-filtered (mip) levels chosen from the paint's footprint in the image,
// so that it does not alias whatever the filter.
struct Texture {
  std::shared_ptr<const Image> image;
  Affine xf;  // image space (pixel (i, j) covers [i, i+1) x [j, j+1)) to scene units
  TextureFilter filter = TextureFilter::Bilinear;
  TextureWrap wrap_x = TextureWrap::Clamp, wrap_y = TextureWrap::Clamp;
  RGBA tint{1, 1, 1, 1};  // multiplies every texel (stencil masks: a white image tinted)
};

struct Scene;

// A pattern: a tile that is itself a scene, repeated over the plane. The
// tile is [0, tile->width) x [0, tile->height) of the tile scene's units;
// content outside it is clipped. The tile gets its own shortcut tree and is
// evaluated per sample at the sample's wrapped position, so a pattern stays
// resolution independent. A tile's paints may be patterns again, nested at
// most kMaxPatternDepth deep (core/paint/paint.h).
struct Pattern {
  std::shared_ptr<const Scene> tile;
  Affine xf;  // tile space to scene units
};

// A mesh of Gouraud-shaded triangles: PDF's mesh shadings (types 4 and 5,
// and 6 and 7 with their patches subdivided into triangles), and its
// function-based shadings sampled on a grid. The colour at a point is
// interpolated linearly over the top-most (last) triangle containing it.
// A mesh paints only inside its triangles: fill it with mesh_outline()
// (core/paint/mesh_build.h), the union of the triangles, and the colour is defined
// wherever the fill is.
struct MeshVertex {
  Vec2 p;
  RGBA color;  // straight alpha, sRGB-encoded; with a ramp, t in color.r
};
struct Mesh {
  Affine xf;                         // mesh space to scene units
  std::vector<MeshVertex> vertices;  // three per triangle
  // Empty: the vertices' colours are interpolated (in the colour space of
  // integration). Otherwise t is interpolated (PDF shadings with a
  // Function) and its colour read from this ramp.
  std::vector<ColorStop> ramp;
  // The mesh is filled over an area that holds its triangles (its box),
  // not over mesh_outline(): the triangles decide per sample where it
  // paints. For meshes whose outline would be large (a soup of 200,000
  // overlapping triangles has 600,000 outline edges, which the shortcut
  // tree would hold in every cell they cross); the same coverage, up to
  // rounding on the edges.
  bool area_by_triangles = false;
};

struct Paint {
  PaintType type = PaintType::Solid;
  RGBA color;         // Solid only
  float opacity = 1;  // multiplies the paint, whatever its type (fill-opacity × opacity)
  uint32_t index = 0; // gradients (LinearGradient, RadialGradient, SweepGradient), textures, patterns, meshes or filters of the scene
};

// One path instance of the stream: geometry, its transform to scene units,
// fill rule, and for fills the paint.
// ------------------------------------------------------------------ strokes

// SVG 2 painting.html#StrokeProperties; PDF's line styles map onto these.
enum class LineJoin : uint8_t { Miter, MiterClip, Arcs, Round, Bevel };
enum class LineCap : uint8_t { Butt, Round, Square };

// How a path is stroked (stroker/stroke.h builds the stroke, in user space,
// when the scene is rendered).
struct StrokeStyle {
  double width = 1;  // user units; > 0 and finite, or nothing is drawn
  LineJoin join = LineJoin::Miter;
  LineCap cap = LineCap::Butt;
  double miter_limit = 4;  // ratio of miter length to width; values below 1 act as 1
  // Dash and gap lengths in user units, repeated along each subpath. An odd
  // list is repeated once to make it even; an empty list, one that sums to
  // zero, or one with a negative or non-finite value means no dashing.
  std::vector<double> dashes;
  double dash_offset = 0;
};

struct ScenePath {
  uint32_t geometry = 0;
  Affine xf;
  FillRule rule = FillRule::NonZero;
  // >= 0: the geometry is a centreline, and the path is its stroke with
  // Scene::strokes[stroke] (filled nonzero; rule is ignored).
  int32_t stroke = -1;
  bool is_clip = false;
  // Drawn without antialiasing (SVG shape-rendering: crispEdges,
  // optimizeSpeed): each pixel is covered wholly or not at all, as its
  // centre is.
  bool aliased = false;
  uint32_t paint = 0;  // fills only
};

// ----------------------------------------------------- groups and masks

// W3C Compositing and Blending Level 1's blend modes, in core/paint/blend.h's
// order, then three Porter-Duff operators (premultiplied; Compositing 1
// §9.1, Compositing 2 for plus-lighter) that COLR v1's PaintComposite needs:
//   PlusLighter: co = min(1, cs + cb), ao = min(1, as + ab)
//   SourceAtop:  co = cs ab + cb (1 - as), ao = ab
//   Xor:         co = cs (1 - ab) + cb (1 - as), ao = as + ab - 2 as ab
// All three are bounded (a transparent source leaves the backdrop as it
// is), so a group with one of them is treated like a group with a blend
// mode: its list runs back to front, it never hides its backdrop. Filters'
// feBlend takes the 16 blend modes and PlusLighter.
enum class BlendMode : uint8_t {
  Normal, Multiply, Screen, Overlay, Darken, Lighten, ColorDodge, ColorBurn,
  HardLight, SoftLight, Difference, Exclusion, Hue, Saturation, Color, Luminosity,
  PlusLighter, SourceAtop, Xor,
};

// The mode's CSS keyword ("normal", "color-dodge", ..., "plus-lighter",
// "source-atop", "xor").
const char* blend_mode_name(BlendMode m);

enum class MaskType : uint8_t { None, Luminance, Alpha };

// How one colour channel of a group's result meets its backdrop, where the
// channels are inks (print preview: core/inks/inks.h): through the group's
// blend function (Blend), as the source whatever the mode (Source), or
// kept as the backdrop has it (Backdrop: the channel is not painted, PDF
// 32000-1 §11.7.4.3's compatible overprint, B = Cb). PDF's non-separable
// modes in CMYK give K the backdrop's (hue, saturation, color) or the
// source's (luminosity) value and spot colorants Normal (§11.3.5.3).
enum class ChannelRule : uint8_t { Blend, Source, Backdrop };

// A transparency group (PDF 32000-1 §11.4; SVG's group opacity, masks,
// mix-blend-mode and isolation). Every sample's shape is 0 or 1, so a
// group covers a sample where one of its fills does (a mask that is 0
// there takes that away).
struct Group {
  float opacity = 1;                    // multiplies the group's result once
  BlendMode blend = BlendMode::Normal;  // how the result meets its backdrop
  // Isolated: the content is composited onto transparency; otherwise onto
  // the group's backdrop, whose contribution is removed afterwards (PDF
  // §11.4.8). The difference shows only through blend modes inside.
  bool isolated = true;
  // Knockout: each element is composited onto the group's initial backdrop
  // and replaces the elements below it where it covers the sample.
  bool knockout = false;
  // A mask (set only on a group that is the first content of another):
  // Luminance takes luminance[] . rgb of the content composited over
  // `backdrop` (PDF /BC; SVG: transparent), rgb sRGB-encoded or linear as
  // `luminance_space` says; Alpha takes its alpha. The value, times the
  // mask's opacity, multiplies the group the mask belongs to. A mask is
  // always isolated; its blend mode does not apply.
  MaskType mask = MaskType::None;
  float luminance[3] = {0.2125f, 0.7154f, 0.0721f};
  RGBA backdrop{0, 0, 0, 0};
  ColorSpace luminance_space = ColorSpace::Srgb;
  // Ink scenes (core/inks/inks.h): per channel (r, g, b carry three inks), how
  // it meets the backdrop; and whether the channels are subtractive (ink
  // amounts), which blend modes complement before and after blending
  // (PDF 32000-1 §11.3.4). A Backdrop channel makes the group blend even
  // with the Normal mode.
  ChannelRule channels[3] = {ChannelRule::Blend, ChannelRule::Blend, ChannelRule::Blend};
  bool subtractive = false;
  // Set by SceneBuilder::finish: the group's fill list is stored (and
  // evaluated) back to front, because a blend mode in it needs its
  // backdrop. Ignored on input.
  bool back_to_front = false;
};

// Does the group composite as plain source-over (Normal, no channel kept
// as the backdrop)?
inline bool composites_normally(const Group& g) {
  if (g.blend != BlendMode::Normal) return false;
  for (ChannelRule r : g.channels)
    if (r == ChannelRule::Backdrop) return false;
  return true;
}

enum class ElementKind : uint8_t { Push, Activate, Pop, Fill, Clip, BeginGroup, EndGroup };

struct Element {
  ElementKind kind;
  uint32_t path;  // Fill and Clip: index into Scene::paths; BeginGroup, EndGroup: into Scene::groups
};

struct Scene {
  double width = 0, height = 0;  // intrinsic size, in scene units (CSS px)
  std::vector<Path> geometries;
  std::vector<StrokeStyle> strokes;  // ScenePath::stroke
  std::vector<ScenePath> paths;  // indexed by Element::path; stream order
  std::vector<Paint> paints;
  std::vector<Gradient> gradients;
  std::vector<Texture> textures;
  std::vector<Pattern> patterns;
  std::vector<Mesh> meshes;
  std::vector<FilterEffect> filters;  // PaintType::Filter
  std::vector<Group> groups;
  std::vector<Element> stream;   // top-most first (see the grammar above)
};

// The memory a path's arrays hold: what the memory budget is charged for it.
size_t path_bytes(const Path& p);

}  // namespace mpvg
