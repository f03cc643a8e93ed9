#include "frame/encoding.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>

#include "core/error.h"
#include "core/paint/mesh_build.h"
#include "core/parallel.h"

namespace mpvg {

namespace {

void check_finite(Vec2 p) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw Error("path has a non-finite coordinate");
}

float clamp01(double v) { return static_cast<float>(std::min(1.0, std::max(0.0, v))); }

Affine2f to_float(const Affine& m) {
  return Affine2f{float(m.a), float(m.b), float(m.c), float(m.d), float(m.e), float(m.f)};
}

// The largest singular value of m's linear part: how far a unit step in
// m's domain can move in its range.
double max_stretch(const Affine& m) {
  const double t = m.a * m.a + m.b * m.b + m.c * m.c + m.d * m.d;
  const double det = m.a * m.d - m.b * m.c;
  return std::sqrt(std::max(0.0, 0.5 * (t + std::sqrt(std::max(0.0, t * t - 4 * det * det)))));
}

// Linear part of m (its translation dropped).
Affine linear_part(const Affine& m) { return Affine{m.a, m.b, m.c, m.d, 0, 0}; }

// ------------------------------------------------------------ ramps

// Straight colours as a ramp sees them: in the interpolation space on the
// way in, in the integration space on the way out.
struct RampSpaces {
  bool interp_linear, out_linear;

  Rgba4 to_interp(const RGBA& c) const {
    Rgba4 r{clamp01(c.r), clamp01(c.g), clamp01(c.b), clamp01(c.a)};
    if (interp_linear) r = Rgba4{srgb_to_linear(r.r), srgb_to_linear(r.g), srgb_to_linear(r.b), r.a};
    return r;
  }
  Rgba4 to_out(const Rgba4& c) const {
    if (interp_linear == out_linear) return c;
    if (interp_linear) return Rgba4{linear_to_srgb(c.r), linear_to_srgb(c.g), linear_to_srgb(c.b), c.a};
    return Rgba4{srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), c.a};
  }
};

Rgba4 lerp4(const Rgba4& a, const Rgba4& b, double s) {
  const float f = static_cast<float>(s);
  return Rgba4{a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b), a.a + f * (b.a - a.a)};
}

float max_diff(const Rgba4& a, const Rgba4& b) {
  return std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b), std::fabs(a.a - b.a)});
}

// Linear pieces in the output space stay this close to the exact colours.
constexpr float kRampTolerance = 1.0f / 4096.0f;

class RampBuilder {
 public:
  RampBuilder(const Gradient& g, Gamma gamma)
      : g_(g), sp_{g.interpolation == ColorSpace::LinearRgb, gamma == Gamma::Linear} {
    for (const ColorStop& s : g.stops) stops_.push_back(sp_.to_interp(s.color));
  }

  // The exact straight output colour at t (stops' rule: constant beyond the
  // ends, the later stop from a step on).
  Rgba4 exact(double t) const {
    const size_t n = g_.stops.size();
    if (!(t > g_.stops[0].offset)) return sp_.to_out(stops_[0]);
    if (t >= g_.stops[n - 1].offset) return sp_.to_out(stops_[n - 1]);
    size_t i = 0;
    while (i + 1 < n && g_.stops[i + 1].offset <= t) i++;
    const double span = g_.stops[i + 1].offset - g_.stops[i].offset;
    return sp_.to_out(lerp4(stops_[i], stops_[i + 1], (t - g_.stops[i].offset) / span));
  }

  void exact_knots(std::vector<float>& kt, std::vector<Rgba4>& kc) const {
    const size_t n = g_.stops.size();
    for (size_t i = 0; i < n; i++) {
      kt.push_back(static_cast<float>(g_.stops[i].offset));
      kc.push_back(sp_.to_out(stops_[i]));
      if (i + 1 < n && sp_.interp_linear != sp_.out_linear && g_.stops[i + 1].offset > g_.stops[i].offset)
        refine(g_.stops[i].offset, stops_[i], g_.stops[i + 1].offset, stops_[i + 1], 0, kt, kc);
    }
  }

  void table_knots(int n, std::vector<float>& kt, std::vector<Rgba4>& kc) const {
    for (int i = 0; i < n; i++) {
      const double t = double(i) / (n - 1);
      kt.push_back(static_cast<float>(t));
      kc.push_back(exact(t));
    }
  }

 private:
  // Knots strictly between (ta, a) and (tb, b) (interpolation-space colours)
  // until linear pieces of the converted colours are within tolerance.
  void refine(double ta, const Rgba4& a, double tb, const Rgba4& b, int depth, std::vector<float>& kt,
              std::vector<Rgba4>& kc) const {
    const Rgba4 oa = sp_.to_out(a), ob = sp_.to_out(b);
    float err = 0;
    for (double s : {0.25, 0.5, 0.75}) err = std::max(err, max_diff(sp_.to_out(lerp4(a, b, s)), lerp4(oa, ob, s)));
    if (err <= kRampTolerance || depth >= 10) return;
    const double tm = 0.5 * (ta + tb);
    const Rgba4 m = lerp4(a, b, 0.5);
    refine(ta, a, tm, m, depth + 1, kt, kc);
    kt.push_back(static_cast<float>(tm));
    kc.push_back(sp_.to_out(m));
    refine(tm, m, tb, b, depth + 1, kt, kc);
  }

