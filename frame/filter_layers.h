// Filter effects as layers (core/filters/filter.h): how a FilterEffect of a scene
// becomes a texture paint before encoding.
//
//   1. The filter region, mapped to output pixels, gives the layer's box:
//      its pixel bounds, cut to the output grown by what the primitives
//      can pull in from outside it (blur extents, offsets, morphology
//      radii); a layer over kMaxFilterLayerPixels is cut further and
//      warned of, never allocated.
//   2. The source (SourceGraphic) is rendered by the same pipeline over that
//      box, at the output's resolution and antialiasing, transparent
//      background: the layer.
//   3. The primitives are resolved to the layer's pixels (FilterOp,
//      core/filters/filter_primitives.h) and run on an executor.
//   4. The result, straight 16-bit sRGB, becomes a texture mapped pixel for
//      pixel onto the output, painted by the region fill that referred to
//      the filter.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/output/image.h"
#include "core/filters/filter_primitives.h"
#include "frame/render_options.h"
#include "core/scene.h"

namespace mpvg {

// Layers larger than this are cut to it (about 4x a 4K frame), and to what
// kMaxFilterBytes (or what a blur over four times the output's pixels
// takes, kOneOpLayerBytes a pixel, where that is more) holds of what the layer
// needs while it is made (filter_layer_bytes), within a quarter of the
// memory budget.
constexpr uint64_t kMaxFilterLayerPixels = uint64_t(1) << 25;
constexpr uint64_t kMaxFilterBytes = uint64_t(1) << 30;
// What filter_layer_bytes gives a graph of one op (a blur): 16 bytes for
// each of its result, two inputs and output, and the source's image and
// the result's texels beside them.
constexpr uint64_t kOneOpLayerBytes = 16 * (1 + 3) + 16 + 8;
// A graph whose ops would read more pixels than this (blur windows,
// morphology windows, convolution kernels, summed over their boxes) is not
// run: the filter draws nothing, with a warning (a bounded time, not a hang).
constexpr double kMaxFilterReads = 2e10;

// One filter effect resolved to pixels: what an executor runs.
struct FilterLayer {
  int width = 0, height = 0;
  std::vector<FilterOp> ops;
  // For each op, the last op that reads its result (ops.size() for none):
  // executors drop a result after it (filter_last_uses).
  std::vector<uint32_t> last_use;
  uint64_t bytes_per_pixel = 0;  // while it is made (filter_layer_bytes)
  std::vector<float> tables;  // component transfer tables
  std::vector<int32_t> inputs;  // merge nodes
  std::vector<double> noise;    // turbulence lattices (turbulence_init)
  // feImage's pictures over the layer (FilterOp::image), premultiplied, in
  // linear light where image_linear says so.
  std::vector<ImageF> images;
  std::vector<uint8_t> image_linear;
  ImageF source;              // SourceGraphic over the layer, premultiplied
  bool source_linear = false; // ... in linear light (else sRGB-encoded)
  Rgba4 fill_paint{0, 0, 0, 0}, stroke_paint{0, 0, 0, 0};  // straight, sRGB-encoded
};

// The graph's result (the last op's): premultiplied RGBA over the layer, in
// linear light when `linear`.
struct FilterResult {
  std::vector<float> rgba;
  bool linear = false;
};

// Renders a scene over options' size and view (the source of a layer):
// the executor's pipeline.
using LayerRenderer = std::function<ImageF(const Scene&, const RenderOptions&)>;

// A layer to make: its graph resolved to pixels and what an executor
// renders into it. layer.width == 0: the filter draws nothing (no pixel of
// it can reach the output, or it was refused as too costly).
struct LayerJob {
  FilterLayer layer;  // source and element pictures not rendered yet
  FilterBox box;      // in output pixels, [x0, x1) x [y0, y1)
  const Scene* source = nullptr;
  RenderOptions source_options;  // the output's, over the layer's pixels, transparent
  // feImage's element references: scenes rendered over the layer like the
  // source, into layer.images[image].
  struct Element {
    uint32_t image = 0;
    const Scene* scene = nullptr;
    RenderOptions options;
  };
  std::vector<Element> elements;
};

// For each primitive of f, the last primitive that reads its result
// (in, in2, merge inputs); f.primitives.size() for none. The last result
// is the graph's.
std::vector<uint32_t> filter_last_uses(const FilterEffect& f);
// Bytes a pixel of f's layer costs while it is made: the source rendered
// over it (its frame's image, unit areas and sums), then the graph (the
// results alive at once, dropped after their last use, and an op's inputs
// and output, 16 bytes a pixel each), the larger of the two; beside both
// the source's image and the result's texels.
uint64_t filter_layer_bytes(const FilterEffect& f);

// The layer of filter `f` of a scene rendered with `options`, planned:
// everything but the renders.
LayerJob plan_layer(const FilterEffect& f, const RenderOptions& options, std::string* warning = nullptr);

// ... with its source and element pictures rendered by `render`; box
// receives its position in output pixels (empty: it draws nothing).
FilterLayer filter_layer(const FilterEffect& f, const RenderOptions& options, const LayerRenderer& render,
                         FilterBox& box, std::string* warning = nullptr);

// An executor of filter layers. run_layers renders every job's source and
// element pictures (resolving the filters inside them with itself), runs
// the graphs, and returns each result as the texels of its texture
// (filter_texel; ExecutorTexels, on the host or the executor's device), in
// job order; null for a job whose layer is empty. It may do the jobs
// together: they are independent.
struct FilterExecutor {
  std::function<std::vector<std::shared_ptr<const Image>>(std::vector<LayerJob>& jobs)> run_layers;
};

// A planned layer's element pictures and source, rendered by `render`
// (an executor's run_layers, before it runs the graph).
void render_layer_inputs(LayerJob& job, const LayerRenderer& render);

// A graph's result as texels of a frame integrated as `gamma`, on the host.
std::vector<Texel16> result_texels(const FilterResult& r, Gamma gamma, int threads = 0);

// Does the scene, or a pattern tile in it, have filter effects?
bool has_filters(const Scene& scene);

// The scene with every Filter paint replaced by the texture of its layer
// (the scene itself when it has none), the layers of its filters made by
// `ex` all together. Warnings (layers cut or refused) are appended. The
// textures are read with `lookup`: Nearest where a layer's texels are the
// frame's pixels (each sample reads its own pixel's), Bilinear where they
// are resampled (a pattern tile's grid drawn rotated or scaled).
Scene resolve_filters(const Scene& scene, const RenderOptions& options, const FilterExecutor& ex,
                      std::vector<std::string>* warnings = nullptr, TextureFilter lookup = TextureFilter::Nearest);

}  // namespace mpvg
