// Filter effects (issue 28): each primitive of the CPU executor against a
// direct double-precision reference written from Filter Effects Module
// Level 1 on small layers, and filter effects end to end through the
// renderer (regions to layers, the result as a texture).
#include <cmath>
#include <functional>
#include <random>

#include "core/filters/filter.h"
#include "frame/filter_layers.h"
#include "frame/frame.h"
#include "tests/catch.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"
#include "frame/scene_info.h"

using namespace mpvg;

namespace {

constexpr int W = 48, H = 40;

struct Px {
  double r = 0, g = 0, b = 0, a = 0;
};

// A random premultiplied source, transparent outside [14, 34) x [12, 28)
// so that blurs and offsets stay inside the layer.
ImageF random_source(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  ImageF img;
  img.width = W;
  img.height = H;
  img.rgba.assign(size_t(W) * H * 4, 0.0f);
  for (int y = 12; y < 28; y++)
    for (int x = 14; x < 34; x++) {
      float* p = &img.rgba[4 * (size_t(y) * W + x)];
      const float a = u(rng) < 0.2f ? 0.0f : u(rng);
      for (int c = 0; c < 3; c++) p[c] = u(rng) * a;
      p[3] = a;
    }
  return img;
}

Px src_at(const ImageF& img, int x, int y) {
  if (x < 0 || y < 0 || x >= W || y >= H) return {};
  const float* p = &img.rgba[4 * (size_t(y) * W + x)];
  return {p[0], p[1], p[2], p[3]};
}

FilterLayer layer_of(const ImageF& src) {
  FilterLayer l;
  l.width = W;
  l.height = H;
  l.source = src;
  l.source_linear = false;
  return l;
}

FilterOp op_of(uint32_t kind, FilterBox box = {0, 0, W, H}) {
  FilterOp op;
  op.kind = kind;
  op.box = box;
  op.linear = 0;
  return op;
}

// The executor's result against ref(x, y) over the whole layer (zero
// outside the last op's box, as the reference must say itself).
void check(const FilterLayer& l, const std::function<Px(int, int)>& ref, double tol = 1.0 / 1024) {
  const FilterResult r = run_filter_cpu(l, 2);
  REQUIRE(r.rgba.size() == size_t(W) * H * 4);
  double worst = 0;
  int wx = -1, wy = -1;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      const Px e = ref(x, y);
      const float* p = &r.rgba[4 * (size_t(y) * W + x)];
      const double d = std::max({std::abs(p[0] - e.r), std::abs(p[1] - e.g), std::abs(p[2] - e.b), std::abs(p[3] - e.a)});
      if (d > worst) worst = d, wx = x, wy = y;
    }
  INFO("worst difference " << worst << " at " << wx << ", " << wy);
  CHECK(worst <= tol);
}

bool in_box(const FilterBox& b, int x, int y) { return x >= b.x0 && x < b.x1 && y >= b.y0 && y < b.y1; }

double clamp01(double v) { return v < 0 ? 0 : (v > 1 ? 1 : v); }

// Straight colour in, straight colour out, premultiplied around it.
Px straight(const Px& p, const std::function<void(double*)>& f) {
  double c[4] = {p.a > 0 ? p.r / p.a : 0, p.a > 0 ? p.g / p.a : 0, p.a > 0 ? p.b / p.a : 0, p.a};
  f(c);
  for (double& v : c) v = clamp01(v);
  return {c[0] * c[3], c[1] * c[3], c[2] * c[3], c[3]};
}

// The spec's box blur passes (§15.17) along one axis, in double.
std::vector<Px> box_blur_axis(const std::vector<Px>& in, double s, bool horizontal) {
  const int d = int(std::floor(s * 3 * std::sqrt(2 * M_PI) / 4 + 0.5));
  std::vector<std::pair<int, int>> passes;  // (size, first offset)
  if (d % 2) passes = {{d, -d / 2}, {d, -d / 2}, {d, -d / 2}};
  else passes = {{d, -d / 2}, {d, -d / 2 + 1}, {d + 1, -d / 2}};
  std::vector<Px> cur = in;
  for (auto [size, first] : passes) {
    std::vector<Px> next(cur.size());
    for (int y = 0; y < H; y++)
      for (int x = 0; x < W; x++) {
        Px acc;
        for (int k = 0; k < size; k++) {
          const int sx = horizontal ? x + first + k : x, sy = horizontal ? y : y + first + k;
          if (sx < 0 || sy < 0 || sx >= W || sy >= H) continue;
          const Px& q = cur[sy * W + sx];
          acc.r += q.r, acc.g += q.g, acc.b += q.b, acc.a += q.a;
        }
        next[y * W + x] = {acc.r / size, acc.g / size, acc.b / size, acc.a / size};
      }
    cur = next;
  }
  return cur;
}

