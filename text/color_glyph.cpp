// COLR v1 paint graphs to core scenes (color_glyph.h). Two passes: the graph
// is read through FreeType's COLR v1 API under the db's mutex (with_ft_face)
// into a tree of Nodes, palette colours resolved and cycles cut; it is then
// lowered with SceneBuilder outside the mutex, since glyph_outline takes it
// itself.
#include "text/color_glyph.h"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_COLOR_H
#include FT_SIZES_H
#include FT_TRUETYPE_TABLES_H

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <optional>

#include "core/error.h"
#include "frame/scene_builder.h"

namespace mpvg::text {

namespace {

// A DAG read as a tree: a shared sub-graph counts each time it is reached.
constexpr size_t kMaxNodes = size_t(1) << 16;

struct Box {  // x0 <= x1, y0 <= y1 unless empty()
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  bool empty() const { return !(x0 <= x1 && y0 <= y1); }
  void add(Vec2 p) {
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  // The box of this box's corners mapped by m.
  Box mapped(const Affine& m) const {
    Box r;
    for (Vec2 p : {Vec2{x0, y0}, Vec2{x1, y0}, Vec2{x1, y1}, Vec2{x0, y1}}) r.add(m.apply(p));
    return r;
  }
};

struct Warnings {
  std::vector<std::string>* out;
  void once(const std::string& w) const {
    if (out && std::find(out->begin(), out->end(), w) == out->end()) out->push_back(w);
  }
};

struct ColorLine {
  std::vector<ColorStop> stops;  // by offset (stable: equal offsets keep their order), any offsets
  Spread spread = Spread::Pad;
};

struct Node {
  enum class Kind : uint8_t { Layers, Solid, Linear, Radial, Sweep, Glyph, ColrGlyph, Transform, Composite };
  Kind kind = Kind::Layers;
  // Layers: the layers, bottom first; Glyph, ColrGlyph, Transform: the
  // child; Composite: source, backdrop. -1: a paint not read (nothing).
  std::vector<int32_t> children;
  uint32_t glyph = 0;  // Glyph: the outline's; ColrGlyph: the base glyph's
  Affine m;            // Transform: child space to parent space (font units)
  FT_Composite_Mode mode = FT_COLR_COMPOSITE_SRC_OVER;
  RGBA color;          // Solid, straight
  ColorLine line;      // gradients
  Vec2 p[3];           // Linear: p0, p1, p2; Radial: c0, c1; Sweep: the centre
  double a = 0, b = 0; // Radial: r0, r1; Sweep: start, end angle (degrees, counter-clockwise from +x)
  Box clip;            // ColrGlyph: the referenced glyph's clip box, font units (empty: none)

  bool is_fill() const {
    return kind == Kind::Solid || kind == Kind::Linear || kind == Kind::Radial || kind == Kind::Sweep;
  }
};

double fixed(FT_Fixed v) { return v / 65536.0; }
Vec2 fixed(const FT_Vector& v) { return {fixed(v.x), fixed(v.y)}; }

// FreeType 2.13 widened FT_ColorStop::stop_offset from F2Dot14 to 16.16.
template <typename T>
double stop_offset(T v) {
  return sizeof(T) == sizeof(FT_F2Dot14) ? v / 16384.0 : v / 65536.0;
}

// The paint graph of one glyph, read under the db's mutex.
struct Reader {
  FT_Face f;
  const ColorGlyphOptions& opts;
  const Warnings& warn;
  const FT_Color* palette = nullptr;
  unsigned palette_size = 0;
  std::vector<Node> nodes;
  std::vector<const FT_Byte*> active;  // the paints on the path from the root: a repeat is a cycle

  RGBA color(FT_UInt16 index, FT_F2Dot14 alpha) const {
    RGBA c = opts.foreground;
    if (index != 0xFFFF) {
      if (palette && index < palette_size) {
        const FT_Color& p = palette[index];
        c = {p.red / 255.0f, p.green / 255.0f, p.blue / 255.0f, p.alpha / 255.0f};
      } else {
        warn.once("COLR: palette index " + std::to_string(index) + " out of range: the text's colour used");
      }
    }
    c.a = std::clamp(c.a * static_cast<float>(alpha / 16384.0), 0.0f, 1.0f);
    return c;
  }

  ColorLine line(const FT_ColorLine& cl) const {
    ColorLine l;
    l.spread = cl.extend == FT_COLR_PAINT_EXTEND_REPEAT    ? Spread::Repeat
               : cl.extend == FT_COLR_PAINT_EXTEND_REFLECT ? Spread::Reflect
                                                           : Spread::Pad;
    FT_ColorStopIterator it = cl.color_stop_iterator;
    FT_ColorStop s;
    while (FT_Get_Colorline_Stops(f, &s, &it))
      l.stops.push_back({stop_offset(s.stop_offset), color(s.color.palette_index, s.color.alpha)});
    std::stable_sort(l.stops.begin(), l.stops.end(),
                     [](const ColorStop& x, const ColorStop& y) { return x.offset < y.offset; });
    return l;
  }

