// Paint servers as scene paints (SVG 1.1 §13, SVG 2 pservers.html):
// linearGradient and radialGradient become core Gradients, pattern a core
// Pattern whose tile is a scene converted like any content.
//
// A paint server is resolved for each use, as it depends on the shape:
// objectBoundingBox units need the shape's bounding box, and a pattern's
// strokes are prepared for the tile's size on screen. Every transform ends
// in scene units (core/scene.h): user space to scene units (the shape's
// `space`) after the bounding-box mapping and gradientTransform or
// patternTransform.
//
// Template inheritance (href) follows resvg, as the suite's references do:
// a gradient takes each attribute it lacks from the first element of its
// href chain that has it, geometry (x1, cx, ...) only from gradients of its
// own kind and the shared attributes from either kind; the chain ends at an
// element that is not a gradient. Stops come from the first gradient of the
// chain that has stop children. Patterns inherit from patterns only, their
// content from the first pattern of the chain that has children. A cycle
// ends the chain where it closes.
#include <algorithm>
#include <cmath>

#include "core/paint/paint.h"
#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_style.h"
#include "frame/scene_builder.h"

namespace mpvg::svg::detail {

namespace {

bool is_gradient(const Element& e) { return e.name == "linearGradient" || e.name == "radialGradient"; }
bool is_pattern(const Element& e) { return e.name == "pattern"; }

// The first element of a paint server's href chain for which `has` holds,
// looking no further than the elements `member` accepts; nullptr if none.
template <class Member, class Has>
const Element* first_in_chain(const std::vector<const Element*>& chain, Member member, Has has) {
  for (const Element* l : chain) {
    if (!member(*l)) break;
    if (has(*l)) return l;
  }
  return nullptr;
}

// The attribute `name` of the first element of the chain (as in
// first_in_chain) that has it.
template <class Member>
const std::string* chain_attribute(const std::vector<const Element*>& chain, Member member, const char* name) {
  const Element* l = first_in_chain(chain, member, [&](const Element& e) { return e.attribute(name) != nullptr; });
  return l ? l->attribute(name) : nullptr;
}

bool has_child(const Element& e, std::string_view name) {
  return std::any_of(e.children.begin(), e.children.end(), [&](const auto& c) { return c->name == name; });
}

// Whether a pattern has content. Descriptive elements do not count.
bool has_content(const Element& e) {
  return std::any_of(e.children.begin(), e.children.end(), [](const auto& c) {
    return c->name != "title" && c->name != "desc" && c->name != "metadata";
  });
}

// spreadMethod (SVG 1.1 §13.2.2): an invalid value is the initial pad.
Spread parse_spread(const std::string* v) {
  if (!v) return Spread::Pad;
  const std::string_view t = trim(*v);
  if (t == "reflect") return Spread::Reflect;
  if (t == "repeat") return Spread::Repeat;
  return Spread::Pad;
}

// stop-color and stop-opacity are not inherited (SVG 1.1 §13.2.4, SVG 2
// pservers.html#StopColorProperty): an element's value is its own, or the
// initial one (black, 1); "inherit" takes the parent's.
RGBA stop_color(const Element& e) {
  const auto p = property<RGBA>(e, "stop-color", [&](std::string_view v) -> std::optional<RGBA> {
    if (iequals(trim(v), "currentColor")) return computed_color(e);
    return parse_color(v);
  });
  if (p.state == Prop<RGBA>::Set) return p.value;
  if (p.state == Prop<RGBA>::Inherit && e.parent) return stop_color(*e.parent);
  return RGBA{0, 0, 0, 1};
}

double stop_opacity(const Element& e) {
  const auto p = property<double>(e, "stop-opacity", parse_alpha);
  if (p.state == Prop<double>::Set) return p.value;
  if (p.state == Prop<double>::Inherit && e.parent) return stop_opacity(*e.parent);
  return 1;
}

// The stops of a gradient element (SVG 1.1 §13.2.4): offsets are numbers or
// percentages, clamped to [0, 1] and to at least the previous stop's; a
// missing or invalid offset is 0 (and so the previous one). stop-opacity
// multiplies the colour's alpha. Children other than stop are ignored.
std::vector<ColorStop> gradient_stops(const Element& g) {
  std::vector<ColorStop> stops;
  double last = 0;
  for (const auto& c : g.children) {
    if (c->name != "stop") continue;
    double offset = 0;
    if (const std::string* a = c->attribute("offset")) {
      const auto l = parse_length(*a);
      if (l && l->unit == Unit::None) offset = l->value;
      if (l && l->unit == Unit::Percent) offset = l->value / 100;
    }
    offset = std::max(last, std::clamp(offset, 0.0, 1.0));
    last = offset;
    ColorStop s;
    s.offset = offset;
    s.color = stop_color(*c);
    s.color.a = static_cast<float>(s.color.a * stop_opacity(*c));
    stops.push_back(s);
  }
  return stops;
}

// color-interpolation (SVG 1.1 §11.7.1, inherited): auto and sRGB
// interpolate sRGB-encoded values, linearRGB linear-light ones.
ColorSpace color_interpolation(const Element& e) {
  return inherited_property<ColorSpace>(e, "color-interpolation", ColorSpace::Srgb,
                                        [](std::string_view v, ColorSpace) -> std::optional<ColorSpace> {
                                          const auto k = parse_keyword(v);
                                          if (k && (*k == "auto" || *k == "srgb")) return ColorSpace::Srgb;
                                          if (k && *k == "linearrgb") return ColorSpace::LinearRgb;
                                          return std::nullopt;
                                        });
}

std::array<double, 6> coefficients(const Affine& m) { return {m.a, m.b, m.c, m.d, m.e, m.f}; }

}  // namespace

// The computed value of `color` on e: currentColor in it means the
// parent's (CSS Color 4 §4.4), initially black.
RGBA computed_color(const Element& e) {
  return inherited_property<RGBA>(e, "color", RGBA{0, 0, 0, 1},
                                  [](std::string_view v, const RGBA& parent) -> std::optional<RGBA> {
                                    if (iequals(trim(v), "currentColor")) return parent;
                                    return parse_color(v);
                                  });
}

bool TileKey::operator<(const TileKey& o) const {
  return std::tie(pattern, content, device, width, height, stack) <
         std::tie(o.pattern, o.content, o.device, o.width, o.height, o.stack);
}

std::vector<const Element*> Converter::href_chain(const Element& e, const char* what) {
  std::vector<const Element*> chain{&e};
  for (;;) {
    const Element& last = *chain.back();
    // href wins over xlink:href (SVG 2 linking.html#XLinkRefAttrs).
    const std::string* href = last.attribute("href");
    if (!href) href = last.attribute("xlink:href");
    if (!href) break;
    const auto id = parse_iri_fragment(*href);
    if (!id) {
      if (!trim(*href).empty())
        warn("references to other documents are not supported: <" + last.name + "> href ignored");
      break;
    }
    const Element* t = find(*id);
    if (!t) break;
    if (std::find(chain.begin(), chain.end(), t) != chain.end()) {
      warn(std::string("recursive href between ") + what + ": the chain ends where it repeats");
      break;
    }
    chain.push_back(t);
  }
  return chain;
}

double Converter::server_length(const std::string* text, Length def, Axis axis, double em, bool obb,
                                double max_magnitude) const {
  Length l = def;
  if (text)
    if (const auto v = parse_length(*text, CalcOk::No, max_magnitude)) l = *v;
  if (obb && l.unit == Unit::Percent) return l.value / 100;
  return to_user(l, axis, em);
}

double Converter::font_size_of(const Element& e) {
  return compute_style(e, document_context(e, true)).inh.font_size;
}

std::optional<uint32_t> Converter::make_paint(const PaintSpec& spec, double opacity, ShapeBox& bbox,
                                              const Affine& space) {
  if (spec.kind == PaintSpec::Kind::None || !(opacity > 0)) return std::nullopt;
  Paint paint;
  paint.opacity = static_cast<float>(opacity);
  paint.color = spec.color;  // a colour, or the server's fallback
  if (spec.kind == PaintSpec::Kind::Server) {
    // A context paint's server lies in the context element's space and box.
    ShapeBox context_box{bbox.shapes, bbox.shape, spec.context >= 0 ? contexts_[spec.context].bbox : bbox.b};
    if (spec.context >= 0 && !context_box.b) context_box.b = Bounds{};
    ShapeBox& box = spec.context >= 0 ? context_box : bbox;
    const Affine& in = spec.context >= 0 ? contexts_[spec.context].space : space;
    const ServerPaint sp = spec.server->name == "pattern" ? pattern_paint(*spec.server, box, in)
                                                          : gradient_paint(*spec.server, box, in);
    switch (sp.kind) {
      case ServerPaint::Kind::Paint:
        paint.type = sp.paint.type;
        paint.index = sp.paint.index;
        paint.color = RGBA{};
        break;
      case ServerPaint::Kind::Color: paint.color = sp.color; break;
      case ServerPaint::Kind::Nothing: return std::nullopt;
      case ServerPaint::Kind::Failed:
        // The server cannot paint this shape: the fallback colour applies,
        // and without one nothing is painted (SVG 2 painting.html#SpecifyingPaint;
        // resvg takes the same path for servers without stops or content).
        if (!spec.fallback) return std::nullopt;
        break;
    }
  }
  if (paint.type == PaintType::Solid && !(paint.color.a > 0)) return std::nullopt;
  paints_.push_back(paint);
  return static_cast<uint32_t>(paints_.size() - 1);
}

Converter::ServerPaint Converter::gradient_paint(const Element& g, ShapeBox& bbox, const Affine& space) {
  const std::vector<const Element*> chain = href_chain(g);
  const bool radial = g.name == "radialGradient";
  // The element of the chain an attribute comes from; `geometry` for the
  // attributes of one kind of gradient only.
  auto attr = [&](const char* name, bool geometry) {
    return chain_attribute(
        chain, [&](const Element& l) { return is_gradient(l) && (!geometry || l.name == g.name); }, name);
  };
  ServerPaint out;  // Failed
  const Element* holder = first_in_chain(chain, is_gradient, [](const Element& l) { return has_child(l, "stop"); });
  // No stops: painted as `none` (SVG 1.1 §13.2.4), or with the fallback
  // colour as resvg does; one stop: its colour.
  if (!holder) return out;
  std::vector<ColorStop> stops = gradient_stops(*holder);
  auto solid = [&](const RGBA& c) {
    out.kind = ServerPaint::Kind::Color;
    out.color = c;
    return out;
  };
  if (stops.size() == 1) return solid(stops[0].color);

  const bool obb = bounding_box_units(attr("gradientUnits", false), true);
  const double em = font_size_of(g);
  auto coord = [&](const char* name, Axis axis, Length def) {
    return server_length(attr(name, true), def, axis, em, obb);
  };
  const Spread spread = parse_spread(attr("spreadMethod", false));
  Gradient gr;
  if (radial) {
    const double r = coord("r", Axis::Diagonal, {50, Unit::Percent});
    // r = 0 paints the last stop's colour (SVG 1.1 §13.2.3). A negative r
    // is an error; resvg paints it as r = 0 too.
    if (r < 0) warn("negative r on <radialGradient>: painted as r = 0");
    if (!(r > 0)) return solid(stops.back().color);
    gr.center = {coord("cx", Axis::X, {50, Unit::Percent}), coord("cy", Axis::Y, {50, Unit::Percent})};
    gr.radius = r;
    // fx and fy default to the resolved cx and cy (SVG 1.1 §13.2.3). The
    // core's gradient is the two-point conical one of SVG 2 and canvas: a
    // focal point outside the end circle is not moved onto it (SVG 1.1's
    // correction); the gradient is then a cone, as resvg draws it.
    gr.focal = {coord("fx", Axis::X, {gr.center.x, Unit::None}), coord("fy", Axis::Y, {gr.center.y, Unit::None})};
    gr.focal_radius = coord("fr", Axis::Diagonal, {0, Unit::None});
    if (gr.focal_radius < 0) {
      warn("negative fr on <radialGradient>: taken as 0");
      gr.focal_radius = 0;
    }
    if (gr.focal.x == gr.center.x && gr.focal.y == gr.center.y && gr.focal_radius == gr.radius) {
      // The two circles coincide. SVG 2 (pservers.html#RadialGradientNotes)
      // draws nothing; resvg and Blink (Skia) draw the limit of nearly
      // coincident circles: with pad, the first stop inside the circle and
      // the last outside; with the other spreads, nothing.
      if (spread != Spread::Pad) {
        out.kind = ServerPaint::Kind::Nothing;
        return out;
      }
      gr.focal_radius = 0;
      stops = {{0, stops.front().color}, {1, stops.front().color}, {1, stops.back().color}};
    }
  } else {
    gr.p0 = {coord("x1", Axis::X, {0, Unit::Percent}), coord("y1", Axis::Y, {0, Unit::Percent})};
    gr.p1 = {coord("x2", Axis::X, {100, Unit::Percent}), coord("y2", Axis::Y, {0, Unit::Percent})};
  }
  Affine units;
  if (obb) {
    // A box without area cannot hold the gradient (SVG 1.1 §7.11): the
    // fallback applies, as for a missing server.
    const Bounds& b = bbox.get();
    if (b.empty() || !(b.width() > 0) || !(b.height() > 0)) return out;
    units = Affine{b.width(), 0, 0, b.height(), b.x0, b.y0};
  }
  // Both ends of the vector in one point: the last stop's colour (SVG 1.1 §13.2.2).
  if (!radial && gr.p0.x == gr.p1.x && gr.p0.y == gr.p1.y) return solid(stops.back().color);

  Affine gt;
  if (const std::string* a = attr("gradientTransform", false)) gt = parse_transform(*a).value_or(Affine{});
  gt = with_origin(g, gt, em);
  gr.xf = space * units * gt;
  // A degenerate transform: the gradient covers no area.
  if (!gr.xf.invertible()) {
    out.kind = ServerPaint::Kind::Nothing;
    return out;
  }
  gr.stops = std::move(stops);
  gr.spread = spread;
  gr.interpolation = color_interpolation(g);
  gradients_.push_back(std::move(gr));
  out.kind = ServerPaint::Kind::Paint;
  out.paint.type = radial ? PaintType::RadialGradient : PaintType::LinearGradient;
  out.paint.index = static_cast<uint32_t>(gradients_.size() - 1);
  return out;
}

Converter::ServerPaint Converter::pattern_paint(const Element& p, ShapeBox& bbox, const Affine& space) {
  const std::vector<const Element*> chain = href_chain(p);
  auto attr = [&](const char* name) { return chain_attribute(chain, is_pattern, name); };
  ServerPaint out;  // Failed
  const Element* content = first_in_chain(chain, is_pattern, has_content);
  if (!content) return out;

  const bool obb = bounding_box_units(attr("patternUnits"), true);
  const bool content_obb = bounding_box_units(attr("patternContentUnits"), false);
  std::optional<ViewBox> vb;
  if (const std::string* a = attr("viewBox")) vb = parse_view_box(*a);
  // A viewBox of zero width or height disables rendering (SVG 1.1 §7.7).
  if (vb && (vb->w == 0 || vb->h == 0)) {
    out.kind = ServerPaint::Kind::Nothing;
    return out;
  }
  AspectRatio ar;
  if (const std::string* a = attr("preserveAspectRatio")) ar = parse_aspect_ratio(*a).value_or(ar);

  // patternContentUnits is ignored when there is a viewBox (SVG 1.1 §13.3).
  Bounds b;
  if (obb || (content_obb && !vb)) {
    b = bbox.get();
    if (b.empty() || !(b.width() > 0) || !(b.height() > 0)) return out;
  }
  const double em = font_size_of(p);
  auto len = [&](const char* name, Axis axis) { return server_length(attr(name), Length{}, axis, em, obb); };
  double x = len("x", Axis::X), y = len("y", Axis::Y), w = len("width", Axis::X), h = len("height", Axis::Y);
  if (obb) {
    x = b.x0 + x * b.width();
    y = b.y0 + y * b.height();
    w *= b.width();
    h *= b.height();
  }
  // A tile of zero size disables the pattern; a negative one is an error
  // (SVG 1.1 §13.3): either way the fallback applies, as in resvg.
  if (!(w > 0 && h > 0)) return out;

  Affine pt;
  if (const std::string* a = attr("patternTransform")) pt = parse_transform(*a).value_or(Affine{});
  pt = with_origin(p, pt, em);
  // The tile's own units: its top left corner at (x, y) of the pattern
  // space, which patternTransform maps to the user space.
  const Affine xf = space * pt * Affine::translate(x, y);
  const Affine content_xf = vb            ? view_box_transform(*vb, ar, w, h)
                            : content_obb ? Affine::scale(b.width(), b.height())
                                          : Affine{};
  if (!xf.invertible() || !content_xf.invertible()) {
    out.kind = ServerPaint::Kind::Nothing;
    return out;
  }
  if (level_ + 1 > kMaxPatternDepth) {
    warn("patterns nested more than " + std::to_string(kMaxPatternDepth) +
         " deep: the innermost are not rendered");
    out.kind = ServerPaint::Kind::Nothing;
    return out;
  }
  // A pattern used inside its own tile (directly, or through other
  // patterns) would never end: the inner use paints nothing, as resvg
  // replaces such paints by none.
  if (std::find(s_.active_patterns.begin(), s_.active_patterns.end(), &p) != s_.active_patterns.end()) {
    warn("recursive pattern reference: the inner use is not rendered");
    out.kind = ServerPaint::Kind::Nothing;
    return out;
  }

  // overflow on a pattern (SVG 1.1 §13.3 leaves overflow=visible
  // undefined): the tile clips its content, as resvg does.
  const Affine tile_device = device_ * xf;
  const TileKey key{&p,
                    coefficients(content_xf),
                    {tile_device.a, tile_device.b, tile_device.c, tile_device.d},
                    w,
                    h,
                    s_.active_patterns};
  auto found = s_.tiles.find(key);
  if (found == s_.tiles.end()) {
    s_.active_patterns.push_back(&p);
    Converter tc(s_, tile_device, level_ + 1);
    Scene scene = tc.convert_tile(*content, content_xf, w, h);
    s_.active_patterns.pop_back();
    Tile t;
    const bool fills =
        std::any_of(scene.paths.begin(), scene.paths.end(), [](const ScenePath& sp) { return !sp.is_clip; });
    if (fills) t.scene = std::make_shared<const Scene>(std::move(scene));
    t.encodings = tc.tile_encodings_;
    found = s_.tiles.emplace(key, std::move(t)).first;
  }
  const Tile& tile = found->second;
  // Content that paints nothing: the fallback applies, as in resvg.
  if (!tile.scene) return out;
  // The encoder encodes a tile once per output scale it is used at, nested
  // tiles included: uses at distinct scales multiply from level to level.
  // The count here (every use) bounds that from above. Past the budget,
  // further uses are not rendered rather than exhausting memory.
  if (tile_encodings_ + 1 + tile.encodings > kMaxTileEncodings) {
    warn("patterns would need more than " + std::to_string(kMaxTileEncodings) +
         " tile encodings: further pattern uses are not rendered");
    out.kind = ServerPaint::Kind::Nothing;
    return out;
  }
  tile_encodings_ += 1 + tile.encodings;
  const auto [it, added] = pattern_of_.emplace(std::make_pair(tile.scene.get(), coefficients(xf)),
                                               static_cast<uint32_t>(patterns_.size()));
  if (added) patterns_.push_back(Pattern{tile.scene, xf});
  out.kind = ServerPaint::Kind::Paint;
  out.paint.type = PaintType::Pattern;
  out.paint.index = it->second;
  return out;
}

Scene Converter::convert_tile(const Element& content, const Affine& content_xf, double width, double height) {
  // Properties inherit into the content from the pattern element and its
  // ancestors, not from the element that references the pattern (SVG 1.1
  // §13.3).
  const Style st = compute_style(content, document_context(content, false));
  const Context ctx = child_context(st, content_xf, false);
  scene_w_ = width;
  scene_h_ = height;
  for (const auto& c : content.children) render(*c, ctx, 1);
  SceneBuilder b(width, height);
  emit(b);
  Scene tile = b.finish();
  if (b.flattened_groups()) warn(flattened_groups_warning(b.flattened_groups()));
  return tile;
}

}  // namespace mpvg::svg::detail
