// Encoding: the host turns a Scene into the flat arrays every executor reads
// (in the spirit of vello's scene encoding). Segments are transformed to
// pixel space in double precision; every contour of a path is closed; paints
// become the records of core/paint/paint.h, in the colour space integration works
// in, with their transforms composed down to pixels; each pattern's tile
// becomes a scene of its own, encoded in the grid its tree is built over.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/geometry/abstraction.h"
#include "core/paint/image_border.h"
#include "core/memory_budget.h"
#include "core/paint/paint.h"
#include "core/paint/paint_data.h"
#include "core/scene.h"
#include "core/tree/shortcut_tree.h"
#include "core/output/srgb.h"
#include "stroker/stroke_input.h"
#include "core/tree/tree.h"

namespace mpvg {

enum class Gamma { Srgb, Linear };

struct EncodedTile;

struct EncodedScene {
  std::vector<InputSegment> segments;   // all filled paths, stream order, contours closed
  // Stroked paths' centrelines, styles and transforms to pixels: the stroke
  // stage (stroker/stroke.h) builds their segments, which join `segments` in
  // path order before abstraction (stroke_input_segments, gpu::Context).
  StrokeBatch strokes;
  std::vector<PathRecord> paths;        // indexed by path id (stream order)
  // The stream with one PATH placeholder per path: delimiters are entries
  // (ENTRY_PUSH/ACTIVATE/POP) and each path is one ENTRY_SEGMENT entry whose
  // path field names it. Abstraction expands placeholders into the path's
  // abstract segments.
  std::vector<Entry> stream;
  size_t input_segment_count = 0;  // segments as given, before closing lines
  // The scene's paints, its tiles' paints included (PathRecord::paint
  // indexes them), and every pattern tile at every depth
  // (PatternRecord::tree indexes them). Set on the top-level scene only.
  std::shared_ptr<const PaintData> paint;
  std::vector<EncodedTile> tiles;
  // A forest frame's scenes, in order (frame/forest.h); empty: one scene,
  // the whole stream, over the grid the tree is built for.
  std::vector<SceneRoot> roots;
};

// A pattern tile: its content in grid coordinates, where the tile is
// [0, width) x [0, height), a grid of unit areas chosen about as fine as
// the output's pixels (at least kMinTileGrid, at most kMaxTileGrid per
// side). The grid only sets how finely the tile's tree is subdivided: the
// tile is evaluated exactly at every sample whatever it is.
struct EncodedTile {
  EncodedScene scene;
  int width = 1, height = 1;
};
constexpr int kMinTileGrid = 16;
constexpr int kMaxTileGrid = 2048;

// Minification (texture.h): the level of detail is log2 of the footprint of
// an output pixel in texels (the largest singular value of the pixel-to-
// texel map) plus this bias, and mip levels are used where it is positive.
// With -1 the chosen level still has features of half a pixel, which the m
// samples of every unit area resolve: images stay sharper than with a
// whole pixel's prefilter, and nothing aliases.
constexpr double kTextureLodBias = -1.0;

struct EncodeOptions {
  // 0: colour ramps as exact knots (the stops, with knots added where the
  // interpolation space differs from the integration space, so that linear
  // pieces stay within 1/4096 of the exact colours). N > 1: a lookup table
  // of N knots evenly spaced in t (measured against the exact ramps in
  // BENCHMARKS.md).
  int ramp_lut = 0;
  // The frame's unit areas, [0, frame_width) x [0, frame_height) in the
  // coordinates `view` maps to, where samples fall (0: unbounded): paints
  // prepared per frame are made for what of them can be sampled (a mesh
  // shading's grid covers only that).
  int frame_width = 0, frame_height = 0;
  // The output image within the frame: the top-level scene's edges on its
  // border are pushed out past the frame (core/paint/image_border.h).
  ImageBorder border;
  // What the encoding holds is charged to it (core/memory_budget.h).
  MemoryBudget* budget = nullptr;
  // Filter effects inside a pattern tile (frame/filter_layers.h): the tile
  // with its filters made layers over the tile's grid (width x height
  // unit areas, `view` from tile units to them). Unset: such a tile is
  // refused.
  std::function<Scene(const Scene& tile, int width, int height, const Affine& view)> tile_filters;
};

// view maps scene units to pixels. Throws mpvg::Error for rational cubics,
// non-finite coordinates, more paths than entries can name, or patterns
// nested deeper than kMaxPatternDepth.
EncodedScene encode(const Scene& scene, const Affine& view, Gamma gamma, const EncodeOptions& options = {});


}  // namespace mpvg
