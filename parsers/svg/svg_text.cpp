// SVG text (SVG 2 text.html, SVG 1.1 §10), laid out as resvg lays it out
// (usvg's text layout is the model; the suite's references are resvg's):
//  1. the characters of a <text>, its tspans, trefs and textPaths, white
//     space handled (xml:space), in spans (one per text node);
//  2. x, y, dx, dy and rotate lists resolved per character;
//  3. text chunks: a new one at each absolute position and around textPaths;
//  4. each chunk shaped whole by HarfBuzz (text/text.h: FriBiDi's visual
//     runs, fallback faces for missing glyphs), spans in other faces or
//     with other features reshaped and their clusters swapped in;
//  5-8. glyph clusters, vertical orientation, letter- and word-spacing,
//     textLength / lengthAdjust;
//  9. positions along the line (anchored) or along a path (textPath:
//     startOffset, side, the path measured as resvg measures it);
//  10-11. each span's glyph outlines (kept as curves) at its baseline
//     (dominant-baseline, alignment-baseline, baseline-shift), with its
//     decorations, painted with the span's fill and stroke.
//
// Colour glyphs, in this order of preference: COLR version 1 paint graphs
// (text/color_glyph.h, where FreeType gives them), OpenType SVG documents,
// bitmaps (CBDT, sbix), COLR version 0 layers.
//
// Not yet: textPath's method and spacing, and its SVG 2 path attribute (as
// resvg and Chrome).
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>

#include "core/error.h"
#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_text_path.h"
#include "parsers/svg/svg_values.h"
#include "parsers/svg/xml_encoding.h"
#include "parsers/svg/svg_style.h"
#include "parsers/svg/svg_css.h"
#include "text/color_glyph.h"
#include "text/text.h"

