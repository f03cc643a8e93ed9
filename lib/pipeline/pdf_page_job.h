// A PDF page as a job of the batch pipeline (lib/pipeline/pipeline.h): interpreted
// and lowered for its resolution, sized (with pdftoppm's crop window),
// encoded; print preview's ink passes side by side in one frame
// (lib/output/ink_output.h). pdf2png's pages and libmpvg's PdfDocument renders
// are made here, so that both give the same pixels.
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "lib/pipeline/cli.h"
#include "lib/pipeline/pipeline.h"
#include "parsers/pdf/pdf_parser.h"

namespace mpvg {

struct PdfPageRequest {
  double dpi = 150;   // output pixels per inch
  double dpi_y = 0;   // the vertical resolution where it differs (pdftoppm's -ry; 0: dpi)
  int scale_to = 0;   // > 0: the longer side in pixels instead of dpi
  // pdftoppm's -scale-to-x and -scale-to-y: > 0 the width (height) in
  // pixels; the other axis keeps its resolution, unless it is -1: then it
  // takes this one's (the aspect ratio kept). scale_to wins over both.
  int scale_to_x = 0, scale_to_y = 0;
  // A window of the page's pixels (pdftoppm's -x -y -W -H; 0: the rest).
  int crop_x = 0, crop_y = 0, crop_w = 0, crop_h = 0;
  pdf::PageOptions page;  // box, annotations, thin lines, inks, press profile
};

// Pixels along a page side of `points` points at `scale` pixels a point,
// as pdf2png sizes pages (at least 1; a side a hair over a whole pixel
// stays that pixel).
inline int page_pixels(double points, double scale) {
  return std::max(1, static_cast<int>(std::ceil(points * scale - 1e-6)));
}

// Pixels a point across (sx) and down (sy) for a page of w x h points, as
// pdftoppm resolves -r/-rx/-ry, -scale-to and -scale-to-x/-y.
inline void page_scale(const PdfPageRequest& r, double w, double h, double* sx, double* sy) {
  *sx = r.dpi / 72.0;
  *sy = (r.dpi_y > 0 ? r.dpi_y : r.dpi) / 72.0;
  if (r.scale_to > 0) {
    *sx = *sy = r.scale_to / std::max(w, h);
    return;
  }
  if (r.scale_to_x > 0) {
    *sx = r.scale_to_x / w;
    if (r.scale_to_y == -1) *sy = *sx;
  }
  if (r.scale_to_y > 0) {
    *sy = r.scale_to_y / h;
    if (r.scale_to_x == -1) *sx = *sy;
  }
}

// Page n (1-based) of `doc` as a job for `out`, rendered with opt's
// rendering options. Throws mpvg::Error (the page's failure, or a frame
// too large for opt's limits).
std::unique_ptr<pipeline::Job> pdf_page_job(const PdfPageRequest& request, const cli::Options& opt,
                                            const pdf::Document& doc, int n, const std::string& out);

}  // namespace mpvg
