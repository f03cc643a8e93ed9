// Integration (paper §5.1), first form: a box filter over each pixel's unit
// area with a fixed per-unit-area sample pattern. Samples of a unit area are
// evaluated once and their weighted sum goes to the pixel; wide filters with
// sample sharing and blue-noise patterns belong to the antialiasing issue.
#pragma once
#include <cstdint>
#include <vector>

#include "core/hd.h"

namespace mpvg {

struct SampleOffset {
  float x, y;  // in [0, 1)^2, relative to the unit area's corner
};

// Stratified pattern of n samples over the unit square, the same for every
// unit area: multi-jittered, so that the samples are stratified both over a
// grid as square as n allows and over n rows and n columns (a horizontal or
// vertical edge is resolved to 1/n). Deterministic for a given seed.
std::vector<SampleOffset> stratified_pattern(int n, uint32_t seed);

// Box filter weight of a sample of the pixel's own unit area: 1/n each.
MPVG_HD_INLINE float box_weight(int n) { return 1.0f / static_cast<float>(n); }

}  // namespace mpvg