namespace mpvg::svg::detail {

namespace {

// Font databases by their folders, shared by every document of the process
// (a batch scans its fonts once).
const text::FontDb& font_db(const std::vector<std::string>& dirs, bool system, std::vector<std::string>* warnings) {
  static std::mutex mutex;
  static std::map<std::pair<std::vector<std::string>, bool>, std::unique_ptr<text::FontDb>> dbs;
  std::lock_guard<std::mutex> lock(mutex);
  auto& db = dbs[{dirs, system}];
  if (!db) {
    db = std::make_unique<text::FontDb>();
    for (const std::string& d : dirs) db->add_dir(d, warnings);
    if (system) db->add_system_fonts();
  }
  return *db;
}

// A variable font's axes (CSS Fonts 4 §6.12, font-optical-sizing auto):
// the weight, width and size the style asks for, then
// font-variation-settings over them. Axes a face lacks are ignored.
std::vector<std::pair<std::string, double>> variations_of(const Inherited& inh) {
  static const double widths[9] = {50, 62.5, 75, 87.5, 100, 112.5, 125, 150, 200};
  std::vector<std::pair<std::string, double>> v = {
      {"wght", double(inh.font_weight)},
      {"wdth", widths[std::clamp(inh.font_stretch, 1, 9) - 1]},
      {"opsz", inh.font_size}};
  for (const auto& [tag, value] : inh.font_variations) {
    bool replaced = false;
    for (auto& [t, x] : v)
      if (t == tag) x = value, replaced = true;
    if (!replaced) v.emplace_back(tag, value);
  }
  return v;
}

// A text content element (text, tspan, tref, a, textPath) with its style.
struct TextElem {
  const Element* e = nullptr;
  Style st;
  int parent = -1;  // index of the enclosing text content element
};

// The characters of one text node (a tref's referenced text counts as
// one), styled by the element holding it.
struct Span {
  int elem = 0;
  int first = 0, end = 0;  // characters
  int flow = -1;           // the textPath it lies on, or -1
};

struct Char {
  char32_t c = 0;
  int span = 0;
  bool split = false;  // first character of a textPath, or the first after one
  std::optional<double> x, y, dx, dy;
  double rotate = 0;
};

// One text chunk (SVG 2 text.html#TextLayoutAlgorithm): characters laid
// out together from one absolute position, anchored as a whole.
struct Chunk {
  int first = 0, end = 0;
  std::optional<double> x, y;
  Inherited::Anchor anchor = Inherited::Anchor::Start;
  int flow = -1;
};

// How a span's characters are shaped: the same key shapes the same.
struct ShapeKey {
  int face = -1;
  std::vector<std::pair<std::string, double>> variations;
  std::vector<std::string> features;
  bool operator==(const ShapeKey& o) const {
    return face == o.face && variations == o.variations && features == o.features;
  }
};

// A glyph as shaped at 1 user unit per em.
struct RawGlyph {
  int face = -1;
  uint32_t id = 0;
  int ch = 0;  // its cluster's first character (logical order)
  int key = 0;
  double advance = 0, dx = 0, dy = 0;
};

struct PlacedGlyph {
  int face;
  uint32_t id;
  int key;
  Vec2 at;  // in the cluster, user units at the span's size
};

// A glyph cluster (the glyphs of one or more characters shaped together):
// the unit of positioning, spacing and rotation.
struct Cluster {
  int ch = 0;
  std::vector<PlacedGlyph> glyphs;
  double width = 0, advance = 0;
  double ascent = 0, descent = 0;  // y up: descent negative
  Affine transform, path_transform;
  bool visible = true;
  bool relative_shift = false;  // positioned by dx or dy, or on a path: decorations break here
};

std::vector<double> number_list(const Element& e, const char* name, const std::function<double(const Length&)>& user) {
  std::vector<double> out;
  const std::string* v = e.attribute(name);
  if (!v) return out;
  // Lengths separated by white space and/or a comma; the list stops at the
  // first that does not parse.
  const std::string& t = *v;
  for (size_t pos = 0; pos < t.size();) {
    const size_t begin = t.find_first_not_of(" \t\n\r,", pos);
    if (begin == std::string::npos) break;
    size_t end = t.find_first_of(" \t\n\r,", begin);
    if (end == std::string::npos) end = t.size();
    const auto l = parse_length(std::string_view(t).substr(begin, end - begin));
    if (!l) break;
    out.push_back(user(*l));
    pos = end;
  }
  return out;
}

bool is_word_separator(char32_t c) {
  // CSS Text 3 §8.1: the word-separator characters.
  return c == 0x20 || c == 0xA0 || c == 0x1361 || c == 0x10100 || c == 0x10101 || c == 0x1039F || c == 0x1091F;
}

double anchor_offset(Inherited::Anchor a, double width) {
  return a == Inherited::Anchor::Middle ? -width / 2 : a == Inherited::Anchor::End ? -width : 0;
}

enum Line { Under = 1, Over = 2, Through = 4 };

// text-decoration (CSS Text Decoration 3 §2.4, the shorthand): its lines;
// a style and a colour may come with them (drawn solid, in the fill:
// svg_style.cpp warns), each component at most once, none only alone,
// keywords case-insensitive. Anything else makes the declaration invalid.
int decoration_of(const Element& e) {
  const auto d = property<int>(e, "text-decoration", [](std::string_view v) -> std::optional<int> {
    int lines = 0;
    bool none = false, style = false, color = false;
    for (size_t pos = 0; pos < v.size();) {
      const size_t b = v.find_first_not_of(" \t\n\r", pos);
      if (b == std::string_view::npos) break;
      size_t end = b;  // a word, or a function with its parentheses (rgb(0, 0, 0))
      for (int depth = 0; end < v.size() && (depth > 0 || !std::strchr(" \t\n\r", v[end])); end++)
        depth += v[end] == '(' ? 1 : v[end] == ')' ? -1 : 0;
      const std::string_view w = v.substr(b, end - b);
      pos = end;
      int line = 0;
      if (iequals(w, "underline")) line = Under;
      else if (iequals(w, "overline")) line = Over;
      else if (iequals(w, "line-through")) line = Through;
      if (line) {
        if (lines & line) return std::nullopt;
        lines |= line;
        continue;
      }
      if (iequals(w, "none") && !none) {
        none = true;
        continue;
      }
      if (!style && (iequals(w, "solid") || iequals(w, "double") || iequals(w, "dotted") || iequals(w, "dashed") ||
                     iequals(w, "wavy"))) {
        style = true;
        continue;
      }
      if (!color && parse_color(w)) {
        color = true;
        continue;
      }
      return std::nullopt;
    }
    if (none && lines) return std::nullopt;
    return lines;
  });
  return d.state == Prop<int>::Set ? d.value : 0;
}

using Baseline = Inherited::Baseline;

// alignment-baseline keywords; -1 for auto and baseline (the dominant
// baseline applies).
std::optional<int> parse_alignment_baseline(std::string_view v) {
  const auto k = parse_keyword(v);
  if (k == "auto" || k == "baseline") return -1;
  if (k == "alphabetic") return int(Baseline::Alphabetic);
  if (k == "middle") return int(Baseline::Middle);
  if (k == "central") return int(Baseline::Central);
  if (k == "hanging") return int(Baseline::Hanging);
  if (k == "mathematical") return int(Baseline::Mathematical);
  if (k == "text-before-edge" || k == "before-edge" || k == "text-top" || k == "top") return int(Baseline::TextTop);
  if (k == "text-after-edge" || k == "after-edge" || k == "text-bottom" || k == "bottom")
    return int(Baseline::TextBottom);
  if (k == "ideographic") return int(Baseline::Ideographic);
  return std::nullopt;
}

// How far (y down) the alphabetic baseline moves to align baseline b with
// the line's: resvg's and Chrome's reading of CSS Inline 3 from the
// font's metrics.
double baseline_offset(Baseline b, const text::Metrics& m) {
  switch (b) {
    case Baseline::Alphabetic: return 0;
    case Baseline::Middle: return m.x_height / 2;
    case Baseline::Central: return (m.ascent - m.descent) / 2;
    case Baseline::Hanging: return 0.8 * m.ascent;
    case Baseline::Mathematical: return 0.5 * m.ascent;
    case Baseline::TextTop: return m.ascent;
    case Baseline::TextBottom:
    case Baseline::Ideographic: return -m.descent;
  }
  return 0;
}

// The colour a colour glyph takes for the text's own (COLR's foreground,
// an SVG glyph's currentColor): the fill's, black where the fill is a paint
// server or none.
RGBA text_color(const Style& st) {
  if (st.inh.fill.kind == PaintSpec::Kind::Color) return st.inh.fill.color;
  return RGBA{0, 0, 0, 1};
}

}  // namespace

std::vector<Converter::TextPiece> Converter::layout_text(const Element& root, const Style& root_style,
                                                        const Affine& space, Bounds* cells) {
  std::vector<TextPiece> pieces;
  std::vector<std::string> font_warnings;
  const text::FontDb& db = font_db(s_.options.font_dirs, s_.options.system_fonts, &font_warnings);
  for (const std::string& w : font_warnings) warn(w);
  if (db.faces().empty()) {
    warn("no fonts found (see --font-dir): text not rendered");
    return pieces;
  }
  const bool vertical = root_style.inh.vertical;

  // 1. The characters, in document order, with white space handled (SVG 2
  // text.html#WhiteSpace, the xml:space rules of SVG 1.1 §10.15): newlines
  // removed and tabs made spaces; unless preserved, runs of spaces become
  // one and the text's leading and trailing spaces go.
  std::vector<TextElem> elems;
  std::vector<Span> spans;
  std::vector<Char> chars;
  std::vector<int> elem_first, elem_end;  // each element's characters
  std::vector<PathMeasure> paths;         // the textPaths' paths
  std::vector<double> start_offsets;
  bool last_space = true;  // at the start, a space is leading
  bool split_next = false;
  int current_flow = -1;
  std::function<void(const Element&, const Style&, int, int)> collect = [&](const Element& e, const Style& st,
                                                                            int parent, int depth) {
    const int index = static_cast<int>(elems.size());
    elems.push_back({&e, st, parent});
    elem_first.push_back(static_cast<int>(chars.size()));
    elem_end.push_back(0);
    const Context inner = child_context(st, space, false);
    // A tref (SVG 1.1 §10.6) holds the character data of the element it
    // references, every descendant's, as if it were its own.
    std::string referenced;
    if (e.name == "tref") {
      const std::string* href = e.attribute("href");
      if (!href) href = e.attribute("xlink:href");
      if (href && href->size() > 1 && (*href)[0] == '#') {
        const auto it = s_.doc.ids.find(href->substr(1));
        std::function<void(const Element&)> gather = [&](const Element& x) {
          for (const auto& k : x.children) {
            if (k->name == "#text") referenced += k->text;
            else if (k->name != "tref") gather(*k);
          }
        };
        if (it != s_.doc.ids.end()) gather(*it->second);
      }
    }
    Element tref_text;
    tref_text.name = "#text";
    tref_text.text = referenced;
    std::vector<const Element*> children;
    for (const auto& c : e.children) children.push_back(c.get());
    if (e.name == "tref") children = {&tref_text};
    for (const Element* c : children) {
      if (c->name == "#text") {
        if (!(st.inh.font_size > 0)) continue;  // a span of no size shows nothing
        std::vector<char32_t> cps;
        text::decode_utf8(c->text, cps);
        Span sp{index, static_cast<int>(chars.size()), 0, current_flow};
        for (char32_t cp : cps) {
          if (cp == '\n' || cp == '\r') {
            if (st.inh.space_preserve) cp = ' ';
            else continue;
          }
          if (cp == '\t') cp = ' ';
          if (cp == ' ' && !st.inh.space_preserve && last_space) continue;
          last_space = cp == ' ';
          Char ch;
          ch.c = cp;
          ch.span = static_cast<int>(spans.size());
          ch.split = split_next;
          split_next = false;
          chars.push_back(ch);
        }
        sp.end = static_cast<int>(chars.size());
        if (sp.end > sp.first) spans.push_back(sp);
      } else if (c->name == "tspan" || c->name == "a" || (c->name == "tref" && depth < 2)) {
        if (depth > 64 || !conditions_pass(*c)) continue;
        const Style cs = compute_style(*c, inner);
        if (cs.display_none) continue;
        collect(*c, cs, index, depth + 1);
      } else if (c->name == "textPath" && depth == 0) {
        // SVG 2 text.html#TextPathElement: the path (or basic shape) it
        // names, with that element's own transform. Without one it
        // renders nothing.
        const std::string* href = c->attribute("href");
        if (!href) href = c->attribute("xlink:href");
        const Element* target = nullptr;
        if (href && href->size() > 1 && (*href)[0] == '#') {
          const auto it = s_.doc.ids.find(href->substr(1));
          if (it != s_.doc.ids.end()) target = it->second;
        }
        // An invalid textPath draws nothing; the white space on either
        // side of it stays (resvg collapses spaces within each text node
        // and across nesting levels, not between sibling nodes).
        auto skip = [&] { last_space = false; };
        if (!target) {
          skip();
          continue;
        }
        std::optional<Path> shape = build_shape(*target, st.inh.font_size);
        if (!shape || shape->empty()) {
          skip();
          continue;
        }
        Affine xf;
        if (const std::string* t = target->attribute("transform"))
          if (const auto m = parse_transform(*t)) xf = with_origin(*target, *m, st.inh.font_size);
        const double scale = std::sqrt(std::hypot(space.a, space.b) * std::hypot(space.c, space.d));
        PathMeasure measure(shape->transformed(xf), 0.5 / std::max(scale, 1.0));
        if (measure.empty()) continue;
        // side="right" (SVG 2): the text goes on the other side of the
        // path, i.e. along it reversed.
        if (const std::string* side = c->attribute("side"); side && trim(*side) == "right") measure.reverse();
        const Style cs = compute_style(*c, inner);
        if (cs.display_none) continue;
        double offset = 0;
        if (const std::string* so = c->attribute("startOffset"))
          if (const auto l = parse_length(*so)) {
            if (l->unit == Unit::Percent) {
              offset = l->value / 100 * measure.total();
            } else {
              offset = to_user(*l, Axis::X, cs.inh.font_size);
              // A length is in the author's units when the path has a
              // pathLength (SVG 2 text.html#TextPathElementStartOffsetAttribute):
              // scaled by the path's length, as the text measures it, over
              // pathLength. Zero scales by infinity (SVG 2
              // paths.html#PathLengthAttribute): any offset but 0 leaves
              // the path, and the text with it, as in Chromium.
              const std::string* pl = target->attribute("pathLength");
              if (const auto author = pl ? parse_path_length(*pl) : std::nullopt) {
                if (*author > 0) offset *= measure.total() / *author;
                else if (offset != 0) offset = std::copysign(HUGE_VAL, offset);
              }
            }
          }
        paths.push_back(std::move(measure));
        start_offsets.push_back(offset);
        current_flow = static_cast<int>(paths.size()) - 1;
        split_next = true;
        collect(*c, cs, index, depth + 1);
        current_flow = -1;
        split_next = true;
      } else if (c->name == "textPath") {
        warn("<textPath> inside another text content element is not supported: ignored");
      }
    }
    elem_end[index] = static_cast<int>(chars.size());
  };
  collect(root, root_style, -1, 0);
  // Trailing spaces go (unless preserved).
  while (!chars.empty() && chars.back().c == ' ' && !elems[spans[chars.back().span].elem].st.inh.space_preserve) {
    chars.pop_back();
    const int n = static_cast<int>(chars.size());
    for (Span& sp : spans) sp.end = std::min(sp.end, n);
    for (int& e : elem_end) e = std::min(e, n);
  }
  while (!spans.empty() && spans.back().end <= spans.back().first) spans.pop_back();
  if (chars.empty()) return pieces;
  const int nchars = static_cast<int>(chars.size());

  // 2. Positions: each text or tspan element's x, y, dx and dy lists give
  // its characters' values in order (a textPath's are ignored); the deeper
  // element's win (elements are in pre-order). rotate: every element's
  // list, its last value (or the last value given before) holding for the
  // characters after it.
  {
    double last_rotate = 0;
    for (size_t k = 0; k < elems.size(); k++) {
      const Element& e = *elems[k].e;
      const int first = elem_first[k], end = std::min(elem_end[k], nchars);
      const double em = elems[k].st.inh.font_size;
      if (e.name != "textPath") {
        auto ux = [&](const Length& l) { return to_user(l, Axis::X, em); };
        auto uy = [&](const Length& l) { return to_user(l, Axis::Y, em); };
        const auto xs = number_list(e, "x", ux), ys = number_list(e, "y", uy);
        const auto dxs = number_list(e, "dx", ux), dys = number_list(e, "dy", uy);
        for (int i = first; i < end; i++) {
          const size_t n = size_t(i - first);
          if (n < xs.size()) chars[i].x = xs[n];
          if (n < ys.size()) chars[i].y = ys[n];
          if (n < dxs.size()) chars[i].dx = dxs[n];
          if (n < dys.size()) chars[i].dy = dys[n];
        }
      }
      // rotate takes plain numbers (degrees): a list with anything else
      // (a unit) is invalid as a whole and ignored.
      if (!e.attribute("rotate")) continue;
      bool valid = true;
      const auto rs = number_list(e, "rotate", [&](const Length& l) {
        if (l.unit != Unit::None) valid = false;
        return l.value;
      });
      if (!valid) continue;
      for (int i = first; i < end; i++) {
        const size_t n = size_t(i - first);
        if (n < rs.size()) last_rotate = rs[n];
        chars[i].rotate = last_rotate;
      }
    }
  }

  // 3. Chunks: a new one at the first character, at each character with an
  // absolute x or y, and where a textPath starts or ends.
  std::vector<Chunk> chunks;
  for (int i = 0; i < nchars; i++) {
    const Char& c = chars[i];
    if (i == 0 || c.x || c.y || c.split) {
      if (!chunks.empty()) chunks.back().end = i;
      Chunk ch;
      ch.first = i;
      ch.x = c.x;
      ch.y = c.y;
      ch.anchor = elems[spans[c.span].elem].st.inh.text_anchor;
      ch.flow = spans[c.span].flow;
      chunks.push_back(ch);
    }
  }
  chunks.back().end = nchars;

  // Per span: the face CSS matching picks, how it shapes, its baseline.
  std::vector<ShapeKey> keys;
  std::vector<int> span_key(spans.size());
  for (size_t k = 0; k < spans.size(); k++) {
    const Inherited& inh = elems[spans[k].elem].st.inh;
    ShapeKey key;
    key.face = db.match(inh.font_family, inh.font_weight, inh.font_italic, inh.font_stretch);
    key.variations = variations_of(inh);
    key.features = inh.font_features;
    if (inh.small_caps) key.features.push_back("smcp");
    if (!inh.kerning) key.features.push_back("-kern");
    // A list naming only families the database lacks: say which face
    // stands in (a generic family, or a family fontconfig aliases to the
    // one used, counts as found).
    if (key.face >= 0) {
      static const char* generics[] = {"serif", "sans-serif", "cursive", "fantasy", "monospace", "system-ui"};
      const std::string& got = db.faces()[key.face].family;
      bool found = false;
      for (const std::string& f : inh.font_family)
        found = found || iequals(f, got) || db.is_alias(f, got) ||
                std::any_of(std::begin(generics), std::end(generics), [&](const char* g) { return iequals(f, g); });
      if (!found && !inh.font_family.empty()) {
        std::string list;
        for (const std::string& f : inh.font_family) list += (list.empty() ? "" : ", ") + f;
        warn("font-family '" + list + "' not found: using " + got);
      }
    }
    const auto it = std::find(keys.begin(), keys.end(), key);
    span_key[k] = static_cast<int>(it - keys.begin());
    if (it == keys.end()) keys.push_back(std::move(key));
  }
  // Synthetic bold and oblique (CSS Fonts 4 §5.5, font-synthesis auto):
  // bold asked for (600 or more) of a face at 500 or less that has no
  // weight axis: outlines grown by 1/32 em; italic or oblique asked for of
  // an upright face: glyphs slanted by a quarter of their height (14°).
  std::vector<uint8_t> synth_bold(spans.size(), 0), synth_oblique(spans.size(), 0);
  for (size_t k = 0; k < spans.size(); k++) {
    const Inherited& inh = elems[spans[k].elem].st.inh;
    const int face = keys[span_key[k]].face;
    if (face < 0) continue;
    const text::FaceInfo& info = db.faces()[face];
    synth_bold[k] = inh.font_weight >= 600 && info.weight <= 500 && !text::has_axis(db, face, "wght");
    synth_oblique[k] = inh.font_italic && !info.italic && !text::has_axis(db, face, "slnt") &&
                       !text::has_axis(db, face, "ital");
  }
  std::map<std::pair<int, double>, text::Metrics> metrics_cache;
  auto metrics = [&](int face, double size) -> const text::Metrics& {
    auto it = metrics_cache.find({face, size});
    if (it == metrics_cache.end()) it = metrics_cache.emplace(std::pair(face, size), text::metrics(db, face, size)).first;
    return it->second;
  };
  // The size the span's glyphs are drawn at: font-size, or with
  // font-size-adjust (CSS Fonts 5 §2.6) the size that gives the first
  // face's x-height that fraction of font-size.
  std::vector<double> used_size(spans.size());
  for (size_t k = 0; k < spans.size(); k++) {
    const Inherited& inh = elems[spans[k].elem].st.inh;
    used_size[k] = inh.font_size;
    const int face = keys[span_key[k]].face;
    if (inh.font_size_adjust > 0 && face >= 0) {
      const text::Metrics m = text::metrics(db, face, 1.0);
      if (m.x_height > 0) used_size[k] = inh.font_size * inh.font_size_adjust / m.x_height;
    }
  }
  auto span_size = [&](int span) { return used_size[span]; };
  // The span's baseline (y down from the line's alphabetic baseline):
  // baseline-shift of its element and its ancestors below the text (a
  // length, a percentage of that element's font size, sub or super from the
  // span's font), then, in horizontal text, alignment-baseline (the
  // element's or its parent's) or else dominant-baseline.
  // Computed once per span (a path chunk asks for every cluster).
  std::vector<std::optional<double>> baselines(spans.size());
  auto span_baseline = [&](int span) {
    if (baselines[span]) return *baselines[span];
    const Span& sp = spans[span];
    const int face = keys[span_key[span]].face;
    const text::Metrics& m = metrics(face, span_size(span));
    double up = 0;
    // The text element's own baseline-shift moves nothing (as in resvg
    // and Chrome: the property applies to inline boxes inside the text).
    for (int k = sp.elem; k > 0; k = elems[k].parent) {
      // "inherit" takes the parent's specified value.
      const Element* at = elems[k].e;
      const double em = elems[k].st.inh.font_size;
      Prop<double> bs;
      for (;;) {
        bs = property<double>(*at, "baseline-shift", [&](std::string_view v) -> std::optional<double> {
          const auto kw = parse_keyword(v);
          if (kw == "baseline") return 0.0;
          if (kw == "sub") return -m.subscript_offset;
          if (kw == "super") return m.superscript_offset;
          const auto l = parse_length(v);
          if (!l) return std::nullopt;
          if (l->unit == Unit::Percent) return l->value / 100 * em;
          return to_user(*l, Axis::Y, em);
        });
        if (bs.state != Prop<double>::Inherit || !at->parent) break;
        at = at->parent;
      }
      if (bs.state == Prop<double>::Set) up += bs.value;
    }
    double down = -up;
    if (!vertical) {
      std::optional<int> align;
      for (int k = sp.elem, n = 0; k >= 0 && n < 2 && !align; k = elems[k].parent, n++) {
        // "inherit" takes the DOM parent's value (the text's parent too).
        for (const Element* at = elems[k].e; at; at = at->parent) {
          const auto ab = property<int>(*at, "alignment-baseline", parse_alignment_baseline);
          if (ab.state == Prop<int>::Set) align = ab.value;
          if (ab.state != Prop<int>::Inherit) break;
        }
      }
      const Baseline b =
          align && *align >= 0 ? static_cast<Baseline>(*align) : elems[sp.elem].st.inh.dominant_baseline;
      down += baseline_offset(b, m);
    }
    baselines[span] = down;
    return down;
  };

  // Glyph outlines, each span's glyphs as one shape.
  std::vector<Path> glyph_paths(spans.size());
  std::vector<Path> decoration_paths(spans.size() * 3);
  std::vector<std::vector<std::pair<Path, text::ColorLayer>>> color_paths(spans.size());
  std::map<std::pair<int, uint32_t>, std::vector<text::ColorLayer>> color_layer_cache;
  // Bitmap and SVG glyphs, each a piece of its own.
  std::vector<std::vector<TextPiece>> picture_pieces(spans.size());
  std::map<int, bool> bitmap_faces;
  auto db_has_bitmaps = [&](int face) {
    auto it = bitmap_faces.find(face);
    if (it == bitmap_faces.end()) it = bitmap_faces.emplace(face, db.has_color_bitmaps(face)).first;
    return it->second;
  };
  double last_x = 0, last_y = 0;
  for (const Chunk& chunk : chunks) {
    // The spans of the chunk (the first and last may be cut by it).
    std::vector<int> chunk_spans;
    for (int i = chunk.first; i < chunk.end; i++)
      if (chunk_spans.empty() || chunk_spans.back() != chars[i].span) chunk_spans.push_back(chars[i].span);
    std::string utf8;
    std::vector<int> char_of_byte;
    for (int i = chunk.first; i < chunk.end; i++) {
      append_utf8(utf8, chars[i].c);
      char_of_byte.resize(utf8.size(), i);
    }

    // 4. Shaping: the whole chunk at once in the first span's face (the
    // bidi algorithm's runs in visual order, with per-cluster fallback to
    // faces that have the glyphs), then each span in another face or with
    // other features shaped whole again and its clusters taken from that.
    std::map<int, std::vector<RawGlyph>> shaped;
    auto shape_with = [&](int key_index, int span) -> const std::vector<RawGlyph>& {
      auto found = shaped.find(key_index);
      if (found != shaped.end()) return found->second;
      const ShapeKey& key = keys[key_index];
      text::ShapeOptions so;
      so.bidi = true;
      so.variations = key.variations;
      so.features = key.features;
      auto run = [&](int face) {
        std::vector<RawGlyph> out;
        for (const text::ShapedGlyph& g : text::shape(db, face, utf8, 1.0, so))
          out.push_back({face, g.glyph, g.cluster < char_of_byte.size() ? char_of_byte[g.cluster] : chunk.first,
                         key_index, g.x_advance, g.x_offset, g.y_offset});
        return out;
      };
      std::vector<RawGlyph> glyphs = key.face >= 0 ? run(key.face) : std::vector<RawGlyph>{};
      std::vector<int> used{key.face};
      const Inherited& inh = elems[spans[span].elem].st.inh;
      for (int tries = 0; tries < 16 && key.face >= 0; tries++) {
        const auto missing = std::find_if(glyphs.begin(), glyphs.end(), [](const RawGlyph& g) { return g.id == 0; });
        if (missing == glyphs.end()) break;
        const int other = db.fallback(chars[missing->ch].c, inh.font_weight, inh.font_italic);
        if (other < 0 || std::find(used.begin(), used.end(), other) != used.end()) break;
        used.push_back(other);
        std::vector<RawGlyph> again = run(other);
        if (std::none_of(again.begin(), again.end(), [](const RawGlyph& g) { return g.id == 0; })) {
          glyphs = std::move(again);
          break;
        }
        if (again.size() != glyphs.size()) break;
        for (size_t i = 0; i < glyphs.size(); i++)
          if (glyphs[i].id == 0 && again[i].id != 0) glyphs[i] = again[i];
      }
      for (const RawGlyph& g : glyphs)
        if (g.id == 0 && chars[g.ch].c != ' ') {
          char code[16];
          std::snprintf(code, sizeof code, "U+%04X", unsigned(chars[g.ch].c));
          warn(std::string("no font has a glyph for ") + code + ": not drawn");
        }
      return shaped.emplace(key_index, std::move(glyphs)).first->second;
    };
    std::vector<RawGlyph> glyphs = shape_with(span_key[chunk_spans[0]], chunk_spans[0]);
    for (size_t s = 1; s < chunk_spans.size(); s++) {
      const int span = chunk_spans[s];
      if (span_key[span] == span_key[chunk_spans[0]]) continue;
      const std::vector<RawGlyph>& other = shape_with(span_key[span], span);
      const int a = std::max(spans[span].first, chunk.first), b = std::min(spans[span].end, chunk.end);
      // Each of its clusters covers the characters up to the next one's
      // (a ligature several): those go from the first shaping.
      std::vector<int> starts;
      for (const RawGlyph& g : other) starts.push_back(g.ch);
      std::sort(starts.begin(), starts.end());
      for (size_t i = 0; i < other.size();) {
        size_t j = i;
        while (j < other.size() && other[j].ch == other[i].ch) j++;
        if (other[i].ch >= a && other[i].ch < b) {
          const auto next = std::upper_bound(starts.begin(), starts.end(), other[i].ch);
          const int covered_end = next == starts.end() ? chunk.end : *next;
          glyphs.erase(std::remove_if(glyphs.begin(), glyphs.end(),
                                      [&](const RawGlyph& g) { return g.ch > other[i].ch && g.ch < covered_end; }),
                       glyphs.end());
          const auto at = std::find_if(glyphs.begin(), glyphs.end(), [&](const RawGlyph& g) { return g.ch == other[i].ch; });
          if (at != glyphs.end()) {
            auto end = at;
            while (end != glyphs.end() && end->ch == at->ch) ++end;
            const auto pos = glyphs.erase(at, end);
            glyphs.insert(pos, other.begin() + static_cast<long>(i), other.begin() + static_cast<long>(j));
          }
        }
        i = j;
      }
    }

    // 5. Clusters: consecutive glyphs of one first character, scaled to
    // their span's font size.
    std::vector<Cluster> clusters;
    for (size_t i = 0; i < glyphs.size();) {
      size_t j = i;
      while (j < glyphs.size() && glyphs[j].ch == glyphs[i].ch) j++;
      Cluster cl;
      cl.ch = glyphs[i].ch;
      const double size = span_size(chars[cl.ch].span);
      double x = 0;
      for (size_t k = i; k < j; k++) {
        const RawGlyph& g = glyphs[k];
        if (g.face >= 0 && g.id != 0)
          cl.glyphs.push_back({g.face, g.id, g.key, {(x + g.dx) * size, g.dy * size}});
        x += g.advance;
      }
      // The pen's advance through the cluster (resvg takes the largest
      // glyph advance instead, which overlaps the next cluster where an
      // Indic cluster has two advancing glyphs).
      cl.width = x * size;
      cl.advance = cl.width;
      if (glyphs[i].face >= 0) {
        const text::Metrics& m = metrics(glyphs[i].face, size);
        cl.ascent = m.ascent;
        cl.descent = -m.descent;
      }
      clusters.push_back(std::move(cl));
      i = j;
    }
    if (clusters.empty()) {
      continue;
    }

    // 6. Vertical writing: upright characters turned back and centred on
    // the line, the others moved down by half their height (as resvg and
    // browsers shift them).
    if (vertical)
      for (Cluster& cl : clusters) {
        const double mid = (cl.ascent + cl.descent) / 2;
        if (text::upright_in_vertical(chars[cl.ch].c)) {
          cl.path_transform = Affine::translate(0, mid) * Affine::translate(cl.width / 2, -mid) *
                              Affine::rotate_degrees(-90) * Affine::translate(-cl.width / 2, mid);
          cl.ascent = cl.width / 2;
          cl.descent = -cl.width / 2;
        } else {
          cl.transform = cl.transform * Affine::translate(0, mid);
        }
      }

    // 7. letter-spacing after every cluster but the chunk's last (not in
    // cursive scripts), word-spacing after word separators.
    for (size_t i = 0; i < clusters.size(); i++) {
      Cluster& cl = clusters[i];
      const Inherited& inh = elems[spans[chars[cl.ch].span].elem].st.inh;
      if (inh.letter_spacing != 0 && text::letter_spacing_applies(chars[cl.ch].c)) {
        if (i + 1 != clusters.size()) cl.advance += inh.letter_spacing;
        if (!(cl.advance > 0)) {
          // A negative advance: nothing of the cluster shows (as Chrome).
          cl.width = cl.advance = 0;
          cl.glyphs.clear();
        }
      }
      if (is_word_separator(chars[cl.ch].c)) cl.advance += inh.word_spacing;
    }

    // 8. textLength and lengthAdjust, per span: spacing spreads the
    // difference between the clusters; spacingAndGlyphs scales them.
    for (int span : chunk_spans) {
      const Element& e = *elems[spans[span].elem].e;
      const std::string* tl = e.attribute("textLength");
      if (!tl) continue;
      const auto l = parse_length(*tl);
      if (!l) continue;
      const double target = to_user(*l, Axis::Diagonal, span_size(span));
      if (!(target >= 0)) continue;
      std::vector<size_t> mine;
      double width = 0;
      for (size_t i = 0; i < clusters.size(); i++)
        if (chars[clusters[i].ch].span == span) mine.push_back(i), width += clusters[i].width;
      if (mine.empty()) continue;
      const std::string* la = e.attribute("lengthAdjust");
      if (la && trim(*la) == "spacingAndGlyphs") {
        const double f = target / width;
        if (!(f >= 0.001)) continue;
        for (size_t i : mine) {
          clusters[i].transform = clusters[i].transform * Affine::scale(f, 1);
          if (chunk.flow >= 0) clusters[i].advance *= f, clusters[i].width *= f;
        }
      } else {
        const double f = mine.size() > 1 ? (target - width) / double(mine.size() - 1) : 0;
        for (size_t i : mine) clusters[i].advance = clusters[i].width + f;
      }
    }

    double length = 0;
    for (const Cluster& cl : clusters) length += cl.advance;
    double end_x = 0, end_y = 0;
    if (chunk.flow < 0) {
      // 9a. Along a line: anchored by the chunk's advance; dx and dy move
      // the pen before their cluster (across and along the line when
      // vertical); rotate turns the cluster about its origin.
      double x = anchor_offset(chunk.anchor, length), y = 0;
      for (Cluster& cl : clusters) {
        const Char& c = chars[cl.ch];
        if (vertical) y += c.dx.value_or(0), x += c.dy.value_or(0);
        else x += c.dx.value_or(0), y += c.dy.value_or(0);
        cl.relative_shift = c.dx || c.dy;
        cl.transform = cl.transform * Affine::translate(x, y);
        if (c.rotate != 0) cl.transform = cl.transform * Affine::rotate_degrees(c.rotate);
        x += cl.advance;
      }
      end_x = x, end_y = y;
    } else {
      // 9b. Along a path (SVG 2 text.html#TextpathLayoutRules): the
      // chunk's x (y when vertical), startOffset and the anchor give the
      // distance where it starts; each cluster's middle goes on the path
      // at its distance, turned with the path's direction there; dy and
      // the baseline move it across. Clusters off the path are hidden.
      const PathMeasure& path = paths[chunk.flow];
      double advance = (vertical ? chunk.y : chunk.x).value_or(0) + start_offsets[chunk.flow] +
                       anchor_offset(chunk.anchor, length);
      double dy = 0;
      for (Cluster& cl : clusters) {
        const Char& c = chars[cl.ch];
        advance += c.dx.value_or(0);
        const double half = cl.width / 2, mid = advance + half;
        advance += cl.advance;
        Vec2 p;
        double angle;
        if (mid < 0 || !path.at(mid, p, angle)) {
          cl.visible = false;
          continue;
        }
        cl.relative_shift = true;
        const Affine own = cl.transform;
        cl.transform = Affine::translate(p.x, p.y) * Affine::rotate_degrees(angle) * Affine::translate(-half, 0);
        dy += c.dy.value_or(0);
        const double shift = dy + span_baseline(c.span);
        if (shift != 0) cl.transform = cl.transform * Affine::translate(0, shift);
        if (c.rotate != 0) cl.transform = cl.transform * Affine::rotate_degrees(c.rotate);
        cl.transform = cl.transform * own;
        end_x = p.x + cl.advance, end_y = p.y;
      }
    }

    // 10. Each span's glyphs and decorations. A horizontal line's spans
    // sit on their baselines; a vertical line is the horizontal one turned
    // by 90° about its start.
    const double x0 = chunk.flow < 0 ? chunk.x.value_or(last_x) : 0;
    const double y0 = chunk.flow < 0 ? chunk.y.value_or(last_y) : 0;
    Affine text_ts;
    if (vertical && chunk.flow < 0)
      text_ts = Affine::translate(x0, y0) * Affine::rotate_degrees(90) * Affine::translate(-x0, -y0);
    for (int span : chunk_spans) {
      Affine span_ts = text_ts * Affine::translate(x0, y0);
      if (chunk.flow < 0) span_ts = span_ts * Affine::translate(0, span_baseline(span));
      const int face = keys[span_key[span]].face;
      for (const Cluster& cl : clusters) {
        if (!cl.visible || chars[cl.ch].span != span) continue;
        const Affine ts = span_ts * cl.transform * cl.path_transform;
        if (cells) {
          const Affine cell = span_ts * cl.transform;
          for (const Vec2 c : {Vec2{0, -cl.ascent}, Vec2{cl.advance, -cl.ascent}, Vec2{0, -cl.descent},
                               Vec2{cl.advance, -cl.descent}})
            cells->add(cell.apply(c));
        }
        for (const PlacedGlyph& g : cl.glyphs) {
          // Synthetic oblique (font-style without an italic face) slants
          // every kind of glyph, colour ones included, as Skia's text
          // matrix does; synthetic bold grows outlines only.
          const Affine slant = synth_oblique[span] ? Affine{1, 0, -0.25, 1, 0, 0} : Affine{};
          const Affine at = ts * Affine::translate(g.at.x, g.at.y) * slant;
          if (std::shared_ptr<const Scene> colr = colr_glyph(db, g.face, g.id, keys[g.key].variations,
                                                             text_color(elems[spans[span].elem].st))) {
            // A COLR v1 glyph (paint graph), drawn instead of its outline,
            // its version 0 layers and its SVG document (as Chromium
            // prefers it).
            TextPiece piece;
            piece.path =
                text::glyph_outline(db, g.face, g.id, span_size(span), keys[g.key].variations).transformed(at);
            piece.image_xf = at * Affine::scale(span_size(span), span_size(span));
            piece.color_scene = std::move(colr);
            picture_pieces[span].push_back(std::move(piece));
            continue;
          }
          if (std::shared_ptr<const SvgGlyphSource> svg = svg_glyph_source(db, g.face, g.id)) {
            // An SVG glyph (OpenType SVG table) is drawn instead of the
            // outline, as COLR layers are; its font units (y down, origin
            // at the pen) scale by size / units per em.
            TextPiece piece;
            piece.path =
                text::glyph_outline(db, g.face, g.id, span_size(span), keys[g.key].variations).transformed(at);
            const double k = span_size(span) / svg->units_per_em;
            piece.image_xf = at * Affine::scale(k, k);
            piece.svg_glyph = std::move(svg);
            piece.svg_glyph_id = g.id;
            picture_pieces[span].push_back(std::move(piece));
            continue;
          }
          if (db_has_bitmaps(g.face)) {
            const text::GlyphBitmap bm = text::glyph_bitmap(db, g.face, g.id, span_size(span));
            if (bm.image) {
              const Affine texel = at * Affine::translate(bm.x, bm.y) * Affine::scale(bm.scale, bm.scale);
              Path rect = Path::rectangle(0, 0, bm.image->width, bm.image->height).transformed(texel);
              picture_pieces[span].push_back({std::move(rect), Style{}, bm.image, texel, nullptr, 0});
              continue;
            }
          }
          auto layers = color_layer_cache.find({g.face, g.id});
          if (layers == color_layer_cache.end())
            layers = color_layer_cache.emplace(std::pair(g.face, g.id), text::color_layers(db, g.face, g.id)).first;
          if (!layers->second.empty()) {
            // A colour glyph (COLR): its layers one above the other.
            for (const text::ColorLayer& l : layers->second) {
              const Path outline = text::glyph_outline(db, g.face, l.glyph, span_size(span), keys[g.key].variations);
              if (!outline.empty()) color_paths[span].push_back({outline.transformed(at), l});
            }
            continue;
          }
          const Path outline = text::glyph_outline(db, g.face, g.id, span_size(span), keys[g.key].variations,
                                                   synth_bold[span] ? 1.0 / 32 : 0);
          if (!outline.empty()) glyph_paths[span].append(outline.transformed(at));
        }
      }
      // text-decoration (CSS Text Decoration 3): one rectangle per run of
      // clusters not moved apart (dx, dy, a path), from the span's font's
      // metrics; all three lines as thick as the underline.
      if (face < 0) continue;
      int lines = 0;
      for (const Element* a = elems[spans[span].elem].e; a; a = a->parent) lines |= decoration_of(*a);
      if (!lines) continue;
      const text::Metrics& m = metrics(face, span_size(span));
      const double thickness = m.underline_thickness;
      for (int line : {Under, Over, Through}) {
        if (!(lines & line)) continue;
        double offset;
        if (line == Under) offset = vertical ? (m.ascent + m.descent) / 2 : m.underline_position - m.underline_thickness / 2;
        else if (line == Over) offset = vertical ? -(m.ascent + m.descent) / 2 : -m.ascent;
        else offset = vertical ? 0 : m.strikeout_position;
        Path& out = decoration_paths[span * 3 + (line == Under ? 0 : line == Over ? 1 : 2)];
        bool started = false;
        double width = 0;
        Affine at;
        auto flush = [&] {
          if (started && width > 0)
            out.append(Path::rectangle(0, -thickness / 2, width, thickness / 2)
                           .transformed(span_ts * at * Affine::translate(0, offset)));
          started = false;
        };
        for (const Cluster& cl : clusters) {
          if (cl.visible && chars[cl.ch].span == span) {
            if (started && cl.relative_shift) flush();
            if (!started) started = true, width = cl.width, at = cl.transform;
            else width += cl.width;
          } else if (started) {
            flush();
          }
        }
        flush();
      }
    }
    if (vertical && chunk.flow < 0) std::swap(end_x, end_y);
    last_x = x0 + end_x;
    last_y = y0 + end_y;
  }

  // 11. The pieces in paint order, span by span: underline, overline, the
  // glyphs, line-through. A decoration is painted with the style of the
  // nearest element, from the span's own up to the text, that sets it
  // (else the text's).
  auto decorating_style = [&](int span, int line) -> const Style& {
    for (int k = spans[span].elem; k >= 0; k = elems[k].parent)
      if ((decoration_of(*elems[k].e) & line) || k == 0) return elems[k].st;
    return elems[0].st;
  };
  for (size_t k = 0; k < spans.size(); k++) {
    const Style& own = elems[spans[k].elem].st;
    if (!own.inh.visible) continue;
    auto add_decoration = [&](int slot, int line) {
      Path& p = decoration_paths[k * 3 + slot];
      if (!p.empty())
        pieces.push_back({std::move(p), decorating_style(static_cast<int>(k), line), nullptr, Affine{}, nullptr, 0});
    };
    add_decoration(0, Under);
    add_decoration(1, Over);
    if (!glyph_paths[k].empty()) {
      // fill-rule does not apply to text (SVG 2 text.html#TextRenderingOrder):
      // glyphs fill by non-zero winding, overlapping contours included.
      Style st = own;
      st.inh.fill_rule = FillRule::NonZero;
      pieces.push_back({std::move(glyph_paths[k]), st, nullptr, Affine{}, nullptr, 0});
    }
    for (TextPiece& piece : picture_pieces[k]) {
      piece.st = own;
      pieces.push_back(std::move(piece));
    }
    for (auto& [path, layer] : color_paths[k]) {
      // A palette colour, or the text's fill for the foreground layers;
      // layers are filled, not stroked.
      Style st = own;
      st.inh.fill_rule = FillRule::NonZero;
      if (!layer.foreground) st.inh.fill = PaintSpec::solid(layer.color);
      st.inh.stroke = PaintSpec();
      pieces.push_back({std::move(path), st, nullptr, Affine{}, nullptr, 0});
    }
    add_decoration(2, Through);
  }
  return pieces;
}

void Converter::text(const Element& e, const Style& st, const Affine& space) {
  // Paint servers in objectBoundingBox units use the text's box: its glyph
  // cells (SVG 2 coords.html#BoundingBoxes: text content elements).
  Bounds box;
  std::vector<TextPiece> pieces = layout_text(e, st, space, &box);
  // The same box for what measures the element (objectBoundingBox clip
  // paths, masks and filters on it): a bounds-only operation.
  if (!box.empty()) {
    Op cells = Op::of(OpKind::Bounds);
    cells.shape = rect_shape({box.x0, box.y0, box.width(), box.height()});
    cells.xf = space;
    ops_.push_back(cells);
  }
  for (TextPiece& piece : pieces) {
    if (piece.svg_glyph) {
      draw_svg_glyph(piece, space);
      continue;
    }
    if (piece.color_scene) {
      append_glyph_drawing(*piece.color_scene, space * piece.image_xf, piece.st.inh.fill_opacity);
      continue;
    }
    const uint32_t shape = static_cast<uint32_t>(shapes_.size());
    add_shape(std::move(piece.path));
    if (!piece.image) {
      // Glyphs and decorations follow text-rendering, not shape-rendering.
      piece.st.inh.aliased_shapes = piece.st.inh.aliased_text;
      paint_shape(shape, piece.st, space, true, &box);
      continue;
    }
    // A bitmap glyph: its image on its rectangle, with the span's
    // fill-opacity (as a tint's alpha) and image-rendering.
    texture_fill(piece.image, space * piece.image_xf, piece.st.inh.image_rendering, piece.st.inh.fill_opacity, shape,
                 space);
  }
}

namespace {

// A copy of e and its subtree under `parent`, its ids entered in `doc`
// (the first element carrying each, in document order).
std::unique_ptr<Element> copy_tree(const Element& e, const Element* parent, Document& doc) {
  auto c = std::make_unique<Element>();
  c->name = e.name;
  c->attributes = e.attributes;
  c->declarations = e.declarations;
  c->style_attribute = e.style_attribute;
  c->text = e.text;
  c->parent = parent;
  if (const std::string* id = c->attribute("id"); id && !id->empty()) doc.ids.emplace(*id, c.get());
  for (const auto& child : e.children) c->children.push_back(copy_tree(*child, c.get(), doc));
  return c;
}

// The document that draws glyph `id` of `source` (OpenType 1.9, SVG
// table): a copy of it on the em square (its root units_per_em wide and
// high, so one user unit per font unit where there is no viewBox). Unless
// the glyph element is the root itself, the root's content becomes defs
// (reachable by id, not drawn) beside a <use> of the element glyph<ID>.
// current_color, when not empty, is the root's `color` for currentColor,
// unless the source's root sets its own.
Document glyph_drawing(const SvgGlyphSource& source, uint32_t id, const std::string& current_color) {
  Document doc;
  doc.root = copy_tree(*source.doc->root, nullptr, doc);
  Element& root = *doc.root;
  char em[32];
  std::snprintf(em, sizeof em, "%.17g", source.units_per_em);
  std::erase_if(root.attributes, [](const auto& a) { return a.first == "width" || a.first == "height"; });
  root.attributes.push_back({"width", em});
  root.attributes.push_back({"height", em});
  if (!current_color.empty() && !root.attribute("color")) root.attributes.push_back({"color", current_color});
  const std::string glyph = "glyph" + std::to_string(id);
  if (const auto target = doc.ids.find(glyph); target != doc.ids.end() && target->second == &root) return doc;
  auto defs = std::make_unique<Element>();
  defs->name = "defs";
  defs->parent = &root;
  defs->children = std::move(root.children);
  for (auto& child : defs->children) child->parent = defs.get();
  auto use = std::make_unique<Element>();
  use->name = "use";
  use->attributes.push_back({"href", "#" + glyph});
  use->parent = &root;
  root.children.clear();
  root.children.push_back(std::move(defs));
  root.children.push_back(std::move(use));
  return doc;
}

}  // namespace

std::shared_ptr<const SvgGlyphSource> Converter::svg_glyph_source(const text::FontDb& db, int face, uint32_t glyph) {
  // A document holds the glyph only with an element glyph<ID>; without
  // one the outline is drawn.
  auto holding = [&](const std::shared_ptr<const SvgGlyphSource>& s) -> std::shared_ptr<const SvgGlyphSource> {
    return s->doc && s->doc->ids.count("glyph" + std::to_string(glyph)) ? s : nullptr;
  };
  std::vector<std::shared_ptr<const SvgGlyphSource>>& sources = s_.svg_glyph_sources[face];
  for (const auto& s : sources)
    if (glyph >= s->first && glyph <= s->last) return holding(s);
  if (s_.plain_glyphs.count({face, glyph})) return nullptr;
  std::optional<text::SvgDocument> found = text::svg_document(db, face, glyph);
  if (!found) {
    s_.plain_glyphs.insert({face, glyph});
    return nullptr;
  }
  auto s = std::make_shared<SvgGlyphSource>();
  s->first = found->first_glyph;
  s->last = found->last_glyph;
  s->units_per_em = text::metrics(db, face, 1).units_per_em;
  s->font = db.faces()[face].family;
  try {
    // No loader: its style sheets' @import and <?xml-stylesheet?> read
    // nothing.
    s->doc = std::make_shared<const Document>(parse_document(found->text));
  } catch (const Error& err) {
    warn("an SVG glyph document of '" + s->font + "' does not parse (" + err.what() + "): its outlines are drawn");
  }
  sources.push_back(s);
  return holding(s);
}

void Converter::draw_svg_glyph(const TextPiece& piece, const Affine& space) {
  // currentColor is the text's fill, as for COLR's foreground layers; a
  // paint server leaves it black.
  std::string current;
  if (piece.st.inh.fill.kind == PaintSpec::Kind::Color) {
    const RGBA& c = piece.st.inh.fill.color;
    auto byte = [](float v) { return static_cast<unsigned>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255)); };
    char hex[16];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x%02x", byte(c.r), byte(c.g), byte(c.b), byte(c.a));
    current = hex;
  }
  const auto [it, added] = s_.svg_glyphs.try_emplace({piece.svg_glyph.get(), piece.svg_glyph_id, current});
  LoadedImage& li = it->second;
  if (added) {
    li.svg = std::make_shared<const Document>(glyph_drawing(*piece.svg_glyph, piece.svg_glyph_id, current));
    li.reads_nothing = true;
  }
  // Drawn as an embedded SVG document is (svg_image.cpp): its own
  // converter, under the same budgets; not clipped to the em square.
  const std::string shown = "glyph" + std::to_string(piece.svg_glyph_id) + " of " + piece.svg_glyph->font;
  auto viewport = [](double w, double h) { return ViewBox{0, 0, w, h}; };
  const double opacity = piece.st.inh.fill_opacity;
  if (!(opacity > 0)) return;
  std::optional<Embedded> doc = embed_document(li, shown, viewport, AspectRatio{}, space * piece.image_xf);
  if (!doc || doc->scene.paths.empty()) return;
  append_glyph_drawing(std::move(doc->scene), space * piece.image_xf * doc->place, opacity);
}

