// A frame, as the host prepares it for either executor: the options it is
// rendered with, the plan both executors make from them (pattern, filter
// weights, grid of unit areas), the scene encoded for that plan (filter
// effects made layers by an executor's FilterExecutor), forests of several
// scenes in one frame, and the stage times of the paper's names. The CPU
// executor's frame is cpu/cpu_frame.h, the GPU's gpu/gpu_backend.h; backend
// choice (auto / cpu / cuda) is lib/backend/backend.h.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/output/image.h"
#include "frame/render_options.h"
#include "frame/encoding.h"
#include "core/sampling/integration.h"
#include "core/memory_budget.h"
#include "core/output/png_encode.h"
#include "core/scene.h"
#include "core/tree/tree.h"

namespace mpvg {

// What both backends prepare from the options: the pattern, the filter's
// weights, the frame of unit areas, and the scene-to-unit-area transform.
struct RenderPlan {
  std::vector<SampleOffset> pattern;
  Integration integ;
  IntegrationFrame frame;
  Affine view;  // scene units to unit-area coordinates
  TreeParams tree;  // options.tree with the stopping rule resolved (resolve_stop_rule)
  RenderOptions options;  // what was planned (filter layers are rendered with them)
};
RenderPlan plan_render(const RenderOptions& options);
// What the encoder takes from a plan: the frame's unit areas, the budget.
EncodeOptions encode_options(const RenderPlan& plan);

// Filter effects' executor (frame/filter_layers.h).
struct FilterExecutor;

// The scene encoded as both backends render it with the plan (a frame plans
// once however many of its stages run on this thread), its filter effects
// resolved into layers first (resolve_filters) by `filters`; stats, if
// given, receive the time (encode_ms, filter_ms) and the layers' warnings.
// The CPU's encode_for (cpu/cpu_frame.h) passes its own executor.
EncodedScene encode_frame(const Scene& scene, const RenderPlan& plan, Gamma gamma, const FilterExecutor& filters,
                          RenderStats* stats = nullptr);

// Forest frames (frame/forest.h): several scenes built into one tree, each
// then rendered over its own grid, to the image it has alone.
//
// May scenes rendered with options a and b share a frame? Everything but
// the output's size and view must agree.
bool same_frame_options(const RenderOptions& a, const RenderOptions& b);

// ... and planned as a and b: do their trees have root squares of one size?
// A forest's roots all have the side of its largest (frame/forest.h); a
// scene's tree, and so its image, is the one a frame of its own gives only
// when that is its own side.
bool same_frame_grid(const RenderPlan& a, const RenderPlan& b);

// What a forest frame throws when its tree would pass TreeParams::
// max_entries (whose cap coarsens every scene's tree): its scenes are
// rendered one frame each instead.
constexpr const char* kForestCapped = "forest frame over the tree's entry cap";

// One scene of a forest frame: encoded for its options (encode_for) and
// planned (its size and view are in the plan). stats, if given, receive the
// scene's stage times (the shared build's divided evenly between the
// scenes).
struct FrameScene {
  const EncodedScene* scene = nullptr;
  const RenderPlan* plan = nullptr;
  RenderStats* stats = nullptr;
};

// The forest of the scenes (copies of their encodings), in order. Throws
// mpvg::Error unless same_frame_grid holds for them all.
EncodedScene forest_of(const std::vector<FrameScene>& scenes);

// What a frame gives back for each of its scenes: the image as 8-bit codes
// (to_rgba8), its PNG rows filtered (png::filter_image, FrameRenderer::
// render_filtered's), or filtered and deflated at level 1
// (png::compress_rgba8, FrameRenderer::render_png's bytes).
enum class FrameOutputKind { Rgba8, Filtered, Png };
struct FrameOutput {
  std::vector<uint8_t> rgba8;
  png::FilteredRows filtered;
  png::ImageData png;
};

// The background as a premultiplied paint in the integration colour space.
PaintRecord background_paint(const RGBA& c, Gamma gamma);

// Final image: unpremultiplied, sRGB-encoded, rounded to 8 or 16 bits,
// RGBA interleaved, row-major. Canonical: a pixel whose alpha rounds to 0
// is all zeros.
std::vector<uint8_t> to_rgba8(const ImageF& image, Gamma gamma);
std::vector<uint16_t> to_rgba16(const ImageF& image, Gamma gamma);

}  // namespace mpvg
