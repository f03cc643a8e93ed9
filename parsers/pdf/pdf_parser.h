// The PDF frontend: MuPDF parses and interprets pages; a custom fz_device
// (pdf_device.cpp) lowers every drawing operation into the core scene,
// which the pipeline renders like any SVG. Nothing downstream knows PDF.
//
// Lowered: paths (fills, strokes, clips), text as glyph outlines (every
// render mode), shadings (axial and radial as gradients, mesh and
// function-based ones as mesh paints), images and image masks, tiling
// patterns, transparency groups and soft masks. What cannot be lowered is
// reported as a warning.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <string>
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

// An open document ("-": read from stdin). Errors (unreadable, broken,
// encrypted without the password) throw mpvg::Error with one line.
class Document {
 public:
  // Files (and standard input) larger than max_input bytes are refused.
  explicit Document(const std::string& path, const std::string& password = "", size_t max_input = SIZE_MAX);
  // The document's bytes (shared with the clones, not copied); `name` says
  // what it is in messages ("<bytes>").
  Document(std::shared_ptr<const std::vector<unsigned char>> bytes, const std::string& name,
           const std::string& password = "");
  ~Document();
  Document(const Document&) = delete;
  Document& operator=(const Document&) = delete;

  // Another handle on the same document for another thread, with its own
  // parse of the same file or bytes; MuPDF allows one thread per context
  // and document. Independent: a MuPDF context of its own (own allocator
  // lock, FreeType instance and resource store). Shared: a clone of this
  // one's context (fz_clone_context: store, glyph cache and FreeType shared
  // under MuPDF's locks), which measured 5-10x slower per page with 16
  // threads (BENCHMARKS.md): every allocation and glyph outline takes a
  // process-wide lock. The original must outlive its clones.
  enum class Context { Independent, Shared };
  std::unique_ptr<Document> clone(Context context = Context::Independent) const;

  int page_count() const;
  // Does the document name its press: an output intent whose profile
  // print preview can use (output_intent.h)?
  bool has_output_intent() const;
  // Page `index`'s box `which` (after /Rotate and /UserUnit), width and
  // height in points, without interpreting the page. Throws mpvg::Error.
  std::pair<double, double> page_size(int index, PageBox which = PageBox::Crop) const;
  // Page `index` (0-based); `pixels_per_point` is the output resolution
  // the page will be rendered at (stroke tolerance, thinnest lines), given
  // or chosen from the page's width and height in points (as
  // svg::ParseOptions::view is). Throws mpvg::Error when MuPDF fails on it.
  // One thread at a time per handle (its glyph outlines are cached for its
  // later pages).
  PageResult page(int index, double pixels_per_point, const PageOptions& options = {}) const;
  PageResult page(int index, const std::function<double(double width, double height)>& pixels_per_point,
                  const PageOptions& options = {}) const;

 private:
  Document(const Document& other, Context context);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mpvg::pdf
