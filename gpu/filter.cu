// The CUDA executor of filter graphs (frame/filter_layers.h): the same ops
// as cpu/filter.cpp, run by kernels over the per-pixel code of
// core/filters/filter_primitives.h, batched: the layers of a batch have graphs of
// one shape (the same ops wired the same way), so each step of the graph is
// one launch over every layer of the batch (blockIdx.z the layer, each with
// its own box, sizes and parameters). Layers stay on the device from the
// sources to the texels.
#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/filters/filter.h"
#include "frame/filter_layers.h"
#include "gpu/cuda_util.h"
#include "gpu/filter.h"

namespace mpvg::gpu {

namespace {

__device__ inline Rgba4 at(const float* px, const FilterBox& b, int w, int x, int y) {
  if (x < b.x0 || x >= b.x1 || y < b.y0 || y >= b.y1) return Rgba4{0, 0, 0, 0};
  return filter_read(px, w, x, y);
}

// One layer's share of a launch: its functor, the box it writes, its row
// length and where its pixels go.
template <class F>
struct Item {
  F f;
  FilterBox box;
  int w;
  float* out;
};

template <class F>
__global__ void k_pixels(const Item<F>* items) {
  const Item<F>& it = items[blockIdx.z];
  const int x = it.box.x0 + static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  const int y = it.box.y0 + static_cast<int>(blockIdx.y * blockDim.y + threadIdx.y);
  if (x >= it.box.x1 || y >= it.box.y1) return;
  const Rgba4 p = it.f(x, y);
  float* o = it.out + 4 * (static_cast<size_t>(y) * it.w + x);
  o[0] = p.r, o[1] = p.g, o[2] = p.b, o[3] = p.a;
}

// A layer's result as the texels of its texture (filter_texel).
struct TexelItem {
  const float* in;
  Texel16* out;
  size_t n;
};

__global__ void k_texels(const TexelItem* items, bool result_linear, bool integ_linear) {
  const TexelItem it = items[blockIdx.y];
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= it.n) return;
  const float* p = it.in + 4 * i;
  it.out[i] = filter_texel(Rgba4{p[0], p[1], p[2], p[3]}, result_linear, integ_linear);
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

// The shape of a layer's graph: what decides the batch's control flow
// (ops, wiring, colour spaces, the number of blur passes, the trivial
// cases); layers of one shape run as one batch.
std::string shape_of(const FilterLayer& l) {
  std::string s;
  auto put = [&s](int64_t v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(l.source_linear);
  for (const FilterOp& op : l.ops) {
    put(op.kind), put(op.in), put(op.in2), put(op.linear), put(op.inputs_count);
    for (uint32_t i = 0; i < op.inputs_count; i++) put(l.inputs[op.inputs_begin + i]);
    FilterBlurPass passes[6];
    if (op.kind == FOP_GAUSSIAN_BLUR) put(filter_blur_passes(op.std_x, op.std_y, op.edge, passes));
    if (op.kind == FOP_DROP_SHADOW) put(filter_blur_passes(op.std_x, op.std_y, FEDGE_NONE, passes));
    if (op.kind == FOP_MORPHOLOGY) put(op.rx <= 0 && op.ry <= 0);
    if (op.kind == FOP_TILE) put(op.tile.x1 <= op.tile.x0 || op.tile.y1 <= op.tile.y0);
  }
  return s;
}

// An image of the batch: every layer's pixels in one buffer (layer k's at
// the batch's offset k), premultiplied in one colour space, each layer
// transparent outside its box.
struct Planes {
  DeviceBuffer<float> px;
  bool linear = true;
  std::vector<FilterBox> boxes;
};
using PlanesPtr = std::shared_ptr<const Planes>;

class Batch {
 public:
  // sources[k]: layer k's source on the device (premultiplied, in the
  // colour space of layers[k]->source_linear).
  Batch(const std::vector<const FilterLayer*>& layers, const std::vector<const float*>& sources)
      : l_(layers), sources_(sources), n_(layers.size()) {
    std::vector<float> tables;
    std::vector<double> noise;
    size_t total = 0;
    for (const FilterLayer* l : l_) {
      off_.push_back(total);
      total += size_t(l->width) * l->height * 4;
      whole_.push_back(FilterBox{0, 0, l->width, l->height});
      table_base_.push_back(tables.size());
      tables.insert(tables.end(), l->tables.begin(), l->tables.end());
      noise_base_.push_back(noise.size());
      noise.insert(noise.end(), l->noise.begin(), l->noise.end());
    }
    total_ = total;
    tables_.upload(tables.empty() ? std::vector<float>{0} : tables);
    noise_.upload(noise.empty() ? std::vector<double>{0} : noise);
  }

  // The last op's planes (transparent ones for an empty graph).
  PlanesPtr run() {
    const FilterLayer& first = *l_[0];
    const size_t n = first.ops.size();
    // Each result is dropped after the last op that reads it (FilterLayer::
    // last_use, as the CPU's graph does): a graph holds the images still
    // to be read, not all it made.
    const bool planned = first.last_use.size() == n;
    for (size_t k = 0; k < n; k++) {
      results_.push_back(apply(k));
      if (!planned) continue;
      for (size_t i = 0; i + 1 < n && i <= k; i++)
        if (results_[i] && (first.last_use[i] == k || (first.last_use[i] == n && i == k))) results_[i].reset();
    }
    if (results_.empty()) return make(whole_, false, [](size_t) { return Constant{Rgba4{0, 0, 0, 0}}; });
    return results_.back();
  }

  size_t offset(size_t k) const { return off_[k]; }
  size_t pixels(size_t k) const { return size_t(l_[k]->width) * l_[k]->height; }

 private:
  const FilterOp& op(size_t k, size_t layer) const { return l_[layer]->ops[k]; }
  int width(size_t i) const { return l_[i]->width; }
  const float* px(const Planes& p, size_t i) const { return p.px.data() + off_[i]; }

  // A new image of the batch: layer i's box boxes[i] made by mk(i)'s
  // functor, one launch for all.
  template <class Make>
  std::shared_ptr<Planes> make(const std::vector<FilterBox>& boxes, bool linear, Make mk) const {
    using F = decltype(mk(size_t(0)));
    auto out = std::make_shared<Planes>();
    out->px.resize(std::max<size_t>(total_, 4));
    MPVG_CUDA(cudaMemsetAsync(out->px.data(), 0, total_ * sizeof(float), cudaStreamPerThread));
    out->linear = linear;
    out->boxes = boxes;
    std::vector<Item<F>> items;
    int mw = 0, mh = 0;
    for (size_t i = 0; i < n_; i++) {
      const FilterBox& b = boxes[i];
      items.push_back(Item<F>{mk(i), b, width(i), out->px.data() + off_[i]});
      mw = std::max(mw, b.x1 - b.x0);
      mh = std::max(mh, b.y1 - b.y0);
    }
    if (mw > 0 && mh > 0) {
      DeviceBuffer<Item<F>> d;
      d.upload(items);
      const dim3 block(32, 8);
      const dim3 grid(grid_for(mw, block.x), grid_for(mh, block.y), static_cast<unsigned>(n_));
      k_pixels<<<grid, block, 0, cudaStreamPerThread>>>(d.data());
      MPVG_LAUNCHED();
    }
    return out;
  }

  std::vector<FilterBox> op_boxes(size_t k) const {
    std::vector<FilterBox> b;
    for (size_t i = 0; i < n_; i++) b.push_back(op(k, i).box);
    return b;
  }

  PlanesPtr input(int32_t in, bool linear) {
    if (in >= 0 && static_cast<size_t>(in) < results_.size()) {
      const PlanesPtr r = results_[in];
      if (!r) throw Error("filter graph: a result read after its last use");
      if (r->linear == linear) return r;
      return make(r->boxes, linear, [&](size_t i) {
        return Converted{px(*r, i), r->boxes[i], width(i), r->linear, linear, false};
      });
    }
    switch (in) {
      case FILTER_SOURCE_GRAPHIC:
      case FILTER_SOURCE_ALPHA:
        return make(whole_, linear, [&](size_t i) {
          return Converted{sources_[i], whole_[i], width(i), l_[i]->source_linear, linear, in == FILTER_SOURCE_ALPHA};
        });
      case FILTER_FILL_PAINT:
      case FILTER_STROKE_PAINT:
        return make(whole_, linear, [&](size_t i) {
          const Rgba4 c = in == FILTER_FILL_PAINT ? l_[i]->fill_paint : l_[i]->stroke_paint;
          return Constant{filter_convert(Rgba4{c.r * c.a, c.g * c.a, c.b * c.a, c.a}, false, linear)};
        });
      default: return make(whole_, linear, [](size_t) { return Constant{Rgba4{0, 0, 0, 0}}; });
    }
  }

  // The blur of `in` by layer i's deviations sx(i), sy(i) (the passes
  // differ between layers, their number does not).
  template <class Sx, class Sy, class Edge>
  PlanesPtr blur(PlanesPtr in, Sx sx, Sy sy, Edge edge) const {
    std::vector<std::vector<FilterBlurPass>> passes(n_);
    int count = 0;
    for (size_t i = 0; i < n_; i++) {
      FilterBlurPass p[6];
      count = filter_blur_passes(sx(i), sy(i), edge(i), p);
      passes[i].assign(p, p + count);
    }
    PlanesPtr cur = in;
    for (int k = 0; k < count; k++) {
      const PlanesPtr src = cur;
      cur = make(whole_, src->linear, [&](size_t i) {
        const FilterBlurPass& p = passes[i][k];
        return BlurPass{px(*src, i), src->boxes[i], width(i), p.size, p.lead, p.horizontal, p.boxes, p.s, p.edge};
      });
    }
    if (count == 0)
      cur = make(in->boxes, in->linear, [&](size_t i) { return Shifted{px(*in, i), in->boxes[i], width(i), 0, 0}; });
    return cur;
  }

  PlanesPtr apply(size_t k) {
    const FilterOp& o0 = op(k, 0);
    const bool lin = o0.linear != 0;
    const std::vector<FilterBox> boxes = op_boxes(k);
    auto shift = [](float d) { return static_cast<int>(lroundf(d)); };
    switch (o0.kind) {
      case FOP_FLOOD:
        return make(boxes, lin, [&](size_t i) {
          const FilterOp& o = op(k, i);
          return Constant{Rgba4{o.color[0], o.color[1], o.color[2], o.color[3]}};
        });
      case FOP_OFFSET: {
        const PlanesPtr a = input(o0.in, lin);
        return make(boxes, lin, [&](size_t i) {
          return Shifted{px(*a, i), a->boxes[i], width(i), shift(op(k, i).dx), shift(op(k, i).dy)};
        });
      }
      case FOP_MERGE: {
        std::vector<PlanesPtr> ins;
        for (uint32_t j = 0; j < o0.inputs_count; j++) ins.push_back(input(l_[0]->inputs[o0.inputs_begin + j], lin));
        const size_t m = std::max<size_t>(1, o0.inputs_count);
        std::vector<const float*> ptrs(n_ * m, nullptr);
        std::vector<FilterBox> bxs(n_ * m, FilterBox{});
        for (size_t i = 0; i < n_; i++)
          for (size_t j = 0; j < ins.size(); j++) ptrs[i * m + j] = px(*ins[j], i), bxs[i * m + j] = ins[j]->boxes[i];
        DeviceBuffer<const float*> dptrs;
        DeviceBuffer<FilterBox> dboxes;
        dptrs.upload(ptrs);
        dboxes.upload(bxs);
        return make(boxes, lin, [&](size_t i) {
          return Merged{dptrs.data() + i * m, dboxes.data() + i * m, o0.inputs_count, width(i)};
        });
      }
      case FOP_COMPOSITE:
      case FOP_BLEND:
      case FOP_COLOR_MATRIX:
      case FOP_COMPONENT_TRANSFER: {
        const PlanesPtr a = input(o0.in, lin);
        const bool two = o0.kind == FOP_COMPOSITE || o0.kind == FOP_BLEND;
        const PlanesPtr b = two ? input(o0.in2, lin) : a;
        return make(boxes, lin, [&](size_t i) {
          return Pointwise{op(k, i), px(*a, i), px(*b, i), tables_.data() + table_base_[i], a->boxes[i], b->boxes[i],
                           width(i)};
        });
      }
      case FOP_GAUSSIAN_BLUR: {
        const PlanesPtr a = input(o0.in, lin);
        const PlanesPtr b = blur(
            a, [&](size_t i) { return op(k, i).std_x; }, [&](size_t i) { return op(k, i).std_y; },
            [&](size_t i) { return op(k, i).edge; });
        return make(boxes, lin, [&](size_t i) { return Shifted{px(*b, i), b->boxes[i], width(i), 0, 0}; });
      }
      case FOP_DROP_SHADOW: {
        const PlanesPtr a = input(o0.in, lin);
        const PlanesPtr shadow = make(a->boxes, lin, [&](size_t i) {
          const FilterOp& o = op(k, i);
          return ShadowColour{px(*a, i), a->boxes[i], width(i), Rgba4{o.color[0], o.color[1], o.color[2], o.color[3]}};
        });
        const PlanesPtr blurred = blur(
            shadow, [&](size_t i) { return op(k, i).std_x; }, [&](size_t i) { return op(k, i).std_y; },
            [](size_t) { return uint32_t(FEDGE_NONE); });
        return make(boxes, lin, [&](size_t i) {
          return UnderShadow{px(*a, i),  px(*blurred, i), a->boxes[i], blurred->boxes[i], width(i),
                             shift(op(k, i).dx), shift(op(k, i).dy)};
        });
      }
      case FOP_MORPHOLOGY: {
        const PlanesPtr a = input(o0.in, lin);
        if (o0.rx <= 0 && o0.ry <= 0)
          return make(boxes, lin, [&](size_t i) { return Shifted{px(*a, i), a->boxes[i], width(i), 0, 0}; });
        const PlanesPtr rows = make(whole_, lin, [&](size_t i) {
          FilterOp h = op(k, i);
          h.ry = 0;
          return Morph{h, px(*a, i), a->boxes[i], width(i)};
        });
        return make(boxes, lin, [&](size_t i) {
          FilterOp v = op(k, i);
          v.rx = 0;
          return Morph{v, px(*rows, i), whole_[i], width(i)};
        });
      }
      case FOP_TILE: {
        const PlanesPtr a = input(o0.in, lin);
        if (o0.tile.x1 <= o0.tile.x0 || o0.tile.y1 <= o0.tile.y0)
          return make(boxes, lin, [](size_t) { return Constant{Rgba4{0, 0, 0, 0}}; });
        return make(boxes, lin, [&](size_t i) { return Tiled{px(*a, i), a->boxes[i], op(k, i).tile, width(i)}; });
      }
      case FOP_IMAGE: {
        std::vector<DeviceBuffer<float>> pics(n_);
        for (size_t i = 0; i < n_; i++) pics[i].upload(l_[i]->images[op(k, i).image].rgba);
        return make(whole_, lin, [&](size_t i) {
          return Converted{pics[i].data(), whole_[i], width(i), l_[i]->image_linear[op(k, i).image] != 0, lin, false};
        });
      }
      case FOP_CONVOLVE_MATRIX:
      case FOP_DISPLACEMENT_MAP:
      case FOP_DIFFUSE_LIGHTING:
      case FOP_SPECULAR_LIGHTING:
      case FOP_TURBULENCE: {
        const bool reads = o0.kind != FOP_TURBULENCE;
        const PlanesPtr a = reads ? input(o0.in, lin) : nullptr;
        const PlanesPtr b = o0.kind == FOP_DISPLACEMENT_MAP ? input(o0.in2, lin) : a;
        return make(boxes, lin, [&](size_t i) {
          return Neighbourhood{op(k, i),
                               a ? px(*a, i) : nullptr,
                               b ? px(*b, i) : nullptr,
                               tables_.data() + table_base_[i],
                               noise_.data() + noise_base_[i],
                               a ? a->boxes[i] : FilterBox{},
                               b ? b->boxes[i] : FilterBox{},
                               width(i)};
        });
      }
      default: return make(boxes, lin, [](size_t) { return Constant{Rgba4{0, 0, 0, 0}}; });
    }
  }

  std::vector<const FilterLayer*> l_;
  std::vector<const float*> sources_;
  size_t n_ = 0, total_ = 0;
  std::vector<size_t> off_, table_base_, noise_base_;
  std::vector<FilterBox> whole_;
  DeviceBuffer<float> tables_;
  DeviceBuffer<double> noise_;
  std::vector<PlanesPtr> results_;
};

// Texels on a device, freed there whichever thread drops the last image.
struct DeviceTexelStore {
  int device = 0;
  DeviceBuffer<Texel16> texels;
  ~DeviceTexelStore() {
    int current = 0;
    cudaGetDevice(&current);
    if (current != device) cudaSetDevice(device);
    texels = DeviceBuffer<Texel16>{};
    if (current != device) cudaSetDevice(current);
  }
};

// Layers of one shape, as batches whose images stay under kMaxFilterBytes.
std::vector<std::vector<size_t>> batches_of(const std::vector<const FilterLayer*>& layers) {
  std::map<std::string, std::vector<size_t>> by_shape;
  std::vector<std::string> order;
  for (size_t k = 0; k < layers.size(); k++) {
    std::string s = shape_of(*layers[k]);
    auto [it, fresh] = by_shape.try_emplace(s);
    if (fresh) order.push_back(s);
    it->second.push_back(k);
  }
  std::vector<std::vector<size_t>> out;
  for (const std::string& s : order) {
    std::vector<size_t> cur;
    uint64_t bytes = 0;
    for (size_t k : by_shape[s]) {
      const uint64_t b = uint64_t(layers[k]->width) * layers[k]->height * 16 * (layers[k]->ops.size() + 4);
      if (!cur.empty() && (bytes + b > kMaxFilterBytes || cur.size() >= 65535)) {
        out.push_back(std::move(cur));
        cur.clear();
        bytes = 0;
      }
      cur.push_back(k);
      bytes += b;
    }
    if (!cur.empty()) out.push_back(std::move(cur));
  }
  return out;
}

}  // namespace

std::vector<std::shared_ptr<const Image>> run_filters_cuda(const std::vector<const FilterLayer*>& layers,
                                                           const std::vector<const float*>& sources, Gamma gamma) {
  std::vector<std::shared_ptr<const Image>> out(layers.size());
  int device = 0;
  MPVG_CUDA(cudaGetDevice(&device));
  for (const std::vector<size_t>& batch : batches_of(layers)) {
    std::vector<const FilterLayer*> ls;
    std::vector<const float*> srcs;
    for (size_t k : batch) ls.push_back(layers[k]), srcs.push_back(sources[k]);
    Batch b(ls, srcs);
    const PlanesPtr r = b.run();
    auto store = std::make_shared<DeviceTexelStore>();
    store->device = device;
    size_t total = 0, most = 0;
    for (size_t i = 0; i < ls.size(); i++) total += b.pixels(i), most = std::max(most, b.pixels(i));
    store->texels.resize(std::max<size_t>(total, 1));
    std::vector<TexelItem> items;
    size_t at = 0;
    for (size_t i = 0; i < ls.size(); i++) {
      items.push_back(TexelItem{r->px.data() + b.offset(i), store->texels.data() + at, b.pixels(i)});
      at += b.pixels(i);
    }
    if (most > 0) {
      DeviceBuffer<TexelItem> d;
      d.upload(items);
      k_texels<<<dim3(grid_for(most, 256), static_cast<unsigned>(ls.size())), 256, 0, cudaStreamPerThread>>>(
          d.data(), r->linear, gamma == Gamma::Linear);
      MPVG_LAUNCHED();
    }
    std::shared_ptr<const void> owner = store;
    for (size_t i = 0; i < ls.size(); i++) {
      auto texels = std::make_shared<ExecutorTexels>();
      texels->device = items[i].out;
      texels->owner = owner;
      auto img = std::make_shared<Image>();
      img->width = ls[i]->width;
      img->height = ls[i]->height;
      img->texels = std::move(texels);
      out[batch[i]] = std::move(img);
    }
  }
  return out;
}

std::vector<std::shared_ptr<const Image>> run_filters_cuda(const std::vector<const FilterLayer*>& layers, Gamma gamma) {
  std::vector<DeviceBuffer<float>> sources(layers.size());
  std::vector<const float*> ptrs;
  for (size_t k = 0; k < layers.size(); k++) {
    const std::vector<float>& px = layers[k]->source.rgba;
    if (px.size() != size_t(layers[k]->width) * layers[k]->height * 4) throw Error("a layer's source of the wrong size");
    sources[k].upload(px.empty() ? std::vector<float>(4, 0.0f) : px);
    ptrs.push_back(sources[k].data());
  }
  return run_filters_cuda(layers, ptrs, gamma);
}

std::vector<Texel16> download_texels(const Image& image) {
  const size_t n = size_t(image.width) * image.height;
  if (!image.texels) throw Error("not an executor's image");
  if (!image.texels->device) return image.texels->host;
  std::vector<Texel16> out(n);
  if (n) MPVG_CUDA(cudaMemcpy(out.data(), image.texels->device, n * sizeof(Texel16), cudaMemcpyDeviceToHost));
  return out;
}

FilterResult run_filter_cuda(const FilterLayer& layer) {
  FilterResult r;
  DeviceBuffer<float> source;
  source.upload(layer.source.rgba.empty() ? std::vector<float>(4, 0.0f) : layer.source.rgba);
  Batch b({&layer}, {source.data()});
  const PlanesPtr p = b.run();
  r.rgba = p->px.download(b.pixels(0) * 4);
  r.linear = p->linear;
  MPVG_CUDA(cudaStreamSynchronize(cudaStreamPerThread));
  return r;
}

}  // namespace mpvg::gpu
