// Computed style (CSS Cascade 4 as SVG 2 styling.html uses it): properties
// from presentation attributes and style declarations, inheritance, and the
// fill and stroke paint values; and the table of every property of SVG 2's
// index (kProperties): which mpvg supports, which are presentation
// attributes, and the warning for those it does not support.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>

#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_style.h"

namespace mpvg::svg::detail {

namespace {

std::optional<FillRule> parse_fill_rule(std::string_view s) {
  s = trim(s);
  if (iequals(s, "nonzero")) return FillRule::NonZero;
  if (iequals(s, "evenodd")) return FillRule::EvenOdd;
  return std::nullopt;
}

// <dasharray> = [ <length> | <percentage> ]# with commas and/or white space
// between values (SVG 2 painting.html#StrokeDasharrayProperty), or none.
// A negative value invalidates the whole list.
template <class ToUser>
std::optional<std::vector<double>> parse_dasharray(std::string_view v, ToUser to_user) {
  v = trim(v);
  std::vector<double> out;
  if (iequals(v, "none")) return out;
  while (!v.empty()) {
    size_t n = 0;
    while (n < v.size() && v[n] != ',' && !is_ws(v[n])) n++;
    const auto l = to_user(v.substr(0, n));
    if (!l || *l < 0) return std::nullopt;
    out.push_back(*l);
    v = trim(v.substr(n));
    if (!v.empty() && v.front() == ',') {
      v = trim(v.substr(1));
      if (v.empty()) return std::nullopt;
    }
  }
  if (out.empty()) return std::nullopt;
  return out;
}

// font-size (CSS Fonts 4 §2.5): an absolute-size keyword (scaled from
// medium = 16px), larger / smaller (a factor of 1.2), or a non-negative
// length or percentage, em, ex and % relative to the parent's size, rem to
// the root's (root).
std::optional<double> parse_font_size(std::string_view v, double parent, double root = 16) {
  v = trim(v);
  static const struct {
    const char* name;
    double scale;
  } sizes[] = {{"xx-small", 3.0 / 5}, {"x-small", 3.0 / 4}, {"small", 8.0 / 9}, {"medium", 1},
               {"large", 6.0 / 5},    {"x-large", 3.0 / 2}, {"xx-large", 2},      {"xxx-large", 3}};
  for (const auto& k : sizes)
    if (iequals(v, k.name)) return 16 * k.scale;
  if (iequals(v, "larger")) return parent * 1.2;
  if (iequals(v, "smaller")) return parent / 1.2;
  const auto l = parse_length(v, CalcOk::Yes);
  if (!l) return std::nullopt;
  const double size = resolve_length(*l, parent, parent, root);  // % of the parent's size too
  if (size < 0) return std::nullopt;
  return size;
}

// paint-order: normal | [ fill || stroke || markers ]; the layers left out
// follow in their normal order (SVG 2 painting.html#PaintOrder).
std::optional<PaintOrder> parse_paint_order(std::string_view v) {
  v = trim(v);
  if (iequals(v, "normal")) return kNormalPaintOrder;
  Scanner s(v);
  std::vector<PaintLayer> given;
  while (!s.at_end()) {
    const std::string_view w = s.word();
    PaintLayer l;
    if (iequals(w, "fill"))
      l = PaintLayer::Fill;
    else if (iequals(w, "stroke"))
      l = PaintLayer::Stroke;
    else if (iequals(w, "markers"))
      l = PaintLayer::Markers;
    else
      return std::nullopt;
    if (std::find(given.begin(), given.end(), l) != given.end()) return std::nullopt;
    given.push_back(l);
    s.skip_ws();
  }
  if (given.empty()) return std::nullopt;
  for (PaintLayer l : kNormalPaintOrder)
    if (std::find(given.begin(), given.end(), l) == given.end()) given.push_back(l);
  return PaintOrder{given[0], given[1], given[2]};
}

// shape-rendering and text-rendering: whether the keyword turns
// antialiasing off (crispEdges for shapes only, optimizeSpeed for both).
std::optional<bool> parse_rendering(std::string_view v, bool text) {
  const auto k = parse_keyword(v);
  if (!k) return std::nullopt;
  if (*k == "auto" || *k == "geometricprecision") return false;
  if (*k == "optimizespeed") return true;
  if (!text && *k == "crispedges") return true;
  if (text && *k == "optimizelegibility") return false;
  return std::nullopt;
}

bool is_paint_server(const std::string& name) {
  return name == "linearGradient" || name == "radialGradient" || name == "pattern" ||
         name == "meshgradient" || name == "hatch" || name == "solidcolor";
}

// The value of a property that is not inherited with "inherit" resolved:
// the parent's value, up the document tree (CSS Cascade 4 §7.3.2); at the
// root, none (the initial value).
template <class T, class Parse>
Prop<T> own_property(const Element& e, std::string_view name, Parse parse) {
  Prop<T> p = property<T>(e, name, parse);
  for (const Element* a = e.parent; p.state == Prop<T>::Inherit && a; a = a->parent) p = property<T>(*a, name, parse);
  if (p.state == Prop<T>::Inherit) p.state = Prop<T>::Unset;
  return p;
}

}  // namespace

// image-rendering (CSS Images 3 and SVG 1.1's keywords), as resvg maps
// them to filters.
std::optional<TextureFilter> parse_image_rendering(std::string_view v) {
  const auto k = parse_keyword(v);
  if (!k) return std::nullopt;
  if (*k == "auto" || *k == "optimizequality" || *k == "high-quality") return TextureFilter::Bicubic;
  if (*k == "smooth") return TextureFilter::Bilinear;
  if (*k == "optimizespeed" || *k == "crisp-edges" || *k == "pixelated") return TextureFilter::Nearest;
  return std::nullopt;
}

std::optional<std::string> parse_keyword(std::string_view s) {
  s = trim(s);
  Scanner sc(s);
  if (s.empty() || sc.word().size() != s.size()) return std::nullopt;
  std::string k(s);
  std::transform(k.begin(), k.end(), k.begin(),
                 [](char c) { return (c >= 'A' && c <= 'Z') ? char(c - 'A' + 'a') : c; });
  return k;
}

// font-family: a comma-separated list of names, quoted or not.
std::optional<std::vector<std::string>> parse_font_family(std::string_view v) {
  std::vector<std::string> out;
  for (size_t pos = 0; pos <= v.size();) {
    size_t end = pos;
    std::string name;
    const size_t lead = v.find_first_not_of(" \t\n\r", pos);
    if (lead != std::string_view::npos && (v[lead] == '"' || v[lead] == '\'')) {
      const size_t close = v.find(v[lead], lead + 1);
      if (close == std::string_view::npos) return std::optional<std::vector<std::string>>();
      name = std::string(v.substr(lead + 1, close - lead - 1));
      end = v.find(',', close);
    } else {
      end = v.find(',', pos);
      name = std::string(trim(v.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos)));
      // Unquoted names: runs of spaces are one.
      std::string c;
      for (char ch : name)
        if (!(ch == ' ' && !c.empty() && c.back() == ' ')) c += ch;
      name = c;
    }
    if (!name.empty()) out.push_back(name);
    if (end == std::string_view::npos) break;
    pos = end + 1;
  }
  return out.empty() ? std::optional<std::vector<std::string>>() : std::optional(out);
}

// font-weight: a keyword or a number 1..1000; bolder and lighter from the
// parent's weight.
std::optional<int> parse_font_weight(std::string_view v, int parent) {
  const auto k = parse_keyword(v);
  if (k == "normal") return 400;
  if (k == "bold") return 700;
  // CSS Fonts 4 §2.2's table for bolder and lighter.
  if (k == "bolder") return parent < 350 ? 400 : parent < 550 ? 700 : parent < 900 ? 900 : parent;
  if (k == "lighter") return parent < 100 ? parent : parent < 550 ? 100 : parent < 750 ? 400 : 700;
  double n = 0;
  const std::string t(trim(v));
  const auto r = std::from_chars(t.data(), t.data() + t.size(), n);
  if (r.ec == std::errc() && r.ptr == t.data() + t.size() && n >= 1 && n <= 1000) return int(std::lround(n));
  return std::nullopt;
}