  const Gradient& g_;
  RampSpaces sp_;
  std::vector<Rgba4> stops_;  // interpolation space
};

// ------------------------------------------------------------ textures

// Level 0 of an image: premultiplied texels in the integration space.
std::vector<Texel16> base_level(const Image& im, Gamma gamma) {
  const size_t n = size_t(im.width) * im.height;
  std::vector<Texel16> out(n);
  // Component conversion tables: 8-bit values directly, 16-bit values
  // through a 65536-entry table (the same function, so the two depths agree).
  const int levels = im.bits == 16 ? 65536 : 256;
  std::vector<float> lut(levels);
  for (int i = 0; i < levels; i++) {
    const float v = float(i) / float(levels - 1);
    lut[i] = gamma == Gamma::Linear ? srgb_to_linear(v) : v;
  }
  parallel_for((n + 4095) / 4096, 0, [&](size_t block) {
    const size_t end = std::min(n, (block + 1) * 4096);
    for (size_t i = block * 4096; i < end; i++) {
      float c[3], a;
      if (im.bits == 16) {
        const uint16_t* p = &im.rgba16[i * 4];
        for (int k = 0; k < 3; k++) c[k] = lut[p[k]];
        a = p[3] / 65535.0f;
      } else {
        const uint8_t* p = &im.rgba8[i * 4];
        for (int k = 0; k < 3; k++) c[k] = lut[p[k]];
        a = p[3] / 255.0f;
      }
      auto q = [](float v) { return static_cast<uint16_t>(std::lround(std::min(1.0f, std::max(0.0f, v)) * 65535.0f)); };
      out[i] = Texel16{q(c[0] * a), q(c[1] * a), q(c[2] * a), q(a)};
    }
  });
  return out;
}

// The next mip level: ceil(w / 2) x ceil(h / 2) texels, each the mean of
// the 2 x 2 block it covers (an odd last row or column repeats the edge).
std::vector<Texel16> half_level(const std::vector<Texel16>& src, uint32_t w, uint32_t h, uint32_t& nw, uint32_t& nh) {
  nw = (w + 1) / 2;
  nh = (h + 1) / 2;
  std::vector<Texel16> out(size_t(nw) * nh);
  for (uint32_t y = 0; y < nh; y++)
    for (uint32_t x = 0; x < nw; x++) {
      const uint32_t x0 = 2 * x, y0 = 2 * y, x1 = std::min(w - 1, x0 + 1), y1 = std::min(h - 1, y0 + 1);
      const Texel16* t[4] = {&src[size_t(y0) * w + x0], &src[size_t(y0) * w + x1], &src[size_t(y1) * w + x0],
                             &src[size_t(y1) * w + x1]};
      auto avg = [&](uint16_t Texel16::*c) {
        return static_cast<uint16_t>((uint32_t(t[0]->*c) + t[1]->*c + t[2]->*c + t[3]->*c + 2) / 4);
      };
      out[size_t(y) * nw + x] = Texel16{avg(&Texel16::r), avg(&Texel16::g), avg(&Texel16::b), avg(&Texel16::a)};
    }
  return out;
}

// ------------------------------------------------------------ the encoder

class Encoder {
 public:
  Encoder(Gamma gamma, const EncodeOptions& options, PaintData& paint, std::vector<EncodedTile>& tiles)
      : gamma_(gamma), options_(options), paint_(paint), tiles_(tiles) {}

  // Encodes `scene` into `out`: view maps its units to the frame's
  // coordinates (pixels, or a tile's grid), frame_to_out maps the frame's
  // coordinates to output pixels (its linear part: how large things look).
  void scene(const Scene& scene, const Affine& view, const Affine& frame_to_out, const MeshBounds& bounds, int depth,
             EncodedScene& out) {
    if (scene.paths.size() >= kMaxPaths) throw Error("scene has too many paths");
    // The scene's paints first: path records need their flags. Their slots
    // are taken before any is encoded, as a pattern's tile appends paints
    // of its own.
    const uint32_t base = static_cast<uint32_t>(paint_.paints.size());
    paint_.paints.resize(base + scene.paints.size());
    std::vector<uint32_t> flags(scene.paints.size());
    for (size_t i = 0; i < scene.paints.size(); i++) {
      PaintRecord rec;  // paint_.paints may grow meanwhile: no reference into it
      flags[i] = paint(scene, scene.paints[i], view, frame_to_out, bounds, depth, rec);
      paint_.paints[base + i] = rec;
    }
    paths(scene, view, base, flags, groups(scene), depth == 0 ? options_.border : ImageBorder{}, out);
  }

