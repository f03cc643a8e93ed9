// The SVG document to Scene converter, shared by the files that implement
// it (internal to the SVG frontend):
//
//   svg_parser.cpp    entry points, the document walk, shapes and use,
//                     clip paths, emission into the SceneBuilder
//   svg_style.cpp     computed style: properties, inheritance, paint values
//   svg_strokes.cpp   strokes as fill geometry, converted in parallel
//   svg_paint_servers.cpp  gradients and patterns as scene paints
//   svg_masks.cpp     group opacity, mix-blend-mode, isolation and masks as
//                     transparency groups
//   svg_image.cpp     <image>: rasters as texture paints, SVG documents
//                     converted on their own and appended as vectors
//   svg_filters.cpp   the filter property: filter elements and filter
//                     functions resolved into the core's filter effects,
//                     the element's content converted into their source
//   svg_resources.cpp hrefs to bytes, gzip, image signatures (decoding in
//                     svg_image_decode_oiio.cpp or svg_image_decode_png.cpp)
//
// Content kinds that come later (text) get files of their own beside
// these, rendered from render() as shapes are.
//
// The conversion walks the element tree once, in document order, and writes
// a flat list of operations that mirrors the SceneBuilder calls (push,
// activate, pop, fill, clip). The list exists because a clip group's clip
// items come before its content in the stream, yet clipPathUnits=
// "objectBoundingBox" needs the content's bounding box: an element's content
// is converted first, and its clip prefix is then inserted in front of it.
// Bounds-only operations keep the geometry of shapes that paint nothing
// (fill="none", visibility="hidden", opacity 0), which still counts for
// bounding boxes (SVG 2 coords.html#BoundingBoxes), and are dropped when the
// scene is built.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/scene.h"
#include "parsers/svg/svg_basic_shapes.h"
#include "parsers/svg/svg_dom.h"
#include "parsers/svg/svg_geometry.h"
#include "parsers/svg/svg_options.h"
#include "parsers/svg/svg_resources.h"
#include "parsers/svg/svg_values.h"
#include "frame/scene_builder.h"

namespace mpvg::text {
class FontDb;
}

namespace mpvg::svg::detail {

// Nesting of elements plus use and clip-path indirections. tinyxml2 already
// limits the XML depth; references can chain further.
constexpr int kMaxDepth = 256;
// Element instances (after use expansion) converted before giving up, so
// that exponentially nested use references stay bounded.
constexpr size_t kMaxInstances = 1'000'000;
// Pattern tile encodings a scene may imply (frame/encoding.h encodes a tile
// once per paint that uses it, so nested patterns multiply): about 40 KB
// and 0.1 ms each for small tiles.
constexpr size_t kMaxTileEncodings = 10'000;
// SVG documents embedded by <image> inside one another, the document
// itself not counted.
constexpr int kMaxImageDepth = 8;
// Segments that embedded SVG documents may add to a document, nested ones
// included: every embedding copies the embedded scene's geometry
// (SceneBuilder::append), so many images of a large document would
// otherwise multiply it without bound.
constexpr size_t kMaxEmbeddedSegments = 10'000'000;
// Filter effects a document may hold, nested ones and those of embedded
// documents included: each is an offscreen layer when rendered, and its
// source a scene of its own (a use of a filtered element 10^5 times over
// would otherwise take gigabytes before any rendering).
constexpr size_t kMaxFilterEffects = 10'000;

// Append: a whole scene (an SVG document of an <image>) replayed into the
// stream (SceneBuilder::append). GroupBegin, GroupEnd: a transparency group
// or a mask (SceneBuilder::begin_group, end_group).
enum class OpKind : uint8_t { Push, Activate, Pop, Fill, Clip, Bounds, Append, GroupBegin, GroupEnd };

struct Op {
  OpKind kind = OpKind::Bounds;
  FillRule rule = FillRule::NonZero;
  uint32_t shape = 0;  // Fill, Clip, Bounds: index into Converter::shapes_
  uint32_t paint = 0;  // Fill: index into Converter::paints_
  uint32_t scene = 0;  // Append: index into Converter::embedded_; GroupBegin: into Converter::groups_
  Affine xf;           // Fill, Clip, Bounds: user space to scene; Append: the scene's units to ours
  // Fill: the geometry is a centreline, stroked with
  // Converter::stroke_styles_[stroke_style] (SceneBuilder::stroke). Strokes
  // are not part of an element's object bounding box (SVG 2
  // coords.html#BoundingBoxes), so bounds skip them.
  bool stroke = false;
  uint32_t stroke_style = 0;
  bool aliased = false;  // Fill, Clip: drawn without antialiasing (ScenePath::aliased)
  // Fill: a filter effect's result over its region (a paint of type
  // Filter). It is not part of bounding boxes: an element's box is that of
  // its content, whatever its filter (SVG 2 coords.html#BoundingBoxes);
  // the content's geometry stays as bounds-only operations beside it.
  bool filter = false;
  // Drawn by a marker: not part of its element's bounding box (SVG 2
  // coords.html#BoundingBoxes: the object bounding box leaves markers
  // out), so a mask or clip region in objectBoundingBox units cuts the
  // markers as browsers do.
  bool marker = false;

