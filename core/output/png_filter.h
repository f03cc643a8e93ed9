// PNG row filtering (PNG specification, sections 9.2 and 12.8), written
// once for both executors: each row of raw samples becomes a filter-type
// byte and the row's bytes filtered by Up (type 2: minus the byte above) or
// Sub (type 1: minus the byte one pixel to the left), whichever leaves the
// smaller sum of bytes taken as signed values, the specification's
// heuristic. Up wins ties and is what a row equal to the one above (all
// zeros) gets. None, Average and Paeth are not tried: on rendered images
// they make files no smaller (within 1 %) and Paeth alone costs a third of
// the encoding time (BENCHMARKS.md, "PNG encoder").
//
// Raw samples: `channels` (3: RGB, 4: RGBA) of every pixel of an image
// stored as RGBA, `Sample` uint8_t or uint16_t (written big-endian, two
// bytes per sample).
//
//   filtered image: height rows of  [type][width * channels * sizeof(Sample) bytes]
#pragma once
#include <cstddef>
#include <cstdint>

#include "core/hd.h"

namespace mpvg::png {

constexpr uint8_t kFilterSub = 1;
constexpr uint8_t kFilterUp = 2;

struct FilterLayout {
  int width = 0, height = 0;
  int channels = 4;  // of the 4 stored per pixel, the first `channels`
  int sample_bytes = 1;

  MPVG_HD_INLINE int bpp() const { return channels * sample_bytes; }
  MPVG_HD_INLINE size_t row_bytes() const { return size_t(width) * bpp(); }
  MPVG_HD_INLINE size_t stride() const { return row_bytes() + 1; }  // the type byte and the row
  MPVG_HD_INLINE size_t size() const { return stride() * size_t(height); }
};

// Byte k (0 <= k < bpp) of pixel x in row y, as the PNG stream holds it.
template <class Sample>
MPVG_HD_INLINE uint8_t raw_byte(const Sample* rgba, const FilterLayout& l, int y, int x, int k) {
  const Sample s = rgba[(size_t(y) * l.width + x) * 4 + k / int(sizeof(Sample))];
  if constexpr (sizeof(Sample) == 1) return static_cast<uint8_t>(s);
  else return static_cast<uint8_t>(k & 1 ? s & 0xff : s >> 8);
}

// |v| for v taken as a signed byte.
MPVG_HD_INLINE uint32_t signed_cost(uint8_t v) { return v < 128 ? v : 256u - v; }

// A byte filtered by `type`, given the byte one pixel to its left and the
// one above (0 outside the image).
MPVG_HD_INLINE uint8_t filter_byte(uint8_t type, uint8_t b, uint8_t left, uint8_t above) {
  return static_cast<uint8_t>(b - (type == kFilterUp ? above : left));
}

// The row's filter from its sums of signed_cost over all bytes.
MPVG_HD_INLINE uint8_t choose_filter(uint64_t up_sum, uint64_t sub_sum) {
  return up_sum <= sub_sum ? kFilterUp : kFilterSub;
}

// Pixel x of row y: its contribution to the row's Up and Sub sums, and
// its filtered bytes (after the row's type byte) once the type is chosen.
template <class Sample>
MPVG_HD_INLINE void filter_costs(const Sample* rgba, const FilterLayout& l, int y, int x, uint32_t& up, uint32_t& sub) {
  up = sub = 0;
  for (int k = 0; k < l.bpp(); k++) {
    const uint8_t b = raw_byte(rgba, l, y, x, k);
    up += signed_cost(filter_byte(kFilterUp, b, 0, y > 0 ? raw_byte(rgba, l, y - 1, x, k) : 0));
    sub += signed_cost(filter_byte(kFilterSub, b, x > 0 ? raw_byte(rgba, l, y, x - 1, k) : 0, 0));
  }
}

template <class Sample>
MPVG_HD_INLINE void filter_pixel(const Sample* rgba, const FilterLayout& l, int y, int x, uint8_t type, uint8_t* row) {
  uint8_t* out = row + size_t(x) * l.bpp();
  for (int k = 0; k < l.bpp(); k++)
    out[k] = filter_byte(type, raw_byte(rgba, l, y, x, k), x > 0 ? raw_byte(rgba, l, y, x - 1, k) : 0,
                         y > 0 ? raw_byte(rgba, l, y - 1, x, k) : 0);
}

// Is every pixel's alpha the largest value (the image is written as RGB)?
template <class Sample>
MPVG_HD_INLINE bool opaque_pixel(const Sample* rgba, size_t i) {
  return rgba[4 * i + 3] == static_cast<Sample>(~Sample(0));
}

}  // namespace mpvg::png