// font-style: normal | italic | oblique <angle>? (any angle slants as
// italic does here).
std::optional<bool> parse_font_style(std::string_view v) {
  v = trim(v);
  Scanner s(v);
  const std::string_view w = s.word();
  if (w.size() == v.size()) {
    const auto k = parse_keyword(v);
    if (k == "normal") return false;
    if (k == "italic" || k == "oblique") return true;
    return std::nullopt;
  }
  s.skip_ws();
  const std::string_view angle = v.substr(s.pos());
  Scanner a(angle);
  if (!iequals(w, "oblique") || !a.number()) return std::nullopt;
  for (const char* unit : {"deg", "grad", "rad", "turn"})
    if (iequals(angle.substr(a.pos()), unit)) return true;
  return std::nullopt;
}

// font-stretch: a keyword, as 1 (ultra-condensed) .. 9 (ultra-expanded),
// or a percentage, taken as the nearest keyword (CSS Fonts 4 §2.4's
// table: 50% .. 200%).
std::optional<int> parse_font_stretch(std::string_view v) {
  static const char* names[] = {"ultra-condensed", "extra-condensed", "condensed", "semi-condensed", "normal",
                                "semi-expanded",   "expanded",        "extra-expanded", "ultra-expanded"};
  static const double percents[] = {50, 62.5, 75, 87.5, 100, 112.5, 125, 150, 200};
  const auto k = parse_keyword(v);
  for (int i = 0; i < 9; i++)
    if (k == names[i]) return i + 1;
  const auto l = parse_length(v);
  if (!l || l->unit != Unit::Percent || l->value < 0) return std::nullopt;
  int best = 0;
  for (int i = 1; i < 9; i++)
    if (std::fabs(percents[i] - l->value) < std::fabs(percents[best] - l->value)) best = i;
  return best + 1;
}

// The font shorthand, for the font attribute: style sheets and style
// attributes have it split into its longhands already (svg_css.cpp).
struct FontShorthand {
  bool italic = false, small_caps = false;
  int weight = 400, stretch = 5;
  double size = 16;
  std::vector<std::string> family;
};

std::optional<FontShorthand> parse_font_shorthand(std::string_view v, const Inherited& parent) {
  // (property() takes the CSS-wide keywords before this is called.)
  const auto longhands = split_font_shorthand(v);
  if (!longhands) return std::nullopt;
  FontShorthand f;
  for (const auto& [name, value] : *longhands) {
    if (name == "font-style") {
      const auto it = parse_font_style(value);
      if (!it) return std::nullopt;
      f.italic = *it;
    } else if (name == "font-variant") {
      f.small_caps = value == "small-caps";
    } else if (name == "font-weight") {
      const auto w = parse_font_weight(value, parent.font_weight);
      if (!w) return std::nullopt;
      f.weight = *w;
    } else if (name == "font-stretch") {
      const auto st = parse_font_stretch(value);
      if (!st) return std::nullopt;
      f.stretch = *st;
    } else if (name == "font-size") {
      const auto size = parse_font_size(value, parent.font_size);
      if (!size) return std::nullopt;
      f.size = *size;
    } else if (name == "font-family") {
      const auto family = parse_font_family(value);
      if (!family) return std::nullopt;
      f.family = *family;
    }
  }
  return f;
}

// The inherited text properties (CSS Fonts 4, CSS Text 3, SVG 2 text.html).
void text_style(const Element& e, const Context& ctx, Inherited& inh, double diagonal) {
  if (const auto f = property<std::vector<std::string>>(e, "font-family", parse_font_family);
      f.state == Prop<std::vector<std::string>>::Set)
    inh.font_family = f.value;
  if (const auto w = property<int>(
          e, "font-weight", [&](std::string_view v) { return parse_font_weight(v, ctx.inh.font_weight); });
      w.state == Prop<int>::Set)
    inh.font_weight = w.value;
  if (const auto it = property<bool>(e, "font-style", parse_font_style);
      it.state == Prop<bool>::Set)
    inh.font_italic = it.value;
  if (const auto fs = property<int>(e, "font-stretch", parse_font_stretch);
      fs.state == Prop<int>::Set)
    inh.font_stretch = fs.value;
  if (const auto a = property<Inherited::Anchor>(e, "text-anchor", [](std::string_view v) {
        const auto k = parse_keyword(v);
        using A = Inherited::Anchor;
        return k == "start" ? std::optional(A::Start) : k == "middle" ? std::optional(A::Middle)
                                                      : k == "end"    ? std::optional(A::End)
                                                                      : std::optional<A>();
      });
      a.state == Prop<Inherited::Anchor>::Set)
    inh.text_anchor = a.value;
  for (const char* name : {"letter-spacing", "word-spacing"}) {
    const auto sp = property<double>(e, name, [&](std::string_view v) -> std::optional<double> {
      if (parse_keyword(v) == "normal") return 0.0;
      const auto l = parse_length(v, CalcOk::Yes);
      if (!l) return std::nullopt;
      // A percentage of the viewport's normalised diagonal, as resvg resolves it.
      return resolve_length(*l, diagonal, inh.font_size, 16);
    });
    if (sp.state == Prop<double>::Set) (name[0] == 'l' ? inh.letter_spacing : inh.word_spacing) = sp.value;
  }
  // writing-mode (SVG 1.1 keywords and CSS Writing Modes 3): vertical or not.
  if (const auto wm = property<bool>(e, "writing-mode", [](std::string_view v) -> std::optional<bool> {
        const auto k = parse_keyword(v);
        if (k == "lr" || k == "lr-tb" || k == "rl" || k == "rl-tb" || k == "horizontal-tb") return false;
        if (k == "tb" || k == "tb-rl" || k == "vertical-rl" || k == "vertical-lr") return true;
        return std::nullopt;
      });
      wm.state == Prop<bool>::Set)
    inh.vertical = wm.value;
  // font-variant: small-caps (the font's smcp feature); font-kerning: none
  // (and SVG 1.1's kerning="0") turns kerning off.
  if (const auto fv = property<bool>(e, "font-variant", [](std::string_view v) -> std::optional<bool> {
        const auto k = parse_keyword(v);
        if (k == "small-caps") return true;
        if (k == "normal") return false;
        return std::nullopt;
      });
      fv.state == Prop<bool>::Set)
    inh.small_caps = fv.value;
  if (const auto fk = property<bool>(e, "font-kerning", [](std::string_view v) -> std::optional<bool> {
        const auto k = parse_keyword(v);
        if (k == "none") return false;
        if (k == "auto" || k == "normal") return true;
        return std::nullopt;
      });
      fk.state == Prop<bool>::Set)
    inh.kerning = fk.value;
  if (const std::string* k = e.attribute("kerning"))
    if (const auto l = parse_length(*k); l && l->value == 0) inh.kerning = false;
  // font-size-adjust: none or a number (the aspect value).
  if (const auto fa = property<double>(e, "font-size-adjust", [](std::string_view v) -> std::optional<double> {
        if (parse_keyword(v) == "none") return 0.0;
        const auto n = parse_number(trim(v));
        if (!n || *n < 0) return std::nullopt;
        return *n;
      });
      fa.state == Prop<double>::Set)
    inh.font_size_adjust = fa.value;
  // font-feature-settings (CSS Fonts 4 §6.12): normal or a comma-separated
  // list of <string> [ <integer [0,∞]> | on | off ]?, the string a
  // four-character tag; the items are kept as written (text/ parses them).
  if (const auto ff = property<std::vector<std::string>>(
          e, "font-feature-settings", [](std::string_view v) -> std::optional<std::vector<std::string>> {
            std::vector<std::string> out;
            if (parse_keyword(v) == "normal") return out;
            for (size_t pos = 0; pos <= v.size();) {
              size_t end = v.find(',', pos);
              if (end == std::string_view::npos) end = v.size();
              const std::string_view item = trim(v.substr(pos, end - pos));
              const size_t close = item.empty() ? 0 : item.find(item[0], 1);
              if (item.empty() || (item[0] != '"' && item[0] != '\'') || close != 5) return std::nullopt;
              for (size_t i = 1; i < 5; i++)
                if (item[i] < 0x20 || item[i] > 0x7e) return std::nullopt;
              const std::string_view rest = trim(item.substr(6));
              if (!rest.empty() && !iequals(rest, "on") && !iequals(rest, "off") &&
                  rest.find_first_not_of("0123456789") != std::string_view::npos)
                return std::nullopt;
              out.emplace_back(item);
              pos = end + 1;
            }
            return out;
          });
      ff.state == Prop<std::vector<std::string>>::Set)
    inh.font_features = ff.value;
  using Variations = std::vector<std::pair<std::string, double>>;
  if (const auto fv = property<Variations>(e, "font-variation-settings", [](std::string_view v) -> std::optional<Variations> {
        Variations out;
        if (parse_keyword(v) == "normal") return out;
        // "'wght' 100, 'wdth' 75": a quoted four-letter tag and a number each.
        for (size_t pos = 0; pos < v.size();) {
          const size_t q = v.find_first_of("'\"", pos);
          if (q == std::string_view::npos) break;
          const size_t close = v.find(v[q], q + 1);
          if (close == std::string_view::npos || close - q - 1 != 4) return std::nullopt;
          const std::string tag(v.substr(q + 1, 4));
          size_t end = v.find(',', close);
          if (end == std::string_view::npos) end = v.size();
          const auto n = parse_number(trim(v.substr(close + 1, end - close - 1)));
          if (!n) return std::nullopt;
          out.emplace_back(tag, *n);
          pos = end + 1;
        }
        return out;
      });
      fv.state == Prop<Variations>::Set)
    inh.font_variations = fv.value;
  if (const auto db = property<Inherited::Baseline>(e, "dominant-baseline", [](std::string_view v) {
        using B = Inherited::Baseline;
        const auto k = parse_keyword(v);
        if (k == "auto" || k == "alphabetic") return std::optional(B::Alphabetic);
        if (k == "middle") return std::optional(B::Middle);
        if (k == "central") return std::optional(B::Central);
        if (k == "hanging") return std::optional(B::Hanging);
        if (k == "mathematical") return std::optional(B::Mathematical);
        if (k == "text-before-edge" || k == "text-top") return std::optional(B::TextTop);
        if (k == "text-after-edge" || k == "text-bottom") return std::optional(B::TextBottom);
        if (k == "ideographic") return std::optional(B::Ideographic);
        return std::optional<B>();
      });
      db.state == Prop<Inherited::Baseline>::Set)
    inh.dominant_baseline = db.value;
  // White space: the white-space property (CSS Text 3; inherited) over
  // the xml:space attribute, which SVG 2 text.html#WhiteSpace maps to it in
  // the user agent's sheet, below any author declaration. pre, pre-wrap
  // and break-spaces keep spaces as xml:space="preserve" does (newlines
  // and tabs become spaces: without wrapping there are no line breaks);
  // normal and nowrap collapse them; pre-line is not supported (warned).
  const auto ws = property<bool>(e, "white-space", [](std::string_view v) -> std::optional<bool> {
    const auto k = parse_keyword(v);
    if (k == "pre" || k == "pre-wrap" || k == "break-spaces") return true;
    if (k == "normal" || k == "nowrap") return false;
    return std::nullopt;
  });
  const std::string* xs = e.attribute("xml:space");
  if (ws.state == Prop<bool>::Set)
    inh.space_preserve = ws.value;
  else if (ws.state == Prop<bool>::Inherit)
    inh.space_preserve = ctx.inh.space_preserve;
  else if (ws.state == Prop<bool>::Initial)
    inh.space_preserve = false;
  else if (xs)
    inh.space_preserve = *xs == "preserve";
}