  static Op of(OpKind k) {
    Op op;
    op.kind = k;
    return op;
  }
};

// paint-order (SVG 2 painting.html#PaintOrder): the order in which fill,
// stroke and markers are painted.
enum class PaintLayer : uint8_t { Fill, Stroke, Markers };
using PaintOrder = std::array<PaintLayer, 3>;
constexpr PaintOrder kNormalPaintOrder{PaintLayer::Fill, PaintLayer::Stroke, PaintLayer::Markers};

// A computed fill or stroke (SVG 2 painting.html#SpecifyingPaint). A
// reference to a paint server is kept as such: what it paints depends on
// the shape it is used on (its bounding box, its user space).
struct PaintSpec {
  enum class Kind : uint8_t { None, Color, Server };
  Kind kind = Kind::None;
  RGBA color;  // Color; Server: the fallback colour, when `fallback`
  const Element* server = nullptr;  // Server: linearGradient, radialGradient or pattern
  bool fallback = false;  // Server: a fallback colour was given (otherwise none)
  // A context paint (context-fill, context-stroke): the index of the
  // context element's paints in Converter::contexts_, whose user space and
  // bounding box a paint server then uses; -1 otherwise.
  int context = -1;
  // `color` is currentColor (the paint's, or a server's fallback): where
  // the paint is inherited, it follows the inheriting element's color.
  bool current_color = false;

  static PaintSpec solid(const RGBA& c) {
    PaintSpec p;
    p.kind = Kind::Color;
    p.color = c;
    return p;
  }
};

// Computed values of the inherited properties that the scene can express
// (SVG 2 painting, CSS Masking 1 clip-rule; CSS Cascade 4 §7.2 inheritance).
struct Inherited {
  PaintSpec fill = PaintSpec::solid({0, 0, 0, 1});  // initial value: black
  FillRule fill_rule = FillRule::NonZero;
  double fill_opacity = 1;
  // Stroke properties (SVG 2 painting.html#StrokeProperties), all inherited;
  // lengths in user units.
  PaintSpec stroke;  // initial value: none
  double stroke_opacity = 1;
  double stroke_width = 1;
  LineJoin stroke_join = LineJoin::Miter;
  LineCap stroke_cap = LineCap::Butt;
  double stroke_miterlimit = 4;
  std::vector<double> stroke_dasharray;  // empty: none
  double stroke_dashoffset = 0;
  PaintOrder paint_order = kNormalPaintOrder;
  // font-size in user units (CSS Fonts 4; medium = 16px): em and ex lengths.
  double font_size = 16;
  // Text (svg_text.cpp): font-family as a list (generic names kept as
  // such), font-weight 1-1000, font-style italic/oblique, font-stretch 1-9
  // (CSS keywords ultra-condensed .. ultra-expanded), text-anchor,
  // letter-spacing and word-spacing in user units, xml:space="preserve".
  std::vector<std::string> font_family{"serif"};
  int font_weight = 400;
  bool font_italic = false;
  int font_stretch = 5;
  enum class Anchor : uint8_t { Start, Middle, End } text_anchor = Anchor::Start;
  double letter_spacing = 0, word_spacing = 0;
  bool space_preserve = false;
  // dominant-baseline (inherited, CSS Inline 3 as SVG 2 uses it).
  enum class Baseline : uint8_t { Alphabetic, Middle, Central, Hanging, Mathematical, TextTop, TextBottom,
                                  Ideographic } dominant_baseline = Baseline::Alphabetic;
  // font-variation-settings (CSS Fonts 4 §6.12): axis tag and value pairs.
  std::vector<std::pair<std::string, double>> font_variations;
  // writing-mode: vertical (tb, tb-rl, vertical-rl, vertical-lr) or not;
  // font-variant small-caps; font-kerning (false: none);
  // font-feature-settings items as written.
  bool vertical = false;
  bool small_caps = false;
  double font_size_adjust = 0;  // none (0) or the x-height as a fraction of font-size
  bool kerning = true;
  std::vector<std::string> font_features;
  // marker-start, marker-mid, marker-end as specified ("url(#m)"); empty
  // for none.
  std::string marker_start, marker_mid, marker_end;
  FillRule clip_rule = FillRule::NonZero;
  bool visible = true;
  RGBA color{0, 0, 0, 1};
  // image-rendering (CSS Images 3, SVG 2 painting.html#ImageRendering) as
  // the filter of raster images: auto is bicubic, as in resvg.
  TextureFilter image_rendering = TextureFilter::Bicubic;
  // shape-rendering (SVG 2 painting.html#ShapeRendering): crispEdges and
  // optimizeSpeed draw shapes without antialiasing, as browsers and resvg
  // do; text-rendering: optimizeSpeed does the same for text, which
  // shape-rendering does not affect.
  bool aliased_shapes = false;
  bool aliased_text = false;
};

// What an element is converted in: its parent's computed style and user space.
struct Context {
  Context() = default;
  // From a style's inherited values, copied (default-built, the
  // font-family list would be allocated only to be replaced).
  explicit Context(const Inherited& inherited) : inh(inherited) {}