 private:
  // The scene's group records, appended to the table (their GROUP_IN_*
  // flags come from the stream, in paths()); returns the first's index.
  uint32_t groups(const Scene& scene) {
    const uint32_t base = static_cast<uint32_t>(paint_.groups.size());
    for (const Group& g : scene.groups) {
      GroupRecord r{};
      r.opacity = clamp01(g.opacity);
      r.blend = static_cast<uint32_t>(g.blend);
      r.channels = blend_channels(static_cast<uint32_t>(g.channels[0]), static_cast<uint32_t>(g.channels[1]),
                                  static_cast<uint32_t>(g.channels[2]), g.subtractive);
      if (!g.isolated && g.back_to_front) r.flags |= GROUP_BACKDROP;
      if (g.mask == MaskType::Alpha) r.flags |= GROUP_MASK_ALPHA;
      if (g.mask == MaskType::Luminance) {
        r.flags |= GROUP_MASK_LUMINANCE;
        const bool linear_space = g.luminance_space == ColorSpace::LinearRgb;
        if (gamma_ == Gamma::Linear && !linear_space) r.flags |= GROUP_LUMINANCE_ENCODE;
        if (gamma_ == Gamma::Srgb && linear_space) r.flags |= GROUP_LUMINANCE_DECODE;
        for (int k = 0; k < 3; k++) r.lum[k] = g.luminance[k];
        const float a = clamp01(g.backdrop.a);
        const Rgba4 c = out_color(g.backdrop);
        r.backdrop = Rgba4{c.r * a, c.g * a, c.b * a, a};
      }
      paint_.groups.push_back(r);
    }
    return base;
  }

  // Does a fill with this paint make the mask 1 where it covers (exactly,
  // by the sampler's own arithmetic)?
  static bool fills_mask(const GroupRecord& mask, const PaintRecord& p, uint32_t path_flags) {
    if (!(path_flags & PATH_OPAQUE)) return false;
    if (mask.flags & GROUP_MASK_ALPHA) return true;
    return p.kind == PAINT_SOLID && mask_value(mask, Rgba4{p.r, p.g, p.b, p.a}) == 1.0f;
  }

  // The entry of a group delimiter; `in` are the flags of the list the
  // group is in (GROUP_IN_*), recorded on its begin.
  Entry group_entry(const Element& e, const Group& g, uint32_t group_base, uint32_t in) {
    const uint32_t id = group_base + e.path;
    GroupRecord& r = paint_.groups[id];
    uint32_t bits = e.kind == ElementKind::EndGroup ? GROUP_ENTRY_END : 0u;
    if (r.flags & (GROUP_MASK_ALPHA | GROUP_MASK_LUMINANCE)) {
      bits |= GROUP_ENTRY_MASK;
      if (mask_value(r, Rgba4{0.0f, 0.0f, 0.0f, 0.0f}) == 0.0f) bits |= GROUP_ENTRY_EMPTY_HIDES;
    }
    if (e.kind == ElementKind::BeginGroup) r.flags |= in;
    if (r.opacity == 1.0f && group_record_normal(r) && !(bits & GROUP_ENTRY_MASK) &&
        !(r.flags & GROUP_IN_KNOCKOUT) && !g.knockout)
      bits |= GROUP_ENTRY_SOLID;
    if (r.flags & GROUP_IN_BACK_TO_FRONT) bits |= GROUP_ENTRY_IN_BACK_TO_FRONT;
    if (r.flags & GROUP_BACKDROP) bits |= GROUP_ENTRY_BACKDROP;
    if (group_record_normal(r)) bits |= GROUP_ENTRY_NORMAL;
    if ((bits & GROUP_ENTRY_SOLID) && !(r.flags & GROUP_BACKDROP) &&
        g.back_to_front == ((r.flags & GROUP_IN_BACK_TO_FRONT) != 0))
      bits |= GROUP_ENTRY_DISSOLVES;
    return make_entry(ENTRY_GROUP, bits, id);
  }
  // The record of paint p, into `out`; returns the path flags it implies
  // (PATH_OPAQUE, PATH_VARYING).
  uint32_t paint(const Scene& scene, const Paint& p, const Affine& view, const Affine& frame_to_out,
                 const MeshBounds& bounds, int depth, PaintRecord& out) {
    const float op = clamp01(p.opacity);
    PaintRecord rec{op, op, op, op, PAINT_SOLID, 0, 0, 0};
    uint32_t flags = 0;
    switch (p.type) {
      case PaintType::Solid: {
        const float a = clamp01(double(p.color.a) * op);
        const Rgba4 c = out_color(p.color);
        rec = PaintRecord{c.r * a, c.g * a, c.b * a, a, PAINT_SOLID, 0, 0, 0};
        if (a >= 1.0f) flags |= PATH_OPAQUE;
        break;
      }
      case PaintType::LinearGradient:
      case PaintType::RadialGradient:
      case PaintType::SweepGradient: {
        bool opaque = false;
        if (gradient(scene.gradients.at(p.index), p.type, view, rec, opaque)) {
          flags |= PATH_VARYING;
          if (opaque && op >= 1.0f) flags |= PATH_OPAQUE;
        } else {
          rec = PaintRecord{0, 0, 0, 0, PAINT_SOLID, 0, 0, 0};  // paints nothing
        }
        break;
      }
      case PaintType::Texture: {
        bool opaque = false;
        const Texture& t = scene.textures.at(p.index);
        if (texture(t, view, frame_to_out, rec, opaque)) {
          const float a = clamp01(double(t.tint.a) * op);
          const Rgba4 c = out_color(t.tint);
          rec.r = c.r * a;
          rec.g = c.g * a;
          rec.b = c.b * a;
          rec.a = a;
          flags |= PATH_VARYING;
          if (opaque && a >= 1.0f) flags |= PATH_OPAQUE;
        } else {
          rec = PaintRecord{0, 0, 0, 0, PAINT_SOLID, 0, 0, 0};
        }
        break;
      }
      case PaintType::Mesh:
        // Never opaque for pruning: a fill larger than the triangles'
        // union would be transparent outside it.
        if (mesh(scene.meshes.at(p.index), view, bounds, rec))
          flags |= PATH_VARYING;
        else
          rec = PaintRecord{0, 0, 0, 0, PAINT_SOLID, 0, 0, 0};
        break;
      case PaintType::Pattern:
        if (pattern(scene.patterns.at(p.index), view, frame_to_out, depth, rec)) {
          flags |= PATH_VARYING;
        } else {
          rec = PaintRecord{0, 0, 0, 0, PAINT_SOLID, 0, 0, 0};
        }
        break;
      case PaintType::Filter:
        // The renderer replaces filters by textures first (frame/filter_layers.h).
        throw Error("encoding: a filter effect was not resolved into its layer");
    }
    out = rec;
    return flags;
  }