  // The glyph's clip box in font units. FreeType scales it by the active
  // size: a size of its own at one pixel per font unit (64 in 26.6) gives
  // font units, and leaves the face's size as it was.
  Box clip_box(uint32_t glyph) const {
    Box r;
    FT_Size old = f->size, tmp = nullptr;
    if (FT_New_Size(f, &tmp) != 0) return r;
    if (FT_Activate_Size(tmp) == 0 &&
        FT_Set_Char_Size(f, 0, static_cast<FT_F26Dot6>(f->units_per_EM ? f->units_per_EM : 1000) << 6, 72, 72) == 0) {
      FT_ClipBox cb;
      if (FT_Get_Color_Glyph_ClipBox(f, glyph, &cb))
        for (const FT_Vector& v : {cb.bottom_left, cb.top_left, cb.top_right, cb.bottom_right})
          r.add({v.x / 64.0, v.y / 64.0});
    }
    FT_Activate_Size(old);
    FT_Done_Size(tmp);
    return r;
  }

  // Transforms about a centre: to it, the transform, back.
  static Affine about(const Affine& t, double cx, double cy) {
    return Affine::translate(cx, cy) * t * Affine::translate(-cx, -cy);
  }

  int32_t read(FT_OpaquePaint op, int depth) {
    if (depth >= kMaxPaintDepth) {
      warn.once("COLR: paint graph deeper than " + std::to_string(kMaxPaintDepth) + " paints: cut there");
      return -1;
    }
    if (nodes.size() >= kMaxNodes) {
      warn.once("COLR: paint graph of more than " + std::to_string(kMaxNodes) + " paints: cut");
      return -1;
    }
    if (std::find(active.begin(), active.end(), op.p) != active.end()) {
      warn.once("COLR: cycle in the paint graph: cut");
      return -1;
    }
    FT_COLR_Paint p;
    p.format = FT_COLR_PAINTFORMAT_UNSUPPORTED;
    if (!FT_Get_Paint(f, op, &p)) {
      // FreeType sets the format before it gives up on one it does not
      // read (2.12: the variable formats, PaintVar*).
      warn.once(p.format != FT_COLR_PAINTFORMAT_UNSUPPORTED
                    ? "COLR: paint format " + std::to_string(int(p.format)) + " unsupported (FreeType " +
                          std::to_string(FREETYPE_MAJOR) + "." + std::to_string(FREETYPE_MINOR) + "): skipped"
                    : std::string("COLR: unreadable paint: skipped"));
      return -1;
    }
    active.push_back(op.p);
    Node n;
    using K = Node::Kind;
    switch (p.format) {
      case FT_COLR_PAINTFORMAT_COLR_LAYERS: {
        n.kind = K::Layers;
        FT_LayerIterator it = p.u.colr_layers.layer_iterator;
        FT_OpaquePaint layer{nullptr, 0};
        while (FT_Get_Paint_Layers(f, &it, &layer)) n.children.push_back(read(layer, depth + 1));
        break;
      }
      case FT_COLR_PAINTFORMAT_SOLID:
        n.kind = K::Solid;
        n.color = color(p.u.solid.color.palette_index, p.u.solid.color.alpha);
        break;
      case FT_COLR_PAINTFORMAT_LINEAR_GRADIENT:
        n.kind = K::Linear;
        n.line = line(p.u.linear_gradient.colorline);
        n.p[0] = fixed(p.u.linear_gradient.p0);
        n.p[1] = fixed(p.u.linear_gradient.p1);
        n.p[2] = fixed(p.u.linear_gradient.p2);
        break;
      case FT_COLR_PAINTFORMAT_RADIAL_GRADIENT:
        n.kind = K::Radial;
        n.line = line(p.u.radial_gradient.colorline);
        n.p[0] = fixed(p.u.radial_gradient.c0);
        n.p[1] = fixed(p.u.radial_gradient.c1);
        n.a = fixed(p.u.radial_gradient.r0);
        n.b = fixed(p.u.radial_gradient.r1);
        break;
      case FT_COLR_PAINTFORMAT_SWEEP_GRADIENT:
        n.kind = K::Sweep;
        n.line = line(p.u.sweep_gradient.colorline);
        n.p[0] = fixed(p.u.sweep_gradient.center);
        // 180 degrees per unit, with OpenType 1.9.1's bias of 1 (180
        // degrees), which FreeType leaves to its callers (as Skia adds it).
        n.a = fixed(p.u.sweep_gradient.start_angle) * 180.0 + 180.0;
        n.b = fixed(p.u.sweep_gradient.end_angle) * 180.0 + 180.0;
        break;
      case FT_COLR_PAINTFORMAT_GLYPH:
        n.kind = K::Glyph;
        n.glyph = p.u.glyph.glyphID;
        n.children.push_back(read(p.u.glyph.paint, depth + 1));
        break;
      case FT_COLR_PAINTFORMAT_COLR_GLYPH: {
        n.kind = K::ColrGlyph;
        n.glyph = p.u.colr_glyph.glyphID;
        FT_OpaquePaint root{nullptr, 0};
        if (FT_Get_Color_Glyph_Paint(f, n.glyph, FT_COLOR_NO_ROOT_TRANSFORM, &root)) {
          n.children.push_back(read(root, depth + 1));
          n.clip = clip_box(n.glyph);
        } else {
          warn.once("COLR: PaintColrGlyph of glyph " + std::to_string(n.glyph) + ", which has no paint graph: skipped");
          n.children.push_back(-1);
        }
        break;
      }
      case FT_COLR_PAINTFORMAT_TRANSFORM: {
        const FT_Affine23& t = p.u.transform.affine;
        n.kind = K::Transform;
        // x' = xx x + xy y + dx, y' = yx x + yy y + dy.
        n.m = {fixed(t.xx), fixed(t.yx), fixed(t.xy), fixed(t.yy), fixed(t.dx), fixed(t.dy)};
        n.children.push_back(read(p.u.transform.paint, depth + 1));
        break;
      }
      case FT_COLR_PAINTFORMAT_TRANSLATE:
        n.kind = K::Transform;
        n.m = Affine::translate(fixed(p.u.translate.dx), fixed(p.u.translate.dy));
        n.children.push_back(read(p.u.translate.paint, depth + 1));
        break;
      case FT_COLR_PAINTFORMAT_SCALE:  // all four PaintScale* (no centre: (0, 0))
        n.kind = K::Transform;
        n.m = about(Affine::scale(fixed(p.u.scale.scale_x), fixed(p.u.scale.scale_y)), fixed(p.u.scale.center_x),
                    fixed(p.u.scale.center_y));
        n.children.push_back(read(p.u.scale.paint, depth + 1));
        break;
      case FT_COLR_PAINTFORMAT_ROTATE:  // counter-clockwise in font space (y up)
        n.kind = K::Transform;
        n.m = about(Affine::rotate_degrees(fixed(p.u.rotate.angle) * 180.0), fixed(p.u.rotate.center_x),
                    fixed(p.u.rotate.center_y));
        n.children.push_back(read(p.u.rotate.paint, depth + 1));
        break;
      case FT_COLR_PAINTFORMAT_SKEW: {
        // The matrix the COLR spec gives for skew angles phi (x) and psi
        // (y): xx = yy = 1, yx = tan(psi), xy = -tan(phi).
        const double phi = fixed(p.u.skew.x_skew_angle) * M_PI, psi = fixed(p.u.skew.y_skew_angle) * M_PI;
        n.kind = K::Transform;
        n.m = about(Affine{1, std::tan(psi), -std::tan(phi), 1, 0, 0}, fixed(p.u.skew.center_x),
                    fixed(p.u.skew.center_y));
        n.children.push_back(read(p.u.skew.paint, depth + 1));
        break;
      }
      case FT_COLR_PAINTFORMAT_COMPOSITE:
        n.kind = K::Composite;
        n.mode = p.u.composite.composite_mode;
        n.children.push_back(read(p.u.composite.source_paint, depth + 1));
        n.children.push_back(read(p.u.composite.backdrop_paint, depth + 1));
        break;
      default:
        warn.once("COLR: paint format " + std::to_string(int(p.format)) + " unsupported: skipped");
        active.pop_back();
        return -1;
    }
    active.pop_back();
    nodes.push_back(std::move(n));
    return static_cast<int32_t>(nodes.size() - 1);
  }
};

// COLR interpolates colour stops with premultiplied alpha ("Interpolation
// of colors", OFF AMD2 / the CPAL chapter of OpenType 1.9); core's ramps
// interpolate straight alpha. Equal alphas interpolate alike. Where one end
// is transparent, giving it the other's colour is exact (the colour stays,
// alpha is linear). Otherwise the straight ramp gets stops added until its
// premultiplied colour is within 1/1024 of the premultiplied
// interpolation's. Each segment starts with its own copy of its first stop
// (a step of zero height where it differs from the previous segment's end).
std::vector<ColorStop> premultiplied_stops(const std::vector<ColorStop>& in) {
  if (in.size() < 2) return in;
  auto exact = [](const ColorStop& a, const ColorStop& b, double s) {  // at a + s (b - a)
    const double al = a.color.a + s * (b.color.a - a.color.a);
    auto ch = [&](float x, float y) {
      return al > 0 ? static_cast<float>((a.color.a * x + s * (b.color.a * y - a.color.a * x)) / al) : x;
    };
    return ColorStop{a.offset + s * (b.offset - a.offset),
                     RGBA{ch(a.color.r, b.color.r), ch(a.color.g, b.color.g), ch(a.color.b, b.color.b), float(al)}};
  };
  auto same = [](const RGBA& x, const RGBA& y) { return x.r == y.r && x.g == y.g && x.b == y.b && x.a == y.a; };
  std::vector<ColorStop> out{in[0]};
  for (size_t i = 0; i + 1 < in.size(); i++) {
    ColorStop a = in[i], b = in[i + 1];
    if (a.offset == b.offset || a.color.a == b.color.a) {
      if (!same(out.back().color, a.color)) out.push_back(a);
      out.push_back(b);
      continue;
    }
    if (a.color.a == 0) a.color = RGBA{b.color.r, b.color.g, b.color.b, 0};
    if (b.color.a == 0) b.color = RGBA{a.color.r, a.color.g, a.color.b, 0};
    if (!same(out.back().color, a.color)) out.push_back(a);
    if (a.color.a == 0 || b.color.a == 0) {
      out.push_back(b);
      continue;
    }
    // [s0, s1] of the segment, its ends exact: split at the middle while
    // the straight mix there is off.
    auto split = [&](auto&& self, double s0, const ColorStop& c0, double s1, const ColorStop& c1, int depth) -> void {
      const double sm = 0.5 * (s0 + s1);
      const ColorStop cm = exact(a, b, sm);
      const double err = cm.color.a * std::max({std::fabs(0.5 * (c0.color.r + c1.color.r) - cm.color.r),
                                                std::fabs(0.5 * (c0.color.g + c1.color.g) - cm.color.g),
                                                std::fabs(0.5 * (c0.color.b + c1.color.b) - cm.color.b)});
      if (depth < 8 && err > 1.0 / 1024) {
        self(self, s0, c0, sm, cm, depth + 1);
        self(self, sm, cm, s1, c1, depth + 1);
      } else {
        out.push_back(c1);
      }
    };
    split(split, 0.0, a, 1.0, b, 0);
  }
  return out;
}

// A colour line's stops moved to [0, 1] from [s0, s1], the span of its
// offsets (the geometry moves to s0 and s1 instead: COLR's extend modes
// repeat [s0, s1]). nullopt: nothing is painted (no stops; all at one
// offset with repeat or reflect, as Skia does).
struct Ramp {
  std::vector<ColorStop> stops;
  double s0 = 0, s1 = 1;
  Spread spread = Spread::Pad;
};
std::optional<Ramp> ramp(const ColorLine& l) {
  if (l.stops.empty()) return std::nullopt;
  Ramp r;
  r.spread = l.spread;
  std::vector<ColorStop> st = l.stops;
  if (st.size() == 1) {  // one colour everywhere
    r.stops = {{0, st[0].color}};
    r.spread = Spread::Pad;
    return r;
  }
  r.s0 = st.front().offset;
  r.s1 = st.back().offset;
  if (!(r.s1 - r.s0 > 1e-9)) {
    // Pad: the first colour below the offset, the last from it on, the
    // same as a span of 1 whose last stop is the last colour again.
    if (l.spread != Spread::Pad) return std::nullopt;
    st.push_back({r.s1 + 1, st.back().color});
    r.s1 += 1;
  }
  for (ColorStop& s : st) s.offset = std::clamp((s.offset - r.s0) / (r.s1 - r.s0), 0.0, 1.0);
  r.stops = premultiplied_stops(st);
  return r;
}

bool blend_mode(FT_Composite_Mode m, BlendMode& out) {
  switch (m) {
    case FT_COLR_COMPOSITE_SCREEN: out = BlendMode::Screen; return true;
    case FT_COLR_COMPOSITE_OVERLAY: out = BlendMode::Overlay; return true;
    case FT_COLR_COMPOSITE_DARKEN: out = BlendMode::Darken; return true;
    case FT_COLR_COMPOSITE_LIGHTEN: out = BlendMode::Lighten; return true;
    case FT_COLR_COMPOSITE_COLOR_DODGE: out = BlendMode::ColorDodge; return true;
    case FT_COLR_COMPOSITE_COLOR_BURN: out = BlendMode::ColorBurn; return true;
    case FT_COLR_COMPOSITE_HARD_LIGHT: out = BlendMode::HardLight; return true;
    case FT_COLR_COMPOSITE_SOFT_LIGHT: out = BlendMode::SoftLight; return true;
    case FT_COLR_COMPOSITE_DIFFERENCE: out = BlendMode::Difference; return true;
    case FT_COLR_COMPOSITE_EXCLUSION: out = BlendMode::Exclusion; return true;
    case FT_COLR_COMPOSITE_MULTIPLY: out = BlendMode::Multiply; return true;
    case FT_COLR_COMPOSITE_HSL_HUE: out = BlendMode::Hue; return true;
    case FT_COLR_COMPOSITE_HSL_SATURATION: out = BlendMode::Saturation; return true;
    case FT_COLR_COMPOSITE_HSL_COLOR: out = BlendMode::Color; return true;
    case FT_COLR_COMPOSITE_HSL_LUMINOSITY: out = BlendMode::Luminosity; return true;
    case FT_COLR_COMPOSITE_SRC_ATOP: out = BlendMode::SourceAtop; return true;
    case FT_COLR_COMPOSITE_XOR: out = BlendMode::Xor; return true;
    case FT_COLR_COMPOSITE_PLUS: out = BlendMode::PlusLighter; return true;
    default: return false;
  }
}

// The tree as scene content. ctm: font space (units, y up) to user units.
struct Lowering {
  Lowering(const FontDb& db, int face, const ColorGlyphOptions& opts, const std::vector<Node>& nodes,
           const Warnings& warn)
      : db(db), face(face), opts(opts), nodes(nodes), warn(warn) {}