std::vector<Px> gauss_axis(const std::vector<Px>& in, double s, bool horizontal) {
  const int r = int(std::ceil(3 * s));
  std::vector<Px> out(in.size());
  double wsum = 0;
  for (int k = -r; k <= r; k++) wsum += std::exp(-0.5 * k * k / (s * s));
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      Px acc;
      for (int k = -r; k <= r; k++) {
        const int sx = horizontal ? x + k : x, sy = horizontal ? y : y + k;
        if (sx < 0 || sy < 0 || sx >= W || sy >= H) continue;
        const double w = std::exp(-0.5 * k * k / (s * s)) / wsum;
        const Px& q = in[sy * W + sx];
        acc.r += w * q.r, acc.g += w * q.g, acc.b += w * q.b, acc.a += w * q.a;
      }
      out[y * W + x] = acc;
    }
  return out;
}

std::vector<Px> blurred(const ImageF& src, double sx, double sy) {
  std::vector<Px> v(size_t(W) * H);
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) v[y * W + x] = src_at(src, x, y);
  if (sx > 0) v = sx >= 2 ? box_blur_axis(v, sx, true) : gauss_axis(v, sx, true);
  if (sy > 0) v = sy >= 2 ? box_blur_axis(v, sy, false) : gauss_axis(v, sy, false);
  return v;
}

}  // namespace

TEST_CASE("filter primitives: flood, offset, merge and tile against the spec", "[filter]") {
  const ImageF src = random_source(1);
  FilterLayer l = layer_of(src);
  const FilterBox fb{5, 6, 30, 22};
  FilterOp flood = op_of(FOP_FLOOD, fb);
  const float c[4] = {0.2f * 0.5f, 0.4f * 0.5f, 0.9f * 0.5f, 0.5f};
  std::copy(c, c + 4, flood.color);
  l.ops = {flood};
  check(l, [&](int x, int y) { return in_box(fb, x, y) ? Px{c[0], c[1], c[2], c[3]} : Px{}; });

  FilterOp off = op_of(FOP_OFFSET);
  off.in = FILTER_SOURCE_GRAPHIC;
  off.dx = 7;
  off.dy = -3;
  l.ops = {off};
  check(l, [&](int x, int y) { return src_at(src, x - 7, y + 3); });

  // Merge: the offset source over the flood.
  FilterOp merge = op_of(FOP_MERGE);
  l.ops = {flood, off, merge};
  l.inputs = {0, 1};
  l.ops[2].inputs_begin = 0;
  l.ops[2].inputs_count = 2;
  check(l, [&](int x, int y) {
    const Px b = in_box(fb, x, y) ? Px{c[0], c[1], c[2], c[3]} : Px{};
    const Px t = src_at(src, x - 7, y + 3);
    return Px{t.r + b.r * (1 - t.a), t.g + b.g * (1 - t.a), t.b + b.b * (1 - t.a), t.a + b.a * (1 - t.a)};
  });

  // Tile: the source's [16, 24) x [14, 19) repeated over the layer.
  FilterOp crop = op_of(FOP_OFFSET, FilterBox{16, 14, 24, 19});
  crop.in = FILTER_SOURCE_GRAPHIC;
  FilterOp tile = op_of(FOP_TILE);
  tile.in = 0;
  tile.tile = crop.box;
  l.ops = {crop, tile};
  check(l, [&](int x, int y) {
    const int mx = ((x - 16) % 8 + 8) % 8, my = ((y - 14) % 5 + 5) % 5;
    return src_at(src, 16 + mx, 14 + my);
  });
}

TEST_CASE("filter primitives: feComposite's operators and arithmetic", "[filter]") {
  const ImageF a = random_source(2), b = random_source(3);
  FilterLayer l = layer_of(a);
  FilterOp shifted = op_of(FOP_OFFSET);  // in2: the source moved, so the two differ
  shifted.in = FILTER_SOURCE_GRAPHIC;
  shifted.dx = 3;
  shifted.dy = 2;
  for (uint32_t mode : {FCOMP_OVER, FCOMP_IN, FCOMP_OUT, FCOMP_ATOP, FCOMP_XOR, FCOMP_LIGHTER, FCOMP_ARITHMETIC}) {
    INFO("operator " << mode);
    FilterOp comp = op_of(FOP_COMPOSITE);
    comp.in = FILTER_SOURCE_GRAPHIC;
    comp.in2 = 0;
    comp.mode = mode;
    const double k[4] = {0.5, 0.7, -0.3, 0.1};
    for (int i = 0; i < 4; i++) comp.k[i] = float(k[i]);
    l.ops = {shifted, comp};
    check(l, [&](int x, int y) {
      const Px s = src_at(a, x, y), d = src_at(a, x - 3, y - 2);
      auto pd = [&](double fa, double fb) {
        return Px{s.r * fa + d.r * fb, s.g * fa + d.g * fb, s.b * fa + d.b * fb, s.a * fa + d.a * fb};
      };
      Px o;
      switch (mode) {
        case FCOMP_OVER: o = pd(1, 1 - s.a); break;
        case FCOMP_IN: o = pd(d.a, 0); break;
        case FCOMP_OUT: o = pd(1 - d.a, 0); break;
        case FCOMP_ATOP: o = pd(d.a, 1 - s.a); break;
        case FCOMP_XOR: o = pd(1 - d.a, 1 - s.a); break;
        case FCOMP_LIGHTER: o = pd(1, 1); break;
        default: {
          auto f = [&](double i1, double i2) { return k[0] * i1 * i2 + k[1] * i1 + k[2] * i2 + k[3]; };
          o = {f(s.r, d.r), f(s.g, d.g), f(s.b, d.b), f(s.a, d.a)};
        }
      }
      o.a = clamp01(o.a);
      o.r = std::min(clamp01(o.r), o.a), o.g = std::min(clamp01(o.g), o.a), o.b = std::min(clamp01(o.b), o.a);
      return o;
    });
  }
  (void)b;
}