  // A colour (straight alpha dropped) in the integration space.
  Rgba4 out_color(const RGBA& c) const {
    Rgba4 r{clamp01(c.r), clamp01(c.g), clamp01(c.b), 1.0f};
    if (gamma_ == Gamma::Linear) r = Rgba4{srgb_to_linear(r.r), srgb_to_linear(r.g), srgb_to_linear(r.b), 1.0f};
    return r;
  }

  // Fills in a gradient paint of type `type` (linear, radial or sweep);
  // false when the gradient paints nothing anywhere (degenerate geometry or
  // transform).
  bool gradient(const Gradient& g, PaintType type, const Affine& view, PaintRecord& rec, bool& opaque) {
    const Affine to_paint = view * g.xf;
    if (!to_paint.invertible()) return false;
    const Affine G = to_paint.inverted();  // pixels to gradient space
    GradientRecord gr{};
    const Vec2 cd = g.center - g.focal;
    bool covers = true;  // every point gets a t
    if (type == PaintType::SweepGradient) {
      // The angle does not depend on the scale: the centre is moved to the
      // origin and nothing else.
      gr.m = to_float(Affine::translate(-g.center.x, -g.center.y) * G);
      const double span = g.end_angle - g.start_angle;
      const float start = static_cast<float>(g.start_angle), inv = static_cast<float>(1 / span);
      if (!std::isfinite(start)) return false;  // beyond float range: no angle compares with it
      gr.r0 = start;
      // A span too small for its inverse to be a float is the step of
      // equal angles (dr = 0), which only pad paints.
      gr.dr = std::isfinite(inv) ? inv : 0.0f;
      if (gr.dr == 0.0f && g.spread != Spread::Pad) return false;
      // Every angle gets a t (pad extends, repeat and reflect wrap): the
      // spread decides below whether the plane is covered.
    } else if (type == PaintType::RadialGradient) {
      const double s = std::max({std::hypot(cd.x, cd.y), std::fabs(g.focal_radius), std::fabs(g.radius)});
      if (!(s > 0)) return false;
      const Affine N = Affine::scale(1 / s, 1 / s) * Affine::translate(-g.focal.x, -g.focal.y);
      gr.m = to_float(N * G);
      gr.cdx = static_cast<float>(cd.x / s);
      gr.cdy = static_cast<float>(cd.y / s);
      gr.r0 = static_cast<float>(g.focal_radius / s);
      gr.dr = static_cast<float>((g.radius - g.focal_radius) / s);
      double a = (cd.x * cd.x + cd.y * cd.y - (g.radius - g.focal_radius) * (g.radius - g.focal_radius)) / (s * s);
      // Tangent circles within float precision: the degenerate case proper.
      if (std::fabs(a) < 1e-6) a = 0;
      gr.a = static_cast<float>(a);
      // The circles sweep the whole plane when the start circle lies
      // strictly inside the end circle (as t goes to -r0 / dr and to
      // infinity): |cd| < r - fr, i.e. a < 0. Internally tangent circles
      // (a snapped to 0 above) sweep only a half plane.
      covers = a < 0 && g.radius > g.focal_radius && g.focal_radius >= 0;
    } else {
      const Vec2 d = g.p1 - g.p0;
      const double l2 = d.x * d.x + d.y * d.y;
      if (!(l2 > 0)) return false;
      // t = dot(G(p) - p0, d) / |d|^2 as an affine function of the pixel.
      gr.m = Affine2f{float((d.x * G.a + d.y * G.b) / l2),
                      0.0f,
                      float((d.x * G.c + d.y * G.d) / l2),
                      0.0f,
                      float((d.x * (G.e - g.p0.x) + d.y * (G.f - g.p0.y)) / l2),
                      0.0f};
    }
    gr.flags = static_cast<uint32_t>(g.spread);
    if (g.spread == Spread::Pad) {
      if (!g.extend_start) gr.flags |= GRADIENT_NO_EXTEND_START;
      if (!g.extend_end) gr.flags |= GRADIENT_NO_EXTEND_END;
      covers = covers && g.extend_start && g.extend_end;
    }
    const bool ramp_opaque = ramp(g, gr);  // always appends the ramp
    opaque = covers && ramp_opaque;
    rec.kind = type == PaintType::SweepGradient    ? PAINT_SWEEP
               : type == PaintType::RadialGradient ? PAINT_RADIAL
                                                   : PAINT_LINEAR;
    rec.index = static_cast<uint32_t>(paint_.gradients.size());
    paint_.gradients.push_back(gr);
    return true;
  }