namespace {

// How mpvg treats a property of the table below.
enum class Support : uint8_t {
  Yes,     // read and applied
  Partly,  // read; a value with a word outside `quiet` is not supported (warned)
  No,      // ignored; warned unless every word of its value is in `quiet`
  Moot,    // ignored without a warning: it cannot change a static drawing,
           // or only through a property that is warned itself
};

// Whether the attribute of the property's name is read as a declaration.
enum class Attr : uint8_t {
  Yes,     // a presentation attribute (SVG 2 styling.html#PresentationAttributes;
           // mask-type by CSS Masking 1 §7.3; clip as in SVG 1.1)
  No,      // none: the attribute is ignored, as browsers ignore it
  Legacy,  // none in SVG 2 (browsers ignore it), yet read as one: tests rely on it
};

const Inherited kInitial{};

using Reset = void (*)(Inherited&);

struct PropertyRow {
  const char* name;
  Support support;
  Attr attr;
  // Space-separated lower-case words: for No, the values that change
  // nothing (the initial one and its equivalents; "0": a zero length);
  // for Partly, the supported ones.
  const char* quiet;
  // Inherited properties that mpvg applies: their initial value, for the
  // keyword "initial" (CSS Cascade 4 §7.3.1); null for the others.
  Reset reset;
};

// Every property of SVG 2's property index (propidx.html), with the CSS
// longhands it names (CSS Masking 1 mask-*, CSS Fonts 4 font-variant-*,
// CSS Text Decoration 3) and the geometry properties. Where each is
// applied: svg_style.cpp unless noted.
// clang-format off
const PropertyRow kProperties[] = {
    {"alignment-baseline", Support::Yes, Attr::Yes, nullptr, nullptr},  // svg_text.cpp
    {"baseline-shift", Support::Yes, Attr::Yes, nullptr, nullptr},      // svg_text.cpp
    {"clip", Support::No, Attr::Yes, "auto", nullptr},  // rect() on viewports: deprecated (CSS Masking 1 §5.1)
    {"clip-path", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"clip-rule", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.clip_rule = kInitial.clip_rule; }},
    {"color", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.color = kInitial.color; }},
    {"color-interpolation", Support::Yes, Attr::Yes, nullptr, nullptr},          // gradients: svg_paint_servers.cpp
    {"color-interpolation-filters", Support::Yes, Attr::Yes, nullptr, nullptr},  // svg_filters.cpp
    {"color-rendering", Support::Moot, Attr::Yes, nullptr, nullptr},  // a speed hint: colours are exact anyway
    {"cursor", Support::Moot, Attr::Yes, nullptr, nullptr},           // interactive only
    {"cx", Support::Yes, Attr::Yes, nullptr, nullptr},  // geometry: svg_parser.cpp, svg_basic_shapes.cpp
    {"cy", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"d", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"direction", Support::No, Attr::Yes, "ltr", nullptr},  // bidi runs take their direction from the text
    {"display", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"dominant-baseline", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.dominant_baseline = kInitial.dominant_baseline; }},
    {"fill", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.fill = kInitial.fill; }},
    {"fill-opacity", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.fill_opacity = kInitial.fill_opacity; }},
    {"fill-rule", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.fill_rule = kInitial.fill_rule; }},
    {"filter", Support::Yes, Attr::Yes, nullptr, nullptr},          // svg_filters.cpp
    {"flood-color", Support::Yes, Attr::Yes, nullptr, nullptr},     // svg_filters.cpp
    {"flood-opacity", Support::Yes, Attr::Yes, nullptr, nullptr},   // svg_filters.cpp
    // font: declarations come split into longhands (svg_css.cpp); the
    // attribute is read for tests/test_svg_text.cpp.
    {"font", Support::Yes, Attr::Legacy, nullptr, nullptr},
    {"font-family", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.font_family = kInitial.font_family; }},
    {"font-feature-settings", Support::Yes, Attr::No, nullptr,
     [](Inherited& i) { i.font_features = kInitial.font_features; }},
    {"font-kerning", Support::Yes, Attr::No, nullptr, [](Inherited& i) { i.kerning = kInitial.kerning; }},
    {"font-size", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.font_size = kInitial.font_size; }},
    {"font-size-adjust", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.font_size_adjust = kInitial.font_size_adjust; }},
    {"font-stretch", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.font_stretch = kInitial.font_stretch; }},
    {"font-style", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.font_italic = kInitial.font_italic; }},
    {"font-variant", Support::Partly, Attr::Yes, "normal small-caps",
     [](Inherited& i) { i.small_caps = kInitial.small_caps; }},
    {"font-variant-alternates", Support::No, Attr::No, "normal", nullptr},
    {"font-variant-caps", Support::No, Attr::No, "normal", nullptr},
    {"font-variant-east-asian", Support::No, Attr::No, "normal", nullptr},
    {"font-variant-emoji", Support::No, Attr::No, "normal", nullptr},
    {"font-variant-ligatures", Support::No, Attr::No, "normal", nullptr},
    {"font-variant-numeric", Support::No, Attr::No, "normal", nullptr},
    {"font-variant-position", Support::No, Attr::No, "normal", nullptr},
    // Not in SVG 2's index (CSS Fonts 4); the attribute is read for
    // testdata/golden-text/variable_weight.svg.
    {"font-variation-settings", Support::Yes, Attr::Legacy, nullptr,
     [](Inherited& i) { i.font_variations = kInitial.font_variations; }},
    {"font-weight", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.font_weight = kInitial.font_weight; }},
    {"glyph-orientation-vertical", Support::No, Attr::Yes, "auto", nullptr},
    {"height", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"image-rendering", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.image_rendering = kInitial.image_rendering; }},
    {"inline-size", Support::No, Attr::No, "0 auto", nullptr},  // auto-wrapped text
    {"isolation", Support::Yes, Attr::No, nullptr, nullptr},     // svg_masks.cpp
    {"letter-spacing", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.letter_spacing = kInitial.letter_spacing; }},
    {"lighting-color", Support::Yes, Attr::Yes, nullptr, nullptr},  // svg_filters.cpp
    {"line-height", Support::Moot, Attr::No, nullptr, nullptr},  // spaces the lines of wrapped text only
    {"marker", Support::Yes, Attr::No, nullptr, nullptr},        // split into longhands (svg_css.cpp)
    {"marker-end", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.marker_end = kInitial.marker_end; }},
    {"marker-mid", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.marker_mid = kInitial.marker_mid; }},
    {"marker-start", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.marker_start = kInitial.marker_start; }},
    {"mask", Support::Yes, Attr::Yes, nullptr, nullptr},  // url(#mask) (svg_masks.cpp warns about the rest)
    // Mask borders, and the mask layers' images: not supported. The other
    // mask-* longhands size, place, clip and combine mask images only.
    {"mask-border", Support::No, Attr::No, "none", nullptr},
    {"mask-border-mode", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-border-outset", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-border-repeat", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-border-slice", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-border-source", Support::No, Attr::No, "none", nullptr},
    {"mask-border-width", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-clip", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-composite", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-image", Support::No, Attr::No, "none", nullptr},
    {"mask-mode", Support::No, Attr::No, "match-source", nullptr},  // it would override mask-type
    {"mask-origin", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-position", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-repeat", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-size", Support::Moot, Attr::No, nullptr, nullptr},
    {"mask-type", Support::Yes, Attr::Yes, nullptr, nullptr},  // svg_masks.cpp
    // svg_masks.cpp; the attribute is read for tests/test_svg_masks.cpp.
    {"mix-blend-mode", Support::Yes, Attr::Legacy, nullptr, nullptr},
    {"opacity", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"overflow", Support::Yes, Attr::Yes, nullptr, nullptr},  // svg_viewports.cpp, svg_markers.cpp
    {"paint-order", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.paint_order = kInitial.paint_order; }},
    {"pointer-events", Support::Moot, Attr::Yes, nullptr, nullptr},  // interactive only
    {"r", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"rx", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"ry", Support::Yes, Attr::Yes, nullptr, nullptr},
    // Text flowed into shapes (SVG 2 text.html#TextShapeInside): only
    // shape-inside starts it; the others shape what it does.
    {"shape-image-threshold", Support::Moot, Attr::No, nullptr, nullptr},
    {"shape-inside", Support::No, Attr::No, "auto none", nullptr},
    {"shape-margin", Support::Moot, Attr::No, nullptr, nullptr},
    {"shape-padding", Support::Moot, Attr::No, nullptr, nullptr},
    {"shape-rendering", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.aliased_shapes = kInitial.aliased_shapes; }},
    {"shape-subtract", Support::Moot, Attr::No, nullptr, nullptr},
    {"stop-color", Support::Yes, Attr::Yes, nullptr, nullptr},    // svg_paint_servers.cpp
    {"stop-opacity", Support::Yes, Attr::Yes, nullptr, nullptr},  // svg_paint_servers.cpp
    {"stroke", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.stroke = kInitial.stroke; }},
    {"stroke-dasharray", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.stroke_dasharray = kInitial.stroke_dasharray; }},
    {"stroke-dashoffset", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.stroke_dashoffset = kInitial.stroke_dashoffset; }},
    {"stroke-linecap", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.stroke_cap = kInitial.stroke_cap; }},
    {"stroke-linejoin", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.stroke_join = kInitial.stroke_join; }},
    {"stroke-miterlimit", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.stroke_miterlimit = kInitial.stroke_miterlimit; }},
    {"stroke-opacity", Support::Yes, Attr::Yes, nullptr,
     [](Inherited& i) { i.stroke_opacity = kInitial.stroke_opacity; }},
    {"stroke-width", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.stroke_width = kInitial.stroke_width; }},
    {"text-anchor", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.text_anchor = kInitial.text_anchor; }},
    {"text-decoration", Support::Partly, Attr::Yes, "none underline overline line-through", nullptr},  // svg_text.cpp
    // SVG paints a decoration with the fill and stroke of the element that
    // declares it (text.html#TextDecorationProperties), not in a colour.
    {"text-decoration-color", Support::Moot, Attr::No, nullptr, nullptr},
    {"text-decoration-line", Support::No, Attr::No, "none", nullptr},
    {"text-decoration-style", Support::No, Attr::No, "solid", nullptr},
    {"text-overflow", Support::Moot, Attr::Yes, nullptr, nullptr},  // wrapped text only (inline-size)
    {"text-rendering", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.aliased_text = kInitial.aliased_text; }},
    {"transform", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"transform-box", Support::Yes, Attr::No, nullptr, nullptr},
    {"transform-origin", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"unicode-bidi", Support::No, Attr::Yes, "normal", nullptr},
    {"vector-effect", Support::Partly, Attr::Yes, "none non-scaling-stroke viewport screen", nullptr},
    {"visibility", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.visible = kInitial.visible; }},
    {"white-space", Support::Partly, Attr::Yes, "normal nowrap pre pre-wrap break-spaces",
     [](Inherited& i) { i.space_preserve = kInitial.space_preserve; }},
    {"width", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"word-spacing", Support::Yes, Attr::Yes, nullptr, [](Inherited& i) { i.word_spacing = kInitial.word_spacing; }},
    {"writing-mode", Support::Partly, Attr::Yes, "horizontal-tb vertical-rl vertical-lr lr lr-tb rl rl-tb tb tb-rl",
     [](Inherited& i) { i.vertical = kInitial.vertical; }},
    {"x", Support::Yes, Attr::Yes, nullptr, nullptr},
    {"y", Support::Yes, Attr::Yes, nullptr, nullptr},
};
// clang-format on

