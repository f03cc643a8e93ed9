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
// fill, fill-rule, fill-opacity, stroke, stroke-width, stroke-opacity,
// stroke-linejoin, stroke-linecap, stroke-miterlimit, stroke-dasharray,
// stroke-dashoffset, paint-order, vector-effect, opacity, clip-path,
// clip-rule, display, visibility, color and transform. Curves stay curves;
// arcs, circles and rounded corners become exact rational quadratics.
// Strokes become fill geometry (the stroke stage, stroker/stroke.h, builds it
// from the centreline when the scene is rendered), painted with the nonzero
// rule above or below the fill as paint-order says; they are not part of
// clip paths or bounding boxes.
//
// Paint servers, for fills and strokes: linearGradient and radialGradient
// (gradientUnits, gradientTransform, spreadMethod, fx/fy/fr as the
// two-point conical gradient of SVG 2, stops with stop-color and
// stop-opacity, color-interpolation) and pattern (patternUnits,
// patternContentUnits, viewBox, preserveAspectRatio, patternTransform;
// tiles are scenes of their own, nested up to kMaxPatternDepth), with href
// templates, and fallback colours where a server cannot paint. Each use is
// resolved against the shape's bounding box and user space.
//
// image: PNG, JPEG, GIF (first frame) and WebP images as texture paints
// (x, y, width, height with auto sizes, preserveAspectRatio,
// image-rendering), and SVG and SVGZ documents converted and embedded as
// vectors; from data: URIs, and from local files inside the folders the
// document may read (its own folder's tree and ParseOptions::allowed_dirs),
// never from the network (svg_resources.h).
//
// Not supported (warned about, and rendered approximately or not at all):
// text, meshgradient and hatch paint servers (the fallback colour
// is used), paint servers in other documents, markers, masks, filters,
// nested <svg>, symbol, switch, <style> sheets, and group opacity
// (multiplied into each descendant's paint).
#pragma once
#include <string>
#include <string_view>

#include "parsers/svg/svg_options.h"

namespace mpvg::svg {

// Reads and parses a file; "-" reads standard input (relative references
// then resolve against the current directory). Throws mpvg::Error with
// a one-line message: "cannot read 'PATH': <reason>", "XML parse error at
// line N: ...", or a message naming a non-SVG root or an invalid root size.
ParseResult parse_svg_file(const std::string& path, const ParseOptions& options = {});

// The bytes parse_svg_file reads ("-": standard input), at most max_bytes
// (a regular file's size is checked before it is read; a stream, e.g.
// /dev/zero, is read up to the limit). Throws mpvg::Error ("cannot read
// 'x.svg': No such file or directory", "'x.svg' is larger than the input
// limit of 1 GiB").
std::string read_svg_file(const std::string& path, size_t max_bytes = SIZE_MAX);

// Parses SVG text. base_dir is where relative references of the document
// resolve (the document's directory); its tree may be read, as may
// options.allowed_dirs.
ParseResult parse_svg_string(std::string_view text, const std::string& base_dir = ".",
                             const ParseOptions& options = {});

}  // namespace mpvg::svg