  // Appends g's colour ramp to the tables and points gr at it; true when
  // every colour of the ramp is opaque.
  bool ramp(const Gradient& g, GradientRecord& gr) {
    const RampBuilder rb(g, gamma_);
    gr.first = static_cast<uint32_t>(paint_.ramp_t.size());
    if (options_.ramp_lut > 1) {
      rb.table_knots(options_.ramp_lut, paint_.ramp_t, paint_.ramp_color);
      gr.flags |= GRADIENT_UNIFORM_KNOTS;
    } else {
      rb.exact_knots(paint_.ramp_t, paint_.ramp_color);
    }
    gr.count = static_cast<uint32_t>(paint_.ramp_t.size()) - gr.first;
    bool opaque = true;
    for (uint32_t i = gr.first; i < gr.first + gr.count; i++) opaque = opaque && paint_.ramp_color[i].a >= 1.0f;
    return opaque;
  }

  // Fills in a mesh paint (core/paint/mesh_build.h); false when no triangle has
  // an area in pixels.
  bool mesh(const Mesh& m, const Affine& view, const MeshBounds& bounds, PaintRecord& rec) {
    MeshRecord mr{};
    auto color = [this](const RGBA& c) {
      Rgba4 r = out_color(c);
      r.a = clamp01(c.a);
      return r;
    };
    if (!build_mesh(m, view * m.xf, color, bounds, options_.budget, paint_, mr)) return false;
    if (m.area_by_triangles) mr.flags |= MESH_AREA_BY_TRIANGLES;
    if (!m.ramp.empty()) {
      Gradient g;  // only its stops: t comes from the triangles
      g.stops = m.ramp;
      GradientRecord gr{};
      ramp(g, gr);
      mr.ramp = static_cast<uint32_t>(paint_.gradients.size());
      paint_.gradients.push_back(gr);
    }
    rec.kind = PAINT_MESH;
    rec.index = static_cast<uint32_t>(paint_.meshes.size());
    paint_.meshes.push_back(mr);
    return true;
  }

  // Fills in a texture paint (its factor is set by the caller); false when
  // the texture's transform is degenerate.
  bool texture(const Texture& t, const Affine& view, const Affine& frame_to_out, PaintRecord& rec, bool& opaque) {
    const Affine to_paint = view * t.xf;
    if (!to_paint.invertible() || !frame_to_out.invertible()) return false;
    const Affine M = to_paint.inverted();  // frame to texels
    // Footprint of an output pixel in texels: the same everywhere.
    const double stretch = max_stretch(linear_part(M) * linear_part(frame_to_out).inverted());
    const double lod = stretch > 0 ? std::log2(stretch) + kTextureLodBias : 0;
    ImageEntry& img = image(t.image);
    TextureRecord tr{};
    tr.m = to_float(M);
    tr.flags = static_cast<uint32_t>(t.filter) | static_cast<uint32_t>(t.wrap_x) << TEXTURE_WRAP_X_SHIFT |
               static_cast<uint32_t>(t.wrap_y) << TEXTURE_WRAP_Y_SHIFT;
    if (lod > 0) {
      int level = static_cast<int>(std::floor(lod));
      double frac = lod - level;
      const int needed = level + (frac > 0 ? 1 : 0);
      while (static_cast<int>(img.levels.size()) - 1 < needed && !img.complete) add_level(img);
      const int last = static_cast<int>(img.levels.size()) - 1;
      if (level >= last) {
        level = last;
        frac = 0;
      }
      tr.lod_level = static_cast<uint32_t>(level);
      tr.lod_frac = static_cast<float>(frac);
      if (level == 0 && frac == 0) tr.lod_frac = 0;
    }
    // Levels are appended to the tables when the scene is finished (the
    // chain can still grow); remember which record points at which image.
    texture_images_.push_back({static_cast<uint32_t>(paint_.textures.size()), &img});
    paint_.textures.push_back(tr);
    rec.kind = PAINT_TEXTURE;
    rec.index = static_cast<uint32_t>(paint_.textures.size() - 1);
    opaque = img.opaque && t.wrap_x != TextureWrap::Decal && t.wrap_y != TextureWrap::Decal;
    return true;
  }

