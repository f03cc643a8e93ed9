// Stages "schedule", "sample" and "integrate" on the CPU. Cells are aligned
// to pixels, so the unit areas of a leaf are the pixels it covers (the
// non-warped scheduler of §5.3); threads take strips of one leaf at a time,
// so a cell's stream stays in cache while its samples are evaluated.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "core/cpu/cpu_stages.h"
#include "core/sampling.h"

namespace mpvg {

namespace {

struct Task {
  uint32_t leaf;
  uint32_t x0, x1, y0, y1;
};

constexpr uint32_t kMaxTaskPixels = 256;

}  // namespace

ImageF render_tree_cpu(const ShortcutTree& tree, int width, int height, const std::vector<SampleOffset>& pattern,
                       const PaintRecord& background, int threads, RenderTimes* times) {
  auto t0 = std::chrono::steady_clock::now();
  ImageF img;
  img.width = width;
  img.height = height;
  img.rgba.assign(size_t(width) * size_t(height) * 4, 0.0f);
  // Schedule: each leaf's pixels inside the image, in strips.
  std::vector<Task> tasks;
  std::vector<char> uniform(tree.leaves.size(), 1);
  for (size_t l = 0; l < tree.leaves.size(); l++)
    for (uint32_t i = tree.leaves[l].begin; i < tree.leaves[l].end && uniform[l]; i++)
      uniform[l] = !entry_is_geometry(tree.leaf_entries[i]);
  for (uint32_t l = 0; l < tree.leaves.size(); l++) {
    const Cell& c = tree.leaves[l];
    const uint32_t s = tree.root_size >> c.level;
    const uint32_t x0 = c.ix * s, y0 = c.iy * s;
    const uint32_t x1 = std::min<uint32_t>(x0 + s, static_cast<uint32_t>(width));
    const uint32_t y1 = std::min<uint32_t>(y0 + s, static_cast<uint32_t>(height));
    if (x0 >= x1 || y0 >= y1) continue;
    const uint32_t rows = std::max<uint32_t>(1, kMaxTaskPixels / (x1 - x0));
    for (uint32_t y = y0; y < y1; y += rows) tasks.push_back({l, x0, x1, y, std::min(y1, y + rows)});
  }
  if (times) times->schedule_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  t0 = std::chrono::steady_clock::now();
  const SampleInputs in{tree.leaf_entries.data(), tree.segments.data(), tree.paths.data(), tree.paints.data()};
  const int n = static_cast<int>(pattern.size());
  const float w = box_weight(n);
  std::atomic<size_t> next{0};
  auto worker = [&]() {
    for (;;) {
      const size_t ti = next.fetch_add(1, std::memory_order_relaxed);
      if (ti >= tasks.size()) return;
      const Task& task = tasks[ti];
      const Cell& c = tree.leaves[task.leaf];
      if (uniform[task.leaf]) {
        // No geometry in the cell: every sample has the colour of its
        // initial windings, so one evaluation serves the whole strip.
        const Rgba4 col = sample_cell(in, c.begin, c.end, float(task.x0), float(task.y0));
        const float under = 1.0f - col.a;
        const float px[4] = {col.r + under * background.r, col.g + under * background.g,
                             col.b + under * background.b, col.a + under * background.a};
        for (uint32_t y = task.y0; y < task.y1; y++)
          for (uint32_t x = task.x0; x < task.x1; x++)
            std::copy(px, px + 4, &img.rgba[(size_t(y) * size_t(width) + x) * 4]);
        continue;
      }
      for (uint32_t y = task.y0; y < task.y1; y++) {
        for (uint32_t x = task.x0; x < task.x1; x++) {
          float acc[4] = {0, 0, 0, 0};
          for (int k = 0; k < n; k++) {
            const Rgba4 col = sample_cell(in, c.begin, c.end, float(x) + pattern[k].x, float(y) + pattern[k].y);
            acc[0] += col.r;
            acc[1] += col.g;
            acc[2] += col.b;
            acc[3] += col.a;
          }
          float* px = &img.rgba[(size_t(y) * size_t(width) + x) * 4];
          const float r = acc[0] * w, g = acc[1] * w, b = acc[2] * w, a = acc[3] * w;
          const float under = 1.0f - a;
          px[0] = r + under * background.r;
          px[1] = g + under * background.g;
          px[2] = b + under * background.b;
          px[3] = a + under * background.a;
        }
      }
    }
  };
  int nt = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  nt = std::max(1, std::min<int>(nt, static_cast<int>(tasks.size())));
  std::vector<std::thread> pool;
  for (int i = 1; i < nt; i++) pool.emplace_back(worker);
  worker();
  for (std::thread& th : pool) th.join();
  if (times) times->sample_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return img;
}

}  // namespace mpvg
