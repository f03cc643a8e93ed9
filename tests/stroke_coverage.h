// Coverage of stroke outputs for the stroke stage's tests (test_stroke on
// the CPU, test_gpu on the device): input segments' per-pixel coverage at
// 1x32 box on the CPU renderer.
#pragma once
#include <cmath>
#include <vector>

#include "frame/frame.h"
#include "core/scene.h"
#include "tests/catch.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"

namespace mpvg::test {

constexpr int kSize = 96;

namespace stroke_coverage_detail {
inline RenderOptions options() {
  RenderOptions o;
  o.width = o.height = kSize;
  o.samples = 32;
  o.filter = Filter::Box;
  o.backend = Backend::Cpu;
  o.gamma = Gamma::Linear;
  o.threads = 1;
  return o;
}
}  // namespace stroke_coverage_detail

// A path filled nonzero, `xf` mapping it to pixels, as input segments
// (encode() closes its contours).
inline std::vector<InputSegment> segments_of(const Path& p, const Affine& xf) {
  SceneBuilder b(kSize, kSize);
  b.fill(b.add_geometry(p), xf, FillRule::NonZero, Paint{});
  return encode_for(b.finish(), stroke_coverage_detail::options()).segments;
}

// Per-pixel coverage (1x32 box) of input segments in pixels, filled
// nonzero as one path: the stage's output, whose closed contours come in no
// particular order, goes straight to abstraction.
inline std::vector<float> coverage(std::vector<InputSegment> segs) {
  const RenderOptions o = stroke_coverage_detail::options();
  SceneBuilder b(kSize, kSize);
  b.fill(b.add_geometry(Path::rectangle(0, 0, 1, 1)), Affine{}, FillRule::NonZero, Paint{});
  EncodedScene enc = encode_for(b.finish(), o);
  for (InputSegment& s : segs) s.path = 0;
  enc.segments = std::move(segs);
  enc.input_segment_count = enc.segments.size();
  const ImageF img = render_cpu(enc, o);
  std::vector<float> a(size_t(kSize) * kSize);
  for (size_t i = 0; i < a.size(); i++) a[i] = img.rgba[4 * i + 3];
  return a;
}

}  // namespace mpvg::test
