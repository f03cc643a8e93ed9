// clip-path's CSS values (CSS Masking 1 §3.1: <basic-shape> ||
// <geometry-box>): the basic shapes of CSS Shapes 1 §3.1 parsed into
// lengths as written, and resolved against a reference box into a path in
// the clipped element's user space.
//
// Internal to the SVG frontend.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/scene.h"
#include "parsers/svg/svg_geometry.h"
#include "parsers/svg/svg_values.h"

namespace mpvg::svg::detail {

// The reference boxes of SVG elements (CSS Masking 1 §3.1 <geometry-box>):
// they have no CSS layout box, so content-box and padding-box act as
// fill-box, border-box and margin-box as stroke-box.
enum class ReferenceBox : uint8_t { Fill, Stroke, View };

// A <shape-radius> (CSS Shapes 1 §3.1): a length or one of two keywords.
struct ShapeRadius {
  enum class Kind : uint8_t { Length, ClosestSide, FarthestSide } kind = Kind::ClosestSide;
  Length length;
};

// One coordinate of a <position>: an offset from the box's start edge
// (left, top) or, when from_end, from its end edge (right, bottom).
struct PositionOffset {
  Length offset{50, Unit::Percent};
  bool from_end = false;
};

struct BasicShape {
  enum class Kind : uint8_t { None, Circle, Ellipse, Inset, Polygon, Path } kind = Kind::None;
  FillRule rule = FillRule::NonZero;      // Polygon, Path
  std::array<ShapeRadius, 2> radii;       // Circle: [0]; Ellipse: rx, ry
  std::array<PositionOffset, 2> center;   // Circle, Ellipse: x, y
  std::array<Length, 4> inset;            // Inset: top, right, bottom, left
  // Inset: the round radii, horizontal then vertical, each top-left,
  // top-right, bottom-right, bottom-left (CSS Backgrounds 3 border-radius).
  std::array<Length, 8> corners;
  std::vector<std::pair<Length, Length>> points;  // Polygon
  std::string path_data;                          // Path
};

// A clip-path value made of a basic shape, a reference box or both. With
// neither shape nor box given the box defaults to border-box (stroke-box).
struct ClipShape {
  BasicShape shape;
  ReferenceBox box = ReferenceBox::Stroke;
};

// A value that is one path() function, path( <'fill-rule'>? , <string> )
// (CSS Shapes 1 §3.1; the d property's path(<string>), SVG 2
// paths.html#TheDProperty, is the same without the fill rule): its fill
// rule if given and its path data, which parses whole. nullopt for any
// other value, and for a path() whose data has an error.
struct CssPath {
  std::optional<FillRule> rule;
  std::string data;
};
std::optional<CssPath> parse_css_path(std::string_view value);

// Parses a clip-path value. nullopt when it is not a basic shape or a
// geometry box (none, url(), anything else); then *invalid is set when it
// starts like one (a shape function or a box keyword) but does not parse,
// which makes the declaration invalid.
std::optional<ClipShape> parse_clip_shape(std::string_view value, bool* invalid);

// The shape in the user space of the reference box `box` (non-empty), its
// lengths' em and rem against `em` and `rem`. A shape of no area is an
// empty path (it clips everything away).
Path clip_shape_path(const ClipShape& cs, const Bounds& box, double em, double rem);

// Adds to `b` the box of the stroke of `centreline` with `style` (its
// dashes ignored), the centreline mapped to output pixels by `to_pixels`
// and the stroke's box back to the wanted space by `from_pixels`.
void add_stroke_bounds(const Path& centreline, StrokeStyle style, const Affine& to_pixels, const Affine& from_pixels,
                       Bounds& b);

}  // namespace mpvg::svg::detail
