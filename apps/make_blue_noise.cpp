// make_blue_noise: generates the blue-noise sample patterns of
// core/sampling/blue_noise_tables.inc by capacity-constrained Voronoi tessellation
// (Balzer, Schlömer and Deussen, "Capacity-Constrained Point Distributions:
// A Variant of Lloyd's Method", SIGGRAPH 2009).
//
// A pattern is a tile of K x K unit areas holding m samples each, periodic
// on the K x K torus. With sample sharing (integration.h) a pixel's support
// covers K x K unit areas, one of each position in the tile, so every pixel
// integrates over the whole tile: K^2 m samples that are blue noise as one
// set, not K^2 copies of one m-sample pattern. Tiles exist for K = 1 to 5
// and m = 8, 32, 64.
//
// Steps:
//   1. CCVT: K^2 m sites share capacity points on the torus; for neighbouring
//      pairs of sites, points are swapped while that lowers the total squared
//      distance (capacities stay fixed), and sites move to their centroids.
//      At convergence the sites are evenly spread, without Lloyd's drift
//      towards a regular grid: a blue-noise spectrum.
//   2. Balance: every unit area must hold exactly m sites. Sites are nudged
//      across unit-area borders towards the nearest unit area with room, then
//      a Gaussian repulsion (each site kept in its unit area) spreads out the
//      pairs this pushed together.
//   3. Latinise: x and y are replaced by their ranks' stratum centres, so the
//      projections are stratified at 1/(K m) (an axis-aligned edge is
//      resolved that finely over a pixel's support); swaps of x within a
//      column of unit areas (of y within a row) that lower a Gaussian
//      repulsion energy then restore the 2D spread.
//
//   make_blue_noise > core/sampling/blue_noise_tables.inc
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

struct P {
  double x, y;
};

struct Torus {
  double size;
  double wrap(double d) const { return d - size * std::floor(d / size + 0.5); }  // to [-size/2, size/2)
  double dist2(P a, P b) const {
    const double dx = wrap(a.x - b.x), dy = wrap(a.y - b.y);
    return dx * dx + dy * dy;
  }
  double mod(double v) const { return v - size * std::floor(v / size); }
};

int cell_of(P p, int K) { return std::min(K - 1, int(p.y)) * K + std::min(K - 1, int(p.x)); }

// Plain CCVT on the K x K torus.
std::vector<P> ccvt(int K, int n, int capacity, int iterations, uint32_t seed) {
  const Torus t{double(K)};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, double(K));
  const int total = n * capacity;
  std::vector<P> pts(total);
  for (P& p : pts) p = {u(rng), u(rng)};
  std::vector<P> sites(n);
  for (P& q : sites) q = {u(rng), u(rng)};
  std::vector<int> owner(total);
  for (int i = 0; i < total; i++) owner[i] = i % n;
  std::shuffle(owner.begin(), owner.end(), rng);
  const double spacing = K / std::sqrt(double(n));
  std::vector<std::vector<int>> members(n);
  for (int iter = 0; iter < iterations; iter++) {
    for (auto& v : members) v.clear();
    for (int i = 0; i < total; i++) members[owner[i]].push_back(i);
    bool changed = false;
    for (int a = 0; a < n; a++) {
      for (int b = a + 1; b < n; b++) {
        if (t.dist2(sites[a], sites[b]) > 9.0 * spacing * spacing) continue;  // only neighbours exchange
        std::vector<std::pair<double, int>> ha, hb;
        for (int i : members[a]) ha.push_back({t.dist2(pts[i], sites[a]) - t.dist2(pts[i], sites[b]), i});
        for (int i : members[b]) hb.push_back({t.dist2(pts[i], sites[b]) - t.dist2(pts[i], sites[a]), i});
        std::sort(ha.rbegin(), ha.rend());
        std::sort(hb.rbegin(), hb.rend());
        bool swapped = false;
        for (size_t k = 0; k < ha.size() && k < hb.size() && ha[k].first + hb[k].first > 1e-15; k++) {
          owner[ha[k].second] = b;
          owner[hb[k].second] = a;
          swapped = true;
        }
        if (swapped) {
          changed = true;
          std::vector<int> na, nb;
          for (int i : members[a]) (owner[i] == a ? na : nb).push_back(i);
          for (int i : members[b]) (owner[i] == a ? na : nb).push_back(i);
          members[a].swap(na);
          members[b].swap(nb);
        }
      }
    }
    for (int q = 0; q < n; q++) {
      double sx = 0, sy = 0;
      for (int i : members[q]) {
        sx += t.wrap(pts[i].x - sites[q].x);
        sy += t.wrap(pts[i].y - sites[q].y);
      }
      const double k = static_cast<double>(members[q].size());
      sites[q] = {t.mod(sites[q].x + sx / k), t.mod(sites[q].y + sy / k)};
    }
    if (!changed) break;
  }
  return sites;
}

