// The filter property (W3C Filter Effects Module Level 1, "FE1" below)
// as the core's filter effects (core/filters/filter.h).
//
// A filtered element's content is converted by a converter of its own into
// a scene in our scene units: the filter's SourceGraphic. In the content's
// place this converter keeps its geometry as bounds (an element's bounding
// box ignores its filter) and fills the filter region's box in scene units
// with the effect's result, a paint of type Filter. The element's
// clip-path, mask and opacity then wrap that fill like any content: filter
// first, then clipping, masking and opacity (CSS Masking 1 §1). A list of
// filters applies one after another: each next effect's source is a scene
// holding the previous effect's result over its region. Filtered content
// inside filtered content nests the same way, at most kMaxFilterDepth
// deep, and a document holds at most kMaxFilterEffects.
//
// Everything the core needs is resolved here: regions and subregions in the
// element's user space (units, percentages, the spec's defaults), lengths
// of primitiveUnits="objectBoundingBox" multiplied out, inputs as primitive
// indices, color-interpolation-filters, colour matrices and transfer
// functions as numbers, feImage's raster or element as an Image or a scene.
//
// Where FE1 leaves room or browsers disagree, the references of resvg's
// test suite decide (shared/resvg-suite, tests/filters/...; the test names
// are given where each decision is made).
#include <algorithm>
#include <cctype>
#include <cmath>

#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_style.h"
#include "frame/scene_builder.h"