  Inherited inh;
  Affine ctm;  // the parent's user space to scene units
  // The parent's values of non-inherited properties, for the keyword
  // "inherit" (CSS Cascade 4 §7.3).
  double parent_opacity = 1;
  std::string parent_clip_path;
  std::string parent_mask;
  std::string parent_filter;
  bool parent_display_none = false;
  bool in_clip = false;  // converting the content of a clipPath
};

struct Style {
  Style() = default;
  explicit Style(const Inherited& inherited) : inh(inherited) {}  // as Context's

  Inherited inh;
  double opacity = 1;
  std::string clip_path;  // specified value; empty or "none" for no clipping
  std::string mask;       // specified value; empty or "none" for no mask
  std::string filter;     // specified value; empty or "none" for no filter
  BlendMode blend = BlendMode::Normal;  // mix-blend-mode
  bool isolate = false;                 // isolation: isolate
  bool display_none = false;
  Affine transform;
  bool transform_invalid = false;  // the transform attribute did not parse
  bool non_scaling_stroke = false;  // vector-effect (not inherited)
};

bool same(const Affine& l, const Affine& r);

// gradientUnits, patternUnits, patternContentUnits, filterUnits,
// primitiveUnits: whether the value is objectBoundingBox; `def` when
// absent or invalid.
inline bool bounding_box_units(const std::string* v, bool def) {
  if (!v) return def;
  const std::string_view t = trim(*v);
  if (t == "objectBoundingBox") return true;
  if (t == "userSpaceOnUse") return false;
  return def;
}

enum class Kind { Container, Shape, Use, Image, Text, Unsupported, Ignored };

Kind classify(const Element& e);

// One url() or filter function of a filter value (svg_filters.cpp).
struct FilterItem;

// A clip-path or mask value resolved to its target. Shape: a clip-path
// basic shape or reference box (CSS Masking 1 §3.1), not an element.
struct ClipRef {
  enum State { None, Valid, Invalid, Shape } state = None;
  const Element* element = nullptr;
  std::shared_ptr<const ClipShape> shape;  // Shape
};
using MaskRef = ClipRef;

// A pattern tile already converted: the same pattern element used with
// the same tile geometry, the same on-screen scale and within the same
// patterns gives the same tile scene (patternUnits, patternContentUnits
// and viewBox are all folded into the size and the content transform;
// strokes depend on the linear part of the tile's transform to pixels
// only; the enclosing patterns decide which recursive uses are cut).
struct TileKey {
  const Element* pattern;
  std::array<double, 6> content;  // content user space to tile units
  std::array<double, 4> device;   // linear part of tile units to output pixels
  double width, height;
  std::vector<const Element*> stack;  // Session::active_patterns
  bool operator<(const TileKey& o) const;
};

// A converted tile: its scene (null when it paints nothing) and the tile
// encodings that one use of it costs the encoder, nested tiles included.
struct Tile {
  std::shared_ptr<const Scene> scene;
  size_t encodings = 0;
};

// An <image>'s href loaded: a decoded raster image or a parsed SVG
// document, or why neither could be had.
struct LoadedImage {
  // A raster image: its bytes, kept to be decoded at the size each use
  // needs (image_reduction.h), its own size once known, and the images
  // decoded so far by reduction factor.
  std::shared_ptr<const std::vector<uint8_t>> raster_bytes;
  mutable int width = 0, height = 0;
  mutable std::map<int, std::shared_ptr<const Image>> rasters;
  std::shared_ptr<const Document> svg;  // inflated first when it was svgz
  std::string path;   // the file's canonical path; "" for data: URIs
  std::string error;  // one line; non-empty when nothing can be drawn
  // An OpenType SVG glyph's document: it reads no file, whatever folders
  // the document that shows it may read.
  bool reads_nothing = false;
};

// Loaded images by (base folder, href), shared by a document and the
// documents it embeds: a resource is read and decoded once, and its uses
// share one Image (the encoder builds one mip chain per Image).
using ImageCache = std::map<std::pair<std::string, std::string>, LoadedImage>;

// An OpenType SVG table's document, parsed (svg_text.cpp): the glyph IDs
// of its record, and the font's units per em (a glyph's viewport is the
// em square, one user unit per font unit).
struct SvgGlyphSource {
  uint32_t first = 0, last = 0;
  double units_per_em = 1000;
  std::shared_ptr<const Document> doc;  // null when it does not parse
  std::string font;                     // the family, for warnings
};

// What the converters of one document share: a pattern's tile is converted
// by a converter of its own, nested in the one that meets the pattern.
// An SVG document embedded by <image> gets a session of its own.
struct Session {
  Session(const Document& d, const ParseOptions& o, std::vector<std::string>& w)
      : doc(d), options(o), warnings(w) {}

