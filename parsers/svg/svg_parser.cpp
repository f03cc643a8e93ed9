// SVG document -> Scene.
//
// The conversion walks the element tree once, in document order, and writes
// a flat list of operations that mirrors the SceneBuilder calls (push,
// activate, pop, fill, clip). The list exists because a clip group's clip
// items come before its content in the stream, yet clipPathUnits=
// "objectBoundingBox" needs the content's bounding box: an element's content
// is converted first, and its clip prefix is then inserted in front of it.
// Bounds-only operations keep the geometry of shapes that paint nothing
// (fill="none", visibility="hidden", opacity 0), which still counts for
// bounding boxes (SVG 2 coords.html#BoundingBoxes), and are dropped when the scene is built.
#include "parsers/svg/svg_parser.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "core/error.h"
#include "core/parallel.h"
#include "parsers/svg/svg_dom.h"
#include "parsers/svg/svg_geometry.h"
#include "parsers/svg/svg_values.h"
#include "stroker/stroker.h"

namespace mpvg::svg {

namespace {

using namespace detail;

// Nesting of elements plus use and clip-path indirections. tinyxml2 already
// limits the XML depth; references can chain further.
constexpr int kMaxDepth = 256;
// Element instances (after use expansion) converted before giving up, so
// that exponentially nested use references stay bounded.
constexpr size_t kMaxInstances = 1'000'000;

enum class OpKind : uint8_t { Push, Activate, Pop, Fill, Clip, Bounds };

struct Op {
  OpKind kind = OpKind::Bounds;
  FillRule rule = FillRule::NonZero;
  uint32_t shape = 0;  // Fill, Clip, Bounds: index into Converter::shapes_
  uint32_t paint = 0;  // Fill: index into Converter::paints_
  Affine xf;           // Fill, Clip, Bounds: user space to scene
  // Fill: the geometry is a stroke converted to fill geometry. Strokes are
  // not part of an element's object bounding box (SVG 2
  // coords.html#BoundingBoxes), so bounds skip them.
  bool stroke = false;

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

// Computed values of the inherited properties that the scene can express
// (SVG 2 painting, CSS Masking 1 clip-rule; CSS Cascade 4 §7.2 inheritance).
struct Inherited {
  bool fill_none = false;
  RGBA fill{0, 0, 0, 1};  // initial value: black
  FillRule fill_rule = FillRule::NonZero;
  double fill_opacity = 1;
  // Stroke properties (SVG 2 painting.html#StrokeProperties), all inherited;
  // lengths in user units.
  bool stroke_none = true;  // initial value: none
  RGBA stroke{0, 0, 0, 1};
  double stroke_opacity = 1;
  double stroke_width = 1;
  stroke::Join stroke_join = stroke::Join::Miter;
  stroke::Cap stroke_cap = stroke::Cap::Butt;
  double stroke_miterlimit = 4;
  std::vector<double> stroke_dasharray;  // empty: none
  double stroke_dashoffset = 0;
  PaintOrder paint_order = kNormalPaintOrder;
  // font-size in user units (CSS Fonts 4; medium = 16px): em and ex lengths.
  double font_size = 16;
  FillRule clip_rule = FillRule::NonZero;
  bool visible = true;
  RGBA color{0, 0, 0, 1};
};

// What an element is converted in: its parent's computed style and user space.
struct Context {
  Inherited inh;
  Affine ctm;  // the parent's user space to scene units
  // The parent's values of non-inherited properties, for the keyword
  // "inherit" (CSS Cascade 4 §7.3).
  double parent_opacity = 1;
  std::string parent_clip_path;
  bool parent_display_none = false;
  bool in_clip = false;  // converting the content of a clipPath
};

struct Style {
  Inherited inh;
  double opacity = 1;
  std::string clip_path;  // specified value; empty or "none" for no clipping
  bool display_none = false;
  Affine transform;
  bool transform_invalid = false;  // the transform attribute did not parse
  bool non_scaling_stroke = false;  // vector-effect (not inherited)
};

// A property's value on one element.
template <class T>
struct Prop {
  enum State { Unset, Inherit, Set } state = Unset;
  T value{};
};

// The value of property `name` on `e`. Declarations of the style attribute
// win over the presentation attribute (SVG 2 styling.html#PresentationAttributes:
// they count as author style sheet rules of specificity 0, before all others); a
// later declaration wins over an earlier one; a declaration or attribute
// whose value does not parse is ignored (CSS Syntax 3: invalid declarations are dropped), so the
// next candidate applies.
template <class T, class Parse>
Prop<T> property(const Element& e, std::string_view name, Parse parse) {
  Prop<T> p;
  auto accept = [&](const std::string& text) {
    if (iequals(trim(text), "inherit")) {
      p.state = Prop<T>::Inherit;
      return true;
    }
    std::optional<T> v = parse(text);
    if (!v) return false;
    p.state = Prop<T>::Set;
    p.value = std::move(*v);
    return true;
  };
  for (auto it = e.declarations.rbegin(); it != e.declarations.rend(); ++it)
    if (it->first == name && accept(it->second)) return p;
  if (const std::string* a = e.attribute(name)) accept(*a);
  return p;
}

std::optional<FillRule> parse_fill_rule(std::string_view s) {
  s = trim(s);
  if (iequals(s, "nonzero")) return FillRule::NonZero;
  if (iequals(s, "evenodd")) return FillRule::EvenOdd;
  return std::nullopt;
}

std::optional<std::string> parse_keyword(std::string_view s) {
  s = trim(s);
  Scanner sc(s);
  if (s.empty() || sc.word().size() != s.size()) return std::nullopt;
  std::string k(s);
  std::transform(k.begin(), k.end(), k.begin(),
                 [](char c) { return (c >= 'A' && c <= 'Z') ? char(c - 'A' + 'a') : c; });
  return k;
}

// <dasharray> = [ <length> | <percentage> ]# with commas and/or white space
// between values (SVG 2 painting.html#StrokeDasharrayProperty), or none.
// A negative value invalidates the whole list.
template <class ToUser>
std::optional<std::vector<double>> parse_dasharray(std::string_view v, ToUser to_user) {
  v = trim(v);
  std::vector<double> out;
  if (iequals(v, "none")) return out;
  while (!v.empty()) {
    size_t n = 0;
    while (n < v.size() && v[n] != ',' && !is_ws(v[n])) n++;
    const auto l = to_user(v.substr(0, n));
    if (!l || *l < 0) return std::nullopt;
    out.push_back(*l);
    v = trim(v.substr(n));
    if (!v.empty() && v.front() == ',') {
      v = trim(v.substr(1));
      if (v.empty()) return std::nullopt;
    }
  }
  if (out.empty()) return std::nullopt;
  return out;
}

// font-size (CSS Fonts 4 §2.5): an absolute-size keyword (scaled from
// medium = 16px), larger / smaller (a factor of 1.2), or a non-negative
// length or percentage, em, ex and % relative to the parent's size.
std::optional<double> parse_font_size(std::string_view v, double parent) {
  v = trim(v);
  static const struct {
    const char* name;
    double scale;
  } sizes[] = {{"xx-small", 3.0 / 5}, {"x-small", 3.0 / 4}, {"small", 8.0 / 9}, {"medium", 1},
               {"large", 6.0 / 5},    {"x-large", 3.0 / 2}, {"xx-large", 2},      {"xxx-large", 3}};
  for (const auto& k : sizes)
    if (iequals(v, k.name)) return 16 * k.scale;
  if (iequals(v, "larger")) return parent * 1.2;
  if (iequals(v, "smaller")) return parent / 1.2;
  const auto l = parse_length(v);
  if (!l || l->value < 0) return std::nullopt;
  switch (l->unit) {
    case Unit::Em: return l->value * parent;
    case Unit::Ex: return l->value * parent / 2;
    default: return length_to_px(*l, parent);  // % of the parent's size too
  }
}

// paint-order: normal | [ fill || stroke || markers ]; the layers left out
// follow in their normal order (SVG 2 painting.html#PaintOrder).
std::optional<PaintOrder> parse_paint_order(std::string_view v) {
  v = trim(v);
  if (iequals(v, "normal")) return kNormalPaintOrder;
  Scanner s(v);
  std::vector<PaintLayer> given;
  while (!s.at_end()) {
    const std::string_view w = s.word();
    PaintLayer l;
    if (iequals(w, "fill"))
      l = PaintLayer::Fill;
    else if (iequals(w, "stroke"))
      l = PaintLayer::Stroke;
    else if (iequals(w, "markers"))
      l = PaintLayer::Markers;
    else
      return std::nullopt;
    if (std::find(given.begin(), given.end(), l) != given.end()) return std::nullopt;
    given.push_back(l);
    s.skip_ws();
  }
  if (given.empty()) return std::nullopt;
  for (PaintLayer l : kNormalPaintOrder)
    if (std::find(given.begin(), given.end(), l) == given.end()) given.push_back(l);
  return PaintOrder{given[0], given[1], given[2]};
}

bool invertible(const Affine& m) {
  const double v[6] = {m.a, m.b, m.c, m.d, m.e, m.f};
  for (double x : v)
    if (!std::isfinite(x)) return false;
  const double det = m.det();
  return std::isfinite(det) && det != 0;
}

Affine inverse(const Affine& m) {
  const double det = m.det();
  return {m.d / det,
          -m.b / det,
          -m.c / det,
          m.a / det,
          (m.c * m.f - m.d * m.e) / det,
          (m.b * m.e - m.a * m.f) / det};
}

bool same(const Affine& l, const Affine& r) {
  return l.a == r.a && l.b == r.b && l.c == r.c && l.d == r.d && l.e == r.e && l.f == r.f;
}

enum class Kind { Container, Shape, Use, Unsupported, Ignored };

Kind classify(const Element& e) {
  const std::string& n = e.name;
  // `a` is a container as far as rendering goes (SVG 2 linking.html#AElement).
  if (n == "g" || n == "a") return Kind::Container;
  if (n == "svg") return e.parent ? Kind::Unsupported : Kind::Container;
  if (n == "path" || n == "rect" || n == "circle" || n == "ellipse" || n == "line" || n == "polyline" ||
      n == "polygon")
    return Kind::Shape;
  if (n == "use") return Kind::Use;
  if (n == "text" || n == "image" || n == "switch" || n == "foreignObject" || n == "style")
    return Kind::Unsupported;
  // defs, clipPath, symbol, gradients, patterns, masks, filters, markers,
  // metadata, animation...: never rendered directly.
  return Kind::Ignored;
}

bool is_paint_server(const std::string& name) {
  return name == "linearGradient" || name == "radialGradient" || name == "pattern" ||
         name == "meshgradient" || name == "hatch" || name == "solidcolor";
}

// A clip-path value resolved to its target.
struct ClipRef {
  enum State { None, Valid, Invalid } state = None;
  const Element* element = nullptr;
};

class Converter {
 public:
  Converter(const Document& doc, const ParseOptions& options, ParseResult& result)
      : doc_(doc), options_(options), warnings_(result.warnings) {}

