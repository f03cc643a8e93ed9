// What the device stages share besides a Context: small results read back
// (HostWords), staged uploads (HostStaging), and scans, reductions and
// compactions through CUB (Primitives).
#pragma once
#include <cub/cub.cuh>

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <utility>
#include <vector>

#include "core/error.h"
#include "gpu/cuda_util.h"

namespace mpvg::gpu {

// Small results the host reads back. Once pinned (page-locked memory), the
// copies of several words are queued and one synchronization waits for all
// of them; before, each copy waits on its own (locking pages takes time a
// one-shot run would not earn back: the owner pins from its second frame).
class HostWords {
 public:
  static constexpr size_t kMax = 32;
  using Word = std::pair<const uint32_t*, uint32_t*>;
  HostWords() = default;
  ~HostWords() {
    if (words_) cudaFreeHost(words_);
  }
  HostWords(const HostWords&) = delete;
  HostWords& operator=(const HostWords&) = delete;
  void pin() {
    if (!words_) MPVG_CUDA(cudaMallocHost(&words_, kMax * sizeof(uint32_t)));
  }
  // *host = *device for each pair (at most kMax), in one round trip.
  void read(std::initializer_list<Word> words) { read(words.begin(), words.size()); }
  void read(const Word* w, size_t n) {
    if (n > kMax) throw Error("HostWords: more words than one read holds");
    if (!words_) {
      for (size_t k = 0; k < n; k++)
        MPVG_CUDA(cudaMemcpy(w[k].second, w[k].first, sizeof(uint32_t), cudaMemcpyDeviceToHost));
      return;
    }
    for (size_t k = 0; k < n; k++)
      MPVG_CUDA(cudaMemcpyAsync(words_ + k, w[k].first, sizeof(uint32_t), cudaMemcpyDeviceToHost));
    MPVG_CUDA(cudaStreamSynchronize(0));
    for (size_t k = 0; k < n; k++) *w[k].second = words_[k];
  }

 private:
  uint32_t* words_ = nullptr;
};

// Host memory the device copies from without waiting: page-locked, grown
// as needed and kept. begin() makes room for a set of arrays (waiting for
// copies still queued from it), put() copies one in and queues its upload;
// the caller's next round trip finds them done. Locking pages costs
// milliseconds per megabyte, which only a reused context earns back: the
// first set goes up the plain way (a copy that waits), later sets through
// the staging.
class HostStaging {
 public:
  HostStaging() = default;
  ~HostStaging() {
    if (p_) cudaFreeHost(p_);
  }
  HostStaging(const HostStaging&) = delete;
  HostStaging& operator=(const HostStaging&) = delete;

  static size_t room(size_t bytes) { return (bytes + 255) & ~size_t{255}; }
  void begin(size_t bytes) {
    used_ = 0;
    staged_ = sets_++ > 0;
    if (!staged_) return;
    MPVG_CUDA(cudaStreamSynchronize(0));
    if (bytes <= cap_) return;
    const size_t cap = std::max(bytes, cap_ + cap_ / 2);  // room for sets to vary
    if (p_) MPVG_CUDA(cudaFreeHost(p_));
    p_ = nullptr;
    cap_ = 0;
    MPVG_CUDA(cudaMallocHost(&p_, cap));
    cap_ = cap;
  }
  template <class T>
  void put(DeviceBuffer<T>& dst, const std::vector<T>& v) {
    if (!staged_) {
      dst.upload(v);
      return;
    }
    dst.resize(v.size());
    const size_t bytes = v.size() * sizeof(T);
    if (!bytes) return;
    if (used_ + room(bytes) > cap_) throw Error("staging: more bytes put than begin() made room for");
    std::memcpy(p_ + used_, v.data(), bytes);
    MPVG_CUDA(cudaMemcpyAsync(dst.data(), p_ + used_, bytes, cudaMemcpyHostToDevice));
    used_ += room(bytes);
  }