  const Document& doc;
  const ParseOptions& options;
  std::vector<std::string>& warnings;
  std::unordered_set<std::string> warned;
  double percent_w = 100, percent_h = 100;  // the root viewport, for percentages
  double root_em = 16;                       // the root element's font size, for rem
  // The root declares version 1.0, 1.1 or 1.2: geometry (x, y, width, ...)
  // is attributes only, as SVG 1 defines it; SVG 2 made it CSS properties.
  bool svg1 = false;
  size_t instances = 0;
  std::vector<const Element*> active;         // elements being converted (use cycles)
  std::vector<const Element*> active_clips;   // clipPaths being expanded (clip-path cycles)
  std::vector<const Element*> active_masks;   // masks being converted (mask cycles)
  // Elements whose mask reference is recursive (Converter::cut_recursive_masks),
  // decided on the first mask reference met.
  std::unordered_set<const Element*> cut_masks;
  bool masks_checked = false;
  // The document's properties were checked for unsupported ones
  // (Converter::warn_unsupported_properties).
  bool properties_checked = false;
  std::vector<const Element*> active_patterns;  // patterns whose tiles are being converted
  // Filter effects whose sources are being converted, nested (at most
  // kMaxFilterDepth), and the filter elements whose primitives are (an
  // feImage that reaches its own filter again).
  int filter_depth = 0;
  std::vector<const Element*> active_filters;
  // ParseOptions::export_id: the element drawn alone (null: everything),
  // and whether its subtree is being converted now.
  const Element* export_target = nullptr;
  bool exporting = false;
  Bounds export_box;  // what it draws, in scene units (Converter::run)
  // ParseOptions::query: the boxes of the drawn elements with an id
  // (ParseResult::elements), and the ids listed so far.
  std::vector<ElementBox>* boxes = nullptr;
  std::unordered_set<std::string> boxed;
  size_t filter_effects = 0;  // made so far (kMaxFilterEffects)
  std::map<TileKey, Tile> tiles;
  size_t stroked_paths = 0;
  // Where relative hrefs resolve (the document's folder) and the folders
  // that may be read (svg_resources.h); the first is the document's own.
  std::string base_dir = ".";
  std::vector<std::string> allowed_dirs;
  // For documents embedded by <image>: how deep this one is (0 for the
  // document itself), and the real paths of the embedded documents that
  // enclose it, itself included (a document embedding itself).
  int image_depth = 0;
  std::vector<std::string> documents;
  // Segments appended by embedded documents so far, in the whole tree of
  // documents (kMaxEmbeddedSegments).
  size_t embedded_segments = 0;
  std::shared_ptr<ImageCache> images = std::make_shared<ImageCache>();
  // OpenType SVG glyphs: each face's documents met so far, each parsed
  // once; the glyphs found to have none; the document that draws one
  // glyph (its source, the glyph, currentColor as #rrggbbaa or "").
  std::map<int, std::vector<std::shared_ptr<const SvgGlyphSource>>> svg_glyph_sources;
  std::set<std::pair<int, uint32_t>> plain_glyphs;
  std::map<std::tuple<const SvgGlyphSource*, uint32_t, std::string>, LoadedImage> svg_glyphs;
  // COLR v1 glyphs: each glyph's drawing at 1 user unit per em, by face,
  // glyph, variations and foreground colour; null for glyphs without one.
  std::map<std::tuple<int, uint32_t, std::string, std::array<float, 4>>, std::shared_ptr<const Scene>> colr_glyphs;
};

class Converter {
 public:
  // `device` maps the scene's units to output pixels; `level` is the
  // scene's pattern nesting (0 for the document, n for a tile n deep).
  Converter(Session& s, const Affine& device, int level) : s_(s), device_(device), level_(level) {}
  // What it held of the memory budget is given back (its shapes, moved on
  // into scenes, are charged by their builders: emit).
  ~Converter();
  Converter(const Converter&) = delete;
  Converter& operator=(const Converter&) = delete;

  // The document's scene.
  Scene run();

 private:
  void warn(std::string msg) const;
  // Appends a shape, charged to the memory budget; its index.
  void add_shape(Path p);
  // Charges the operations added since the last charge.
  void charge_ops();
  // Depth and size limits; false when the element must be skipped.
  bool enter(int depth);
  const Element* find(const std::string& id) const;

  // ------------------------------------------------------------ style (svg_style.cpp)