  double stroke_seconds() const { return stroke_seconds_; }
  size_t stroked_paths() const { return stroked_paths_; }

  Scene run() {
    const Element& root = *doc_.root;
    // Root viewport (SVG 2 coords.html, "The initial viewport"): width and
    // height default to 100%; percentages resolve against the viewBox size,
    // or against 100 when there is no viewBox (the size of an unsized
    // document).
    std::optional<ViewBox> vb;
    if (const std::string* a = root.attribute("viewBox")) vb = parse_view_box(*a);
    auto side = [&](const char* name, double vb_size) {
      std::optional<Length> l;
      if (const std::string* a = root.attribute(name)) l = parse_length(*a);
      const double base = vb ? vb_size : 100;
      const double v = l ? length_to_px(*l, base) : base;
      if (v < 0)
        throw Error(std::string("invalid root <svg>: negative ") + name + " '" + *root.attribute(name) + "'");
      return v;
    };
    const double width = side("width", vb ? vb->w : 0);
    const double height = side("height", vb ? vb->h : 0);
    SceneBuilder builder(width, height);
    device_ = options_.view ? options_.view(width, height)
                            : Affine::scale(options_.device_scale, options_.device_scale);
    // A zero-sized viewport or viewBox disables rendering (SVG 2 geometry properties
    // width/height, coords.html#ViewBoxAttribute).
    if (width == 0 || height == 0 || (vb && (vb->w == 0 || vb->h == 0))) return builder.finish();

    Context ctx;
    if (vb) {
      AspectRatio ar;
      if (const std::string* a = root.attribute("preserveAspectRatio"))
        ar = parse_aspect_ratio(*a).value_or(ar);
      ctx.ctm = view_box_transform(*vb, ar, width, height);
      percent_w_ = vb->w;
      percent_h_ = vb->h;
    } else {
      percent_w_ = width;
      percent_h_ = height;
    }
    render(root, ctx, 0);
    convert_strokes();
    emit(builder);
    return builder.finish();
  }

