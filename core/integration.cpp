#include "core/integration.h"

#include <cmath>
#include <utility>

namespace mpvg {

namespace {

// splitmix64: a well-mixed 64-bit hash of (seed, index).
uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

float unit_float(uint64_t h) { return static_cast<float>(h >> 40) * (1.0f / 16777216.0f); }

}  // namespace

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