namespace mpvg::svg::detail {

// One item of a <filter-value-list>: url(#id), or a filter function with
// the text between its parentheses.
struct FilterItem {
  bool url = false;
  std::string id;         // url: the fragment
  bool external = false;  // url: into another document
  std::string function;   // lower-cased name
  std::string args;
  std::optional<FilterPrimitive> primitive;  // a function's, resolved
};

// What a filter element's primitives are resolved against.
struct Converter::FilterSpace {
  Bounds bbox;          // the filtered element's bounding box, user space
  FilterRect region;    // the filter region, user space
  bool primitive_obb;   // primitiveUnits="objectBoundingBox"
  Affine space;         // user space to scene units
  int depth;
};

namespace {

// none | <filter-value-list> (FE1 §"The filter property"): url()s and
// functions, white space between them optional. nullopt on a syntax error,
// which invalidates the whole value.
std::optional<std::vector<FilterItem>> parse_filter_list(std::string_view v) {
  std::vector<FilterItem> out;
  v = trim(v);
  if (iequals(v, "none")) return out;
  size_t i = 0;
  while (true) {
    while (i < v.size() && is_ws(v[i])) i++;
    if (i == v.size()) break;
    size_t open = i;
    while (open < v.size() && (std::isalpha(static_cast<unsigned char>(v[open])) || v[open] == '-')) open++;
    if (open == i || open == v.size() || v[open] != '(') return std::nullopt;
    // The matching parenthesis: colours in drop-shadow() have their own.
    size_t close = open + 1;
    int depth = 1;
    char quote = 0;
    for (; close < v.size(); close++) {
      const char c = v[close];
      if (quote) {
        if (c == quote) quote = 0;
      } else if (c == '\'' || c == '"') {
        quote = c;
      } else if (c == '(') {
        depth++;
      } else if (c == ')' && --depth == 0) {
        break;
      }
    }
    if (close == v.size()) return std::nullopt;
    FilterItem item;
    const std::string_view name = v.substr(i, open - i);
    if (iequals(name, "url")) {
      Scanner s(v.substr(i, close + 1 - i));
      const auto id = parse_func_iri(s, &item.external);
      if (!id || !s.at_end()) return std::nullopt;
      item.url = true;
      item.id = *id;
    } else {
      for (char c : name) item.function += ascii_lower(c);
      item.args = std::string(trim(v.substr(open + 1, close - open - 1)));
    }
    out.push_back(std::move(item));
    i = close + 1;
  }
  return out;
}

// A list of numbers separated by comma-wsp; nullopt on anything else.
std::optional<std::vector<double>> parse_numbers(std::string_view v) {
  Scanner s(trim(v));
  std::vector<double> out;
  while (!s.at_end()) {
    const auto n = s.number();
    if (!n) return std::nullopt;
    out.push_back(*n);
    if (s.skip_comma_ws() && s.at_end()) return std::nullopt;  // a trailing comma
  }
  return out;
}

// A number attribute; `def` when absent or invalid.
double number_attr(const Element& e, const char* name, double def) {
  const std::string* a = e.attribute(name);
  if (!a) return def;
  return parse_number(*a).value_or(def);
}

bool has_area(const Bounds& b) { return !b.empty() && b.width() > 0 && b.height() > 0; }

// A rectangle in fractions of the box b, in b's space.
FilterRect in_box(const Bounds& b, double x, double y, double w, double h) {
  return {b.x0 + x * b.width(), b.y0 + y * b.height(), w * b.width(), h * b.height()};
}

// The box of rectangle r mapped by m: where a filter's result shows. The
// core takes a region as the pixel box of its transformed rectangle (the
// layer is axis-aligned), as resvg does
// (filters/filter/transform-on-shape-with-filter-region shows a skewed
// element's blur cut by a vertical edge).
ViewBox mapped_box(const FilterRect& r, const Affine& m) {
  double x0, y0, x1, y1;
  filter_rect_bounds(r, m, x0, y0, x1, y1);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

// Where a filter's result is painted, in scene units: its region's box,
// clipped to the scene grown by its size on every side (no more of the
// region can show; the layer itself is cut to the output in pixels), so
// that a region of 1e12 units makes no geometry that large.
ViewBox Converter::region_fill(const FilterRect& region, const Affine& space) const {
  const ViewBox r = mapped_box(region, space);
  if (!(scene_w_ > 0 && scene_h_ > 0)) return r;
  const double x0 = std::max(r.x, -scene_w_), y0 = std::max(r.y, -scene_h_);
  const double x1 = std::min(r.x + r.w, 2 * scene_w_), y1 = std::min(r.y + r.h, 2 * scene_h_);
  return {x0, y0, std::max(0.0, x1 - x0), std::max(0.0, y1 - y0)};
}

namespace {

FilterRect unite(const FilterRect& a, const FilterRect& b) {
  const double x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
  const double x1 = std::max(a.x + a.w, b.x + b.w), y1 = std::max(a.y + a.h, b.y + b.h);
  return {x0, y0, x1 - x0, y1 - y0};
}

// A property that is not inherited (flood-color, flood-opacity,
// lighting-color): e's own value, or with "inherit" its parent's computed
// value; `initial` otherwise. parse(element, text).
template <class T, class Parse>
T own_property(const Element& e, const char* name, T initial, Parse parse) {
  const auto p = property<T>(e, name, [&](std::string_view v) { return parse(e, v); });
  if (p.state == Prop<T>::Set) return p.value;
  if (p.state == Prop<T>::Inherit && e.parent) return own_property(*e.parent, name, initial, parse);
  return initial;
}

std::optional<RGBA> color_or_current(const Element& e, std::string_view v) {
  if (iequals(trim(v), "currentColor")) return computed_color(e);
  return parse_color(v);
}

// flood-color times flood-opacity (FE1 §"Flood properties"), straight.
void flood(const Element& fe, float out[4]) {
  const RGBA c = own_property<RGBA>(fe, "flood-color", RGBA{0, 0, 0, 1}, color_or_current);
  const double o = own_property<double>(fe, "flood-opacity", 1.0,
                                         [](const Element&, std::string_view v) { return parse_alpha(v); });
  out[0] = c.r, out[1] = c.g, out[2] = c.b, out[3] = static_cast<float>(c.a * o);
}

// color-interpolation-filters (FE1 §17.7, inherited; auto is linearRGB)
// on a primitive: from the primitive and its ancestors (the filter
// element's), not from the filtered element.
bool linear_rgb(const Element& fe) {
  return inherited_property<bool>(fe, "color-interpolation-filters", true,
                                  [](std::string_view v, bool) -> std::optional<bool> {
                                    const auto k = parse_keyword(v);
                                    if (k && (*k == "auto" || *k == "linearrgb")) return true;
                                    if (k && *k == "srgb") return false;
                                    return std::nullopt;
                                  });
}

void set_matrix(float m[20], const double v[20]) {
  for (int i = 0; i < 20; i++) m[i] = static_cast<float>(v[i]);
}

// feColorMatrix type="saturate" (FE1 §15.10). Values outside [0, 1] under-
// or oversaturate; they are not clamped.
void saturate_matrix(double s, float m[20]) {
  const double v[20] = {0.213 + 0.787 * s, 0.715 - 0.715 * s, 0.072 - 0.072 * s, 0, 0,
                        0.213 - 0.213 * s, 0.715 + 0.285 * s, 0.072 - 0.072 * s, 0, 0,
                        0.213 - 0.213 * s, 0.715 - 0.715 * s, 0.072 + 0.928 * s, 0, 0,
                        0,                 0,                 0,                 1, 0};
  set_matrix(m, v);
}

// feColorMatrix type="hueRotate" by `degrees` (FE1 §15.10).
void hue_rotate_matrix(double degrees, float m[20]) {
  double s = 0, c = 1;
  sincos_snapped(degrees * M_PI / 180, s, c);
  const double v[20] = {
      0.213 + c * 0.787 - s * 0.213, 0.715 - c * 0.715 - s * 0.715, 0.072 - c * 0.072 + s * 0.928, 0, 0,
      0.213 - c * 0.213 + s * 0.143, 0.715 + c * 0.285 + s * 0.140, 0.072 - c * 0.072 - s * 0.283, 0, 0,
      0.213 - c * 0.213 - s * 0.787, 0.715 - c * 0.715 + s * 0.715, 0.072 + c * 0.928 + s * 0.072, 0, 0,
      0,                             0,                             0,                             1, 0};
  set_matrix(m, v);
}

// A primitive whose result is transparent black: what FE1 makes of a
// primitive in error, and of an empty subregion.
void make_transparent(FilterPrimitive& p) {
  p.kind = FilterKind::Flood;
  p.in = p.in2 = FILTER_SOURCE_GRAPHIC;
  p.inputs.clear();
  p.color[0] = p.color[1] = p.color[2] = p.color[3] = 0;
}

std::optional<FilterKind> primitive_kind(std::string_view name) {
  static const std::pair<const char*, FilterKind> kinds[] = {
      {"feBlend", FilterKind::Blend},
      {"feColorMatrix", FilterKind::ColorMatrix},
      {"feComponentTransfer", FilterKind::ComponentTransfer},
      {"feComposite", FilterKind::Composite},
      {"feConvolveMatrix", FilterKind::ConvolveMatrix},
      {"feDiffuseLighting", FilterKind::DiffuseLighting},
      {"feDisplacementMap", FilterKind::DisplacementMap},
      {"feDropShadow", FilterKind::DropShadow},
      {"feFlood", FilterKind::Flood},
      {"feGaussianBlur", FilterKind::GaussianBlur},
      {"feImage", FilterKind::Image},
      {"feMerge", FilterKind::Merge},
      {"feMorphology", FilterKind::Morphology},
      {"feOffset", FilterKind::Offset},
      {"feSpecularLighting", FilterKind::SpecularLighting},
      {"feTile", FilterKind::Tile},
      {"feTurbulence", FilterKind::Turbulence},
  };
  for (const auto& [n, k] : kinds)
    if (name == n) return k;
  return std::nullopt;
}

// Whether an feImage among the primitives of a filter (its href chain
// `chain`) shows element `e`.
bool shows_element(const std::vector<const Element*>& chain, const Element& e,
                   const std::unordered_map<std::string, const Element*>& ids) {
  for (const Element* l : chain) {
    if (l->name != "filter") break;
    if (l->children.empty()) continue;
    for (const auto& c : l->children) {
      if (c->name != "feImage") continue;
      const std::string* href = c->attribute("href");
      if (!href) href = c->attribute("xlink:href");
      const auto id = href ? parse_iri_fragment(*href) : std::nullopt;
      const auto it = id ? ids.find(*id) : ids.end();
      if (it != ids.end() && it->second == &e) return true;
    }
    break;
  }
  return false;
}

}  // namespace

// ------------------------------------------------------------ the property

bool Converter::filter_content(const Element& e, const Style& st, const Affine& space, int depth,
                               const std::function<void(Converter&)>& draw) {
  const std::optional<std::vector<FilterItem>> items = filter_items(e, st);
  if (!items) {
    draw(*this);
    return true;
  }
  // The content in the element's own scene: the SourceGraphic.
  Converter fc(s_, device_, level_);
  fc.contexts_ = contexts_;
  fc.context_ = context_;
  fc.scene_w_ = scene_w_;
  fc.scene_h_ = scene_h_;
  s_.filter_depth++;
  draw(fc);
  bool invalid = false;
  std::vector<FilterEffect> effects = filter_effects(*items, fc.content_bounds(0, fc.ops_.size(), space), space,
                                                     depth, &invalid);
  const bool filtered = !effects.empty();
  if (filtered) filter_fill(fc, std::move(effects), space);
  s_.filter_depth--;
  if (filtered) return true;
  // Following resvg (filters/filter-functions/one-invalid-url-in-list,
  // filters/filter/no-children): a url() to a missing element, to one that
  // is not a filter, or to a filter that is invalid here (no primitives,
  // an empty region, objectBoundingBox units without a box) is skipped;
  // when nothing else remains, the element is not rendered.
  if (invalid) {
    warn("an element whose filter references nothing usable is not rendered");
    return false;
  }
  // Only functions, none of which applies (no box): the content once more,
  // unfiltered, here.
  draw(*this);
  return true;
}

std::optional<std::vector<FilterItem>> Converter::filter_items(const Element& e, const Style& st) {
  if (st.filter.empty() || iequals(st.filter, "none")) return std::nullopt;
  // An invalid value (syntax, or a function's arguments) is ignored like
  // any invalid declaration: the element is drawn unfiltered
  // (filter-functions/one-invalid-function-in-list,
  // color-adjust-functions-negative, drop-shadow-function-comma-separated).
  std::optional<std::vector<FilterItem>> items = parse_filter_list(st.filter);
  if (!items) {
    warn("invalid filter value: filter ignored");
    return std::nullopt;
  }
  if (items->empty()) return std::nullopt;
  for (FilterItem& item : *items) {
    if (item.url) continue;
    item.primitive = filter_function(item.function, item.args, st);
    if (!item.primitive) {
      warn("invalid filter function " + item.function + "(): filter ignored");
      return std::nullopt;
    }
  }
  for (const FilterItem& item : *items) {
    const Element* f = item.url ? find(item.id) : nullptr;
    if (!f || f->name != "filter") continue;
    // A filter whose feImage shows the filtered element itself would
    // never end: resvg drops such a filter property
    // (filters/feImage/self-recursive), and so do we.
    if (shows_element(href_chain(*f, "filters"), e, s_.doc.ids)) {
      warn("a filter whose <feImage> shows the filtered element itself is ignored");
      return std::nullopt;
    }
    // An element reached again through another feImage, whose filter is
    // being resolved already.
    if (std::find(s_.active_filters.begin(), s_.active_filters.end(), f) != s_.active_filters.end()) {
      warn("recursive filter reference through <feImage>: the inner element is drawn unfiltered");
      return std::nullopt;
    }
  }
  if (s_.filter_depth >= kMaxFilterDepth) {
    warn("filters nested more than " + std::to_string(kMaxFilterDepth) + " deep: the innermost are drawn unfiltered");
    return std::nullopt;
  }
  if (s_.filter_effects + items->size() > kMaxFilterEffects) {
    warn("more than " + std::to_string(kMaxFilterEffects) + " filter effects: further filters are not applied");
    return std::nullopt;
  }
  return items;
}

std::vector<FilterEffect> Converter::filter_effects(const std::vector<FilterItem>& items, const Bounds& bbox,
                                                    const Affine& space, int depth, bool* invalid) {
  std::vector<FilterEffect> effects;
  for (const FilterItem& item : items) {
    if (item.url) {
      const Element* f = item.external ? nullptr : find(item.id);
      if (item.external)
        warn("references to other documents are not supported: filter reference ignored");
      else if (!f || f->name != "filter")
        warn("filter reference to a missing element or to one that is not a <filter>");
      std::optional<FilterEffect> fx;
      if (f && f->name == "filter") fx = filter_effect(*f, bbox, space, depth);
      if (fx) effects.push_back(std::move(*fx));
      else *invalid = true;
      continue;
    }
    // A filter function has no filter region of its own; resvg gives it
    // one around the box, larger for the blurs (filters/filter-functions/
    // drop-shadow-function-filter-region), and skips it on an element
    // without a box.
    if (!has_area(bbox)) {
      warn("filter function on an element without a bounding box area: ignored");
      continue;
    }
    FilterPrimitive p = *item.primitive;
    const bool blurs = p.kind == FilterKind::GaussianBlur || p.kind == FilterKind::DropShadow;
    FilterEffect fx;
    fx.xf = space;
    fx.region = blurs ? in_box(bbox, -0.5, -0.5, 2, 2) : in_box(bbox, -0.1, -0.1, 1.2, 1.2);
    p.subregion = fx.region;
    fx.primitives.push_back(std::move(p));
    effects.push_back(std::move(fx));
  }
  return effects;
}

void Converter::filter_fill(Converter& fc, std::vector<FilterEffect> effects, const Affine& space) {
  s_.filter_effects += effects.size();
  // The content's geometry stays here for bounding boxes.
  std::unordered_map<uint32_t, uint32_t> copied;
  fc.for_each_content(0, fc.ops_.size(), [&](const Op& op) {
    if (op.stroke || op.filter || (op.kind != OpKind::Fill && op.kind != OpKind::Bounds)) return;
    auto [it, added] = copied.emplace(op.shape, static_cast<uint32_t>(shapes_.size()));
    if (added) add_shape(fc.shapes_[op.shape]);
    Op bounds = Op::of(OpKind::Bounds);
    bounds.shape = it->second;
    bounds.xf = op.xf;
    ops_.push_back(bounds);
  });
  SceneBuilder b(scene_w_, scene_h_);
  fc.emit(b);
  auto source = std::make_shared<const Scene>(b.finish());
  if (b.flattened_groups()) warn(flattened_groups_warning(b.flattened_groups()));
  tile_encodings_ += fc.tile_encodings_;

  // Each next filter's SourceGraphic is the previous one's result.
  Paint paint;
  paint.type = PaintType::Filter;
  for (size_t i = 0; i + 1 < effects.size(); i++) {
    effects[i].source = source;
    const ViewBox r = region_fill(effects[i].region, space);
    SceneBuilder nb(scene_w_, scene_h_);
    paint.index = nb.add_filter(std::move(effects[i]));
    nb.fill(nb.add_geometry(rect_path(r.x, r.y, r.w, r.h, 0, 0)), Affine{}, FillRule::NonZero, paint);
    source = std::make_shared<const Scene>(nb.finish());
  }
  effects.back().source = source;
  const ViewBox r = region_fill(effects.back().region, space);
  filters_.push_back(std::move(effects.back()));
  paint.index = static_cast<uint32_t>(filters_.size() - 1);
  paints_.push_back(paint);
  // In scene units: the box of the region.
  Op fill = Op::of(OpKind::Fill);
  fill.shape = rect_shape(r);
  fill.paint = static_cast<uint32_t>(paints_.size() - 1);
  fill.filter = true;
  ops_.push_back(fill);
}

// ------------------------------------------------------------ filter elements

std::optional<FilterEffect> Converter::filter_effect(const Element& f, const Bounds& bbox, const Affine& space,
                                                     int depth) {
  // Template inheritance (as for patterns, and in resvg:
  // filters/filter/complex-order-and-xlink-href): each attribute from the
  // first filter of the href chain that has it, the primitives from the
  // first that has children.
  const std::vector<const Element*> chain = href_chain(f, "filters");
  auto attr = [&](const char* name) -> const std::string* {
    for (const Element* l : chain) {
      if (l->name != "filter") break;
      if (const std::string* a = l->attribute(name)) return a;
    }
    return nullptr;
  };
  const bool obb = bounding_box_units(attr("filterUnits"), true);
  const bool primitive_obb = bounding_box_units(attr("primitiveUnits"), false);
  if ((obb || primitive_obb) && !has_area(bbox)) {
    warn("<filter> in objectBoundingBox units on an element without a bounding box area: ignored");
    return std::nullopt;
  }
  // The filter region (FE1 §"Filter region"): -10%, -10%, 120%, 120% by
  // default, of the box or (userSpaceOnUse) of the viewport.
  const double em = font_size_of(f);
  auto len = [&](const char* name, Axis axis, double def) {
    return server_length(attr(name), Length{def, Unit::Percent}, axis, em, obb, kMaxRegionNumber);
  };
  FilterRect region{len("x", Axis::X, -10), len("y", Axis::Y, -10), len("width", Axis::X, 120),
                    len("height", Axis::Y, 120)};
  if (obb) region = in_box(bbox, region.x, region.y, region.w, region.h);
  if (!(region.w > 0 && region.h > 0)) {
    warn("<filter> region of zero or negative size: ignored");
    return std::nullopt;
  }
  const Element* holder = nullptr;
  for (const Element* l : chain) {
    if (l->name != "filter") break;
    if (!l->children.empty()) {
      holder = l;
      break;
    }
  }
  FilterEffect fx;
  fx.xf = space;
  fx.region = region;
  if (holder) {
    const FilterSpace fs{bbox, region, primitive_obb, space, depth};
    std::unordered_map<std::string, int32_t> results;
    s_.active_filters.push_back(&f);
    for (const auto& c : holder->children) filter_primitive(*c, fs, fx.primitives, results);
    s_.active_filters.pop_back();
  }
  // A filter without primitives disables the element's rendering (FE1
  // §"The filter element"; filters/filter/no-children).
  if (fx.primitives.empty()) {
    warn("<filter> without primitives: ignored");
    return std::nullopt;
  }
  return fx;
}

// The input `name` (in, in2) of a primitive (FE1 §"Filter primitive
// attributes"): none, or a result name no earlier primitive gave, is the
// previous primitive's result (SourceGraphic for the first;
// filters/filter/in-to-invalid-2).
int32_t Converter::filter_input(const Element& fe, const char* name, const std::vector<FilterPrimitive>& prims,
                                const std::unordered_map<std::string, int32_t>& results) {
  const int32_t previous = prims.empty() ? FILTER_SOURCE_GRAPHIC : static_cast<int32_t>(prims.size() - 1);
  const std::string* a = fe.attribute(name);
  if (!a) return previous;
  const std::string_view v = trim(*a);
  if (v == "SourceGraphic") return FILTER_SOURCE_GRAPHIC;
  if (v == "SourceAlpha") return FILTER_SOURCE_ALPHA;
  // resvg takes the element's content for these (filters/filter/in=FillPaint,
  // in=FillPaint-with-pattern, in=StrokePaint, enable-background/
  // with-filter-on-the-same-element), and the suite's references show it.
  if (v == "BackgroundImage" || v == "BackgroundAlpha" || v == "FillPaint" || v == "StrokePaint") {
    warn("filter input " + std::string(v) + " is not supported: SourceGraphic used instead");
    return FILTER_SOURCE_GRAPHIC;
  }
  const auto it = results.find(std::string(v));
  return it == results.end() ? previous : it->second;
}

namespace {

// A primitive's lengths in user units (FE1 §"primitiveUnits"): with
// objectBoundingBox, numbers are fractions of the box's width (x), height
// (y) or normalised diagonal, positions relative to its corner.
struct PrimitiveUnits {
  double sx = 1, sy = 1, sd = 1;
  double x0 = 0, y0 = 0;
};

std::string keyword_attr(const Element& fe, const char* name) {
  const std::string* a = fe.attribute(name);
  return a ? std::string(trim(*a)) : std::string();
}

// One or two numbers (stdDeviation, radius, baseFrequency, order), the
// second defaulting to the first; nullopt when absent, and with *invalid
// set when not one or two numbers.
std::optional<std::pair<double, double>> number_pair(const Element& fe, const char* name, bool* invalid) {
  *invalid = false;
  const std::string* a = fe.attribute(name);
  if (!a) return std::nullopt;
  const auto v = parse_numbers(*a);
  if (!v || v->empty() || v->size() > 2) {
    *invalid = true;
    return std::nullopt;
  }
  return std::pair((*v)[0], v->back());
}

EdgeMode edge_mode(const Element& fe, EdgeMode def) {
  const std::string k = keyword_attr(fe, "edgeMode");
  return k == "duplicate" ? EdgeMode::Duplicate
         : k == "wrap"    ? EdgeMode::Wrap
         : k == "mirror"  ? EdgeMode::Mirror
         : k == "none"    ? EdgeMode::None
                          : def;
}

// stdDeviation (FE1 §15.17): a negative value disables the blur (the
// result is the input: filters/filter/invalid-primitive-1), as does an
// invalid list; zero in one direction blurs in the other only.
void std_deviation(const Element& fe, const PrimitiveUnits& u, double def, FilterPrimitive& p) {
  bool bad = false;
  auto v = number_pair(fe, "stdDeviation", &bad);
  if (!v) v = bad ? std::pair(0.0, 0.0) : std::pair(def, def);
  if (v->first < 0 || v->second < 0) v = std::pair(0.0, 0.0);
  p.std_dev_x = v->first * u.sx;
  p.std_dev_y = v->second * u.sy;
}

// feColorMatrix (FE1 §15.10): an invalid type is the initial matrix;
// values that do not fit the type leave the identity
// (filters/feColorMatrix/invalid-type, type=matrix-with-empty-values).
void color_matrix(const Element& fe, FilterPrimitive& p) {
  const std::string type = keyword_attr(fe, "type");
  const std::string* a = fe.attribute("values");
  const auto values = a ? parse_numbers(*a) : std::nullopt;
  const bool one = values && values->size() == 1;
  if (type == "saturate") {
    saturate_matrix(one ? (*values)[0] : 1.0, p.matrix);
  } else if (type == "hueRotate") {
    hue_rotate_matrix(one ? (*values)[0] : 0.0, p.matrix);
  } else if (type == "luminanceToAlpha") {
    const double v[20] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.2125, 0.7154, 0.0721, 0, 0};
    set_matrix(p.matrix, v);
  } else if (values && values->size() == 20) {
    set_matrix(p.matrix, values->data());
  }
}

// One feFuncX (FE1 §15.11): a missing or invalid type, and an empty
// table, are the identity; offset is a number, not a stop's percentage
// (filters/feComponentTransfer/type=gamma-with-an-invalid-offset).
TransferFunction transfer_function(const Element& f) {
  TransferFunction tf;
  const std::string type = keyword_attr(f, "type");
  if (type == "table" || type == "discrete") {
    const std::string* a = f.attribute("tableValues");
    const auto values = a ? parse_numbers(*a) : std::nullopt;
    if (values && !values->empty()) {
      tf.type = type == "table" ? TransferType::Table : TransferType::Discrete;
      tf.table.assign(values->begin(), values->end());
    }
  } else if (type == "linear") {
    tf.type = TransferType::Linear;
    tf.slope = static_cast<float>(number_attr(f, "slope", 1));
    tf.intercept = static_cast<float>(number_attr(f, "intercept", 0));
  } else if (type == "gamma") {
    tf.type = TransferType::Gamma;
    tf.amplitude = static_cast<float>(number_attr(f, "amplitude", 1));
    tf.exponent = static_cast<float>(number_attr(f, "exponent", 1));
    tf.offset = static_cast<float>(number_attr(f, "offset", 0));
  }
  return tf;
}

// feComponentTransfer: the last feFuncX of each channel counts.
void component_transfer(const Element& fe, FilterPrimitive& p) {
  static const char* const names[] = {"feFuncR", "feFuncG", "feFuncB", "feFuncA"};
  for (const auto& c : fe.children) {
    const auto slot = std::find(std::begin(names), std::end(names), c->name);
    if (slot != std::end(names)) p.funcs[slot - std::begin(names)] = transfer_function(*c);
  }
}

// feComposite (FE1 §15.12); an invalid operator is over.
void composite(const Element& fe, FilterPrimitive& p) {
  static const std::pair<const char*, CompositeOp> ops[] = {
      {"over", CompositeOp::Over}, {"in", CompositeOp::In},   {"out", CompositeOp::Out},
      {"atop", CompositeOp::Atop}, {"xor", CompositeOp::Xor}, {"arithmetic", CompositeOp::Arithmetic},
      {"lighter", CompositeOp::Lighter}};
  const std::string op = keyword_attr(fe, "operator");
  for (const auto& [n, o] : ops)
    if (op == n) p.op = o;
  static const char* const ks[] = {"k1", "k2", "k3", "k4"};
  for (int i = 0; i < 4; i++) p.k[i] = number_attr(fe, ks[i], 0);
}

// feConvolveMatrix (FE1 §15.13). An order that is not one or two positive
// integers (truncated), a kernel of another size, a target outside the
// kernel, or a zero divisor put the primitive in error: its result is
// transparent black (filters/feConvolveMatrix/order-with-a-negative-value-1,
// targetX=3, divisor=0).
void convolve_matrix(const Element& fe, FilterPrimitive& p) {
  bool bad = false;
  const auto order = number_pair(fe, "order", &bad);
  const double ox = order ? std::trunc(order->first) : 3, oy = order ? std::trunc(order->second) : 3;
  const std::string* km = fe.attribute("kernelMatrix");
  const auto kernel = km ? parse_numbers(*km) : std::nullopt;
  if (bad || !(ox >= 1 && oy >= 1 && ox * oy <= 1e6) || !kernel || static_cast<double>(kernel->size()) != ox * oy)
    return make_transparent(p);
  double sum = 0;
  for (double k : *kernel) sum += k;
  const double divisor = number_attr(fe, "divisor", sum == 0 ? 1 : sum);
  const double tx = std::trunc(number_attr(fe, "targetX", std::floor(ox / 2)));
  const double ty = std::trunc(number_attr(fe, "targetY", std::floor(oy / 2)));
  if (divisor == 0 || tx < 0 || tx >= ox || ty < 0 || ty >= oy) return make_transparent(p);
  p.order_x = static_cast<int>(ox);
  p.order_y = static_cast<int>(oy);
  p.kernel.assign(kernel->begin(), kernel->end());
  p.divisor = divisor;
  p.bias = number_attr(fe, "bias", 0);
  p.target_x = static_cast<int>(tx);
  p.target_y = static_cast<int>(ty);
  p.edge_mode = edge_mode(fe, EdgeMode::Duplicate);
  p.preserve_alpha = keyword_attr(fe, "preserveAlpha") == "true";
}

// feDistantLight, fePointLight, feSpotLight (FE1 §15.15, 15.21, 15.23).
LightSource light_source(const Element& light, const PrimitiveUnits& u) {
  LightSource l;
  if (light.name == "feDistantLight") {
    l.type = LightType::Distant;
    l.azimuth = number_attr(light, "azimuth", 0);
    l.elevation = number_attr(light, "elevation", 0);
    return l;
  }
  auto point = [&](const char* x, const char* y, const char* z, double& px, double& py, double& pz) {
    px = u.x0 + number_attr(light, x, 0) * u.sx;
    py = u.y0 + number_attr(light, y, 0) * u.sy;
    pz = number_attr(light, z, 0) * u.sd;
  };
  l.type = LightType::Point;
  point("x", "y", "z", l.x, l.y, l.z);
  if (light.name != "feSpotLight") return l;
  l.type = LightType::Spot;
  point("pointsAtX", "pointsAtY", "pointsAtZ", l.points_at_x, l.points_at_y, l.points_at_z);
  // A non-positive exponent is taken as 1, as resvg does
  // (filters/feSpotLight/specularExponent=-10).
  l.specular_exponent = number_attr(light, "specularExponent", 1);
  if (!(l.specular_exponent > 0)) l.specular_exponent = 1;
  if (const std::string* a = light.attribute("limitingConeAngle"))
    if (const auto v = parse_number(*a)) {
      l.has_cone = true;
      l.limiting_cone_angle = *v;
    }
  return l;
}

// feDiffuseLighting, feSpecularLighting (FE1 §15.14, §15.22):
// lighting-color's alpha plays no part
// (filters/feDiffuseLighting/lighting-color=hsla). Without a light
// source, or with a specular exponent outside [1, 128], the primitive is
// in error (resvg: filters/feDiffuseLighting/no-light-source,
// feSpecularLighting/specularExponent=256).
void lighting(const Element& fe, const PrimitiveUnits& u, FilterPrimitive& p) {
  const RGBA lc = own_property<RGBA>(fe, "lighting-color", RGBA{1, 1, 1, 1}, color_or_current);
  p.color[0] = lc.r, p.color[1] = lc.g, p.color[2] = lc.b, p.color[3] = 1;
  p.surface_scale = number_attr(fe, "surfaceScale", 1);
  p.diffuse_constant = number_attr(fe, "diffuseConstant", 1);
  p.specular_constant = number_attr(fe, "specularConstant", 1);
  p.specular_exponent = number_attr(fe, "specularExponent", 1);
  const auto light = std::find_if(fe.children.begin(), fe.children.end(), [](const auto& c) {
    return c->name == "feDistantLight" || c->name == "fePointLight" || c->name == "feSpotLight";
  });
  const bool exponent_ok = p.specular_exponent >= 1 && p.specular_exponent <= 128;
  if (light == fe.children.end() || (p.kind == FilterKind::SpecularLighting && !exponent_ok))
    return make_transparent(p);
  p.light = light_source(**light, u);
}

// feDisplacementMap (FE1 §15.16): one scale for both directions; with
// objectBoundingBox, of the box's mean side, as resvg has it.
void displacement_map(const Element& fe, const PrimitiveUnits& u, FilterPrimitive& p) {
  p.scale = number_attr(fe, "scale", 0) * (u.sx + u.sy) / 2;
  auto channel = [&](const char* name) -> uint8_t {
    const std::string k = keyword_attr(fe, name);
    return k == "R" ? 0 : k == "G" ? 1 : k == "B" ? 2 : 3;
  };
  p.x_channel = channel("xChannelSelector");
  p.y_channel = channel("yChannelSelector");
}

// feMorphology (FE1 §15.20). FE1 makes a zero or negative radius the
// identity; resvg (after Chrome and Safari, by its comment) takes a
// missing, invalid or zero radius as 1, and a negative one as the
// default 1 too, and the suite's references show that 1
// (filters/feMorphology/zero-radius, no-radius, empty-radius,
// radius-with-too-many-values all erode by a pixel and a half at 300 px).
void morphology(const Element& fe, const PrimitiveUnits& u, FilterPrimitive& p) {
  p.dilate = keyword_attr(fe, "operator") == "dilate";
  double rx = 1, ry = 1;
  if (const std::string* a = fe.attribute("radius")) {
    const auto v = parse_numbers(*a);
    rx = ry = 0;
    if (v && (v->size() == 1 || v->size() == 2)) rx = (*v)[0], ry = v->back();
    if (rx == 0) rx = 1;
    if (ry == 0) ry = 1;
    if (rx < 0 || ry < 0) rx = ry = 1;
  }
  p.radius_x = rx * u.sx;
  p.radius_y = ry * u.sy;
}

// feTurbulence (FE1 §15.25). A negative frequency is an error: none (as
// resvg); with objectBoundingBox, frequencies are per box side.
void turbulence(const Element& fe, const PrimitiveUnits& u, FilterPrimitive& p) {
  bool bad = false;
  const auto f = number_pair(fe, "baseFrequency", &bad);
  if (f && f->first >= 0 && f->second >= 0) {
    p.base_frequency_x = f->first / u.sx;
    p.base_frequency_y = f->second / u.sy;
  }
  p.num_octaves = static_cast<int>(std::clamp(std::round(number_attr(fe, "numOctaves", 1)), 0.0, 1e6));
  p.seed = number_attr(fe, "seed", 0);
  p.stitch_tiles = keyword_attr(fe, "stitchTiles") == "stitch";
  p.fractal_noise = keyword_attr(fe, "type") == "fractalNoise";
}

// The parameters of every primitive but feImage.
void primitive_parameters(const Element& fe, const PrimitiveUnits& u, FilterPrimitive& p) {
  switch (p.kind) {
    case FilterKind::Blend:
      if (const std::string* m = fe.attribute("mode"))
        p.blend_mode = static_cast<uint8_t>(parse_blend_mode(*m).value_or(BlendMode::Normal));
      break;
    case FilterKind::ColorMatrix: color_matrix(fe, p); break;
    case FilterKind::ComponentTransfer: component_transfer(fe, p); break;
    case FilterKind::Composite: composite(fe, p); break;
    case FilterKind::ConvolveMatrix: convolve_matrix(fe, p); break;
    case FilterKind::DiffuseLighting:
    case FilterKind::SpecularLighting: lighting(fe, u, p); break;
    case FilterKind::DisplacementMap: displacement_map(fe, u, p); break;
    case FilterKind::DropShadow:
      p.dx = number_attr(fe, "dx", 2) * u.sx;
      p.dy = number_attr(fe, "dy", 2) * u.sy;
      std_deviation(fe, u, 2, p);
      flood(fe, p.color);
      break;
    case FilterKind::Flood: flood(fe, p.color); break;
    case FilterKind::GaussianBlur:
      std_deviation(fe, u, 0, p);
      p.edge_mode = edge_mode(fe, EdgeMode::None);
      break;
    case FilterKind::Morphology: morphology(fe, u, p); break;
    case FilterKind::Offset:
      p.dx = number_attr(fe, "dx", 0) * u.sx;
      p.dy = number_attr(fe, "dy", 0) * u.sy;
      break;
    case FilterKind::Turbulence: turbulence(fe, u, p); break;
    case FilterKind::Image:
    case FilterKind::Merge:
    case FilterKind::Tile: break;
  }
}

}  // namespace

void Converter::filter_primitive(const Element& fe, const FilterSpace& fs, std::vector<FilterPrimitive>& prims,
                                 std::unordered_map<std::string, int32_t>& results) {
  const auto kind = primitive_kind(fe.name);
  if (!kind) {
    if (fe.name.rfind("fe", 0) == 0) warn("<" + fe.name + "> is not a filter primitive: ignored");
    return;
  }
  FilterPrimitive p;
  p.kind = *kind;
  p.linear_rgb = linear_rgb(fe);
  auto input = [&](const Element& el, const char* name) { return filter_input(el, name, prims, results); };
  std::vector<int32_t> referenced;
  switch (p.kind) {
    case FilterKind::Flood:
    case FilterKind::Image:
    case FilterKind::Turbulence: break;
    case FilterKind::Merge:
      for (const auto& c : fe.children)
        if (c->name == "feMergeNode") p.inputs.push_back(input(*c, "in"));
      referenced = p.inputs;
      break;
    case FilterKind::Blend:
    case FilterKind::Composite:
    case FilterKind::DisplacementMap:
      p.in = input(fe, "in");
      p.in2 = input(fe, "in2");
      referenced = {p.in, p.in2};
      break;
    default:
      p.in = input(fe, "in");
      referenced = {p.in};
      break;
  }
  p.subregion = primitive_subregion(fe, fs, p.kind, referenced, prims);
  PrimitiveUnits u;
  if (fs.primitive_obb) {
    u.sx = fs.bbox.width();
    u.sy = fs.bbox.height();
    u.sd = std::sqrt((u.sx * u.sx + u.sy * u.sy) / 2);
    u.x0 = fs.bbox.x0;
    u.y0 = fs.bbox.y0;
  }
  if (p.kind == FilterKind::Image) fe_image(fe, fs, p);
  else primitive_parameters(fe, u, p);
  // A zero or negative width or height: transparent black (FE1 §"Filter
  // primitive subregion"; filters/filter/invalid-subregion).
  if (!(p.subregion.w > 0 && p.subregion.h > 0)) make_transparent(p);
  if (const std::string* r = fe.attribute("result"))
    if (!trim(*r).empty()) results[std::string(trim(*r))] = static_cast<int32_t>(prims.size());
  prims.push_back(std::move(p));
}

// The subregion (FE1 §"Filter primitive subregion"): x, y, width and
// height default to the union of the referenced results' subregions, or
// to the filter region when there is none, when one is a standard input,
// and for feTile (filters/feTile/simple-case tiles the 10 x 10 subregion
// that feOffset inherits from feFlood). Percentages and numbers are
// fractions of the box with primitiveUnits="objectBoundingBox", user
// lengths otherwise.
FilterRect Converter::primitive_subregion(const Element& fe, const FilterSpace& fs, FilterKind kind,
                                          const std::vector<int32_t>& referenced,
                                          const std::vector<FilterPrimitive>& prims) {
  FilterRect sub = fs.region;
  if (kind != FilterKind::Tile && !referenced.empty() &&
      std::all_of(referenced.begin(), referenced.end(), [](int32_t in) { return in >= 0; })) {
    sub = prims[referenced[0]].subregion;
    for (int32_t in : referenced) sub = unite(sub, prims[in].subregion);
  }
  const double em = font_size_of(fe);
  auto coord = [&](const char* name, Axis axis, double& v, bool size) {
    const std::string* a = fe.attribute(name);
    const auto l = a ? parse_length(*a, CalcOk::No, kMaxRegionNumber) : std::nullopt;
    if (!l) return;
    if (!fs.primitive_obb) {
      v = to_user(*l, axis, em);
      return;
    }
    const double frac = l->unit == Unit::Percent ? l->value / 100 : to_user(*l, axis, em);
    const double base = axis == Axis::X ? fs.bbox.width() : fs.bbox.height();
    v = size ? frac * base : (axis == Axis::X ? fs.bbox.x0 : fs.bbox.y0) + frac * base;
  };
  coord("x", Axis::X, sub.x, false);
  coord("y", Axis::Y, sub.y, false);
  coord("width", Axis::X, sub.w, true);
  coord("height", Axis::Y, sub.h, true);
  return sub;
}

// feImage (FE1 §15.19). An element reference is drawn like a use of it,
// its user space the filtered element's moved to the subregion's corner
// (resvg, and the suite: filters/feImage/link-to-g,
// with-x-y-and-protruding-subregion-1); a raster (or SVG document) is
// placed in the subregion by preserveAspectRatio, as an <image> in its
// viewport. Anything unusable leaves a transparent result.
void Converter::fe_image(const Element& fe, const FilterSpace& fs, FilterPrimitive& p) {
  const std::string* href = fe.attribute("href");
  if (!href) href = fe.attribute("xlink:href");
  const FilterRect sub = p.subregion;
  if (!href || trim(*href).empty() || !(sub.w > 0 && sub.h > 0)) return;
  const Affine corner = Affine::translate(sub.x, sub.y);
  if (const auto id = parse_iri_fragment(*href)) {
    const Element* target = find(*id);
    if (!target) return;
    if (s_.filter_depth >= kMaxFilterDepth) {
      warn("filters nested more than " + std::to_string(kMaxFilterDepth) + " deep: the innermost are drawn unfiltered");
      return;
    }
    // The element's scene is in the filter's user space.
    Converter ic(s_, device_ * fs.space, level_);
    ic.document_space_ = false;
    ic.scene_w_ = fs.region.w;
    ic.scene_h_ = fs.region.h;
    Context ctx = document_context(*target, false);
    ctx.ctm = corner;
    s_.filter_depth++;
    ic.render(*target, ctx, fs.depth + 1);
    s_.filter_depth--;
    SceneBuilder b(ic.scene_w_, ic.scene_h_);
    ic.emit(b);
    Scene scene = b.finish();
    if (b.flattened_groups()) warn(flattened_groups_warning(b.flattened_groups()));
    tile_encodings_ += ic.tile_encodings_;
    if (std::any_of(scene.paths.begin(), scene.paths.end(), [](const ScenePath& sp) { return !sp.is_clip; }))
      p.scene = std::make_shared<const Scene>(std::move(scene));
    return;
  }
  AspectRatio ar;
  if (const std::string* a = fe.attribute("preserveAspectRatio")) ar = parse_aspect_ratio(*a).value_or(ar);
  const ViewBox vp{0, 0, sub.w, sub.h};
  const LoadedImage& li = load_image(*href);
  if (!li.error.empty()) {
    warn("<feImage> not rendered: " + li.error);
    return;
  }
  if (li.raster_bytes) {
    // A w x h raster's pixels to user space.
    auto placed = [&](double w, double h) { return corner * view_box_transform({0, 0, w, h}, ar, sub.w, sub.h); };
    std::string why;
    int k = 1;
    std::shared_ptr<const Image> raster =
        raster_for(li, [&](int w, int h) { return fs.space * placed(w, h); }, &k, &why);
    if (!raster) {
      warn("<feImage> not rendered: " + why);
      return;
    }
    p.image = std::move(raster);
    // image-rendering on the feImage (painting/image-rendering/on-feImage).
    p.image_pixelated = inherited_property<TextureFilter>(fe, "image-rendering", TextureFilter::Bicubic,
                                                          [](std::string_view v, TextureFilter) {
                                                            return parse_image_rendering(v);
                                                          }) == TextureFilter::Nearest;
    // A reduced raster's texels cover k x k of the image's own.
    p.image_xf = placed(li.width, li.height) * Affine::scale(k, k);
    return;
  }
  // An SVG document: its scene, clipped to the subregion.
  const std::string_view h = trim(*href);
  const std::string shown = h.size() >= 5 && iequals(h.substr(0, 5), "data:") ? "data:..." : std::string(h);
  std::optional<Embedded> doc = embed_document(li, shown, [&](double, double) { return vp; }, ar, fs.space * corner);
  if (!doc || doc->scene.paths.empty()) return;
  SceneBuilder b(sub.w, sub.h);
  b.push();
  b.clip(b.add_geometry(rect_path(sub.x, sub.y, sub.w, sub.h, 0, 0)), Affine{}, FillRule::NonZero);
  b.activate();
  b.append(doc->scene, corner * doc->place);
  b.pop();
  p.scene = std::make_shared<const Scene>(b.finish());
}

// ------------------------------------------------------------ filter functions

namespace {

// An amount of a colour-adjusting function: <number> | <percentage>, not
// negative; `def` when omitted (FE1 §"Supported Filter Functions"). A
// negative value makes the whole value invalid
// (filters/filter-functions/color-adjust-functions-negative).
std::optional<double> function_amount(std::string_view args, double def) {
  if (args.empty()) return def;
  const auto l = parse_length(args);
  if (!l || (l->unit != Unit::None && l->unit != Unit::Percent) || l->value < 0) return std::nullopt;
  return l->unit == Unit::Percent ? l->value / 100 : l->value;
}

// hue-rotate()'s <angle> | <zero> in degrees: a number other than 0 needs
// a unit (filters/filter-functions/hue-rotate-function-45).
std::optional<double> function_angle(std::string_view args) {
  if (args.empty()) return 0.0;
  Scanner s(args);
  const auto v = s.number();
  if (!v) return std::nullopt;
  const std::string_view unit = s.word();
  if (!s.at_end()) return std::nullopt;
  if (iequals(unit, "deg")) return *v;
  if (iequals(unit, "grad")) return *v * 0.9;
  if (iequals(unit, "rad")) return *v * 180 / M_PI;
  if (iequals(unit, "turn")) return *v * 360;
  if (unit.empty() && *v == 0) return 0.0;
  return std::nullopt;
}

// The parts of a function's arguments between white space, parenthesised
// groups (a colour's) kept whole.
std::vector<std::string_view> split_parts(std::string_view args) {
  std::vector<std::string_view> parts;
  for (size_t i = 0; i < args.size();) {
    while (i < args.size() && is_ws(args[i])) i++;
    if (i == args.size()) break;
    size_t j = i;
    for (int depth = 0; j < args.size() && (depth > 0 || !is_ws(args[j])); j++) {
      if (args[j] == '(') depth++;
      if (args[j] == ')') depth--;
    }
    parts.push_back(args.substr(i, j - i));
    i = j;
  }
  return parts;
}

TransferFunction linear_transfer(double slope, double intercept) {
  TransferFunction f;
  f.type = TransferType::Linear;
  f.slope = static_cast<float>(slope);
  f.intercept = static_cast<float>(intercept);
  return f;
}

TransferFunction table_transfer(std::vector<float> values) {
  TransferFunction f;
  f.type = TransferType::Table;
  f.table = std::move(values);
  return f;
}

// The colour-adjusting functions as their primitives (FE1 §"Shorthands
// Defined"); false for a name that is none of them. grayscale, invert,
// opacity and sepia clamp their amount to 1.
bool color_function(std::string_view name, double v, FilterPrimitive& p) {
  const double c = std::min(v, 1.0), k = 1 - c;
  auto rgb = [&](const TransferFunction& f) {
    p.kind = FilterKind::ComponentTransfer;
    p.funcs[0] = p.funcs[1] = p.funcs[2] = f;
  };
  auto matrix = [&](const double (&m)[20]) {
    p.kind = FilterKind::ColorMatrix;
    set_matrix(p.matrix, m);
  };
  if (name == "brightness") {
    rgb(linear_transfer(v, 0));
  } else if (name == "contrast") {
    rgb(linear_transfer(v, 0.5 - 0.5 * v));
  } else if (name == "grayscale") {
    matrix({0.2126 + 0.7874 * k, 0.7152 - 0.7152 * k, 0.0722 - 0.0722 * k, 0, 0,
            0.2126 - 0.2126 * k, 0.7152 + 0.2848 * k, 0.0722 - 0.0722 * k, 0, 0,
            0.2126 - 0.2126 * k, 0.7152 - 0.7152 * k, 0.0722 + 0.9278 * k, 0, 0,
            0, 0, 0, 1, 0});
  } else if (name == "invert") {
    rgb(table_transfer({static_cast<float>(c), static_cast<float>(1 - c)}));
  } else if (name == "opacity") {
    p.kind = FilterKind::ComponentTransfer;
    p.funcs[3] = table_transfer({0, static_cast<float>(c)});
  } else if (name == "saturate") {
    p.kind = FilterKind::ColorMatrix;
    saturate_matrix(v, p.matrix);
  } else if (name == "sepia") {
    matrix({0.393 + 0.607 * k, 0.769 - 0.769 * k, 0.189 - 0.189 * k, 0, 0,
            0.349 - 0.349 * k, 0.686 + 0.314 * k, 0.168 - 0.168 * k, 0, 0,
            0.272 - 0.272 * k, 0.534 - 0.534 * k, 0.131 + 0.869 * k, 0, 0,
            0, 0, 0, 1, 0});
  } else {
    return false;
  }
  return true;
}

}  // namespace

std::optional<FilterPrimitive> Converter::filter_function(std::string_view name, std::string_view args,
                                                          const Style& st) {
  FilterPrimitive p;
  p.in = FILTER_SOURCE_GRAPHIC;
  // The shorthands' equivalents (FE1 §"Shorthands Defined") work in sRGB.
  p.linear_rgb = false;
  // A <length> (no percentage), not negative where `positive`.
  auto length = [&](std::string_view t, bool positive) -> std::optional<double> {
    const auto l = parse_length(t, CalcOk::Yes);
    if (!l || l->unit == Unit::Percent) return std::nullopt;
    const double v = to_user(*l, Axis::X, st.inh.font_size);
    if (positive && v < 0) return std::nullopt;
    return v;
  };
  if (name == "blur") {
    const auto s = args.empty() ? std::optional<double>(0.0) : length(args, true);
    if (!s) return std::nullopt;
    p.kind = FilterKind::GaussianBlur;
    p.std_dev_x = p.std_dev_y = *s;
    p.edge_mode = EdgeMode::None;
    return p;
  }
  if (name == "drop-shadow") {
    // drop-shadow( <color>? && [<length>{2} <length [0,∞]>?] ): white
    // space between the parts, no commas
    // (filters/filter-functions/drop-shadow-function-comma-separated);
    // the colour first or last, currentColor when omitted
    // (drop-shadow-function-color-as-attribute).
    std::vector<std::string_view> parts = split_parts(args);
    auto as_color = [&](std::string_view t) {
      return iequals(t, "currentColor") ? std::optional<RGBA>(st.inh.color) : parse_color(t);
    };
    std::optional<RGBA> color = st.inh.color;
    if (!parts.empty() && !length(parts.front(), false)) {
      color = as_color(parts.front());
      parts.erase(parts.begin());
    } else if (!parts.empty() && !length(parts.back(), false)) {
      color = as_color(parts.back());
      parts.pop_back();
    }
    if (!color || parts.size() < 2 || parts.size() > 3) return std::nullopt;
    double lengths[3] = {0, 0, 0};
    for (size_t i = 0; i < parts.size(); i++) {
      const auto l = length(parts[i], i == 2);  // the blur is not negative
      if (!l) return std::nullopt;
      lengths[i] = *l;
    }
    p.kind = FilterKind::DropShadow;
    p.dx = lengths[0];
    p.dy = lengths[1];
    p.std_dev_x = p.std_dev_y = lengths[2];
    p.color[0] = color->r, p.color[1] = color->g, p.color[2] = color->b, p.color[3] = color->a;
    return p;
  }
  if (name == "hue-rotate") {
    const auto degrees = function_angle(args);
    if (!degrees) return std::nullopt;
    p.kind = FilterKind::ColorMatrix;
    hue_rotate_matrix(*degrees, p.matrix);
    return p;
  }
  const auto amount = function_amount(args, 1);
  if (!amount || !color_function(name, *amount, p)) return std::nullopt;
  return p;
}

}  // namespace mpvg::svg::detail
