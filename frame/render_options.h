// What a frame is rendered with (RenderOptions) and what its stages report
// (RenderStats, with the paper's stage names): the frame's inputs and
// outputs, shared by frame/frame.h, the filter layers that render frames of
// their own (frame/filter_layers.h) and both executors.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/memory_budget.h"
#include "core/sampling/integration.h"
#include "core/scene.h"
#include "core/tree/tree.h"
#include "frame/encoding.h"

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
  // Filter layers (frame/filter_layers.h), inside encode_ms: the frame's own
  // layers made (theirs nested inside included), and the time taken.
  size_t filter_layers = 0;
  double filter_ms = 0;
  size_t input_segments = 0, abstract_segments = 0, leaves = 0, leaf_entries = 0;
  size_t tree_bytes = 0;
  int depth = 0;
  // Samples evaluated (adaptive sampling: one per flat unit area and per
  // uniform leaf), and the output pixels they were for.
  uint64_t samples = 0, pixels = 0;
  // Time the device's stages (CUDA events: the host waits for each frame's
  // last one); off, a device-driven frame's host only enqueues and waits
  // for its result (pipelines without --stats).
  bool stage_times = true;
};

}  // namespace mpvg