// The rows by name, in an open-addressed table of FNV-1a hashes: the style
// computation looks up every attribute's name and then some (a few dozen
// per element), and std::unordered_map's hash and prime modulo cost more
// than these short names. A name listed twice finds its first row.
const PropertyRow* property_row(std::string_view name) {
  constexpr size_t kSlots = 512;  // a power of two, at least twice the rows
  static_assert(std::size(kProperties) * 2 <= kSlots);
  struct Slot {
    std::string_view name;
    const PropertyRow* row = nullptr;
  };
  auto hash = [](std::string_view s) {
    uint32_t h = 2166136261u;
    for (const char c : s) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
    return size_t(h) & (kSlots - 1);
  };
  static const std::array<Slot, kSlots> slots = [&] {
    std::array<Slot, kSlots> t{};
    for (const PropertyRow& r : kProperties) {
      size_t i = hash(r.name);
      while (t[i].row) i = (i + 1) & (kSlots - 1);
      t[i] = {r.name, &r};
    }
    return t;
  }();
  for (size_t i = hash(name); slots[i].row; i = (i + 1) & (kSlots - 1))
    if (slots[i].name == name) return slots[i].row;
  return nullptr;
}

bool css_wide_keyword(std::string_view v) {
  for (const char* k : {"inherit", "initial", "unset", "revert", "revert-layer"})
    if (iequals(v, k)) return true;
  return false;
}

