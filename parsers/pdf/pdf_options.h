// What a PDF page is rendered with (PageOptions: the page box, thin lines,
// the ink model) and what lowering it gives (PageResult): shared by the
// frontend's entry points (pdf_parser.h) and its lowering device
// (pdf_device.h).
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/scene.h"

namespace mpvg::pdf {

class OutputProfile;  // output_intent.h

// The page box a page is rendered over (PDF 32000-1 §14.11.2): CropBox
// defaults to the MediaBox, BleedBox, TrimBox and ArtBox to the CropBox;
// each is intersected with the MediaBox (a box that leaves less than 1 pt
// falls back to the CropBox); MediaBox and CropBox are inherited from the
// page tree, the others are the page's own (Table 30). Crop is what MuPDF
// and pdftoppm -cropbox render.
enum class PageBox { Media, Crop, Bleed, Trim, Art };

// How a page is lowered: over which box, whether its annotations and form
// fields are drawn (as printed; pdftoppm's -hide-annotations leaves them
// out), and how thin lines are drawn.
// How strokes and rules narrower than a pixel are drawn: at their exact
// coverage (as MuPDF draws them), or snapped to the pixel grid and at least
// a pixel wide (stroke adjustment, as Poppler and Acrobat draw them;
// stroker/stroke_adjust.h).
enum class ThinLines { Exact, Snap };

// The colour model a page is drawn in: RGB, or inks for print preview
// (core/inks/inks.h): CMYK (spot colours converted to their CMYK alternates, as
// a CMYK proof shows them) or Separations (CMYK and the page's spot
// colours as inks of their own). Overprint (OP, op, OPM) and blend modes
// then composite per ink (PDF 32000-1 §11.7.4, §11.3.5).
enum class InkModel { Rgb, Cmyk, Separations };

struct PageOptions {
  PageBox box = PageBox::Crop;
  bool annotations = true;
  ThinLines thin_lines = ThinLines::Exact;
  InkModel inks = InkModel::Rgb;
  // Print preview's press profile (output_intent.h) where the document has
  // no output intent, or over it; null: the output intent's, or none.
  std::shared_ptr<const OutputProfile> cmyk_profile;
  // The render's memory budget (core/memory_budget.h): the page's scene is
  // charged to it as it is lowered; null: not counted.
  std::shared_ptr<MemoryBudget> budget;
  PageOptions() = default;
  PageOptions(PageBox b) : box(b) {}  // NOLINT: a box alone is the common case
};

// A page lowered to a scene: units are PDF points, (0, 0) the top-left
// corner of the page's box (PageBox) after /Rotate and /UserUnit.
struct PageResult {
  Scene scene;
  std::vector<std::string> warnings;  // one line each, deduplicated
  double pixels_per_point = 1;        // the output resolution it was lowered for
  // With PageOptions::inks: scene is empty, and the page is ink_passes
  // (core/inks/inks.h: pass p draws inks 3p .. 3p + 2 in r, g, b, over no ink),
  // inks named by ink_names ("Cyan", "Magenta", "Yellow", "Black", then
  // the spots'), each spot's CMYK equivalent in spot_cmyk (four a spot).
  std::vector<Scene> ink_passes;
  std::vector<std::string> ink_names;
  std::vector<float> spot_cmyk;
  // Wall time of MuPDF interpreting the page (parsing, fonts, images) and
  // of lowering what it draws into the scene (glyph outlines, strokes, the
  // builder's finish), in ms.
  double interpret_ms = 0, lower_ms = 0;
};

}  // namespace mpvg::pdf
