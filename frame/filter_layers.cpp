// Filter effects as layers: regions to pixel boxes, primitives to ops, the
// source rendered, the result as a texture (frame/filter_layers.h).
#include "frame/filter_layers.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "core/parallel.h"
#include "frame/scene_info.h"

namespace mpvg {

namespace {

// The pixel bounds of a user-space rectangle mapped by m, rounded out.
FilterBox pixel_box(const FilterRect& r, const Affine& m) {
  if (!(r.w > 0) || !(r.h > 0)) return FilterBox{};
  double x0, y0, x1, y1;
  filter_rect_bounds(r, m, x0, y0, x1, y1);
  auto clampi = [](double v) { return static_cast<int>(std::clamp(v, -1e9, 1e9)); };
  // A hair inside, so that a region on pixel edges is not grown by rounding.
  return FilterBox{clampi(std::floor(x0 + 1e-6)), clampi(std::floor(y0 + 1e-6)), clampi(std::ceil(x1 - 1e-6)),
                   clampi(std::ceil(y1 - 1e-6))};
}

FilterBox intersect(const FilterBox& a, const FilterBox& b) {
  FilterBox r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
  if (r.x1 <= r.x0 || r.y1 <= r.y0) return FilterBox{};
  return r;
}

bool empty(const FilterBox& b) { return b.x1 <= b.x0 || b.y1 <= b.y0; }

// What a primitive can pull into a pixel from outside the output, in
// pixels: blur extents, offsets, radii (tiles and lighting read more, and
// are bounded by the layer cap instead).
double reach(const FilterPrimitive& p, double sx, double sy) {
  const double blur = 3.0 * std::max(std::abs(p.std_dev_x) * sx, std::abs(p.std_dev_y) * sy);
  switch (p.kind) {
    case FilterKind::GaussianBlur: return blur + 2;
    case FilterKind::DropShadow: return blur + 2 + std::hypot(p.dx * sx, p.dy * sy);
    case FilterKind::Offset: return std::hypot(p.dx * sx, p.dy * sy) + 1;
    case FilterKind::Morphology: return std::max(std::abs(p.radius_x) * sx, std::abs(p.radius_y) * sy) + 1;
    case FilterKind::DisplacementMap: return std::abs(p.scale) * std::max(sx, sy) + 1;
    case FilterKind::ConvolveMatrix: return std::max(p.order_x, p.order_y) + 1;
    case FilterKind::Tile: return 1e9;
    default: return 0;
  }
}

// A straight sRGB-encoded colour premultiplied in the op's space.
void premultiplied(const float c[4], bool linear, float out[4]) {
  const float a = filter_clamp01(c[3]);
  for (int i = 0; i < 3; i++) {
    const float v = filter_clamp01(c[i]);
    out[i] = (linear ? srgb_to_linear(v) : v) * a;
  }
  out[3] = a;
}

}  // namespace

std::vector<uint32_t> filter_last_uses(const FilterEffect& f) {
  const uint32_t n = static_cast<uint32_t>(f.primitives.size());
  std::vector<uint32_t> last(n, n);
  for (uint32_t k = 0; k < n; k++) {
    const FilterPrimitive& p = f.primitives[k];
    auto use = [&](int32_t in) {
      if (in >= 0 && static_cast<uint32_t>(in) < k) last[in] = k;
    };
    use(p.in), use(p.in2);
    for (int32_t in : p.inputs) use(in);
  }
  return last;
}

uint64_t filter_layer_bytes(const FilterEffect& f) {
  const std::vector<uint32_t> last = filter_last_uses(f);
  const size_t n = last.size();
  // Results alive as op k makes its own: those made before and read by k
  // or later (or the graph's, the last).
  std::vector<size_t> drops(n, 0);  // results dropped after op k
  for (size_t i = 0; i < n; i++) drops[last[i] < n ? last[i] : i]++;
  size_t alive = 0, peak = 0;
  for (size_t k = 0; k < n; k++) {
    peak = std::max(peak, ++alive);
    if (k + 1 < n) alive -= drops[k];
  }
  // The source's render first (its frame: 16 + 16 + 32 bytes a pixel,
  // render_cpu), then the graph: the results and an op's two inputs
  // (converted or made) and output; beside both the source's image (16)
  // and the result's texels (8).
  return std::max<uint64_t>(64, 16 * (peak + 3)) + 16 + 8;
}

LayerJob plan_layer(const FilterEffect& f, const RenderOptions& o, std::string* warning) {
  LayerJob job;
  FilterLayer& l = job.layer;
  FilterBox& box = job.box;
  const Affine m = o.view * f.xf;  // user space to output pixels
  const double sx = std::hypot(m.a, m.b), sy = std::hypot(m.c, m.d);
  double margin = 0;
  for (const FilterPrimitive& p : f.primitives) margin += reach(p, sx, sy);
  margin = std::min(margin, 1e8);
  const int g = static_cast<int>(std::ceil(margin));
  const FilterBox grown{-g, -g, o.width + g, o.height + g};
  FilterBox b = intersect(pixel_box(f.region, m), grown);
  if (empty(b)) return job;
  // The memory cap: kMaxFilterBytes, or what a blur's layer of four
  // times the output's pixels takes where that is more, within a quarter
  // of the budget (its limit, not what is left: both executors cut
  // alike); the box is cut around the output's centre.
  const uint64_t per_pixel = filter_layer_bytes(f);
  uint64_t share = std::max<uint64_t>(kMaxFilterBytes, 4 * uint64_t(o.width) * uint64_t(o.height) * kOneOpLayerBytes);
  if (o.budget) share = std::min(share, o.budget->limit() / 4);
  const uint64_t max_pixels = std::min<uint64_t>(kMaxFilterLayerPixels, share / per_pixel);
  while (static_cast<uint64_t>(b.x1 - b.x0) * static_cast<uint64_t>(b.y1 - b.y0) > max_pixels) {
    if (warning) *warning = "filter region too large for a layer: cut to the pixels nearest the output";
    const int cx = o.width / 2, cy = o.height / 2;
    if (b.x1 - b.x0 >= b.y1 - b.y0) {
      const int half = (b.x1 - b.x0) / 4;
      b.x0 = std::max(b.x0, cx - half), b.x1 = std::min(b.x1, cx + half);
    } else {
      const int half = (b.y1 - b.y0) / 4;
      b.y0 = std::max(b.y0, cy - half), b.y1 = std::min(b.y1, cy + half);
    }
    if (empty(b)) return job;
  }
  box = b;
  l.width = b.x1 - b.x0;
  l.height = b.y1 - b.y0;
  l.last_use = filter_last_uses(f);
  l.bytes_per_pixel = per_pixel;
  const Affine to_layer = Affine::translate(-b.x0, -b.y0);
  const Affine lm = to_layer * m;  // user space to layer pixels
  const FilterBox whole{0, 0, l.width, l.height};
  const FilterBox region = intersect(pixel_box(f.region, lm), whole);

  for (const FilterPrimitive& p : f.primitives) {
    FilterOp op;
    op.kind = static_cast<uint32_t>(p.kind);
    op.in = p.in;
    op.in2 = p.in2;
    op.box = intersect(pixel_box(p.subregion, lm), region);
    op.linear = p.linear_rgb ? 1 : 0;
    premultiplied(p.color, p.linear_rgb, op.color);
    // Offsets move by whole pixels, truncated toward zero (as resvg does; a
    // half-pixel shift would resample the layer).
    const Vec2 d = lm.apply_linear({p.dx, p.dy});
    op.dx = static_cast<float>(std::trunc(std::clamp(d.x, -1e7, 1e7)));
    op.dy = static_cast<float>(std::trunc(std::clamp(d.y, -1e7, 1e7)));
    op.std_x = static_cast<float>(std::max(0.0, p.std_dev_x) * sx);
    op.std_y = static_cast<float>(std::max(0.0, p.std_dev_y) * sy);
    op.edge = static_cast<uint32_t>(p.edge_mode);
    op.mode = p.kind == FilterKind::Blend ? p.blend_mode : static_cast<uint32_t>(p.op);
    for (int i = 0; i < 4; i++) op.k[i] = static_cast<float>(p.k[i]);
    std::copy(p.matrix, p.matrix + 20, op.matrix);
    for (int c = 0; c < 4; c++) {
      const TransferFunction& tf = p.funcs[c];
      op.func[c] = static_cast<uint32_t>(tf.type);
      op.table_begin[c] = static_cast<uint32_t>(l.tables.size());
      op.table_size[c] = static_cast<uint32_t>(tf.table.size());
      l.tables.insert(l.tables.end(), tf.table.begin(), tf.table.end());
      if (tf.type == TransferType::Linear) op.fparam[c][0] = tf.slope, op.fparam[c][1] = tf.intercept;
      if (tf.type == TransferType::Gamma)
        op.fparam[c][0] = tf.amplitude, op.fparam[c][1] = tf.exponent, op.fparam[c][2] = tf.offset;
    }
    op.dilate = p.dilate ? 1 : 0;
    op.rx = static_cast<int>(std::ceil(std::min(1e6, std::max(0.0, p.radius_x) * sx) - 1e-9));
    op.ry = static_cast<int>(std::ceil(std::min(1e6, std::max(0.0, p.radius_y) * sy) - 1e-9));
    op.inputs_begin = static_cast<uint32_t>(l.inputs.size());
    op.inputs_count = static_cast<uint32_t>(p.inputs.size());
    l.inputs.insert(l.inputs.end(), p.inputs.begin(), p.inputs.end());
    if (p.kind == FilterKind::Tile)  // the input's subregion: its op's box, or the region
      op.tile = p.in >= 0 && static_cast<size_t>(p.in) < l.ops.size() ? l.ops[p.in].box : region;
    if (p.kind == FilterKind::Turbulence) {
      const Affine u = lm.inverted();  // layer pixels to user space
      const double to_user[6] = {u.a, u.b, u.c, u.d, u.e, u.f};
      std::copy(to_user, to_user + 6, op.to_user);
      op.freq_x = std::max(0.0, p.base_frequency_x);
      op.freq_y = std::max(0.0, p.base_frequency_y);
      op.octaves = std::min(p.num_octaves, 24);  // later octaves add nothing a float holds
      op.fractal = p.fractal_noise ? 1 : 0;
      op.stitch = p.stitch_tiles ? 1 : 0;
      const double tile[4] = {p.subregion.x, p.subregion.y, p.subregion.w, p.subregion.h};
      std::copy(tile, tile + 4, op.tile_user);
      op.noise_begin = static_cast<uint32_t>(l.noise.size());
      l.noise.resize(l.noise.size() + kNoiseDoubles);
      // The spec rounds the seed to the nearest integer (halves up).
      turbulence_init(static_cast<long>(std::floor(std::clamp(p.seed, -2e9, 2e9) + 0.5)), l.noise.data() + op.noise_begin);
    }
    if (p.kind == FilterKind::ConvolveMatrix) {
      op.order_x = p.order_x;
      op.order_y = p.order_y;
      op.target_x = p.target_x;
      op.target_y = p.target_y;
      op.kernel_begin = static_cast<uint32_t>(l.tables.size());
      l.tables.insert(l.tables.end(), p.kernel.begin(), p.kernel.end());
      op.divisor = p.divisor != 0 ? static_cast<float>(p.divisor) : 1.0f;
      op.bias = static_cast<float>(p.bias);
      op.preserve_alpha = p.preserve_alpha ? 1 : 0;
    }
    if (p.kind == FilterKind::DisplacementMap) {
      op.scale_x = static_cast<float>(p.scale * sx);
      op.scale_y = static_cast<float>(p.scale * sy);
      op.x_channel = p.x_channel & 3;
      op.y_channel = p.y_channel & 3;
    }
    if (p.kind == FilterKind::DiffuseLighting || p.kind == FilterKind::SpecularLighting) {
      op.surface_scale = static_cast<float>(p.surface_scale);
      op.kd = static_cast<float>(p.diffuse_constant);
      op.ks = static_cast<float>(p.specular_constant);
      op.specular_exponent = static_cast<float>(p.specular_exponent);
      // The light colour, straight in the op's space.
      for (int c = 0; c < 3; c++) {
        const float v = filter_clamp01(p.color[c]);
        op.color[c] = p.linear_rgb ? srgb_to_linear(v) : v;
      }
      const LightSource& ls = p.light;
      const double zs = std::sqrt((sx * sx + sy * sy) / 2);  // z scales like lengths
      switch (ls.type) {
        case LightType::Distant: {
          const double az = ls.azimuth * M_PI / 180, el = ls.elevation * M_PI / 180;
          op.light = 1;
          op.light_dir[0] = static_cast<float>(std::cos(az) * std::cos(el));
          op.light_dir[1] = static_cast<float>(std::sin(az) * std::cos(el));
          op.light_dir[2] = static_cast<float>(std::sin(el));
          break;
        }
        case LightType::Point:
        case LightType::Spot: {
          op.light = ls.type == LightType::Point ? 2 : 3;
          const Vec2 pos = lm.apply({ls.x, ls.y}), at = lm.apply({ls.points_at_x, ls.points_at_y});
          const float lp[3] = {float(pos.x), float(pos.y), float(ls.z * zs)};
          const float la[3] = {float(at.x), float(at.y), float(ls.points_at_z * zs)};
          std::copy(lp, lp + 3, op.light_pos);
          std::copy(la, la + 3, op.light_at);
          op.spot_exponent = static_cast<float>(ls.specular_exponent);
          op.cone_cos = ls.has_cone ? static_cast<float>(std::cos(std::abs(ls.limiting_cone_angle) * M_PI / 180)) : -2.0f;
          break;
        }
        case LightType::None: op.light = 0; break;
      }
    }
    if (p.kind == FilterKind::Image) op.image = static_cast<uint32_t>(l.images.size()), l.images.push_back(ImageF{}),
                                     l.image_linear.push_back(0);
    l.ops.push_back(op);
  }
  // The time cap: pixels each op reads, over its box.
  double reads = 0;
  for (const FilterOp& op : l.ops) {
    const double px = double(op.box.x1 - op.box.x0) * double(op.box.y1 - op.box.y0) + double(l.width) * l.height;
    double per = 4;
    if (op.kind == FOP_GAUSSIAN_BLUR || op.kind == FOP_DROP_SHADOW) {
      FilterBlurPass passes[6];
      const int n = filter_blur_passes(op.std_x, op.std_y, op.edge, passes);
      for (int i = 0; i < n; i++) per += passes[i].boxes ? passes[i].size + 1.0 : 6.0 * passes[i].s + 1;
    }
    if (op.kind == FOP_MORPHOLOGY) per += 2.0 * op.rx + 2.0 * op.ry;
    if (op.kind == FOP_CONVOLVE_MATRIX) per += double(op.order_x) * op.order_y;
    if (op.kind == FOP_TURBULENCE) per += 16.0 * op.octaves;
    reads += px * per;
  }
  if (reads > kMaxFilterReads) {
    if (warning) *warning = "filter effect too costly (blur, morphology or convolution windows over a large layer): not drawn";
    job.layer = FilterLayer{};
    return job;
  }
  // feImage's pictures: an element rendered over the layer like the
  // source, a raster resampled (bilinear, premultiplied) into its box.
  for (size_t k = 0; k < f.primitives.size(); k++) {
    const FilterPrimitive& p = f.primitives[k];
    if (p.kind != FilterKind::Image) continue;
    const FilterOp& op = l.ops[k];
    ImageF& pic = l.images[op.image];
    if (p.scene) {
      RenderOptions io = o;
      io.width = l.width;
      io.height = l.height;
      io.view = to_layer * o.view * f.xf;
      io.background = RGBA{0, 0, 0, 0};
      io.aliased_paths = o.aliased_paths || has_aliased_paths(*p.scene);
      job.elements.push_back(LayerJob::Element{op.image, p.scene.get(), io});
      l.image_linear[op.image] = o.gamma == Gamma::Linear ? 1 : 0;
      continue;
    }
    pic.width = l.width;
    pic.height = l.height;
    pic.rgba.assign(size_t(l.width) * l.height * 4, 0.0f);
    if (!p.image || p.image->width <= 0 || p.image->height <= 0) continue;
    const Affine to_image = (lm * p.image_xf);
    if (!to_image.invertible()) continue;
    const Affine inv = to_image.inverted();  // layer pixels to image pixels
    const Image& im = *p.image;
    auto texel = [&](int i, int j) {
      i = std::clamp(i, 0, im.width - 1), j = std::clamp(j, 0, im.height - 1);
      const size_t o4 = 4 * (size_t(j) * im.width + i);
      float c[4];
      for (int ch = 0; ch < 4; ch++)
        c[ch] = im.bits == 16 ? im.rgba16[o4 + ch] / 65535.0f : im.rgba8[o4 + ch] / 255.0f;
      return Rgba4{c[0] * c[3], c[1] * c[3], c[2] * c[3], c[3]};
    };
    for (int y = op.box.y0; y < op.box.y1; y++)
      for (int x = op.box.x0; x < op.box.x1; x++) {
        const Vec2 q = inv.apply({x + 0.5, y + 0.5});
        if (q.x < 0 || q.y < 0 || q.x >= im.width || q.y >= im.height) continue;
        if (p.image_pixelated) {
          const Rgba4 t = texel(static_cast<int>(q.x), static_cast<int>(q.y));
          float* o4 = &pic.rgba[4 * (size_t(y) * l.width + x)];
          o4[0] = t.r, o4[1] = t.g, o4[2] = t.b, o4[3] = t.a;
          continue;
        }
        const double u = q.x - 0.5, v = q.y - 0.5;
        const int i = static_cast<int>(std::floor(u)), j = static_cast<int>(std::floor(v));
        const float s = static_cast<float>(u - i), t = static_cast<float>(v - j);
        const Rgba4 a = texel(i, j), b = texel(i + 1, j), c = texel(i, j + 1), d = texel(i + 1, j + 1);
        float* o4 = &pic.rgba[4 * (size_t(y) * l.width + x)];
        o4[0] = (1 - t) * ((1 - s) * a.r + s * b.r) + t * ((1 - s) * c.r + s * d.r);
        o4[1] = (1 - t) * ((1 - s) * a.g + s * b.g) + t * ((1 - s) * c.g + s * d.g);
        o4[2] = (1 - t) * ((1 - s) * a.b + s * b.b) + t * ((1 - s) * c.b + s * d.b);
        o4[3] = (1 - t) * ((1 - s) * a.a + s * b.a) + t * ((1 - s) * c.a + s * d.a);
      }
  }
  // The source over the layer, at the output's resolution and sampling.
  RenderOptions& so = job.source_options;
  so = o;
  so.width = l.width;
  so.height = l.height;
  so.view = to_layer * o.view;
  so.background = RGBA{0, 0, 0, 0};
  so.aliased_paths = o.aliased_paths || has_aliased_paths(*f.source);
  job.source = f.source.get();
  l.source_linear = o.gamma == Gamma::Linear;
  l.fill_paint = Rgba4{f.fill_paint[0], f.fill_paint[1], f.fill_paint[2], f.fill_paint[3]};
  l.stroke_paint = Rgba4{f.stroke_paint[0], f.stroke_paint[1], f.stroke_paint[2], f.stroke_paint[3]};
  return job;
}

void render_layer_inputs(LayerJob& job, const LayerRenderer& render) {
  for (const LayerJob::Element& e : job.elements) job.layer.images[e.image] = render(*e.scene, e.options);
  job.layer.source = render(*job.source, job.source_options);
}

FilterLayer filter_layer(const FilterEffect& f, const RenderOptions& o, const LayerRenderer& render, FilterBox& box,
                         std::string* warning) {
  LayerJob job = plan_layer(f, o, warning);
  box = job.box;
  if (job.layer.width <= 0 || job.layer.height <= 0) return FilterLayer{};
  render_layer_inputs(job, render);
  return std::move(job.layer);
}

std::vector<Texel16> result_texels(const FilterResult& r, Gamma gamma, int threads) {
  const size_t n = r.rgba.size() / 4;
  std::vector<Texel16> out(n);
  const bool integ_linear = gamma == Gamma::Linear;
  parallel_for((n + 4095) / 4096, threads, [&](size_t block) {
    const size_t end = std::min(n, (block + 1) * 4096);
    for (size_t i = block * 4096; i < end; i++) {
      const float* p = &r.rgba[4 * i];
      out[i] = filter_texel(Rgba4{p[0], p[1], p[2], p[3]}, r.linear, integ_linear);
    }
  });
  return out;
}

bool has_filters(const Scene& scene) {
  if (!scene.filters.empty()) return true;
  for (const Pattern& p : scene.patterns)
    if (p.tile && has_filters(*p.tile)) return true;
  return false;
}

Scene resolve_filters(const Scene& scene, const RenderOptions& o, const FilterExecutor& ex,
                      std::vector<std::string>* warnings, TextureFilter lookup) {
  Scene out = scene;
  if (scene.filters.empty()) return out;  // (pattern tiles' are the encoder's: EncodeOptions::tile_filters)
  if (!o.view.invertible()) throw Error("filter layers need an invertible view");
  // The filters the scene paints with, each planned once; their layers made
  // together.
  std::vector<int64_t> job_of(scene.filters.size(), -1);
  std::vector<LayerJob> jobs;
  std::vector<uint32_t> filter_of;
  for (const Paint& p : out.paints) {
    if (p.type != PaintType::Filter || job_of[p.index] >= 0) continue;
    std::string warning;
    jobs.push_back(plan_layer(scene.filters[p.index], o, &warning));
    if (warnings && !warning.empty()) warnings->push_back(warning);
    job_of[p.index] = static_cast<int64_t>(jobs.size() - 1);
    filter_of.push_back(p.index);
  }
  const std::vector<std::shared_ptr<const Image>> images = ex.run_layers(jobs);
  std::vector<int64_t> texture(scene.filters.size(), -1);  // -1: draws nothing
  for (size_t k = 0; k < jobs.size(); k++) {
    if (k >= images.size() || !images[k]) continue;
    Texture t;
    t.image = images[k];
    // Layer pixels onto output pixels, texel for pixel.
    t.xf = o.view.inverted() * Affine::translate(jobs[k].box.x0, jobs[k].box.y0);
    t.filter = lookup;
    t.wrap_x = t.wrap_y = TextureWrap::Decal;
    out.textures.push_back(std::move(t));
    texture[filter_of[k]] = static_cast<int64_t>(out.textures.size() - 1);
  }
  for (Paint& p : out.paints) {
    if (p.type != PaintType::Filter) continue;
    const int64_t t = texture[p.index];
    const float opacity = p.opacity;
    if (t < 0) {
      p = Paint{};
      p.color = RGBA{0, 0, 0, 0};
    } else {
      p.type = PaintType::Texture;
      p.index = static_cast<uint32_t>(t);
    }
    p.opacity = opacity;
  }
  out.filters.clear();
  return out;
}

}  // namespace mpvg