  const FontDb& db;
  int face;
  const ColorGlyphOptions& opts;
  const std::vector<Node>& nodes;
  const Warnings& warn;
  double k = 1;        // user units per font unit
  Affine to_font;      // user units (glyph_outline's) to font units
  Box extent;          // user units: where unbounded paints are filled
  SceneBuilder* b = nullptr;
  int groups = 0;      // transparency groups and masks open
  std::map<uint32_t, Path> outlines;
  std::map<uint32_t, int64_t> geometries;  // -1: an empty outline
  int64_t extent_geometry = -1;

  const Path& outline(uint32_t glyph) {
    auto it = outlines.find(glyph);
    if (it == outlines.end())
      it = outlines.emplace(glyph, glyph_outline(db, face, glyph, opts.size, opts.variations)).first;
    return it->second;
  }

  // Where the drawing can be: outlines (their control points) and clip
  // boxes, in user units. Paints outside any PaintGlyph add nothing.
  void bounds(int32_t i, const Affine& ctm, Box& box) {
    if (i < 0) return;
    const Node& n = nodes[i];
    switch (n.kind) {
      case Node::Kind::Glyph: {
        const Affine m = ctm * to_font;
        for (Vec2 p : outline(n.glyph).points()) box.add(m.apply(p));
        return;
      }
      case Node::Kind::ColrGlyph:
        if (!n.clip.empty()) {
          const Box c = n.clip.mapped(ctm);
          box.add({c.x0, c.y0});
          box.add({c.x1, c.y1});
          return;
        }
        break;
      case Node::Kind::Transform: bounds(n.children[0], ctm * n.m, box); return;
      default: break;
    }
    for (int32_t c : n.children) bounds(c, ctm, box);
  }

