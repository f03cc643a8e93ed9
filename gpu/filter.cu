// The CUDA executor of filter graphs (core/filter_layers.h): the same ops
// as core/cpu/filter.cpp, each a kernel over its box running the per-pixel
// code of core/filter_primitives.h, layers kept on the device from the
// source's upload to the result's download.
#include <memory>
#include <vector>

#include "core/filter.h"
#include "core/filter_layers.h"
#include "gpu/cuda_util.h"
#include "gpu/filter.h"

namespace mpvg::gpu {

namespace {

// A layer on the device: premultiplied, in one colour space, transparent
// outside its box.
struct Layer {
  DeviceBuffer<float> px;
  bool linear = true;
  FilterBox box;
};
using LayerPtr = std::shared_ptr<const Layer>;

__device__ inline Rgba4 at(const float* px, const FilterBox& b, int w, int x, int y) {
  if (x < b.x0 || x >= b.x1 || y < b.y0 || y >= b.y1) return Rgba4{0, 0, 0, 0};
  return filter_read(px, w, x, y);
}

template <class F>
__global__ void k_pixels(FilterBox box, int w, float* out, F f) {
  const int x = box.x0 + static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  const int y = box.y0 + static_cast<int>(blockIdx.y * blockDim.y + threadIdx.y);
  if (x >= box.x1 || y >= box.y1) return;
  const Rgba4 p = f(x, y);
  float* o = out + 4 * (static_cast<size_t>(y) * w + x);
  o[0] = p.r, o[1] = p.g, o[2] = p.b, o[3] = p.a;
}

// The functors: one per kind of pixel the executor makes.
struct Constant {
  Rgba4 c;
  __device__ Rgba4 operator()(int, int) const { return c; }
};
struct Shifted {  // offset, copy
  const float* in;
  FilterBox box;
  int w, ox, oy;
  __device__ Rgba4 operator()(int x, int y) const { return at(in, box, w, x - ox, y - oy); }
};
struct Converted {
  const float* in;
  FilterBox box;
  int w;
  bool from, to, alpha_only;
  __device__ Rgba4 operator()(int x, int y) const {
    const Rgba4 p = at(in, box, w, x, y);
    return alpha_only ? Rgba4{0, 0, 0, p.a} : filter_convert(p, from, to);
  }
};
struct Merged {
  const float* const* ins;
  const FilterBox* boxes;
  uint32_t n;
  int w;
  __device__ Rgba4 operator()(int x, int y) const {
    Rgba4 acc{0, 0, 0, 0};
    for (uint32_t i = 0; i < n; i++) {
      const Rgba4 p = at(ins[i], boxes[i], w, x, y);
      const float k = 1.0f - p.a;
      acc = Rgba4{p.r + acc.r * k, p.g + acc.g * k, p.b + acc.b * k, p.a + acc.a * k};
    }
    return acc;
  }
};
struct Pointwise {  // composite, blend, colour matrix, component transfer
  FilterOp op;
  const float *a, *b, *tables;
  FilterBox abox, bbox;
  int w;
  __device__ Rgba4 operator()(int x, int y) const {
    const Rgba4 p = at(a, abox, w, x, y);
    switch (op.kind) {
      case FOP_COMPOSITE: return filter_composite(op, p, at(b, bbox, w, x, y));
      case FOP_BLEND: return filter_blend(op, p, at(b, bbox, w, x, y));
      case FOP_COLOR_MATRIX: return filter_color_matrix(op, p);
      default: return filter_component_transfer(op, p, tables);
    }
  }
};
struct BlurPass {
  const float* in;
  FilterBox read;
  int w, size, lead;
  bool horizontal, boxes;
  float s;
  uint32_t edge;
  __device__ Rgba4 operator()(int x, int y) const {
    return boxes ? filter_box_pass(in, w, read, x, y, horizontal, size, lead, edge)
                 : filter_gauss_pass(in, w, read, x, y, horizontal, s, edge);
  }
};
struct ShadowColour {
  const float* in;
  FilterBox box;
  int w;
  Rgba4 c;
  __device__ Rgba4 operator()(int x, int y) const {
    const float k = at(in, box, w, x, y).a;
    return Rgba4{c.r * k, c.g * k, c.b * k, c.a * k};
  }
};
struct UnderShadow {
  const float *in, *shadow;
  FilterBox box, sbox;
  int w, ox, oy;
  __device__ Rgba4 operator()(int x, int y) const {
    const Rgba4 s = at(shadow, sbox, w, x - ox, y - oy), p = at(in, box, w, x, y);
    const float k = 1.0f - p.a;
    return Rgba4{p.r + s.r * k, p.g + s.g * k, p.b + s.b * k, p.a + s.a * k};
  }
};
struct Morph {
  FilterOp op;
  const float* in;
  FilterBox box;
  int w;
  __device__ Rgba4 operator()(int x, int y) const { return filter_morphology(op, in, w, box, x, y); }
};
struct Tiled {
  const float* in;
  FilterBox box, t;
  int w;
  __device__ Rgba4 operator()(int x, int y) const {
    const int tw = t.x1 - t.x0, th = t.y1 - t.y0;
    int mx = (x - t.x0) % tw, my = (y - t.y0) % th;
    if (mx < 0) mx += tw;
    if (my < 0) my += th;
    return at(in, box, w, t.x0 + mx, t.y0 + my);
  }
};
struct Neighbourhood {  // convolution, displacement, lighting, turbulence
  FilterOp op;
  const float *a, *b, *tables;
  const double* noise;
  FilterBox abox, bbox;
  int w;
  __device__ Rgba4 operator()(int x, int y) const {
    switch (op.kind) {
      case FOP_CONVOLVE_MATRIX: return filter_convolve(op, a, w, abox, tables + op.kernel_begin, x, y);
      case FOP_DISPLACEMENT_MAP: return filter_displace(op, a, abox, b, bbox, w, x, y);
      case FOP_TURBULENCE: return filter_turbulence(op, noise + op.noise_begin, x, y);
      default: return filter_lighting(op, a, w, abox, x, y);
    }
  }
};

class Graph {
 public:
  explicit Graph(const FilterLayer& l) : l_(l), whole_{0, 0, l.width, l.height} {
    source_.upload(l.source.rgba);
    tables_.upload(l.tables.empty() ? std::vector<float>{0} : l.tables);
    noise_.upload(l.noise.empty() ? std::vector<double>{0} : l.noise);
  }

