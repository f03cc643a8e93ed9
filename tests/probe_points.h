// Points at which a scene is compared with the reference compositor
// (tests/reference_compositor.h), with the inside tests it needs: random
// points away from every curve (within 1e-3 a point's side is not decided
// in double, let alone in float), each with its brute-force winding
// numbers. Used by test_groups and test_inks.
#pragma once
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "frame/encoding.h"
#include "core/scene.h"
#include "tests/oracle.h"
#include "tests/reference_compositor.h"

namespace mpvg::probe_points {

// Inside tests from brute-force winding numbers at a set of points.
struct BruteInside : reference::Inside {
  std::vector<std::vector<int>> windings;  // per point, per path
  std::map<uint32_t, uint32_t> path_of;    // geometry -> path id
  bool operator()(size_t point, uint32_t geometry, FillRule rule) const override {
    const int w = windings[point][path_of.at(geometry)];
    return rule == FillRule::EvenOdd ? (w & 1) != 0 : w != 0;
  }
};

struct Probe {
  std::vector<std::pair<float, float>> points;
  BruteInside inside;
};

// Up to `count` random points in [0, size)^2 of `scene` (encoded as `enc`).
inline Probe probe(const Scene& scene, const EncodedScene& enc, uint32_t seed, int count, int size) {
  const oracle::Windings brute(enc.segments, scene.paths.size());
  Probe p;
  for (uint32_t id = 0; id < scene.paths.size(); id++) p.inside.path_of[scene.paths[id].geometry] = id;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(0.0f, float(size));
  for (int n = 0; n < count; n++) {
    const float px = coord(rng), py = coord(rng);
    auto w = brute.at(px, py, 1e-3);
    if (!w) continue;
    p.points.push_back({px, py});
    p.inside.windings.push_back(std::move(*w));
  }
  return p;
}

}  // namespace mpvg::probe_points
