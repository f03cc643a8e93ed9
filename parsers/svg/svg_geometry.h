// SVG geometry to scene paths: path data, elliptical arcs as rational
// quadratics, the basic shapes, tight bounding boxes and path lengths.
//
// Internal to the SVG frontend. Curves stay curves: quadratic and cubic
// commands become Quad and Cubic segments, arcs become RQuad conics.
#pragma once
#include <array>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/scene.h"

namespace mpvg::svg::detail {

// Builds a Path from SVG-style commands. A moveto is only materialised when a
// drawing command or a closepath follows it, so lone movetos ("M 1 1 M 2 2
// ...") leave no empty contours behind; "M 1 1 Z" is a closed contour
// without segments (a zero-length subpath, stroked as a dot).
class PathBuilder {
 public:
  void move_to(Vec2 p);
  void line_to(Vec2 p);
  void quad_to(Vec2 p1, Vec2 p2);
  void rquad_to(Vec2 p1, Vec2 p2, double w);
  void cubic_to(Vec2 p1, Vec2 p2, Vec2 p3);
  // Elliptical arc from the current point (SVG 1.1 F.6.5 endpoint to center
  // conversion, F.6.6 out-of-range radii), emitted as conics of at most 90°.
  void arc_to(double rx, double ry, double x_axis_rotation_deg, bool large_arc, bool sweep, Vec2 p);
  void close();

  Vec2 current_point() const { return current_; }
  Path take() { return std::move(path_); }
  // The segments (indices into the path's) that continue an arc command:
  // every conic piece of an arc after its first.
  const std::vector<uint32_t>& arc_continuations() const { return arc_continuations_; }

 private:
  void begin_segment();

  Path path_;
  Vec2 current_;
  Vec2 start_;
  bool pending_move_ = false;
  bool after_move_ = false;  // the last command was a moveto
  std::vector<uint32_t> arc_continuations_;
};

// Path data (SVG 2 paths.html#PathDataBNF). On a syntax error the path holds
// every segment before the erroneous one (SVG 2 paths.html
// #PathDataErrorHandling) and the function returns false.
// `arc_continuations`, when given, receives PathBuilder::arc_continuations
// (markers are placed per command, not per conic piece).
bool parse_path_data(std::string_view d, Path& out, std::vector<uint32_t>* arc_continuations = nullptr);

// A points attribute (polyline, polygon): coordinate pairs; an odd trailing
// coordinate is dropped and parsing stops at the first error (SVG 1.1 §9.7.1).
std::vector<Vec2> parse_points(std::string_view s);

// The basic shapes as paths (SVG 2 shapes.html: each shape's "equivalent path"). Callers
// have validated the sizes (w, h, rx, ry > 0 where required).
Path rect_path(double x, double y, double w, double h, double rx, double ry);
Path ellipse_path(double cx, double cy, double rx, double ry);
Path line_path(Vec2 p0, Vec2 p1);
Path poly_path(const std::vector<Vec2>& points, bool close);

// An axis-aligned box; empty until something is added.
struct Bounds {
  double x0 = std::numeric_limits<double>::infinity(), y0 = std::numeric_limits<double>::infinity();
  double x1 = -std::numeric_limits<double>::infinity(), y1 = -std::numeric_limits<double>::infinity();

  bool empty() const { return !(x0 <= x1 && y0 <= y1); }
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  void add(Vec2 p);
  void add(const Bounds& b);
};

// Adds the tight bounds of `path` mapped by `m` to `b`: the curves' extrema
// are solved for, not approximated by their control polygons.
void add_path_bounds(const Path& path, const Affine& m, Bounds& b);

// A curve segment (quadratic, conic or cubic; not a line) as the cubic
// resvg's kurbo makes of it: a quadratic raised exactly; a conic, a piece
// of an elliptical arc of angle 2 acos(w), with arms 4/3 tan(angle / 4) of
// its end tangents (tan(angle / 2) of which reach the control point); a
// rational cubic's weights ignored (its end directions do not depend on
// them). Used where text paths and markers measure and orient along a
// path as resvg does.
std::array<Vec2, 4> segment_cubic(const Path& path, const Path::Segment& sg);

// The length of `path` as the stroke stage measures it to place dashes
// (stroker/stroke_curve.h's ArcTable, lines exactly): the sum of its segments'
// arc lengths, each closepath's line included. The "computed length" that
// pathLength is compared with, so that dashes scaled by it end where the
// author meant them to.
double path_length(const Path& path);

// A pathLength attribute (SVG 2 paths.html#PathLengthAttribute): a
// non-negative number; nullopt when it is negative or not a number, which
// leaves the attribute without effect.
std::optional<double> parse_path_length(std::string_view s);

}  // namespace mpvg::svg::detail