  FilterResult run() {
    for (const FilterOp& op : l_.ops) results_.push_back(apply(op));
    FilterResult r;
    if (results_.empty()) {
      r.rgba.assign(size(), 0.0f);
      return r;
    }
    r.rgba = results_.back()->px.download(size());
    r.linear = results_.back()->linear;
    return r;
  }

 private:
  size_t size() const { return static_cast<size_t>(l_.width) * l_.height * 4; }

  template <class F>
  std::shared_ptr<Layer> make(const FilterBox& box, bool linear, F f) const {
    auto b = std::make_shared<Layer>();
    b->px.resize(std::max<size_t>(size(), 4));
    MPVG_CUDA(cudaMemsetAsync(b->px.data(), 0, size() * sizeof(float), cudaStreamPerThread));
    b->linear = linear;
    b->box = box;
    const int bw = box.x1 - box.x0, bh = box.y1 - box.y0;
    if (bw > 0 && bh > 0) {
      const dim3 block(32, 8);
      const dim3 grid(grid_for(bw, block.x), grid_for(bh, block.y));
      k_pixels<<<grid, block, 0, cudaStreamPerThread>>>(box, l_.width, b->px.data(), f);
      MPVG_LAUNCHED();
    }
    return b;
  }

  LayerPtr input(int32_t in, bool linear) {
    const int w = l_.width;
    if (in >= 0 && static_cast<size_t>(in) < results_.size()) {
      const LayerPtr& r = results_[in];
      if (r->linear == linear) return r;
      return make(r->box, linear, Converted{r->px.data(), r->box, w, r->linear, linear, false});
    }
    switch (in) {
      case FILTER_SOURCE_GRAPHIC:
      case FILTER_SOURCE_ALPHA:
        return make(whole_, linear,
                    Converted{source_.data(), whole_, w, l_.source_linear, linear, in == FILTER_SOURCE_ALPHA});
      case FILTER_FILL_PAINT:
      case FILTER_STROKE_PAINT: {
        const Rgba4 c = in == FILTER_FILL_PAINT ? l_.fill_paint : l_.stroke_paint;
        return make(whole_, linear, Constant{filter_convert(Rgba4{c.r * c.a, c.g * c.a, c.b * c.a, c.a}, false, linear)});
      }
      default: return make(whole_, linear, Constant{Rgba4{0, 0, 0, 0}});
    }
  }

  std::shared_ptr<Layer> blur(LayerPtr in, float sx, float sy, uint32_t edge) const {
    std::shared_ptr<Layer> cur;
    const int w = l_.width;
    FilterBlurPass passes[6];
    const int n = filter_blur_passes(sx, sy, edge, passes);
    for (int i = 0; i < n; i++) {
      const FilterBlurPass p = passes[i];
      const Layer& src = cur ? *cur : *in;
      cur = make(whole_, src.linear,
                 BlurPass{src.px.data(), src.box, w, p.size, p.lead, p.horizontal, p.boxes, p.s, p.edge});
    }
    if (!cur) cur = make(in->box, in->linear, Shifted{in->px.data(), in->box, w, 0, 0});
    return cur;
  }

