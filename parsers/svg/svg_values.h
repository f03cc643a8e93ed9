// Lexical parsers for SVG attribute and property values: numbers, lengths,
// transform lists, colours, paints, the font shorthand, viewBox and
// preserveAspectRatio.
//
// Internal to the SVG frontend. Every parser is total: it returns nullopt (or
// reports how far it got) on malformed text, never throws, and rejects NaN,
// infinities and magnitudes above kMaxNumber.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/scene.h"

namespace mpvg::svg::detail {

// Numbers beyond this magnitude are treated as syntax errors: no drawing has
// coordinates this large, and keeping them finite after transforms matters
// more than accepting them.
constexpr double kMaxNumber = 1e9;
// Filter regions and subregions may be larger (a userSpaceOnUse region
// 2e9 wide around the drawing): they are clipped to what can reach the
// output before anything is sized (Converter::region_fill, plan_layer).
constexpr double kMaxRegionNumber = 1e30;

// XML whitespace (XML 1.0 §2.3 S), which is also SVG's wsp.
inline bool is_ws(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f'; }

// ASCII lower case (names and keywords are ASCII; no locale applies).
inline char ascii_lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// The value of a hexadecimal digit, or -1.
inline int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  c = ascii_lower(c);
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

std::string_view trim(std::string_view s);
bool iequals(std::string_view a, std::string_view b);

// A cursor over value text following the SVG 2 / CSS lexical rules.
class Scanner {
 public:
  // Numbers beyond max_magnitude are syntax errors.
  explicit Scanner(std::string_view s, double max_magnitude = kMaxNumber) : s_(s), max_(max_magnitude) {}

  bool at_end() const { return pos_ >= s_.size(); }
  char peek() const { return at_end() ? '\0' : s_[pos_]; }
  size_t pos() const { return pos_; }
  std::string_view rest() const { return s_.substr(pos_); }

  // Defined here, not in svg_values.cpp: path data calls these around
  // every number, and the call cost more than the few bytes they skip.
  void skip_ws() {
    while (pos_ < s_.size() && is_ws(s_[pos_])) pos_++;
  }
  // wsp* [',' wsp*]; returns whether a comma was consumed.
  bool skip_comma_ws() {
    skip_ws();
    const bool comma = consume(',');
    if (comma) skip_ws();
    return comma;
  }
  bool consume(char c) {
    if (at_end() || s_[pos_] != c) return false;
    pos_++;
    return true;
  }
  // Consumes `word` if it comes next, ASCII case-insensitively.
  bool consume_word(std::string_view word);
  // An SVG number: [+-]? (digits ['.' digits?] | '.' digits) ([eE] [+-]? digits)?.
  // An exponent is only taken when digits follow, so "1em" is 1 then "em".
  // On failure the cursor does not move.
  std::optional<double> number();
  // An arc flag: exactly one '0' or '1' (SVG 2 path grammar).
  std::optional<bool> flag() {
    if (consume('0')) return false;
    if (consume('1')) return true;
    return std::nullopt;
  }
  // An identifier-like run of letters, digits and '-' (for keywords).
  std::string_view word();

 private:
  std::string_view s_;
  double max_ = kMaxNumber;
  size_t pos_ = 0;
};

// Whole-value number (trimmed); nullopt unless the text is exactly one number.
std::optional<double> parse_number(std::string_view s);

// Calc: a calc() expression's value, a sum of terms of different units
// (absolute ones folded into px).
enum class Unit { None, Px, Pt, Pc, Mm, Cm, In, Em, Ex, Rem, Percent, Calc };

struct Length {
  double value = 0;  // Calc: the px term
  Unit unit = Unit::None;
  // Calc only: the terms that resolve later (percent as written: 50% is 50).
  double percent = 0, em = 0, ex = 0, rem = 0;
};

// Where calc() is accepted: in CSS property values and presentation
// attributes (CSS Values 4 §10; browsers parse SVG 2's geometry properties
// and the style properties so), not in attributes that are no properties
// (x1, gradient and pattern attributes, ...), which browsers reject.
enum class CalcOk : bool { No, Yes };

// <length> | <percentage> (CSS Values 3, as used by SVG 2), trimmed, units
// case-insensitive; with CalcOk::Yes also calc() (+ - * / and parentheses,
// nested calc(), CSS Values 4 §10.1's typing: a sum of lengths and
// percentages, scaled by plain numbers). nullopt on anything else.
std::optional<Length> parse_length(std::string_view s, CalcOk calc = CalcOk::No, double max_magnitude = kMaxNumber);

// The font-relative units are resolved with a fixed font: 1em = 16px and
// 1ex = 8px (fonts are not modelled). `percent_base` is the reference length
// that 100% stands for.
double length_to_px(const Length& l, double percent_base);
// The absolute units (in, cm, mm, pt, pc) convert at `dpi` pixels per inch
// instead of 96 for the lengths this thread converts while the scope
// lives (ParseOptions::dpi, for the parse of one document).
class AbsoluteUnitsScope {
 public:
  explicit AbsoluteUnitsScope(double dpi);
  ~AbsoluteUnitsScope();
  AbsoluteUnitsScope(const AbsoluteUnitsScope&) = delete;
  AbsoluteUnitsScope& operator=(const AbsoluteUnitsScope&) = delete;

 private:
  double saved_;
};
// A length with its font-relative units resolved: em against `em`, ex as
// half of it, rem against `rem`; percentages of `percent_base`.
double resolve_length(const Length& l, double percent_base, double em, double rem);

// A transform list (SVG 1.1 §7.6 grammar), with what browsers also take
// there and in the CSS transform property (CSS Transforms 1): angle units
// (deg, grad, rad, turn), absolute length units on translations,
// translateX/Y, scaleX/Y, skew(), none. nullopt on any syntax error (the
// caller ignores the whole attribute, as CSS does); an empty or blank list
// is the identity.
std::optional<Affine> parse_transform(std::string_view s);

// cos and sin of an angle in radians, snapped to exact 0 and ±1 when within
// 1e-15 of them, so that rotate(90) and arcs through the axes stay exact.
void sincos_snapped(double radians, double& s, double& c);

// A CSS colour (CSS Color 3/4 subset: named, #rgb[a], #rrggbb[aa],
// rgb[a](), hsl[a]()) at the cursor. Components are clamped to [0, 1].
// Does not accept currentColor (the caller resolves it).
std::optional<RGBA> parse_color(Scanner& s);
// A whole colour value; a trailing SVG 1.1 icc-color(...) is ignored.
std::optional<RGBA> parse_color(std::string_view s);
std::optional<RGBA> named_color(std::string_view name);

// A <paint> value (SVG 1.1 §11.2, SVG 2 painting.html#SpecifyingPaint): none | currentColor |
// <color> [<icccolor>] | <url> [none | currentColor | <color>] |
// context-fill | context-stroke.
struct PaintValue {
  enum class Kind { None, Color, CurrentColor, Url, Context };
  enum class Fallback { Absent, None, Color, CurrentColor };
  Kind kind = Kind::None;
  bool context_stroke = false;  // Kind::Context: context-stroke (else context-fill)
  RGBA color;
  std::string url;  // fragment id for Kind::Url ("" when not a local reference)
  bool url_external = false;
  Fallback fallback = Fallback::Absent;
  RGBA fallback_color;
};
std::optional<PaintValue> parse_paint(std::string_view s);

// A FuncIRI "url(#id)", quotes and inner whitespace allowed. Returns the
// fragment id; `external` is set when the IRI points into another document.
std::optional<std::string> parse_func_iri(Scanner& s, bool* external);
// An IRI as used by href: "#id". nullopt when not a same-document reference.
std::optional<std::string> parse_iri_fragment(std::string_view s);

// opacity, fill-opacity: <number> | <percentage>, clamped to [0, 1]
// (CSS Color 4 <alpha-value>).
std::optional<double> parse_alpha(std::string_view s);

// mix-blend-mode (Compositing and Blending 1): one of the 16 blend-mode
// keywords; anything else (plus-lighter, plus-darker, invalid) is nullopt.
std::optional<BlendMode> parse_blend_mode(std::string_view s);

// The font shorthand (CSS Fonts 4 §2.8) split into the longhands it sets,
// values as written: [ <font-style> || small-caps || <font-weight> ||
// <font-stretch keyword> ]? <font-size> [ / <line-height> ]? <family>#,
// each word before the size at most once ("normal" standing for any of
// them), a unitless number there a weight. The result sets font-style,
// font-variant, font-weight, font-stretch, font-size, line-height and
// font-family (normal where the value leaves one out) and resets
// font-size-adjust and font-kerning, as the shorthand does; a CSS-wide
// keyword (inherit, initial, unset, revert) goes to all of them. nullopt
// when the value does not follow the grammar (system fonts such as
// "caption" included: they are not supported), which makes the
// declaration invalid.
std::optional<std::vector<std::pair<std::string, std::string>>> split_font_shorthand(std::string_view v);

struct ViewBox {
  double x = 0, y = 0, w = 0, h = 0;
};
// Four numbers separated by comma-wsp. A negative width or height is an
// error (SVG 1.1 §7.7): nullopt. Zero sizes are returned (they disable
// rendering).
std::optional<ViewBox> parse_view_box(std::string_view s);

struct AspectRatio {
  enum class Align { None, Min, Mid, Max };
  Align x = Align::Mid, y = Align::Mid;
  bool slice = false;
};
// preserveAspectRatio (SVG 1.1 §7.8): [defer] <align> [meet | slice].
std::optional<AspectRatio> parse_aspect_ratio(std::string_view s);

// The viewBox-to-viewport transform (SVG 2 coords.html
// #ComputingAViewportsTransform). vb must have positive width and height.
Affine view_box_transform(const ViewBox& vb, const AspectRatio& ar, double width, double height);

}  // namespace mpvg::svg::detail
