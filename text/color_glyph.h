// COLR version 1 colour glyphs (OpenType 1.9 COLR table: paint graphs),
// read with FreeType's COLR v1 API and lowered to a core scene.
//
// Lowering, per paint format (font space: font units, y up; the root
// transform scales by size / units per em and flips y):
//   PaintColrLayers   its layers in order, each source-over on the ones below.
//   PaintSolid        palette 0's colour times alpha; 0xFFFF: opts.foreground.
//   PaintLinear/Radial/SweepGradient
//                     a core Gradient whose xf maps font space (with every
//                     enclosing transform) to user units. Linear: p0 -> p1
//                     with isolines parallel to p0 -> p2, projected to the
//                     equivalent two-point line p0 -> p3. Radial: the
//                     two-point conical gradient, focal = c0 / r0, end =
//                     c1 / r1. Sweep: angles counter-clockwise from +x in
//                     font space (OpenType 1.9.1's bias of 180 degrees
//                     added: FreeType reports the stored value). A colour
//                     line whose stops span [s0, s1] other than [0, 1] moves
//                     the geometry to s0 and s1 and its stops to [0, 1], so
//                     that the spread repeats [s0, s1] as COLR says. Stops
//                     are interpolated with premultiplied alpha (COLR's
//                     rule), which core's straight-alpha ramps approximate
//                     with added stops (premultiplied_stops), between
//                     sRGB-encoded values (ColorSpace::Srgb). The OFF
//                     text asks for premultiplied, linear-light values;
//                     Skia's COLR v1 code takes straight sRGB ones.
//                     A paint not under a PaintGlyph fills the glyph's
//                     extent (its clip box, else the bounds of its outlines).
//   PaintGlyph        a fill of the outline when its child is a solid or a
//                     gradient (under transforms); otherwise a clip section
//                     of the outline around the child's content.
//   PaintColrGlyph    the referenced glyph's graph inline, inside its clip
//                     box where it has one.
//   PaintTransform, Translate, Scale, Rotate, Skew (with or without centre)
//                     compose into the affine of the child's outlines and
//                     gradients.
//   PaintComposite    blend modes: an isolated group of the backdrop and,
//                     over it, the source in a group of that blend mode;
//                     SRC_ATOP, XOR, PLUS: the same with core's SourceAtop,
//                     Xor, PlusLighter; DEST_ATOP: the operands swapped;
//                     SRC_IN / DEST_IN: a group masked by the other operand's
//                     alpha; SRC_OUT / DEST_OUT: masked by one minus that
//                     alpha (a luminance mask: black over white, the black
//                     alpha-masked by the other operand; exact where
//                     integration is sRGB-encoded, core's default); SRC_OVER,
//                     DEST_OVER, SRC, DEST, CLEAR: the operands drawn in
//                     order, or one, or none (no group: nothing blends).
//
// A glyph's clip box clips its whole drawing. Groups (composites) nest at
// most kMaxColorGlyphGroups deep inside the scene, leaving core's other
// levels (kMaxGroupDepth) to whatever embeds it; a composite past that is
// drawn without its groups (blends: source over backdrop; masks: the masked
// operand alone), with a warning. Cycles (PaintColrGlyph back
// to a glyph being drawn) and graphs deeper than kMaxPaintDepth paints are
// cut with a warning; so are paints FreeType cannot read (FreeType 2.12
// reports the variable formats, PaintVar*, as unsupported; FreeType 2.13
// reads them with the face's variation deltas applied).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/scene.h"
#include "text/text.h"

namespace mpvg::text {

constexpr int kMaxColorGlyphGroups = 8;
constexpr int kMaxPaintDepth = 64;

struct ColorGlyphOptions {
  double size = 1;                                         // user units per em (as glyph_outline's size)
  RGBA foreground{0, 0, 0, 1};                             // palette index 0xFFFF (the text's colour), straight alpha
  std::vector<std::pair<std::string, double>> variations;  // as glyph_outline's
};

// The glyph's COLR v1 paint graph as a core scene: user units at opts.size,
// y down, origin at the pen (the same space as glyph_outline). width and
// height are the size of the glyph's clip box, else of the bounds of the
// outlines it draws (the box itself is where the glyph is, above the
// baseline: not at the origin). nullptr when the glyph has no COLR v1 paint
// (COLR v0-only glyphs, fonts without the table), and where FreeType's COLR
// v1 API is disabled (Debian 12's libfreetype6 ships it so: the font's COLR
// v1 glyphs then all return nullptr, with a warning). Warnings (each once):
// paints skipped or cut, groups past the depth limit.
std::shared_ptr<const Scene> color_glyph_scene(const FontDb& db, int face, uint32_t glyph,
                                               const ColorGlyphOptions& opts,
                                               std::vector<std::string>* warnings = nullptr);

}  // namespace mpvg::text
