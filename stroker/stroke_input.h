// Stage "stroke", host side: stroked paths (a Path, a style, the transform
// to pixels) gathered into the flat arrays of stroker/stroke.h that either
// executor expands: records, subpaths, segments and dash patterns. Only
// the centreline crosses to the device; the stroke is built there. Also
// the hairline rule that frontends apply to the widths they stroke with.
#pragma once
#include <cstdint>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/memory_budget.h"
#include "core/scene.h"
#include "stroker/stroke.h"

namespace mpvg {

// The flat input, in host memory.
struct StrokeBatch {
  std::vector<stroking::StrokeRecord> strokes;
  std::vector<stroking::StrokeSubpath> subpaths;
  std::vector<stroking::StrokeSegment> segments;
  std::vector<double> dashes;
  // Beside each dash element, its pattern's sum up to and with it, added
  // in order (StrokeInput::dash_ends: the binary searches of DashPattern).
  std::vector<double> dash_ends;
  std::vector<uint32_t> first_element;  // per subpath (StrokeInput::first_element)
  uint32_t nvertices = 0, nelements = 0;

  // Adds the stroke of `path` (user space) with output path id `path_id`.
  // `to_pixels` maps user space to pixels, where the output lies within
  // `tolerance_px` of the exact outline. Degenerate input adds nothing and
  // never throws: a non-positive or non-finite width, a non-invertible or
  // non-finite transform; a contour with a non-finite coordinate or weight
  // (or a rational cubic) is left out; zero-length segments are left out
  // of their subpaths. Returns whether anything was added.
  bool add(const Path& path, const StrokeStyle& style, const Affine& to_pixels, uint32_t path_id,
           double tolerance_px = 1.0 / 16);

  bool empty() const { return strokes.empty(); }
};

// The CPU executor of the stage: measuring, the scan of lengths, then every
// item's segments (threads <= 0: every core). Output segments come grouped
// by path, in increasing path id.
struct StrokeTimes {
  double measure_ms = 0, elements_ms = 0, parts_ms = 0, fit_ms = 0;
};
// What it makes is charged to `budget` (if any) as it is made, and given
// back when it returns: the caller charges the output it keeps.
std::vector<InputSegment> stroke_cpu(const StrokeBatch& batch, int threads = 0, StrokeTimes* times = nullptr,
                                     MemoryBudget* budget = nullptr);

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

}  // namespace mpvg