// The first word of `value` that is not one of `quiet`'s (case-insensitive;
// "0" in quiet takes any zero length); empty when there is none.
std::string unquiet_word(std::string_view value, const char* quiet) {
  value = trim(value);
  if (css_wide_keyword(value)) return {};
  for (size_t pos = 0; pos < value.size();) {
    const size_t b = value.find_first_not_of(" \t\n\r\f", pos);
    if (b == std::string_view::npos) break;
    size_t end = value.find_first_of(" \t\n\r\f", b);
    if (end == std::string_view::npos) end = value.size();
    const std::string_view word = value.substr(b, end - b);
    bool found = false;
    for (std::string_view q = quiet ? quiet : ""; !q.empty() && !found;) {
      const size_t sp = q.find(' ');
      const std::string_view k = q.substr(0, sp);
      const auto l = k == "0" ? parse_length(word) : std::nullopt;
      found = iequals(word, k) || (l && l->value == 0 && l->unit != Unit::Calc);
      q = sp == std::string_view::npos ? std::string_view() : q.substr(sp + 1);
    }
    if (!found) return std::string(word);
    pos = end;
  }
  return {};
}

}  // namespace

bool presentation_attribute(std::string_view name) {
  const PropertyRow* r = property_row(name);
  return !r || r->attr != Attr::No;
}

bool value_valid(std::string_view name, std::string_view value, bool attribute) {
  // Properties whose value is one keyword, which the files that read them
  // take as any word (svg_masks.cpp, svg_viewports.cpp): another word is
  // an invalid declaration, dropped.
  static const std::pair<const char*, const char*> keywords[] = {
      {"mask-type", "luminance alpha"},
      {"overflow", "visible hidden scroll auto clip"},
  };
  for (const auto& [n, k] : keywords)
    if (name == n) return unquiet_word(value, k).empty() && !trim(value).empty() && parse_keyword(value);
  // Sizes that CSS makes non-negative (SVG 2 geometry.html): a negative
  // one in a declaration is invalid; a negative attribute keeps SVG's
  // error handling (the element is not rendered), where svg_parser.cpp
  // and svg_basic_shapes.cpp read it.
  if (!attribute && (name == "width" || name == "height" || name == "r" || name == "rx" || name == "ry"))
    if (const auto l = parse_length(value); l && l->value < 0) return false;
  return true;
}

// "initial" on an inherited property: its initial value instead of the
// parent's (the non-inherited ones start from their initial values anyway).
void reset_initial(const Element& e, Inherited& inh) {
  // Most elements have no "initial" at all: one scan decides.
  bool any = false;
  for (const auto& [k, v] : e.declarations) any = any || iequals(trim(v), "initial");
  for (const auto& [k, v] : e.attributes) any = any || iequals(trim(v), "initial");
  if (!any) return;
  for (const PropertyRow& r : kProperties)
    if (r.reset &&
        property<int>(e, r.name, [](std::string_view) { return std::optional<int>(); }).state == Prop<int>::Initial)
      r.reset(inh);
}

void Converter::warn_unsupported_properties() {
  s_.properties_checked = true;
  auto check = [&](const std::string& name, const std::string& value, bool attribute) {
    const PropertyRow* r = property_row(name);
    if (!r || (attribute && r->attr == Attr::No)) return;
    if (r->support == Support::No && !unquiet_word(value, r->quiet).empty())
      warn("property '" + name + "' is not supported: ignored");
    if (r->support == Support::Partly)
      if (const std::string w = unquiet_word(value, r->quiet); !w.empty())
        warn("property '" + name + "' value '" + w + "' is not supported: ignored");
  };
  std::vector<const Element*> stack{s_.doc.root.get()};
  while (!stack.empty()) {
    const Element* e = stack.back();
    stack.pop_back();
    if (!e) continue;
    for (const auto& [name, value] : e->attributes) check(name, value, true);
    for (const auto& [name, value] : e->declarations) check(name, value, false);
    for (auto it = e->children.rbegin(); it != e->children.rend(); ++it) stack.push_back(it->get());
  }
}

