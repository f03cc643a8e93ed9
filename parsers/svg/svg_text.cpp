// SVG text (SVG 2 text.html, SVG 1.1 §10): the characters of a <text> and
// the tspans inside it, white space handled (xml:space), positioned by the
// x, y, dx, dy and rotate lists, cut into chunks at absolute positions and
// anchored (text-anchor), shaped by HarfBuzz in the faces CSS font matching
// picks (text/text.h, per-character fallback), and drawn as glyph outlines
// kept as curves: each span's glyphs become one shape painted with that
// span's fill and stroke, like any path.
//
// Not yet: textPath, tref, baselines other than the alphabetic one,
// text-decoration, vertical writing, bidi reordering across spans,
// textLength, font-variant and feature settings, text inside clip paths.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>

#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_values.h"
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

// UTF-8 to code points, with each one's byte offset; invalid bytes become
// U+FFFD.
void decode_utf8(const std::string& s, std::vector<char32_t>& cps) {
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    int n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    char32_t cp = n == 1 ? c : n == 2 ? (c & 0x1f) : n == 3 ? (c & 0x0f) : (c & 0x07);
    bool ok = n > 0 && i + n <= s.size();
    for (int k = 1; ok && k < n; k++) {
      const unsigned char d = static_cast<unsigned char>(s[i + k]);
      ok = (d >> 6) == 2;
      cp = (cp << 6) | (d & 0x3f);
    }
    cps.push_back(ok ? cp : 0xfffd);
    i += ok ? n : 1;
  }
}

