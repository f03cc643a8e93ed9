// The CPU executor of filter graphs (frame/filter_layers.h): every op in a
// loop over its box's rows, on all cores, with the per-pixel code of
// core/filter_primitives.h.
#include <algorithm>
#include <cmath>
#include <memory>

#include "core/filters/filter.h"
#include "frame/filter_layers.h"
#include "core/parallel.h"

namespace mpvg {

namespace {

// A result or input over the whole layer: premultiplied, in one colour
// space, transparent outside its box.
struct Buffer {
  std::vector<float> px;
  bool linear = true;
  FilterBox box;
};
using BufferPtr = std::shared_ptr<const Buffer>;

class Graph {
 public:
  Graph(const FilterLayer& l, int threads) : l_(l), threads_(threads), whole_{0, 0, l.width, l.height} {}

  FilterResult run() {
    // Each result is dropped after the last op that reads it (FilterLayer::
    // last_use, as the GPU's graph does): a graph holds the images still to
    // be read, not all it made.
    const size_t n = l_.ops.size();
    const bool planned = l_.last_use.size() == n;
    for (size_t k = 0; k < n; k++) {
      results_.push_back(std::make_shared<const Buffer>(apply(l_.ops[k])));
      if (!planned) continue;
      for (size_t i = 0; i + 1 < n && i <= k; i++)
        if (results_[i] && (l_.last_use[i] == k || (l_.last_use[i] == n && i == k))) results_[i].reset();
    }
    FilterResult r;
    if (results_.empty()) {
      r.rgba.assign(size(), 0.0f);
      return r;
    }
    r.rgba = results_.back()->px;
    r.linear = results_.back()->linear;
    return r;
  }

 private:
  size_t size() const { return static_cast<size_t>(l_.width) * l_.height * 4; }

  // f(x, y) -> Rgba4 for every pixel of box, rows in parallel.
  template <class F>
  Buffer make(const FilterBox& box, bool linear, F&& f) const {
    Buffer b;
    b.px.assign(size(), 0.0f);
    b.linear = linear;
    b.box = box;
    const int w = l_.width;
    parallel_for(static_cast<size_t>(std::max(0, box.y1 - box.y0)), threads_, [&](size_t row) {
      const int y = box.y0 + static_cast<int>(row);
      for (int x = box.x0; x < box.x1; x++) {
        const Rgba4 p = f(x, y);
        float* o = b.px.data() + 4 * (static_cast<size_t>(y) * w + x);
        o[0] = p.r, o[1] = p.g, o[2] = p.b, o[3] = p.a;
      }
    });
    return b;
  }

  // Input `in` in colour space `linear`.
  BufferPtr input(int32_t in, bool linear) const {
    if (in >= 0 && static_cast<size_t>(in) < results_.size()) {
      const BufferPtr& r = results_[in];
      if (r->linear == linear) return r;
      return convert(*r, linear);
    }
    const int w = l_.width;
    switch (in) {
      case FILTER_SOURCE_GRAPHIC:
      case FILTER_SOURCE_ALPHA: {
        const bool alpha = in == FILTER_SOURCE_ALPHA;
        return std::make_shared<const Buffer>(make(whole_, linear, [&](int x, int y) {
          const Rgba4 p = filter_read(l_.source.rgba.data(), w, x, y);
          return alpha ? Rgba4{0, 0, 0, p.a} : filter_convert(p, l_.source_linear, linear);
        }));
      }
      case FILTER_FILL_PAINT:
      case FILTER_STROKE_PAINT: {
        const Rgba4 c = in == FILTER_FILL_PAINT ? l_.fill_paint : l_.stroke_paint;
        const Rgba4 p = filter_convert(Rgba4{c.r * c.a, c.g * c.a, c.b * c.a, c.a}, false, linear);
        return std::make_shared<const Buffer>(make(whole_, linear, [&](int, int) { return p; }));
      }
      default: {  // BackgroundImage, BackgroundAlpha: transparent black
        auto b = std::make_shared<Buffer>();
        b->px.assign(size(), 0.0f);
        b->linear = linear;
        b->box = whole_;
        return b;
      }
    }
  }

  BufferPtr convert(const Buffer& from, bool linear) const {
    const int w = l_.width;
    return std::make_shared<const Buffer>(
        make(from.box, linear, [&](int x, int y) { return filter_convert(filter_read(from.px.data(), w, x, y), from.linear, linear); }));
  }

  Rgba4 at(const Buffer& b, int x, int y) const {
    if (x < b.box.x0 || x >= b.box.x1 || y < b.box.y0 || y >= b.box.y1) return Rgba4{0, 0, 0, 0};
    return filter_read(b.px.data(), l_.width, x, y);
  }