 private:
  void warn(std::string msg) {
    if (warned_.insert(msg).second) warnings_.push_back(std::move(msg));
  }

  // Depth and size limits; false when the element must be skipped.
  bool enter(int depth) {
    if (depth > kMaxDepth) {
      warn("nesting deeper than " + std::to_string(kMaxDepth) +
           " levels (elements, use and clip-path references): deeper content ignored");
      return false;
    }
    if (++instances_ > kMaxInstances) {
      warn("more than " + std::to_string(kMaxInstances) +
           " element instances: the rest of the document is ignored");
      return false;
    }
    return true;
  }

  const Element* find(const std::string& id) const {
    const auto it = doc_.ids.find(id);
    return it == doc_.ids.end() ? nullptr : it->second;
  }

  // ------------------------------------------------------------ style

  Style compute_style(const Element& e, const Context& ctx) {
    Style st;
    st.inh = ctx.inh;
    Inherited& inh = st.inh;

    // color first: currentColor in fill refers to this element's color.
    const auto color = property<RGBA>(e, "color", [&](std::string_view v) -> std::optional<RGBA> {
      if (iequals(trim(v), "currentColor")) return ctx.inh.color;  // CSS Color 4: acts as inherit
      return parse_color(v);
    });
    if (color.state == Prop<RGBA>::Set) inh.color = color.value;
    // font-size before any length: em units refer to it. Relative values
    // (em, ex, %, larger, smaller) are relative to the parent's font size.
    const double parent_em = ctx.inh.font_size;
    const auto font_size = property<double>(
        e, "font-size", [&](std::string_view v) -> std::optional<double> { return parse_font_size(v, parent_em); });
    if (font_size.state == Prop<double>::Set) inh.font_size = font_size.value;

    if (!ctx.in_clip) {
      // Inside a clipPath only geometry counts (CSS Masking 1, the clipPath
      // element): fill is moot.
      const auto fill = property<PaintValue>(e, "fill", parse_paint);
      if (fill.state == Prop<PaintValue>::Set) resolve_paint(fill.value, inh.color, inh.fill_none, inh.fill, "fill");
      stroke_style(e, inh, st);
      unsupported_reference(e, "mask", "masks are not supported: mask ignored");
      unsupported_reference(e, "filter", "filters are not supported: filter ignored");
      for (const char* m : {"marker-start", "marker-mid", "marker-end"})
        unsupported_reference(e, m, "markers are not supported: marker ignored");
    }
    if (const auto r = property<FillRule>(e, "fill-rule", parse_fill_rule); r.state == Prop<FillRule>::Set)
      inh.fill_rule = r.value;
    if (const auto o = property<double>(e, "fill-opacity", parse_alpha); o.state == Prop<double>::Set)
      inh.fill_opacity = o.value;
    if (const auto r = property<FillRule>(e, "clip-rule", parse_fill_rule); r.state == Prop<FillRule>::Set)
      inh.clip_rule = r.value;
    const auto vis =
        property<std::string>(e, "visibility", [](std::string_view v) -> std::optional<std::string> {
          auto k = parse_keyword(v);
          if (k && (*k == "visible" || *k == "hidden" || *k == "collapse")) return k;
          return std::nullopt;
        });
    if (vis.state == Prop<std::string>::Set) inh.visible = vis.value == "visible";

    // Non-inherited properties.
    const auto opacity = property<double>(e, "opacity", parse_alpha);
    st.opacity = opacity.state == Prop<double>::Set       ? opacity.value
                 : opacity.state == Prop<double>::Inherit ? ctx.parent_opacity
                                                          : 1.0;
    const auto display = property<std::string>(e, "display", parse_keyword);
    st.display_none = display.state == Prop<std::string>::Set       ? display.value == "none"
                      : display.state == Prop<std::string>::Inherit ? ctx.parent_display_none
                                                                    : false;
    const auto clip = property<std::string>(
        e, "clip-path", [](std::string_view v) { return std::optional<std::string>(std::string(trim(v))); });
    st.clip_path = clip.state == Prop<std::string>::Set       ? clip.value
                   : clip.state == Prop<std::string>::Inherit ? ctx.parent_clip_path
                                                              : std::string();
    // transform is a presentation attribute in SVG 2 (CSS Transforms 1); an unparsable
    // value is ignored like any invalid declaration.
    const auto xf = property<Affine>(e, "transform", parse_transform);
    if (xf.state == Prop<Affine>::Set) st.transform = xf.value;
    st.transform_invalid = xf.state == Prop<Affine>::Unset && (e.attribute("transform") != nullptr);
    return st;
  }

