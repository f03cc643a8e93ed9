#include "frame/frame.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <mutex>

#include "core/error.h"
#include "frame/filter_layers.h"
#include "frame/forest.h"
#include "core/sampling/integration.h"
#include "core/output/rgba8.h"

namespace mpvg {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Unpremultiplies a pixel and encodes it to sRGB in [0, 1].
void to_straight_srgb(const float* p, Gamma gamma, float out[4]) {
  const float a = std::min(1.0f, std::max(0.0f, p[3]));
  for (int c = 0; c < 3; c++) {
    float v = a > 0.0f ? p[c] / a : 0.0f;
    v = std::min(1.0f, std::max(0.0f, v));
    out[c] = gamma == Gamma::Linear ? linear_to_srgb(v) : v;
  }
  out[3] = a;
}

}  // namespace

PaintRecord background_paint(const RGBA& c, Gamma gamma) {
  const float a = std::min(1.0f, std::max(0.0f, c.a));
  float r = c.r, g = c.g, b = c.b;
  if (gamma == Gamma::Linear) {
    r = srgb_to_linear(r);
    g = srgb_to_linear(g);
    b = srgb_to_linear(b);
  }
  return PaintRecord{r * a, g * a, b * a, a, PAINT_SOLID, 0, 0, 0};
}

namespace {

// make_integration depends on five options, not on the frame, and costs
// ~45 us (a 4x4x32 pattern and its weights): the frames of a run (a
// batch's pages, a scene's filter layers, 100 of them) share the last few.
Integration integration_for(const RenderOptions& o) {
  struct Entry {
    Filter filter;
    PatternKind pattern;
    int samples;
    uint32_t seed;
    bool aliased;
    Integration integ;
  };
  static std::mutex mutex;
  static std::vector<Entry> cache;  // most recent last
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (const Entry& e : cache)
      if (e.filter == o.filter && e.pattern == o.pattern && e.samples == o.samples && e.seed == o.seed &&
          e.aliased == o.aliased_paths)
        return e.integ;
  }
  Integration integ = make_integration(o.filter, o.pattern, o.samples, o.seed, o.aliased_paths);
  const std::lock_guard<std::mutex> lock(mutex);
  if (cache.size() >= 8) cache.erase(cache.begin());
  cache.push_back(Entry{o.filter, o.pattern, o.samples, o.seed, o.aliased_paths, integ});
  return integ;
}

}  // namespace

RenderPlan plan_render(const RenderOptions& o) {
  if (o.width <= 0 || o.height <= 0) throw Error("output size must be positive");
  if (o.width > 32768 || o.height > 32768) throw Error("output size is larger than 32768 pixels");
  if (o.samples < 1 || o.samples > 1024) throw Error("samples per unit area must be between 1 and 1024");
  RenderPlan p;
  p.integ = integration_for(o);
  p.pattern = std::vector<SampleOffset>(p.integ.offsets.begin(), p.integ.offsets.begin() + o.samples);
  p.frame = integration_frame(p.integ, o.width, o.height);
  p.view = Affine::translate(p.frame.to_unit_areas, p.frame.to_unit_areas) * o.view;
  p.tree = resolve_stop_rule(o.tree, o.samples);
  p.options = o;
  return p;
}

EncodeOptions encode_options(const RenderPlan& plan) {
  EncodeOptions eo;
  eo.frame_width = plan.frame.ua_w;
  eo.frame_height = plan.frame.ua_h;
  const double off = plan.frame.to_unit_areas;
  eo.border.set = true;
  eo.border.x0 = off, eo.border.y0 = off;
  eo.border.x1 = off + plan.frame.width, eo.border.y1 = off + plan.frame.height;
  eo.border.fx1 = plan.frame.ua_w, eo.border.fy1 = plan.frame.ua_h;
  eo.budget = plan.options.budget.get();
  return eo;
}
EncodedScene encode_frame(const Scene& scene, const RenderPlan& plan, Gamma gamma, const FilterExecutor& filters,
                          RenderStats* stats) {
  const auto t0 = std::chrono::steady_clock::now();
  if (has_filters(scene)) {
    // Filter effects become layers first (frame/filter_layers.h): their
    // sources rendered, their graphs run.
    std::vector<std::string> warnings;
    RenderOptions o = plan.options;
    o.gamma = gamma;
    const FilterExecutor& ex = filters;
    const Scene resolved = resolve_filters(scene, o, ex, &warnings);
    double filter_ms = ms_since(t0);
    size_t tile_layers = 0;
    // Filters inside pattern tiles: layers over each tile's grid, made as
    // the encoder reaches the tile (it chooses the grid).
    EncodeOptions eo = encode_options(plan);
    eo.tile_filters = [&](const Scene& tile, int width, int height, const Affine& view) {
      const auto t1 = std::chrono::steady_clock::now();
      RenderOptions to = o;
      to.width = width;
      to.height = height;
      to.view = view;
      to.background = RGBA{0, 0, 0, 0};
      Scene r = resolve_filters(tile, to, ex, &warnings, TextureFilter::Bilinear);
      tile_layers += r.textures.size() - tile.textures.size();
      filter_ms += ms_since(t1);
      return r;
    };
    EncodedScene enc = encode(resolved, plan.view, gamma, eo);
    if (stats) {
      stats->filter_ms += filter_ms;
      stats->filter_layers += resolved.textures.size() - scene.textures.size() + tile_layers;
      stats->warnings.insert(stats->warnings.end(), warnings.begin(), warnings.end());
      stats->encode_ms += ms_since(t0);
    }
    return enc;
  }
  EncodedScene enc = encode(scene, plan.view, gamma, encode_options(plan));
  if (stats) stats->encode_ms += ms_since(t0);
  return enc;
}

