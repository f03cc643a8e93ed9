// Strokes: each painted stroke becomes a stroke operation, its centreline
// and style, which the scene carries (SceneBuilder::stroke) and the stroke
// stage builds when the scene is rendered.
#include "stroker/stroke_input.h"
#include "parsers/svg/svg_converter.h"
#include "frame/scene_builder.h"

namespace mpvg::svg::detail {

// The stroke of shapes_[shape] as a stroke operation with the stroke paint,
// or nothing when it paints nothing (SVG 2 painting.html#StrokeProperties:
// stroke none, zero width, invisible or fully transparent). `bbox` is the
// shape's, for paint servers. The outline itself is built when the scene is
// rendered (stroker/stroke.h), in user space, to 1/16 of an output pixel.
std::optional<Op> Converter::shape_stroke(uint32_t shape, const Style& st, const Affine& space, ShapeBox& bbox,
                                          const Element* element) {
  const Inherited& inh = st.inh;
  if (inh.stroke.kind == PaintSpec::Kind::None || !inh.visible || !(inh.stroke_width > 0)) return std::nullopt;
  StrokeStyle style;
  style.join = inh.stroke_join;
  style.cap = inh.stroke_cap;
  style.miter_limit = inh.stroke_miterlimit;
  style.dashes = inh.stroke_dasharray;
  style.dash_offset = inh.stroke_dashoffset;
  // pathLength (SVG 2 painting.html#StrokeDashing): the dash array and
  // offset are lengths in the author's units along the path, scaled by
  // its computed length over pathLength. pathLength="0" (an infinite
  // scale in SVG 2) leaves the stroke solid, as Chromium draws it, and so
  // does a path of length zero.
  if (const std::string* pl = element ? element->attribute("pathLength") : nullptr; pl && !style.dashes.empty())
    if (const auto author = parse_path_length(*pl)) {
      const double k = *author > 0 ? path_length(shapes_[shape]) / *author : 0;
      if (k > 0) {
        for (double& d : style.dashes) d *= k;
        style.dash_offset *= k;
      } else {
        style.dashes.clear();
        style.dash_offset = 0;
      }
    }
  Op op = Op::of(OpKind::Fill);
  op.stroke = true;
  op.rule = FillRule::NonZero;
  op.aliased = inh.aliased_shapes;
  op.shape = shape;
  // Hairlines need to know what a pixel is: the scene as the parse options
  // expect it to be rendered.
  Hairline hl;
  if (st.non_scaling_stroke) {
    // vector-effect: non-scaling-stroke: the stroke is computed in the
    // host coordinate space, here scene units (SVG 2 coords.html#VectorEffects):
    // the centreline mapped there.
    hl = hairline(inh.stroke_width, device_);
    op.shape = static_cast<uint32_t>(shapes_.size());
    add_shape(shapes_[shape].transformed(space));
    op.xf = Affine{};
  } else {
    hl = hairline(inh.stroke_width, device_ * space);
    op.xf = space;
  }
  const auto paint = make_paint(inh.stroke, inh.stroke_opacity * hl.opacity, bbox, space);
  if (!paint) return std::nullopt;
  op.paint = *paint;
  style.width = hl.width;
  op.stroke_style = static_cast<uint32_t>(stroke_styles_.size());
  stroke_styles_.push_back(std::move(style));
  s_.stroked_paths++;
  return op;
}

}  // namespace mpvg::svg::detail