TEST_CASE("filter primitives: feColorMatrix and feComponentTransfer on straight colours", "[filter]") {
  const ImageF src = random_source(4);
  FilterLayer l = layer_of(src);
  FilterOp m = op_of(FOP_COLOR_MATRIX);
  m.in = FILTER_SOURCE_GRAPHIC;
  const float mat[20] = {0.3f, 0.5f, 0.2f, 0, 0.1f, -0.2f, 1.1f, 0.1f, 0, 0, 0.5f, 0.5f, 0, 0.2f, -0.1f,
                         0, 0, 0, 0.8f, 0.15f};
  std::copy(mat, mat + 20, m.matrix);
  l.ops = {m};
  check(l, [&](int x, int y) {
    return straight(src_at(src, x, y), [&](double* c) {
      double o[4];
      for (int r = 0; r < 4; r++)
        o[r] = mat[5 * r] * c[0] + mat[5 * r + 1] * c[1] + mat[5 * r + 2] * c[2] + mat[5 * r + 3] * c[3] + mat[5 * r + 4];
      for (int i = 0; i < 4; i++) c[i] = o[i];
    });
  });

  FilterOp t = op_of(FOP_COMPONENT_TRANSFER);
  t.in = FILTER_SOURCE_GRAPHIC;
  l.tables = {0.1f, 0.9f, 0.3f, 1.0f, 0.0f, 0.5f, 1.0f};
  t.func[0] = FTRANSFER_TABLE, t.table_begin[0] = 0, t.table_size[0] = 4;
  t.func[1] = FTRANSFER_DISCRETE, t.table_begin[1] = 4, t.table_size[1] = 3;
  t.func[2] = FTRANSFER_GAMMA, t.fparam[2][0] = 0.8f, t.fparam[2][1] = 2.2f, t.fparam[2][2] = 0.05f;
  t.func[3] = FTRANSFER_LINEAR, t.fparam[3][0] = 0.7f, t.fparam[3][1] = 0.2f;
  l.ops = {t};
  const std::vector<double> table = {0.1, 0.9, 0.3, 1.0}, disc = {0.0, 0.5, 1.0};
  check(l, [&](int x, int y) {
    return straight(src_at(src, x, y), [&](double* c) {
      const double n = double(table.size() - 1);
      int k = std::min(int(std::floor(c[0] * n)), int(n) - 1);
      c[0] = table[k] + (c[0] - k / n) * n * (table[k + 1] - table[k]);
      c[1] = disc[std::min(int(std::floor(c[1] * 3)), 2)];
      c[2] = 0.8 * std::pow(c[2], 2.2) + 0.05;
      c[3] = 0.7 * c[3] + 0.2;
    });
  });
}

TEST_CASE("filter primitives: feGaussianBlur as the spec's three box blurs, exact below 2", "[filter]") {
  const ImageF src = random_source(5);
  FilterLayer l = layer_of(src);
  for (auto [sx, sy] : {std::pair{3.0, 2.5}, std::pair{1.0, 0.0}, std::pair{2.0, 1.5}}) {
    INFO("std deviation " << sx << ", " << sy);
    FilterOp b = op_of(FOP_GAUSSIAN_BLUR);
    b.in = FILTER_SOURCE_GRAPHIC;
    b.std_x = float(sx);
    b.std_y = float(sy);
    l.ops = {b};
    const std::vector<Px> ref = blurred(src, sx, sy);
    check(l, [&](int x, int y) { return ref[y * W + x]; });
  }
  // A drop shadow: the alpha, flooded, blurred and offset, under the source.
  FilterOp ds = op_of(FOP_DROP_SHADOW);
  ds.in = FILTER_SOURCE_GRAPHIC;
  ds.std_x = ds.std_y = 2.5f;
  ds.dx = 4;
  ds.dy = 3;
  const float col[4] = {0.5f * 0.6f, 0.1f * 0.6f, 0.2f * 0.6f, 0.6f};
  std::copy(col, col + 4, ds.color);
  l.ops = {ds};
  ImageF alpha = src;
  for (size_t i = 0; i < alpha.rgba.size(); i += 4)
    for (int c = 0; c < 4; c++) alpha.rgba[i + c] = col[c] * src.rgba[i + 3];
  const std::vector<Px> sh = blurred(alpha, 2.5, 2.5);
  check(l, [&](int x, int y) {
    const Px s = (x - 4 >= 0 && y - 3 >= 0) ? sh[(y - 3) * W + (x - 4)] : Px{};
    const Px p = src_at(src, x, y);
    return Px{p.r + s.r * (1 - p.a), p.g + s.g * (1 - p.a), p.b + s.b * (1 - p.a), p.a + s.a * (1 - p.a)};
  });
}

