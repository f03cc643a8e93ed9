#include "core/encoding.h"

#include <cmath>

#include "core/error.h"

namespace mpvg {

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

namespace {

void check_finite(Vec2 p) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw Error("path has a non-finite coordinate");
}

}  // namespace

EncodedScene encode(const Scene& scene, const Affine& view, Gamma gamma) {
  EncodedScene out;
  if (scene.paths.size() >= kMaxPaths) throw Error("scene has too many paths");
  out.paths.resize(scene.paths.size());
  for (const Paint& p : scene.paints) {
    const float a = std::min(1.0f, std::max(0.0f, p.color.a * p.opacity));
    float r = p.color.r, g = p.color.g, b = p.color.b;
    if (gamma == Gamma::Linear) {
      r = srgb_to_linear(r);
      g = srgb_to_linear(g);
      b = srgb_to_linear(b);
    }
    out.paints.push_back({r * a, g * a, b * a, a});
  }
  for (const Element& e : scene.stream) {
    switch (e.kind) {
      case ElementKind::Push: out.stream.push_back(make_entry(ENTRY_PUSH, 0, 0)); continue;
      case ElementKind::Activate: out.stream.push_back(make_entry(ENTRY_ACTIVATE, 0, 0)); continue;
      case ElementKind::Pop: out.stream.push_back(make_entry(ENTRY_POP, 0, 0)); continue;
      default: break;
    }
    const uint32_t id = e.path;
    const ScenePath& sp = scene.paths[id];
    PathRecord& rec = out.paths[id];
    rec.flags = (sp.rule == FillRule::EvenOdd ? PATH_EVENODD : 0u) | (sp.is_clip ? PATH_CLIP : 0u);
    rec.paint = sp.paint;
    if (!sp.is_clip && out.paints[sp.paint].a >= 1.0f) rec.flags |= PATH_OPAQUE;
    out.stream.push_back(make_entry(ENTRY_SEGMENT, id, 0));

    const Affine xf = view * sp.xf;
    const Path& g = scene.geometries[sp.geometry];
    std::vector<Vec2> pts(g.points().size());
    for (size_t i = 0; i < pts.size(); i++) {
      pts[i] = xf.apply(g.points()[i]);
      check_finite(pts[i]);
    }
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
  }
  return out;
}

}  // namespace mpvg