  // Fills in a pattern paint and encodes its tile; false when the pattern's
  // transform is degenerate.
  bool pattern(const Pattern& p, const Affine& view, const Affine& frame_to_out, int depth, PaintRecord& rec) {
    if (depth + 1 > kMaxPatternDepth)
      throw Error("patterns nested more than " + std::to_string(kMaxPatternDepth) + " deep");
    const Scene& tile = *p.tile;
    const Affine to_frame = view * p.xf;  // tile units to the frame
    if (!to_frame.invertible()) return false;
    // The tile's size in output pixels sets its grid.
    const Affine to_out = linear_part(frame_to_out) * linear_part(to_frame);
    auto grid = [](double units) {
      const double g = std::ceil(units - 1e-9);
      return static_cast<int>(std::min<double>(kMaxTileGrid, std::max<double>(kMinTileGrid, std::isfinite(g) ? g : 0)));
    };
    const int gw = grid(tile.width * std::hypot(to_out.a, to_out.b));
    const int gh = grid(tile.height * std::hypot(to_out.c, to_out.d));
    const Affine grid_view = Affine::scale(gw / tile.width, gh / tile.height);
    const Affine tile_to_out = to_out * linear_part(grid_view).inverted();
    PatternRecord pr{};
    pr.m = to_float(grid_view * to_frame.inverted());
    // A tile encoded for the same grid, output scale and depth is shared:
    // its encoding depends on nothing else, and a tile used by many
    // patterns (or by a pattern nested in itself through several levels)
    // is otherwise encoded once per use.
    const TileKey key{&tile, gw, gh, depth, tile_to_out.a, tile_to_out.b, tile_to_out.c, tile_to_out.d};
    if (auto it = tile_index_.find(key); it != tile_index_.end()) {
      pr.tree = it->second;
    } else {
      pr.tree = static_cast<uint32_t>(tiles_.size());
      tiles_.emplace_back();
      tiles_.back().width = gw;
      tiles_.back().height = gh;
      EncodedScene enc;
      const Scene* content = &tile;
      if (!tile.filters.empty()) {
        // Its filters made layers over the tile's grid, as the output's
        // are over its pixels; kept while the encoder runs (its images are
        // known by their addresses).
        if (!options_.tile_filters) throw Error("encoding: a filter effect in a pattern tile was not resolved");
        resolved_tiles_.push_back(std::make_shared<const Scene>(options_.tile_filters(tile, gw, gh, grid_view)));
        content = resolved_tiles_.back().get();
      }
      // Samples of the tile fall in its grid (positions wrap).
      scene(*content, grid_view, tile_to_out, MeshBounds{0, 0, double(gw), double(gh)}, depth + 1, enc);
      tiles_[pr.tree].scene = std::move(enc);  // tiles_ may have grown meanwhile
      tile_index_.emplace(key, pr.tree);
    }
    rec.kind = PAINT_PATTERN;
    rec.index = static_cast<uint32_t>(paint_.patterns.size());
    paint_.patterns.push_back(pr);
    return true;
  }

  // What the encoding of scene's paths holds (its segments with the lines
  // that close contours, or its strokes' centrelines), charged before it
  // is made.
  void charge_paths(const Scene& scene) {
    if (!options_.budget) return;
    uint64_t n = scene.paths.size() * sizeof(PathRecord) + scene.stream.size() * sizeof(Entry);
    for (const ScenePath& sp : scene.paths) {
      const Path& g = scene.geometries[sp.geometry];
      const uint64_t segments = g.segments().size(), contours = g.contours().size();
      if (sp.stroke >= 0)
        n += segments * sizeof(stroking::StrokeSegment) +
             contours * (sizeof(stroking::StrokeSubpath) + sizeof(uint32_t)) + sizeof(stroking::StrokeRecord) +
             scene.strokes[sp.stroke].dashes.size() * 2 * 2 * sizeof(double);
      else
        n += (segments + contours) * sizeof(InputSegment);
    }
    options_.budget->charge(n, "the scene's encoding");
  }

