// SVG frontend: parses an SVG document and builds a mpvg::Scene.
//
// The scene is normalised the way usvg normalises SVG: absolute transforms,
// resolved styles, no units, only the scene model's segment types. Nothing
// downstream knows SVG exists.
//
// Supported: the root <svg> viewport (width, height, viewBox,
// preserveAspectRatio), g, a (as g), defs, path, rect, circle, ellipse, line,
// polyline, polygon, use, clipPath (nested, objectBoundingBox units); the
// transform attribute; presentation attributes and the style attribute for
// fill, fill-rule, fill-opacity, opacity, clip-path, clip-rule, display,
// visibility, color and transform. Curves stay curves; arcs, circles and
// rounded corners become exact rational quadratics.
//
// Not supported (warned about, and rendered approximately or not at all):
// strokes, text, images, gradients and patterns (the paint's fallback colour
// is used), masks, filters, nested <svg>, symbol, switch, <style> sheets,
// and group opacity (multiplied into each descendant's paint).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "core/scene.h"

namespace mpvg::svg {

struct ParseResult {
  Scene scene;
  // One short line per feature rendered approximately or not at all,
  // deduplicated, in the order first met.
  std::vector<std::string> warnings;
};

// Reads and parses a file; "-" reads standard input. Throws mpvg::Error with
// a one-line message: "cannot read 'PATH': <reason>", "XML parse error at
// line N: ...", or a message naming a non-SVG root or an invalid root size.
ParseResult parse_svg_file(const std::string& path);

// Parses SVG text. base_dir is where relative references of the document
// resolve (the document's directory); no external resource is loaded yet.
ParseResult parse_svg_string(std::string_view text, const std::string& base_dir = ".");

}  // namespace mpvg::svg
