// clip-path's basic shapes (CSS Masking 1 §3.1) in the conversion: the
// shape resolved against its reference box (svg_basic_shapes.h) becomes the
// clip item around an element's content.
#include "parsers/svg/svg_basic_shapes.h"
#include "parsers/svg/svg_converter.h"

namespace mpvg::svg::detail {

// The clip item of basic shape `cs` in user space `space` for content of
// bounding box `bbox`, its lengths' em against `em`: a shape without area,
// or no box, gives none (nothing shows through).
bool Converter::clip_shape_items(const ClipShape& cs, const Affine& space, LazyBounds& bbox, double em) {
  Bounds box;
  switch (cs.box) {
    case ReferenceBox::Fill: box = bbox.get(); break;
    case ReferenceBox::Stroke: box = content_bounds(bbox.begin, bbox.end, space, true); break;
    case ReferenceBox::View:
      // The nearest viewport's size at the origin of its user space
      // (CSS Masking 1 §3.1 view-box; Chromium does the same).
      box.add(Vec2{0, 0});
      box.add(Vec2{s_.percent_w, s_.percent_h});
      break;
  }
  if (box.empty()) return true;
  Path p = clip_shape_path(cs, box, em, s_.root_em);
  if (p.empty()) return true;
  Op op = Op::of(OpKind::Clip);
  op.shape = static_cast<uint32_t>(shapes_.size());
  add_shape(std::move(p));
  op.xf = space;
  op.rule = cs.shape.rule;
  ops_.push_back(op);
  return true;
}

// Wraps the content in ops_[start, end) into a clip group of basic shape
// `cs` in user space `space`, its lengths' em against `em`.
void Converter::clip_shape_content(size_t start, const ClipShape& cs, const Affine& space, double em) {
  clip_content(start, space, [&](LazyBounds& bbox) { return clip_shape_items(cs, space, bbox, em); });
}

}  // namespace mpvg::svg::detail
