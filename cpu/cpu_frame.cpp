// The CPU frame: a scene encoded (its filter layers made by the CPU
// executor), its tree built and sampled by the CPU executor's stages.
#include "cpu/cpu_frame.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include "core/error.h"
#include "cpu/png_encode.h"
#include "core/parallel.h"
#include "cpu/cpu_stages.h"
#include "frame/filter_layers.h"
#include "frame/forest.h"
#include "frame/scene_info.h"

namespace mpvg {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

EncodedScene encode_for(const Scene& scene, const RenderPlan& plan, Gamma gamma, RenderStats* stats,
                        const FilterExecutor* filters) {
  if (filters) return encode_frame(scene, plan, gamma, *filters, stats);
  return encode_frame(scene, plan, gamma, cpu_filters(plan.options.threads), stats);
}

EncodedScene encode_for(const Scene& scene, const RenderOptions& o, RenderStats* stats) {
  return encode_for(scene, plan_render(o), o.gamma, stats);
}

ImageF render_cpu(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
  RenderStats local;
  RenderStats& st = stats ? *stats : local;
  const auto t_all = std::chrono::steady_clock::now();
  RenderOptions o = options;
  o.aliased_paths = o.aliased_paths || has_aliased_paths(scene);
  const RenderPlan plan = plan_render(o);
  const EncodedScene enc = encode_for(scene, plan, o.gamma, &st);
  const double encode_ms = ms_since(t_all);
  ImageF img = render_cpu(enc, plan, o, &st);
  st.total_ms += encode_ms;
  return img;
}

ImageF render_cpu(const EncodedScene& enc, const RenderOptions& o, RenderStats* stats) {
  return render_cpu(enc, plan_render(o), o, stats);
}

namespace {

// render_cpu's frame: the tree built, then render(tree, background, times)
// samples it into what it returns.
template <class Render>
auto render_frame_cpu(const EncodedScene& enc, const RenderPlan& plan, const RenderOptions& o, RenderStats* stats,
                      Render&& render) {
  RenderStats local;
  RenderStats& st = stats ? *stats : local;
  st.backend = "cpu";
  if (enc.paint && !enc.paint->device_texels.empty())
    throw Error("a scene encoded with device texels (filter layers rendered on a GPU) cannot render on the CPU");
  const auto t_all = std::chrono::steady_clock::now();
  BuildTimes bt;
  MemoryBudget* budget = o.budget.get();
  const ShortcutTree tree = build_tree_cpu(enc, plan.frame.ua_w, plan.frame.ua_h, plan.tree, &bt, budget);
  // The frame's buffers while it renders: the image, and for wide filters
  // the unit areas' colours and the fixed-point sums.
  const IntegrationFrame& f = plan.frame;
  const BudgetCharge frame(budget,
                           uint64_t(f.width) * f.height * 16 + uint64_t(f.ua_w) * f.ua_h * 16 +
                               uint64_t(f.acc_w) * f.acc_h * 32,
                           "the frame");
  st.stroke_ms += bt.stroke_ms;
  st.abstract_ms += bt.abstract_ms;
  st.subdivide_ms += bt.subdivide_ms;
  st.prune_ms += bt.prune_ms;
  RenderTimes rt;
  auto img = render(tree, background_paint(o.background, o.gamma), &rt);
  st.schedule_ms += rt.schedule_ms;
  st.sample_ms += rt.sample_ms;
  st.samples += rt.samples;
  st.pixels += uint64_t(f.width) * uint64_t(f.height);
  st.total_ms += ms_since(t_all);
  st.input_segments = enc.input_segment_count;
  st.abstract_segments = tree.segments.size();
  st.leaves = tree.leaves.size();
  st.leaf_entries = tree.leaf_entries.size();
  st.tree_bytes = tree.memory_bytes();
  st.depth = tree.depth;
  return img;
}

}  // namespace

ImageF render_cpu(const EncodedScene& enc, const RenderPlan& plan, const RenderOptions& o, RenderStats* stats) {
  return render_frame_cpu(enc, plan, o, stats, [&](const ShortcutTree& tree, const PaintRecord& bg, RenderTimes* rt) {
    return render_tree_cpu(tree, plan.integ, plan.frame, bg, o.threads, rt);
  });
}

std::vector<uint8_t> render_cpu_rgba8(const EncodedScene& enc, const RenderPlan& plan, const RenderOptions& o,
                                      RenderStats* stats) {
  return render_frame_cpu(enc, plan, o, stats, [&](const ShortcutTree& tree, const PaintRecord& bg, RenderTimes* rt) {
    return render_tree_cpu_rgba8(tree, plan.integ, plan.frame, bg, o.gamma, o.threads, rt);
  });
}

std::vector<ImageF> render_forest_cpu(const std::vector<FrameScene>& scenes, const RenderOptions& o) {
  const auto t_all = std::chrono::steady_clock::now();
  const EncodedScene forest = forest_of(scenes);
  int w = 0, h = 0;
  forest_grid(forest, w, h);
  BuildTimes bt;
  const ShortcutTree tree = build_tree_cpu(forest, w, h, resolve_stop_rule(o.tree, o.samples), &bt);
  if (tree.capped) throw Error(kForestCapped);
  const double share = 1.0 / std::max<size_t>(1, scenes.size());
  const double build_ms = ms_since(t_all);
  const PaintRecord bg = background_paint(o.background, o.gamma);
  std::vector<ImageF> out;
  for (size_t k = 0; k < scenes.size(); k++) {
    const auto t0 = std::chrono::steady_clock::now();
    RenderTimes rt;
    out.push_back(render_tree_cpu(tree, scenes[k].plan->integ, scenes[k].plan->frame, bg, o.threads, &rt,
                                  static_cast<uint32_t>(k)));
    if (!scenes[k].stats) continue;
    RenderStats& st = *scenes[k].stats;
    st.backend = "cpu";
    st.stroke_ms += bt.stroke_ms * share;
    st.abstract_ms += bt.abstract_ms * share;
    st.subdivide_ms += bt.subdivide_ms * share;
    st.prune_ms += bt.prune_ms * share;
    st.schedule_ms += rt.schedule_ms;
    st.sample_ms += rt.sample_ms;
    st.samples += rt.samples;
    st.pixels += uint64_t(scenes[k].plan->frame.width) * uint64_t(scenes[k].plan->frame.height);
    st.total_ms += build_ms * share + ms_since(t0);
    st.input_segments = scenes[k].scene->input_segment_count;
    st.abstract_segments = static_cast<size_t>(tree.segments.size() * share);
    st.leaves = static_cast<size_t>(tree.leaves.size() * share);
    st.leaf_entries = static_cast<size_t>(tree.leaf_entries.size() * share);
    st.tree_bytes = tree.memory_bytes();
    st.depth = tree.depth;
  }
  return out;
}

std::vector<FrameOutput> render_forest_cpu_8bit(const std::vector<FrameScene>& scenes, const RenderOptions& options,
                                                FrameOutputKind kind) {
  std::vector<ImageF> images = render_forest_cpu(scenes, options);
  std::vector<FrameOutput> out(images.size());
  for (size_t k = 0; k < images.size(); k++) {
    const auto t0 = std::chrono::steady_clock::now();
    if (kind == FrameOutputKind::Filtered) {
      out[k].filtered = filter_rows_cpu(images[k], options.gamma, scenes[k].stats);
    } else if (kind == FrameOutputKind::Png) {
      out[k].png = png::compress_rgba8(to_rgba8(images[k], options.gamma).data(), images[k].width, images[k].height);
      if (scenes[k].stats) scenes[k].stats->png_ms += ms_since(t0);
    } else {
      out[k].rgba8 = to_rgba8(images[k], options.gamma);
    }
    images[k] = ImageF{};
  }
  return out;
}

png::FilteredRows filter_rows_cpu(const uint8_t* rgba8, int width, int height, RenderStats* stats,
                                  std::vector<uint8_t> storage) {
  const auto t0 = std::chrono::steady_clock::now();
  png::FilteredRows rows;
  rows.rows = std::move(storage);
  rows.channels = png::filter_image(rgba8, width, height, 1, rows.rows);
  if (stats) stats->png_ms += ms_since(t0);
  return rows;
}

png::FilteredRows filter_rows_cpu(const ImageF& image, Gamma gamma, RenderStats* stats, std::vector<uint8_t> storage) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<uint8_t> rgba8 = to_rgba8(image, gamma);
  if (stats) stats->png_ms += ms_since(t0);
  return filter_rows_cpu(rgba8.data(), image.width, image.height, stats, std::move(storage));
}