  // The stroke properties of `e` (SVG 2 painting.html#StrokeProperties),
  // over the inherited values in `inh`. Invalid values are ignored like any
  // invalid declaration: a negative width or dash, a miter limit below 1.
  void stroke_style(const Element& e, Inherited& inh, Style& st) {
    const auto stroke = property<PaintValue>(e, "stroke", parse_paint);
    if (stroke.state == Prop<PaintValue>::Set)
      resolve_paint(stroke.value, inh.color, inh.stroke_none, inh.stroke, "stroke");
    if (const auto o = property<double>(e, "stroke-opacity", parse_alpha); o.state == Prop<double>::Set)
      inh.stroke_opacity = o.value;
    // Lengths that are neither horizontal nor vertical: percentages of the
    // normalised viewport diagonal (SVG 2 coords.html#Units).
    auto user_length = [&](std::string_view v) -> std::optional<double> {
      const auto l = parse_length(v);
      if (!l) return std::nullopt;
      return to_user(*l, Axis::Diagonal, inh.font_size);
    };
    const auto width = property<double>(e, "stroke-width", [&](std::string_view v) -> std::optional<double> {
      const auto w = user_length(v);
      if (!w || *w < 0) return std::nullopt;
      return w;
    });
    if (width.state == Prop<double>::Set) inh.stroke_width = width.value;
    const auto join = property<stroke::Join>(e, "stroke-linejoin", [](std::string_view v) {
      std::optional<stroke::Join> none;
      const auto k = parse_keyword(v);
      if (!k) return none;
      if (*k == "miter") return std::optional(stroke::Join::Miter);
      if (*k == "miter-clip") return std::optional(stroke::Join::MiterClip);
      if (*k == "round") return std::optional(stroke::Join::Round);
      if (*k == "bevel") return std::optional(stroke::Join::Bevel);
      if (*k == "arcs") return std::optional(stroke::Join::Arcs);
      return none;
    });
    if (join.state == Prop<stroke::Join>::Set) inh.stroke_join = join.value;
    const auto cap = property<stroke::Cap>(e, "stroke-linecap", [](std::string_view v) -> std::optional<stroke::Cap> {
      const auto k = parse_keyword(v);
      if (!k) return std::nullopt;
      if (*k == "butt") return stroke::Cap::Butt;
      if (*k == "round") return stroke::Cap::Round;
      if (*k == "square") return stroke::Cap::Square;
      return std::nullopt;
    });
    if (cap.state == Prop<stroke::Cap>::Set) inh.stroke_cap = cap.value;
    // A <number> of at least 1 (SVG 2 painting.html#StrokeMiterlimitProperty); "5mm" is not one.
    const auto ml = property<double>(e, "stroke-miterlimit", [](std::string_view v) -> std::optional<double> {
      const auto n = parse_number(v);
      if (!n || *n < 1) return std::nullopt;
      return n;
    });
    if (ml.state == Prop<double>::Set) inh.stroke_miterlimit = ml.value;
    const auto dashes = property<std::vector<double>>(e, "stroke-dasharray", [&](std::string_view v) {
      return parse_dasharray(v, user_length);
    });
    if (dashes.state == Prop<std::vector<double>>::Set) inh.stroke_dasharray = dashes.value;
    if (const auto o = property<double>(e, "stroke-dashoffset", user_length); o.state == Prop<double>::Set)
      inh.stroke_dashoffset = o.value;
    if (const auto po = property<PaintOrder>(e, "paint-order", parse_paint_order); po.state == Prop<PaintOrder>::Set)
      inh.paint_order = po.value;
    // vector-effect is not inherited (SVG 2 coords.html#VectorEffects); of its values only
    // non-scaling-stroke concerns what we draw.
    const auto ve = property<std::string>(e, "vector-effect", parse_keyword);
    st.non_scaling_stroke = ve.state == Prop<std::string>::Set && ve.value == "non-scaling-stroke";
  }

  void unsupported_reference(const Element& e, const char* name, const char* message) {
    const auto v = property<std::string>(
        e, name, [](std::string_view t) { return std::optional<std::string>(std::string(trim(t))); });
    if (v.state == Prop<std::string>::Set && !iequals(v.value, "none")) warn(message);
  }

  // Resolves a fill or stroke paint (SVG 2 painting.html#SpecifyingPaint)
  // into `none` and `color`; `current` is the element's color, for
  // currentColor. `what` names the property in warnings.
  void resolve_paint(const PaintValue& p, const RGBA& current, bool& none, RGBA& color, const std::string& what) {
    auto solid = [&](const RGBA& c) {
      none = false;
      color = c;
    };
    switch (p.kind) {
      case PaintValue::Kind::None: none = true; return;
      case PaintValue::Kind::Color: solid(p.color); return;
      case PaintValue::Kind::CurrentColor: solid(current); return;
      case PaintValue::Kind::Context:
        warn("context-fill and context-stroke paints are not supported: " + what + " not rendered");
        none = true;
        return;
      case PaintValue::Kind::Url: break;
    }
    const Element* target = p.url_external ? nullptr : find(p.url);
    if (p.url_external) warn("references to other documents are not supported: " + what + " falls back");
    if (target && !is_paint_server(target->name)) {
      // A reference to an element that cannot paint (SVG 2 painting.html#SpecifyingPaint): the
      // paint is not rendered, fallback or not (as resvg does).
      none = true;
      return;
    }
    const bool has_fallback =
        p.fallback == PaintValue::Fallback::Color || p.fallback == PaintValue::Fallback::CurrentColor;
    if (target) {
      warn(has_fallback ? "gradients and patterns are not supported: painted with the fallback colour"
                        : "gradients and patterns are not supported: " + what + " not rendered");
    }
    // A missing paint server uses the fallback, and without one paints
    // nothing (SVG 2 painting.html#SpecifyingPaint).
    switch (p.fallback) {
      case PaintValue::Fallback::Color: solid(p.fallback_color); return;
      case PaintValue::Fallback::CurrentColor: solid(current); return;
      default: none = true; return;
    }
  }

  Context child_context(const Style& st, const Affine& space, bool in_clip) const {
    Context c;
    c.inh = st.inh;
    c.ctm = space;
    c.parent_opacity = st.opacity;
    c.parent_clip_path = st.clip_path;
    c.parent_display_none = st.display_none;
    c.in_clip = in_clip;
    return c;
  }

  // Resolves a clip-path value. Following resvg (and the suite's
  // masking/clipPath tests): a reference to a missing element or a reference
  // cycle is ignored (the element is drawn unclipped); a reference to an
  // element that is not a clipPath makes the element invisible. Other values
  // (CSS basic shapes) are not supported and ignored.
  ClipRef resolve_clip(const std::string& value) {
    ClipRef r;
    if (value.empty() || iequals(value, "none")) return r;
    Scanner s(value);
    bool external = false;
    const auto id = parse_func_iri(s, &external);
    s.skip_ws();
    if (!id || !s.at_end()) {
      warn("clip-path values other than url(#id) are not supported: clip-path ignored");
      return r;
    }
    if (external) {
      warn("references to other documents are not supported: clip-path ignored");
      return r;
    }
    const Element* target = find(*id);
    if (!target) return r;
    if (target->name != "clipPath") {
      r.state = ClipRef::Invalid;
      return r;
    }
    if (std::find(active_clips_.begin(), active_clips_.end(), target) != active_clips_.end()) {
      warn("recursive clip-path reference ignored");
      return r;
    }
    r.state = ClipRef::Valid;
    r.element = target;
    return r;
  }

