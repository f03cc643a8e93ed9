#include "frame/scene_info.h"

#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <unordered_set>

namespace mpvg {

size_t segment_count(const Scene& scene) {
  size_t n = 0;
  for (const ScenePath& sp : scene.paths) {
    const Path& g = scene.geometries[sp.geometry];
    if (sp.stroke >= 0) {
      // A stroke's segments are made when it is rendered: about ten per
      // centreline segment (bodies, joins, caps; more for dashes and tight
      // curves), as an estimate.
      n += 10 * (g.segments().size() + g.contours().size());
      continue;
    }
    n += g.segments().size();
    for (const Path::Contour& c : g.contours()) {
      if (c.segment_count == 0) continue;
      const Path::Segment& last = g.segments()[c.first_segment + c.segment_count - 1];
      const Vec2 end = g.points()[last.first_point + segment_degree(last.type)];
      if (end != g.points()[c.start_point]) n++;
    }
  }
  return n;
}

namespace {

void appendf(std::string& s, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& s, const char* fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  const int n = vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (n > 0) s.append(buf, static_cast<size_t>(n) < sizeof buf ? static_cast<size_t>(n) : sizeof buf - 1);
}

const char* paint_type_name(PaintType t) {
  switch (t) {
    case PaintType::Solid: return "solid";
    case PaintType::LinearGradient: return "linear";
    case PaintType::RadialGradient: return "radial";
    case PaintType::Texture: return "texture";
    case PaintType::Pattern: return "pattern";
    case PaintType::Mesh: return "mesh";
    case PaintType::Filter: return "filter";
    case PaintType::SweepGradient: return "sweep";
  }
  return "?";
}

void append_matrix(std::string& s, const Affine& m) {
  if (!m.is_identity()) appendf(s, " matrix(%g %g %g %g %g %g)", m.a, m.b, m.c, m.d, m.e, m.f);
}

void dump_into(std::string& s, const Scene& scene, const std::string& indent);

void dump_servers(std::string& s, const Scene& scene, const std::string& indent) {
  static const char* const spreads[] = {"pad", "reflect", "repeat"};
  for (size_t i = 0; i < scene.gradients.size(); i++) {
    const Gradient& g = scene.gradients[i];
    appendf(s, "%sgradient %zu linear %g %g %g %g radial %g %g %g %g %g %g %s %s", indent.c_str(), i, g.p0.x, g.p0.y,
            g.p1.x, g.p1.y, g.focal.x, g.focal.y, g.focal_radius, g.center.x, g.center.y, g.radius,
            spreads[static_cast<int>(g.spread)], g.interpolation == ColorSpace::Srgb ? "srgb" : "linearrgb");
    if (!g.extend_start || !g.extend_end) appendf(s, " extend %d %d", g.extend_start ? 1 : 0, g.extend_end ? 1 : 0);
    // The sweep's angles (around `center`) where they are not the defaults.
    if (g.start_angle != 0 || g.end_angle != 360) appendf(s, " sweep %g %g", g.start_angle, g.end_angle);
    append_matrix(s, g.xf);
    s += "\n";
    appendf(s, "%s  stops", indent.c_str());
    for (const ColorStop& st : g.stops)
      appendf(s, " %g rgba(%g,%g,%g,%g)", st.offset, st.color.r, st.color.g, st.color.b, st.color.a);
    s += "\n";
  }
  static const char* const filters[] = {"nearest", "bilinear", "bicubic"};
  static const char* const wraps[] = {"clamp", "repeat", "decal"};
  for (size_t i = 0; i < scene.textures.size(); i++) {
    const Texture& t = scene.textures[i];
    appendf(s, "%stexture %zu image %dx%dx%d %s %s %s", indent.c_str(), i, t.image->width, t.image->height,
            t.image->bits, filters[static_cast<int>(t.filter)], wraps[static_cast<int>(t.wrap_x)],
            wraps[static_cast<int>(t.wrap_y)]);
    if (t.tint.r != 1 || t.tint.g != 1 || t.tint.b != 1 || t.tint.a != 1)
      appendf(s, " tint rgba(%g,%g,%g,%g)", t.tint.r, t.tint.g, t.tint.b, t.tint.a);
    append_matrix(s, t.xf);
    s += "\n";
  }
  for (size_t i = 0; i < scene.patterns.size(); i++) {
    const Pattern& p = scene.patterns[i];
    appendf(s, "%spattern %zu", indent.c_str(), i);
    append_matrix(s, p.xf);
    s += "\n";
    dump_into(s, *p.tile, indent + "    ");
  }
  for (size_t i = 0; i < scene.meshes.size(); i++) {
    const Mesh& m = scene.meshes[i];
    appendf(s, "%smesh %zu triangles %zu", indent.c_str(), i, m.vertices.size() / 3);
    if (!m.ramp.empty()) appendf(s, " ramp %zu stops", m.ramp.size());
    append_matrix(s, m.xf);
    s += "\n";
  }
}

const char* filter_kind_name(FilterKind k) {
  static const char* const names[] = {"blend", "colormatrix", "componenttransfer", "composite", "convolvematrix",
                                      "diffuselighting", "displacementmap", "dropshadow", "flood", "gaussianblur",
                                      "image", "merge", "morphology", "offset", "specularlighting", "tile",
                                      "turbulence"};
  return names[static_cast<int>(k)];
}

void append_input(std::string& s, int32_t in) {
  static const char* const named[] = {"SourceGraphic", "SourceAlpha", "BackgroundImage", "BackgroundAlpha",
                                      "FillPaint", "StrokePaint"};
  if (in >= 0) appendf(s, " %d", in);
  else appendf(s, " %s", named[-in - 1]);
}

// A primitive's inputs and the parameters its kind reads.
void dump_primitive(std::string& s, const FilterPrimitive& p, size_t i, const std::string& indent) {
  appendf(s, "%s%zu %s", indent.c_str(), i, filter_kind_name(p.kind));
  const FilterKind k = p.kind;
  const bool two = k == FilterKind::Blend || k == FilterKind::Composite || k == FilterKind::DisplacementMap;
  const bool none = k == FilterKind::Flood || k == FilterKind::Image || k == FilterKind::Turbulence ||
                    k == FilterKind::Merge;
  if (!none) {
    s += " in";
    append_input(s, p.in);
  }
  if (two) {
    s += " in2";
    append_input(s, p.in2);
  }
  if (k == FilterKind::Merge) {
    s += " nodes";
    for (int32_t in : p.inputs) append_input(s, in);
  }
  appendf(s, " subregion %g %g %g %g%s", p.subregion.x, p.subregion.y, p.subregion.w, p.subregion.h,
          p.linear_rgb ? "" : " srgb");
  static const char* const edges[] = {"none", "duplicate", "wrap", "mirror"};
  static const char* const ops[] = {"over", "in", "out", "atop", "xor", "arithmetic", "lighter"};
  switch (k) {
    case FilterKind::Flood:
    case FilterKind::DropShadow:
      appendf(s, " color rgba(%g,%g,%g,%g)", p.color[0], p.color[1], p.color[2], p.color[3]);
      if (k == FilterKind::Flood) break;
      [[fallthrough]];
    case FilterKind::Offset:
      appendf(s, " d %g %g", p.dx, p.dy);
      if (k == FilterKind::Offset) break;
      appendf(s, " std %g %g", p.std_dev_x, p.std_dev_y);
      break;
    case FilterKind::GaussianBlur: appendf(s, " std %g %g edge %s", p.std_dev_x, p.std_dev_y, edges[int(p.edge_mode)]); break;
    case FilterKind::Blend: appendf(s, " mode %s", blend_mode_name(static_cast<BlendMode>(p.blend_mode))); break;
    case FilterKind::Composite:
      appendf(s, " op %s", ops[int(p.op)]);
      if (p.op == CompositeOp::Arithmetic) appendf(s, " k %g %g %g %g", p.k[0], p.k[1], p.k[2], p.k[3]);
      break;
    case FilterKind::ColorMatrix:
      s += " matrix";
      for (float v : p.matrix) appendf(s, " %g", v);
      break;
    case FilterKind::ComponentTransfer: {
      static const char* const types[] = {"identity", "table", "discrete", "linear", "gamma"};
      for (int c = 0; c < 4; c++) {
        const TransferFunction& f = p.funcs[c];
        appendf(s, " %c:%s", "rgba"[c], types[int(f.type)]);
        if (f.type == TransferType::Table || f.type == TransferType::Discrete)
          for (float v : f.table) appendf(s, ",%g", v);
        if (f.type == TransferType::Linear) appendf(s, ",%g,%g", f.slope, f.intercept);
        if (f.type == TransferType::Gamma) appendf(s, ",%g,%g,%g", f.amplitude, f.exponent, f.offset);
      }
      break;
    }
    case FilterKind::Morphology: appendf(s, " %s %g %g", p.dilate ? "dilate" : "erode", p.radius_x, p.radius_y); break;
    case FilterKind::ConvolveMatrix:
      appendf(s, " order %d %d target %d %d divisor %g bias %g edge %s%s kernel", p.order_x, p.order_y, p.target_x,
              p.target_y, p.divisor, p.bias, edges[int(p.edge_mode)], p.preserve_alpha ? " preserve-alpha" : "");
      for (float v : p.kernel) appendf(s, " %g", v);
      break;
    case FilterKind::DisplacementMap:
      appendf(s, " scale %g channels %c %c", p.scale, "RGBA"[p.x_channel & 3], "RGBA"[p.y_channel & 3]);
      break;
    case FilterKind::DiffuseLighting:
    case FilterKind::SpecularLighting: {
      appendf(s, " surface %g color rgba(%g,%g,%g,%g)", p.surface_scale, p.color[0], p.color[1], p.color[2],
              p.color[3]);
      if (k == FilterKind::DiffuseLighting) appendf(s, " kd %g", p.diffuse_constant);
      else appendf(s, " ks %g exponent %g", p.specular_constant, p.specular_exponent);
      const LightSource& l = p.light;
      if (l.type == LightType::Distant) appendf(s, " distant %g %g", l.azimuth, l.elevation);
      if (l.type == LightType::Point) appendf(s, " point %g %g %g", l.x, l.y, l.z);
      if (l.type == LightType::Spot) {
        appendf(s, " spot %g %g %g at %g %g %g exponent %g", l.x, l.y, l.z, l.points_at_x, l.points_at_y,
                l.points_at_z, l.specular_exponent);
        if (l.has_cone) appendf(s, " cone %g", l.limiting_cone_angle);
      }
      break;
    }
    case FilterKind::Turbulence:
      appendf(s, " %s freq %g %g octaves %d seed %g%s", p.fractal_noise ? "fractalnoise" : "turbulence",
              p.base_frequency_x, p.base_frequency_y, p.num_octaves, p.seed, p.stitch_tiles ? " stitch" : "");
      break;
    case FilterKind::Image:
      if (p.image) appendf(s, " image %dx%d", p.image->width, p.image->height);
      append_matrix(s, p.image_xf);
      if (p.image_pixelated) s += " pixelated";
      if (p.scene) s += " scene";
      break;
    case FilterKind::Merge:
    case FilterKind::Tile: break;
  }
  s += "\n";
  if (k == FilterKind::Image && p.scene) dump_into(s, *p.scene, indent + "    ");
}

void dump_filters(std::string& s, const Scene& scene, const std::string& indent) {
  for (size_t i = 0; i < scene.filters.size(); i++) {
    const FilterEffect& f = scene.filters[i];
    appendf(s, "%sfilter %zu region %g %g %g %g", indent.c_str(), i, f.region.x, f.region.y, f.region.w, f.region.h);
    append_matrix(s, f.xf);
    if (f.fill_paint[3] > 0)
      appendf(s, " fill rgba(%g,%g,%g,%g)", f.fill_paint[0], f.fill_paint[1], f.fill_paint[2], f.fill_paint[3]);
    if (f.stroke_paint[3] > 0)
      appendf(s, " stroke rgba(%g,%g,%g,%g)", f.stroke_paint[0], f.stroke_paint[1], f.stroke_paint[2],
              f.stroke_paint[3]);
    s += "\n";
    for (size_t k = 0; k < f.primitives.size(); k++) dump_primitive(s, f.primitives[k], k, indent + "  ");
    appendf(s, "%s  source\n", indent.c_str());
    dump_into(s, *f.source, indent + "    ");
  }
}

void dump_groups(std::string& s, const Scene& scene, const std::string& indent) {
  for (size_t i = 0; i < scene.groups.size(); i++) {
    const Group& g = scene.groups[i];
    appendf(s, "%sgroup %zu opacity %g %s%s%s", indent.c_str(), i, g.opacity, blend_mode_name(g.blend),
            g.isolated ? "" : " non-isolated", g.knockout ? " knockout" : "");
    if (g.mask == MaskType::Alpha) s += " mask alpha";
    if (!(g.channels[0] == ChannelRule::Blend && g.channels[1] == ChannelRule::Blend &&
          g.channels[2] == ChannelRule::Blend)) {
      s += " channels";
      for (ChannelRule r : g.channels)
        s += r == ChannelRule::Blend ? " blend" : r == ChannelRule::Source ? " source" : " backdrop";
    }
    if (g.subtractive) s += " subtractive";
    if (g.mask == MaskType::Luminance) {
      appendf(s, " mask luminance %g %g %g %s", g.luminance[0], g.luminance[1], g.luminance[2],
              g.luminance_space == ColorSpace::Srgb ? "srgb" : "linearrgb");
      if (g.backdrop.a != 0)
        appendf(s, " backdrop rgba(%g,%g,%g,%g)", g.backdrop.r, g.backdrop.g, g.backdrop.b, g.backdrop.a);
    }
    if (g.back_to_front) s += " back-to-front";
    s += "\n";
  }
}

void dump_into(std::string& s, const Scene& scene, const std::string& indent) {
  const char* in = indent.c_str();
  appendf(s, "%sscene %g %g\n", in, scene.width, scene.height);
  for (size_t i = 0; i < scene.paths.size(); i++) {
    const ScenePath& sp = scene.paths[i];
    appendf(s, "%spath %zu %s %s", in, i, sp.is_clip ? "clip" : "fill",
            sp.rule == FillRule::NonZero ? "nonzero" : "evenodd");
    if (!sp.is_clip) {
      const Paint& p = scene.paints[sp.paint];
      if (p.type == PaintType::Solid)
        appendf(s, " rgba(%g,%g,%g,%g) opacity %g", p.color.r, p.color.g, p.color.b, p.color.a, p.opacity);
      else
        appendf(s, " %s %u opacity %g", paint_type_name(p.type), p.index, p.opacity);
    }
    if (sp.aliased) s += " aliased";
    if (sp.stroke >= 0) {
      static const char* joins[] = {"miter", "miter-clip", "arcs", "round", "bevel"};
      static const char* caps[] = {"butt", "round", "square"};
      const StrokeStyle& st = scene.strokes[sp.stroke];
      appendf(s, " stroke %g %s %s %g", st.width, joins[static_cast<int>(st.join)], caps[static_cast<int>(st.cap)],
              st.miter_limit);
      if (!st.dashes.empty()) {
        s += " dashes";
        for (double d : st.dashes) appendf(s, " %g", d);
        appendf(s, " offset %g", st.dash_offset);
      }
    }
    append_matrix(s, sp.xf);
    s += "\n";
    const Path& g = scene.geometries[sp.geometry];
    for (const Path::Contour& c : g.contours()) {
      const Vec2 p0 = g.points()[c.start_point];
      appendf(s, "%s  M %g %g", in, p0.x, p0.y);
      for (uint32_t k = 0; k < c.segment_count; k++) {
        const Path::Segment& seg = g.segments()[c.first_segment + k];
        const Vec2* p = &g.points()[seg.first_point];
        switch (seg.type) {
          case SegmentType::Line: appendf(s, " L %g %g", p[1].x, p[1].y); break;
          case SegmentType::Quad: appendf(s, " Q %g %g %g %g", p[1].x, p[1].y, p[2].x, p[2].y); break;
          case SegmentType::RQuad:
            appendf(s, " R %g %g %g %g w %g", p[1].x, p[1].y, p[2].x, p[2].y, g.weights()[seg.first_weight]);
            break;
          case SegmentType::Cubic:
            appendf(s, " C %g %g %g %g %g %g", p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
            break;
          case SegmentType::RCubic:
            appendf(s, " RC %g %g %g %g %g %g", p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
            break;
        }
      }
      if (c.closed) s += " Z";
      s += "\n";
    }
  }
  dump_servers(s, scene, indent);
  dump_filters(s, scene, indent);
  dump_groups(s, scene, indent);
  s += indent + "stream";
  for (const Element& e : scene.stream) {
    switch (e.kind) {
      case ElementKind::Push: s += " ("; break;
      case ElementKind::Activate: s += " |"; break;
      case ElementKind::Pop: s += " )"; break;
      case ElementKind::Fill: appendf(s, " F%u", e.path); break;
      case ElementKind::Clip: appendf(s, " C%u", e.path); break;
      case ElementKind::BeginGroup: appendf(s, " {%u", e.path); break;
      case ElementKind::EndGroup: s += " }"; break;
    }
  }
  s += "\n";
}

}  // namespace

std::string dump(const Scene& scene) {
  std::string s;
  dump_into(s, scene, "");
  return s;
}


namespace {

// Each tile once: a tile shared by many patterns is not walked again.
bool aliased_in(const Scene& scene, std::unordered_set<const Scene*>& seen) {
  if (!seen.insert(&scene).second) return false;
  for (const ScenePath& p : scene.paths)
    if (p.aliased) return true;
  for (const Pattern& p : scene.patterns)
    if (p.tile && aliased_in(*p.tile, seen)) return true;
  for (const FilterEffect& f : scene.filters)
    if (f.source && aliased_in(*f.source, seen)) return true;
  return false;
}

}  // namespace

bool has_aliased_paths(const Scene& scene) {
  std::unordered_set<const Scene*> seen;
  return aliased_in(scene, seen);
}

}  // namespace mpvg

