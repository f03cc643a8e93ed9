// The lowering device (pdf_device.cpp): one page's drawing operations, as
// MuPDF interprets them, into a SceneBuilder. Internal to the PDF frontend.
#pragma once
#include <mupdf/fitz.h>

#include <string>
#include <vector>

#include "core/scene.h"

namespace mpvg::pdf::detail {

// What lowering a page gave besides the scene: warnings, one line each,
// deduplicated; the wall time of running the page, and of it the time
// spent in the device's callbacks (lowering), in ms.
struct Lowered {
  std::vector<std::string> warnings;
  double run_ms = 0, lower_ms = 0;
};

// Runs `page` with `ctm` (page space to scene units) through the lowering
// device into `b`, a page of width x height scene units; `device` maps
// scene units to output pixels (stroke tolerance, thinnest lines). The
// page's content shows optional content as viewed; annotations and form
// fields show as printed. Throws mpvg::Error when MuPDF or the lowering
// fails.
Lowered lower_page(fz_context* ctx, fz_page* page, const fz_matrix& ctm, const Affine& device, double width,
                   double height, SceneBuilder& b);

}  // namespace mpvg::pdf::detail