bool same_frame_options(const RenderOptions& a, const RenderOptions& b) {
  const TreeParams &ta = a.tree, &tb = b.tree;
  return a.background.r == b.background.r && a.background.g == b.background.g && a.background.b == b.background.b &&
         a.background.a == b.background.a && a.samples == b.samples && a.seed == b.seed && a.filter == b.filter &&
         a.pattern == b.pattern && a.gamma == b.gamma && a.backend == b.backend && a.threads == b.threads &&
         a.aliased_paths == b.aliased_paths && ta.min_segments == tb.min_segments && ta.max_depth == tb.max_depth &&
         ta.max_entries == tb.max_entries && ta.prune == tb.prune && ta.grid_levels == tb.grid_levels &&
         ta.keep_levels == tb.keep_levels;
}

bool same_frame_grid(const RenderPlan& a, const RenderPlan& b) {
  return tree_root_size(a.frame.ua_w, a.frame.ua_h) == tree_root_size(b.frame.ua_w, b.frame.ua_h);
}

EncodedScene forest_of(const std::vector<FrameScene>& scenes) {
  std::vector<ForestScene> fs;
  fs.reserve(scenes.size());
  for (const FrameScene& s : scenes)
    if (!same_frame_grid(*s.plan, *scenes.front().plan))
      throw Error("a forest frame's scenes need root squares of one size (same_frame_grid)");
  for (const FrameScene& s : scenes)
    fs.push_back(ForestScene{s.scene, s.plan->frame.ua_w, s.plan->frame.ua_h});
  return make_forest(fs);
}

const SrgbCodeTable& srgb_code_table() {
  static const SrgbCodeTable table = [] {
    SrgbCodeTable t{};
    auto code = [](float v) { return std::lround(linear_to_srgb(v) * 255.0f); };
    t.start[0] = 0.0f;
    for (int k = 1; k < 256; k++) {
      uint32_t lo = 0, hi = 0x3f800000u;  // the bit patterns of 0 and 1: positive floats order as integers
      while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        float v;
        std::memcpy(&v, &mid, sizeof v);
        if (code(v) >= k)
          hi = mid;
        else
          lo = mid + 1;
      }
      std::memcpy(&t.start[k], &lo, sizeof lo);
    }
    t.start[256] = INFINITY;
    for (int i = 0; i <= SrgbCodeTable::kBuckets; i++) {
      const float v = static_cast<float>(i) / SrgbCodeTable::kBuckets;
      int k = 0;
      while (k < 255 && t.start[k + 1] <= v) k++;
      t.bucket[i] = static_cast<uint8_t>(k);
    }
    return t;
  }();
  return table;
}

std::vector<uint8_t> to_rgba8(const ImageF& image, Gamma gamma) {
  const SrgbCodeTable& t = srgb_code_table();
  const bool linear = gamma == Gamma::Linear;
  std::vector<uint8_t> out(image.rgba.size());
  for (size_t i = 0; i < image.rgba.size(); i += 4) {
    const float* p = &image.rgba[i];
    const uint32_t v = rgba8_pixel(p[0], p[1], p[2], p[3], linear, t);
    for (int c = 0; c < 4; c++) out[i + c] = static_cast<uint8_t>(v >> (8 * c));
  }
  return out;
}

std::vector<uint16_t> to_rgba16(const ImageF& image, Gamma gamma) {
  std::vector<uint16_t> out(image.rgba.size());
  for (size_t i = 0; i < image.rgba.size(); i += 4) {
    float v[4];
    to_straight_srgb(&image.rgba[i], gamma, v);
    for (int c = 0; c < 4; c++) out[i + c] = static_cast<uint16_t>(std::lround(v[c] * 65535.0f));
    if (out[i + 3] == 0) out[i] = out[i + 1] = out[i + 2] = 0;  // as rgba8_pixel: no colour without alpha
  }
  return out;
}

}  // namespace mpvg
