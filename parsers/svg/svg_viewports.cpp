// Nested viewports (SVG 2 coords.html#EstablishingANewSVGViewport): an svg
// element inside another, and a symbol (or svg) drawn by a use. The
// viewport is x, y, width, height in the parent's user space (a use's own
// width and height win over its target's); the content's user space maps
// the viewBox into it (preserveAspectRatio); overflow hidden or scroll
// (the default of both elements) clips the content to the viewport, with
// a clip group around it. Percentages inside resolve against the new
// viewport (its viewBox when it has one).
#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_values.h"
#include "parsers/svg/svg_style.h"

namespace mpvg::svg::detail {

// overflow on an element that establishes a viewport (svg, symbol,
// marker): hidden or scroll clip (hidden is their default); visible and
// auto do not; inherit takes the parent's value, the initial visible at
// the root.
bool Converter::clips_overflow(const Element& e) const {
  auto value = [](const Element& x) {
    return property<std::string>(x, "overflow", [](std::string_view v) { return parse_keyword(v); });
  };
  auto p = value(e);
  if (p.state == Prop<std::string>::Unset) return true;
  if (p.state == Prop<std::string>::Initial) return false;  // CSS's initial value: visible
  const Element* at = &e;
  while (p.state == Prop<std::string>::Inherit) {
    at = at->parent;
    if (!at) return false;
    p = value(*at);
    if (p.state == Prop<std::string>::Unset || p.state == Prop<std::string>::Initial)
      return false;  // the parent's computed value: initial (visible)
  }
  return !(p.value == "visible" || p.value == "auto");
}

void Converter::render_viewport(const Element& e, const Context& ctx, int depth, const Element* use) {
  if (!enter(depth)) return;
  Placed pl;
  if (!place(e, Kind::Container, ctx, pl)) return;
  const auto& [st, space, target, clip] = pl;
  (void)target;
  const double em = st.inh.font_size;

  // The viewport, against the parent's viewport.
  auto size = [&](const char* name, Axis axis) -> double {
    if (use)
      if (const auto v = auto_length(*use, name, axis, em)) return *v;
    const auto v = auto_length(e, name, axis, em);
    return v ? *v : percent_base(axis);  // auto: 100%
  };
  const double x = e.name == "svg" || e.name == "symbol" ? length(e, "x", Axis::X, 0, em) : 0;
  const double y = e.name == "svg" || e.name == "symbol" ? length(e, "y", Axis::Y, 0, em) : 0;
  const double w = size("width", Axis::X), h = size("height", Axis::Y);
  // A zero or negative size disables rendering.
  if (!(w > 0 && h > 0)) return;
  std::optional<ViewBox> vb;
  if (const std::string* a = e.attribute("viewBox")) vb = parse_view_box(*a);
  if (vb && !(vb->w > 0 && vb->h > 0)) return;
  AspectRatio ar;
  if (const std::string* a = e.attribute("preserveAspectRatio")) ar = parse_aspect_ratio(*a).value_or(ar);
  const Affine content = space * Affine::translate(x, y) * (vb ? view_box_transform(*vb, ar, w, h) : Affine{});
  if (!content.invertible()) return;

  const bool clipped = clips_overflow(e);

  const size_t start = ops_.size();
  // The viewport clip is part of what the element draws: a filter on the
  // element takes the clipped content as its source. (pl's members, not
  // the bindings: clang before 16 cannot capture a structured binding.)
  auto draw = [&](Converter& c) {
    if (clipped) {
      c.ops_.push_back(Op::of(OpKind::Push));
      Op clip_op = Op::of(OpKind::Clip);
      clip_op.shape = c.rect_shape({x, y, w, h});
      clip_op.xf = pl.space;
      c.ops_.push_back(clip_op);
      c.ops_.push_back(Op::of(OpKind::Activate));
    }
    const double saved_w = s_.percent_w, saved_h = s_.percent_h;
    s_.percent_w = vb ? vb->w : w;
    s_.percent_h = vb ? vb->h : h;
    const Context inner = child_context(pl.st, content, false);
    s_.active.push_back(&e);
    for (const auto& child : e.children) c.render(*child, inner, depth + 1);
    s_.active.pop_back();
    s_.percent_w = saved_w;
    s_.percent_h = saved_h;
    if (clipped) c.ops_.push_back(Op::of(OpKind::Pop));
  };
  if (!filter_content(e, st, space, depth, draw)) return;
  if (!group_content(e, start, st, space, depth)) return;
  if (clip.state == ClipRef::Valid) clip_content(start, *clip.element, space, depth);
  if (clip.state == ClipRef::Shape) clip_shape_content(start, *clip.shape, space, st.inh.font_size);
}

}  // namespace mpvg::svg::detail
