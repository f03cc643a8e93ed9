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
#include "parsers/pdf/pdf_options.h"

namespace mpvg::pdf {

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