TEST_CASE("filter primitives: feMorphology erodes and dilates per channel", "[filter]") {
  const ImageF src = random_source(6);
  FilterLayer l = layer_of(src);
  for (bool dilate : {false, true}) {
    FilterOp m = op_of(FOP_MORPHOLOGY);
    m.in = FILTER_SOURCE_GRAPHIC;
    m.dilate = dilate;
    m.rx = 2;
    m.ry = 1;
    l.ops = {m};
    check(l, [&](int x, int y) {
      double e[4] = {dilate ? 0.0 : 1.0, dilate ? 0.0 : 1.0, dilate ? 0.0 : 1.0, dilate ? 0.0 : 1.0};
      for (int j = y - 1; j <= y; j++)  // the spec's 2 rx x 2 ry window
        for (int i = x - 2; i <= x + 1; i++) {
          const Px p = src_at(src, i, j);
          const double v[4] = {p.r, p.g, p.b, p.a};
          for (int c = 0; c < 4; c++) e[c] = dilate ? std::max(e[c], v[c]) : std::min(e[c], v[c]);
        }
      return Px{e[0], e[1], e[2], e[3]};
    });
  }
}

TEST_CASE("filter effects end to end: the source offset inside its region, as a texture", "[filter]") {
  // A blue square [10, 20)^2 offset by (12, 4) user units under view x2:
  // the filter region [0, 40)^2 is 80 x 80 pixels of a 100 x 100 image.
  SceneBuilder src(40, 40);
  const uint32_t sq = src.add_geometry(Path::rectangle(10, 10, 20, 20));
  Paint blue;
  blue.color = RGBA{0, 0, 1, 1};
  src.fill(sq, Affine{}, FillRule::NonZero, blue);
  FilterEffect f;
  f.source = std::make_shared<const Scene>(src.finish());
  f.region = FilterRect{0, 0, 40, 40};
  FilterPrimitive off;
  off.kind = FilterKind::Offset;
  off.in = FILTER_SOURCE_GRAPHIC;
  off.dx = 12;
  off.dy = 4;
  off.subregion = f.region;
  FilterPrimitive flood;  // a translucent red under it, over [0, 10) x [0, 40)
  flood.kind = FilterKind::Flood;
  flood.subregion = FilterRect{0, 0, 10, 40};
  const float red[4] = {1, 0, 0, 0.5f};
  std::copy(red, red + 4, flood.color);
  flood.linear_rgb = false;
  FilterPrimitive merge;
  merge.kind = FilterKind::Merge;
  merge.inputs = {1, 0};
  merge.subregion = f.region;
  f.primitives = {off, flood, merge};

  SceneBuilder b(50, 50);
  const uint32_t region = b.add_geometry(Path::rectangle(0, 0, 40, 40));
  Paint fp;
  fp.type = PaintType::Filter;
  fp.index = b.add_filter(f);
  b.fill(region, Affine{}, FillRule::NonZero, fp);
  const Scene scene = b.finish();
  CHECK(dump(scene).find("filter 0 region 0 0 40 40") != std::string::npos);

  RenderOptions o;
  o.width = o.height = 100;
  o.view = Affine::scale(2, 2);
  o.samples = 32;
  o.gamma = Gamma::Srgb;
  o.threads = 2;
  const ImageF img = render_cpu(scene, o);
  auto px = [&](int x, int y) {
    const float* p = &img.rgba[4 * (size_t(y) * 100 + x)];
    return Px{p[0], p[1], p[2], p[3]};
  };
  // The square moved to [22, 32) x [14, 24) user units: pixels [44, 64) x [28, 48).
  const Px in = px(54, 38), was = px(30, 30), left = px(10, 70), out = px(90, 90);
  CHECK(in.b == Approx(1).margin(1e-3));
  CHECK(in.a == Approx(1).margin(1e-3));
  CHECK(was.a == Approx(0).margin(1e-3));
  CHECK(left.r == Approx(0.5).margin(2e-3));
  CHECK(left.a == Approx(0.5).margin(2e-3));
  CHECK(out.a == Approx(0).margin(1e-3));
  // The square's edges stay sharp: the layer maps texel for pixel.
  CHECK(px(43, 38).a == Approx(0).margin(1e-3));
  CHECK(px(44, 38).a == Approx(1).margin(1e-3));
}