 private:
  unsigned char* p_ = nullptr;
  size_t cap_ = 0, used_ = 0, sets_ = 0;
  bool staged_ = false;
};

// An element count a kernel is launched over: exact on the host (dev
// null), or, in a frame the device drives (build_tree.cu), a bound the host
// sized the launch and the buffers to, with the exact count on the device:
// scale * *dev + plus (a level's pairs are four per entry; a scan that
// ends on a total has one item more than the count).
struct Count {
  size_t n = 0;
  const uint32_t* dev = nullptr;
  uint32_t scale = 1, plus = 0;
  __host__ __device__ size_t get() const {
#ifdef __CUDA_ARCH__
    if (dev) {
      const size_t v = size_t(*dev) * scale + plus;
      return v < n ? v : n;
    }
#endif
    return n;
  }
  Count times(uint32_t k) const { return Count{n * k, dev, scale * k, plus * k}; }
  Count and_one() const { return Count{n + 1, dev, scale, plus + 1}; }
};

// The sum, as an operator of the counted scans.
struct Plus {
  template <class T>
  __host__ __device__ T operator()(T a, T b) const {
    return a + b;
  }
};

// Scans whose length is on the device (Count): tiles of kTile items, each
// block's total, an exclusive scan of the totals by one block, then each
// tile scanned from its prefix. Blocks past the count's tiles exit at
// once, so the work is the count's, not the bound's. For the integer
// operators of the pipeline (sums, SplitScanOp, SegmentedMax, LevelCounts)
// any association gives the same bits as CUB's device scans.
namespace counted_scan {
constexpr int kThreads = 256, kItems = 8;
constexpr size_t kTile = size_t(kThreads) * kItems;

template <class T, class In>
__device__ __forceinline__ void load_tile(In in, size_t base, size_t count, T identity, T (&items)[kItems]) {
  for (int k = 0; k < kItems; k++) {
    const size_t i = base + size_t(threadIdx.x) * kItems + k;
    items[k] = i < count ? T(in[i]) : identity;
  }
}

template <class T, class In, class Op>
__global__ void __launch_bounds__(kThreads) k_tile_totals(In in, Count n, Op op, T identity, T* totals) {
  const size_t count = n.get(), base = size_t(blockIdx.x) * kTile;
  if (base >= count) return;
  T items[kItems];
  load_tile(in, base, count, identity, items);
  T acc = items[0];
  for (int k = 1; k < kItems; k++) acc = op(acc, items[k]);
  using Scan = cub::BlockScan<T, kThreads>;
  __shared__ typename Scan::TempStorage tmp;
  T ignored, total;
  Scan(tmp).InclusiveScan(acc, ignored, op, total);
  if (threadIdx.x == 0) totals[blockIdx.x] = total;
}

template <class T, class Op>
struct RunningPrefix {
  T total;
  Op op;
  __device__ T operator()(T block_total) {
    const T before = total;
    total = op(total, block_total);
    return before;
  }
};

template <class T, class Op>
__global__ void __launch_bounds__(kThreads) k_scan_totals(T* totals, Count n, Op op, T identity) {
  const size_t tiles = (n.get() + kTile - 1) / kTile;
  using Scan = cub::BlockScan<T, kThreads>;
  __shared__ typename Scan::TempStorage tmp;
  RunningPrefix<T, Op> prefix{identity, op};
  for (size_t b = 0; b < tiles; b += kThreads) {
    const size_t i = b + threadIdx.x;
    const T v = i < tiles ? totals[i] : identity;
    T out;
    Scan(tmp).ExclusiveScan(v, out, op, prefix);
    __syncthreads();
    if (i < tiles) totals[i] = out;
  }
}

template <class T>
struct FixedPrefix {
  T value;
  __device__ T operator()(T) const { return value; }
};

template <bool Inclusive, class T, class In, class Out, class Op>
__global__ void __launch_bounds__(kThreads) k_scan_tiles(In in, Out out, Count n, Op op, T identity,
                                                         const T* prefix) {
  const size_t count = n.get(), base = size_t(blockIdx.x) * kTile;
  if (base >= count) return;
  T items[kItems];
  load_tile(in, base, count, identity, items);
  using Scan = cub::BlockScan<T, kThreads>;
  __shared__ typename Scan::TempStorage tmp;
  FixedPrefix<T> p{prefix[blockIdx.x]};
  if (Inclusive) Scan(tmp).InclusiveScan(items, items, op, p);
  else Scan(tmp).ExclusiveScan(items, items, op, p);
  for (int k = 0; k < kItems; k++) {
    const size_t i = base + size_t(threadIdx.x) * kItems + k;
    if (i < count) out[i] = items[k];
  }
}

}  // namespace counted_scan

// The bits a radix sort needs for keys up to max_key (at least one).
inline int key_bits(uint64_t max_key) {
  int bits = 1;
  while (bits < 32 && (uint64_t{1} << bits) <= max_key) bits++;
  return bits;
}

// Scans, reductions and compactions through CUB, with one temporary buffer
// ("ask for the temp storage size first").
class Primitives {
 public:
  size_t calls = 0;  // CUB calls issued (each one to three kernels)