  // One box pass with edge mode none as a running sum along each row or
  // column: O(1) a pixel whatever the box (filter_box_pass, which the CUDA
  // executor runs a thread a pixel, sums its window: O(size)). The sum is
  // filter_box_pass's, in fixed point: exact, so it neither drifts along a
  // long row nor differs from the window's sum in a bit.
  Buffer box_pass(const Buffer& src, const FilterBox& read, bool horizontal, int size, int lead) const {
    Buffer out;
    out.px.assign(this->size(), 0.0f);
    out.linear = src.linear;
    out.box = whole_;
    const int w = l_.width, h = l_.height;
    const int lines = horizontal ? h : w, n = horizontal ? w : h;
    const int lo = horizontal ? read.x0 : read.y0, hi = horizontal ? read.x1 : read.y1;
    const int line_lo = horizontal ? read.y0 : read.x0, line_hi = horizontal ? read.y1 : read.x1;
    parallel_for(static_cast<size_t>(lines), threads_, [&](size_t li) {
      const int line = static_cast<int>(li);
      if (line < line_lo || line >= line_hi) return;  // nothing to read on this line
      auto at = [&](int i) -> const float* {
        return src.px.data() + 4 * (horizontal ? static_cast<size_t>(line) * w + i : static_cast<size_t>(i) * w + line);
      };
      long long acc[4] = {0, 0, 0, 0};
      // The window of output i is [i - lead, i - lead + size); start at i = 0.
      for (int j = -lead; j < -lead + size; j++)
        if (j >= lo && j < hi && j >= 0 && j < n)
          for (int c = 0; c < 4; c++) acc[c] += box_fixed(at(j)[c]);
      for (int i = 0; i < n; i++) {
        float* o = out.px.data() + 4 * (horizontal ? static_cast<size_t>(line) * w + i : static_cast<size_t>(i) * w + line);
        for (int c = 0; c < 4; c++) o[c] = box_mean(acc[c], size);
        const int leave = i - lead, enter = i - lead + size;
        if (leave >= lo && leave < hi && leave >= 0 && leave < n)
          for (int c = 0; c < 4; c++) acc[c] -= box_fixed(at(leave)[c]);
        if (enter >= lo && enter < hi && enter >= 0 && enter < n)
          for (int c = 0; c < 4; c++) acc[c] += box_fixed(at(enter)[c]);
      }
    });
    return out;
  }

  // A separable blur of `in` by standard deviations sx, sy (pixels), over
  // the whole layer (it spreads past the input's box), edge mode on the
  // first pass of each axis.
  Buffer blur(const Buffer& in, float sx, float sy, uint32_t edge) const {
    Buffer cur = in;
    const int w = l_.width;
    FilterBlurPass passes[6];
    const int n = filter_blur_passes(sx, sy, edge, passes);
    for (int i = 0; i < n; i++) {
      const FilterBlurPass p = passes[i];
      const FilterBox read = cur.box;  // the input's box first, then the whole layer
      const Buffer src = std::move(cur);
      if (p.boxes && p.edge == FEDGE_NONE) {
        cur = box_pass(src, read, p.horizontal, p.size, p.lead);
        continue;
      }
      cur = make(whole_, src.linear, [&](int x, int y) {
        return p.boxes ? filter_box_pass(src.px.data(), w, read, x, y, p.horizontal, p.size, p.lead, p.edge)
                       : filter_gauss_pass(src.px.data(), w, read, x, y, p.horizontal, p.s, p.edge);
      });
    }
    return cur;
  }