  int64_t glyph_geometry(uint32_t glyph) {
    auto it = geometries.find(glyph);
    if (it != geometries.end()) return it->second;
    const Path& p = outline(glyph);
    const int64_t g = p.empty() ? -1 : int64_t(b->add_geometry(p));
    geometries.emplace(glyph, g);
    return g;
  }

  uint32_t extent_rect() {
    if (extent_geometry < 0)
      extent_geometry = b->add_geometry(Path::rectangle(extent.x0, extent.y0, extent.x1, extent.y1));
    return static_cast<uint32_t>(extent_geometry);
  }

  // A solid or gradient node as a paint whose gradient space is font space
  // mapped by m; nullopt where it paints nothing.
  std::optional<Paint> paint(const Node& n, const Affine& m) {
    Paint p;
    if (n.kind == Node::Kind::Solid) {
      p.type = PaintType::Solid;
      p.color = n.color;
      return p;
    }
    if (!m.invertible()) return std::nullopt;
    const std::optional<Ramp> r = ramp(n.line);
    if (!r) return std::nullopt;
    Gradient g;
    g.xf = m;
    g.stops = r->stops;
    g.spread = r->spread;
    g.interpolation = ColorSpace::Srgb;
    if (n.kind == Node::Kind::Linear) {
      // p3: p1 - p0 projected onto the normal of p0 -> p2 (COLR's
      // equivalent two-point line: isolines run parallel to p0 -> p2).
      const Vec2 d1 = n.p[1] - n.p[0], d2 = n.p[2] - n.p[0];
      const Vec2 normal{-d2.y, d2.x};
      const double nn = dot(normal, normal), l1 = dot(d1, d1);
      if (!(nn > 0) || !(l1 > 0) || std::fabs(cross(d1, d2)) <= 1e-9 * std::sqrt(nn * l1)) {
        warn.once("COLR: ill-formed linear gradient (p1 or p2 at p0, or p0p2 parallel to p0p1): not drawn");
        return std::nullopt;
      }
      const Vec2 p3 = n.p[0] + (dot(d1, normal) / nn) * normal;
      p.type = PaintType::LinearGradient;
      g.p0 = lerp(n.p[0], p3, r->s0);
      g.p1 = lerp(n.p[0], p3, r->s1);
    } else if (n.kind == Node::Kind::Radial) {
      if (n.p[0] == n.p[1] && n.a == n.b) return std::nullopt;  // identical circles: nothing (COLR step 1)
      p.type = PaintType::RadialGradient;
      g.focal = lerp(n.p[0], n.p[1], r->s0);
      g.center = lerp(n.p[0], n.p[1], r->s1);
      g.focal_radius = n.a + r->s0 * (n.b - n.a);
      g.radius = n.a + r->s1 * (n.b - n.a);
    } else {
      p.type = PaintType::SweepGradient;
      g.center = n.p[0];
      const double sector = n.b - n.a;
      // No sector: core's hard step at the angle with pad (Skia's rule);
      // nothing with repeat or reflect.
      if (!(std::fabs(sector) > 1e-9) && r->spread != Spread::Pad) return std::nullopt;
      g.start_angle = n.a + r->s0 * sector;
      g.end_angle = n.a + r->s1 * sector;
    }
    p.index = b->add_gradient(std::move(g));
    return p;
  }

