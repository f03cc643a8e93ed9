// Stroke adjustment (PDF 32000-1 §10.7.5, PostScript's setstrokeadjust)
// and the thin-line mode of screen viewers: geometry moved onto the output
// pixel grid, so that a rule narrower than a pixel is drawn as one whole
// pixel row or column instead of a faint partial one, and rules of one
// nominal width come out equally wide wherever they fall.
//
// What is adjusted, in the device (output pixel) space `to_device` maps
// the path's user space to, and only where that map is axis-aligned with
// equal scales (a page's, rotated by a multiple of 90 degrees or not):
// - a stroke: its width becomes n = max(1, round(width in pixels)) pixels,
//   and every contour made only of horizontal and vertical lines has its
//   lines centred so that their edges fall on pixel boundaries (the
//   centre on a pixel centre for odd n, on a boundary for even n). Other
//   contours keep their points; the width still applies to them.
// - a fill: every contour made only of horizontal and vertical lines has
//   its coordinates rounded to pixel boundaries; a contour that spans two
//   distinct x (or y) values and would collapse to zero width keeps one
//   pixel, the one nearest its middle. Abutting edges stay abutting.
// Curves, diagonal lines and maps that rotate or shear are left as they
// are (a stroke's width is still widened to one pixel).
//
// Poppler (pdftoppm) and Acrobat draw pages this way; MuPDF draws exact
// coverage. The PDF frontend applies it to page content (not to glyphs,
// clips or pattern cells) when asked (pdf2png --thin-lines snap).
#pragma once
#include "core/geometry/geometry.h"
#include "core/scene.h"

namespace mpvg {

// Is to_device axis-aligned with equal scales, up to a relative error of
// 1e-9 (a page placed at a resolution, rotated by k x 90 degrees)?
bool grid_aligned(const Affine& to_device);

// The stroke of `centreline` with `width` (user units), adjusted: returns
// the adjusted centreline and sets *width. Unchanged where to_device is not
// grid-aligned, except that a width under one pixel becomes one pixel
// (with the uniform part of the map's scale).
Path adjust_stroke(const Path& centreline, double* width, const Affine& to_device);

// A filled path, adjusted (its rectilinear contours on pixel boundaries).
Path adjust_fill(const Path& geometry, const Affine& to_device);

}  // namespace mpvg
