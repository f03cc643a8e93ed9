// Encoding: the host turns a Scene into the flat arrays every executor reads
// (in the spirit of vello's scene encoding). Segments are transformed to
// pixel space in double precision; every contour of a path is closed; paints
// are premultiplied in the colour space integration works in.
#pragma once
#include <cstdint>
#include <vector>

#include "core/abstraction.h"
#include "core/scene.h"
#include "core/shortcut_tree.h"

namespace mpvg {

enum class Gamma { Srgb, Linear };

struct EncodedScene {
  std::vector<InputSegment> segments;   // all paths, stream order, contours closed
  std::vector<PathRecord> paths;        // indexed by path id (stream order)
  std::vector<PaintRecord> paints;
  // The stream with one PATH placeholder per path: delimiters are entries
  // (ENTRY_PUSH/ACTIVATE/POP) and each path is one ENTRY_SEGMENT entry whose
  // path field names it. Abstraction expands placeholders into the path's
  // abstract segments.
  std::vector<Entry> stream;
  size_t input_segment_count = 0;  // segments as given, before closing lines
};

// view maps scene units to pixels. Throws mpvg::Error for rational cubics,
// non-finite coordinates or more paths than entries can name.
EncodedScene encode(const Scene& scene, const Affine& view, Gamma gamma);

// Colour conversions for paints and the final image.
float srgb_to_linear(float c);
float linear_to_srgb(float c);

}  // namespace mpvg
