#include "core/sampling/integration.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"

namespace mpvg {

namespace {

#include "core/sampling/blue_noise_tables.inc"

// splitmix64: a well-mixed 64-bit hash of (seed, index).
uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

float unit_float(uint64_t h) { return static_cast<float>(h >> 40) * (1.0f / 16777216.0f); }

float frac(float v) { return v - std::floor(v); }

struct FilterName {
  Filter filter;
  const char* name;
};
constexpr FilterName kFilterNames[] = {
    {Filter::Box, "box"},           {Filter::Hat, "hat"},           {Filter::BSpline, "bspline"},
    {Filter::Cardinal, "cardinal"}, {Filter::Mitchell, "mitchell"}, {Filter::CatmullRom, "catmull-rom"},
};

}  // namespace

bool parse_filter(const std::string& name, Filter* out) {
  for (const FilterName& f : kFilterNames)
    if (name == f.name) {
      *out = f.filter;
      return true;
    }
  return false;
}

const char* filter_name(Filter f) {
  for (const FilterName& n : kFilterNames)
    if (n.filter == f) return n.name;
  return "?";
}

namespace {

// Weights, sums and per-pixel totals for given class patterns.
Integration build_integration(Filter f, int K, int m, int classes, std::vector<SampleOffset> offsets) {
  Integration in;
  in.filter = f;
  in.support = K;
  in.pad = f == Filter::Cardinal ? kCardinalPad : 0;
  in.samples = m;
  in.prefilter = f == Filter::Cardinal;
  const int T = K * K;
  in.classes = classes;
  in.class_mod = classes > 1 ? K : 1;
  in.offsets = std::move(offsets);
  // Sample i of unit area u lies at u + o_i; the accumulation pixel u - e
  // has its centre at u - e + K/2 in unit-area coordinates (integer for even
  // K, a unit area's centre for K = 1), so the sample sits at e + o_i - K/2.
  const float half = 0.5f * static_cast<float>(K);
  in.weights.resize(size_t(in.classes) * T * m);
  in.weight_sums.resize(size_t(in.classes) * T);
  for (int c = 0; c < in.classes; c++)
    for (int ey = 0; ey < K; ey++)
      for (int ex = 0; ex < K; ex++) {
        const size_t t = size_t(c) * T + size_t(ey) * K + ex;
        float sum = 0.0f;
        for (int i = 0; i < m; i++) {
          const SampleOffset o = in.offsets[size_t(c) * m + i];
          const float w = filter_kernel(f, static_cast<float>(ex) + o.x - half) *
                          filter_kernel(f, static_cast<float>(ey) + o.y - half) / static_cast<float>(m);
          in.weights[(size_t(c) * m + i) * T + size_t(ey) * K + ex] = w;
          sum += w;
        }
        in.weight_sums[t] = sum;
      }
  // Pixel (a, b) receives from unit areas (a + ex, b + ey), of class
  // ((a + ex) mod K, (b + ey) mod K): its total depends on its own class.
  in.totals.assign(size_t(in.classes), 0.0);
  for (int pc = 0; pc < in.classes; pc++) {
    const int a = pc % in.class_mod, b = pc / in.class_mod;
    for (int ey = 0; ey < K; ey++)
      for (int ex = 0; ex < K; ex++) {
        const int c = unit_area_class(uint32_t(a + ex), uint32_t(b + ey), in.class_mod);
        in.totals[pc] += in.weight_sums[size_t(c) * T + size_t(ey) * K + ex];
      }
    if (!(std::fabs(in.totals[pc]) > 1e-6)) throw Error("the sample pattern gives the filter no weight");
  }
  return in;
}

// Class patterns from one pattern: class (cx, cy) shifted by (cy, cx)/(K m)
// (with stratified projections, K m distinct rows and columns per support).
std::vector<SampleOffset> shifted_classes(const std::vector<SampleOffset>& pattern, int K) {
  const int m = static_cast<int>(pattern.size());
  std::vector<SampleOffset> out(size_t(K) * K * m);
  for (int c = 0; c < K * K; c++) {
    const float sx = float(c / K) / float(K * m), sy = float(c % K) / float(K * m);
    for (int i = 0; i < m; i++) out[size_t(c) * m + i] = {frac(pattern[i].x + sx), frac(pattern[i].y + sy)};
  }
  return out;
}

const float (*blue_noise_tile(int m, int K))[2] {
  if (K == 1) return m == 8 ? kBlueNoise8x1 : m == 32 ? kBlueNoise32x1 : m == 64 ? kBlueNoise64x1 : nullptr;
  if (K == 2) return m == 8 ? kBlueNoise8x2 : m == 32 ? kBlueNoise32x2 : m == 64 ? kBlueNoise64x2 : nullptr;
  if (K == 3) return m == 8 ? kBlueNoise8x3 : m == 32 ? kBlueNoise32x3 : m == 64 ? kBlueNoise64x3 : nullptr;
  if (K == 4) return m == 8 ? kBlueNoise8x4 : m == 32 ? kBlueNoise32x4 : m == 64 ? kBlueNoise64x4 : nullptr;
  if (K == 5) return m == 8 ? kBlueNoise8x5 : m == 32 ? kBlueNoise32x5 : m == 64 ? kBlueNoise64x5 : nullptr;
  return nullptr;
}

// The seed's transform of a tile of K x K unit areas: one of the 8
// symmetries of the square and a toroidal shift by whole unit areas. Both map
// unit areas to unit areas and keep every distance on the torus, so each
// variant is as blue as the generated tile and still has m samples per unit
// area (8 K^2 variants; seed 0 is the tile itself).
std::vector<SampleOffset> transform_tile(const std::vector<SampleOffset>& tile, int K, int m, uint32_t seed) {
  if (seed == 0) return tile;
  const uint64_t h = mix64(seed);
  const uint32_t sym = static_cast<uint32_t>(h & 7);
  const int shift = static_cast<int>((h >> 3) % static_cast<uint64_t>(K * K));
  const int tx = shift % K, ty = shift / K;
  std::vector<SampleOffset> out(tile.size());
  for (int c = 0; c < K * K; c++) {
    int cx = c % K, cy = c / K;
    bool flip_x = false, flip_y = false, swap = false;
    if (sym & 1) {
      std::swap(cx, cy);
      swap = true;
    }
    if (sym & 2) {
      cx = K - 1 - cx;
      flip_x = true;
    }
    if (sym & 4) {
      cy = K - 1 - cy;
      flip_y = true;
    }
    cx = (cx + tx) % K;
    cy = (cy + ty) % K;
    for (int i = 0; i < m; i++) {
      SampleOffset o = tile[size_t(c) * m + i];
      if (swap) std::swap(o.x, o.y);
      if (flip_x) o.x = 1.0f - o.x;
      if (flip_y) o.y = 1.0f - o.y;
      // Keep offsets in [0, 1): a flipped 0 would land on the next unit area.
      out[(size_t(cy) * K + cx) * m + i] = {std::min(o.x, 0.99999994f), std::min(o.y, 0.99999994f)};
    }
  }
  return out;
}

}  // namespace

int integration_support(Filter f, bool odd) {
  const int K = filter_support(f);
  return odd && K % 2 == 0 ? K + 1 : K;
}

Integration make_integration(Filter f, const std::vector<SampleOffset>& pattern, bool odd_support) {
  const int K = integration_support(f, odd_support);
  if (K == 1) return build_integration(f, K, static_cast<int>(pattern.size()), 1, pattern);
  return build_integration(f, K, static_cast<int>(pattern.size()), K * K, shifted_classes(pattern, K));
}

Integration make_integration(Filter f, PatternKind kind, int m, uint32_t seed, bool odd_support) {
  const int K = integration_support(f, odd_support);
  if (kind == PatternKind::Stratified) return make_integration(f, stratified_pattern(m, seed), odd_support);
  const float(*table)[2] = blue_noise_tile(m, K);
  if (!table)
    throw Error("blue-noise patterns have 8, 32 or 64 samples (use a stratified pattern for " + std::to_string(m) +
                ")");
  std::vector<SampleOffset> tile(size_t(K) * K * m);
  for (size_t i = 0; i < tile.size(); i++) tile[i] = {table[i][0], table[i][1]};
  return build_integration(f, K, m, K == 1 ? 1 : K * K, transform_tile(tile, K, m, seed));
}

IntegrationFrame integration_frame(const Integration& in, int width, int height) {
  IntegrationFrame f;
  f.width = width;
  f.height = height;
  f.acc_w = width + 2 * in.pad;
  f.acc_h = height + 2 * in.pad;
  f.ua_w = f.acc_w + in.support - 1;
  f.ua_h = f.acc_h + in.support - 1;
  // Output pixel p has its centre at p + 1/2; in unit-area coordinates that
  // is accumulation pixel a = p + pad's centre, a + K/2.
  f.to_unit_areas = in.pad + in.support / 2 - (in.support % 2 == 0 ? 0.5 : 0.0);
  return f;
}

std::vector<SampleOffset> sample_pattern(PatternKind kind, int n, uint32_t seed) {
  if (kind == PatternKind::Stratified) return stratified_pattern(n, seed);
  return make_integration(Filter::Box, kind, n, seed).offsets;
}

std::vector<SampleOffset> stratified_pattern(int n, uint32_t seed) {
  if (n < 1) n = 1;
  int ny = static_cast<int>(std::floor(std::sqrt(static_cast<double>(n))));
  while (n % ny != 0) ny--;
  const int nx = n / ny;
  // Multi-jittered sampling (Chiu, Shirley and Wang 1994): the canonical
  // arrangement puts one sample in each of the nx x ny cells and, at the same
  // time, one in each of the n columns and n rows of width 1/n (n-rooks);
  // shuffling x within grid columns and y within grid rows keeps both.
  std::vector<SampleOffset> p(static_cast<size_t>(n));
  uint64_t state = mix64(seed);
  auto next = [&state]() {
    state = mix64(state);
    return state;
  };
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      const float jx = unit_float(next()), jy = unit_float(next());
      p[size_t(j * nx + i)] = {(static_cast<float>(i) + (static_cast<float>(j) + jx) / static_cast<float>(ny)) /
                                   static_cast<float>(nx),
                               (static_cast<float>(j) + (static_cast<float>(i) + jy) / static_cast<float>(nx)) /
                                   static_cast<float>(ny)};
    }
  for (int i = 0; i < nx; i++)
    for (int j = 0; j < ny - 1; j++) {
      const int k = j + static_cast<int>(next() % static_cast<uint64_t>(ny - j));
      std::swap(p[size_t(j * nx + i)].x, p[size_t(k * nx + i)].x);
    }
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx - 1; i++) {
      const int k = i + static_cast<int>(next() % static_cast<uint64_t>(nx - i));
      std::swap(p[size_t(j * nx + i)].y, p[size_t(j * nx + k)].y);
    }
  return p;
}

}  // namespace mpvg
