// Stroke-to-fill conversion (paper §1: strokes become filled primitives on
// the CPU). Frontends describe a stroke with a Style and get back fill
// geometry to be filled with the nonzero rule.
//
// The stroke of a path is, by SVG 2 (painting.html#StrokeShape), the union
// of (a) for every segment, the normal segments of length stroke-width
// centred on it, (b) a join shape at every vertex inside a subpath (and at
// the start of a closed one), and (c) a cap shape at both ends of every open
// subpath or dash. stroke_to_fill() builds exactly these pieces, each
// oriented so that its winding number is positive everywhere inside it;
// the nonzero fill of the pieces is then their union, however they overlap
// (Nehab 2020, "Converting stroked primitives to filled primitives", builds
// strokes the same way). Pieces that share an edge are emitted as one
// contour whose winding is their sum, to save segments. The traps of the
// direct approach, outlines of inner offsets that fold back where the
// radius of curvature is below half the width, cusps and 180° turns, never
// make a negative region here: see stroker.cpp for how the pieces are built.
//
// Output curves: offsets are approximated by quadratics to the tolerance
// (never flattened to polylines), lines stay lines, circular arcs (round
// joins and caps, arcs joins) are exact rational quadratics.
#pragma once
#include <optional>
#include <vector>

#include "core/geometry.h"
#include "core/scene.h"

namespace mpvg::stroke {

enum class Join { Miter, MiterClip, Arcs, Round, Bevel };
enum class Cap { Butt, Round, Square };

struct Style {
  double width = 1;
  Join join = Join::Miter;
  double miter_limit = 4;  // ratio of miter length to width; values below 1 act as 1
  Cap cap = Cap::Butt;
  // Dash and gap lengths in user units, repeated along each subpath. An odd
  // list is repeated once to make it even; an empty list, one that sums to
  // zero, or one with a negative or non-finite value means no dashing
  // (see dash_pattern()).
  std::vector<double> dashes;
  double dash_offset = 0;
};

// Fill geometry (to be filled with the nonzero rule) covering the stroke of
// `path`, in the user space of `path`. `to_device` maps user space to device
// pixels; the output stays within `tolerance_px` of the exact stroke outline
// measured in device pixels. The stroke is computed in user space, so
// non-uniform scales and skews distort it as SVG requires.
//
// Degenerate input never throws: a non-positive or non-finite width or a
// non-invertible or non-finite transform give an empty path; a contour with
// a non-finite coordinate or weight (or a rational cubic, which no frontend
// produces) is left out. Zero-length subpaths ("M p Z", "M p L p") get a
// round dot or an axis-aligned square for round and square caps, nothing
// for butt caps (SVG 2 painting.html#LineCaps); zero-length segments inside
// a subpath are ignored. Dash lengths and offsets are in user units, along
// the arc length. A cusp inside a curve gets a disk of the stroke width:
// at an almost-cusp the normal turns half a turn and sweeps that disk, so
// the stroke stays continuous as the cusp becomes exact (Nehab 2020 argues
// for such continuity).
Path stroke_to_fill(const Path& path, const Style& style, const Affine& to_device, double tolerance_px = 1.0 / 16);

// The dash pattern that `dashes` describes (SVG 2 painting.html#StrokeDashing):
// nullopt when a value is negative or not finite (the value is invalid);
// an empty pattern (no dashing) when the list is empty or sums to zero;
// otherwise the list, repeated once if its length is odd.
std::optional<std::vector<double>> dash_pattern(const std::vector<double>& dashes);

// An interval of arc length along a subpath.
struct Interval {
  double begin, end;
};

// The "dash positions" of SVG 2 painting.html#TermDashPositions for a
// subpath of length `length`, a valid non-empty pattern and an offset
// (negative offsets count from the end of the pattern). Dashes may have
// zero length; they then only carry caps.
std::vector<Interval> dash_positions(double length, const std::vector<double>& pattern, double offset);

// The arc length of every contour of `path` (user units).
std::vector<double> contour_lengths(const Path& path);

// The centrelines of the dashes of `path`: one open contour per dash of
// positive length, in order. A dash that runs through the start point of a
// closed contour continues across it (as resvg and Skia do), so it is one
// contour there. Zero-length dashes are left out (they are only caps).
Path dash_path(const Path& path, const Style& style);

// Hairlines. A stroke whose device width is below `min_device_width` pixels
// would be thinner than a pixel and, with point sampling, flicker in and out
// of existence. It is drawn instead at the minimum width with its opacity
// multiplied by width / minimum width: the same amount of ink per unit
// length, but smoothly antialiased. The device width of a user-space width
// is measured with sqrt(|det|), the geometric mean of the transform's
// scales. A width of zero is the thinnest line that can be drawn (PDF's
// line width 0): the minimum width at full opacity.
struct Hairline {
  double width;    // user units
  double opacity;  // factor for the stroke's opacity
};
Hairline hairline(double width, const Affine& to_device, double min_device_width = 1.0);

// `path` with every point mapped by `m`: conics keep their weights, which
// affine maps preserve. Used to stroke in device space
// (vector-effect: non-scaling-stroke).
Path transformed(const Path& path, const Affine& m);

}  // namespace mpvg::stroke