  void draw(int32_t i, const Affine& ctm) {
    if (i < 0) return;
    const Node& n = nodes[i];
    switch (n.kind) {
      case Node::Kind::Layers:
        for (int32_t c : n.children) draw(c, ctm);
        return;
      case Node::Kind::Solid:
      case Node::Kind::Linear:
      case Node::Kind::Radial:
      case Node::Kind::Sweep:
        // Not under a PaintGlyph: everywhere, which the extent covers.
        if (std::optional<Paint> p = paint(n, ctm)) b->fill(extent_rect(), Affine{}, FillRule::NonZero, *p);
        return;
      case Node::Kind::Glyph: glyph(n, ctm); return;
      case Node::Kind::ColrGlyph:
        if (n.clip.empty()) {
          draw(n.children[0], ctm);
        } else {
          b->push();
          b->clip(b->add_geometry(Path::rectangle(n.clip.x0, n.clip.y0, n.clip.x1, n.clip.y1)), ctm, FillRule::NonZero);
          b->activate();
          draw(n.children[0], ctm);
          b->pop();
        }
        return;
      case Node::Kind::Transform: draw(n.children[0], ctm * n.m); return;
      case Node::Kind::Composite: composite(n, ctm); return;
    }
  }

  void glyph(const Node& n, const Affine& ctm) {
    const Affine oxf = ctm * to_font;  // glyph_outline's user units to ours
    const int64_t g = glyph_geometry(n.glyph);
    if (g < 0 || !oxf.invertible()) return;  // an empty clip: nothing shows
    // The child through its transforms: a solid or a gradient fills the
    // outline, anything else is drawn clipped by it.
    int32_t c = n.children[0];
    Affine m = ctm;
    while (c >= 0 && nodes[c].kind == Node::Kind::Transform) {
      m = m * nodes[c].m;
      c = nodes[c].children[0];
    }
    if (c < 0) return;
    if (nodes[c].is_fill()) {
      if (std::optional<Paint> p = paint(nodes[c], m)) b->fill(static_cast<uint32_t>(g), oxf, FillRule::NonZero, *p);
      return;
    }
    b->push();
    b->clip(static_cast<uint32_t>(g), oxf, FillRule::NonZero);
    b->activate();
    draw(n.children[0], ctm);
    b->pop();
  }

