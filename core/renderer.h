// The renderer's public entry points: a Scene in, an image out, with the
// stage names of the paper for timings. The CPU backend lives here; backend
// choice (auto / cpu / cuda) is gpu/backend.h, which falls back to this.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/output/image.h"
#include "core/encoding.h"
#include "core/sampling/integration.h"
#include "core/memory_budget.h"
#include "core/output/png_encode.h"
#include "core/scene.h"
#include "core/tree/tree.h"

namespace mpvg {

enum class Backend { Auto, Cpu, Cuda };

struct RenderOptions {
  int width = 0, height = 0;  // output pixels
  Affine view;                // scene units to pixels
  RGBA background{0, 0, 0, 0};
  int samples = 32;           // per unit area
  uint32_t seed = 0;          // sample pattern
  Filter filter = Filter::Box;
  PatternKind pattern = PatternKind::Stratified;
  Gamma gamma = Gamma::Srgb;  // colour space of integration
  Backend backend = Backend::Auto;
  TreeParams tree;
  int threads = 0;  // CPU threads, 0 = all cores
  // The scene has aliased paths (has_aliased_paths): a filter of even
  // support then integrates over an odd number of unit areas, which are
  // pixels, so that those paths are drawn aliased (core/sampling/integration.h).
  // Set before planning: the frame, and so the encoding, depend on it.
  bool aliased_paths = false;
  // The render's memory budget (core/memory_budget.h), shared by the
  // parser that made the scene and every stage; null: nothing is counted.
  std::shared_ptr<MemoryBudget> budget;
};

// Per-stage wall times in milliseconds, and what was built.
struct RenderStats {
  std::string backend;  // "cpu" or "cuda"
  std::string note;     // e.g. why auto fell back to the CPU
  std::vector<std::string> warnings;  // what the user should hear of (filter layers cut or not drawn)
  double encode_ms = 0, stroke_ms = 0, abstract_ms = 0, subdivide_ms = 0, prune_ms = 0, schedule_ms = 0, sample_ms = 0;
  double total_ms = 0;
  double png_ms = 0;  // FrameRenderer::render_png's PNG stage (with CUDA: its kernels, timed on the device)
  // Filter layers (core/filters/filter_layers.h), inside encode_ms: the frame's own
  // layers made (theirs nested inside included), and the time taken.
  size_t filter_layers = 0;
  double filter_ms = 0;
  size_t input_segments = 0, abstract_segments = 0, leaves = 0, leaf_entries = 0;
  size_t tree_bytes = 0;
  int depth = 0;
  // Samples evaluated (adaptive sampling: one per flat unit area and per
  // uniform leaf), and the output pixels they were for.
  uint64_t samples = 0, pixels = 0;
};

// Renders on the CPU. Throws mpvg::Error for scenes it cannot render.
ImageF render_cpu(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);
// The same for a scene already encoded for these options (encode_for), so
// that encoding can run on another thread than rendering.
ImageF render_cpu(const EncodedScene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

// The scene encoded as both backends render it with these options;
// stats->encode_ms, if given, receives the time.
EncodedScene encode_for(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

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

// Filter effects' executor (core/filters/filter_layers.h).
struct FilterExecutor;

// encode_for and render_cpu with the plan already made: a frame plans once
// however many of its stages run on this thread. Filter effects are
// resolved into layers first (resolve_filters), by `filters` or the CPU.
EncodedScene encode_for(const Scene& scene, const RenderPlan& plan, Gamma gamma, RenderStats* stats = nullptr,
                        const FilterExecutor* filters = nullptr);
ImageF render_cpu(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                  RenderStats* stats = nullptr);

// Forest frames (core/tree/forest.h): several scenes built into one tree, each
// then rendered over its own grid, to the image it has alone.
//
// May scenes rendered with options a and b share a frame? Everything but
// the output's size and view must agree.
bool same_frame_options(const RenderOptions& a, const RenderOptions& b);

// ... and planned as a and b: do their trees have root squares of one size?
// A forest's roots all have the side of its largest (core/tree/forest.h); a
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

// The CPU executor: one build, then each scene's image as render_cpu gives
// it alone. options: the scenes' shared options (same_frame_options).
std::vector<ImageF> render_forest_cpu(const std::vector<FrameScene>& scenes, const RenderOptions& options);

// A forest frame's image as 8-bit codes (to_rgba8), or with `png` filtered
// and deflated at level 1 (png::compress_rgba8, FrameRenderer::render_png's
// bytes).
struct FrameOutput {
  std::vector<uint8_t> rgba8;
  png::ImageData png;
};

// render_forest_cpu, converted: what either backend's FrameRenderer gives
// for a forest frame on the CPU.
std::vector<FrameOutput> render_forest_cpu_8bit(const std::vector<FrameScene>& scenes, const RenderOptions& options,
                                                bool png);

// The background as a premultiplied paint in the integration colour space.
PaintRecord background_paint(const RGBA& c, Gamma gamma);

// Final image: unpremultiplied, sRGB-encoded, rounded to 8 or 16 bits,
// RGBA interleaved, row-major. Canonical: a pixel whose alpha rounds to 0
// is all zeros.
std::vector<uint8_t> to_rgba8(const ImageF& image, Gamma gamma);
std::vector<uint16_t> to_rgba16(const ImageF& image, Gamma gamma);

}  // namespace mpvg