  // The element a use references (SVG 2 struct.html#UseElement); nullptr when missing or when
  // the reference would recurse. href wins over xlink:href (SVG 2 linking.html#XLinkRefAttrs).
  const Element* use_target(const Element& use) {
    const std::string* href = use.attribute("href");
    if (!href) href = use.attribute("xlink:href");
    if (!href) return nullptr;
    const auto id = parse_iri_fragment(*href);
    if (!id) {
      if (!trim(*href).empty()) warn("references to other documents are not supported: use ignored");
      return nullptr;
    }
    const Element* t = find(*id);
    if (!t) return nullptr;
    if (t == &use || std::find(active_.begin(), active_.end(), t) != active_.end()) {
      warn("recursive use reference ignored");
      return nullptr;
    }
    // A use of an ancestor of itself recurses as well.
    for (const Element* a = use.parent; a; a = a->parent) {
      if (a == t) {
        warn("recursive use reference ignored");
        return nullptr;
      }
    }
    if (t->name == "symbol" || t->name == "svg") {
      warn("use of <" + t->name + "> is not supported: ignored");
      return nullptr;
    }
    return t;
  }

  Affine use_offset(const Element& use, double em) {
    return Affine::translate(length(use, "x", Axis::X, 0, em), length(use, "y", Axis::Y, 0, em));
  }

  // ------------------------------------------------------------ geometry

  enum class Axis { X, Y, Diagonal };

  // What 100% stands for along `axis`: the viewport, i.e. the viewBox when
  // there is one (SVG 2 coords.html#Units); diagonal lengths such as r use
  // sqrt((w^2 + h^2) / 2).
  double percent_base(Axis axis) const {
    switch (axis) {
      case Axis::X: return percent_w_;
      case Axis::Y: return percent_h_;
      default: return std::sqrt((percent_w_ * percent_w_ + percent_h_ * percent_h_) / 2);
    }
  }

  // A length in user units, em and ex relative to the element's font size
  // `em` (ex is taken as half an em: fonts are not modelled).
  double to_user(const Length& l, Axis axis, double em) const {
    if (l.unit == Unit::Em) return l.value * em;
    if (l.unit == Unit::Ex) return l.value * em / 2;
    return length_to_px(l, percent_base(axis));
  }

  // A length attribute in user units; `def` when absent or invalid.
  double length(const Element& e, const char* name, Axis axis, double def, double em) const {
    const std::string* a = e.attribute(name);
    if (!a) return def;
    const auto l = parse_length(*a);
    return l ? to_user(*l, axis, em) : def;
  }

  // A length that may be "auto" (rect rx/ry, ellipse rx/ry in SVG 2): absent,
  // "auto", invalid or negative values all mean auto (nullopt).
  std::optional<double> auto_length(const Element& e, const char* name, Axis axis, double em) const {
    const std::string* a = e.attribute(name);
    if (!a || !parse_length(*a)) return std::nullopt;
    const double v = length(e, name, axis, 0, em);
    if (v < 0) return std::nullopt;
    return v;
  }

  // The element's geometry, built once; -1 when it has none (invalid sizes,
  // empty path data).
  // The font size `em` of the first instance converted applies to all (em
  // lengths in shapes reused with different font sizes are rare).
  int shape_index(const Element& e, double em) {
    const auto it = shape_of_.find(&e);
    if (it != shape_of_.end()) return it->second;
    std::optional<Path> p = build_shape(e, em);
    int index = -1;
    // Zero-length subpaths ("M p Z") have no segments but are stroked.
    if (p && !p->contours().empty()) {
      index = static_cast<int>(shapes_.size());
      shapes_.push_back(std::move(*p));
    }
    shape_of_.emplace(&e, index);
    return index;
  }

  std::optional<Path> build_shape(const Element& e, double em) const {
    const std::string& n = e.name;
    if (n == "path") {
      const std::string* d = e.attribute("d");
      if (!d) return std::nullopt;
      Path p;
      parse_path_data(*d, p);  // on an error, what came before it is kept
      return p;
    }
    if (n == "rect") {
      // SVG 2 shapes.html#RectElement: width/height "auto" (absent) or <= 0
      // disable rendering; an auto radius takes the other's value, both auto
      // mean square corners, and each is clamped to half the side.
      const double w = length(e, "width", Axis::X, 0, em), h = length(e, "height", Axis::Y, 0, em);
      if (!(w > 0 && h > 0)) return std::nullopt;
      auto rx = auto_length(e, "rx", Axis::X, em), ry = auto_length(e, "ry", Axis::Y, em);
      if (!rx) rx = ry;
      if (!ry) ry = rx;
      const double crx = std::min(rx.value_or(0), w / 2), cry = std::min(ry.value_or(0), h / 2);
      return rect_path(length(e, "x", Axis::X, 0, em), length(e, "y", Axis::Y, 0, em), w, h, crx, cry);
    }
    if (n == "circle") {
      const double r = length(e, "r", Axis::Diagonal, 0, em);
      if (!(r > 0)) return std::nullopt;
      return ellipse_path(length(e, "cx", Axis::X, 0, em), length(e, "cy", Axis::Y, 0, em), r, r);
    }
    if (n == "ellipse") {
      // SVG 2 shapes.html#EllipseElement: an auto radius takes the other's value.
      auto rx = auto_length(e, "rx", Axis::X, em), ry = auto_length(e, "ry", Axis::Y, em);
      if (!rx) rx = ry;
      if (!ry) ry = rx;
      if (!rx || !(*rx > 0) || !(*ry > 0)) return std::nullopt;
      return ellipse_path(length(e, "cx", Axis::X, 0, em), length(e, "cy", Axis::Y, 0, em), *rx, *ry);
    }
    if (n == "line") {
      return line_path({length(e, "x1", Axis::X, 0, em), length(e, "y1", Axis::Y, 0, em)},
                       {length(e, "x2", Axis::X, 0, em), length(e, "y2", Axis::Y, 0, em)});
    }
    if (n == "polyline" || n == "polygon") {
      const std::string* pts = e.attribute("points");
      if (!pts) return std::nullopt;
      return poly_path(parse_points(*pts), n == "polygon");
    }
    return std::nullopt;
  }