  Style compute_style(const Element& e, const Context& ctx);
  void stroke_style(const Element& e, Inherited& inh, Style& st);
  // One warning per property of the document that mpvg does not support
  // (or per unsupported value), wherever it is declared; run once, by the
  // first compute_style of a session.
  void warn_unsupported_properties();
  PaintSpec resolve_paint(const PaintValue& p, const RGBA& current, const std::string& what);
  Context child_context(const Style& st, const Affine& space, bool in_clip) const;
  // The context `e` is converted in when reached from its document
  // ancestors (for clipPaths, paint servers and their content, which
  // inherit from where they are defined, not from where they are used).
  Context document_context(const Element& e, bool in_clip);

  // ------------------------------------------------------------ paint servers (svg_paint_servers.cpp)

  // The object bounding box of a shape (its fill geometry in user space),
  // computed on first use.
  struct ShapeBox {
    const std::vector<Path>& shapes;  // shapes_, which may grow meanwhile
    uint32_t shape;
    std::optional<Bounds> b;
    const Bounds& get() {
      if (!b) {
        b.emplace();
        add_path_bounds(shapes[shape], Affine{}, *b);
      }
      return *b;
    }
  };
  // What a paint server yields for one use: a paint into paints_, a plain
  // colour, nothing (an empty area or a cycle), or a failure that lets the
  // fallback colour apply (no stops, no tile content, an invalid size, a
  // bounding box without area).
  struct ServerPaint {
    enum class Kind { Paint, Color, Nothing, Failed } kind = Kind::Failed;
    Paint paint;  // Paint: type and index
    RGBA color;   // Color
  };
  // The fill or stroke `spec` of a shape with bounding box `bbox` in user
  // space `space`, with opacity `opacity`, as an index into paints_;
  // nullopt when it paints nothing.
  std::optional<uint32_t> make_paint(const PaintSpec& spec, double opacity, ShapeBox& bbox, const Affine& space);
  // A paint server (or filter) and the elements its href chain leads to,
  // in order; `what` names them in the warning about a cycle.
  std::vector<const Element*> href_chain(const Element& e, const char* what = "paint servers");
  // The font size of an element where it is defined (em lengths).
  double font_size_of(const Element& e);
  ServerPaint gradient_paint(const Element& g, ShapeBox& bbox, const Affine& space);
  ServerPaint pattern_paint(const Element& p, ShapeBox& bbox, const Affine& space);
  // Run on a tile's own converter: the children of `content` (a pattern)
  // in a scene of width x height tile units, their user space mapped to
  // tile units by `content_xf`.
  Scene convert_tile(const Element& content, const Affine& content_xf, double width, double height);

  // ------------------------------------------------------------ images (svg_image.cpp)

  void image(const Element& e, const Style& st, const Affine& space);
  const LoadedImage& load_image(const std::string& href);
  // li's raster decoded for a use whose texels map to output pixels by
  // `texels(w, h)` (for an image of w x h): reduced by the largest k that
  // keeps a texel per output pixel in every direction (*k: texel i of the
  // result covers the image's [i k, (i + 1) k)). nullptr with *why when it
  // cannot be decoded.
  std::shared_ptr<const Image> raster_for(const LoadedImage& li, const std::function<Affine(int w, int h)>& texels,
                                          int* k, std::string* why);
  // The drawing of an embedded SVG document: its scene, the <image>'s
  // viewport for the document's size, and where the document's units go
  // in the <image>'s user space; nullopt when it draws nothing.
  struct Embedded {
    Scene scene;
    ViewBox viewport;
    Affine place;
  };
  std::optional<Embedded> embed_document(const LoadedImage& li, const std::string& shown,
                                         const std::function<ViewBox(double, double)>& viewport,
                                         const AspectRatio& ar, const Affine& space);
  uint32_t rect_shape(const ViewBox& r);
  // A fill of `shape` (in `space`) with an image: texel (i, j) mapped to
  // scene units by `texels`, clamped at its edges, its alpha times opacity.
  void texture_fill(std::shared_ptr<const Image> image, const Affine& texels, TextureFilter filter, double opacity,
                    uint32_t shape, const Affine& space);

  // ------------------------------------------------------------ references

  ClipRef resolve_clip(const std::string& value);
  const Element* use_target(const Element& use);
  Affine use_offset(const Element& use, double em);

  // ------------------------------------------------------------ geometry

  enum class Axis { X, Y, Diagonal };