  template <class In, class Out>
  void exclusive_sum(In in, Out out, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::ExclusiveSum(temp(bytes), bytes, in, out, static_cast<int>(n)));
  }
  template <class In, class Out>
  void inclusive_sum(In in, Out out, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::InclusiveSum(nullptr, bytes, in, out, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::InclusiveSum(temp(bytes), bytes, in, out, static_cast<int>(n)));
  }
  template <class In, class Out, class Op>
  void inclusive_scan(In in, Out out, Op op, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::InclusiveScan(nullptr, bytes, in, out, op, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::InclusiveScan(temp(bytes), bytes, in, out, op, static_cast<int>(n)));
  }
  template <class In, class Out, class Op, class T>
  void exclusive_scan(In in, Out out, Op op, T init, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceScan::ExclusiveScan(nullptr, bytes, in, out, op, init, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceScan::ExclusiveScan(temp(bytes), bytes, in, out, op, init, static_cast<int>(n)));
  }
  // Stable: equal keys keep their order. Only keys' bits [0, bits) count
  // (key_bits).
  template <class K, class V>
  void sort_pairs(const K* keys_in, K* keys_out, const V* values_in, V* values_out, size_t n, int bits) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys_in, keys_out, values_in, values_out,
                                              static_cast<int>(n), 0, bits));
    MPVG_CUDA(cub::DeviceRadixSort::SortPairs(temp(bytes), bytes, keys_in, keys_out, values_in, values_out,
                                              static_cast<int>(n), 0, bits));
  }
  // Scans of n.get() items (identity: the operator's), n.n bounding them
  // (counted_scan); the same results as the device scans above.
  template <class T, bool Inclusive, class In, class Out, class Op>
  void counted(In in, Out out, Op op, T identity, Count n) {
    calls++;
    if (n.n == 0) return;
    namespace cs = counted_scan;
    const size_t tiles = (n.n + cs::kTile - 1) / cs::kTile;
    T* totals = static_cast<T*>(counted_temp(tiles * sizeof(T)));
    const unsigned grid = static_cast<unsigned>(tiles);
    cs::k_tile_totals<T><<<grid, cs::kThreads>>>(in, n, op, identity, totals);
    MPVG_LAUNCHED();
    cs::k_scan_totals<T><<<1, cs::kThreads>>>(totals, n, op, identity);
    MPVG_LAUNCHED();
    cs::k_scan_tiles<Inclusive, T><<<grid, cs::kThreads>>>(in, out, n, op, identity, totals);
    MPVG_LAUNCHED();
  }
  template <class T, class In, class Out, class Op>
  void counted_inclusive(In in, Out out, Op op, T identity, Count n) {
    counted<T, true>(in, out, op, identity, n);
  }
  template <class T, class In, class Out, class Op>
  void counted_exclusive(In in, Out out, Op op, T identity, Count n) {
    counted<T, false>(in, out, op, identity, n);
  }
  template <class In, class Out>
  void reduce_max(In in, Out out, size_t n) {
    calls++;
    size_t bytes = 0;
    MPVG_CUDA(cub::DeviceReduce::Max(nullptr, bytes, in, out, static_cast<int>(n)));
    MPVG_CUDA(cub::DeviceReduce::Max(temp(bytes), bytes, in, out, static_cast<int>(n)));
  }

 private:
  void* temp(size_t bytes) {
    temp_.resize(bytes);
    return temp_.data();
  }
  // The counted scans' tile totals: a buffer of their own, so that a CUB
  // call's temporary storage never moves under a counted scan in flight.
  void* counted_temp(size_t bytes) {
    counted_temp_.resize(std::max<size_t>(bytes, 16));
    return counted_temp_.data();
  }
  DeviceBuffer<uint8_t> temp_, counted_temp_;
};

}  // namespace mpvg::gpu