  // ------------------------------------------------------------ rendering

  // Converts a rendered element (and its subtree) in painter's order.
  // What rendering an element (or a clipPath child) needs, resolved once:
  // its style, the space its content lives in, a use's target, its clip.
  // False when the element shows nothing.
  struct Placed {
    Style st;
    Affine space;
    const Element* target = nullptr;
    ClipRef clip;
  };
  bool place(const Element& e, Kind kind, const Context& ctx, Placed& out) {
    out.st = compute_style(e, ctx);
    if (out.st.display_none) return false;
    out.space = ctx.ctm * out.st.transform;
    if (kind == Kind::Use) {
      out.target = use_target(e);
      if (!out.target) return false;
      // The use's x/y are an extra translation after its transform (SVG 1.1
      // §5.6); clip-path and bounding box live in that translated space.
      out.space = out.space * use_offset(e, out.st.inh.font_size);
    }
    // A non-invertible transform makes everything degenerate: nothing shows.
    if (!invertible(out.space)) return false;
    out.clip = resolve_clip(out.st.clip_path);
    return out.clip.state != ClipRef::Invalid;
  }

  void render(const Element& e, const Context& ctx, int depth) {
    const Kind kind = classify(e);
    if (kind == Kind::Ignored) return;
    if (kind == Kind::Unsupported) {
      if (e.name == "style")
        warn("<style> sheets are not supported: ignored");
      else if (e.name == "svg")
        warn("nested <svg> elements are not supported: ignored");
      else
        warn("<" + e.name + "> elements are not supported: ignored");
      return;
    }
    if (!enter(depth)) return;
    Placed pl;
    if (!place(e, kind, ctx, pl)) return;
    const auto& [st, space, target, clip] = pl;

    const size_t start = ops_.size();
    const Context inner = child_context(st, space, false);
    active_.push_back(&e);
    switch (kind) {
      case Kind::Container:
        for (const auto& c : e.children) render(*c, inner, depth + 1);
        break;
      case Kind::Use: render(*target, inner, depth + 1); break;
      default: shape_paint(e, st, space); break;
    }
    active_.pop_back();

    apply_opacity(start, st.opacity);
    if (clip.state == ClipRef::Valid) clip_content(start, *clip.element, space, depth);
  }

  // A shape's fill and stroke, in the order of paint-order. The fill
  // operation is always there (as bounds only when it paints nothing): it
  // carries the shape's bounding box.
  void shape_paint(const Element& e, const Style& st, const Affine& space) {
    const int shape = shape_index(e, st.inh.font_size);
    if (shape < 0) return;
    Op fill = Op::of(OpKind::Bounds);
    fill.shape = static_cast<uint32_t>(shape);
    fill.xf = space;
    fill.rule = st.inh.fill_rule;
    // A line encloses no area (SVG 2 shapes.html#LineElement): it can only
    // be stroked.
    const bool fills = e.name != "line" && !shapes_[shape].empty() && !st.inh.fill_none && st.inh.visible &&
                       st.inh.fill.a * st.inh.fill_opacity > 0;
    if (fills) {
      Paint paint;
      paint.color = st.inh.fill;
      paint.opacity = static_cast<float>(st.inh.fill_opacity);
      paints_.push_back(paint);
      fill.kind = OpKind::Fill;
      fill.paint = static_cast<uint32_t>(paints_.size() - 1);
    }
    const std::optional<Op> stroke = shape_stroke(static_cast<uint32_t>(shape), st, space);
    // Markers are not supported; only fill and stroke order matters.
    for (PaintLayer l : st.inh.paint_order) {
      if (l == PaintLayer::Fill) ops_.push_back(fill);
      if (l == PaintLayer::Stroke && stroke) ops_.push_back(*stroke);
    }
  }

  // The stroke of shapes_[shape] as a filled path (nonzero) with the stroke
  // paint, or nothing when it paints nothing (SVG 2 painting.html#StrokeProperties:
  // stroke none, zero width, invisible or fully transparent). The outline
  // itself is computed later, with all others, by convert_strokes().
  std::optional<Op> shape_stroke(uint32_t shape, const Style& st, const Affine& space) {
    const Inherited& inh = st.inh;
    if (inh.stroke_none || !inh.visible || !(inh.stroke_width > 0) || !(inh.stroke.a * inh.stroke_opacity > 0))
      return std::nullopt;
    StrokeJob job;
    job.source = shape;
    job.style.join = inh.stroke_join;
    job.style.cap = inh.stroke_cap;
    job.style.miter_limit = inh.stroke_miterlimit;
    job.style.dashes = inh.stroke_dasharray;
    job.style.dash_offset = inh.stroke_dashoffset;
    Op op = Op::of(OpKind::Fill);
    op.stroke = true;
    op.rule = FillRule::NonZero;
    // Device pixels for tolerances and hairlines: the scene as the parse
    // options expect it to be rendered.
    stroke::Hairline hl;
    if (st.non_scaling_stroke) {
      // vector-effect: non-scaling-stroke: the stroke is computed in the
      // host coordinate space, here scene units (SVG 2 coords.html#VectorEffects).
      hl = stroke::hairline(inh.stroke_width, device_);
      job.device = device_;
      job.transform_first = true;
      job.space = space;
      op.xf = Affine{};
    } else {
      hl = stroke::hairline(inh.stroke_width, device_ * space);
      job.device = device_ * space;
      op.xf = space;
    }
    job.style.width = hl.width;
    job.out = static_cast<uint32_t>(shapes_.size());
    shapes_.emplace_back();
    op.shape = job.out;
    stroke_jobs_.push_back(std::move(job));
    Paint paint;
    paint.color = inh.stroke;
    paint.opacity = static_cast<float>(inh.stroke_opacity * hl.opacity);
    paints_.push_back(paint);
    op.paint = static_cast<uint32_t>(paints_.size() - 1);
    return op;
  }