  double percent_base(Axis axis) const;
  // transform-origin of e (user units), and a transform moved to it.
  std::optional<Vec2> transform_origin(const Element& e, double em) const;
  std::optional<Bounds> object_box(const Element& e, double em) const;
  // object_box's walk: e's box mapped by xf added to b; false where it
  // holds an element whose box is not known before conversion.
  bool add_object_bounds(const Element& e, const Affine& xf, double em, Bounds& b, int depth) const;
  static constexpr int kMaxBoxDepth = 64;  // nested groups object_box looks into
  Affine with_origin(const Element& e, const Affine& t, double em) const;
  double to_user(const Length& l, Axis axis, double em) const;
  // A length attribute of a paint server (`def` when absent or invalid):
  // with objectBoundingBox units (obb) a percentage is a fraction of the
  // box like a plain number; with userSpaceOnUse, of the viewport (SVG 1.1
  // §13.2.2, §13.3).
  // Warns when `value` of attribute `name` is a length out of range.
  void warn_out_of_range(std::string_view name, std::string_view value, CalcOk calc) const;
  double server_length(const std::string* text, Length def, Axis axis, double em, bool obb,
                       double max_magnitude = kMaxNumber) const;
  double length(const Element& e, const char* name, Axis axis, double def, double em) const;
  // The length `name` of e as specified, or nullopt when absent or
  // invalid. SVG 2's geometry properties (x, y, width, height, cx, cy, r,
  // rx, ry) are CSS properties: set by style sheets and style attributes
  // too (not in a document that declares an SVG 1 version), and taking
  // calc(); other length attributes are attributes only.
  std::optional<Length> length_value(const Element& e, const char* name) const;
  std::optional<double> auto_length(const Element& e, const char* name, Axis axis, double em) const;
  int shape_index(const Element& e, double em);
  // arc_continuations, for a path: PathBuilder::arc_continuations.
  std::optional<Path> build_shape(const Element& e, double em,
                                  std::vector<uint32_t>* arc_continuations = nullptr) const;

  // ------------------------------------------------------------ rendering

  // What rendering an element (or a clipPath child) needs, resolved once:
  // its style, the space its content lives in, a use's target, its clip.
  struct Placed {
    Style st;
    Affine space;
    const Element* target = nullptr;
    ClipRef clip;
  };
  bool place(const Element& e, Kind kind, const Context& ctx, Placed& out);
  void render(const Element& e, const Context& ctx, int depth);
  // render()'s work: the element with its effects. render() itself decides
  // what --export-id leaves out and measures the boxes --query lists. An
  // `ancestor` of the element --export-id draws gives its transform and the
  // properties it passes down, none of its effects; its children are
  // rendered (render() skips those off the path).
  void render_element(const Element& e, const Context& ctx, int depth, bool ancestor = false);
  // What ops_[begin, end) paints, in scene units: strokes with their width,
  // markers, filter regions, embedded documents; invisible shapes (bounds
  // operations) and clip and mask content not.
  Bounds drawn_bounds(size_t begin, size_t end) const;
  // What render() draws of an element, its own clip-path, mask, opacity
  // and filter aside: a container's children, a use's target, a shape.
  void draw_content(const Element& e, Kind kind, const Placed& pl, const Context& inner, int depth);
  bool conditions_pass(const Element& e) const;
  // Context elements (SVG 2 painting.html#TermContextElement): the shape a
  // marker is drawn for, the use element a tree is drawn by. contexts_
  // holds every one met (PaintSpec::context indexes it); context_ is the
  // one in effect, -1 outside markers and use.
  struct ContextPaint {
    PaintSpec fill, stroke;
    Affine space;
    std::optional<Bounds> bbox;
  };
  std::vector<ContextPaint> contexts_;
  int context_ = -1;
  // Each marker's parent context (its ancestors' cascade), computed once
  // where none of those ancestors asks for context-fill or context-stroke
  // (which CSS inherits as keywords, resolved against each marked shape).
  std::unordered_map<const Element*, Context> marker_contexts_;
  const Context& marker_context(const Element& marker, Context& scratch);
  // A nested svg, or a symbol or svg drawn by `use` (svg_viewports.cpp).
  void render_viewport(const Element& e, const Context& ctx, int depth, const Element* use);
  bool clips_overflow(const Element& e) const;
  void shape_paint(const Element& e, const Style& st, const Affine& space, int depth);
  // shapes_[shape] filled (unless !fillable) and stroked with st, in
  // paint-order.
  // box: the bounding box for objectBoundingBox paint servers when it is
  // not the shape's own (a text's spans use the whole text's).
  // markable: the shape element, whose markers are drawn and whose
  // pathLength scales the dashes; nullptr for text.
  void paint_shape(uint32_t shape, const Style& st, const Affine& space, bool fillable, const Bounds* box = nullptr,
                   const Element* markable = nullptr, int depth = 0);
  // The markers of e's shape (svg_markers.cpp).
  void draw_markers(const Element& e, const Style& st, uint32_t shape, const Affine& space, int depth);

  // ------------------------------------------------------------ text (svg_text.cpp)