Style Converter::compute_style(const Element& e, const Context& ctx) {
  if (!s_.properties_checked) warn_unsupported_properties();
  Style st(ctx.inh);
  Inherited& inh = st.inh;
  reset_initial(e, inh);

  // color first: currentColor in fill refers to this element's color.
  const auto color = property<RGBA>(e, "color", [&](std::string_view v) -> std::optional<RGBA> {
    if (iequals(trim(v), "currentColor")) return ctx.inh.color;  // CSS Color 4: acts as inherit
    return parse_color(v);
  });
  if (color.state == Prop<RGBA>::Set) inh.color = color.value;
  // An inherited currentColor paint is the keyword, not the parent's
  // colour (CSS Color 4 §6.4; Chromium and librsvg agree): it takes this
  // element's color.
  if (inh.fill.current_color) inh.fill.color = inh.color;
  if (inh.stroke.current_color) inh.stroke.color = inh.color;
  // font-size before any length: em units refer to it. Relative values
  // (em, ex, %, larger, smaller) are relative to the parent's font size.
  const double parent_em = ctx.inh.font_size;
  // The font attribute first (declarations of the shorthand come split
  // into longhands); the longhands (here and in text_style) override it.
  if (const auto f = property<FontShorthand>(
          e, "font", [&](std::string_view v) { return parse_font_shorthand(v, ctx.inh); });
      f.state == Prop<FontShorthand>::Set) {
    inh.font_size = f.value.size;
    inh.font_family = f.value.family;
    inh.font_weight = f.value.weight;
    inh.font_italic = f.value.italic;
    inh.font_stretch = f.value.stretch;
    inh.small_caps = f.value.small_caps;
  }
  const auto font_size = property<double>(
      e, "font-size", [&](std::string_view v) -> std::optional<double> {
        // rem: of the root's font size (on the root itself, of the initial 16px).
        return parse_font_size(v, parent_em, e.parent ? s_.root_em : 16);
      });
  if (font_size.state == Prop<double>::Set) inh.font_size = font_size.value;
  if (!e.parent) s_.root_em = inh.font_size;

  if (!ctx.in_clip) {
    // Inside a clipPath only geometry counts (CSS Masking 1, the clipPath
    // element): fill is moot.
    const auto fill = property<PaintValue>(e, "fill", parse_paint);
    if (fill.state == Prop<PaintValue>::Set) inh.fill = resolve_paint(fill.value, inh.color, "fill");
    stroke_style(e, inh, st);
    // filter (Filter Effects 1, not inherited): a clipPath's content
    // ignores it (CSS Masking 1, the clipPath element), so it is read only
    // here; svg_filters.cpp parses the value.
    const auto filter = property<std::string>(
        e, "filter", [](std::string_view v) { return std::optional<std::string>(std::string(trim(v))); });
    st.filter = filter.state == Prop<std::string>::Set       ? filter.value
                : filter.state == Prop<std::string>::Inherit ? ctx.parent_filter
                                                             : std::string();
    // Markers (inherited): none or a url. The marker shorthand, from style
    // sheets and the style attribute only (it is not a presentation
    // attribute), comes split into the three (svg_css.cpp).
    auto marker_value = [](std::string_view v) -> std::optional<std::string> {
      if (parse_keyword(v) == "none") return std::string();
      Scanner sc(v);
      bool external = false;
      if (!parse_func_iri(sc, &external)) return std::nullopt;
      sc.skip_ws();
      if (!sc.at_end()) return std::nullopt;
      return std::string(trim(v));
    };
    std::string* slots[] = {&inh.marker_start, &inh.marker_mid, &inh.marker_end};
    const char* names[] = {"marker-start", "marker-mid", "marker-end"};
    for (int i = 0; i < 3; i++)
      if (const auto m = property<std::string>(e, names[i], marker_value); m.state == Prop<std::string>::Set)
        *slots[i] = m.value;
  }
  if (const auto r = property<FillRule>(e, "fill-rule", parse_fill_rule); r.state == Prop<FillRule>::Set)
    inh.fill_rule = r.value;
  if (const auto o = property<double>(e, "fill-opacity", parse_alpha); o.state == Prop<double>::Set)
    inh.fill_opacity = o.value;
  if (const auto r = property<FillRule>(e, "clip-rule", parse_fill_rule); r.state == Prop<FillRule>::Set)
    inh.clip_rule = r.value;
  const auto vis =
      property<std::string>(e, "visibility", [](std::string_view v) -> std::optional<std::string> {
        auto k = parse_keyword(v);
        if (k && (*k == "visible" || *k == "hidden" || *k == "collapse")) return k;
        return std::nullopt;
      });
  if (vis.state == Prop<std::string>::Set) inh.visible = vis.value == "visible";
  if (const auto ir = property<TextureFilter>(e, "image-rendering", parse_image_rendering);
      ir.state == Prop<TextureFilter>::Set)
    inh.image_rendering = ir.value;
  if (const auto r = property<bool>(e, "shape-rendering", [](std::string_view v) { return parse_rendering(v, false); });
      r.state == Prop<bool>::Set)
    inh.aliased_shapes = r.value;
  if (const auto r = property<bool>(e, "text-rendering", [](std::string_view v) { return parse_rendering(v, true); });
      r.state == Prop<bool>::Set)
    inh.aliased_text = r.value;
  text_style(e, ctx, inh, percent_base(Axis::Diagonal));

  // Non-inherited properties.
  const auto opacity = property<double>(e, "opacity", parse_alpha);
  st.opacity = opacity.state == Prop<double>::Set       ? opacity.value
               : opacity.state == Prop<double>::Inherit ? ctx.parent_opacity
                                                        : 1.0;
  // display (CSS Display 3): only none matters here; any other valid
  // value renders, an invalid one is dropped.
  const auto display = property<std::string>(e, "display", [](std::string_view v) -> std::optional<std::string> {
    static const char* const keywords[] = {
        "none",         "contents",        "inline",          "block",        "run-in",           "flow",
        "flow-root",    "table",           "flex",            "grid",         "ruby",             "list-item",
        "inline-block", "inline-table",    "inline-flex",     "inline-grid",  "table-row-group",  "table-row",
        "table-cell",   "table-caption",   "table-column",    "table-column-group", "table-header-group",
        "table-footer-group", "ruby-base", "ruby-text",       "ruby-base-container", "ruby-text-container"};
    std::string k;  // the words in lower case, one space apart
    int n = 0;
    for (size_t pos = 0; pos < v.size();) {
      const size_t b = v.find_first_not_of(" \t\n\r\f", pos);
      if (b == std::string_view::npos) break;
      size_t end = v.find_first_of(" \t\n\r\f", b);
      if (end == std::string_view::npos) end = v.size();
      const std::string_view w = v.substr(b, end - b);
      if (std::none_of(std::begin(keywords), std::end(keywords), [&](const char* kw) { return iequals(w, kw); }))
        return std::nullopt;
      if (n++ > 0) k += ' ';
      for (char c : w) k += ascii_lower(c);
      pos = end;
    }
    // One keyword, or an outer and an inner display ("block flow", "inline flow-root list-item").
    if (n == 0 || n > 3 || (n > 1 && k.find("none") != std::string::npos)) return std::nullopt;
    return k;
  });
  st.display_none = display.state == Prop<std::string>::Set       ? display.value == "none"
                    : display.state == Prop<std::string>::Inherit ? ctx.parent_display_none
                                                                  : false;
  // A basic shape or reference box that does not parse makes the
  // declaration invalid (CSS Masking 1 §3.1), so that the next one applies.
  const auto clip = property<std::string>(e, "clip-path", [](std::string_view v) -> std::optional<std::string> {
    bool invalid = false;
    parse_clip_shape(v, &invalid);
    if (invalid) return std::nullopt;
    return std::string(trim(v));
  });
  st.clip_path = clip.state == Prop<std::string>::Set       ? clip.value
                 : clip.state == Prop<std::string>::Inherit ? ctx.parent_clip_path
                                                            : std::string();
  // mask: the CSS Masking 1 §7.1 shorthand. Its grammar is checked word by
  // word (url()s, image functions, the keywords of its longhands, lengths,
  // '/' and ','), so that an invalid value is dropped; svg_masks.cpp draws
  // url(#mask) and warns about the rest.
  const auto mask = property<std::string>(e, "mask", [](std::string_view v) -> std::optional<std::string> {
    static const char* const keywords[] = {
        "none",      "alpha",       "luminance",   "match-source", "repeat",   "repeat-x",  "repeat-y",
        "space",     "round",       "no-repeat",   "left",         "right",    "top",       "bottom",
        "center",    "cover",       "contain",     "auto",         "border-box", "padding-box", "content-box",
        "margin-box", "fill-box",   "stroke-box",  "view-box",     "no-clip",  "add",       "subtract",
        "intersect", "exclude"};
    static const char* const images[] = {"url(", "linear-gradient(", "radial-gradient(", "conic-gradient(",
                                         "repeating-linear-gradient(", "repeating-radial-gradient(",
                                         "repeating-conic-gradient(", "image(", "image-set(", "cross-fade(",
                                         "element(", "paint("};
    const std::string_view t = trim(v);
    if (t.empty()) return std::nullopt;
    for (size_t pos = 0; pos < t.size();) {
      const char c = t[pos];
      if (is_ws(c) || c == '/' || c == ',') {
        pos++;
        continue;
      }
      size_t end = pos;
      int depth = 0;
      while (end < t.size() && (depth > 0 || !(is_ws(t[end]) || t[end] == '/' || t[end] == ','))) {
        if (t[end] == '(') depth++;
        if (t[end] == ')') depth--;
        end++;
      }
      if (depth != 0) return std::nullopt;
      const std::string_view w = t.substr(pos, end - pos);
      const bool ok =
          std::any_of(std::begin(keywords), std::end(keywords), [&](const char* k) { return iequals(w, k); }) ||
          std::any_of(std::begin(images), std::end(images),
                      [&](const char* f) {
                        const size_t n = std::strlen(f);
                        return w.size() > n && iequals(w.substr(0, n), f);
                      }) ||
          parse_length(w, CalcOk::Yes);
      if (!ok) return std::nullopt;
      pos = end;
    }
    return std::string(t);
  });
  st.mask = mask.state == Prop<std::string>::Set       ? mask.value
            : mask.state == Prop<std::string>::Inherit ? ctx.parent_mask
                                                       : std::string();
  if (const auto b = own_property<BlendMode>(e, "mix-blend-mode", parse_blend_mode); b.state == Prop<BlendMode>::Set)
    st.blend = b.value;
  const auto iso = own_property<std::string>(e, "isolation", [](std::string_view v) {
    auto k = parse_keyword(v);
    if (k && (*k == "auto" || *k == "isolate")) return k;
    return std::optional<std::string>();
  });
  st.isolate = iso.state == Prop<std::string>::Set && iso.value == "isolate";
  // transform is a presentation attribute in SVG 2 (CSS Transforms 1); an unparsable
  // value is ignored like any invalid declaration.
  const auto xf = own_property<Affine>(e, "transform", parse_transform);
  if (xf.state == Prop<Affine>::Set) st.transform = with_origin(e, xf.value, inh.font_size);
  // A transform attribute that does not parse, with no declaration over it.
  const std::string* xf_attribute = e.attribute("transform");
  st.transform_invalid = xf.state == Prop<Affine>::Unset && xf_attribute && !parse_transform(*xf_attribute);
  return st;
}

