// A rendered frame as both executors hand it over: premultiplied floats in
// the integration colour space (core/sampling/integration.h), four a
// pixel, row-major; the output encodings (srgb.h, rgba8.h, PNG) start
// from it.
#pragma once
#include <vector>

namespace mpvg {

struct ImageF {
  int width = 0, height = 0;
  std::vector<float> rgba;  // premultiplied, integration colour space, row-major
};

}  // namespace mpvg