  void text(const Element& e, const Style& st, const Affine& space);
  // The text's glyphs inside a clipPath.
  void clip_text(const Element& e, const Style& st, const Affine& space);
  // Each span's glyph outlines (user space) with its style.
  struct TextPiece {
    Path path;
    Style st;
    // A bitmap glyph instead (colour emoji): its image, filling `path` (its
    // rectangle), texel (i, j) mapped to user space by image_xf.
    std::shared_ptr<const Image> image;
    Affine image_xf;
    // An OpenType SVG glyph instead: the document that holds glyph
    // svg_glyph_id, its font units mapped to user space by image_xf; `path`
    // is the glyph's outline (what a clip path takes).
    std::shared_ptr<const SvgGlyphSource> svg_glyph;
    uint32_t svg_glyph_id = 0;
    // A COLR v1 glyph instead: its paint graph's scene (text/color_glyph.h)
    // at 1 user unit per em, mapped to user space by image_xf; `path` is
    // the glyph's outline.
    std::shared_ptr<const Scene> color_scene;
  };
  // The COLR v1 drawing of a glyph with `foreground` as the text's colour,
  // null when it has none (cached per document).
  std::shared_ptr<const Scene> colr_glyph(const text::FontDb& db, int face, uint32_t glyph,
                                          const std::vector<std::pair<std::string, double>>& variations,
                                          const RGBA& foreground);
  // A piece's drawing (an SVG glyph's embedded document or a COLR v1
  // glyph's scene) appended to the scene, the text's fill-opacity fading
  // it as a whole.
  void append_glyph_drawing(Scene scene, const Affine& xf, double opacity);
  // The parsed SVG document of a glyph, null when it has none.
  std::shared_ptr<const SvgGlyphSource> svg_glyph_source(const text::FontDb& db, int face, uint32_t glyph);
  // A text piece's SVG glyph appended to the scene: the element glyph<ID>
  // of its document, drawn as a <use> of it would be.
  void draw_svg_glyph(const TextPiece& piece, const Affine& space);
  // cells, when given: the union of the glyph cells (each cluster's
  // advance by the font's ascent and descent), the text's box.
  std::vector<TextPiece> layout_text(const Element& e, const Style& st, const Affine& space, Bounds* cells = nullptr);

  // ------------------------------------------------------------ groups and masks (svg_masks.cpp)

  MaskRef resolve_mask(const Element& e, const std::string& value);
  ClipRef resolve_reference(const std::string& value, const char* what, const char* element,
                            const std::vector<const Element*>& active);
  const Element* mask_link(const Element& e) const;
  void cut_recursive_masks();
  bool group_content(const Element& e, size_t start, const Style& st, const Affine& space, int depth);
  void hide_content(size_t start);
  bool fold_opacity(size_t start, double opacity);
  struct LazyBounds;
  bool mask_ops(const Element& mask, const Affine& space, LazyBounds& bbox, int depth);

  // ------------------------------------------------------------ filters (svg_filters.cpp)

  // Draws the content of element `e` (style `st`, user space `space`)
  // through its filter property. `draw` converts the content into the
  // converter it is given: this one when there is no filter; with one, a
  // converter of its own whose scene becomes the filter's source, while
  // this one gets the content's bounds and the filter's result over its
  // region. Returns false when the element is not rendered (its filter
  // references nothing usable).
  bool filter_content(const Element& e, const Style& st, const Affine& space, int depth,
                      const std::function<void(Converter&)>& draw);
  // The filter value's url()s and functions; nullopt when the element is
  // drawn unfiltered (none, an invalid value, a recursion, too deep).
  std::optional<std::vector<FilterItem>> filter_items(const Element& e, const Style& st);
  // The effects of the items for content with box `bbox` (*invalid: a
  // url() led nowhere usable).
  std::vector<FilterEffect> filter_effects(const std::vector<FilterItem>& items, const Bounds& bbox,
                                           const Affine& space, int depth, bool* invalid);
  // Here: the bounds of fc's content, and the last effect's result over
  // its region; fc's scene is the first one's source.
  void filter_fill(Converter& fc, std::vector<FilterEffect> effects, const Affine& space);
  // Where an effect's result is painted: its region's box in scene units,
  // clipped to what of it can show.
  ViewBox region_fill(const FilterRect& region, const Affine& space) const;
  // What a filter element's primitives are resolved against (svg_filters.cpp).
  struct FilterSpace;
  // Filter element `f` (its href chain resolved) applied to an element with
  // bounding box `bbox` in user space `space`; nullopt when it is invalid.
  std::optional<FilterEffect> filter_effect(const Element& f, const Bounds& bbox, const Affine& space, int depth);
  // One primitive element into prims (nothing for elements that are not
  // primitives); `results` maps result names to the latest primitive.
  void filter_primitive(const Element& fe, const FilterSpace& fs, std::vector<FilterPrimitive>& prims,
                        std::unordered_map<std::string, int32_t>& results);
  int32_t filter_input(const Element& fe, const char* name, const std::vector<FilterPrimitive>& prims,
                       const std::unordered_map<std::string, int32_t>& results);
  FilterRect primitive_subregion(const Element& fe, const FilterSpace& fs, FilterKind kind,
                                 const std::vector<int32_t>& referenced,
                                 const std::vector<FilterPrimitive>& prims);
  void fe_image(const Element& fe, const FilterSpace& fs, FilterPrimitive& p);
  // A CSS filter function (Filter Effects 1 §"Filter Functions") as its
  // primitive; nullopt when its arguments are invalid.
  std::optional<FilterPrimitive> filter_function(std::string_view name, std::string_view args, const Style& st);

