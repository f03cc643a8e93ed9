// Group opacity, mix-blend-mode, isolation and masks (SVG 2 render.html
// #ObjectAndGroupOpacityProperties, Compositing and Blending 1 §3, CSS
// Masking 1 §7) as the core's transparency groups (core/group.h).
//
// An element's converted content ops_[start, end) becomes, when it needs
// one, a group: GroupBegin, its mask (a group of mask type, first), the
// content, GroupEnd. Every such group is isolated, as an element with
// opacity, a mask, a blend mode or isolation: isolate is a stacking context
// in CSS; plain containers are not groups at all. Opacity on content that
// is one fill folds into its paint instead, which is exact.
#include <algorithm>

#include "parsers/svg/svg_converter.h"

namespace mpvg::svg::detail {

// A mask value (see resolve_reference): a reference back into a mask
// being converted (a mask on itself, or on its content) is ignored.
MaskRef Converter::resolve_mask(const std::string& value) {
  return resolve_reference(value, "mask", "mask", s_.active_masks);
}

// Wraps the element content ops_[start, end) in the group that its
// opacity, mask, mix-blend-mode and isolation make. Returns false when the
// element is not rendered at all (an invalid mask reference).
bool Converter::group_content(size_t start, const Style& st, const Affine& space, int depth) {
  const MaskRef mask = resolve_mask(st.mask);
  if (mask.state == MaskRef::Invalid) {
    ops_.resize(start);
    return false;
  }
  if (!(st.opacity > 0)) {
    hide_content(start);
    return true;
  }
  const size_t end = ops_.size();
  bool draws = false;
  for_each_content(start, end, [&](const Op& op) { draws = draws || op.kind != OpKind::Bounds; });
  if (!draws) return true;
  const bool group = mask.state == MaskRef::Valid || st.blend != BlendMode::Normal || st.isolate;
  if (!group && (st.opacity >= 1 || fold_opacity(start, st.opacity))) return true;

  Group g;
  g.opacity = static_cast<float>(st.opacity);
  g.blend = st.blend;
  Op begin = Op::of(OpKind::GroupBegin);
  begin.scene = static_cast<uint32_t>(groups_.size());
  groups_.push_back(g);
  ops_.push_back(begin);
  if (mask.state == MaskRef::Valid) {
    LazyBounds bbox{*this, start, end, space, std::nullopt};
    if (!mask_ops(*mask.element, space, bbox, depth + 1)) {
      ops_.resize(start);
      return false;
    }
  }
  std::rotate(ops_.begin() + static_cast<ptrdiff_t>(start), ops_.begin() + static_cast<ptrdiff_t>(end), ops_.end());
  ops_.push_back(Op::of(OpKind::GroupEnd));
  return true;
}

// Content with opacity 0 paints nothing; its shapes still count for
// bounding boxes, as bounds-only operations.
void Converter::hide_content(size_t start) {
  std::vector<Op> kept;
  for_each_content(start, ops_.size(), [&](const Op& op) {
    if (op.kind != OpKind::Fill && op.kind != OpKind::Bounds) return;
    kept.push_back(op);
    kept.back().kind = OpKind::Bounds;
  });
  ops_.resize(start);
  ops_.insert(ops_.end(), kept.begin(), kept.end());
}

// Opacity on content that is a single fill (no group, no embedded
// document) multiplies into that fill's paint: the same result without a
// group. Returns false when the content is anything else.
bool Converter::fold_opacity(size_t start, double opacity) {
  Op* fill = nullptr;
  for (size_t i = start; i < ops_.size(); i++) {
    const OpKind k = ops_[i].kind;
    if (k == OpKind::Append || k == OpKind::GroupBegin) return false;
    if (k != OpKind::Fill) continue;
    if (fill) return false;
    fill = &ops_[i];
  }
  if (!fill) return false;
  Paint& p = paints_[fill->paint];
  p.opacity = static_cast<float>(p.opacity * opacity);
  return true;
}

// Appends the mask group of <mask> `mask` applied to an element with user
// space `space` and bounding box `bbox`: its own mask first (mask on a
// mask), then its content clipped to the mask region. Returns false when
// the mask is invalid (objectBoundingBox units on a box without area, an
// empty region), which hides the element.
bool Converter::mask_ops(const Element& mask, const Affine& space, LazyBounds& bbox, int depth) {
  if (!enter(depth)) return false;
  // Properties inherit into a mask from its document ancestors; its own
  // transform does not apply (CSS Masking 1 §7.2).
  const Style st = compute_style(mask, document_context(mask, false));
  const double em = st.inh.font_size;
  auto attr_is = [&](const char* name, const char* value) {
    const std::string* a = mask.attribute(name);
    return a && trim(*a) == value;
  };
  const bool obb = !attr_is("maskUnits", "userSpaceOnUse");
  const bool obb_content = attr_is("maskContentUnits", "objectBoundingBox");
  Affine box;  // the bounding box's unit square to user space
  if (obb || obb_content) {
    const Bounds& b = bbox.get();
    if (b.empty() || !(b.width() > 0) || !(b.height() > 0)) return false;
    box = Affine{b.width(), 0, 0, b.height(), b.x0, b.y0};
  }
  auto len = [&](const char* name, Axis axis, double def) {
    return server_length(mask.attribute(name), Length{def, Unit::Percent}, axis, em, obb);
  };
  double x = len("x", Axis::X, -10), y = len("y", Axis::Y, -10);
  double w = len("width", Axis::X, 120), h = len("height", Axis::Y, 120);
  if (!(w > 0 && h > 0)) return false;
  const Affine region_xf = obb ? space * box : space;

  const auto type = property<std::string>(mask, "mask-type", parse_keyword);
  Group g;
  g.mask = type.state == Prop<std::string>::Set && type.value == "alpha" ? MaskType::Alpha : MaskType::Luminance;
  Op begin = Op::of(OpKind::GroupBegin);
  begin.scene = static_cast<uint32_t>(groups_.size());
  groups_.push_back(g);
  ops_.push_back(begin);

  s_.active_masks.push_back(&mask);
  const MaskRef nested = resolve_mask(st.mask);
  bool ok = nested.state != MaskRef::Invalid;
  if (ok && nested.state == MaskRef::Valid) ok = mask_ops(*nested.element, space, bbox, depth + 1);
  if (ok) {
    // The content, clipped to the mask region.
    ops_.push_back(Op::of(OpKind::Push));
    Op clip = Op::of(OpKind::Clip);
    clip.shape = static_cast<uint32_t>(shapes_.size());
    shapes_.push_back(rect_path(x, y, w, h, 0, 0));
    clip.xf = region_xf;
    ops_.push_back(clip);
    ops_.push_back(Op::of(OpKind::Activate));
    const Context inner = child_context(st, obb_content ? space * box : space, false);
    for (const auto& c : mask.children) render(*c, inner, depth + 1);
    ops_.push_back(Op::of(OpKind::Pop));
    ops_.push_back(Op::of(OpKind::GroupEnd));
  }
  s_.active_masks.pop_back();
  return ok;
}

}  // namespace mpvg::svg::detail
