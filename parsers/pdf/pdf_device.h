// The lowering device (pdf_device.cpp): one page's drawing operations, as
// MuPDF interprets them, into a SceneBuilder. Internal to the PDF frontend.
#pragma once
#include <mupdf/fitz.h>

#include <string>
#include <vector>

#include "core/scene.h"

namespace mpvg::pdf::detail {

// Runs `page` with `ctm` (page space to scene units) through the lowering
// device into `b`, a page of width x height scene units; `device` maps
// scene units to output pixels (stroke tolerance, thinnest lines). Returns the warnings; throws mpvg::Error when
// MuPDF or the lowering fails.
std::vector<std::string> lower_page(fz_context* ctx, fz_page* page, const fz_matrix& ctm, const Affine& device,
                                    double width, double height, SceneBuilder& b);

}  // namespace mpvg::pdf::detail