  Buffer apply(const FilterOp& op) const {
    const bool lin = op.linear != 0;
    const int w = l_.width;
    switch (op.kind) {
      case FOP_FLOOD: {
        const Rgba4 c{op.color[0], op.color[1], op.color[2], op.color[3]};
        return make(op.box, lin, [&](int, int) { return c; });
      }
      case FOP_OFFSET: {
        const BufferPtr a = input(op.in, lin);
        const int ox = static_cast<int>(std::lround(op.dx)), oy = static_cast<int>(std::lround(op.dy));
        return make(op.box, lin, [&](int x, int y) { return at(*a, x - ox, y - oy); });
      }
      case FOP_MERGE: {
        std::vector<BufferPtr> ins;
        for (uint32_t i = 0; i < op.inputs_count; i++) ins.push_back(input(l_.inputs[op.inputs_begin + i], lin));
        return make(op.box, lin, [&](int x, int y) {
          Rgba4 acc{0, 0, 0, 0};
          for (const BufferPtr& b : ins) {
            const Rgba4 p = at(*b, x, y);
            const float k = 1.0f - p.a;
            acc = Rgba4{p.r + acc.r * k, p.g + acc.g * k, p.b + acc.b * k, p.a + acc.a * k};
          }
          return acc;
        });
      }
      case FOP_COMPOSITE:
      case FOP_BLEND: {
        const BufferPtr a = input(op.in, lin), b = input(op.in2, lin);
        return make(op.box, lin, [&](int x, int y) {
          return op.kind == FOP_BLEND ? filter_blend(op, at(*a, x, y), at(*b, x, y))
                                      : filter_composite(op, at(*a, x, y), at(*b, x, y));
        });
      }
      case FOP_COLOR_MATRIX: {
        const BufferPtr a = input(op.in, lin);
        return make(op.box, lin, [&](int x, int y) { return filter_color_matrix(op, at(*a, x, y)); });
      }
      case FOP_COMPONENT_TRANSFER: {
        const BufferPtr a = input(op.in, lin);
        const float* tables = l_.tables.data();
        return make(op.box, lin, [&](int x, int y) { return filter_component_transfer(op, at(*a, x, y), tables); });
      }
      case FOP_GAUSSIAN_BLUR: {
        const BufferPtr a = input(op.in, lin);
        const Buffer b = blur(*a, op.std_x, op.std_y, op.edge);
        return make(op.box, lin, [&](int x, int y) { return at(b, x, y); });
      }
      case FOP_DROP_SHADOW: {
        const BufferPtr a = input(op.in, lin);
        const Rgba4 c{op.color[0], op.color[1], op.color[2], op.color[3]};
        const Buffer shadow = make(a->box, lin, [&](int x, int y) {
          const float k = at(*a, x, y).a;
          return Rgba4{c.r * k, c.g * k, c.b * k, c.a * k};
        });
        const Buffer blurred = blur(shadow, op.std_x, op.std_y, FEDGE_NONE);
        const int ox = static_cast<int>(std::lround(op.dx)), oy = static_cast<int>(std::lround(op.dy));
        return make(op.box, lin, [&](int x, int y) {
          const Rgba4 s = at(blurred, x - ox, y - oy), p = at(*a, x, y);
          const float k = 1.0f - p.a;
          return Rgba4{p.r + s.r * k, p.g + s.g * k, p.b + s.b * k, p.a + s.a * k};
        });
      }
      case FOP_MORPHOLOGY: {
        const BufferPtr a = input(op.in, lin);
        if (op.rx <= 0 && op.ry <= 0) return make(op.box, lin, [&](int x, int y) { return at(*a, x, y); });
        // Separable: the rectangle's extreme is the extreme of its rows'.
        FilterOp h = op, v = op;
        h.ry = 0;
        v.rx = 0;
        const Buffer rows = make(whole_, lin, [&](int x, int y) { return filter_morphology(h, a->px.data(), w, a->box, x, y); });
        return make(op.box, lin, [&](int x, int y) { return filter_morphology(v, rows.px.data(), w, whole_, x, y); });
      }
      case FOP_TILE: {
        const BufferPtr a = input(op.in, lin);
        const FilterBox t = op.tile;
        const int tw = t.x1 - t.x0, th = t.y1 - t.y0;
        if (tw <= 0 || th <= 0) return make(op.box, lin, [](int, int) { return Rgba4{0, 0, 0, 0}; });
        return make(op.box, lin, [&](int x, int y) {
          int mx = (x - t.x0) % tw, my = (y - t.y0) % th;
          if (mx < 0) mx += tw;
          if (my < 0) my += th;
          return at(*a, t.x0 + mx, t.y0 + my);
        });
      }
      case FOP_CONVOLVE_MATRIX: {
        const BufferPtr a = input(op.in, lin);
        const float* kernel = l_.tables.data() + op.kernel_begin;
        return make(op.box, lin, [&](int x, int y) { return filter_convolve(op, a->px.data(), w, a->box, kernel, x, y); });
      }
      case FOP_DISPLACEMENT_MAP: {
        const BufferPtr a = input(op.in, lin), m = input(op.in2, lin);
        return make(op.box, lin, [&](int x, int y) {
          return filter_displace(op, a->px.data(), a->box, m->px.data(), m->box, w, x, y);
        });
      }
      case FOP_DIFFUSE_LIGHTING:
      case FOP_SPECULAR_LIGHTING: {
        const BufferPtr a = input(op.in, lin);
        return make(op.box, lin, [&](int x, int y) { return filter_lighting(op, a->px.data(), w, a->box, x, y); });
      }
      case FOP_IMAGE: {
        const ImageF& pic = l_.images[op.image];
        const bool from = l_.image_linear[op.image] != 0;
        return make(op.box, lin, [&](int x, int y) { return filter_convert(filter_read(pic.rgba.data(), w, x, y), from, lin); });
      }
      case FOP_TURBULENCE: {
        const double* noise = l_.noise.data() + op.noise_begin;
        return make(op.box, lin, [&](int x, int y) { return filter_turbulence(op, noise, x, y); });
      }
      default:  // no other kinds (FilterKind): transparent black
        return make(op.box, lin, [](int, int) { return Rgba4{0, 0, 0, 0}; });
    }
  }

  const FilterLayer& l_;
  int threads_;
  FilterBox whole_;
  std::vector<BufferPtr> results_;
};

}  // namespace

FilterResult run_filter_cpu(const FilterLayer& layer, int threads) { return Graph(layer, threads).run(); }

}  // namespace mpvg
