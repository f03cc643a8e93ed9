// Computed style (CSS Cascade 4 as SVG 2 styling.html uses it): properties
// from presentation attributes and style declarations, inheritance, and the
// fill and stroke paint values.
#include <algorithm>
#include <cmath>

#include <charconv>
#include <cmath>

#include "parsers/svg/svg_converter.h"

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

std::optional<bool> parse_font_style(std::string_view v) {
  const auto k = parse_keyword(v);
  if (k == "normal") return false;
  if (k == "italic" || k == "oblique") return true;
  return std::nullopt;
}

std::optional<int> parse_font_stretch(std::string_view v) {
  static const char* names[] = {"ultra-condensed", "extra-condensed", "condensed", "semi-condensed", "normal",
                                "semi-expanded",   "expanded",        "extra-expanded", "ultra-expanded"};
  const auto k = parse_keyword(v);
  for (int i = 0; i < 9; i++)
    if (k == names[i]) return i + 1;
  return std::nullopt;
}

// The font shorthand (CSS Fonts 4 §2.9): [ style || variant || weight ||
// stretch ]? size [ / line-height ]? family; what it leaves out is reset to
// its initial value.
struct FontShorthand {
  bool italic = false, small_caps = false;
  int weight = 400, stretch = 5;
  double size = 16;
  std::vector<std::string> family;
};