TEST_CASE("filter primitives: feConvolveMatrix, feDisplacementMap and lighting against the spec", "[filter]") {
  const ImageF src = random_source(7);
  FilterLayer l = layer_of(src);
  // A 3 x 2 kernel, target (2, 0), divisor 2, bias 0.1, edge mode none over
  // the whole layer.
  FilterOp cv = op_of(FOP_CONVOLVE_MATRIX);
  cv.in = FILTER_SOURCE_GRAPHIC;
  cv.order_x = 3, cv.order_y = 2, cv.target_x = 2, cv.target_y = 0;
  cv.divisor = 2, cv.bias = 0.1f;
  const std::vector<float> kernel = {1, -1, 0.5f, 2, 0, -0.5f};
  l.tables = kernel;
  cv.kernel_begin = 0;
  l.ops = {cv};
  check(l, [&](int x, int y) {
    double s[4] = {0, 0, 0, 0};
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 3; j++) {
        const Px p = src_at(src, x - 2 + j, y - 0 + i);
        const double k = kernel[6 - 1 - (i * 3 + j)];
        s[0] += k * p.r, s[1] += k * p.g, s[2] += k * p.b, s[3] += k * p.a;
      }
    const double a = s[3] / 2 + 0.1, ba = clamp01(a);
    auto c = [&](double v) { return std::clamp(v / 2 + 0.1 * a, 0.0, ba); };
    return Px{c(s[0]), c(s[1]), c(s[2]), ba};
  });

  // Displacement by a map that is 0.5 everywhere moves nothing; by one
  // whose red is 1 moves by scale / 2 to the right.
  for (float red : {0.5f, 1.0f}) {
    FilterOp map = op_of(FOP_FLOOD);
    const float mc[4] = {red * 0.8f, 0.5f * 0.8f, 0.5f * 0.8f, 0.8f};
    std::copy(mc, mc + 4, map.color);
    FilterOp d = op_of(FOP_DISPLACEMENT_MAP);
    d.in = FILTER_SOURCE_GRAPHIC;
    d.in2 = 0;
    d.scale_x = d.scale_y = 6;
    d.x_channel = 0, d.y_channel = 1;
    l.ops = {map, d};
    const int shift = red == 1.0f ? 3 : 0;
    check(l, [&](int x, int y) { return src_at(src, x + shift, y); });
  }

  // Lighting of a flat surface: the normal is (0, 0, 1); a distant light at
  // elevation 30 degrees gives kd sin(30) diffusely, alpha 1; specular
  // takes N.H of H = L + (0, 0, 1).
  ImageF flat = src;
  for (size_t i = 0; i < flat.rgba.size(); i += 4) flat.rgba[i + 3] = 0.5f, flat.rgba[i] = flat.rgba[i + 1] = flat.rgba[i + 2] = 0;
  FilterLayer fl = layer_of(flat);
  for (uint32_t kind : {FOP_DIFFUSE_LIGHTING, FOP_SPECULAR_LIGHTING}) {
    FilterOp li = op_of(kind);
    li.in = FILTER_SOURCE_GRAPHIC;
    li.kd = 0.9f, li.ks = 1.2f, li.specular_exponent = 3;
    li.color[0] = 1, li.color[1] = 0.5f, li.color[2] = 0.25f;
    li.light = 1;
    const double el = 30 * M_PI / 180, az = 20 * M_PI / 180;
    li.light_dir[0] = float(std::cos(az) * std::cos(el)), li.light_dir[1] = float(std::sin(az) * std::cos(el));
    li.light_dir[2] = float(std::sin(el));
    fl.ops = {li};
    double k;
    if (kind == FOP_DIFFUSE_LIGHTING) {
      k = 0.9 * std::sin(el);
    } else {
      const double h[3] = {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el) + 1};
      k = 1.2 * std::pow(h[2] / std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]), 3);
    }
    const Px e = {clamp01(k), clamp01(k * 0.5), clamp01(k * 0.25), 0};
    check(fl, [&](int, int) {
      Px p = e;
      p.a = kind == FOP_DIFFUSE_LIGHTING ? 1.0 : std::max({e.r, e.g, e.b});
      return p;
    });
  }
}