  void paths(const Scene& scene, const Affine& view, uint32_t paint_base, const std::vector<uint32_t>& paint_flags,
             uint32_t group_base, const ImageBorder& border, EncodedScene& out) {
    charge_paths(scene);
    out.paths.resize(scene.paths.size());
    // How the innermost open group's list composites (GROUP_IN_* of its
    // children); the top level runs front to back.
    std::vector<uint32_t> lists{0u};
    // The innermost open group's record when it is a mask of opacity 1.
    std::vector<uint32_t> masks{~0u};
    for (const Element& e : scene.stream) {
      switch (e.kind) {
        case ElementKind::Push: out.stream.push_back(make_entry(ENTRY_PUSH, 0, 0)); continue;
        case ElementKind::Activate: out.stream.push_back(make_entry(ENTRY_ACTIVATE, 0, 0)); continue;
        case ElementKind::Pop: out.stream.push_back(make_entry(ENTRY_POP, 0, 0)); continue;
        case ElementKind::BeginGroup: {
          const Group& g = scene.groups[e.path];
          out.stream.push_back(group_entry(e, g, group_base, lists.back()));
          masks.push_back(g.mask != MaskType::None && g.opacity >= 1.0f ? group_base + e.path : ~0u);
          if (lists.size() > static_cast<size_t>(kMaxGroupDepth))
            throw Error("groups and masks nested more than " + std::to_string(kMaxGroupDepth) + " deep");
          lists.push_back((g.back_to_front ? GROUP_IN_BACK_TO_FRONT : 0u) | (g.knockout ? GROUP_IN_KNOCKOUT : 0u));
          continue;
        }
        case ElementKind::EndGroup:
          lists.pop_back();
          masks.pop_back();
          out.stream.push_back(group_entry(e, scene.groups[e.path], group_base, 0));
          continue;
        default: break;
      }
      const uint32_t id = e.path;
      const ScenePath& sp = scene.paths[id];
      PathRecord& rec = out.paths[id];
      rec.flags = (sp.rule == FillRule::EvenOdd ? PATH_EVENODD : 0u) | (sp.is_clip ? PATH_CLIP : 0u) |
                  (sp.aliased ? PATH_ALIASED : 0u);
      if (sp.aliased) paint_.aliased = true;
      if (!sp.is_clip) {
        rec.paint = paint_base + sp.paint;
        rec.flags |= paint_flags[sp.paint];
        if (lists.back() & GROUP_IN_BACK_TO_FRONT) rec.flags |= PATH_BACK_TO_FRONT;
        if (lists.back() & GROUP_IN_KNOCKOUT) rec.flags |= PATH_KNOCKOUT;
        if (masks.back() != ~0u && fills_mask(paint_.groups[masks.back()], paint_.paints[rec.paint], rec.flags))
          rec.flags |= PATH_MASK_FULL;
      }
      out.stream.push_back(make_entry(ENTRY_SEGMENT, id, 0));

      const Affine xf = view * sp.xf;
      const Path& g = scene.geometries[sp.geometry];
      if (sp.stroke >= 0) {
        // Built when rendered, by either executor, to 1/16 of a unit area.
        out.strokes.add(g, scene.strokes[sp.stroke], xf, id);
        continue;
      }
      std::vector<Vec2> pts(g.points().size());
      for (size_t i = 0; i < pts.size(); i++) {
        pts[i] = xf.apply(g.points()[i]);
        check_finite(pts[i]);
      }
      const size_t path_first = out.segments.size();
      for (const Path::Contour& c : g.contours()) {
        if (c.segment_count == 0) continue;
        Vec2 last{};
        for (uint32_t k = 0; k < c.segment_count; k++) {
          const Path::Segment& s = g.segments()[c.first_segment + k];
          InputSegment in{};
          in.path = id;
          in.w = 1.0;
          const int deg = segment_degree(s.type);
          for (int j = 0; j <= deg; j++) {
            in.x[j] = pts[s.first_point + j].x;
            in.y[j] = pts[s.first_point + j].y;
          }
          switch (s.type) {
            case SegmentType::Line: in.type = INPUT_LINE; break;
            case SegmentType::Quad: in.type = INPUT_QUAD; break;
            case SegmentType::RQuad:
              in.type = INPUT_RQUAD;
              in.w = g.weights()[s.first_weight];
              if (!(in.w > 0.0) || !std::isfinite(in.w))
                throw Error("rational quadratic segment with a non-positive or non-finite weight");
              break;
            case SegmentType::Cubic: in.type = INPUT_CUBIC; break;
            case SegmentType::RCubic:
              throw Error("rational cubic segments are not supported (their monotonization needs quartic roots)");
          }
          out.segments.push_back(in);
          out.input_segment_count++;
          last = pts[s.first_point + deg];
        }
        const Vec2 start = pts[c.start_point];
        if (last != start) {
          InputSegment in{};
          in.type = INPUT_LINE;
          in.path = id;
          in.w = 1.0;
          in.x[0] = last.x;
          in.y[0] = last.y;
          in.x[1] = start.x;
          in.y[1] = start.y;
          out.segments.push_back(in);
        }
      }
      // Edges on the image's border go out past the frame (core/paint/image_border.h).
      push_out_border_edges(border, out.segments, path_first);
    }
  }

 public:
  // An image's mip chain, built as far as some texture needs it.
  struct ImageEntry {
    std::vector<std::vector<Texel16>> levels;
    std::vector<uint32_t> widths, heights;
    bool opaque = true;
    bool complete = false;  // reached 1 x 1
    // Executor texels in device memory (ExecutorTexels::device): no host
    // levels, no mips.
    const Texel16* device = nullptr;
    std::shared_ptr<const void> device_owner;
  };

