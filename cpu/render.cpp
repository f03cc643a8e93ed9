// Stages "schedule", "sample" and "integrate" on the CPU. Cells are aligned
// to unit areas, so the unit areas of a leaf are the unit-area grid squares
// it covers (the non-warped scheduler of §5.3); threads take strips of one
// leaf at a time, so a cell's stream stays in cache while its samples are
// evaluated, a unit area's samples together (sample lanes, sampling.h).
//
// Integration (integration.h): with the box filter a unit area is its pixel
// and the average of its samples is written directly. Wider filters send one
// weighted sum per covered pixel into fixed-point accumulators (integers, so
// the order of arrival does not matter; bands of rows keep threads off each
// other's, band_schedule), which are then normalised, passed through the
// cardinal prefilter if asked, clamped and cropped. Pixels go to a sink:
// floats (ImageF) or the 8-bit codes the frames write.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>

#include "cpu/cpu_stages.h"
#include "core/parallel.h"
#include "core/output/rgba8.h"
#include "core/sampling/sampling.h"

namespace mpvg {

namespace {

struct Task {
  uint32_t leaf;
  uint32_t x0, x1, y0, y1;
};

constexpr uint32_t kMaxTaskPixels = 256;

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Schedule: every leaf's unit areas inside the w x h grid, in strips (the
// leaves of one root of a forest).
std::vector<Task> schedule(const ShortcutTree& tree, int w, int h, uint32_t root) {
  std::vector<Task> tasks;
  for (uint32_t l = 0; l < tree.leaves.size(); l++) {
    const Cell& c = tree.leaves[l];
    if (c.root != root) continue;
    const uint32_t s = tree.root_size >> c.level;
    const uint32_t x0 = c.ix * s, y0 = c.iy * s;
    const uint32_t x1 = std::min<uint32_t>(x0 + s, static_cast<uint32_t>(w));
    const uint32_t y1 = std::min<uint32_t>(y0 + s, static_cast<uint32_t>(h));
    if (x0 >= x1 || y0 >= y1) continue;
    const uint32_t rows = std::max<uint32_t>(1, kMaxTaskPixels / (x1 - x0));
    for (uint32_t y = y0; y < y1; y += rows) tasks.push_back({l, x0, x1, y, std::min(y1, y + rows)});
  }
  return tasks;
}

// Schedule for shared samples: the same strips cut at the edges of bands
// of `band` unit-area rows, band by band. A unit area of row uy sends its
// sums to accumulator rows uy - K + 1 .. uy, so bands of at least K - 1
// rows two apart never reach the same accumulator: the even bands run in
// parallel, then the odd ones, each band on one thread, and the sums are
// added without atomics (fixed point: the same total in any order).
std::vector<std::vector<Task>> band_schedule(const std::vector<Task>& tasks, int h, uint32_t band) {
  std::vector<std::vector<Task>> bands((static_cast<uint32_t>(h) + band - 1) / band);
  for (const Task& t : tasks)
    for (uint32_t y = t.y0; y < t.y1;) {
      const uint32_t b = y / band, y1 = std::min(t.y1, (b + 1) * band);
      bands[b].push_back({t.leaf, t.x0, t.x1, y, y1});
      y = y1;
    }
  return bands;
}

// Leaves without geometry or position-dependent paints have one colour
// everywhere.
std::vector<char> uniform_leaves(const ShortcutTree& tree, uint32_t root) {
  std::vector<char> uniform(tree.leaves.size(), 1);
  for (size_t l = 0; l < tree.leaves.size(); l++)
    if (tree.leaves[l].root == root)
      for (uint32_t i = tree.leaves[l].begin; i < tree.leaves[l].end && uniform[l]; i++)
        uniform[l] = !entry_varies(tree.leaf_entries[i], tree.paths.data());
  return uniform;
}

void composite(const float* p, const PaintRecord& bg, float* out) {
  const float under = 1.0f - p[3];
  out[0] = p[0] + under * bg.r;
  out[1] = p[1] + under * bg.g;
  out[2] = p[2] + under * bg.b;
  out[3] = p[3] + under * bg.a;
}

// The positions of unit area (ux, uy)'s n samples, offsets o.
void unit_area_samples(const SampleOffset* o, int n, uint32_t ux, uint32_t uy, float* sx, float* sy) {
  for (int k = 0; k < n; k++) {
    sx[k] = float(ux) + o[k].x;
    sy[k] = float(uy) + o[k].y;
  }
}

// Where render_tree_into puts a pixel: its premultiplied colour p over the
// background, as floats (ImageF) or as 8-bit codes (what to_rgba8 makes of
// the same floats), n pixels from pixel index i.
struct FloatSink {
  float* rgba;
  PaintRecord bg;
  void put(size_t i, size_t n, const float* p) const {
    for (size_t k = 0; k < n; k++) composite(p, bg, &rgba[(i + k) * 4]);
  }
};
struct Rgba8Sink {
  uint8_t* rgba;
  PaintRecord bg;
  bool linear;
  const SrgbCodeTable& table;
  void put(size_t i, size_t n, const float* p) const {
    float q[4];
    composite(p, bg, q);
    const uint32_t v = rgba8_pixel(q[0], q[1], q[2], q[3], linear, table);
    for (size_t k = 0; k < n; k++)
      for (int c = 0; c < 4; c++) rgba[(i + k) * 4 + c] = static_cast<uint8_t>(v >> (8 * c));
  }
};

// A tree's paint tables as the sampler reads them: views of the tables and
// of the pattern tiles' trees (not copyable: tables points into tiles).
struct TreePaint {
  explicit TreePaint(const ShortcutTree& tree) : data(tree.paint ? *tree.paint : no_paints()) {
    for (const ShortcutTree& t : tree.tiles) tiles.push_back(t.view());
    tables = data.view(tiles.data());
  }
  TreePaint(const TreePaint&) = delete;
  TreePaint& operator=(const TreePaint&) = delete;