TEST_CASE("filter primitives: feTurbulence is deterministic, bounded and stitches", "[filter]") {
  FilterLayer l = layer_of(random_source(8));
  FilterOp t = op_of(FOP_TURBULENCE);
  t.freq_x = 0.05, t.freq_y = 0.08;
  t.octaves = 3;
  t.fractal = 1;
  l.noise.resize(kNoiseDoubles);
  turbulence_init(7, l.noise.data());
  l.ops = {t};
  const FilterResult a = run_filter_cpu(l, 2), b = run_filter_cpu(l, 1);
  CHECK(a.rgba == b.rgba);
  float lo = 1, hi = 0;
  for (float v : a.rgba) lo = std::min(lo, v), hi = std::max(hi, v);
  CHECK(lo >= 0);
  CHECK(hi <= 1);
  CHECK(hi - lo > 0.2f);  // not flat
  // Seeds of the spec's generator: 0 and 1 set up the same lattice (seed
  // <= 0 becomes -(seed % (m - 1)) + 1), 2 another.
  std::vector<double> n0(kNoiseDoubles), n1(kNoiseDoubles), n2(kNoiseDoubles);
  turbulence_init(0, n0.data());
  turbulence_init(1, n1.data());
  turbulence_init(2, n2.data());
  CHECK(n0 == n1);
  CHECK(n0 != n2);
  // Stitching over a 40-unit tile: the noise repeats with its period.
  t.stitch = 1;
  t.tile_user[0] = 0, t.tile_user[1] = 0, t.tile_user[2] = 40, t.tile_user[3] = 40;
  t.freq_x = t.freq_y = 0.1;
  for (int ch = 0; ch < 4; ch++)
    for (double y : {1.0, 7.5, 13.0}) {
      const double v0 = turbulence_sum(t, l.noise.data(), ch, 0.0, y), v1 = turbulence_sum(t, l.noise.data(), ch, 40.0, y);
      CHECK(v0 == Approx(v1).margin(1e-9));
    }
}

TEST_CASE("filter effects stay bounded: huge layers are cut, costly graphs refused", "[filter]") {
  SceneBuilder src(10, 10);
  Paint red;
  red.color = RGBA{1, 0, 0, 1};
  src.fill(src.add_geometry(Path::rectangle(0, 0, 10, 10)), Affine{}, FillRule::NonZero, red);
  FilterEffect f;
  f.source = std::make_shared<const Scene>(src.finish());
  f.region = FilterRect{-1e6, -1e6, 2e6, 2e6};
  FilterPrimitive big;
  big.kind = FilterKind::ConvolveMatrix;
  big.order_x = big.order_y = 1000;
  big.target_x = big.target_y = 500;
  big.kernel.assign(1000000, 1.0f);
  big.subregion = f.region;
  f.primitives = {big};
  RenderOptions o;
  o.width = o.height = 2000;
  o.samples = 8;
  o.threads = 2;
  int renders = 0;
  const LayerRenderer render = [&](const Scene& s, const RenderOptions& so) {
    renders++;
    return render_cpu(s, so);
  };
  std::string warning;
  FilterBox box;
  FilterLayer l = filter_layer(f, o, render, box, &warning);
  CHECK(l.width == 0);  // 4 million pixels x 1 million taps: refused before the source is rendered
  CHECK(renders == 0);
  CHECK(warning.find("too costly") != std::string::npos);
  // A flood over a region far larger than the output: the layer is cut
  // to the output (plus nothing: a flood reaches no further).
  FilterPrimitive flood;
  flood.kind = FilterKind::Flood;
  flood.subregion = f.region;
  f.primitives = {flood};
  warning.clear();
  l = filter_layer(f, o, render, box, &warning);
  CHECK(l.width == 2000);
  CHECK(l.height == 2000);
  // 200 floods that nothing reads: one result is held at a time (each
  // dropped after its last use), the layer is whole.
  f.primitives.assign(200, flood);
  warning.clear();
  l = filter_layer(f, o, render, box, &warning);
  CHECK(l.width == 2000);
  CHECK(l.height == 2000);
  CHECK(warning.empty());
  CHECK(filter_layer_bytes(f) == 64 + 24);
  // 20,000 merged: all of them are held until the merge reads them, and
  // the memory cap cuts the layer to what they fit in.
  f.primitives.assign(20000, flood);
  FilterPrimitive merge;
  merge.kind = FilterKind::Merge;
  merge.subregion = f.region;
  for (int32_t i = 0; i < 20000; i++) merge.inputs.push_back(i);
  f.primitives.push_back(merge);
  CHECK(filter_layer_bytes(f) == 16 * (20001 + 3) + 24);
  l = filter_layer(f, o, render, box, &warning);
  CHECK(l.width > 0);
  // The cap: kMaxFilterBytes, or a blur's 88 bytes over four times the
  // output's 4 M pixels where that is more (1.408 GB here).
  const uint64_t cap = std::max<uint64_t>(kMaxFilterBytes, uint64_t(4) * 2000 * 2000 * 88);
  CHECK(cap == 1408000000u);
  CHECK(uint64_t(l.width) * l.height * filter_layer_bytes(f) <= cap);
  CHECK(uint64_t(l.width) * l.height * filter_layer_bytes(f) > cap / 2);
  CHECK(warning.find("too large") != std::string::npos);
  // A chain holds two; a budget's quarter bounds the layer where one is given.
  std::vector<uint32_t> last = filter_last_uses(f);
  CHECK(last[0] == 20000);
  CHECK(last[19999] == 20000);
  CHECK(last[20000] == 20001);
  f.primitives.assign(3, flood);
  f.primitives[1].in = 0;
  f.primitives[2].in = 1;
  CHECK(filter_last_uses(f) == std::vector<uint32_t>{1, 2, 3});
  CHECK(filter_layer_bytes(f) == 16 * (2 + 3) + 24);
  o.budget = std::make_shared<MemoryBudget>(uint64_t(4) << 20);
  warning.clear();
  l = filter_layer(f, o, render, box, &warning);
  CHECK(uint64_t(l.width) * l.height * filter_layer_bytes(f) <= (uint64_t(1) << 20));
  CHECK(warning.find("too large") != std::string::npos);
}

