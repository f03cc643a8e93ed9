// The lowering device (pdf_device.cpp): one page's drawing operations, as
// MuPDF interprets them, into a SceneBuilder. Internal to the PDF frontend.
#pragma once
#include <mupdf/fitz.h>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/inks/inks.h"
#include "core/scene.h"
#include "parsers/pdf/output_intent.h"
#include "parsers/pdf/pdf_options.h"
#include "frame/scene_builder.h"

namespace mpvg::pdf::detail {

// What lowering a page gave besides the scene: warnings, one line each,
// deduplicated; the wall time of running the page, and of it the time
// spent in the device's callbacks (lowering), in ms.
struct Lowered {
  std::vector<std::string> warnings;
  double run_ms = 0, lower_ms = 0;
};

// Glyph outlines in glyph space (before the text matrix), per font and glyph
// id, so that a worker outlines each glyph of a document once: a glyph's
// outline is linear in the matrix MuPDF applies (width adjustment, fake
// italic and bold come before it), so the matrix is applied afterwards, in
// double precision. Keeps a reference to each font it has seen, dropped
// with the cache (before its context).
class GlyphCache {
 public:
  explicit GlyphCache(fz_context* ctx) : ctx_(ctx) {}
  ~GlyphCache();
  GlyphCache(const GlyphCache&) = delete;
  GlyphCache& operator=(const GlyphCache&) = delete;
  // The outline, or null where the glyph has none (Type 3 procedures,
  // missing glyphs) or MuPDF failed.
  const Path* outline(fz_font* font, int gid);

 private:
  fz_context* ctx_;
  std::map<std::pair<fz_font*, int>, std::optional<Path>> glyphs_;
  std::vector<fz_font*> fonts_;  // kept
};

// Print preview: a page drawn in inks (core/inks/inks.h), one pass at a time:
// the spot inks after C, M, Y, K (empty for InkModel::Cmyk), and the pass.
struct InkTarget {
  std::vector<std::string> spots;
  InkPass pass;
  // The press's CMYK profile RGB-based colours and images are converted
  // through (output_intent.h); null: MuPDF's device formulas.
  const OutputProfile* profile = nullptr;
};

// Runs `page` with `ctm` (page space to scene units) through the lowering
// device into `b`, a page of width x height scene units; `device` maps
// scene units to output pixels (stroke tolerance, thinnest lines). The
// page's content shows optional content as viewed; annotations and form
// fields show as printed (none without options.annotations); thin lines as
// options.thin_lines says (its box is the caller's business). Glyph
// outlines come from `glyphs` (of ctx); colours are RGB, or with `inks`
// the ink amounts of its pass. Throws mpvg::Error when MuPDF or the
// lowering fails.
Lowered lower_page(fz_context* ctx, fz_page* page, const fz_matrix& ctm, const Affine& device, double width,
                   double height, SceneBuilder& b, GlyphCache& glyphs, const PageOptions& options = {},
                   const InkTarget* inks = nullptr);

}  // namespace mpvg::pdf::detail