  // Converts every stroke to fill geometry, in parallel. A stroke is the
  // union of its subpaths' strokes, each dashed from the start of the
  // pattern (SVG 2 painting.html#StrokeDashing), so a path of several
  // subpaths is stroked one subpath per task (one long stroke does not hold
  // up the others) and the pieces are concatenated in order: the result is
  // the same geometry as stroking it whole. A stroke that comes out empty
  // paints nothing.
  void convert_strokes() {
    const auto t0 = std::chrono::steady_clock::now();
    struct Task {
      uint32_t job;
      int64_t contour;  // -1: the whole source
    };
    std::vector<Task> tasks;
    std::vector<size_t> first_task(stroke_jobs_.size() + 1);
    for (uint32_t j = 0; j < stroke_jobs_.size(); j++) {
      first_task[j] = tasks.size();
      const size_t n = shapes_[stroke_jobs_[j].source].contours().size();
      if (n <= 1)
        tasks.push_back({j, -1});
      else
        for (size_t c = 0; c < n; c++) tasks.push_back({j, static_cast<int64_t>(c)});
    }
    first_task[stroke_jobs_.size()] = tasks.size();
    std::vector<Path> pieces(tasks.size());
    parallel_for(tasks.size(), 0, [&](size_t i) {
      const StrokeJob& job = stroke_jobs_[tasks[i].job];
      const Path& whole = shapes_[job.source];
      const Path part = tasks[i].contour < 0 ? Path{} : whole.contour_path(static_cast<size_t>(tasks[i].contour));
      const Path& source = tasks[i].contour < 0 ? whole : part;
      pieces[i] = job.transform_first
                      ? stroke::stroke_to_fill(stroke::transformed(source, job.space), job.style, job.device)
                      : stroke::stroke_to_fill(source, job.style, job.device);
    });
    for (size_t j = 0; j < stroke_jobs_.size(); j++) {
      Path& out = shapes_[stroke_jobs_[j].out];
      out = std::move(pieces[first_task[j]]);
      for (size_t i = first_task[j] + 1; i < first_task[j + 1]; i++) out.append(pieces[i]);
    }
    stroke_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stroked_paths_ = stroke_jobs_.size();
    for (Op& op : ops_)
      if (op.kind == OpKind::Fill && op.stroke && shapes_[op.shape].empty()) op.kind = OpKind::Bounds;
  }

  // Element opacity multiplies into the paints below it. For one shape that
  // is exact; for a group it is not (SVG 2 render.html
  // #ObjectAndGroupOpacityProperties composites the group as a whole, so
  // overlapping children do not show through each other), which the scene
  // cannot express yet.
  void apply_opacity(size_t start, double opacity) {
    if (opacity >= 1) return;
    size_t fills = 0;
    for (size_t i = start; i < ops_.size(); i++) {
      Op& op = ops_[i];
      if (op.kind != OpKind::Fill) continue;
      Paint& p = paints_[op.paint];
      p.opacity = static_cast<float>(p.opacity * opacity);
      if (p.opacity * p.color.a > 0)
        fills++;
      else
        op.kind = OpKind::Bounds;
    }
    if (fills > 1) warn("group opacity applied per shape");
  }

  // Calls f for each operation in ops_[begin, end) that is content: a Fill,
  // Clip or Bounds outside every clip section (between a push and its
  // activate). In a clipPath the content is made of Clip operations.
  template <class F>
  void for_each_content(size_t begin, size_t end, F f) const {
    std::vector<bool> in_clip_section;  // one per open group
    int open_clip_sections = 0;
    for (size_t i = begin; i < end; i++) {
      const Op& op = ops_[i];
      switch (op.kind) {
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
          if (open_clip_sections == 0) f(op);
          break;
      }
    }
  }

  // The tight bounding box of the content in ops_[begin, end), in the user
  // space `space`.
  Bounds content_bounds(size_t begin, size_t end, const Affine& space) const {
    Bounds b;
    const Affine inv = inverse(space);
    for_each_content(begin, end, [&](const Op& op) {
      if (op.stroke) return;
      add_path_bounds(shapes_[op.shape], same(op.xf, space) ? Affine{} : inv * op.xf, b);
    });
    return b;
  }

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

  // Wraps the element content in ops_[start, end) into a clip group of clip
  // path `cp`: push, the clip items, activate, the content, pop. An invalid
  // clip path removes the content (the element is not rendered).
  void clip_content(size_t start, const Element& cp, const Affine& space, int depth) {
    const size_t end = ops_.size();
    LazyBounds bbox{*this, start, end, space, std::nullopt};
    ops_.push_back(Op::of(OpKind::Push));
    if (!clip_items(cp, space, bbox, depth + 1)) {
      ops_.resize(start);
      return;
    }
    ops_.push_back(Op::of(OpKind::Activate));
    bool draws = false;
    for_each_content(start, end, [&](const Op& op) { draws = draws || op.kind != OpKind::Bounds; });
    if (!draws) {
      // Nothing to clip; keep the bounds-only content for enclosing boxes.
      ops_.resize(end);
      return;
    }
    std::rotate(ops_.begin() + static_cast<ptrdiff_t>(start), ops_.begin() + static_cast<ptrdiff_t>(end),
                ops_.end());
    ops_.push_back(Op::of(OpKind::Pop));
  }

  // Appends the clip items of clipPath `cp` (CSS Masking 1, the clipPath
  // element) applied to an element with user space `space`: a clip test per
  // rendered child shape, wrapped in a group intersecting it with cp's own
  // clip-path if any. Returns false when the clip path is invalid.
  bool clip_items(const Element& cp, const Affine& space, LazyBounds& bbox, int depth) {
    if (!enter(depth)) return false;
    // Properties inherit into a clipPath from its document ancestors, not
    // from the element that references it.
    Context ctx;
    ctx.in_clip = true;
    std::vector<const Element*> chain;
    for (const Element* a = cp.parent; a; a = a->parent) chain.push_back(a);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it)
      ctx = child_context(compute_style(**it, ctx), {}, true);
    const Style st = compute_style(cp, ctx);
    // An unparsable or degenerate transform invalidates the clip path (resvg).
    if (st.transform_invalid || !invertible(st.transform)) return false;

