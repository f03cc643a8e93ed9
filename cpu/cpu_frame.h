// The CPU executor's frame: a scene encoded, its filter layers made on the
// CPU (cpu_filters), its tree built and sampled by the stages of
// cpu/cpu_stages.h, one frame or a forest of them. The tested reference the
// GPU's frames (gpu/gpu_backend.h) match byte for byte.
#pragma once
#include <vector>

#include "core/output/image.h"
#include "frame/filter_layers.h"
#include "frame/frame.h"

namespace mpvg {

// Renders on the CPU. Throws mpvg::Error for scenes it cannot render.
ImageF render_cpu(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);
// The same for a scene already encoded for these options (encode_for), so
// that encoding can run on another thread than rendering.
ImageF render_cpu(const EncodedScene& scene, const RenderOptions& options, RenderStats* stats = nullptr);
// ... with the plan already made.
ImageF render_cpu(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                  RenderStats* stats = nullptr);

// render_cpu's frame as 8-bit codes (to_rgba8's of its image), made
// without the float image: what FrameRenderer's CPU frames render.
std::vector<uint8_t> render_cpu_rgba8(const EncodedScene& scene, const RenderPlan& plan, const RenderOptions& options,
                                      RenderStats* stats = nullptr);

// The scene encoded as both backends render it with these options
// (encode_frame), filter layers made by `filters` or, when null, by the CPU
// (cpu_filters); stats->encode_ms, if given, receives the time.
EncodedScene encode_for(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);
EncodedScene encode_for(const Scene& scene, const RenderPlan& plan, Gamma gamma, RenderStats* stats = nullptr,
                        const FilterExecutor* filters = nullptr);

// The CPU executor of a forest frame (frame/forest.h): one build, then each
// scene's image as render_cpu gives it alone. options: the scenes' shared
// options (same_frame_options).
std::vector<ImageF> render_forest_cpu(const std::vector<FrameScene>& scenes, const RenderOptions& options);

// render_forest_cpu, converted: what either backend's FrameRenderer gives
// for a forest frame on the CPU.
std::vector<FrameOutput> render_forest_cpu_8bit(const std::vector<FrameScene>& scenes, const RenderOptions& options,
                                                FrameOutputKind kind);

// An image's PNG rows filtered on the CPU (to_rgba8, png::filter_image on
// one thread), into storage's memory: what render_filtered gives on the
// CPU; stats->png_ms, if given, receives the time.
png::FilteredRows filter_rows_cpu(const ImageF& image, Gamma gamma, RenderStats* stats = nullptr,
                                  std::vector<uint8_t> storage = {});
// ... of 8-bit codes already made, width x height pixels.
png::FilteredRows filter_rows_cpu(const uint8_t* rgba8, int width, int height, RenderStats* stats = nullptr,
                                  std::vector<uint8_t> storage = {});

// The CPU's filter executor: each source rendered by render_cpu, each graph
// by run_filter_cpu.
FilterExecutor cpu_filters(int threads = 0);

// The CPU executor's filter graph (cpu/filter.cpp).
FilterResult run_filter_cpu(const FilterLayer& layer, int threads = 0);

}  // namespace mpvg
