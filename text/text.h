// mpvg's font engine: a database of font faces (FreeType), CSS font matching,
// HarfBuzz shaping and glyph outlines as mpvg::Path. It knows nothing of SVG:
// the frontends resolve their styles to the calls below.
//
// Units: every length is in user units for a font `size` of user units per
// em, with y pointing down (as in a scene), origin at the pen position on the
// baseline.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/scene.h"

namespace mpvg::text {

struct FaceInfo {
  std::string family;  // typographic family (name ID 16) if present, else FreeType's family_name
  int weight = 400;    // OS/2 usWeightClass
  bool italic = false;
  int stretch = 5;     // 1..9, CSS font-stretch keywords (OS/2 usWidthClass)
  std::string path;
  int index = 0;       // face index inside a collection
  bool sfnt = true;    // TrueType or OpenType; false: Type 1 and other formats FreeType reads
};

// Thread-safe: one mutex serialises every FreeType and HarfBuzz call on the
// db's FT_Library. faces() and the add_* / set_generic calls must not run
// concurrently with each other (build the db first, then share it).
class FontDb {
 public:
  FontDb();
  ~FontDb();
  FontDb(const FontDb&) = delete;
  FontDb& operator=(const FontDb&) = delete;

  // Every font file (ttf, otf, ttc/otc: every face of a collection) directly
  // in dir and its subfolders, in sorted path order; unreadable or broken
  // files are skipped with one warning each. Returns the faces added (a face
  // already in the db, same path and index, is not added again).
  size_t add_dir(const std::string& dir, std::vector<std::string>* warnings = nullptr);
  size_t add_file(const std::string& path, std::vector<std::string>* warnings = nullptr);
  // fontconfig's list of fonts, read from its cache (no font file is opened
  // but variable fonts'); 0 when mpvg was built without fontconfig. It also
  // makes match() resolve families as fontconfig's configuration says.
  size_t add_system_fonts();

  // Generic families (serif, sans-serif, cursive, fantasy, monospace; names
  // case-insensitive). Defaults are resvg's test-suite mapping: Noto Serif,
  // Noto Sans, Yellowtail, Sedgwick Ave Display, Noto Mono. When the mapped
  // family is absent, match() takes a family by name heuristics.
  void set_generic(const std::string& generic, const std::string& family);

  const std::vector<FaceInfo>& faces() const;

  // CSS Fonts 4 §5.2 font matching: the first family of the list (names
  // case-insensitive) that has faces; among its faces the nearest stretch,
  // then style, then weight by the CSS rules, an OpenType face before a
  // Type 1 one of the same family and style. A family the db lacks is
  // resolved as fontconfig's rules alias it (FcConfigSubstitute: Helvetica
  // to Nimbus Sans, Arial to Liberation Sans; the families its
  // configuration puts ahead of its default list, as Chromium and librsvg
  // take them); a generic name by its mapping when that family is present
  // (set_generic, resvg's test-suite defaults), else as fontconfig resolves
  // it. No family found: "serif" the same way, else a family chosen by name
  // heuristics. -1 only when the db is empty.
  int match(const std::vector<std::string>& families, int weight, bool italic, int stretch = 5) const;

  // Is `substitute` a family fontconfig's configuration puts in for
  // `family` (an alias such as Helvetica's Nimbus Sans, not its default)?
  bool is_alias(const std::string& family, const std::string& substitute) const;

  bool has_glyph(int face, char32_t c) const;
  // Whether the face has colour bitmap strikes (CBDT, sbix).
  bool has_color_bitmaps(int face) const;

  // Per-character fallback: the face with a glyph for c that is nearest in
  // style, then weight (the earliest such face of the db); -1 if none has it.
  int fallback(char32_t c, int weight, bool italic) const;