  // Room for `levels` more nested groups; else a warning.
  bool room(int levels) const {
    if (groups + levels <= kMaxColorGlyphGroups) return true;
    warn.once("COLR: composites nest deeper than " + std::to_string(kMaxColorGlyphGroups) +
              " groups: the deeper ones drawn without their groups");
    return false;
  }

  void begin(const Group& g) {
    b->begin_group(g);
    groups++;
  }
  void end() {
    b->end_group();
    groups--;
  }

  // An isolated group of `below` and, over it, `above` in a group of blend
  // mode `mode`: the blend meets only `below`.
  void blended(int32_t below, int32_t above, BlendMode mode, const Affine& ctm) {
    if (!room(2)) {
      draw(below, ctm);
      draw(above, ctm);
      return;
    }
    begin(Group{});
    draw(below, ctm);
    Group g;
    g.blend = mode;
    begin(g);
    draw(above, ctm);
    end();
    end();
  }

  // `content` times the alpha of `other` (outside: one minus it).
  void masked(int32_t content, int32_t other, bool outside, const Affine& ctm) {
    if (other < 0) {  // a transparent operand
      if (outside) draw(content, ctm);
      return;
    }
    if (!room(outside ? 4 : 2)) {
      draw(content, ctm);
      return;
    }
    begin(Group{});
    Group alpha;
    alpha.mask = MaskType::Alpha;
    if (!outside) {
      begin(alpha);
      draw(other, ctm);
      end();
    } else {
      // One minus alpha: the luminance of black, alpha-masked by `other`,
      // over white (exact where integration is sRGB-encoded, the default;
      // with linear integration the luminance is of 1 - alpha encoded).
      Group lum;
      lum.mask = MaskType::Luminance;
      lum.backdrop = RGBA{1, 1, 1, 1};
      lum.luminance_space = ColorSpace::Srgb;
      begin(lum);
      begin(Group{});
      begin(alpha);
      draw(other, ctm);
      end();
      Paint black;
      black.color = RGBA{0, 0, 0, 1};
      b->fill(extent_rect(), Affine{}, FillRule::NonZero, black);
      end();
      end();
    }
    draw(content, ctm);
    end();
  }

