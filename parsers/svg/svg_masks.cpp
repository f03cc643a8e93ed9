// Group opacity, mix-blend-mode, isolation and masks (SVG 2 render.html
// #ObjectAndGroupOpacityProperties, Compositing and Blending 1 §3, CSS
// Masking 1 §7) as the core's transparency groups (core/paint/group.h).
//
// An element's converted content ops_[start, end) becomes, when it needs
// one, a group: GroupBegin, its mask (a group of mask type, first), the
// content, GroupEnd. Every such group is isolated, as an element with
// opacity, a mask, a blend mode or isolation: isolate is a stacking context
// in CSS; plain containers are not groups at all. Opacity on content that
// is one fill folds into its paint instead, which is exact.
#include <algorithm>

#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_style.h"

namespace mpvg::svg::detail {

// Resolves the mask value of element `e`. As with clip-path (resvg, and
// the suite's masking/mask tests): a reference to a missing element is
// ignored, one to an element that is not a mask hides the element, and a
// recursive reference is ignored with a warning: those that
// cut_recursive_masks() finds, and any other reference back into a mask
// being converted.
MaskRef Converter::resolve_mask(const Element& e, const std::string& value) {
  if (!s_.masks_checked) cut_recursive_masks();
  if (s_.cut_masks.count(&e) != 0) {
    warn("recursive mask reference ignored");
    return MaskRef{};
  }
  return resolve_reference(value, "mask", "mask", s_.active_masks);
}

namespace {

// Calls f on `e` and its descendants, in document order.
template <class F>
void for_each_element(const Element& e, F f) {
  f(e);
  for (const auto& c : e.children) for_each_element(*c, f);
}

}  // namespace

// The element that `e`'s own mask property names in this document, unless
// that reference has been cut.
const Element* Converter::mask_link(const Element& e) const {
  if (s_.cut_masks.count(&e) != 0) return nullptr;
  const auto v = property<std::string>(e, "mask", [](std::string_view t) { return std::optional<std::string>(trim(t)); });
  if (v.state != Prop<std::string>::Set) return nullptr;
  Scanner s(v.value);
  bool external = false;
  const auto id = parse_func_iri(s, &external);
  return id && !external ? find(*id) : nullptr;
}

// Which mask references of the document are recursive, decided once on
// the document tree as resvg does, so that a chain of masks means the same
// wherever it is entered (masking/mask/recursive-on-child): for each mask
// M in document order, a reference to M from M or its descendants is cut;
// so is, when M or a descendant references an element L, every reference
// to M from L or L's descendants. Cuts take effect at once (a cut
// reference leads nowhere for the masks after it). Longer cycles are
// caught while converting, through Session::active_masks.
void Converter::cut_recursive_masks() {
  s_.masks_checked = true;
  for_each_element(*s_.doc.root, [&](const Element& m) {
    if (m.name != "mask") return;
    std::unordered_set<const Element*> scanned;  // L whose references to m are cut already
    for_each_element(m, [&](const Element& d) {
      const Element* l = mask_link(d);
      if (l == &m) s_.cut_masks.insert(&d);
      if (!l || l == &m || !scanned.insert(l).second) return;
      for_each_element(*l, [&](const Element& d2) {
        if (mask_link(d2) == &m) s_.cut_masks.insert(&d2);
      });
    });
  });
}

// Wraps the content ops_[start, end) of element `e` in the group that its
// opacity, mask, mix-blend-mode and isolation make. Returns false when the
// element is not rendered at all (an invalid mask reference).
bool Converter::group_content(const Element& e, size_t start, const Style& st, const Affine& space, int depth) {
  const MaskRef mask = resolve_mask(e, st.mask);
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
// bounding boxes, as bounds-only operations (a filter's region is no shape).
void Converter::hide_content(size_t start) {
  std::vector<Op> kept;
  for_each_content(start, ops_.size(), [&](const Op& op) {
    if ((op.kind != OpKind::Fill && op.kind != OpKind::Bounds) || op.filter) return;
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

  // mask-type is not inherited: inherit takes the parent's value.
  auto type = property<std::string>(mask, "mask-type", parse_keyword);
  for (const Element* at = mask.parent; type.state == Prop<std::string>::Inherit && at; at = at->parent)
    type = property<std::string>(*at, "mask-type", parse_keyword);
  Group g;
  g.mask = type.state == Prop<std::string>::Set && type.value == "alpha" ? MaskType::Alpha : MaskType::Luminance;
  Op begin = Op::of(OpKind::GroupBegin);
  begin.scene = static_cast<uint32_t>(groups_.size());
  groups_.push_back(g);
  ops_.push_back(begin);

  s_.active_masks.push_back(&mask);
  const MaskRef nested = resolve_mask(mask, st.mask);
  bool ok = nested.state != MaskRef::Invalid;
  if (ok && nested.state == MaskRef::Valid) ok = mask_ops(*nested.element, space, bbox, depth + 1);
  if (ok) {
    // The content, clipped to the mask region.
    ops_.push_back(Op::of(OpKind::Push));
    Op clip = Op::of(OpKind::Clip);
    clip.shape = static_cast<uint32_t>(shapes_.size());
    add_shape(rect_path(x, y, w, h, 0, 0));
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