namespace spec_turbulence {

// Filter Effects 1 §15.23's reference code, transcribed in its own form
// (globals, setup by seed, lattice masked after stitching) as the oracle
// of core/filters/filter_primitives.h's per-pixel version.
constexpr int BSize = 0x100, BM = 0xff, PerlinN = 0x1000;
int uLatticeSelector[BSize + BSize + 2];
double fGradient[4][BSize + BSize + 2][2];
struct StitchInfo {
  int nWidth, nHeight, nWrapX, nWrapY;
};
constexpr long RAND_m = 2147483647, RAND_a = 16807, RAND_q = 127773, RAND_r = 2836;
long setup_seed(long lSeed) {
  if (lSeed <= 0) lSeed = -(lSeed % (RAND_m - 1)) + 1;
  if (lSeed > RAND_m - 1) lSeed = RAND_m - 1;
  return lSeed;
}
long random(long lSeed) {
  long result = RAND_a * (lSeed % RAND_q) - RAND_r * (lSeed / RAND_q);
  if (result <= 0) result += RAND_m;
  return result;
}
void init(long lSeed) {
  double s;
  int i, j, k;
  lSeed = setup_seed(lSeed);
  for (k = 0; k < 4; k++) {
    for (i = 0; i < BSize; i++) {
      uLatticeSelector[i] = i;
      for (j = 0; j < 2; j++) fGradient[k][i][j] = (double)(((lSeed = random(lSeed)) % (BSize + BSize)) - BSize) / BSize;
      s = double(std::sqrt(fGradient[k][i][0] * fGradient[k][i][0] + fGradient[k][i][1] * fGradient[k][i][1]));
      fGradient[k][i][0] /= s;
      fGradient[k][i][1] /= s;
    }
  }
  while (--i) {
    k = uLatticeSelector[i];
    uLatticeSelector[i] = uLatticeSelector[j = (lSeed = random(lSeed)) % BSize];
    uLatticeSelector[j] = k;
  }
  for (i = 0; i < BSize + 2; i++) {
    uLatticeSelector[BSize + i] = uLatticeSelector[i];
    for (k = 0; k < 4; k++)
      for (j = 0; j < 2; j++) fGradient[k][BSize + i][j] = fGradient[k][i][j];
  }
}
#define s_curve(t) (t * t * (3. - 2. * t))
#define lerp(t, a, b) (a + t * (b - a))
double noise2(int nColorChannel, double vec[2], StitchInfo* pStitchInfo) {
  int bx0, bx1, by0, by1, b00, b10, b01, b11;
  double rx0, rx1, ry0, ry1, *q, sx, sy, a, b, t, u, v;
  int i, j;
  t = vec[0] + PerlinN;
  bx0 = (int)t;
  bx1 = bx0 + 1;
  rx0 = t - (int)t;
  rx1 = rx0 - 1.0f;
  t = vec[1] + PerlinN;
  by0 = (int)t;
  by1 = by0 + 1;
  ry0 = t - (int)t;
  ry1 = ry0 - 1.0f;
  if (pStitchInfo != NULL) {
    if (bx0 >= pStitchInfo->nWrapX) bx0 -= pStitchInfo->nWidth;
    if (bx1 >= pStitchInfo->nWrapX) bx1 -= pStitchInfo->nWidth;
    if (by0 >= pStitchInfo->nWrapY) by0 -= pStitchInfo->nHeight;
    if (by1 >= pStitchInfo->nWrapY) by1 -= pStitchInfo->nHeight;
  }
  bx0 &= BM;
  bx1 &= BM;
  by0 &= BM;
  by1 &= BM;
  i = uLatticeSelector[bx0];
  j = uLatticeSelector[bx1];
  b00 = uLatticeSelector[i + by0];
  b10 = uLatticeSelector[j + by0];
  b01 = uLatticeSelector[i + by1];
  b11 = uLatticeSelector[j + by1];
  sx = double(s_curve(rx0));
  sy = double(s_curve(ry0));
  q = fGradient[nColorChannel][b00];
  u = rx0 * q[0] + ry0 * q[1];
  q = fGradient[nColorChannel][b10];
  v = rx1 * q[0] + ry0 * q[1];
  a = lerp(sx, u, v);
  q = fGradient[nColorChannel][b01];
  u = rx0 * q[0] + ry1 * q[1];
  q = fGradient[nColorChannel][b11];
  v = rx1 * q[0] + ry1 * q[1];
  b = lerp(sx, u, v);
  return lerp(sy, a, b);
}
#undef s_curve
#undef lerp
double turbulence(int nColorChannel, double* point, double fBaseFreqX, double fBaseFreqY, int nNumOctaves,
                  bool bFractalSum, bool bDoStitching, double fTileX, double fTileY, double fTileWidth,
                  double fTileHeight) {
  StitchInfo stitch;
  StitchInfo* pStitchInfo = NULL;
  if (bDoStitching) {
    if (fBaseFreqX != 0.0) {
      double fLoFreq = double(std::floor(fTileWidth * fBaseFreqX)) / fTileWidth;
      double fHiFreq = double(std::ceil(fTileWidth * fBaseFreqX)) / fTileWidth;
      if (fBaseFreqX / fLoFreq < fHiFreq / fBaseFreqX) fBaseFreqX = fLoFreq;
      else fBaseFreqX = fHiFreq;
    }
    if (fBaseFreqY != 0.0) {
      double fLoFreq = double(std::floor(fTileHeight * fBaseFreqY)) / fTileHeight;
      double fHiFreq = double(std::ceil(fTileHeight * fBaseFreqY)) / fTileHeight;
      if (fBaseFreqY / fLoFreq < fHiFreq / fBaseFreqY) fBaseFreqY = fLoFreq;
      else fBaseFreqY = fHiFreq;
    }
    pStitchInfo = &stitch;
    stitch.nWidth = int(fTileWidth * fBaseFreqX + 0.5f);
    stitch.nWrapX = fTileX * fBaseFreqX + PerlinN + stitch.nWidth;
    stitch.nHeight = int(fTileHeight * fBaseFreqY + 0.5f);
    stitch.nWrapY = fTileY * fBaseFreqY + PerlinN + stitch.nHeight;
  }
  double fSum = 0.0f;
  double vec[2];
  vec[0] = point[0] * fBaseFreqX;
  vec[1] = point[1] * fBaseFreqY;
  double ratio = 1;
  for (int nOctave = 0; nOctave < nNumOctaves; nOctave++) {
    if (bFractalSum) fSum += double(noise2(nColorChannel, vec, pStitchInfo) / ratio);
    else fSum += double(std::fabs(noise2(nColorChannel, vec, pStitchInfo)) / ratio);
    vec[0] *= 2;
    vec[1] *= 2;
    ratio *= 2;
    if (pStitchInfo != NULL) {
      stitch.nWidth *= 2;
      stitch.nWrapX = 2 * stitch.nWrapX - PerlinN;
      stitch.nHeight *= 2;
      stitch.nWrapY = 2 * stitch.nWrapY - PerlinN;
    }
  }
  return fSum;
}

}  // namespace spec_turbulence