  static const PaintData& no_paints() {
    static const PaintData none;
    return none;
  }

  const PaintData& data;
  std::vector<TreeView> tiles;
  PaintTables tables;
};

}  // namespace

Rgba4 sample_tree_cpu(const ShortcutTree& tree, float px, float py, uint32_t root) {
  const TreePaint paint(tree);
  const SampleInputs in{tree.leaf_entries.data(), tree.segments.data(), tree.paths.data(), &paint.tables};
  const Cell& c = tree.leaves[tree_find_leaf(tree.nodes.data(), tree.root_size, uint32_t(px), uint32_t(py), root)];
  return sample_cell(in, c.begin, c.end, px, py);
}

void sample_leaf_cpu(const ShortcutTree& tree, uint32_t leaf, uint32_t kinds, const float* px, const float* py, int n,
                     Rgba4* together, Rgba4* one_by_one) {
  const TreePaint paint(tree);
  const SampleInputs in{tree.leaf_entries.data(), tree.segments.data(), tree.paths.data(), &paint.tables};
  const Cell& c = tree.leaves[leaf];
  with_sampler_kinds(kinds, [&](auto k) {
    constexpr uint32_t Kinds = decltype(k)::value;
    sample_cell_lanes<0, Kinds>(in, c.begin, c.end, px, py, n, together);
    for (int i = 0; i < n; i++) one_by_one[i] = sample_cell<0, Kinds>(in, c.begin, c.end, px[i], py[i]);
  });
}

ImageF render_tree_cpu(const ShortcutTree& tree, int width, int height, const std::vector<SampleOffset>& pattern,
                       const PaintRecord& background, int threads, RenderTimes* times) {
  const Integration box = make_integration(Filter::Box, pattern);
  return render_tree_cpu(tree, box, integration_frame(box, width, height), background, threads, times);
}

namespace {

// render_tree_cpu's body: every pixel of the frame once into sink (put;
// from several threads, each pixel from one).
template <class Sink>
void render_tree_into(const ShortcutTree& tree, const Integration& integ, const IntegrationFrame& frame,
                      const Sink& sink, int threads, RenderTimes* times, uint32_t root) {
  const std::vector<SampleOffset>& pattern = integ.offsets;  // class 0 first
  auto t0 = std::chrono::steady_clock::now();
  const std::vector<Task> tasks = schedule(tree, frame.ua_w, frame.ua_h, root);
  const std::vector<char> uniform = uniform_leaves(tree, root);
  if (times) times->schedule_ms += ms_since(t0);
  // Samples evaluated (--stats): one per uniform leaf of the frame, one per
  // flat unit area, integ.samples per other unit area.
  std::atomic<uint64_t> samples{0};
  for (size_t l = 0; l < tree.leaves.size(); l++)
    if (uniform[l] && tree.leaves[l].root == root) samples.fetch_add(1, std::memory_order_relaxed);

  t0 = std::chrono::steady_clock::now();
  const TreePaint paint(tree);
  const SampleInputs in{tree.leaf_entries.data(), tree.segments.data(), tree.paths.data(), &paint.tables};
  // Threads worth starting for `work` samples (or weighted pixel values):
  // one per ~64k, so that a small frame does not pay for starting every
  // core's thread in each pass (a 10x10 image at 4x4x32 took 4.6 ms on 16
  // cores, 0.3 ms on one).
  const int all = threads > 0 ? threads : hardware_threads();
  auto threads_for = [all](double work) { return std::max(1, std::min(all, static_cast<int>(work / 65536)));
  };
  // Uniform leaves hold solid paints only (entry_varies); the rest is
  // sampled by the specialisation the scene's paints need.
  // The root's own specialisation (a forest's scenes each render as they
  // would alone); trees made without roots (tests) take the paints'.
  const bool aliasing = integ.support % 2 == 1;
  const uint32_t root_kinds =
      root < tree.roots.size() ? tree.roots[root].kinds[aliasing] : sampler_kinds(paint.data, aliasing);
  with_sampler_kinds(root_kinds, [&](auto kinds) {
    constexpr uint32_t Kinds = decltype(kinds)::value;
    const int n = integ.samples;
    const bool direct = integ.support == 1 && integ.pad == 0;
    if (direct) {
      // Box filter: each unit area is its pixel.
      const float w = box_weight(n);
      // Tasks kChunk at a time: one count and one set of buffers for many
      // small leaves (an atomic add per task was a tenth of a text page's
      // sampling).
      constexpr size_t kChunk = 64;
      parallel_for((tasks.size() + kChunk - 1) / kChunk, threads_for(double(frame.ua_w) * frame.ua_h * n),
                   [&](size_t chunk) {
        uint64_t evaluated = 0;
        std::vector<float> sx(static_cast<size_t>(n)), sy(static_cast<size_t>(n));
        std::vector<Rgba4> col(static_cast<size_t>(n));
        for (size_t ti = chunk * kChunk; ti < std::min(tasks.size(), (chunk + 1) * kChunk); ti++) {
        const Task& task = tasks[ti];
        const Cell& c = tree.leaves[task.leaf];
        if (uniform[task.leaf]) {
          const Rgba4 col = sample_cell<0, kUniformKinds<Kinds>>(in, c.begin, c.end, float(task.x0), float(task.y0));
          const float p[4] = {col.r, col.g, col.b, col.a};
          for (uint32_t y = task.y0; y < task.y1; y++)
            sink.put(size_t(y) * size_t(frame.width) + task.x0, task.x1 - task.x0, p);
          continue;
        }
        for (uint32_t y = task.y0; y < task.y1; y++) {
          for (uint32_t x = task.x0; x < task.x1; x++) {
            const size_t out = size_t(y) * size_t(frame.width) + x;
            if (unit_area_flat(in, c.begin, c.end, x, y)) {
              const Rgba4 col = sample_cell<0, Kinds>(in, c.begin, c.end, float(x) + pattern[0].x, float(y) + pattern[0].y);
              const float p[4] = {col.r, col.g, col.b, col.a};
              sink.put(out, 1, p);
              evaluated++;
              continue;
            }
            evaluated += uint64_t(n);
            unit_area_samples(pattern.data(), n, x, y, sx.data(), sy.data());
            sample_cell_lanes<0, Kinds>(in, c.begin, c.end, sx.data(), sy.data(), n, col.data());
            float acc[4] = {0, 0, 0, 0};
            for (int k = 0; k < n; k++) {
              acc[0] += col[k].r;
              acc[1] += col[k].g;
              acc[2] += col[k].b;
              acc[3] += col[k].a;
            }
            const float p[4] = {acc[0] * w, acc[1] * w, acc[2] * w, acc[3] * w};
            sink.put(out, 1, p);
          }
        }
        }
        samples.fetch_add(evaluated, std::memory_order_relaxed);
      });
      if (times) times->sample_ms += ms_since(t0);
      return;
    }

    // Shared samples: every unit area sends K x K weighted sums. Unit areas
    // of uniform leaves are gathered in the normalisation instead (as on the
    // GPU): their flat colours go to ua_color.
    const int K = integ.support, T = K * K;
    std::vector<long long> acc(size_t(frame.acc_w) * frame.acc_h * 4, 0);
    std::vector<Rgba4> ua_color(size_t(frame.ua_w) * frame.ua_h, Rgba4{0, 0, 0, -1});
    const int pass_threads = threads_for(double(frame.acc_w) * frame.acc_h * T);
    const int sample_threads = threads_for(double(frame.ua_w) * frame.ua_h * n * T);
    // Bands: four per thread and phase, at least K rows.
    const uint32_t band = std::max<uint32_t>(
        uint32_t(K), (uint32_t(frame.ua_h) + 8 * uint32_t(sample_threads) - 1) / (8 * uint32_t(sample_threads)));
    const std::vector<std::vector<Task>> bands = band_schedule(tasks, frame.ua_h, band);
    // A band's buffers and count.
    struct Scratch {
      explicit Scratch(int n, int T) : col(size_t(n)), sx(size_t(n)), sy(size_t(n)), sums(size_t(T) * 4) {}
      std::vector<Rgba4> col;
      std::vector<float> sx, sy, sums;
      uint64_t evaluated = 0;
    };
    auto sample_task = [&](const Task& task, Scratch& sc) {
      const Cell& c = tree.leaves[task.leaf];
      if (uniform[task.leaf]) {
        const Rgba4 flat =
            sample_cell<0, kUniformKinds<Kinds>>(in, c.begin, c.end, float(task.x0), float(task.y0));
        for (uint32_t uy = task.y0; uy < task.y1; uy++)
          for (uint32_t ux = task.x0; ux < task.x1; ux++) ua_color[size_t(uy) * frame.ua_w + ux] = flat;
        return;
      }
      std::vector<Rgba4>& col = sc.col;
      std::vector<float>&sx = sc.sx, &sy = sc.sy, &sums = sc.sums;
      static_assert(sizeof(Rgba4) == 4 * sizeof(float), "Rgba4 is four floats");
      uint64_t& evaluated = sc.evaluated;
      for (uint32_t uy = task.y0; uy < task.y1; uy++) {
        for (uint32_t ux = task.x0; ux < task.x1; ux++) {
          const int cls = unit_area_class(ux, uy, integ.class_mod);
          const SampleOffset* o = &integ.offsets[size_t(cls) * n];
          if (unit_area_flat(in, c.begin, c.end, ux, uy)) {
            // Gathered in the normalisation, as a uniform leaf's unit areas.
            ua_color[size_t(uy) * frame.ua_w + ux] =
                sample_cell<0, Kinds>(in, c.begin, c.end, float(ux) + o[0].x, float(uy) + o[0].y);
            evaluated++;
            continue;
          }
          evaluated += uint64_t(n);
          unit_area_samples(o, n, ux, uy, sx.data(), sy.data());
          sample_cell_lanes<0, Kinds>(in, c.begin, c.end, sx.data(), sy.data(), n, col.data());
          integrate_unit_area_all(integ.weights.data() + size_t(cls) * n * T, T, n, &col[0].r, sums.data());
          for (int ey = 0; ey < K; ey++) {
            const int ay = static_cast<int>(uy) - ey;
            if (ay < 0 || ay >= frame.acc_h) continue;
            for (int ex = 0; ex < K; ex++) {
              const int ax = static_cast<int>(ux) - ex;
              if (ax < 0 || ax >= frame.acc_w) continue;
              const float* s = &sums[size_t(ey * K + ex) * 4];
              long long* a = &acc[(size_t(ay) * frame.acc_w + ax) * 4];
              for (int ch = 0; ch < 4; ch++) a[ch] += to_fixed(s[ch]);
            }
          }
        }
      }
    };
    for (size_t phase = 0; phase < 2; phase++)
      parallel_for((bands.size() + 1 - phase) / 2, sample_threads, [&](size_t i) {
        Scratch sc(n, T);
        for (const Task& task : bands[2 * i + phase]) sample_task(task, sc);
        samples.fetch_add(sc.evaluated, std::memory_order_relaxed);
      });
    // Normalise (adding the uniform unit areas), prefilter rows then columns,
    // clamp, crop, composite.
    // A uniform unit area's sums depend on its colour and on the weight
    // sum of (its class, e) alone: each row keeps the last colour and sums
    // of every such pair, and most of a row (a flat background, a large
    // shape) reuses them. A pixel whose K x K unit areas are all uniform, of
    // one colour, with nothing else sent to it, depends on that colour and
    // on its column's class alone (the row's is the row's): each row keeps
    // the last such pixel of each column class. Classes are counted along
    // the row, not taken modulo per unit area.
    struct Uniform {
      Rgba4 color;
      long long fixed[4];
    };
    struct Pixel {
      Rgba4 color;
      float out[4];
    };
    const int cm = integ.class_mod;
    const size_t slots = size_t(cm) * cm * T;
    auto same = [](const Rgba4& a, const Rgba4& b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    std::vector<float> buf(acc.size());
    parallel_for(size_t(frame.acc_h), pass_threads, [&](size_t ay) {
      std::vector<Uniform> last(slots, Uniform{Rgba4{0, 0, 0, -1}, {0, 0, 0, 0}});
      std::vector<Pixel> last_pixel(size_t(cm), Pixel{Rgba4{0, 0, 0, -1}, {0, 0, 0, 0}});
      std::vector<const Rgba4*> rows(static_cast<size_t>(K));
      std::vector<int> row_class(static_cast<size_t>(K)), col_class(static_cast<size_t>(cm) * K);
      for (int ey = 0; ey < K; ey++) {
        rows[ey] = &ua_color[(ay + size_t(ey)) * frame.ua_w];
        row_class[ey] = int((ay + size_t(ey)) % size_t(cm)) * cm;
      }
      for (int xm = 0; xm < cm; xm++)
        for (int ex = 0; ex < K; ex++) col_class[size_t(xm) * K + ex] = (xm + ex) % cm;
      std::vector<int> run(static_cast<size_t>(frame.ua_w));
      int ran = 0;  // columns of run[] made
      for (int ax = 0, xm = 0; ax < frame.acc_w; ax++, xm = xm + 1 == cm ? 0 : xm + 1) {
        const size_t px = ay * size_t(frame.acc_w) + ax;
        long long sum[4];
        for (int ch = 0; ch < 4; ch++) sum[ch] = acc[px * 4 + ch];
        // run[x]: how many columns up to x have their K unit areas uniform,
        // of u0's colour (K compares a column, not K^2 a pixel).
        const Rgba4& u0 = rows[0][ax];
        for (; ran < ax + K; ran++) {
          const Rgba4& top = rows[0][ran];
          bool column = top.a >= 0.0f;
          for (int ey = 1; ey < K && column; ey++) column = same(rows[ey][ran], top);
          run[ran] = !column ? 0 : (ran > 0 && run[ran - 1] > 0 && same(rows[0][ran - 1], top)) ? run[ran - 1] + 1 : 1;
        }
        const bool flat = run[ax + K - 1] >= K && (sum[0] | sum[1] | sum[2] | sum[3]) == 0;
        Pixel& lp = last_pixel[size_t(xm)];
        if (flat && same(lp.color, u0)) {
          std::copy_n(lp.out, 4, &buf[px * 4]);
          continue;
        }
        const int* cc = &col_class[size_t(xm) * K];
        for (int ey = 0; ey < K; ey++)
          for (int ex = 0; ex < K; ex++) {
            const Rgba4& u = rows[ey][ax + ex];
            if (u.a < 0.0f) continue;
            const int e = ey * K + ex;
            const int slot = (row_class[ey] + cc[ex]) * T + e;
            Uniform& m = last[size_t(slot)];
            if (!same(m.color, u)) {
              float s[4];
              integrate_unit_area(nullptr, 0, integ.weight_sums[slot], 0, true, &u.r, nullptr, s);
              for (int ch = 0; ch < 4; ch++) m.fixed[ch] = to_fixed(s[ch]);
              m.color = u;
            }
            for (int ch = 0; ch < 4; ch++) sum[ch] += m.fixed[ch];
          }
        const double norm = kFixedScale * integ.totals[row_class[0] + cc[0]];
        for (int ch = 0; ch < 4; ch++) buf[px * 4 + ch] = fixed_to_float(sum[ch], norm);
        if (flat) {
          lp.color = u0;
          std::copy_n(&buf[px * 4], 4, lp.out);
        }
      }
    });
    if (integ.prefilter) {
      parallel_for(size_t(frame.acc_h), pass_threads,
                   [&](size_t y) { cardinal_prefilter_line(&buf[y * frame.acc_w * 4], frame.acc_w, 4); });
      // Columns kColumns at a time, each copied into a line of its own
      // (rows kColumns * 4 floats apart, read whole): the same operations on
      // the same values as the column in place, without a cache line per
      // sample (the column pass was most of the prefilter's time).
      constexpr size_t kColumns = 16;
      const size_t aw = size_t(frame.acc_w), ah = size_t(frame.acc_h);
      parallel_for((aw + kColumns - 1) / kColumns, pass_threads, [&](size_t b) {
        thread_local std::vector<float> line;
        const size_t x0 = b * kColumns, cols = std::min(kColumns, aw - x0);
        line.resize(cols * ah * 4);
        for (size_t y = 0; y < ah; y++)
          for (size_t k = 0; k < cols; k++)
            std::copy_n(&buf[(y * aw + x0 + k) * 4], 4, &line[(k * ah + y) * 4]);
        for (size_t k = 0; k < cols; k++) cardinal_prefilter_line(&line[k * ah * 4], frame.acc_h, 4);
        for (size_t y = 0; y < ah; y++)
          for (size_t k = 0; k < cols; k++)
            std::copy_n(&line[(k * ah + y) * 4], 4, &buf[(y * aw + x0 + k) * 4]);
      });
    }
    parallel_for(size_t(frame.height), pass_threads, [&](size_t y) {
      for (int x = 0; x < frame.width; x++) {
        float p[4];
        const float* q = &buf[((y + integ.pad) * frame.acc_w + x + integ.pad) * 4];
        std::copy(q, q + 4, p);
        clamp_premultiplied(p);
        sink.put(y * frame.width + x, 1, p);
      }
    });
    if (times) times->sample_ms += ms_since(t0);
  });
  if (times) times->samples += samples.load(std::memory_order_relaxed);
}

}  // namespace

ImageF render_tree_cpu(const ShortcutTree& tree, const Integration& integ, const IntegrationFrame& frame,
                       const PaintRecord& background, int threads, RenderTimes* times, uint32_t root) {
  const auto t0 = std::chrono::steady_clock::now();
  ImageF img;
  img.width = frame.width;
  img.height = frame.height;
  img.rgba.assign(size_t(frame.width) * size_t(frame.height) * 4, 0.0f);
  if (times) times->schedule_ms += ms_since(t0);
  render_tree_into(tree, integ, frame, FloatSink{img.rgba.data(), background}, threads, times, root);
  return img;
}

std::vector<uint8_t> render_tree_cpu_rgba8(const ShortcutTree& tree, const Integration& integ,
                                           const IntegrationFrame& frame, const PaintRecord& background, Gamma gamma,
                                           int threads, RenderTimes* times, uint32_t root) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<uint8_t> out(size_t(frame.width) * size_t(frame.height) * 4);
  if (times) times->schedule_ms += ms_since(t0);
  render_tree_into(tree, integ, frame, Rgba8Sink{out.data(), background, gamma == Gamma::Linear, srgb_code_table()},
                   threads, times, root);
  return out;
}

}  // namespace mpvg