    Affine base = space * st.transform;
    const std::string* units = cp.attribute("clipPathUnits");
    if (units && trim(*units) == "objectBoundingBox") {
      // Content coordinates are fractions of the clipped element's bounding
      // box (clipPathUnits); a box with no area makes the reference invalid.
      const Bounds& b = bbox.get();
      if (b.empty() || !(b.width() > 0) || !(b.height() > 0)) return false;
      base = base * Affine{b.width(), 0, 0, b.height(), b.x0, b.y0};
    }
    if (!invertible(base)) return false;

    active_clips_.push_back(&cp);
    const ClipRef nested = resolve_clip(st.clip_path);
    bool ok = nested.state != ClipRef::Invalid;
    if (ok && nested.state == ClipRef::Valid) {
      // clip-path on the clipPath itself intersects, in the user space of
      // the clipped element.
      ops_.push_back(Op::of(OpKind::Push));
      ok = clip_items(*nested.element, space, bbox, depth + 1);
      if (ok) ops_.push_back(Op::of(OpKind::Activate));
    }
    if (ok) {
      const Context inner = child_context(st, base, true);
      for (const auto& c : cp.children) clip_child(*c, inner, depth + 1);
      if (nested.state == ClipRef::Valid) ops_.push_back(Op::of(OpKind::Pop));
    }
    active_clips_.pop_back();
    return ok;
  }

  // One child of a clipPath: a shape, or a use of one (CSS Masking 1 content
  // model); groups and everything else are not valid children.
  void clip_child(const Element& e, const Context& ctx, int depth) {
    const Kind kind = classify(e);
    if (kind != Kind::Shape && kind != Kind::Use) {
      if (e.name == "text") warn("<text> elements are not supported: ignored");
      return;
    }
    if (e.name == "line") return;  // no area
    if (!enter(depth)) return;
    Placed pl;
    if (!place(e, kind, ctx, pl)) return;
    const auto& [st, space, target, clip] = pl;

    const size_t start = ops_.size();
    if (kind == Kind::Use) {
      active_.push_back(&e);
      clip_child(*target, child_context(st, space, true), depth + 1);
      active_.pop_back();
    } else {
      const int shape = shape_index(e, st.inh.font_size);
      // A shape without segments ("M p Z") has no area to clip with.
      if (shape < 0 || !st.inh.visible || shapes_[shape].empty()) return;
      Op op = Op::of(OpKind::Clip);
      op.shape = static_cast<uint32_t>(shape);
      op.xf = space;
      op.rule = st.inh.clip_rule;
      ops_.push_back(op);
    }
    if (clip.state == ClipRef::Valid && ops_.size() > start) clip_content(start, *clip.element, space, depth);
  }

  // ------------------------------------------------------------ output

  void emit(SceneBuilder& b) {
    std::vector<int64_t> geometry(shapes_.size(), -1);
    auto geometry_of = [&](uint32_t shape) {
      if (geometry[shape] < 0) geometry[shape] = b.add_geometry(std::move(shapes_[shape]));
      return static_cast<uint32_t>(geometry[shape]);
    };
    for (const Op& op : ops_) {
      switch (op.kind) {
        case OpKind::Push: b.push(); break;
        case OpKind::Activate: b.activate(); break;
        case OpKind::Pop: b.pop(); break;
        case OpKind::Fill: b.fill(geometry_of(op.shape), op.xf, op.rule, paints_[op.paint]); break;
        case OpKind::Clip: b.clip(geometry_of(op.shape), op.xf, op.rule); break;
        case OpKind::Bounds: break;
      }
    }
  }

  const Document& doc_;
  const ParseOptions& options_;
  Affine device_;  // scene units to output pixels (ParseOptions::view)
  std::vector<std::string>& warnings_;
  std::unordered_set<std::string> warned_;
  double percent_w_ = 100, percent_h_ = 100;

  std::vector<Op> ops_;
  std::vector<Paint> paints_;
  std::vector<Path> shapes_;
  // A stroke waiting for convert_strokes(): shapes_[source] stroked with
  // `style` into shapes_[out]; with transform_first (non-scaling-stroke)
  // the source is mapped by `space` first. `device` maps the stroked
  // geometry to output pixels.
  struct StrokeJob {
    uint32_t source = 0, out = 0;
    stroke::Style style;
    Affine device, space;
    bool transform_first = false;
  };
  std::vector<StrokeJob> stroke_jobs_;
  std::unordered_map<const Element*, int> shape_of_;
  std::vector<const Element*> active_;        // elements being converted (use cycles)
  std::vector<const Element*> active_clips_;  // clipPaths being expanded (clip-path cycles)
  size_t instances_ = 0;
  double stroke_seconds_ = 0;
  size_t stroked_paths_ = 0;
};

}  // namespace

ParseResult parse_svg_string(std::string_view text, [[maybe_unused]] const std::string& base_dir,
                             const ParseOptions& options) {
  const Document doc = parse_document(text);
  ParseResult result;
  Converter conv(doc, options, result);
  result.scene = conv.run();
  result.stroke_seconds = conv.stroke_seconds();
  result.stroked_paths = conv.stroked_paths();
  return result;
}

ParseResult parse_svg_file(const std::string& path, const ParseOptions& options) {
  auto fail = [&](int err) { return Error("cannot read '" + path + "': " + std::strerror(err)); };
  FILE* f = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
  if (!f) throw fail(errno);
  std::string data;
  char buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, n);
  const bool failed = std::ferror(f);
  const int err = errno;
  if (f != stdin) std::fclose(f);
  if (failed) throw fail(err);
  const std::filesystem::path dir =
      path == "-" ? std::filesystem::path() : std::filesystem::path(path).parent_path();
  return parse_svg_string(data, dir.empty() ? std::string(".") : dir.string(), options);
}

ParseOptions ParseOptions::at_width(int pixels) {
  ParseOptions o;
  o.view = [pixels](double w, double h) {
    const double height = std::max(1.0, std::round(h * pixels / w));
    return Affine::scale(pixels / w, height / h);
  };
  return o;
}

}  // namespace mpvg::svg
