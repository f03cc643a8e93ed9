// SVG document -> Scene: the entry points, the document walk (containers,
// shapes, use), clip paths, and emission into the SceneBuilder. The
// Converter class and the shape of the conversion are described in
// svg_converter.h.
#include "parsers/svg/svg_parser.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <sys/stat.h>

#include "core/error.h"
#include "core/memory_budget.h"
#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_resources.h"
#include "parsers/svg/svg_style.h"
#include "parsers/svg/svg_css.h"
#include "frame/scene_builder.h"

namespace mpvg::svg {

namespace detail {

bool same(const Affine& l, const Affine& r) {
  return l.a == r.a && l.b == r.b && l.c == r.c && l.d == r.d && l.e == r.e && l.f == r.f;
}

Kind classify(const Element& e) {
  const std::string& n = e.name;
  // `a` is a container as far as rendering goes (SVG 2 linking.html#AElement).
  if (n == "g" || n == "a" || n == "switch") return Kind::Container;
  if (n == "svg") return Kind::Container;
  if (n == "path" || n == "rect" || n == "circle" || n == "ellipse" || n == "line" || n == "polyline" ||
      n == "polygon")
    return Kind::Shape;
  if (n == "use") return Kind::Use;
  if (n == "image") return Kind::Image;
#if MPVG_HAVE_TEXT
  if (n == "text") return Kind::Text;
#endif
  if (n == "text" || n == "foreignObject") return Kind::Unsupported;
  // defs, clipPath, symbol, gradients, patterns, masks, filters, markers,
  // metadata, animation...: never rendered directly.
  return Kind::Ignored;
}

Scene Converter::run() {
  const Element& root = *s_.doc.root;
  // Root viewport (SVG 2 coords.html, "The initial viewport"): width and
  // height default to 100%; percentages resolve against the viewBox size,
  // or against 100 when there is no viewBox (the size of an unsized
  // document).
  if (const std::string* v = root.attribute("version")) s_.svg1 = trim(*v).substr(0, 2) == "1.";
  std::optional<ViewBox> vb;
  if (const std::string* a = root.attribute("viewBox")) vb = parse_view_box(*a);
  auto side = [&](const char* name, double vb_size) {
    std::optional<Length> l;
    if (const std::string* a = root.attribute(name)) l = parse_length(*a);
    const double base = vb ? vb_size : 100;
    const double v = l ? length_to_px(*l, base) : base;
    if (v < 0)
      throw ParseError(std::string("invalid root <svg>: negative ") + name + " '" + *root.attribute(name) + "'");
    return v;
  };
  const double width = side("width", vb ? vb->w : 0);
  const double height = side("height", vb ? vb->h : 0);
  SceneBuilder builder(width, height);
  scene_w_ = width;
  scene_h_ = height;
  device_ = s_.options.view ? s_.options.view(width, height)
                            : Affine::scale(s_.options.device_scale, s_.options.device_scale);
  // A zero-sized viewport or viewBox disables rendering (SVG 2 geometry properties
  // width/height, coords.html#ViewBoxAttribute).
  if (width == 0 || height == 0 || (vb && (vb->w == 0 || vb->h == 0))) return builder.finish();

  Context ctx;
  if (vb) {
    AspectRatio ar;
    if (const std::string* a = root.attribute("preserveAspectRatio"))
      ar = parse_aspect_ratio(*a).value_or(ar);
    ctx.ctm = view_box_transform(*vb, ar, width, height);
    s_.percent_w = vb->w;
    s_.percent_h = vb->h;
  } else {
    s_.percent_w = width;
    s_.percent_h = height;
  }
  // background-color on the root (CSS Backgrounds 3, as browsers paint
  // the root element's background): the whole viewport, under everything.
  if (const auto bg = property<RGBA>(root, "background-color", [](std::string_view v) { return parse_color(v); });
      !s_.export_target && bg.state == Prop<RGBA>::Set && bg.value.a > 0) {
    Paint paint;
    paint.color = bg.value;
    paints_.push_back(paint);
    Op fill = Op::of(OpKind::Fill);
    fill.shape = rect_shape({0, 0, width, height});
    fill.paint = static_cast<uint32_t>(paints_.size() - 1);
    ops_.push_back(fill);
  }
  render(root, ctx, 0);
  if (s_.export_target) s_.export_box = drawn_bounds(0, ops_.size());
  emit(builder);
  Scene scene = builder.finish();
  if (builder.flattened_groups()) warn(flattened_groups_warning(builder.flattened_groups()));
  return scene;
}

void Converter::warn(std::string msg) const {
  if (s_.warned.insert(msg).second) s_.warnings.push_back(std::move(msg));
}

Converter::~Converter() {
  if (s_.options.budget) s_.options.budget->release(charged_);
}

void Converter::add_shape(Path p) {
  if (MemoryBudget* b = s_.options.budget.get()) {
    const uint64_t n = path_bytes(p);
    b->charge(n, "the document's shapes");
    charged_ += n;
  }
  shapes_.push_back(std::move(p));
}

void Converter::charge_ops() {
  MemoryBudget* b = s_.options.budget.get();
  // (Its capacity: what the array holds, grown by doubling.)
  if (!b || ops_.capacity() <= ops_charged_) return;
  const uint64_t n = (ops_.capacity() - ops_charged_) * sizeof(Op);
  b->charge(n, "the document's elements");
  charged_ += n;
  ops_charged_ = ops_.capacity();
}

// Depth and size limits; false when the element must be skipped.
bool Converter::enter(int depth) {
  charge_ops();
  if (depth > kMaxDepth) {
    warn("nesting deeper than " + std::to_string(kMaxDepth) +
         " levels (elements, use and clip-path references): deeper content ignored");
    return false;
  }
  if (++s_.instances > kMaxInstances) {
    warn("more than " + std::to_string(kMaxInstances) +
         " element instances: the rest of the document is ignored");
    return false;
  }
  return true;
}

const Element* Converter::find(const std::string& id) const {
  const auto it = s_.doc.ids.find(id);
  return it == s_.doc.ids.end() ? nullptr : it->second;
}

// ------------------------------------------------------------ references

// Resolves a clip-path or mask value: `what` is the property, `element`
// the name its target must have, `active` the targets being converted.
// Following resvg (and the suite's masking tests): a reference to a
// missing element or a reference cycle is ignored (the element is drawn
// unclipped, unmasked); a reference to an element of another kind makes
// the element invisible. Other values (images) are not supported and
// ignored; clip-path's basic shapes are resolved before (resolve_clip).
ClipRef Converter::resolve_reference(const std::string& value, const char* what, const char* element,
                                     const std::vector<const Element*>& active) {
  ClipRef r;
  if (value.empty() || iequals(value, "none")) return r;
  Scanner s(value);
  bool external = false;
  const auto id = parse_func_iri(s, &external);
  s.skip_ws();
  if (!id || !s.at_end()) {
    warn(std::string(what) + " values other than url(#id) are not supported: " + what + " ignored");
    return r;
  }
  if (external) {
    warn(std::string("references to other documents are not supported: ") + what + " ignored");
    return r;
  }
  const Element* target = find(*id);
  if (!target) return r;
  if (target->name != element) {
    r.state = ClipRef::Invalid;
    return r;
  }
  if (std::find(active.begin(), active.end(), target) != active.end()) {
    warn(std::string("recursive ") + what + " reference ignored");
    return r;
  }
  r.state = ClipRef::Valid;
  r.element = target;
  return r;
}

ClipRef Converter::resolve_clip(const std::string& value) {
  bool invalid = false;
  if (auto cs = parse_clip_shape(value, &invalid)) {
    ClipRef r;
    r.state = ClipRef::Shape;
    r.shape = std::make_shared<const ClipShape>(std::move(*cs));
    return r;
  }
  return resolve_reference(value, "clip-path", "clipPath", s_.active_clips);
}

// The element a use references (SVG 2 struct.html#UseElement); nullptr when missing or when
// the reference would recurse. href wins over xlink:href (SVG 2 linking.html#XLinkRefAttrs).
const Element* Converter::use_target(const Element& use) {
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
  // A target being converted already recurses, unless it is a shape: a
  // shape reached again through its own marker (a marker whose content
  // uses the marked path) is a new instance, and the chain ends where a
  // marker would enter itself (draw_markers), as in resvg and browsers.
  if (t == &use ||
      (classify(*t) != Kind::Shape && std::find(s_.active.begin(), s_.active.end(), t) != s_.active.end())) {
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
  return t;
}

Affine Converter::use_offset(const Element& use, double em) {
  return Affine::translate(length(use, "x", Axis::X, 0, em), length(use, "y", Axis::Y, 0, em));
}

// ------------------------------------------------------------ geometry

// What 100% stands for along `axis`: the viewport, i.e. the viewBox when
// there is one (SVG 2 coords.html#Units); diagonal lengths such as r use
// sqrt((w^2 + h^2) / 2).
double Converter::percent_base(Axis axis) const {
  switch (axis) {
    case Axis::X: return s_.percent_w;
    case Axis::Y: return s_.percent_h;
    default: return std::sqrt((s_.percent_w * s_.percent_w + s_.percent_h * s_.percent_h) / 2);
  }
}

// A length in user units, em and ex relative to the element's font size
// `em` (ex is taken as half an em: fonts are not modelled).
double Converter::to_user(const Length& l, Axis axis, double em) const {
  return resolve_length(l, percent_base(axis), em, s_.root_em);
}

// A length attribute in user units; `def` when absent or invalid.
double Converter::length(const Element& e, const char* name, Axis axis, double def, double em) const {
  const auto l = length_value(e, name);
  return l ? to_user(*l, axis, em) : def;
}

std::optional<Length> Converter::length_value(const Element& e, const char* name) const {
  static constexpr std::string_view geometry[] = {"x", "y", "width", "height", "cx", "cy", "r", "rx", "ry"};
  const bool property_like = std::find(std::begin(geometry), std::end(geometry), name) != std::end(geometry);
  if (!s_.svg1 && property_like) {
    // rx and ry take auto too (SVG 2 geometry.html#RX): a value of its
    // own, which overrides a lower declaration or the attribute.
    const bool takes_auto = std::string_view(name) == "rx" || std::string_view(name) == "ry";
    const auto p = property<std::optional<Length>>(e, name, [&](std::string_view v) {
      if (takes_auto && iequals(trim(v), "auto")) return std::optional<std::optional<Length>>(std::optional<Length>());
      const auto l = parse_length(v, CalcOk::Yes);
      if (!l) warn_out_of_range(name, v, CalcOk::Yes);
      return l ? std::optional<std::optional<Length>>(l) : std::nullopt;
    });
    if (p.state == Prop<std::optional<Length>>::Set) return p.value;
    // inherit in a declaration: the parent's value (these properties are
    // not inherited otherwise), from its declarations, or from its
    // attribute where that is the property's presentation attribute (x on
    // a rect, not on a g). In an attribute Chromium takes inherit as
    // invalid, as resvg's suite expects. Absent, invalid, initial or
    // unset: the initial value.
    if (p.state == Prop<std::optional<Length>>::Inherit && e.parent &&
        std::any_of(e.declarations.begin(), e.declarations.end(),
                    [&](const auto& d) { return d.first == name && iequals(trim(d.second), "inherit"); })) {
      const Element& parent = *e.parent;
      const bool attribute_is_property = classify(parent) == Kind::Shape || parent.name == "image" ||
                                         parent.name == "svg" || parent.name == "foreignObject";
      if (!attribute_is_property && !std::any_of(parent.declarations.begin(), parent.declarations.end(),
                                                 [&](const auto& d) { return d.first == name; }))
        return std::nullopt;
      return length_value(parent, name);
    }
    return std::nullopt;
  }
  const std::string* a = e.attribute(name);
  if (!a) return std::nullopt;
  const CalcOk calc = property_like ? CalcOk::Yes : CalcOk::No;
  const auto l = parse_length(*a, calc);
  if (!l) warn_out_of_range(name, *a, calc);
  return l;
}

// A length that is one but for its magnitude is ignored as invalid
// values are (numbers beyond kMaxNumber are syntax errors), and said so.
void Converter::warn_out_of_range(std::string_view name, std::string_view value, CalcOk calc) const {
  if (!parse_length(value, calc, kMaxRegionNumber)) return;
  const std::string v(value.substr(0, 40));
  warn(std::string(name) + "=\"" + v + "\": numbers beyond 1e9 are out of range: ignored");
}

// A length that may be "auto" (rect rx/ry, ellipse rx/ry in SVG 2): absent,
// "auto", invalid or negative values all mean auto (nullopt).
std::optional<double> Converter::auto_length(const Element& e, const char* name, Axis axis, double em) const {
  const auto l = length_value(e, name);
  if (!l) return std::nullopt;
  const double v = to_user(*l, axis, em);
  if (v < 0) return std::nullopt;
  return v;
}

// The element's geometry, built once; -1 when it has none (invalid sizes,
// empty path data).
// The font size `em` of the first instance converted applies to all (em
// lengths in shapes reused with different font sizes are rare).
int Converter::shape_index(const Element& e, double em) {
  const auto it = shape_of_.find(&e);
  if (it != shape_of_.end()) return it->second;
  std::vector<uint32_t> arcs;
  std::optional<Path> p = build_shape(e, em, &arcs);
  int index = -1;
  // Zero-length subpaths ("M p Z") have no segments but are stroked.
  if (p && !p->contours().empty()) {
    index = static_cast<int>(shapes_.size());
    add_shape(std::move(*p));
    if (!arcs.empty()) arc_continuations_.emplace(static_cast<uint32_t>(index), std::move(arcs));
  }
  shape_of_.emplace(&e, index);
  return index;
}

namespace {

// The d property of e (SVG 2 paths.html#TheDProperty; not inherited) into
// `out`; false for none. Its last declaration in cascade order that is
// none or path(<string>) wins; path() with a fill rule, or with an error
// anywhere in its path data, is an invalid declaration and dropped, as
// Chromium drops it. Without one, a path's d attribute (the property's
// presentation attribute) applies, its data kept up to an error (SVG 2
// paths.html#PathDataErrorHandling). initial is none; inherit takes the
// parent's value.
bool d_property(const Element& e, Path& out, std::vector<uint32_t>* arc_continuations, bool* error) {
  for (auto it = e.declarations.rbegin(); it != e.declarations.rend(); ++it) {
    if (it->first != "d") continue;
    const auto keyword = parse_keyword(it->second);
    // unset and revert: d is not inherited, and presentation attributes
    // are author style, which revert rolls back past: none.
    if (keyword == "none" || keyword == "initial" || keyword == "unset" || keyword == "revert") return false;
    if (keyword == "inherit") return e.parent && d_property(*e.parent, out, arc_continuations, error);
    if (const auto p = parse_css_path(it->second); p && !p->rule && parse_path_data(p->data, out, arc_continuations))
      return true;
  }
  const std::string* d = e.name == "path" ? e.attribute("d") : nullptr;
  if (!d) return false;
  if (!parse_path_data(*d, out, arc_continuations)) *error = true;
  return true;
}

}  // namespace

std::optional<Path> Converter::build_shape(const Element& e, double em,
                                           std::vector<uint32_t>* arc_continuations) const {
  const std::string& n = e.name;
  if (n == "path") {
    Path p;
    bool error = false;
    if (!d_property(e, p, arc_continuations, &error)) return std::nullopt;
    // Drawn up to the error, as SVG 2 says (paths.html#PathDataErrorHandling).
    if (error) warn("path data with an error (or a number beyond 1e9): drawn up to it");
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

// Resolves what rendering `e` needs into `out`; false when the element
// shows nothing.
bool Converter::place(const Element& e, Kind kind, const Context& ctx, Placed& out) {
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
  if (!out.space.invertible()) return false;
  out.clip = resolve_clip(out.st.clip_path);
  return out.clip.state != ClipRef::Invalid;
}

// Conditional processing (SVG 2 struct.html#ConditionalProcessing):
// requiredExtensions names no extension mpvg has (any value fails, an
// empty one too); requiredFeatures is obsolete and holds; systemLanguage
// holds when one of its comma-separated tags matches one of the user's
// languages (equal, or one a prefix of the other at a '-').
bool Converter::conditions_pass(const Element& e) const {
  if (e.attribute("requiredExtensions")) return false;
  const std::string* langs = e.attribute("systemLanguage");
  if (!langs) return true;
  auto lower = [](std::string_view v) {
    std::string out(trim(v));
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
  };
  for (size_t pos = 0; pos <= langs->size();) {
    size_t end = langs->find(',', pos);
    if (end == std::string::npos) end = langs->size();
    const std::string tag = lower(std::string_view(*langs).substr(pos, end - pos));
    for (const std::string& user : s_.options.languages) {
      const std::string u = lower(user);
      if (tag.empty() || u.empty()) continue;
      if (tag == u || tag.rfind(u + "-", 0) == 0 || u.rfind(tag + "-", 0) == 0) return true;
    }
    pos = end + 1;
  }
  return false;
}

// Converts a rendered element (and its subtree) in painter's order.
void Converter::render(const Element& e, const Context& ctx, int depth) {
  if (s_.export_target && !s_.exporting && document_space_) {
    // --export-id: the element itself, the path down to it, nothing else.
    if (&e != s_.export_target) {
      for (const Element* a = s_.export_target->parent; a; a = a->parent)
        if (a == &e) render_element(e, ctx, depth, true);
      return;
    }
    s_.exporting = true;
    render_element(e, ctx, depth);
    s_.exporting = false;
    return;
  }
  const std::string* id = s_.boxes && document_space_ && level_ == 0 ? e.attribute("id") : nullptr;
  if (!id || id->empty() || s_.boxed.count(*id)) {
    render_element(e, ctx, depth);
    return;
  }
  // --query: listed in document order (before its descendants), measured
  // once converted, dropped when it draws nothing.
  const size_t slot = s_.boxes->size(), start = ops_.size();
  s_.boxed.insert(*id);
  s_.boxes->push_back({*id});
  render_element(e, ctx, depth);
  const Bounds b = drawn_bounds(start, ops_.size());
  ElementBox& box = (*s_.boxes)[slot];
  if (b.empty()) {
    // Not drawn (yet): a later <use> of it may draw it.
    s_.boxes->erase(s_.boxes->begin() + static_cast<ptrdiff_t>(slot));
    s_.boxed.erase(*id);
    return;
  }
  box.x = b.x0;
  box.y = b.y0;
  box.width = b.width();
  box.height = b.height();
}

Bounds Converter::drawn_bounds(size_t begin, size_t end) const {
  Bounds b;
  for_each_content(begin, end, [&](const Op& op) {
    if (op.kind == OpKind::Append) {
      const Scene& doc = embedded_[op.scene];
      for (Vec2 p : {Vec2{0, 0}, Vec2{doc.width, 0}, Vec2{0, doc.height}, Vec2{doc.width, doc.height}})
        b.add(op.xf.apply(p));
    } else if (op.kind == OpKind::Fill && op.stroke) {
      add_stroke_bounds(shapes_[op.shape], stroke_styles_[op.stroke_style], device_ * op.xf, device_.inverted(), b);
    } else if (op.kind == OpKind::Fill) {
      add_path_bounds(shapes_[op.shape], op.xf, b);
    }
  });
  return b;
}

void Converter::render_element(const Element& e, const Context& ctx, int depth, bool ancestor) {
  const Kind kind = classify(e);
  if (kind == Kind::Ignored || !conditions_pass(e)) return;
  if (kind == Kind::Unsupported) {
    if (!ancestor) warn("<" + e.name + "> elements are not supported: ignored");
    return;
  }
  if (e.name == "svg" && e.parent) {
    render_viewport(e, ctx, depth, nullptr);
    return;
  }
  if (!enter(depth)) return;
  Placed pl;
  if (!place(e, kind, ctx, pl)) return;
  if (ancestor) {
    if (kind == Kind::Container) draw_content(e, kind, pl, child_context(pl.st, pl.space, false), depth);
    return;
  }
  const auto& [st, space, target, clip] = pl;

  const size_t start = ops_.size();
  const Context inner = child_context(st, space, false);
  // CSS Masking 1 §1 and Compositing 1 §3: filter, clip, mask, opacity,
  // then blending.
  if (!filter_content(e, st, space, depth, [&](Converter& c) { c.draw_content(e, kind, pl, inner, depth); })) return;
  if (!group_content(e, start, st, space, depth)) return;
  if (clip.state == ClipRef::Valid) clip_content(start, *clip.element, space, depth);
  if (clip.state == ClipRef::Shape) clip_shape_content(start, *clip.shape, space, st.inh.font_size);
}

void Converter::draw_content(const Element& e, Kind kind, const Placed& pl, const Context& inner, int depth) {
  const Style& st = pl.st;
  const Affine& space = pl.space;
  s_.active.push_back(&e);
  switch (kind) {
    case Kind::Container:
      if (e.name == "switch") {
        // SVG 2 struct.html#SwitchElement: the first direct child that is
        // a graphics or container element and whose conditions hold (its
        // display does not count); nothing else.
        for (const auto& c : e.children) {
          const Kind k = classify(*c);
          if (k == Kind::Ignored || !conditions_pass(*c)) continue;
          render(*c, inner, depth + 1);
          break;
        }
        break;
      }
      for (const auto& c : e.children) render(*c, inner, depth + 1);
      break;
    case Kind::Use: {
      // The use is its tree's context element. Its box, for context
      // paints from servers, is its tree's: drawn once to measure it, then
      // again with it.
      auto draw = [&] {
        const Element& target = *pl.target;
        if (target.name == "symbol" || target.name == "svg") render_viewport(target, inner, depth + 1, &e);
        else render(target, inner, depth + 1);
      };
      contexts_.push_back({st.inh.fill, st.inh.stroke, space, std::nullopt});
      const int saved_context = context_;
      context_ = static_cast<int>(contexts_.size()) - 1;
      if (st.inh.fill.kind == PaintSpec::Kind::Server || st.inh.stroke.kind == PaintSpec::Kind::Server) {
        const size_t before = ops_.size();
        draw();
        contexts_[context_].bbox = content_bounds(before, ops_.size(), space);
        ops_.resize(before);
      }
      draw();
      context_ = saved_context;
      break;
    }
    case Kind::Image: image(e, st, space); break;
#if MPVG_HAVE_TEXT
    case Kind::Text: text(e, st, space); break;
#endif
    default: shape_paint(e, st, space, depth); break;
  }
  s_.active.pop_back();
}

// A shape's fill and stroke, in the order of paint-order. The fill
// operation is always there (as bounds only when it paints nothing): it
// carries the shape's bounding box.
void Converter::shape_paint(const Element& e, const Style& st, const Affine& space, int depth) {
  const int shape = shape_index(e, st.inh.font_size);
  if (shape < 0) return;
  // A line encloses no area (SVG 2 shapes.html#LineElement): it can only
  // be stroked.
  paint_shape(static_cast<uint32_t>(shape), st, space, e.name != "line", nullptr, &e, depth);
}

void Converter::paint_shape(uint32_t shape, const Style& st, const Affine& space, bool fillable, const Bounds* box,
                            const Element* markable, int depth) {
  Op fill = Op::of(OpKind::Bounds);
  fill.shape = static_cast<uint32_t>(shape);
  fill.xf = space;
  fill.rule = st.inh.fill_rule;
  fill.aliased = st.inh.aliased_shapes;
  // Paint servers in objectBoundingBox units use the box of the fill
  // geometry, for the stroke too (SVG 2 coords.html#BoundingBoxes).
  ShapeBox bbox{shapes_, static_cast<uint32_t>(shape), box ? std::optional<Bounds>(*box) : std::nullopt};
  if (fillable && !shapes_[shape].empty() && st.inh.visible) {
    if (const auto paint = make_paint(st.inh.fill, st.inh.fill_opacity, bbox, space)) {
      fill.kind = OpKind::Fill;
      fill.paint = *paint;
    }
  }
  const std::optional<Op> stroke = shape_stroke(static_cast<uint32_t>(shape), st, space, bbox, markable);
  for (PaintLayer l : st.inh.paint_order) {
    if (l == PaintLayer::Fill) ops_.push_back(fill);
    if (l == PaintLayer::Stroke && stroke) ops_.push_back(*stroke);
    if (l == PaintLayer::Markers && markable) draw_markers(*markable, st, shape, space, depth);
  }
}

// ------------------------------------------------------------ clip paths

// The tight bounding box of the content in ops_[begin, end), in the user
// space `space`.
Bounds Converter::content_bounds(size_t begin, size_t end, const Affine& space, bool strokes) const {
  Bounds b;
  const Affine inv = space.inverted();
  for_each_content(begin, end, [&](const Op& op) {
    // An embedded document's box is its <image>'s, a Bounds operation; a
    // filter's region is no box at all.
    if (op.filter || op.marker || op.kind == OpKind::Append) return;
    if (!op.stroke) add_path_bounds(shapes_[op.shape], same(op.xf, space) ? Affine{} : inv * op.xf, b);
    else if (strokes)
      add_stroke_bounds(shapes_[op.shape], stroke_styles_[op.stroke_style], device_ * op.xf,
                        (device_ * space).inverted(), b);
  });
  return b;
}

// Wraps the element content in ops_[start, end) into a clip group of clip
// path `cp`: push, the clip items, activate, the content, pop. An invalid
// clip path removes the content (the element is not rendered).
void Converter::clip_content(size_t start, const Element& cp, const Affine& space, int depth) {
  clip_content(start, space, [&](LazyBounds& bbox) { return clip_items(cp, space, bbox, depth + 1); });
}

void Converter::clip_content(size_t start, const Affine& space, const std::function<bool(LazyBounds&)>& items) {
  const size_t end = ops_.size();
  LazyBounds bbox{*this, start, end, space, std::nullopt};
  ops_.push_back(Op::of(OpKind::Push));
  if (!items(bbox)) {
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
bool Converter::clip_items(const Element& cp, const Affine& space, LazyBounds& bbox, int depth) {
  if (!enter(depth)) return false;
  // Properties inherit into a clipPath from its document ancestors, not
  // from the element that references it.
  const Style st = compute_style(cp, document_context(cp, true));
  // An unparsable or degenerate transform invalidates the clip path (resvg).
  if (st.transform_invalid || !st.transform.invertible()) return false;

  Affine base = space * st.transform;
  const std::string* units = cp.attribute("clipPathUnits");
  if (units && trim(*units) == "objectBoundingBox") {
    // Content coordinates are fractions of the clipped element's bounding
    // box (clipPathUnits); a box with no area makes the reference invalid.
    const Bounds& b = bbox.get();
    if (b.empty() || !(b.width() > 0) || !(b.height() > 0)) return false;
    base = base * Affine{b.width(), 0, 0, b.height(), b.x0, b.y0};
  }
  if (!base.invertible()) return false;

  s_.active_clips.push_back(&cp);
  const ClipRef nested = resolve_clip(st.clip_path);
  bool ok = nested.state != ClipRef::Invalid;
  const bool intersects = nested.state == ClipRef::Valid || nested.state == ClipRef::Shape;
  if (ok && intersects) {
    // clip-path on the clipPath itself intersects, in the user space of
    // the clipped element (a basic shape against the clipped element's
    // boxes).
    ops_.push_back(Op::of(OpKind::Push));
    ok = nested.state == ClipRef::Valid ? clip_items(*nested.element, space, bbox, depth + 1)
                                        : clip_shape_items(*nested.shape, space, bbox, st.inh.font_size);
    if (ok) ops_.push_back(Op::of(OpKind::Activate));
  }
  if (ok) {
    const Context inner = child_context(st, base, true);
    for (const auto& c : cp.children) clip_child(*c, inner, depth + 1);
    if (intersects) ops_.push_back(Op::of(OpKind::Pop));
  }
  s_.active_clips.pop_back();
  return ok;
}

// One child of a clipPath: a shape, or a use of one (CSS Masking 1 content
// model); groups and everything else are not valid children.
void Converter::clip_child(const Element& e, const Context& ctx, int depth) {
  const Kind kind = classify(e);
  if (kind != Kind::Shape && kind != Kind::Use && kind != Kind::Text) {
    if (e.name == "text") warn("<text> elements are not supported: ignored");
    return;
  }
  if (e.name == "line") return;  // no area
  if (e.name == "svg" && e.parent) {
    render_viewport(e, ctx, depth, nullptr);
    return;
  }
  if (!enter(depth)) return;
  Placed pl;
  if (!place(e, kind, ctx, pl)) return;
  const auto& [st, space, target, clip] = pl;

  const size_t start = ops_.size();
  if (kind == Kind::Use) {
    s_.active.push_back(&e);
    clip_child(*target, child_context(st, space, true), depth + 1);
    s_.active.pop_back();
#if MPVG_HAVE_TEXT
  } else if (kind == Kind::Text) {
    clip_text(e, st, space);
#endif
  } else {
    const int shape = shape_index(e, st.inh.font_size);
    // A shape without segments ("M p Z") has no area to clip with.
    if (shape < 0 || !st.inh.visible || shapes_[shape].empty()) return;
    Op op = Op::of(OpKind::Clip);
    op.shape = static_cast<uint32_t>(shape);
    op.xf = space;
    op.rule = st.inh.clip_rule;
    op.aliased = st.inh.aliased_shapes;
    ops_.push_back(op);
  }
  if (ops_.size() == start) return;
  if (clip.state == ClipRef::Valid) clip_content(start, *clip.element, space, depth);
  if (clip.state == ClipRef::Shape) clip_shape_content(start, *clip.shape, space, st.inh.font_size);
}

// ------------------------------------------------------------ output

void Converter::emit(SceneBuilder& b) {
  // Every scene of the document is built here: charged as it grows.
  b.set_budget(s_.options.budget.get());
  // Paint servers first, in order: Paint::index counts from 0 in each list.
  for (Gradient& g : gradients_) b.add_gradient(std::move(g));
  for (Pattern& p : patterns_) b.add_pattern(std::move(p));
  for (Texture& t : textures_) b.add_texture(std::move(t));
  // Filter effects on first use: an effect whose fill was dropped (a use
  // drawn once to measure it) would carry its whole source for nothing.
  std::vector<int64_t> filter(filters_.size(), -1);
  auto paint_of = [&](uint32_t paint) {
    Paint p = paints_[paint];
    if (p.type == PaintType::Filter) {
      if (filter[p.index] < 0) filter[p.index] = b.add_filter(std::move(filters_[p.index]));
      p.index = static_cast<uint32_t>(filter[p.index]);
    }
    return p;
  };
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
      case OpKind::Fill:
        if (op.stroke)
          b.stroke(geometry_of(op.shape), op.xf, stroke_styles_[op.stroke_style], paint_of(op.paint), op.aliased);
        else
          b.fill(geometry_of(op.shape), op.xf, op.rule, paint_of(op.paint), op.aliased);
        break;
      case OpKind::Clip: b.clip(geometry_of(op.shape), op.xf, op.rule, op.aliased); break;
      case OpKind::Append: b.append(embedded_[op.scene], op.xf); break;
      case OpKind::GroupBegin: b.begin_group(groups_[op.scene]); break;
      case OpKind::GroupEnd: b.end_group(); break;
      case OpKind::Bounds: break;
    }
  }
}

}  // namespace detail

namespace {

// Files people hand to svg2png by mistake, known by their first bytes
// (after any white space): said so instead of an XML error.
void refuse_other_formats(std::string_view text) {
  const size_t lead = std::min(text.find_first_not_of(" \t\r\n"), text.size());
  const std::string_view t = text.substr(lead);
  struct Signature {
    std::string_view bytes;
    const char* what;
  };
  static const Signature kKnown[] = {
      {"%PDF-", "a PDF document, not SVG: render it with pdf2png"},
      {"%!PS", "a PostScript document, not SVG"},
      {"\x89PNG\r\n\x1a\n", "a PNG image, not SVG"},
      {"\xff\xd8\xff", "a JPEG image, not SVG"},
      {"GIF8", "a GIF image, not SVG"},
      {"PK\x03\x04", "a ZIP archive (perhaps an .odg or .docx), not SVG"},
  };
  for (const Signature& s : kKnown)
    if (t.substr(0, s.bytes.size()) == s.bytes) throw ParseError(std::string("the input is ") + s.what);
  if (t.substr(0, 4) == "RIFF" && t.size() >= 12 && t.substr(8, 4) == "WEBP")
    throw ParseError("the input is a WebP image, not SVG");
}

}  // namespace

ParseResult parse_svg_string(std::string_view text, const std::string& base_dir, const ParseOptions& options) {
  const detail::AbsoluteUnitsScope units(options.dpi);
  // .svgz: gzip-compressed SVG, recognised by the gzip signature and
  // inflated (at most 256 MiB) before parsing.
  std::string inflated;
  if (text.size() >= 2 && static_cast<unsigned char>(text[0]) == 0x1f && static_cast<unsigned char>(text[1]) == 0x8b) {
    std::string why;
    auto out = detail::gunzip(std::vector<uint8_t>(text.begin(), text.end()), &why);
    if (!out) throw ParseError("cannot inflate the gzip-compressed (svgz) input: " + why);
    inflated = std::move(*out);
    text = inflated;
  }
  refuse_other_formats(text);
  ParseResult result;
  // Style sheets that <?xml-stylesheet?> and @import name: local files under
  // the read policy (the document's folder tree and allowed_dirs).
  const std::string base = base_dir.empty() ? std::string(".") : base_dir;
  std::vector<std::string> readable{base};
  readable.insert(readable.end(), options.allowed_dirs.begin(), options.allowed_dirs.end());
  auto load_css = [&](std::string_view href) -> std::optional<std::string> {
    std::string why;
    const auto r = detail::fetch_resource(href, base, readable, &why, size_t(16) << 20);
    if (!r) {
      result.warnings.push_back("style sheet not loaded: " + why);
      return std::nullopt;
    }
    return std::string(r->bytes.begin(), r->bytes.end());
  };
  const detail::Document doc = detail::parse_document(text, load_css);
  result.warnings.insert(result.warnings.end(), doc.warnings.begin(), doc.warnings.end());
  const detail::Element* target = nullptr;
  if (!options.export_id.empty()) {
    const auto it = doc.ids.find(options.export_id);
    if (it == doc.ids.end()) throw ParseError("no element has the id '" + options.export_id + "' (--export-id)");
    target = it->second;
  }
  detail::Bounds box;
  auto convert = [&](const ParseOptions& o, std::vector<std::string>& warnings) {
    detail::Session session(doc, o, warnings);
    session.base_dir = base_dir.empty() ? std::string(".") : base_dir;
    session.allowed_dirs.push_back(session.base_dir);
    session.allowed_dirs.insert(session.allowed_dirs.end(), o.allowed_dirs.begin(), o.allowed_dirs.end());
    session.export_target = target;
    if (o.query) session.boxes = &result.elements;
    Scene scene;
    {
      detail::Converter conv(session, Affine{}, 0);
      scene = conv.run();
    }  // (its charges given back: its scene builders charged the scene)
    result.stroked_paths = session.stroked_paths;
    box = session.export_box;
    return scene;
  };
  if (!target) {
    result.scene = convert(options, result.warnings);
    return result;
  }
  // --export-id: the element's box at the document's own scale first (its
  // hairlines and stroke outlines barely depend on it), then the element
  // converted for the output the box becomes, moved to the origin.
  ParseOptions measure = options;
  measure.view = nullptr;
  measure.query = false;
  std::vector<std::string> ignored;
  convert(measure, ignored);
  if (box.empty() || !(box.width() > 0 && box.height() > 0))
    throw ParseError("the element '" + options.export_id + "' draws nothing (--export-id)");
  const detail::Bounds drawn = box;
  const Affine to_origin = Affine::translate(-drawn.x0, -drawn.y0);
  ParseOptions place = options;
  place.view = [&](double, double) {
    const Affine view = options.view ? options.view(drawn.width(), drawn.height())
                                     : Affine::scale(options.device_scale, options.device_scale);
    return view * to_origin;
  };
  const Scene element = convert(place, result.warnings);
  SceneBuilder b(drawn.width(), drawn.height());
  b.set_budget(options.budget.get());
  b.append(element, to_origin);
  result.scene = b.finish();
  return result;
}

std::string read_svg_file(const std::string& path, size_t max_bytes) {
  auto fail = [&](int err) { return ResourceError("cannot read '" + path + "': " + std::strerror(err)); };
  FILE* f = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
  if (!f) throw fail(errno);
  const auto too_large = [&] {
    if (f != stdin) std::fclose(f);
    return ResourceError("'" + path + "' is larger than the input limit of " + byte_size(max_bytes) + " (--max-input)");
  };
  struct stat st {};
  if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && uint64_t(st.st_size) > max_bytes) throw too_large();
  std::string data;
  // A regular file's size is reserved: grown a chunk at a time, the string
  // copied the text again with every doubling and faulted in its pages
  // twice (a tenth of a large document's parse).
  if (S_ISREG(st.st_mode) && st.st_size > 0) data.reserve(size_t(st.st_size));
  char buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
    if (data.size() + n > max_bytes) throw too_large();
    data.append(buf, n);
  }
  const bool failed = std::ferror(f);
  const int err = errno;
  if (f != stdin) std::fclose(f);
  if (failed) throw fail(err);
  return data;
}

ParseResult parse_svg_file(const std::string& path, const ParseOptions& options) {
  const std::string data = read_svg_file(path, options.max_input_bytes);
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