// Evens the unit areas out to m sites each: while a unit area is crowded,
// the nearest (in steps between unit areas) one with room is found, and one
// site per step along the way is nudged across the border it is closest to.
void balance(std::vector<P>& s, int K, int m) {
  const Torus t{double(K)};
  for (int guard = 0; guard < 1000000; guard++) {
    std::vector<int> count(K * K, 0);
    for (const P& p : s) count[cell_of(p, K)]++;
    int over = -1;
    for (int c = 0; c < K * K && over < 0; c++)
      if (count[c] > m) over = c;
    if (over < 0) return;
    // Breadth-first search for the nearest unit area with room.
    std::vector<int> prev(K * K, -1);
    std::vector<int> queue{over};
    prev[over] = over;
    int found = -1;
    for (size_t qi = 0; qi < queue.size() && found < 0; qi++) {
      const int c = queue[qi], cx = c % K, cy = c / K;
      const int nb[4] = {cy * K + (cx + 1) % K, cy * K + (cx + K - 1) % K, ((cy + 1) % K) * K + cx,
                         ((cy + K - 1) % K) * K + cx};
      for (int d : nb)
        if (prev[d] < 0) {
          prev[d] = c;
          if (count[d] < m) {
            found = d;
            break;
          }
          queue.push_back(d);
        }
    }
    // The first step from `over` towards `found`.
    int step = found;
    while (prev[step] != over) step = prev[step];
    // Nudge the site of `over` closest to the border with `step` across it.
    const int ox = over % K, oy = over / K, sx = step % K, sy = step / K;
    const int dx = (sx - ox + K + 1) % K - 1, dy = (sy - oy + K + 1) % K - 1;  // -1, 0 or 1
    int bi = -1;
    double best = 1e9;
    for (size_t i = 0; i < s.size(); i++) {
      if (cell_of(s[i], K) != over) continue;
      const double fx = s[i].x - ox, fy = s[i].y - oy;
      const double d = dx > 0 ? 1 - fx : dx < 0 ? fx : dy > 0 ? 1 - fy : fy;
      if (d < best) {
        best = d;
        bi = int(i);
      }
    }
    P& q = s[bi];
    if (dx) q.x = t.mod(dx > 0 ? ox + 1 + 1e-4 : ox - 1e-4);
    if (dy) q.y = t.mod(dy > 0 ? oy + 1 + 1e-4 : oy - 1e-4);
  }
}

// Gaussian repulsion with every site kept in its unit area: spreads out the
// pairs that balancing pushed together.
void relax(std::vector<P>& s, int K, int passes) {
  const Torus t{double(K)};
  const int n = static_cast<int>(s.size());
  const double sigma2 = 0.5 * double(K) * K * 2.0 / (std::sqrt(3.0) * n);
  const double step = 0.1 * sigma2;
  for (int pass = 0; pass < passes; pass++) {
    std::vector<P> next = s;
    for (int i = 0; i < n; i++) {
      double fx = 0, fy = 0;
      for (int j = 0; j < n; j++) {
        if (j == i) continue;
        const double dx = t.wrap(s[i].x - s[j].x), dy = t.wrap(s[i].y - s[j].y);
        const double w = std::exp(-(dx * dx + dy * dy) / sigma2);
        fx += dx * w;
        fy += dy * w;
      }
      const double cx = std::floor(s[i].x), cy = std::floor(s[i].y);
      next[i].x = std::min(cx + 1 - 1e-4, std::max(cx + 1e-4, s[i].x + step * fx / sigma2));
      next[i].y = std::min(cy + 1 - 1e-4, std::max(cy + 1e-4, s[i].y + step * fy / sigma2));
    }
    s.swap(next);
  }
}