FilterExecutor cpu_filters(int threads) {
  return FilterExecutor{[threads](std::vector<LayerJob>& jobs) {
    std::vector<std::shared_ptr<const Image>> out(jobs.size());
    for (size_t k = 0; k < jobs.size(); k++) {
      LayerJob& job = jobs[k];
      FilterLayer& l = job.layer;
      if (l.width <= 0 || l.height <= 0) continue;
      // The result's texels stay; the source's frame is charged by its
      // render, then its image and the graph's working set while it runs.
      MemoryBudget* budget = job.source_options.budget.get();
      const uint64_t pixels = uint64_t(l.width) * l.height;
      charge(budget, pixels * sizeof(Texel16), "a filter layer's result");
      render_layer_inputs(job, [](const Scene& s, const RenderOptions& so) { return render_cpu(s, so); });
      const BudgetCharge working(budget, pixels * (l.bytes_per_pixel - 8), "a filter layer");
      const FilterResult r = run_filter_cpu(l, threads);
      auto texels = std::make_shared<ExecutorTexels>();
      texels->host = r.rgba.empty() ? std::vector<Texel16>(size_t(l.width) * l.height, Texel16{0, 0, 0, 0})
                                    : result_texels(r, job.source_options.gamma, threads);
      auto img = std::make_shared<Image>();
      img->width = l.width;
      img->height = l.height;
      img->texels = std::move(texels);
      out[k] = std::move(img);
      l.source = ImageF{};
    }
    return out;
  }};
}

}  // namespace mpvg