  // Internal: the FreeType and HarfBuzz state (text.cpp), for the free
  // functions below.
  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

struct ShapedGlyph {
  uint32_t glyph = 0;
  uint32_t cluster = 0;  // byte offset in the utf8 input
  double x_advance = 0, y_advance = 0, x_offset = 0, y_offset = 0;  // user units at `size`, y down
};

struct ShapeOptions {
  bool rtl = false;
  bool vertical = false;
  // Unicode bidi algorithm (FriBiDi) over the input, paragraph level
  // left-to-right: each level run shaped in its direction (rtl ignored),
  // the runs in visual order.
  bool bidi = false;
  std::string language;  // BCP 47; empty: HarfBuzz's default
  // CSS font-feature-settings items: "\"liga\" 0", "smcp", "'kern' off",
  // and HarfBuzz's forms "-kern", "+liga", "aalt=2".
  std::vector<std::string> features;
  std::vector<std::pair<std::string, double>> variations;  // {"wght", 700}
};

// HarfBuzz shaping of text in one face at `size` user units per em. The
// script is guessed (hb_buffer_guess_segment_properties); the direction comes
// from the options (or the bidi algorithm). Glyphs are in visual order,
// clusters are byte offsets into utf8. Positions are unhinted, exact to
// 1/64 font unit.
std::vector<ShapedGlyph> shape(const FontDb& db, int face, std::string_view utf8, double size,
                               const ShapeOptions& o = {});

// The glyph's outline at `size`: TrueType quadratics as quad_to, CFF cubics
// as cubic_to, from the unhinted, unscaled outline scaled by size / units
// per em in double precision. Every contour is closed. Empty for blank
// glyphs (and bitmap-only ones).
// embolden > 0: the outline grown by that fraction of the em in width and
// height (FT_Outline_EmboldenXY; synthetic bold uses 1/32, as Skia at large
// sizes).
mpvg::Path glyph_outline(const FontDb& db, int face, uint32_t glyph, double size,
                         const std::vector<std::pair<std::string, double>>& variations = {},
                         double embolden = 0);

// Whether the face has the variation axis `tag` ("wght", "wdth", ...).
bool has_axis(const FontDb& db, int face, const char* tag);

// UTF-8 to code points (appended to cps); invalid bytes become U+FFFD. With
// offsets: each code point's byte offset, then the text's length.
void decode_utf8(std::string_view s, std::vector<char32_t>& cps, std::vector<size_t>* offsets = nullptr);

// Whether CSS letter-spacing applies to c's script: not to the cursive
// ones, whose letters join (Arabic, Syriac, Devanagari, ...; CSS Text 3 §8.2).
bool letter_spacing_applies(char32_t c);

// Whether c stands upright in vertical text (Unicode Vertical_Orientation
// U: CJK ideographs, kana, Hangul, fullwidth forms, emoji); other
// characters turn with the line.
bool upright_in_vertical(char32_t c);

// A colour glyph's layers (OpenType COLR version 0), bottom first: each an
// outline glyph filled with a palette colour (palette 0) or, where
// `foreground` is set, with the text's own fill. Empty for glyphs without
// COLR layers (and in fonts without the table).
struct ColorLayer {
  uint32_t glyph = 0;
  bool foreground = false;
  RGBA color;  // sRGB, straight alpha
};
std::vector<ColorLayer> color_layers(const FontDb& db, int face, uint32_t glyph);

// A bitmap glyph (colour emoji: CBDT, sbix) from the face's largest strike
// (as resvg; the texture filter scales it down), as straight RGBA, placed in
// user units at `size`: its top-left corner at (x, y) from the pen (y down),
// each pixel `scale` user units wide; an sbix image sits at its glyph's
// outline box. Empty for outline glyphs and fonts without colour bitmaps.
struct GlyphBitmap {
  std::shared_ptr<const Image> image;
  double x = 0, y = 0, scale = 1;
};
GlyphBitmap glyph_bitmap(const FontDb& db, int face, uint32_t glyph, double size);

// A glyph's SVG document (OpenType `SVG ` table): the document of the
// record whose glyph range holds the glyph, inflated when it is
// gzip-compressed, with that range (the glyphs that share the document).
// nullopt for glyphs without one, fonts without the table, and documents
// that are truncated, corrupt or inflate to more than 64 MiB.
struct SvgDocument {
  std::string text;
  uint32_t first_glyph = 0, last_glyph = 0;
};
std::optional<SvgDocument> svg_document(const FontDb& db, int face, uint32_t glyph);

// Internal, for the font engine's other files (text/color_glyph.cpp): runs
// fn with the face's FT_Face (as void*, so that this header needs no
// FreeType; nullptr where the face cannot be opened) under the db's mutex,
// its variation coordinates set to `variations` for the call (reset after
// it). fn must not call the functions of this header: the mutex is held.
void with_ft_face(const FontDb& db, int face, const std::vector<std::pair<std::string, double>>& variations,
                  const std::function<void(void* ft_face)>& fn);

struct Metrics {
  double ascent = 0, descent = 0;  // descent positive below the baseline
  double x_height = 0, cap_height = 0;
  double underline_position = 0;  // y down: positive below the baseline
  double underline_thickness = 0;
  double strikeout_position = 0;  // negative: above the baseline
  double strikeout_thickness = 0;
  // OS/2 ySubscriptYOffset (down) and ySuperscriptYOffset (up), both
  // positive; 1/5 and 1/3 of the em where the table lacks them.
  double subscript_offset = 0, superscript_offset = 0;
  double units_per_em = 1000;     // the font's, not scaled
};

// From the hhea / OS/2 / post tables, with fallbacks (glyph bounds of 'x' and
// 'H', fractions of the em) where a table or field is missing.
Metrics metrics(const FontDb& db, int face, double size);

}  // namespace mpvg::text