void latinize(std::vector<P>& s, int K, int m, uint32_t seed) {
  const int n = static_cast<int>(s.size());
  const double stratum = double(K) / n;  // 1 / (K m)
  for (int axis = 0; axis < 2; axis++) {
    std::vector<int> order(n);
    for (int i = 0; i < n; i++) order[i] = i;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return axis ? s[a].y < s[b].y : s[a].x < s[b].x; });
    for (int r = 0; r < n; r++) (axis ? s[order[r]].y : s[order[r]].x) = (r + 0.5) * stratum;
  }
  const Torus t{double(K)};
  const double sigma2 = 0.5 * double(K) * K * 2.0 / (std::sqrt(3.0) * n);
  auto energy_of = [&](int i) {
    double e = 0;
    for (int j = 0; j < n; j++)
      if (j != i) e += std::exp(-t.dist2(s[i], s[j]) / sigma2);
    return e;
  };
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  const int iterations = 60 * n;
  for (int it = 0; it < iterations; it++) {
    const int a = pick(rng), b = pick(rng);
    const bool yaxis = it & 1;
    // Swapping x keeps both points in their unit areas only within a column.
    if (a == b || (yaxis ? int(s[a].y) != int(s[b].y) : int(s[a].x) != int(s[b].x))) continue;
    const double before = energy_of(a) + energy_of(b);
    std::swap(yaxis ? s[a].y : s[a].x, yaxis ? s[b].y : s[b].x);
    if (energy_of(a) + energy_of(b) >= before) std::swap(yaxis ? s[a].y : s[a].x, yaxis ? s[b].y : s[b].x);
  }
  (void)m;
}

double min_distance(const std::vector<P>& s, int K) {
  const Torus t{double(K)};
  double d = 1e9;
  for (size_t i = 0; i < s.size(); i++)
    for (size_t j = 0; j < i; j++) d = std::min(d, std::sqrt(t.dist2(s[i], s[j])));
  return d;
}

}  // namespace

int main() {
  std::printf(
      "// Blue-noise sample tiles: K x K unit areas of m samples, periodic on the\n"
      "// K x K torus, from capacity-constrained point distributions (Balzer et al.\n"
      "// 2009), balanced to m per unit area and latinised. Generated by\n"
      "// apps/make_blue_noise.cpp; do not edit. Regenerate with\n"
      "// `build/apps/make_blue_noise > core/sampling/blue_noise_tables.inc`.\n"
      "// Layout: kBlueNoise<m>x<K>[(cy * K + cx) * m + i] = offset of sample i of\n"
      "// the tile's unit area (cx, cy), relative to that unit area.\n");
  // K = 3 and 5: the odd supports of frames with aliased paths (the hat's
  // and the cubics', integration.h).
  for (int K : {1, 2, 3, 4, 5}) {
    for (int m : {8, 32, 64}) {
      const int n = K * K * m;
      std::vector<P> s = ccvt(K, n, K >= 4 ? 64 : 128, K >= 4 ? 80 : 200, 0x5eed0000u + 97u * n + K);
      const double hex = double(K) * std::sqrt(2.0 / (std::sqrt(3.0) * n));
      const double raw = min_distance(s, K) / hex;
      balance(s, K, m);
      relax(s, K, 30);
      latinize(s, K, m, 0x1a7000u + 13u * n + K);
      std::vector<std::vector<P>> cells(K * K);
      for (const P& p : s) cells[cell_of(p, K)].push_back({p.x - std::floor(p.x), p.y - std::floor(p.y)});
      for (const auto& c : cells)
        if (int(c.size()) != m) {
          std::fprintf(stderr, "unbalanced tile K=%d m=%d\n", K, m);
          return 1;
        }
      std::fprintf(stderr, "K=%d m=%2d: minimum distance %.3f of hexagonal packing, %.3f after latinising\n",
                   K, m, raw, min_distance(s, K) / hex);
      std::printf("static const float kBlueNoise%dx%d[%d][2] = {\n", m, K, n);
      for (const auto& c : cells)
        for (const P& p : c) std::printf("    {%.9ff, %.9ff},\n", p.x, p.y);
      std::printf("};\n");
    }
  }
  return 0;
}
