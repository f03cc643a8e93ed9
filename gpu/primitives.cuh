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
  DeviceBuffer<uint8_t> temp_;
};

}  // namespace mpvg::gpu