  void composite(const Node& n, const Affine& ctm) {
    const int32_t src = n.children[0], bd = n.children[1];
    BlendMode mode;
    switch (n.mode) {
      case FT_COLR_COMPOSITE_CLEAR: return;
      case FT_COLR_COMPOSITE_SRC: draw(src, ctm); return;
      case FT_COLR_COMPOSITE_DEST: draw(bd, ctm); return;
      case FT_COLR_COMPOSITE_SRC_OVER:  // associative with what lies below: no group
        draw(bd, ctm);
        draw(src, ctm);
        return;
      case FT_COLR_COMPOSITE_DEST_OVER:
        draw(src, ctm);
        draw(bd, ctm);
        return;
      case FT_COLR_COMPOSITE_SRC_IN: masked(src, bd, false, ctm); return;
      case FT_COLR_COMPOSITE_DEST_IN: masked(bd, src, false, ctm); return;
      case FT_COLR_COMPOSITE_SRC_OUT: masked(src, bd, true, ctm); return;
      case FT_COLR_COMPOSITE_DEST_OUT: masked(bd, src, true, ctm); return;
      case FT_COLR_COMPOSITE_DEST_ATOP: blended(src, bd, BlendMode::SourceAtop, ctm); return;
      default:
        if (blend_mode(n.mode, mode)) {
          blended(bd, src, mode, ctm);
        } else {
          warn.once("COLR: composite mode " + std::to_string(int(n.mode)) + " unknown: drawn as source over");
          draw(bd, ctm);
          draw(src, ctm);
        }
        return;
    }
  }
};

// Whether this FreeType's COLR v1 API answers at all: Debian 12's
// libfreetype6 (2.12.1+dfsg-5+deb12u3 and later) ships it disabled, every
// call returning 0. Asked where a glyph of a face whose COLR table is
// version 1 has no paint: if no glyph of the face has one either, the API
// is taken to be off (a version 1 table without a single paint graph is
// not made by font tools). Once any face answers, that is kept for the
// process: it is the library's property.
std::atomic<bool> api_answered{false}, api_off{false};

bool colr_v1_api_off(FT_Face f) {
  if (api_answered.load(std::memory_order_relaxed)) return false;
  if (api_off.load(std::memory_order_relaxed)) return true;
  // The table's version, its first field (the graph itself is FreeType's).
  FT_Byte version[2] = {0, 0};
  FT_ULong length = 2;
  if (FT_Load_Sfnt_Table(f, FT_MAKE_TAG('C', 'O', 'L', 'R'), 0, version, &length) != 0 || length < 2 ||
      ((version[0] << 8) | version[1]) < 1)
    return false;
  for (FT_Long g = 0; g < f->num_glyphs; g++) {
    FT_OpaquePaint op{nullptr, 0};
    if (FT_Get_Color_Glyph_Paint(f, static_cast<FT_UInt>(g), FT_COLOR_NO_ROOT_TRANSFORM, &op)) {
      api_answered.store(true, std::memory_order_relaxed);
      return false;
    }
  }
  api_off.store(true, std::memory_order_relaxed);
  return true;
}

// Whether the FreeType running is the one whose headers mpvg was built
// with, as far as the COLR v1 API goes: it was experimental in 2.12 (its
// structures changed in 2.13), so a build against 2.12 headers must not
// read a 2.13 library's paints, nor the other way round. Later versions
// keep the API stable.
bool same_colr_v1_abi(FT_Face f) {
  FT_Int major = 0, minor = 0, patch = 0;
  FT_Library_Version(f->glyph->library, &major, &minor, &patch);
  const bool old_headers = FREETYPE_MAJOR == 2 && FREETYPE_MINOR <= 12, old_library = major == 2 && minor <= 12;
  return (major == FREETYPE_MAJOR && minor == FREETYPE_MINOR) || (!old_headers && !old_library);
}

}  // namespace

std::shared_ptr<const Scene> color_glyph_scene(const FontDb& db, int face, uint32_t glyph,
                                               const ColorGlyphOptions& opts, std::vector<std::string>* warnings) {
  // Most faces have no colour tables: answer them without setting their
  // variation coordinates (a variable face would have them set and reset
  // for every glyph of its text).
  bool color = false;
  with_ft_face(db, face, {}, [&](void* vf) { color = vf && FT_HAS_COLOR(static_cast<FT_Face>(vf)); });
  if (!color) return nullptr;
  const Warnings warn{warnings};
  bool found = false;
  std::vector<Node> nodes;
  int32_t root = -1;
  Box clip, em;  // font units
  double upem = 1000;
  with_ft_face(db, face, opts.variations, [&](void* vf) {
    FT_Face f = static_cast<FT_Face>(vf);
    if (!f) return;
    if (!same_colr_v1_abi(f)) {
      FT_Int major = 0, minor = 0, patch = 0;
      FT_Library_Version(f->glyph->library, &major, &minor, &patch);
      warn.once("COLR: mpvg was built with FreeType " + std::to_string(FREETYPE_MAJOR) + "." +
                std::to_string(FREETYPE_MINOR) + " headers but runs with FreeType " + std::to_string(major) + "." +
                std::to_string(minor) + ", whose COLR v1 structures differ: the glyphs are not drawn from COLR v1");
      return;
    }
    FT_OpaquePaint op{nullptr, 0};
    if (!FT_Get_Color_Glyph_Paint(f, glyph, FT_COLOR_NO_ROOT_TRANSFORM, &op)) {
      if (colr_v1_api_off(f))
        warn.once("COLR: the font has COLR version 1 paint graphs, but this FreeType (" +
                  std::to_string(FREETYPE_MAJOR) + "." + std::to_string(FREETYPE_MINOR) + "." +
                  std::to_string(FREETYPE_PATCH) +
                  " headers) gives none: its COLR v1 API is disabled (as in Debian 12's libfreetype6); "
                  "the glyphs are not drawn from COLR v1");
      return;
    }
    api_answered.store(true, std::memory_order_relaxed);
    found = true;
    upem = f->units_per_EM ? f->units_per_EM : 1000;
    em.add({0, double(f->descender)});
    em.add({upem, double(f->ascender)});
    Reader r{f, opts, warn, nullptr, 0, {}, {}};
    FT_Palette_Data pd;
    FT_Color* palette = nullptr;
    if (FT_Palette_Data_Get(f, &pd) == 0 && pd.num_palettes > 0 && FT_Palette_Select(f, 0, &palette) == 0) {
      r.palette = palette;
      r.palette_size = pd.num_palette_entries;
    }
    root = r.read(op, 0);
    clip = r.clip_box(glyph);
    nodes = std::move(r.nodes);
  });
  if (!found) return nullptr;

  Lowering l(db, face, opts, nodes, warn);
  l.k = opts.size / upem;
  const Affine to_user{l.k, 0, 0, -l.k, 0, 0};  // font units, y up, to user units, y down
  l.to_font = Affine{1 / l.k, 0, 0, -1 / l.k, 0, 0};
  if (!clip.empty()) {
    l.extent = clip.mapped(to_user);
  } else {
    l.bounds(root, to_user, l.extent);
    if (l.extent.empty()) l.extent = em.mapped(to_user);
  }
  const double w = l.extent.x1 - l.extent.x0, h = l.extent.y1 - l.extent.y0;
  try {
    SceneBuilder b(std::isfinite(w) ? w : 0, std::isfinite(h) ? h : 0);
    l.b = &b;
    if (!clip.empty()) {
      b.push();
      b.clip(b.add_geometry(Path::rectangle(clip.x0, clip.y0, clip.x1, clip.y1)), to_user, FillRule::NonZero);
      b.activate();
      l.draw(root, to_user);
      b.pop();
    } else {
      l.draw(root, to_user);
    }
    Scene s = b.finish();
    if (b.flattened_groups() > 0) warn.once(flattened_groups_warning(b.flattened_groups()));
    return std::make_shared<const Scene>(std::move(s));
  } catch (const Error& e) {
    warn.once(std::string("COLR: glyph not drawn: ") + e.what());
    SceneBuilder empty(std::isfinite(w) ? w : 0, std::isfinite(h) ? h : 0);
    return std::make_shared<const Scene>(empty.finish());
  }
}

}  // namespace mpvg::text
