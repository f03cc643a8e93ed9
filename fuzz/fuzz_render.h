// The rendering half of the end-to-end targets (fuzz_svg, fuzz_pdf): a
// scene encoded and rendered on the CPU as svg2png and pdf2png do it
// (apps/svg2png.cpp run: output geometry, plan_render, encode_for,
// render_cpu, 8-bit conversion), at most kMaxSide pixels on a side, on one
// thread, under a memory budget of kBudgetBytes. The antialiasing mode cycles with `variant` through the
// converters' presets (4x4x32 in linear light, the default; 1x32 in sRGB, as
// the shared suites' references; 1x8).
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "frame/frame.h"
#include "core/scene.h"
#include "fuzz/fuzz_common.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_info.h"

namespace mpvg::fuzz {

// The scene-to-pixel transform for a document of w x h units, or false
// when it has no size to render (cli::output_geometry throws then).
inline bool output_view(double w, double h, int* width, int* height, Affine* view) {
  if (!(w > 0 && h > 0) || !std::isfinite(w) || !std::isfinite(h)) return false;
  clamp_output(w, h, width, height);
  *view = Affine::scale(*width / w, *height / h);
  return true;
}

// The memory budget of a fuzzed render (the fuzzers' RSS limit is 2 GiB).
constexpr uint64_t kBudgetBytes = uint64_t(256) << 20;

inline void render_small(const Scene& scene, const Affine& view, int width, int height, unsigned variant) {
  RenderOptions ro;
  ro.width = width;
  ro.height = height;
  ro.view = view;
  ro.backend = Backend::Cpu;
  ro.threads = 1;
  switch (variant % 3) {
    case 0: ro.filter = Filter::Cardinal, ro.samples = 32, ro.pattern = PatternKind::BlueNoise, ro.gamma = Gamma::Linear; break;
    case 1: ro.filter = Filter::Box, ro.samples = 32, ro.pattern = PatternKind::Stratified, ro.gamma = Gamma::Srgb; break;
    default: ro.filter = Filter::Box, ro.samples = 8, ro.pattern = PatternKind::Stratified, ro.gamma = Gamma::Linear; break;
  }
  ro.aliased_paths = has_aliased_paths(scene);
  // A budget as the converters give one (core/memory_budget.h), small
  // enough that inputs reach its refusals: a ResourceError is an outcome.
  ro.budget = std::make_shared<MemoryBudget>(kBudgetBytes);
  RenderStats stats;
  const RenderPlan plan = plan_render(ro);
  const EncodedScene enc = encode_for(scene, plan, ro.gamma, &stats);
  const ImageF img = render_cpu(enc, plan, ro, &stats);
  const std::vector<uint8_t> rgba = to_rgba8(img, ro.gamma);
  if (rgba.size() != size_t(width) * size_t(height) * 4) __builtin_trap();
}

}  // namespace mpvg::fuzz