void Converter::append_glyph_drawing(Scene scene, const Affine& xf, double opacity) {
  if (!(opacity > 0)) return;
  // fill-opacity fades the glyph as a whole, as it does COLR's layers
  // (and the outline a browser without colour glyphs draws instead).
  if (opacity < 1) {
    Group g;
    g.opacity = static_cast<float>(opacity);
    Op begin = Op::of(OpKind::GroupBegin);
    begin.scene = static_cast<uint32_t>(groups_.size());
    groups_.push_back(g);
    ops_.push_back(begin);
  }
  Op append = Op::of(OpKind::Append);
  append.scene = static_cast<uint32_t>(embedded_.size());
  append.xf = xf;
  embedded_.push_back(std::move(scene));
  ops_.push_back(append);
  if (opacity < 1) ops_.push_back(Op::of(OpKind::GroupEnd));
}

std::shared_ptr<const Scene> Converter::colr_glyph(const text::FontDb& db, int face, uint32_t glyph,
                                                   const std::vector<std::pair<std::string, double>>& variations,
                                                   const RGBA& foreground) {
  std::string axes;
  for (const auto& [tag, value] : variations) axes += tag + "=" + std::to_string(value) + ";";
  const auto key = std::tuple(face, glyph, axes, std::array<float, 4>{foreground.r, foreground.g, foreground.b, foreground.a});
  if (const auto it = s_.colr_glyphs.find(key); it != s_.colr_glyphs.end()) return it->second;
  text::ColorGlyphOptions o;
  o.foreground = foreground;
  o.variations = variations;
  std::vector<std::string> warnings;
  std::shared_ptr<const Scene> scene = text::color_glyph_scene(db, face, glyph, o, &warnings);
  for (const std::string& w : warnings) warn(w);
  s_.colr_glyphs.emplace(key, scene);
  return scene;
}

void Converter::clip_text(const Element& e, const Style& st, const Affine& space) {
  // Each span's glyphs clip with its clip-rule; the clip path is their union
  // (a bitmap glyph clips with its rectangle, an SVG glyph with its outline).
  for (TextPiece& piece : layout_text(e, st, space)) {
    Op op = Op::of(OpKind::Clip);
    op.shape = static_cast<uint32_t>(shapes_.size());
    add_shape(std::move(piece.path));
    op.xf = space;
    op.rule = piece.st.inh.clip_rule;
    op.aliased = piece.st.inh.aliased_text;
    ops_.push_back(op);
  }
}

}  // namespace mpvg::svg::detail
