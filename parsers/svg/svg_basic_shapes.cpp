// clip-path basic shapes and reference boxes (CSS Masking 1 §3.1, CSS
// Shapes 1 §3.1): the value grammar, the shapes resolved against their
// reference box, and the clip they put around an element's content.
#include "parsers/svg/svg_basic_shapes.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "stroker/stroke_input.h"
#include "cpu/cpu_stages.h"

namespace mpvg::svg::detail {

namespace {

// The component values of `s` (CSS Syntax 3, simplified to what the
// grammar below needs): whitespace separates them, a comma or a slash is
// one of its own, a function keeps its (nested) parentheses and a quoted
// string its quotes. nullopt on unbalanced parentheses or quotes.
std::optional<std::vector<std::string_view>> components(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  auto skip_string = [&](size_t& j) {
    const char q = s[j];
    const size_t close = s.find(q, j + 1);
    if (close == std::string_view::npos) return false;
    j = close + 1;
    return true;
  };
  while (i < s.size()) {
    if (is_ws(s[i])) {
      i++;
      continue;
    }
    const size_t start = i;
    if (s[i] == ',' || s[i] == '/') {
      out.push_back(s.substr(i++, 1));
      continue;
    }
    int depth = 0;
    while (i < s.size()) {
      const char c = s[i];
      if (c == '"' || c == '\'') {
        if (!skip_string(i)) return std::nullopt;
        continue;
      }
      if (depth == 0 && (is_ws(c) || c == ',' || c == '/')) break;
      if (c == '(') depth++;
      if (c == ')' && --depth < 0) return std::nullopt;
      i++;
    }
    if (depth != 0) return std::nullopt;
    out.push_back(s.substr(start, i - start));
  }
  return out;
}

// A function component "name(args)": its name lower-cased and its
// arguments' text; nullopt for anything else.
std::optional<std::pair<std::string, std::string_view>> function(std::string_view t) {
  const size_t open = t.find('(');
  if (open == 0 || open == std::string_view::npos || t.back() != ')') return std::nullopt;
  std::string name;
  for (char c : t.substr(0, open)) {
    if (!(std::isalpha(static_cast<unsigned char>(c)) || c == '-')) return std::nullopt;
    name += ascii_lower(c);
  }
  return std::pair(name, t.substr(open + 1, t.size() - open - 2));
}

bool is_word(std::string_view t, std::string_view w) { return iequals(t, w); }

std::optional<Length> length_percentage(std::string_view t) { return parse_length(t, CalcOk::Yes); }

// A length or percentage that may not be negative (calc() is clamped when
// resolved instead, CSS Values 4 §10.12).
std::optional<Length> non_negative(std::string_view t) {
  const auto l = length_percentage(t);
  if (!l || (l->unit != Unit::Calc && l->value < 0)) return std::nullopt;
  return l;
}

std::optional<ReferenceBox> geometry_box(std::string_view t) {
  if (is_word(t, "fill-box") || is_word(t, "content-box") || is_word(t, "padding-box")) return ReferenceBox::Fill;
  if (is_word(t, "stroke-box") || is_word(t, "border-box") || is_word(t, "margin-box")) return ReferenceBox::Stroke;
  if (is_word(t, "view-box")) return ReferenceBox::View;
  return std::nullopt;
}

std::optional<ShapeRadius> shape_radius(std::string_view t) {
  ShapeRadius r;
  if (is_word(t, "closest-side")) return r;
  if (is_word(t, "farthest-side")) {
    r.kind = ShapeRadius::Kind::FarthestSide;
    return r;
  }
  const auto l = non_negative(t);
  if (!l) return std::nullopt;
  r.kind = ShapeRadius::Kind::Length;
  r.length = *l;
  return r;
}

// <position> (CSS Values 4 §9.2, without the three-value form): one
// value, two values (horizontal first unless both are keywords), or
// four (keyword and offset pairs, in either order).
std::optional<std::array<PositionOffset, 2>> position(const std::vector<std::string_view>& t) {
  enum Side { X, Y, Either, None };
  auto side = [](std::string_view w) {
    if (is_word(w, "left") || is_word(w, "right")) return X;
    if (is_word(w, "top") || is_word(w, "bottom")) return Y;
    if (is_word(w, "center")) return Either;
    return None;
  };
  // A keyword as an offset: center is 50%, right and bottom 0 from the end.
  auto keyword = [](std::string_view w) {
    PositionOffset p;
    if (!is_word(w, "center")) p.offset = Length{0, Unit::None};
    p.from_end = is_word(w, "right") || is_word(w, "bottom");
    return p;
  };
  std::array<PositionOffset, 2> out;
  if (t.size() == 1) {
    if (side(t[0]) == None) {
      const auto l = length_percentage(t[0]);
      if (!l) return std::nullopt;
      out[0].offset = *l;
    } else {
      out[side(t[0]) == Y ? 1 : 0] = keyword(t[0]);
    }
    return out;
  }
  if (t.size() == 2) {
    const Side a = side(t[0]), b = side(t[1]);
    auto coord = [&](std::string_view w, Side s) -> std::optional<PositionOffset> {
      if (s != None) return keyword(w);
      const auto l = length_percentage(w);
      if (!l) return std::nullopt;
      PositionOffset p;
      p.offset = *l;
      return p;
    };
    std::optional<PositionOffset> x, y;
    if ((a == X || a == Either || a == None) && (b == Y || b == Either || b == None)) {
      x = coord(t[0], a);
      y = coord(t[1], b);
    } else if ((a == Y || a == Either) && (b == X || b == Either)) {
      x = keyword(t[1]);
      y = keyword(t[0]);
    }
    if (!x || !y) return std::nullopt;
    return std::array{*x, *y};
  }
  if (t.size() == 4) {
    bool seen[2] = {false, false};
    for (int i = 0; i < 4; i += 2) {
      const Side s = side(t[i]);
      const auto l = length_percentage(t[i + 1]);
      if ((s != X && s != Y) || !l) return std::nullopt;
      if (seen[s]) return std::nullopt;
      seen[s] = true;
      out[s].offset = *l;
      out[s].from_end = is_word(t[i], "right") || is_word(t[i], "bottom");
    }
    return out;
  }
  return std::nullopt;
}

// circle( <shape-radius>? [at <position>]? ), ellipse( [<shape-radius>{2}]?
// [at <position>]? ).
bool circle_or_ellipse(const std::vector<std::string_view>& t, size_t nradii, BasicShape& out) {
  const auto at = std::find_if(t.begin(), t.end(), [](std::string_view w) { return is_word(w, "at"); });
  const size_t given = static_cast<size_t>(at - t.begin());
  if (given != 0 && given != nradii) return false;
  for (size_t i = 0; i < given; i++) {
    const auto r = shape_radius(t[i]);
    if (!r) return false;
    out.radii[i] = *r;
  }
  if (at == t.end()) return true;
  const auto c = position(std::vector<std::string_view>(at + 1, t.end()));
  if (!c) return false;
  out.center = *c;
  return true;
}

// 1 to 4 values for 4 sides or corners, as the margin and border-radius
// shorthands expand them (top/left first, clockwise).
template <class T>
bool four(const std::vector<T>& v, T* out) {
  if (v.empty() || v.size() > 4) return false;
  out[0] = v[0];
  out[1] = v.size() > 1 ? v[1] : v[0];
  out[2] = v.size() > 2 ? v[2] : v[0];
  out[3] = v.size() > 3 ? v[3] : out[1];
  return true;
}

// inset( <length-percentage>{1,4} [round <'border-radius'>]? ).
bool inset(const std::vector<std::string_view>& t, BasicShape& out) {
  const auto round = std::find_if(t.begin(), t.end(), [](std::string_view w) { return is_word(w, "round"); });
  std::vector<Length> sides;
  for (auto it = t.begin(); it != round; ++it) {
    const auto l = length_percentage(*it);
    if (!l) return false;
    sides.push_back(*l);
  }
  if (!four(sides, out.inset.data())) return false;
  if (round == t.end()) return true;
  std::vector<Length> radii[2];
  int part = 0;
  for (auto it = round + 1; it != t.end(); ++it) {
    if (*it == "/" && part == 0) {
      part = 1;
      continue;
    }
    const auto l = non_negative(*it);
    if (!l) return false;
    radii[part].push_back(*l);
  }
  if (part == 0) radii[1] = radii[0];
  return four(radii[0], out.corners.data()) && four(radii[1], out.corners.data() + 4);
}

// The components of a comma-separated argument list, list by list.
std::vector<std::vector<std::string_view>> comma_groups(const std::vector<std::string_view>& t) {
  std::vector<std::vector<std::string_view>> out(1);
  for (std::string_view w : t) {
    if (w == ",") out.emplace_back();
    else out.back().push_back(w);
  }
  return out;
}

// An optional leading <'fill-rule'> argument of polygon() and path();
// removes it from `groups`, setting *given when it was there. False when
// it is there but not followed by anything.
bool leading_fill_rule(std::vector<std::vector<std::string_view>>& groups, FillRule& rule, bool* given = nullptr) {
  if (groups.front().size() != 1) return true;
  const std::string_view w = groups.front()[0];
  if (!is_word(w, "nonzero") && !is_word(w, "evenodd")) return true;
  rule = is_word(w, "evenodd") ? FillRule::EvenOdd : FillRule::NonZero;
  if (given) *given = true;
  groups.erase(groups.begin());
  return !groups.empty();
}

// polygon( <'fill-rule'>? , [<length-percentage> <length-percentage>]# ).
bool polygon(const std::vector<std::string_view>& t, BasicShape& out) {
  auto groups = comma_groups(t);
  if (!leading_fill_rule(groups, out.rule)) return false;
  for (const auto& g : groups) {
    if (g.size() != 2) return false;
    const auto x = length_percentage(g[0]), y = length_percentage(g[1]);
    if (!x || !y) return false;
    out.points.emplace_back(*x, *y);
  }
  return true;
}

// A CSS string token (CSS Syntax 3 §4.3.5) holding path data: its text
// between the quotes. One with an escape, which path data never needs, or
// a newline (a bad string) is taken as invalid.
std::optional<std::string_view> path_string(std::string_view t) {
  if (t.size() < 2 || (t[0] != '"' && t[0] != '\'') || t.back() != t[0]) return std::nullopt;
  const std::string_view data = t.substr(1, t.size() - 2);
  if (data.find_first_of("\\\n") != std::string_view::npos) return std::nullopt;
  return data;
}

// path( <'fill-rule'>? , <string> ): SVG path data that must parse whole.
bool path(const std::vector<std::string_view>& t, BasicShape& out, bool* rule_given = nullptr) {
  auto groups = comma_groups(t);
  if (!leading_fill_rule(groups, out.rule, rule_given) || groups.size() != 1 || groups[0].size() != 1) return false;
  const auto data = path_string(groups[0][0]);
  if (!data) return false;
  out.path_data = std::string(*data);
  Path scratch;
  return parse_path_data(out.path_data, scratch);
}

std::optional<BasicShape> basic_shape(const std::string& name, std::string_view args) {
  const auto t = components(args);
  if (!t) return std::nullopt;
  BasicShape s;
  bool ok = false;
  if (name == "circle") {
    s.kind = BasicShape::Kind::Circle;
    ok = circle_or_ellipse(*t, 1, s);
  } else if (name == "ellipse") {
    s.kind = BasicShape::Kind::Ellipse;
    ok = circle_or_ellipse(*t, 2, s);
  } else if (name == "inset") {
    s.kind = BasicShape::Kind::Inset;
    ok = inset(*t, s);
  } else if (name == "polygon") {
    s.kind = BasicShape::Kind::Polygon;
    ok = polygon(*t, s);
  } else if (name == "path") {
    s.kind = BasicShape::Kind::Path;
    ok = path(*t, s);
  }
  if (!ok) return std::nullopt;
  return s;
}

bool is_shape_function(const std::string& name) {
  return name == "circle" || name == "ellipse" || name == "inset" || name == "polygon" || name == "path";
}

}  // namespace

std::optional<CssPath> parse_css_path(std::string_view value) {
  const auto t = components(value);
  if (!t || t->size() != 1) return std::nullopt;
  const auto f = function(t->front());
  if (!f || f->first != "path") return std::nullopt;
  const auto args = components(f->second);
  if (!args) return std::nullopt;
  BasicShape s;
  bool rule_given = false;
  if (!path(*args, s, &rule_given)) return std::nullopt;
  CssPath out;
  if (rule_given) out.rule = s.rule;
  out.data = std::move(s.path_data);
  return out;
}

std::optional<ClipShape> parse_clip_shape(std::string_view value, bool* invalid) {
  *invalid = false;
  const auto t = components(value);
  if (!t) return std::nullopt;
  auto ours = [](std::string_view w) {
    const auto f = function(w);
    return geometry_box(w).has_value() || (f && is_shape_function(f->first));
  };
  if (std::none_of(t->begin(), t->end(), ours)) return std::nullopt;
  *invalid = true;
  if (t->size() > 2) return std::nullopt;
  ClipShape cs;
  bool has_box = false;
  for (std::string_view w : *t) {
    if (const auto b = geometry_box(w); b && !has_box) {
      cs.box = *b;
      has_box = true;
      continue;
    }
    const auto f = function(w);
    if (!f || cs.shape.kind != BasicShape::Kind::None) return std::nullopt;
    auto s = basic_shape(f->first, f->second);
    if (!s) return std::nullopt;
    cs.shape = std::move(*s);
  }
  *invalid = false;
  return cs;
}

Path clip_shape_path(const ClipShape& cs, const Bounds& box, double em, double rem) {
  const BasicShape& s = cs.shape;
  const double w = box.width(), h = box.height();
  // Percentages: horizontal ones of the box's width, vertical ones of its
  // height, other ones of its normalised diagonal (CSS Shapes 1 §3.1).
  auto len = [&](const Length& l, double base) { return resolve_length(l, base, em, rem); };
  auto at = [&](const PositionOffset& p, double start, double size) {
    const double v = len(p.offset, size);
    return p.from_end ? start + size - v : start + v;
  };
  switch (s.kind) {
    case BasicShape::Kind::None: return rect_path(box.x0, box.y0, w, h, 0, 0);
    case BasicShape::Kind::Circle:
    case BasicShape::Kind::Ellipse: {
      const double cx = at(s.center[0], box.x0, w), cy = at(s.center[1], box.y0, h);
      // The distances from the centre to the box's sides along x, along y.
      const double dx[2] = {std::abs(cx - box.x0), std::abs(cx - box.x1)};
      const double dy[2] = {std::abs(cy - box.y0), std::abs(cy - box.y1)};
      auto radius = [&](const ShapeRadius& r, double base, const double* d, int n) {
        if (r.kind == ShapeRadius::Kind::Length) return std::max(0.0, len(r.length, base));
        const bool closest = r.kind == ShapeRadius::Kind::ClosestSide;
        double v = closest ? std::min(d[0], d[1]) : std::max(d[0], d[1]);
        if (n > 2) v = closest ? std::min({v, dy[0], dy[1]}) : std::max({v, dy[0], dy[1]});
        return v;
      };
      double rx, ry;
      if (s.kind == BasicShape::Kind::Circle) {
        rx = ry = radius(s.radii[0], std::sqrt((w * w + h * h) / 2), dx, 4);
      } else {
        rx = radius(s.radii[0], w, dx, 2);
        ry = radius(s.radii[1], h, dy, 2);
      }
      if (!(rx > 0 && ry > 0)) return Path();
      return ellipse_path(cx, cy, rx, ry);
    }
    case BasicShape::Kind::Inset: {
      const double top = len(s.inset[0], h), right = len(s.inset[1], w);
      const double bottom = len(s.inset[2], h), left = len(s.inset[3], w);
      const double x = box.x0 + left, y = box.y0 + top, iw = w - left - right, ih = h - top - bottom;
      if (!(iw > 0 && ih > 0)) return Path();
      // Corner radii as Chromium resolves them, percentages of the
      // reference box; then scaled down together until the radii along
      // each side fit it (CSS Backgrounds 3 §5.5).
      double rx[4], ry[4];
      for (int i = 0; i < 4; i++) {
        rx[i] = std::max(0.0, len(s.corners[i], w));
        ry[i] = std::max(0.0, len(s.corners[4 + i], h));
      }
      double f = 1;
      for (int i = 0; i < 4; i++) {
        const double along = i % 2 == 0 ? rx[i] + rx[(i + 1) % 4] : ry[i] + ry[(i + 1) % 4];
        if (along > 0) f = std::min(f, (i % 2 == 0 ? iw : ih) / along);
      }
      // Corners clockwise from top-left, and the directions of the edges
      // that leave them (top, right, bottom, left); a corner is a quarter
      // ellipse, a conic with its control point on the corner.
      const Vec2 corner[4] = {{x, y}, {x + iw, y}, {x + iw, y + ih}, {x, y + ih}};
      const Vec2 dir[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
      auto reach = [&](int c, int edge) { return (edge % 2 == 0 ? rx[c] : ry[c]) * f; };
      auto round = [&](int c) { return rx[c] > 0 && ry[c] > 0; };
      PathBuilder pb;
      pb.move_to(round(0) ? corner[0] + reach(0, 0) * dir[0] : corner[0]);
      for (int k = 1; k <= 4; k++) {
        const int c = k % 4, in = (c + 3) % 4;
        if (!round(c)) {
          if (pb.current_point() != corner[c]) pb.line_to(corner[c]);
          continue;
        }
        const Vec2 from = corner[c] - reach(c, in) * dir[in];
        if (pb.current_point() != from) pb.line_to(from);
        pb.rquad_to(corner[c], corner[c] + reach(c, c) * dir[c], M_SQRT1_2);
      }
      pb.close();
      return pb.take();
    }
    case BasicShape::Kind::Polygon: {
      std::vector<Vec2> pts;
      for (const auto& [px, py] : s.points) pts.push_back({box.x0 + len(px, w), box.y0 + len(py, h)});
      return poly_path(pts, true);
    }
    case BasicShape::Kind::Path: {
      // The path's coordinates are relative to the reference box's origin.
      Path p;
      parse_path_data(s.path_data, p);
      return p.transformed(Affine::translate(box.x0, box.y0));
    }
  }
  return Path();
}

// The stroke's part of a stroke bounding box (SVG 2
// coords.html#TermStrokeBoundingBox): the box of the stroke shape without
// its dashes, built to 1/16 of an output pixel (`to_pixels` maps the
// centreline there) and mapped back by `from_pixels`.
void add_stroke_bounds(const Path& centreline, StrokeStyle style, const Affine& to_pixels, const Affine& from_pixels,
                       Bounds& b) {
  style.dashes.clear();
  StrokeBatch batch;
  if (!batch.add(centreline, style, to_pixels, 0)) return;
  PathBuilder pb;
  for (const InputSegment& sg : stroke_cpu(batch, 1)) {
    pb.move_to({sg.x[0], sg.y[0]});
    switch (sg.type) {
      case INPUT_LINE: pb.line_to({sg.x[1], sg.y[1]}); break;
      case INPUT_QUAD: pb.quad_to({sg.x[1], sg.y[1]}, {sg.x[2], sg.y[2]}); break;
      case INPUT_RQUAD: pb.rquad_to({sg.x[1], sg.y[1]}, {sg.x[2], sg.y[2]}, sg.w); break;
      default: pb.cubic_to({sg.x[1], sg.y[1]}, {sg.x[2], sg.y[2]}, {sg.x[3], sg.y[3]}); break;
    }
  }
  add_path_bounds(pb.take(), from_pixels, b);
}

}  // namespace mpvg::svg::detail