// transform-origin (CSS Transforms 1 §6; not inherited): one or two of
// left | center | right | top | bottom | <length-percentage>, the first
// horizontal unless it is top or bottom; a missing one is center.
// Percentages, keywords and the origin itself are of the reference box
// transform-box names (§5; not inherited): view-box, SVG's default, the
// viewport at the user space's origin; fill-box (and content-box, which
// SVG elements map to it) the element's object bounding box, so that
// without a transform-origin (initially 0 0 for SVG elements) the box's
// top-left corner is the origin. stroke-box and border-box take the fill
// box too (warned): the stroke's box is not known before the stroke is
// made. Shapes, images and groups of them have a box here (object_box);
// other elements take view-box, warned.
std::optional<Vec2> Converter::transform_origin(const Element& e, double em) const {
  const auto tb = own_property<std::string>(e, "transform-box", [](std::string_view v) -> std::optional<std::string> {
    const auto k = parse_keyword(v);
    for (const char* known : {"view-box", "fill-box", "content-box", "stroke-box", "border-box"})
      if (k == known) return k;
    return std::nullopt;
  });
  std::optional<Bounds> box;
  if (tb.state == Prop<std::string>::Set && tb.value != "view-box") {
    if (tb.value == "stroke-box" || tb.value == "border-box")
      warn("transform-box " + tb.value + " is taken as fill-box");
    box = object_box(e, em);
    if (!box) warn("transform-box " + tb.value + " on <" + e.name + "> is taken as view-box");
  }
  const auto o = own_property<std::pair<std::string, std::string>>(
      e, "transform-origin", [](std::string_view v) -> std::optional<std::pair<std::string, std::string>> {
        std::vector<std::string> words;
        for (size_t pos = 0; pos < v.size();) {
          const size_t b = v.find_first_not_of(" \t\n\r,", pos);
          if (b == std::string_view::npos) break;
          size_t end = v.find_first_of(" \t\n\r,", b);
          if (end == std::string_view::npos) end = v.size();
          std::string w(v.substr(b, end - b));
          for (char& c : w) c = ascii_lower(c);
          words.push_back(std::move(w));
          pos = end;
        }
        if (words.empty() || words.size() > 3) return std::nullopt;
        auto is = [](const std::string& w, std::initializer_list<const char*> ks) {
          return std::any_of(ks.begin(), ks.end(), [&](const char* k) { return w == k; });
        };
        for (size_t i = 0; i < words.size(); i++) {
          const auto l = parse_length(words[i], CalcOk::Yes);
          // The third value, z, is a length (and moves nothing in 2D).
          const bool ok = i < 2 ? l || is(words[i], {"left", "center", "right", "top", "bottom"})
                                : l && l->unit != Unit::Percent;
          if (!ok) return std::nullopt;
        }
        if (words.size() == 1) words.push_back("center");
        // "top left": vertical keyword first.
        if (is(words[0], {"top", "bottom"}) || is(words[1], {"left", "right"})) std::swap(words[0], words[1]);
        if (is(words[0], {"top", "bottom"}) || is(words[1], {"left", "right"})) return std::nullopt;  // "left right"
        return std::pair(words[0], words[1]);
      });
  if (o.state != Prop<std::pair<std::string, std::string>>::Set) {
    if (box) return Vec2{box->x0, box->y0};  // 0 0 of the box
    return std::nullopt;
  }
  auto resolve = [&](const std::string& w, Axis axis) -> std::optional<double> {
    const double start = box ? (axis == Axis::X ? box->x0 : box->y0) : 0.0;
    const double base = box ? (axis == Axis::X ? box->x1 - box->x0 : box->y1 - box->y0) : percent_base(axis);
    if (w == "center") return start + base / 2;
    if (w == (axis == Axis::X ? "left" : "top")) return start;
    if (w == (axis == Axis::X ? "right" : "bottom")) return start + base;
    const auto l = parse_length(w, CalcOk::Yes);
    if (!l) return std::nullopt;
    if (box && l->unit == Unit::Percent) return start + l->value / 100 * base;
    return start + to_user(*l, axis, em);
  };
  const auto x = resolve(o.value.first, Axis::X), y = resolve(o.value.second, Axis::Y);
  if (!x || !y) return std::nullopt;
  return Vec2{*x, *y};
}

// The object bounding box of e in its own user space (before its
// transform; SVG 2 coords.html#BoundingBoxes): a shape's geometry, an
// image's rectangle, a group's (g, a) rendered children each under its own
// transform, tight for their curves. nullopt for other elements and for
// groups that hold text, use or nested viewports, whose boxes are not
// known before they are converted. A shape without geometry, or a group
// of nothing, has an empty box at the origin.
std::optional<Bounds> Converter::object_box(const Element& e, double em) const {
  Bounds b;
  if (!add_object_bounds(e, Affine{}, em, b, 0)) return std::nullopt;
  if (b.empty()) return Bounds{0, 0, 0, 0};
  return b;
}

bool Converter::add_object_bounds(const Element& e, const Affine& xf, double em, Bounds& b, int depth) const {
  const Kind kind = classify(e);
  if (kind == Kind::Image) {
    const double x = length(e, "x", Axis::X, 0, em), y = length(e, "y", Axis::Y, 0, em);
    const double w = length(e, "width", Axis::X, 0, em), h = length(e, "height", Axis::Y, 0, em);
    for (const Vec2 c : {Vec2{x, y}, Vec2{x + w, y}, Vec2{x, y + h}, Vec2{x + w, y + h}}) b.add(xf.apply(c));
    return true;
  }
  if (kind == Kind::Shape) {
    if (const std::optional<Path> p = build_shape(e, em, nullptr)) add_path_bounds(*p, xf, b);
    return true;
  }
  if (kind != Kind::Container || (e.name != "g" && e.name != "a") || depth > kMaxBoxDepth) return false;
  for (const auto& child : e.children) {
    const Kind k = classify(*child);
    if (k == Kind::Ignored) continue;
    const auto display = property<std::string>(*child, "display", parse_keyword);
    if (display.state == Prop<std::string>::Set && display.value == "none") continue;
    Affine t;
    if (const auto ct = property<Affine>(*child, "transform", parse_transform); ct.state == Prop<Affine>::Set)
      t = with_origin(*child, ct.value, em);
    if (!add_object_bounds(*child, xf * t, em, b, depth + 1)) return false;
  }
  return true;
}

Affine Converter::with_origin(const Element& e, const Affine& t, double em) const {
  const auto o = transform_origin(e, em);
  if (!o) return t;
  return Affine::translate(o->x, o->y) * t * Affine::translate(-o->x, -o->y);
}