void encode_utf8(char32_t c, std::string& out) {
  if (c < 0x80) {
    out += char(c);
  } else if (c < 0x800) {
    out += char(0xc0 | (c >> 6));
    out += char(0x80 | (c & 0x3f));
  } else if (c < 0x10000) {
    out += char(0xe0 | (c >> 12));
    out += char(0x80 | ((c >> 6) & 0x3f));
    out += char(0x80 | (c & 0x3f));
  } else {
    out += char(0xf0 | (c >> 18));
    out += char(0x80 | ((c >> 12) & 0x3f));
    out += char(0x80 | ((c >> 6) & 0x3f));
    out += char(0x80 | (c & 0x3f));
  }
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

// A textPath's path as straight pieces with their lengths, in the text's
// user space: curves sampled finely (32 pieces each), a closed contour's
// closing line added, the moves between subpaths not counted.
struct Polyline {
  struct Piece {
    Vec2 a, b;
    double start, length;  // distance along the path where it starts
  };
  std::vector<Piece> pieces;
  double total = 0;

  explicit Polyline(const Path& path) {
    const auto& pts = path.points();
    const auto& w = path.weights();
    auto add = [&](Vec2 a, Vec2 b) {
      const double l = std::hypot(b.x - a.x, b.y - a.y);
      if (l <= 0) return;
      pieces.push_back({a, b, total, l});
      total += l;
    };
    for (const Path::Contour& c : path.contours()) {
      Vec2 last = pts[c.start_point];
      for (uint32_t k = 0; k < c.segment_count; k++) {
        const Path::Segment& sg = path.segments()[c.first_segment + k];
        const Vec2* q = &pts[sg.first_point];
        if (sg.type == SegmentType::Line) {
          add(q[0], q[1]);
          last = q[1];
          continue;
        }
        const int n = 32;
        Vec2 prev = q[0];
        for (int i = 1; i <= n; i++) {
          const double t = double(i) / n, u = 1 - t;
          Vec2 p;
          if (sg.type == SegmentType::Quad) {
            p = {u * u * q[0].x + 2 * u * t * q[1].x + t * t * q[2].x, u * u * q[0].y + 2 * u * t * q[1].y + t * t * q[2].y};
          } else if (sg.type == SegmentType::RQuad) {
            const double wm = w[sg.first_weight], d = u * u + 2 * wm * u * t + t * t;
            p = {(u * u * q[0].x + 2 * wm * u * t * q[1].x + t * t * q[2].x) / d,
                 (u * u * q[0].y + 2 * wm * u * t * q[1].y + t * t * q[2].y) / d};
          } else {
            p = {u * u * u * q[0].x + 3 * u * u * t * q[1].x + 3 * u * t * t * q[2].x + t * t * t * q[3].x,
                 u * u * u * q[0].y + 3 * u * u * t * q[1].y + 3 * u * t * t * q[2].y + t * t * t * q[3].y};
          }
          add(prev, p);
          prev = p;
        }
        last = prev;
      }
      if (c.closed) add(last, pts[c.start_point]);
    }
  }

  // The point and direction (radians) at distance d; false off the path.
  bool at(double d, Vec2& p, double& angle) const {
    if (pieces.empty() || d < 0 || d > total) return false;
    size_t lo = 0, hi = pieces.size() - 1;
    while (lo < hi) {  // the last piece starting at or before d
      const size_t mid = (lo + hi + 1) / 2;
      if (pieces[mid].start <= d) lo = mid;
      else hi = mid - 1;
    }
    const Piece& pc = pieces[lo];
    const double t = std::clamp((d - pc.start) / pc.length, 0.0, 1.0);
    p = {pc.a.x + (pc.b.x - pc.a.x) * t, pc.a.y + (pc.b.y - pc.a.y) * t};
    angle = std::atan2(pc.b.y - pc.a.y, pc.b.x - pc.a.x);
    return true;
  }
};

// One character of the text, after white-space handling.
struct Char {
  char32_t c = 0;
  int span = 0;  // index into the spans
  std::optional<double> x, y;
  double dx = 0, dy = 0;
  std::optional<double> rotate;
};

// A text content element with its computed style.
struct Span {
  const Element* e = nullptr;
  Style st;
  int first = 0, end = 0;  // its characters (descendants' included)
  double shift = 0;        // baseline-shift, its ancestors' included (y up)
  // alignment-baseline of the span or the nearest span around it (its
  // content aligns as one box), over dominant-baseline.
  std::optional<Inherited::Baseline> align;
  int path = -1;            // the textPath it is in (index into the polylines), or -1
  double start_offset = 0;  // that textPath's startOffset, resolved
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

}  // namespace

std::vector<Converter::TextPiece> Converter::layout_text(const Element& root, const Style& root_style,
                                                        const Affine& space) {
  std::vector<TextPiece> pieces;
  std::vector<std::string> font_warnings;
  const text::FontDb& db = font_db(s_.options.font_dirs, s_.options.system_fonts, &font_warnings);
  for (const std::string& w : font_warnings) warn(w);
  if (db.faces().empty()) {
    warn("no fonts found (see --font-dir): text not rendered");
    return pieces;
  }

  // The characters, in document order, with white space handled (SVG 2
  // text.html#WhiteSpace, the xml:space rules of SVG 1.1 §10.15): newlines
  // removed and tabs made spaces; unless preserved, runs of spaces become
  // one and the text's leading and trailing spaces go.
  std::vector<Span> spans;
  std::vector<Char> chars;
  bool last_space = true;  // at the start, a space is leading
  double parent_shift = 0;
  std::optional<Inherited::Baseline> parent_align;
  std::vector<Polyline> polylines;  // the textPaths' paths
  int current_path = -1;
  double current_offset = 0;
  std::function<void(const Element&, const Style&, int)> collect =
      [&](const Element& e, const Style& st, int depth) {
        const int index = static_cast<int>(spans.size());
        // baseline-shift (not inherited; nested shifts add up): a length,
        // a percentage of the font size, or baseline. sub and super use the
        // usual 1/3 and 1/5 of an em as no metrics give them here.
        double shift = depth == 0 || !e.parent ? 0 : parent_shift;
        if (depth > 0) {
          const auto bs = property<double>(e, "baseline-shift", [&](std::string_view v) -> std::optional<double> {
            const auto k = parse_keyword(v);
            if (k == "baseline") return 0.0;
            if (k == "sub") return -st.inh.font_size / 5;
            if (k == "super") return st.inh.font_size / 3;
            const auto l = parse_length(v);
            if (!l) return std::nullopt;
            if (l->unit == Unit::Percent) return l->value / 100 * st.inh.font_size;
            return to_user(*l, Axis::Y, st.inh.font_size);
          });
          if (bs.state == Prop<double>::Set) shift += bs.value;
        }
        std::optional<Inherited::Baseline> align = parent_align;
        if (depth > 0) {
          const auto ab = property<int>(e, "alignment-baseline", [](std::string_view v) -> std::optional<int> {
            using B = Inherited::Baseline;
            const auto k = parse_keyword(v);
            if (k == "auto" || k == "baseline") return -1;
            if (k == "alphabetic") return int(B::Alphabetic);
            if (k == "middle") return int(B::Middle);
            if (k == "central") return int(B::Central);
            if (k == "hanging") return int(B::Hanging);
            if (k == "mathematical") return int(B::Mathematical);
            if (k == "text-before-edge" || k == "before-edge" || k == "text-top" || k == "top") return int(B::TextTop);
            if (k == "text-after-edge" || k == "after-edge" || k == "text-bottom" || k == "bottom")
              return int(B::TextBottom);
            if (k == "ideographic") return int(B::Ideographic);
            return std::nullopt;
          });
          if (ab.state == Prop<int>::Set)
            align = ab.value < 0 ? std::nullopt : std::optional(static_cast<Inherited::Baseline>(ab.value));
        }
        spans.push_back({&e, st, static_cast<int>(chars.size()), 0, shift, align, current_path, current_offset});
        const double saved_shift = parent_shift;
        const std::optional<Inherited::Baseline> saved_align = parent_align;
        parent_shift = shift;
        parent_align = align;
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
            std::vector<char32_t> cps;
            decode_utf8(c->text, cps);
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
              ch.span = index;
              chars.push_back(ch);
            }
          } else if (c->name == "tspan" || c->name == "a" || (c->name == "tref" && depth < 2)) {
            if (depth > 64) continue;
            const Style cs = compute_style(*c, inner);
            if (cs.display_none) continue;
            collect(*c, cs, depth + 1);
          } else if (c->name == "textPath" && depth == 0) {
            // SVG 2 text.html#TextPathElement: the path (or basic shape) it
            // names, with that element's own transform.
            const std::string* href = c->attribute("href");
            if (!href) href = c->attribute("xlink:href");
            const Element* target = nullptr;
            if (href && href->size() > 1 && (*href)[0] == '#') {
              const auto it = s_.doc.ids.find(href->substr(1));
              if (it != s_.doc.ids.end()) target = it->second;
            }
            if (!target) continue;  // renders nothing (resvg: no-link)
            std::optional<Path> shape = build_shape(*target, st.inh.font_size);
            if (!shape) continue;
            Affine xf;
            if (const std::string* t = target->attribute("transform"))
              if (const auto m = parse_transform(*t)) xf = *m;
            polylines.emplace_back(shape->transformed(xf));
            const Style cs = compute_style(*c, inner);
            if (cs.display_none) continue;
            const double total = polylines.back().total;
            double offset = 0;
            if (const std::string* so = c->attribute("startOffset"))
              if (const auto l = parse_length(*so))
                offset = l->unit == Unit::Percent ? l->value / 100 * total : to_user(*l, Axis::X, cs.inh.font_size);
            current_path = static_cast<int>(polylines.size()) - 1;
            current_offset = offset;
            collect(*c, cs, depth + 1);
            current_path = -1;
          } else if (c->name == "textPath") {
            warn("<textPath> inside another text content element is not supported: ignored");
          }
        }
        spans[index].end = static_cast<int>(chars.size());
        parent_shift = saved_shift;
        parent_align = saved_align;
      };
  collect(root, root_style, 0);
  if (!root_style.inh.space_preserve)
    while (!chars.empty() && chars.back().c == ' ' && !spans[chars.back().span].st.inh.space_preserve) {
      chars.pop_back();
      for (Span& sp : spans) sp.end = std::min(sp.end, static_cast<int>(chars.size()));
    }
  if (chars.empty()) return pieces;

  // Positions: each element's lists apply to its characters in order,
  // descendants' own values over their ancestors' (spans are in pre-order,
  // so later assignments are the deeper ones).
  for (const Span& sp : spans) {
    const double em = sp.st.inh.font_size;
    auto ux = [&](const Length& l) { return to_user(l, Axis::X, em); };
    auto uy = [&](const Length& l) { return to_user(l, Axis::Y, em); };
    const auto xs = number_list(*sp.e, "x", ux), ys = number_list(*sp.e, "y", uy);
    const auto dxs = number_list(*sp.e, "dx", ux), dys = number_list(*sp.e, "dy", uy);
    // rotate takes plain numbers (degrees): a list with anything else
    // (a unit) is invalid as a whole and ignored.
    bool rotate_valid = true;
    auto rs = number_list(*sp.e, "rotate", [&](const Length& l) {
      if (l.unit != Unit::None) rotate_valid = false;
      return l.value;
    });
    if (!rotate_valid) rs.clear();
    for (int i = sp.first; i < sp.end; i++) {
      const size_t k = size_t(i - sp.first);
      if (k < xs.size()) chars[i].x = xs[k];
      if (k < ys.size()) chars[i].y = ys[k];
      if (k < dxs.size()) chars[i].dx = dxs[k];
      if (k < dys.size()) chars[i].dy = dys[k];
      // rotate's last value holds for the characters after it.
      if (!rs.empty()) chars[i].rotate = rs[std::min(k, rs.size() - 1)];
    }
  }

  // Layout: chunks start at characters with an absolute x or y; within a
  // chunk, runs of one span and one face are shaped together.
  struct Glyph {
    int span;
    int face;
    uint32_t id;
    double x, y, size;
    double rotate;
    int ch;          // its cluster's first character
    double advance;  // the pen's move after it (letter spacing included)
  };
  std::vector<Glyph> glyphs;
  double pen_x = 0, pen_y = 0;
  size_t chunk_start = 0;  // first glyph of the chunk
  double chunk_x = 0;
  Inherited::Anchor chunk_anchor = Inherited::Anchor::Start;
  double trailing_spacing = 0;  // letter spacing after the chunk's last character
  auto end_chunk = [&]() {
    // The chunk's advance, without the spacing after its last character.
    const double width = pen_x - chunk_x - trailing_spacing;
    const double shift = chunk_anchor == Inherited::Anchor::Middle ? -width / 2
                         : chunk_anchor == Inherited::Anchor::End  ? -width
                                                                   : 0;
    for (size_t g = chunk_start; g < glyphs.size(); g++) glyphs[g].x += shift;
    chunk_start = glyphs.size();
  };
  // Each span's face, matched once (a character the face lacks falls back
  // on its own).
  std::vector<int> span_face(spans.size(), -2);
  auto matched_face = [&](int span) {
    if (span_face[span] == -2) {
      const Inherited& inh = spans[span].st.inh;
      span_face[span] = db.match(inh.font_family, inh.font_weight, inh.font_italic, inh.font_stretch);
    }
    return span_face[span];
  };
  auto face_for = [&](int span, char32_t c) {
    const Inherited& inh = spans[span].st.inh;
    const int face = matched_face(span);
    if (face < 0 || c == ' ' || db.has_glyph(face, c)) return face;
    const int other = db.fallback(c, inh.font_weight, inh.font_italic);
    return other >= 0 ? other : face;
  };
  for (size_t i = 0; i < chars.size();) {
    const Char& first = chars[i];
    const bool path_change = i > 0 && spans[first.span].path != spans[chars[i - 1].span].path;
    if (i == 0 || first.x || first.y || path_change) {
      if (i > 0) end_chunk();
      if (spans[first.span].path >= 0 && (i == 0 || path_change)) {
        // Along a path: x is the distance along it, y the offset across.
        pen_x = 0;
        pen_y = 0;
      }
      if (first.x) pen_x = *first.x;
      if (first.y) pen_y = *first.y;
      chunk_x = pen_x;
      chunk_anchor = spans[first.span].st.inh.text_anchor;
    }
    // The run: same span and face, no new chunk, no rotation change.
    const Inherited& inh = spans[first.span].st.inh;
    const int face = face_for(first.span, first.c);
    size_t j = i + 1;
    while (j < chars.size() && chars[j].span == first.span && !chars[j].x && !chars[j].y &&
           face_for(first.span, chars[j].c) == face)
      j++;
    if (face < 0) {
      i = j;
      continue;
    }
    std::string utf8;
    std::vector<size_t> char_of_byte;  // byte offset -> character index
    for (size_t k = i; k < j; k++) {
      const size_t before = utf8.size();
      encode_utf8(chars[k].c, utf8);
      char_of_byte.resize(utf8.size(), k);
      (void)before;
    }
    const double size = inh.font_size;
    text::ShapeOptions so;
    so.variations = variations_of(inh);
    // The run's baseline: dominant-baseline from the face's metrics (y
    // down: how far the alphabetic baseline sits below the chosen one),
    // then baseline-shift.
    double baseline_offset = -spans[first.span].shift;
    {
      const text::Metrics m = text::metrics(db, face, size);
      using B = Inherited::Baseline;
      switch (spans[first.span].align.value_or(inh.dominant_baseline)) {
        case B::Alphabetic: break;
        case B::Middle: baseline_offset += m.x_height / 2; break;
        case B::Central: baseline_offset += (m.ascent - m.descent) / 2; break;
        case B::Hanging: baseline_offset += 0.8 * m.ascent; break;
        case B::Mathematical: baseline_offset += 0.5 * m.ascent; break;
        case B::TextTop: baseline_offset += m.ascent; break;
        case B::TextBottom:
        case B::Ideographic: baseline_offset -= m.descent; break;
      }
    }
    const std::vector<text::ShapedGlyph> shaped = text::shape(db, face, utf8, size, so);
    size_t last_char = SIZE_MAX;
    for (const text::ShapedGlyph& g : shaped) {
      const size_t k = g.cluster < char_of_byte.size() ? char_of_byte[g.cluster] : i;
      if (k != last_char) {
        // dx and dy move the pen before the cluster's first glyph.
        pen_x += chars[k].dx;
        pen_y += chars[k].dy;
      }
      glyphs.push_back({first.span, face, g.glyph, pen_x + g.x_offset, pen_y + g.y_offset + baseline_offset, size,
                        chars[k].rotate.value_or(0), static_cast<int>(k), 0});
      const double before = pen_x;
      pen_x += g.x_advance;
      pen_y += g.y_advance;
      if (k != last_char) {
        pen_x += inh.letter_spacing;
        trailing_spacing = inh.letter_spacing;
        if (chars[k].c == ' ') pen_x += inh.word_spacing;
      }
      glyphs.back().advance = pen_x - before;
      last_char = k;
    }
    i = j;
  }
  end_chunk();

  // Each span's glyphs as one shape, painted with the span's style.
  std::vector<Path> paths(spans.size());
  for (const Glyph& g : glyphs) {
    const Path outline = text::glyph_outline(db, g.face, g.id, g.size, variations_of(spans[g.span].st.inh));
    if (outline.empty()) continue;
    Affine place = Affine::translate(g.x, g.y);
    if (const Span& sp = spans[g.span]; sp.path >= 0) {
      // The glyph's middle on the path, turned with it; glyphs whose
      // middle falls off the path are not drawn.
      Vec2 p, p0, p1;
      double angle, a0, a1;
      const double d = sp.start_offset + g.x;
      if (!polylines[sp.path].at(d + g.advance / 2, p, angle)) continue;
      // Turned by the chord from the glyph's start to its end on the path.
      if (polylines[sp.path].at(d, p0, a0) && polylines[sp.path].at(d + g.advance, p1, a1))
        angle = std::atan2(p1.y - p0.y, p1.x - p0.x);
      place = Affine::translate(p.x, p.y) * Affine::rotate_degrees(angle * 180 / M_PI) *
              Affine::translate(-g.advance / 2, g.y);
    }
    if (g.rotate != 0) place = place * Affine::rotate_degrees(g.rotate);
    paths[g.span].append(outline.transformed(place));
  }
  // text-decoration (CSS Text Decoration 3, SVG 2 text.html#TextDecorationProperties):
  // a decoration on the text or outside it is painted with the text's
  // style, one on a tspan with the tspan's, under every glyph of the
  // element (each at its own baseline: dy moves the line with it), from
  // the metrics of the element's font. Underlines and overlines go under
  // the glyphs, line-throughs over them.
  enum Line { Under = 1, Over = 2, Through = 4 };
  auto decoration_of = [](const Element& e) {
    const auto d = property<int>(e, "text-decoration", [](std::string_view v) -> std::optional<int> {
      int lines = 0;
      for (size_t pos = 0; pos < v.size();) {
        const size_t b = v.find_first_not_of(" \t\n\r", pos);
        if (b == std::string_view::npos) break;
        size_t end = v.find_first_of(" \t\n\r", b);
        if (end == std::string_view::npos) end = v.size();
        const std::string_view w = v.substr(b, end - b);
        if (w == "underline") lines |= Under;
        else if (w == "overline") lines |= Over;
        else if (w == "line-through") lines |= Through;
        else if (w != "none") return std::nullopt;
        pos = end;
      }
      return lines;
    });
    return d.state == Prop<int>::Set ? d.value : 0;
  };
  struct Decoration {
    int span;   // whose characters, and whose style paints it
    int lines;
  };
  std::vector<Decoration> decorations;
  {
    int outer = 0;
    for (const Element* a = &root; a; a = a->parent) outer |= decoration_of(*a);
    if (outer) decorations.push_back({0, outer});
    for (size_t k = 1; k < spans.size(); k++)
      if (const int d = decoration_of(*spans[k].e)) decorations.push_back({static_cast<int>(k), d});
  }
  auto decoration_path = [&](const Decoration& d, int line) {
    Path p;
    const Span& sp = spans[d.span];
    const int face = matched_face(d.span);
    if (face < 0) return p;
    const text::Metrics m = text::metrics(db, face, sp.st.inh.font_size);
    double offset, thickness;
    if (line == Under) {
      // FreeType's position is the post table's moved down by half the
      // thickness; the line is centred on the table's own (as resvg draws it).
      offset = m.underline_position - m.underline_thickness / 2;
      thickness = m.underline_thickness;
    } else if (line == Over) {
      offset = -m.ascent;  // centred on the ascent line
      thickness = m.underline_thickness;
    } else {
      offset = m.strikeout_position;
      thickness = m.strikeout_thickness;
    }
    // The lines' centres at offset (y down; FreeType gives the stems'
    // centres), one rectangle per run of glyphs that touch at one baseline
    // (so that a stroked decoration has no joins).
    bool open = false;
    double rx0 = 0, rx1 = 0, ry = 0;
    auto flush = [&] {
      if (open) p.append(Path::rectangle(rx0, ry - thickness / 2, rx1, ry + thickness / 2));
      open = false;
    };
    for (const Glyph& g : glyphs) {
      if (g.ch < sp.first || g.ch >= sp.end || g.advance == 0) continue;
      const double x0 = std::min(g.x, g.x + g.advance), x1 = std::max(g.x, g.x + g.advance), y = g.y + offset;
      if (open && y == ry && std::abs(x0 - rx1) < 1e-9 * std::max(1.0, std::abs(x0))) {
        rx1 = x1;
        continue;
      }
      flush();
      open = true;
      rx0 = x0, rx1 = x1, ry = y;
    }
    flush();
    return p;
  };
  auto add_decorations = [&](bool over) {
    for (const Decoration& d : decorations)
      for (int line : {Under, Over, Through}) {
        if (!(d.lines & line) || (line == Through) != over || !spans[d.span].st.inh.visible) continue;
        Path p = decoration_path(d, line);
        if (!p.empty()) pieces.push_back({std::move(p), spans[d.span].st});
      }
  };
  add_decorations(false);
  for (size_t k = 0; k < spans.size(); k++)
    if (!paths[k].empty() && spans[k].st.inh.visible) {
      // fill-rule does not apply to text (SVG 2 text.html#TextRenderingOrder):
      // glyphs fill by non-zero winding, overlapping contours included.
      Style st = spans[k].st;
      st.inh.fill_rule = FillRule::NonZero;
      pieces.push_back({std::move(paths[k]), st});
    }
  add_decorations(true);
  return pieces;
}

void Converter::text(const Element& e, const Style& st, const Affine& space) {
  for (TextPiece& piece : layout_text(e, st, space)) {
    const uint32_t shape = static_cast<uint32_t>(shapes_.size());
    shapes_.push_back(std::move(piece.path));
    paint_shape(shape, piece.st, space, true);
  }
}

void Converter::clip_text(const Element& e, const Style& st, const Affine& space) {
  // Each span's glyphs clip with its clip-rule; the clip path is their union.
  for (TextPiece& piece : layout_text(e, st, space)) {
    Op op = Op::of(OpKind::Clip);
    op.shape = static_cast<uint32_t>(shapes_.size());
    shapes_.push_back(std::move(piece.path));
    op.xf = space;
    op.rule = piece.st.inh.clip_rule;
    ops_.push_back(op);
  }
}

}  // namespace mpvg::svg::detail