  LayerPtr apply(const FilterOp& op) {
    const bool lin = op.linear != 0;
    const int w = l_.width;
    switch (op.kind) {
      case FOP_FLOOD: return make(op.box, lin, Constant{Rgba4{op.color[0], op.color[1], op.color[2], op.color[3]}});
      case FOP_OFFSET: {
        const LayerPtr a = input(op.in, lin);
        return make(op.box, lin,
                    Shifted{a->px.data(), a->box, w, static_cast<int>(lroundf(op.dx)), static_cast<int>(lroundf(op.dy))});
      }
      case FOP_MERGE: {
        std::vector<LayerPtr> ins;
        std::vector<const float*> ptrs;
        std::vector<FilterBox> boxes;
        for (uint32_t i = 0; i < op.inputs_count; i++) {
          ins.push_back(input(l_.inputs[op.inputs_begin + i], lin));
          ptrs.push_back(ins.back()->px.data());
          boxes.push_back(ins.back()->box);
        }
        DeviceBuffer<const float*> dptrs;
        DeviceBuffer<FilterBox> dboxes;
        dptrs.upload(ptrs.empty() ? std::vector<const float*>{nullptr} : ptrs);
        dboxes.upload(boxes.empty() ? std::vector<FilterBox>{FilterBox{}} : boxes);
        return make(op.box, lin, Merged{dptrs.data(), dboxes.data(), op.inputs_count, w});
      }
      case FOP_COMPOSITE:
      case FOP_BLEND:
      case FOP_COLOR_MATRIX:
      case FOP_COMPONENT_TRANSFER: {
        const LayerPtr a = input(op.in, lin);
        const bool two = op.kind == FOP_COMPOSITE || op.kind == FOP_BLEND;
        const LayerPtr b = two ? input(op.in2, lin) : a;
        return make(op.box, lin, Pointwise{op, a->px.data(), b->px.data(), tables_.data(), a->box, b->box, w});
      }
      case FOP_GAUSSIAN_BLUR: {
        const LayerPtr a = input(op.in, lin);
        const auto b = blur(a, op.std_x, op.std_y, op.edge);
        return make(op.box, lin, Shifted{b->px.data(), b->box, w, 0, 0});
      }
      case FOP_DROP_SHADOW: {
        const LayerPtr a = input(op.in, lin);
        const auto shadow =
            make(a->box, lin, ShadowColour{a->px.data(), a->box, w, Rgba4{op.color[0], op.color[1], op.color[2], op.color[3]}});
        const auto blurred = blur(shadow, op.std_x, op.std_y, FEDGE_NONE);
        return make(op.box, lin,
                    UnderShadow{a->px.data(), blurred->px.data(), a->box, blurred->box, w,
                                static_cast<int>(lroundf(op.dx)), static_cast<int>(lroundf(op.dy))});
      }
      case FOP_MORPHOLOGY: {
        const LayerPtr a = input(op.in, lin);
        if (op.rx <= 0 && op.ry <= 0) return make(op.box, lin, Shifted{a->px.data(), a->box, w, 0, 0});
        FilterOp h = op, v = op;
        h.ry = 0;
        v.rx = 0;
        const auto rows = make(whole_, lin, Morph{h, a->px.data(), a->box, w});
        return make(op.box, lin, Morph{v, rows->px.data(), whole_, w});
      }
      case FOP_TILE: {
        const LayerPtr a = input(op.in, lin);
        if (op.tile.x1 <= op.tile.x0 || op.tile.y1 <= op.tile.y0) return make(op.box, lin, Constant{Rgba4{0, 0, 0, 0}});
        return make(op.box, lin, Tiled{a->px.data(), a->box, op.tile, w});
      }
      case FOP_IMAGE: {
        DeviceBuffer<float> pic;
        pic.upload(l_.images[op.image].rgba);
        return make(op.box, lin, Converted{pic.data(), whole_, w, l_.image_linear[op.image] != 0, lin, false});
      }
      case FOP_CONVOLVE_MATRIX:
      case FOP_DISPLACEMENT_MAP:
      case FOP_DIFFUSE_LIGHTING:
      case FOP_SPECULAR_LIGHTING:
      case FOP_TURBULENCE: {
        const bool reads = op.kind != FOP_TURBULENCE;
        const LayerPtr a = reads ? input(op.in, lin) : nullptr;
        const LayerPtr b = op.kind == FOP_DISPLACEMENT_MAP ? input(op.in2, lin) : a;
        return make(op.box, lin,
                    Neighbourhood{op, a ? a->px.data() : nullptr, b ? b->px.data() : nullptr, tables_.data(),
                                  noise_.data(), a ? a->box : FilterBox{}, b ? b->box : FilterBox{}, w});
      }
      default: return make(op.box, lin, Constant{Rgba4{0, 0, 0, 0}});
    }
  }

  const FilterLayer& l_;
  FilterBox whole_;
  DeviceBuffer<float> source_, tables_;
  DeviceBuffer<double> noise_;
  std::vector<LayerPtr> results_;
};

}  // namespace

FilterResult run_filter_cuda(const FilterLayer& layer) {
  FilterResult r = Graph(layer).run();
  MPVG_CUDA(cudaStreamSynchronize(cudaStreamPerThread));
  return r;
}

}  // namespace mpvg::gpu
