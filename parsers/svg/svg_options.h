// What the SVG frontend is asked (ParseOptions) and what it gives
// (ParseResult): the parser's entry points are svg_parser.h; the converter
// (svg_converter.h) reads the options and fills the result.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/memory_budget.h"
#include "core/scene.h"

namespace mpvg::svg {

// An element with an id and the box of what it draws (svg2png --query):
// in the root viewport's units (CSS pixels of the document's own size),
// strokes, markers and filter regions included, clip paths not applied.
struct ElementBox {
  std::string id;
  double x = 0, y = 0, width = 0, height = 0;
};

struct ParseResult {
  Scene scene;
  // ParseOptions::query: every drawn element with an id, in document
  // order (an element drawn several times through <use>: the first time).
  std::vector<ElementBox> elements;
  // One short line per feature rendered approximately or not at all,
  // deduplicated, in the order first met.
  std::vector<std::string> warnings;
  // The number of stroked paths (the scene's strokes; the stroke stage
  // builds them when the scene is rendered).
  size_t stroked_paths = 0;
};

struct ParseOptions {
  // Hairlines (strokes thinner than a pixel) are drawn one pixel wide with
  // their opacity scaled to keep the ink (hairline(), stroker/stroke_input.h),
  // which needs to know what a pixel is. `view`, when set, is called once
  // with the document's size (scene units) and returns the scene-to-pixel
  // transform the document will be rendered with (svg2png passes the one
  // its -w/-h/-z give). Without it, the scene is prepared for `device_scale`
  // pixels per scene unit. (Stroke outlines themselves are built when the
  // scene is rendered, to 1/16 of an output pixel at whatever scale.)
  std::function<Affine(double width, double height)> view;
  double device_scale = 2;

  // Folders whose files <image> may read besides the document's own
  // folder tree (which is always allowed): relative hrefs, absolute paths
  // and file: URLs are read only when their real path lies inside one of
  // these trees. Network URLs are never loaded.
  std::vector<std::string> allowed_dirs;

  // Fonts for text: every font file in these folders (and their
  // subfolders), then the system's (fontconfig) unless system_fonts is
  // false.
  std::vector<std::string> font_dirs;
  bool system_fonts = true;

  // The user's languages for systemLanguage (conditional processing), as
  // BCP 47 tags; "en" matches "en" and "en-US" (and "en-US" matches "en").
  std::vector<std::string> languages{"en"};

  // Raster images: texels at most once decoded at the size they are drawn
  // (image_reduction.h), and at full size where a decoder must hold the
  // whole image first (GIF, WebP, interlaced PNG). Larger ones are not
  // drawn, with a warning. svg2png sets them from --max-memory.
  size_t max_image_pixels = size_t(1) << 28;
  size_t max_whole_image_pixels = size_t(1) << 26;

  // The render's memory budget (core/memory_budget.h): the document's
  // shapes, elements and scene are charged to it as they are made; a
  // document that needs more fails with ResourceError. Null: not counted.
  std::shared_ptr<MemoryBudget> budget;

  // Bytes of input parse_svg_file reads at most (svg2png --max-input).
  size_t max_input_bytes = SIZE_MAX;

  // Pixels per inch of the absolute units (in, cm, mm, pt, pc) of the
  // document's lengths: CSS's 96 by default; svg2png --dpi, as
  // rsvg-convert's -d and resvg's --dpi (px and user units stay as they
  // are: a document sized in mm comes out at that many dots per inch).
  double dpi = 96;

  // svg2png --export-id: only the element with this id and its subtree,
  // with its ancestors' transforms and the properties they pass down but
  // none of their effects (opacity, clip, mask, filter), as rsvg-convert
  // and resvg draw it; the scene is the box of what it draws
  // (ElementBox), moved to the origin, and `view` is asked for that size.
  // ParseError when no element with that id is drawn.
  std::string export_id;

  // svg2png --query: fill ParseResult::elements.
  bool query = false;

  // Threads converting strokes (0: every core). Batches that parse files
  // on every core already pass 1.
  int threads = 0;

  // Options for rendering at `pixels` wide, the height rounded to keep the
  // aspect ratio (as svg2png -w does).
  static ParseOptions at_width(int pixels);
};

}  // namespace mpvg::svg
