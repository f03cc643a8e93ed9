// Markers (SVG 2 painting.html#Markers): marker-start, marker-mid and
// marker-end (and the marker shorthand in style sheets) on every shape.
// Each marker's content is drawn at its vertices in a coordinate system at
// the vertex, turned by orient (auto: the bisector
// of the directions in and out, as resvg computes it; auto-start-reverse;
// an angle), scaled by the stroke width (markerUnits strokeWidth), its
// viewBox fitted to markerWidth x markerHeight, refX/refY on the vertex;
// overflow hidden (the default) clips it to that viewport. Markers are
// painted in paint-order's markers layer, after fill and stroke by
// default. Vertices: every subpath's start, every command's end (an arc is
// one segment, as in browsers; resvg marks the joints of the cubics it
// approximates an arc with), a closepath's return to the start (not a mid
// marker), as in resvg.
#include <algorithm>
#include <cmath>
#include <optional>

#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_values.h"

namespace mpvg::svg::detail {

namespace {

// The path as resvg's marker code sees it: moves, lines, cubics (quadratics
// raised, conic arcs as their cubics), closes (the closing line implicit).
struct Seg {
  enum Kind { Move, Line, Cubic, Close } kind;
  Vec2 c1, c2, p;
};

// An arc command is one segment, however many conic pieces it became:
// `continued` (sorted) lists the pieces that extend the one before.
std::vector<Seg> marker_segments(const Path& path, const std::vector<uint32_t>& continued) {
  std::vector<Seg> out;
  const auto& pts = path.points();
  for (const Path::Contour& c : path.contours()) {
    const Vec2 start = pts[c.start_point];
    out.push_back({Seg::Move, {}, {}, start});
    for (uint32_t k = 0; k < c.segment_count; k++) {
      const Path::Segment& sg = path.segments()[c.first_segment + k];
      const Vec2* q = &pts[sg.first_point];
      // The closing line that Path::close added: implicit in a close.
      if (c.closed && k + 1 == c.segment_count && sg.type == SegmentType::Line && q[1] == start && k > 0) break;
      switch (sg.type) {
        case SegmentType::Line: out.push_back({Seg::Line, {}, {}, q[1]}); break;
        default: {
          const std::array<Vec2, 4> cubic = segment_cubic(path, sg);
          if (out.back().kind == Seg::Cubic &&
              std::binary_search(continued.begin(), continued.end(), c.first_segment + k)) {
            // Leaving the direction out of the command's start as it was.
            out.back().c2 = cubic[2];
            out.back().p = cubic[3];
            break;
          }
          out.push_back({Seg::Cubic, cubic[1], cubic[2], cubic[3]});
          break;
        }
      }
    }
    if (c.closed) out.push_back({Seg::Close, {}, {}, start});
  }
  return out;
}

double normalize(double rad) {
  const double v = std::fmod(rad, 2 * M_PI);
  return v < 0 ? v + 2 * M_PI : v;
}

double vector_angle(double vx, double vy) {
  const double rad = std::atan2(vy, vx);
  return std::isnan(rad) ? 0 : normalize(rad);
}

// The bisector of the direction (x1,y1)->(x2,y2) and (x3,y3)->(x4,y4), in degrees.
double angle_between(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double in = vector_angle(b.x - a.x, b.y - a.y), out = vector_angle(d.x - c.x, d.y - c.y);
  const double half = (out - in) * 0.5;
  double angle = in + half;
  if (M_PI_2 < std::abs(half)) angle -= M_PI;
  return normalize(angle) * 180 / M_PI;
}

double line_angle(Vec2 a, Vec2 b) { return angle_between(a, b, a, b); }

Vec2 subpath_start(const std::vector<Seg>& s, size_t idx) {
  for (size_t i = idx + 1; i-- > 0;)
    if (s[i].kind == Seg::Move) return s[i].p;
  return {};
}

Vec2 prev_vertex(const std::vector<Seg>& s, size_t idx) {
  if (idx == 0) return {};
  const Seg& p = s[idx - 1];
  return p.kind == Seg::Close ? subpath_start(s, idx - 1) : p.p;
}

// The direction into the vertex at the end of segment idx, and out of it
// along segment idx + 1 (SVG 2 painting.html#OrientAttribute: a curve's
// direction at an end runs to the nearest control point that differs
// from it). nullopt at a move. A zero-length segment's direction is the
// zero vector, whose angle is 0: Chrome and resvg orient markers at its
// ends so (a start marker on "M p L p L q" points along +x, the mid
// marker between the two segments halfway between +x and q - p), where
// SVG 2's path directionality would borrow the neighbours' directions.
std::optional<Vec2> dir_in(const std::vector<Seg>& s, size_t idx) {
  if (idx == 0 || idx >= s.size()) return std::nullopt;
  const Seg& g = s[idx];
  const Vec2 prev = prev_vertex(s, idx);
  Vec2 from = prev, to = g.p;
  switch (g.kind) {
    case Seg::Move: return std::nullopt;
    case Seg::Line: break;
    case Seg::Cubic: from = g.c2 != g.p ? g.c2 : g.c1 != g.p ? g.c1 : prev; break;
    case Seg::Close: to = subpath_start(s, idx); break;
  }
  return Vec2{to.x - from.x, to.y - from.y};
}

std::optional<Vec2> dir_out(const std::vector<Seg>& s, size_t idx) {
  if (idx + 1 >= s.size()) return std::nullopt;
  const Vec2 at = s[idx].kind == Seg::Close ? subpath_start(s, idx) : s[idx].p;
  const Seg& g = s[idx + 1];
  Vec2 to = g.p;
  switch (g.kind) {
    case Seg::Move: return std::nullopt;
    case Seg::Line: break;
    case Seg::Cubic: to = g.c1 != at ? g.c1 : g.c2 != at ? g.c2 : g.p; break;
    case Seg::Close: to = subpath_start(s, idx + 1); break;
  }
  return Vec2{to.x - at.x, to.y - at.y};
}

// orient="auto" at vertex idx (degrees): the bisector of the directions
// in and out (resvg's rule for its direction: half the turn from in to
// out, the other way when that is more than a quarter turn), or the one
// there is. At a path's end after a closepath, only the closing line's.
double vertex_angle(const std::vector<Seg>& s, size_t idx) {
  const bool last = idx + 1 == s.size();
  const std::optional<Vec2> in = dir_in(s, idx), out = last ? std::nullopt : dir_out(s, idx);
  if (in && out) return angle_between({0, 0}, *in, {0, 0}, *out);
  if (in) return line_angle({0, 0}, *in);
  if (out) return line_angle({0, 0}, *out);
  return 0;
}

// An angle: a number with deg, rad, grad or turn, or none (degrees).
std::optional<double> parse_angle(std::string_view v) {
  static const struct {
    const char* unit;
    double deg;
  } units[] = {{"deg", 1}, {"grad", 0.9}, {"rad", 180 / M_PI}, {"turn", 360}};
  double k = 1;
  for (const auto& u : units) {
    const size_t n = std::char_traits<char>::length(u.unit);
    if (v.size() > n && v.substr(v.size() - n) == u.unit) {
      v = v.substr(0, v.size() - n);
      k = u.deg;
      break;
    }
  }
  const auto x = parse_number(v);
  if (!x) return std::nullopt;
  return *x * k;
}

}  // namespace

const Context& Converter::marker_context(const Element& m, Context& scratch) {
  if (const auto it = marker_contexts_.find(&m); it != marker_contexts_.end()) return it->second;
  bool contextual = false;
  for (const Element* a = m.parent; a && !contextual; a = a->parent)
    for (const char* name : {"fill", "stroke"}) {
      auto mentions = [](const std::string& v) { return v.find("context-") != std::string::npos; };
      if (const std::string* v = a->attribute(name); v && mentions(*v)) contextual = true;
      for (const auto& [k, v] : a->declarations)
        if (k == name && mentions(v)) contextual = true;
    }
  if (contextual) return scratch = document_context(m, false);
  return marker_contexts_.emplace(&m, document_context(m, false)).first->second;
}

void Converter::draw_markers(const Element& e, const Style& st, uint32_t shape, const Affine& space, int depth) {
  const Inherited& inh = st.inh;
  if (inh.marker_start.empty() && inh.marker_mid.empty() && inh.marker_end.empty()) return;
  // Every shape is markable in SVG 2 (resvg marks rect, circle and ellipse
  // too, along the paths they stand for).
  if (!(e.name == "path" || e.name == "line" || e.name == "polyline" || e.name == "polygon" || e.name == "rect" ||
        e.name == "circle" || e.name == "ellipse"))
    return;
  // Vertices are the path data's: an arc's conic pieces meet at none.
  static const std::vector<uint32_t> none;
  const auto arcs = arc_continuations_.find(shape);
  const std::vector<Seg> segs = marker_segments(shapes_[shape], arcs == arc_continuations_.end() ? none : arcs->second);
  if (segs.empty()) return;
  // The shape is the markers' context element: context-fill and
  // context-stroke inside them are its paints.
  Bounds box;
  add_path_bounds(shapes_[shape], Affine{}, box);
  contexts_.push_back({inh.fill, inh.stroke, space, box});
  const int saved_context = context_;
  context_ = static_cast<int>(contexts_.size()) - 1;
  struct Restore {
    int& slot;
    int value;
    ~Restore() { slot = value; }
  } restore{context_, saved_context};
  enum Which { Start, Mid, End };
  for (Which which : {Start, Mid, End}) {
    const std::string& value = which == Start ? inh.marker_start : which == Mid ? inh.marker_mid : inh.marker_end;
    if (value.empty()) continue;
    const ClipRef ref = resolve_reference(value, "marker", "marker", s_.active);
    if (ref.state != ClipRef::Valid) continue;
    const Element& m = *ref.element;
    Context scratch;
    const Style mst = compute_style(m, marker_context(m, scratch));
    const double em = mst.inh.font_size;
    const double mw = length(m, "markerWidth", Axis::X, 3, em), mh = length(m, "markerHeight", Axis::Y, 3, em);
    if (!(mw > 0 && mh > 0)) continue;
    const std::string* units = m.attribute("markerUnits");
    const double scale = units && trim(*units) == "userSpaceOnUse" ? 1 : inh.stroke_width;
    std::optional<ViewBox> vb;
    if (const std::string* a = m.attribute("viewBox")) vb = parse_view_box(*a);
    if (vb && !(vb->w > 0 && vb->h > 0)) continue;
    AspectRatio ar;
    if (const std::string* a = m.attribute("preserveAspectRatio")) ar = parse_aspect_ratio(*a).value_or(ar);
    const Affine vbt = vb ? view_box_transform(*vb, ar, mw, mh) : Affine{};
    const Vec2 refp = vbt.apply({length(m, "refX", Axis::X, 0, em), length(m, "refY", Axis::Y, 0, em)});
    // orient: auto, auto-start-reverse or an angle (deg, rad, grad, turn or a number).
    bool automatic = false, reverse_start = false;
    double fixed = 0;
    if (const std::string* o = m.attribute("orient")) {
      const std::string_view v = trim(*o);
      if (v == "auto") automatic = true;
      else if (v == "auto-start-reverse") automatic = reverse_start = true;
      else if (const auto a = parse_angle(v)) fixed = *a;
    }
    const bool clipped = clips_overflow(m);

    auto draw_at = [&](Vec2 p, size_t idx) {
      double angle = fixed;
      if (automatic) {
        angle = vertex_angle(segs, idx);
        if (reverse_start && which == Start) angle += 180;
      }
      double sn, cs;  // exact on the axes, as the transform attribute's rotate
      sincos_snapped(angle * M_PI / 180, sn, cs);
      const Affine at = space * Affine::translate(p.x, p.y) * Affine{cs, sn, -sn, cs, 0, 0} *
                        Affine::scale(scale, scale) * Affine::translate(-refp.x, -refp.y);
      if (!at.invertible()) return;
      const size_t first = ops_.size();
      if (clipped) {
        ops_.push_back(Op::of(OpKind::Push));
        Op c = Op::of(OpKind::Clip);
        c.shape = rect_shape({0, 0, mw, mh});
        c.xf = at;
        ops_.push_back(c);
        ops_.push_back(Op::of(OpKind::Activate));
      }
      const Context inner = child_context(mst, at * vbt, false);
      s_.active.push_back(&m);
      for (const auto& c : m.children) render(*c, inner, depth + 1);
      s_.active.pop_back();
      if (clipped) ops_.push_back(Op::of(OpKind::Pop));
      for (size_t k = first; k < ops_.size(); k++) ops_[k].marker = true;
    };
    if (which == Start) {
      if (segs[0].kind == Seg::Move) draw_at(segs[0].p, 0);
    } else if (which == Mid) {
      for (size_t i = 1; i + 1 < segs.size(); i++)
        if (segs[i].kind != Seg::Close) draw_at(segs[i].p, i);
    } else {
      const size_t i = segs.size() - 1;
      draw_at(segs[i].kind == Seg::Close ? subpath_start(segs, i) : segs[i].p, i);
    }
  }
}

}  // namespace mpvg::svg::detail
