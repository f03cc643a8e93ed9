// Scan operators shared by the stages and both executors (std::inclusive_scan
// on the CPU, cub::DeviceScan on the GPU).
#pragma once
#include <cstdint>

#include "core/hd.h"

namespace mpvg {

// Segmented sum: a value and a flag marking the first element of a segment.
// The operator is associative, so a plain inclusive scan with it restarts
// the running sum at every head (Blelloch's segmented scan).
template <class T>
struct Segmented {
  T value;
  uint32_t head;
};

template <class T>
struct SegmentedSum {
  MPVG_HD_INLINE Segmented<T> operator()(Segmented<T> a, Segmented<T> b) const {
    return Segmented<T>{b.head ? b.value : a.value + b.value, a.head | b.head};
  }
};

// The largest value since the segment's head.
template <class T>
struct SegmentedMax {
  MPVG_HD_INLINE Segmented<T> operator()(Segmented<T> a, Segmented<T> b) const {
    return Segmented<T>{b.head ? b.value : (a.value > b.value ? a.value : b.value), a.head | b.head};
  }
};

}  // namespace mpvg