TEST_CASE("feTurbulence gives the values of the spec's reference code", "[filter]") {
  std::vector<double> noise(kNoiseDoubles);
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> coord(-300.0, 300.0);
  for (long seed : {0L, 1L, 7L, -5L, 123456L}) {
    spec_turbulence::init(seed);
    turbulence_init(seed, noise.data());
    for (uint32_t fractal : {0u, 1u})
      for (uint32_t stitch : {0u, 1u}) {
        FilterOp op;
        op.kind = FOP_TURBULENCE;
        op.freq_x = 0.043, op.freq_y = 0.027;
        op.octaves = 4;
        op.fractal = fractal;
        op.stitch = stitch;
        const double tile[4] = {-20, 15, 170, 90};
        std::copy(tile, tile + 4, op.tile_user);
        for (int k = 0; k < 50; k++) {
          double p[2] = {coord(rng), coord(rng)};
          for (int ch = 0; ch < 4; ch++) {
            const double want = spec_turbulence::turbulence(ch, p, op.freq_x, op.freq_y, op.octaves, fractal != 0,
                                                            stitch != 0, tile[0], tile[1], tile[2], tile[3]);
            const double got = turbulence_sum(op, noise.data(), ch, p[0], p[1]);
            INFO("seed " << seed << " fractal " << fractal << " stitch " << stitch << " at " << p[0] << ", " << p[1]);
            REQUIRE(got == want);
          }
        }
      }
  }
}
