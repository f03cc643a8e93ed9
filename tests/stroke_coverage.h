// Coverage of stroke outputs for the stroke stage's tests (test_stroke on
// the CPU, test_gpu on the device): input segments back to a path, and a
// path's per-pixel coverage at 1x32 box on the CPU renderer.
#pragma once
#include <cmath>
#include <vector>

#include "core/renderer.h"
#include "core/scene.h"
#include "tests/catch.h"

namespace mpvg::test {

constexpr int kSize = 96;

// Input segments (pixels) as a path: a new contour wherever a segment does
// not start where the last one ended.
inline Path path_of(const std::vector<InputSegment>& segs) {
  Path p;
  Vec2 cur{NAN, NAN};
  for (const InputSegment& s : segs) {
    const Vec2 a{s.x[0], s.y[0]};
    if (!(a == cur)) p.move_to(a);
    switch (s.type) {
      case INPUT_LINE: p.line_to({s.x[1], s.y[1]}); cur = {s.x[1], s.y[1]}; break;
      case INPUT_QUAD: p.quad_to({s.x[1], s.y[1]}, {s.x[2], s.y[2]}); cur = {s.x[2], s.y[2]}; break;
      case INPUT_RQUAD: p.rquad_to({s.x[1], s.y[1]}, {s.x[2], s.y[2]}, s.w); cur = {s.x[2], s.y[2]}; break;
      default: FAIL("the stroke stage emits lines, quadratics and conics only");
    }
  }
  return p;
}

// Coverage of a path filled nonzero, `xf` mapping it to pixels: 1x32 box.
inline std::vector<float> coverage(const Path& p, const Affine& xf) {
  SceneBuilder b(kSize, kSize);
  if (!p.empty()) b.fill(b.add_geometry(p), xf, FillRule::NonZero, Paint{});
  const Scene scene = b.finish();
  RenderOptions o;
  o.width = o.height = kSize;
  o.samples = 32;
  o.filter = Filter::Box;
  o.backend = Backend::Cpu;
  o.gamma = Gamma::Linear;
  o.threads = 1;
  const ImageF img = render_cpu(scene, o);
  std::vector<float> a(size_t(kSize) * kSize);
  for (size_t i = 0; i < a.size(); i++) a[i] = img.rgba[4 * i + 3];
  return a;
}

}  // namespace mpvg::test