  // Appends every image's levels and points the texture records at them;
  // the levels of device texels after all the host's (PaintData::
  // device_texels).
  void finish() {
    std::unordered_map<const ImageEntry*, uint32_t> first;
    for (const auto& [tex, img] : texture_images_) {
      if (img->device) continue;  // placed below, after every host texel
      auto it = first.find(img);
      if (it == first.end()) {
        const uint32_t l0 = static_cast<uint32_t>(paint_.levels.size());
        for (size_t k = 0; k < img->levels.size(); k++) {
          TextureLevel lv;
          lv.offset = static_cast<uint32_t>(paint_.texels.size());
          if (paint_.texels.size() + img->levels[k].size() > 0xffffffffu)
            throw Error("images too large: more than 2^32 texels in all");
          lv.width = img->widths[k];
          lv.height = img->heights[k];
          lv.scale = std::ldexp(1.0f, -static_cast<int>(k));
          paint_.levels.push_back(lv);
          paint_.texels.insert(paint_.texels.end(), img->levels[k].begin(), img->levels[k].end());
        }
        it = first.emplace(img, l0).first;
      }
      paint_.textures[tex].level0 = it->second;
      paint_.textures[tex].levels = static_cast<uint32_t>(img->levels.size());
    }
    uint64_t offset = paint_.texels.size();
    for (const auto& [tex, img] : texture_images_) {
      if (!img->device) continue;
      auto it = first.find(img);
      if (it == first.end()) {
        const uint64_t count = uint64_t(img->widths[0]) * img->heights[0];
        if (offset + count > 0xffffffffu) throw Error("images too large: more than 2^32 texels in all");
        it = first.emplace(img, static_cast<uint32_t>(paint_.levels.size())).first;
        paint_.levels.push_back(TextureLevel{static_cast<uint32_t>(offset), img->widths[0], img->heights[0], 1.0f});
        paint_.device_texels.push_back(PaintData::DeviceTexels{offset, count, img->device, img->device_owner});
        offset += count;
      }
      paint_.textures[tex].level0 = it->second;
      paint_.textures[tex].levels = 1;
    }
  }

 private:
  ImageEntry& image(const std::shared_ptr<const Image>& im) {
    auto it = images_.find(im.get());
    if (it != images_.end()) return *it->second;
    auto e = std::make_unique<ImageEntry>();
    if (im->texels) {
      // Made for this frame: one level, in the integration space already.
      e->widths.push_back(static_cast<uint32_t>(im->width));
      e->heights.push_back(static_cast<uint32_t>(im->height));
      e->opaque = false;
      e->complete = true;
      if (im->texels->device) {
        e->device = im->texels->device;
        e->device_owner = im->texels->owner;
      } else {
        if (im->texels->host.size() != size_t(im->width) * im->height) throw Error("executor texels of the wrong size");
        e->levels.push_back(im->texels->host);
      }
      ImageEntry& ref = *e;
      images_.emplace(im.get(), std::move(e));
      return ref;
    }
    e->levels.push_back(base_level(*im, gamma_));
    e->widths.push_back(static_cast<uint32_t>(im->width));
    e->heights.push_back(static_cast<uint32_t>(im->height));
    for (const Texel16& t : e->levels[0]) e->opaque = e->opaque && t.a == 65535;
    e->complete = im->width == 1 && im->height == 1;
    ImageEntry& ref = *e;
    images_.emplace(im.get(), std::move(e));
    return ref;
  }

  static void add_level(ImageEntry& e) {
    uint32_t nw, nh;
    std::vector<Texel16> next = half_level(e.levels.back(), e.widths.back(), e.heights.back(), nw, nh);
    e.levels.push_back(std::move(next));
    e.widths.push_back(nw);
    e.heights.push_back(nh);
    e.complete = nw == 1 && nh == 1;
  }

  Gamma gamma_;
  const EncodeOptions& options_;
  PaintData& paint_;
  std::vector<EncodedTile>& tiles_;
  std::unordered_map<const Image*, std::unique_ptr<ImageEntry>> images_;
  // Encoded tiles by what their encoding depends on.
  using TileKey = std::tuple<const Scene*, int, int, int, double, double, double, double>;
  std::map<TileKey, uint32_t> tile_index_;
  std::vector<std::pair<uint32_t, ImageEntry*>> texture_images_;
  std::vector<std::shared_ptr<const Scene>> resolved_tiles_;  // pattern tiles with their filters as layers
};

}  // namespace

EncodedScene encode(const Scene& scene, const Affine& view, Gamma gamma, const EncodeOptions& options) {
  EncodedScene out;
  auto paint = std::make_shared<PaintData>();
  Encoder enc(gamma, options, *paint, out.tiles);
  MeshBounds bounds;
  if (options.frame_width > 0 && options.frame_height > 0)
    bounds = MeshBounds{0, 0, double(options.frame_width), double(options.frame_height)};
  enc.scene(scene, view, Affine{}, bounds, 0, out);
  enc.finish();
  out.paint = std::move(paint);
  return out;
}

}  // namespace mpvg