// The stroke properties of `e` (SVG 2 painting.html#StrokeProperties),
// over the inherited values in `inh`. Invalid values are ignored like any
// invalid declaration: a negative width or dash, a miter limit below 1.
void Converter::stroke_style(const Element& e, Inherited& inh, Style& st) {
  const auto stroke = property<PaintValue>(e, "stroke", parse_paint);
  if (stroke.state == Prop<PaintValue>::Set)
    inh.stroke = resolve_paint(stroke.value, inh.color, "stroke");
  if (const auto o = property<double>(e, "stroke-opacity", parse_alpha); o.state == Prop<double>::Set)
    inh.stroke_opacity = o.value;
  // Lengths that are neither horizontal nor vertical: percentages of the
  // normalised viewport diagonal (SVG 2 coords.html#Units).
  auto user_length = [&](std::string_view v) -> std::optional<double> {
    const auto l = parse_length(v, CalcOk::Yes);
    if (!l) return std::nullopt;
    return to_user(*l, Axis::Diagonal, inh.font_size);
  };
  const auto width = property<double>(e, "stroke-width", [&](std::string_view v) -> std::optional<double> {
    const auto w = user_length(v);
    if (!w || *w < 0) return std::nullopt;
    return w;
  });
  if (width.state == Prop<double>::Set) inh.stroke_width = width.value;
  const auto join = property<LineJoin>(e, "stroke-linejoin", [](std::string_view v) {
    std::optional<LineJoin> none;
    const auto k = parse_keyword(v);
    if (!k) return none;
    if (*k == "miter") return std::optional(LineJoin::Miter);
    if (*k == "miter-clip") return std::optional(LineJoin::MiterClip);
    if (*k == "round") return std::optional(LineJoin::Round);
    if (*k == "bevel") return std::optional(LineJoin::Bevel);
    if (*k == "arcs") return std::optional(LineJoin::Arcs);
    return none;
  });
  if (join.state == Prop<LineJoin>::Set) inh.stroke_join = join.value;
  const auto cap = property<LineCap>(e, "stroke-linecap", [](std::string_view v) -> std::optional<LineCap> {
    const auto k = parse_keyword(v);
    if (!k) return std::nullopt;
    if (*k == "butt") return LineCap::Butt;
    if (*k == "round") return LineCap::Round;
    if (*k == "square") return LineCap::Square;
    return std::nullopt;
  });
  if (cap.state == Prop<LineCap>::Set) inh.stroke_cap = cap.value;
  // A <number> of at least 1 (SVG 2 painting.html#StrokeMiterlimitProperty); "5mm" is not one.
  const auto ml = property<double>(e, "stroke-miterlimit", [](std::string_view v) -> std::optional<double> {
    const auto n = parse_number(v);
    if (!n || *n < 1) return std::nullopt;
    return n;
  });
  if (ml.state == Prop<double>::Set) inh.stroke_miterlimit = ml.value;
  const auto dashes = property<std::vector<double>>(e, "stroke-dasharray", [&](std::string_view v) {
    return parse_dasharray(v, user_length);
  });
  if (dashes.state == Prop<std::vector<double>>::Set) inh.stroke_dasharray = dashes.value;
  if (const auto o = property<double>(e, "stroke-dashoffset", user_length); o.state == Prop<double>::Set)
    inh.stroke_dashoffset = o.value;
  if (const auto po = property<PaintOrder>(e, "paint-order", parse_paint_order); po.state == Prop<PaintOrder>::Set)
    inh.paint_order = po.value;
  // vector-effect is not inherited (SVG 2 coords.html#VectorEffects):
  // none | [ non-scaling-stroke | non-scaling-size | non-rotation |
  // fixed-position ]+ [ viewport | screen ]?; of these only
  // non-scaling-stroke is drawn (the others are warned about).
  const auto ve = own_property<bool>(e, "vector-effect", [](std::string_view v) -> std::optional<bool> {
    if (parse_keyword(v) == "none") return false;
    bool nss = false, any = false, space = false;
    Scanner sc(trim(v));
    while (!sc.at_end()) {
      const auto k = parse_keyword(sc.word());
      if (!k || space) return std::nullopt;  // the space keyword comes last
      if (*k == "viewport" || *k == "screen") {
        space = true;
      } else if (*k == "non-scaling-stroke" || *k == "non-scaling-size" || *k == "non-rotation" ||
                 *k == "fixed-position") {
        nss = nss || *k == "non-scaling-stroke";
        any = true;
      } else {
        return std::nullopt;
      }
      sc.skip_ws();
    }
    if (!any) return std::nullopt;
    return nss;
  });
  st.non_scaling_stroke = ve.state == Prop<bool>::Set && ve.value;
}

// Resolves a fill or stroke paint (SVG 2 painting.html#SpecifyingPaint);
// `current` is the element's color, for currentColor. `what` names the
// property in warnings. A reference to a linearGradient, radialGradient or
// pattern stays a reference (PaintSpec::Server) with its fallback.
PaintSpec Converter::resolve_paint(const PaintValue& p, const RGBA& current, const std::string& what) {
  switch (p.kind) {
    case PaintValue::Kind::None: return {};
    case PaintValue::Kind::Color: return PaintSpec::solid(p.color);
    case PaintValue::Kind::CurrentColor: {
      PaintSpec c = PaintSpec::solid(current);
      c.current_color = true;
      return c;
    }
    case PaintValue::Kind::Context: {
      // The context element's paint (none without one), keeping its user
      // space and box for a paint server.
      if (context_ < 0) return {};
      PaintSpec c = p.context_stroke ? contexts_[context_].stroke : contexts_[context_].fill;
      if (c.kind == PaintSpec::Kind::Server) c.context = context_;
      c.current_color = false;  // the context element's colour, resolved there
      return c;
    }
    case PaintValue::Kind::Url: break;
  }
  // A missing or unusable paint server uses the fallback, and without one
  // paints nothing (SVG 2 painting.html#SpecifyingPaint).
  PaintSpec fallback;
  if (p.fallback == PaintValue::Fallback::Color) fallback = PaintSpec::solid(p.fallback_color);
  if (p.fallback == PaintValue::Fallback::CurrentColor) {
    fallback = PaintSpec::solid(current);
    fallback.current_color = true;
  }
  if (p.url_external) {
    warn("references to other documents are not supported: " + what + " falls back");
    return fallback;
  }
  const Element* target = find(p.url);
  if (!target) return fallback;
  if (!is_paint_server(target->name)) {
    // A reference to an element that cannot paint: the paint is not
    // rendered, fallback or not (as resvg does).
    return {};
  }
  if (target->name != "linearGradient" && target->name != "radialGradient" && target->name != "pattern") {
    warn("<" + target->name + "> paint servers are not supported: " + what +
         (fallback.kind == PaintSpec::Kind::Color ? " painted with the fallback colour" : " not rendered"));
    return fallback;
  }
  PaintSpec server;
  server.kind = PaintSpec::Kind::Server;
  server.server = target;
  server.fallback = fallback.kind == PaintSpec::Kind::Color;
  server.color = fallback.color;
  server.current_color = fallback.current_color;
  return server;
}

Context Converter::document_context(const Element& e, bool in_clip) {
  Context ctx;
  ctx.in_clip = in_clip;
  std::vector<const Element*> chain;
  for (const Element* a = e.parent; a; a = a->parent) chain.push_back(a);
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) ctx = child_context(compute_style(**it, ctx), {}, in_clip);
  return ctx;
}

Context Converter::child_context(const Style& st, const Affine& space, bool in_clip) const {
  Context c(st.inh);
  c.ctm = space;
  c.parent_opacity = st.opacity;
  c.parent_clip_path = st.clip_path;
  c.parent_mask = st.mask;
  c.parent_filter = st.filter;
  c.parent_display_none = st.display_none;
  c.in_clip = in_clip;
  return c;
}

}  // namespace mpvg::svg::detail