std::optional<FontShorthand> parse_font_shorthand(std::string_view v, const Inherited& parent) {
  FontShorthand f;
  v = trim(v);
  for (size_t pos = 0; pos < v.size();) {
    const size_t b = v.find_first_not_of(" \t\n\r", pos);
    if (b == std::string_view::npos) return std::nullopt;
    size_t end = v.find_first_of(" \t\n\r", b);
    if (end == std::string_view::npos) end = v.size();
    const std::string_view word = v.substr(b, end - b);
    const size_t slash = word.find('/');
    // The first word that is a size ends the prefix; the family follows.
    // A plain number is a weight (a size needs a unit there).
    const auto plain = parse_length(word.substr(0, slash));
    const bool number = plain && plain->unit == Unit::None && slash == std::string_view::npos;
    if (const auto size = number ? std::nullopt : parse_font_size(word.substr(0, slash), parent.font_size)) {
      f.size = *size;
      size_t rest = end;
      if (slash == std::string_view::npos) {
        // "12px / 1.5": a line height after a lone slash.
        const size_t n = v.find_first_not_of(" \t\n\r", end);
        if (n != std::string_view::npos && v[n] == '/') {
          const size_t lh = v.find_first_not_of(" \t\n\r", n + 1);
          rest = lh == std::string_view::npos ? v.size() : v.find_first_of(" \t\n\r", lh);
          if (rest == std::string_view::npos) rest = v.size();
        }
      }
      const auto family = parse_font_family(v.substr(std::min(rest, v.size())));
      if (!family) return std::nullopt;
      f.family = *family;
      return f;
    }
    if (iequals(word, "normal")) {
    } else if (const auto st = parse_font_style(word); st) {
      f.italic = *st;
    } else if (iequals(word, "small-caps")) {
      f.small_caps = true;
    } else if (const auto w = parse_font_weight(word, parent.font_weight); w) {
      f.weight = *w;
    } else if (const auto s = parse_font_stretch(word); s) {
      f.stretch = *s;
    } else {
      return std::nullopt;
    }
    pos = end;
  }
  return std::nullopt;
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
  // font-feature-settings: "normal" or a comma-separated list of items.
  if (const auto ff = property<std::vector<std::string>>(
          e, "font-feature-settings", [](std::string_view v) -> std::optional<std::vector<std::string>> {
            std::vector<std::string> out;
            if (parse_keyword(v) == "normal") return out;
            for (size_t pos = 0; pos <= v.size();) {
              size_t end = v.find(',', pos);
              if (end == std::string_view::npos) end = v.size();
              const std::string_view item = trim(v.substr(pos, end - pos));
              if (!item.empty()) out.emplace_back(item);
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
  // xml:space is an attribute, inherited (XML 1.0 §2.10).
  if (const std::string* xs = e.attribute("xml:space")) inh.space_preserve = *xs == "preserve";
}

// "initial" on an inherited property: its initial value instead of the
// parent's (the non-inherited ones start from their initial values anyway).
void reset_initial(const Element& e, Inherited& inh) {
  static const Inherited init;
  using Reset = void (*)(Inherited&);
  static const std::pair<const char*, Reset> resets[] = {
      {"fill", [](Inherited& i) { i.fill = init.fill; }},
      {"fill-rule", [](Inherited& i) { i.fill_rule = init.fill_rule; }},
      {"fill-opacity", [](Inherited& i) { i.fill_opacity = init.fill_opacity; }},
      {"stroke", [](Inherited& i) { i.stroke = init.stroke; }},
      {"stroke-opacity", [](Inherited& i) { i.stroke_opacity = init.stroke_opacity; }},
      {"stroke-width", [](Inherited& i) { i.stroke_width = init.stroke_width; }},
      {"stroke-linejoin", [](Inherited& i) { i.stroke_join = init.stroke_join; }},
      {"stroke-linecap", [](Inherited& i) { i.stroke_cap = init.stroke_cap; }},
      {"stroke-miterlimit", [](Inherited& i) { i.stroke_miterlimit = init.stroke_miterlimit; }},
      {"stroke-dasharray", [](Inherited& i) { i.stroke_dasharray = init.stroke_dasharray; }},
      {"stroke-dashoffset", [](Inherited& i) { i.stroke_dashoffset = init.stroke_dashoffset; }},
      {"paint-order", [](Inherited& i) { i.paint_order = init.paint_order; }},
      {"font-size", [](Inherited& i) { i.font_size = init.font_size; }},
      {"font-family", [](Inherited& i) { i.font_family = init.font_family; }},
      {"font-weight", [](Inherited& i) { i.font_weight = init.font_weight; }},
      {"font-style", [](Inherited& i) { i.font_italic = init.font_italic; }},
      {"font-stretch", [](Inherited& i) { i.font_stretch = init.font_stretch; }},
      {"text-anchor", [](Inherited& i) { i.text_anchor = init.text_anchor; }},
      {"letter-spacing", [](Inherited& i) { i.letter_spacing = init.letter_spacing; }},
      {"word-spacing", [](Inherited& i) { i.word_spacing = init.word_spacing; }},
      {"dominant-baseline", [](Inherited& i) { i.dominant_baseline = init.dominant_baseline; }},
      {"font-variation-settings", [](Inherited& i) { i.font_variations = init.font_variations; }},
      {"writing-mode", [](Inherited& i) { i.vertical = init.vertical; }},
      {"font-variant", [](Inherited& i) { i.small_caps = init.small_caps; }},
      {"font-kerning", [](Inherited& i) { i.kerning = init.kerning; }},
      {"font-feature-settings", [](Inherited& i) { i.font_features = init.font_features; }},
      {"font-size-adjust", [](Inherited& i) { i.font_size_adjust = init.font_size_adjust; }},
      {"marker-start", [](Inherited& i) { i.marker_start = init.marker_start; }},
      {"marker-mid", [](Inherited& i) { i.marker_mid = init.marker_mid; }},
      {"marker-end", [](Inherited& i) { i.marker_end = init.marker_end; }},
      {"clip-rule", [](Inherited& i) { i.clip_rule = init.clip_rule; }},
      {"visibility", [](Inherited& i) { i.visible = init.visible; }},
      {"color", [](Inherited& i) { i.color = init.color; }},
      {"image-rendering", [](Inherited& i) { i.image_rendering = init.image_rendering; }},
      {"shape-rendering", [](Inherited& i) { i.aliased_shapes = init.aliased_shapes; }},
      {"text-rendering", [](Inherited& i) { i.aliased_text = init.aliased_text; }},
  };
  // Most elements have no "initial" at all: one scan decides.
  bool any = false;
  for (const auto& [k, v] : e.declarations) any = any || iequals(trim(v), "initial");
  for (const auto& [k, v] : e.attributes) any = any || iequals(trim(v), "initial");
  if (!any) return;
  for (const auto& [name, reset] : resets)
    if (property<int>(e, name, [](std::string_view) { return std::optional<int>(); }).state == Prop<int>::Initial)
      reset(inh);
}

Style Converter::compute_style(const Element& e, const Context& ctx) {
  Style st;
  st.inh = ctx.inh;
  Inherited& inh = st.inh;
  reset_initial(e, inh);

  // color first: currentColor in fill refers to this element's color.
  const auto color = property<RGBA>(e, "color", [&](std::string_view v) -> std::optional<RGBA> {
    if (iequals(trim(v), "currentColor")) return ctx.inh.color;  // CSS Color 4: acts as inherit
    return parse_color(v);
  });
  if (color.state == Prop<RGBA>::Set) inh.color = color.value;
  // font-size before any length: em units refer to it. Relative values
  // (em, ex, %, larger, smaller) are relative to the parent's font size.
  const double parent_em = ctx.inh.font_size;
  // The font shorthand first; the longhands (here and in text_style)
  // override it.
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
    // Markers (inherited): none or a url; the marker shorthand sets all
    // three, from style sheets and the style attribute only (it is not a
    // presentation attribute).
    auto marker_value = [](std::string_view v) -> std::optional<std::string> {
      if (parse_keyword(v) == "none") return std::string();
      Scanner sc(v);
      bool external = false;
      if (!parse_func_iri(sc, &external)) return std::nullopt;
      return std::string(trim(v));
    };
    for (const auto& [name, value] : e.declarations)
      if (name == "marker")
        if (const auto m = marker_value(value)) inh.marker_start = inh.marker_mid = inh.marker_end = *m;
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
  const auto display = property<std::string>(e, "display", parse_keyword);
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
  const auto mask = property<std::string>(
      e, "mask", [](std::string_view v) { return std::optional<std::string>(std::string(trim(v))); });
  st.mask = mask.state == Prop<std::string>::Set       ? mask.value
            : mask.state == Prop<std::string>::Inherit ? ctx.parent_mask
                                                       : std::string();
  if (const auto b = property<BlendMode>(e, "mix-blend-mode", parse_blend_mode); b.state == Prop<BlendMode>::Set)
    st.blend = b.value;
  const auto iso = property<std::string>(e, "isolation", [](std::string_view v) {
    auto k = parse_keyword(v);
    if (k && (*k == "auto" || *k == "isolate")) return k;
    return std::optional<std::string>();
  });
  st.isolate = iso.state == Prop<std::string>::Set && iso.value == "isolate";
  // transform is a presentation attribute in SVG 2 (CSS Transforms 1); an unparsable
  // value is ignored like any invalid declaration.
  const auto xf = property<Affine>(e, "transform", parse_transform);
  if (xf.state == Prop<Affine>::Set) st.transform = with_origin(e, xf.value, inh.font_size);
  st.transform_invalid = xf.state == Prop<Affine>::Unset && (e.attribute("transform") != nullptr);
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
// made, and only shapes and images have a box here (other elements:
// view-box, warned).
std::optional<Vec2> Converter::transform_origin(const Element& e, double em) const {
  const auto tb = property<std::string>(e, "transform-box", [](std::string_view v) -> std::optional<std::string> {
    const std::string k = std::string(trim(v));
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
  const auto o = property<std::pair<std::string, std::string>>(
      e, "transform-origin", [](std::string_view v) -> std::optional<std::pair<std::string, std::string>> {
        std::vector<std::string> words;
        for (size_t pos = 0; pos < v.size();) {
          const size_t b = v.find_first_not_of(" \t\n\r,", pos);
          if (b == std::string_view::npos) break;
          size_t end = v.find_first_of(" \t\n\r,", b);
          if (end == std::string_view::npos) end = v.size();
          words.emplace_back(v.substr(b, end - b));
          pos = end;
        }
        if (words.empty() || words.size() > 3) return std::nullopt;
        if (words.size() == 1) words.push_back("center");
        // "top left": vertical keyword first.
        if (words[0] == "top" || words[0] == "bottom" || words[1] == "left" || words[1] == "right")
          std::swap(words[0], words[1]);
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

// The object bounding box of a shape or an image in its own user space
// (before its transform); nullopt for other elements. A shape without
// geometry draws nothing, whatever its box: an empty one at the origin.
std::optional<Bounds> Converter::object_box(const Element& e, double em) const {
  const Kind kind = classify(e);
  if (kind == Kind::Image) {
    const double x = length(e, "x", Axis::X, 0, em), y = length(e, "y", Axis::Y, 0, em);
    return Bounds{x, y, x + length(e, "width", Axis::X, 0, em), y + length(e, "height", Axis::Y, 0, em)};
  }
  if (kind != Kind::Shape) return std::nullopt;
  const std::optional<Path> p = build_shape(e, em, nullptr);
  Bounds b;
  if (p) add_path_bounds(*p, Affine{}, b);
  if (b.empty()) return Bounds{0, 0, 0, 0};
  return b;
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
  // vector-effect is not inherited (SVG 2 coords.html#VectorEffects); of its values only
  // non-scaling-stroke concerns what we draw.
  const auto ve = property<std::string>(e, "vector-effect", parse_keyword);
  st.non_scaling_stroke = ve.state == Prop<std::string>::Set && ve.value == "non-scaling-stroke";
}

// Resolves a fill or stroke paint (SVG 2 painting.html#SpecifyingPaint);
// `current` is the element's color, for currentColor. `what` names the
// property in warnings. A reference to a linearGradient, radialGradient or
// pattern stays a reference (PaintSpec::Server) with its fallback.
PaintSpec Converter::resolve_paint(const PaintValue& p, const RGBA& current, const std::string& what) {
  switch (p.kind) {
    case PaintValue::Kind::None: return {};
    case PaintValue::Kind::Color: return PaintSpec::solid(p.color);
    case PaintValue::Kind::CurrentColor: return PaintSpec::solid(current);
    case PaintValue::Kind::Context: {
      // The context element's paint (none without one), keeping its user
      // space and box for a paint server.
      if (context_ < 0) return {};
      PaintSpec c = p.context_stroke ? contexts_[context_].stroke : contexts_[context_].fill;
      if (c.kind == PaintSpec::Kind::Server) c.context = context_;
      return c;
    }
    case PaintValue::Kind::Url: break;
  }
  // A missing or unusable paint server uses the fallback, and without one
  // paints nothing (SVG 2 painting.html#SpecifyingPaint).
  PaintSpec fallback;
  if (p.fallback == PaintValue::Fallback::Color) fallback = PaintSpec::solid(p.fallback_color);
  if (p.fallback == PaintValue::Fallback::CurrentColor) fallback = PaintSpec::solid(current);
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
  Context c;
  c.inh = st.inh;
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
