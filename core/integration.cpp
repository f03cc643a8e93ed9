#include "core/integration.h"

#include <cmath>

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
  std::vector<SampleOffset> out;
  out.reserve(n);
  for (int j = 0; j < ny; j++) {
    for (int i = 0; i < nx; i++) {
      const uint64_t h = mix64((static_cast<uint64_t>(seed) << 32) ^ static_cast<uint64_t>(j * nx + i));
      const float jx = unit_float(h), jy = unit_float(mix64(h));
      out.push_back({(static_cast<float>(i) + jx) / static_cast<float>(nx),
                     (static_cast<float>(j) + jy) / static_cast<float>(ny)});
    }
  }
  return out;
}

}  // namespace mpvg