  // ------------------------------------------------------------ strokes (svg_strokes.cpp)

  // `element`: the shape element drawn, whose pathLength scales the
  // dashes; nullptr for text.
  std::optional<Op> shape_stroke(uint32_t shape, const Style& st, const Affine& space, ShapeBox& bbox,
                                 const Element* element);


  // ------------------------------------------------------------ clip paths

  template <class F>
  void for_each_content(size_t begin, size_t end, F f) const;
  // strokes: the stroke bounding box instead (SVG 2 coords.html#TermStrokeBoundingBox).
  Bounds content_bounds(size_t begin, size_t end, const Affine& space, bool strokes = false) const;

  // The object bounding box of a clipped element, computed on first use.
  struct LazyBounds {
    const Converter& c;
    size_t begin, end;
    Affine space;
    std::optional<Bounds> b;
    const Bounds& get() {
      if (!b) b = c.content_bounds(begin, end, space);
      return *b;
    }
  };
  void clip_content(size_t start, const Element& cp, const Affine& space, int depth);
  // The same with the clip items that `items` appends (false: the clip
  // is invalid and the content goes).
  void clip_content(size_t start, const Affine& space, const std::function<bool(LazyBounds&)>& items);
  // A clip-path basic shape or reference box (svg_basic_shapes.cpp).
  void clip_shape_content(size_t start, const ClipShape& cs, const Affine& space, double em);
  bool clip_shape_items(const ClipShape& cs, const Affine& space, LazyBounds& bbox, double em);
  bool clip_items(const Element& cp, const Affine& space, LazyBounds& bbox, int depth);
  void clip_child(const Element& e, const Context& ctx, int depth);

  // ------------------------------------------------------------ output

  void emit(SceneBuilder& b);

  Session& s_;
  Affine device_;  // scene units to output pixels
  int level_ = 0;
  // Its operations are in the document's scene units (false for an
  // feImage's element, drawn in the filter's space): --query and
  // --export-id look at this converter's elements.
  bool document_space_ = true;
  double scene_w_ = 0, scene_h_ = 0;  // the size of the scene being converted, in its units
  size_t tile_encodings_ = 0;  // tile encodings this scene's pattern paints imply

  std::vector<Op> ops_;
  size_t ops_charged_ = 0;
  uint64_t charged_ = 0;  // bytes of the memory budget held for shapes_ and ops_
  std::vector<Paint> paints_;
  std::vector<Gradient> gradients_;  // Paint::index of gradient paints
  std::vector<Pattern> patterns_;    // Paint::index of pattern paints
  std::vector<Texture> textures_;    // Paint::index of texture paints
  std::vector<Scene> embedded_;      // Op::scene of Append operations
  std::vector<Group> groups_;        // Op::scene of GroupBegin operations
  std::vector<FilterEffect> filters_;  // Paint::index of filter paints
  std::map<std::pair<const Scene*, std::array<double, 6>>, uint32_t> pattern_of_;  // patterns_ by tile and xf
  std::vector<Path> shapes_;
  // The styles of stroke operations (Op::stroke_style): the stroke stage
  // builds them when the scene is rendered (stroker/stroke.h).
  std::vector<StrokeStyle> stroke_styles_;
  std::unordered_map<const Element*, int> shape_of_;
  // Per shape of a path with arcs: the segments that continue an arc
  // command (markers are placed per command; svg_markers.cpp).
  std::unordered_map<uint32_t, std::vector<uint32_t>> arc_continuations_;
};

// Calls f for every operation of ops_[begin, end) that is content: not in
// a clip group's clip section, not in a mask.
template <class F>
void Converter::for_each_content(size_t begin, size_t end, F f) const {
  std::vector<bool> in_clip_section;  // one per open group
  std::vector<bool> is_mask;          // one per open transparency group
  int open_clip_sections = 0, open_masks = 0;
  for (size_t i = begin; i < end; i++) {
    const Op& op = ops_[i];
    switch (op.kind) {
      case OpKind::GroupBegin:
        is_mask.push_back(groups_[op.scene].mask != MaskType::None);
        open_masks += is_mask.back() ? 1 : 0;
        break;
      case OpKind::GroupEnd:
        open_masks -= is_mask.back() ? 1 : 0;
        is_mask.pop_back();
        break;
      case OpKind::Push:
        in_clip_section.push_back(true);
        open_clip_sections++;
        break;
      case OpKind::Activate:
        in_clip_section.back() = false;
        open_clip_sections--;
        break;
      case OpKind::Pop: in_clip_section.pop_back(); break;
      default:
        if (open_clip_sections == 0 && open_masks == 0) f(op);
        break;
    }
  }
}

}  // namespace mpvg::svg::detail
