// Host-side CUDA helpers: checked calls, RAII device buffers, events.
// Included by .cu files only.
#pragma once
#include <cuda_runtime.h>

#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace mpvg::gpu {

inline void cuda_check(cudaError_t e, const char* what, const char* file, int line) {
  if (e != cudaSuccess)
    throw Error(std::string("CUDA error: ") + cudaGetErrorString(e) + " in " + what + " (" + file + ":" +
                std::to_string(line) + ")");
}

#define MPVG_CUDA(call) ::mpvg::gpu::cuda_check((call), #call, __FILE__, __LINE__)
#define MPVG_LAUNCHED() ::mpvg::gpu::cuda_check(cudaGetLastError(), "kernel launch", __FILE__, __LINE__)

// A device array that only grows. resize() keeps no contents when it has
// to reallocate; grow_keep() copies them. Memory comes from the device's
// stream-ordered pool on the calling thread's default stream
// (use_retaining_pool in gpu_backend.h keeps freed memory in the pool).
template <class T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  explicit DeviceBuffer(size_t n) { resize(n); }
  ~DeviceBuffer() { release(); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept { swap(o); }
  DeviceBuffer& operator=(DeviceBuffer&& o) noexcept {
    swap(o);
    return *this;
  }
  void swap(DeviceBuffer& o) noexcept {
    std::swap(p_, o.p_);
    std::swap(n_, o.n_);
    std::swap(cap_, o.cap_);
  }

  void resize(size_t n) {
    if (n > cap_) {
      const size_t cap = std::max(n, cap_ + cap_ / 2);
      release();
      // capacity only once allocated: a failed allocation (out of device
      // memory, an exception) leaves an empty buffer, not a null one that
      // claims room
      MPVG_CUDA(cudaMallocAsync(&p_, std::max<size_t>(cap, 1) * sizeof(T), cudaStreamPerThread));
      cap_ = cap;
    }
    n_ = n;
  }
  void grow_keep(size_t n) {
    if (n > cap_) {
      DeviceBuffer<T> bigger;
      bigger.resize(std::max(n, cap_ * 2));
      if (n_) MPVG_CUDA(cudaMemcpy(bigger.p_, p_, n_ * sizeof(T), cudaMemcpyDeviceToDevice));
      bigger.n_ = n_;
      swap(bigger);
    }
    n_ = n;
  }
  void upload(const std::vector<T>& v) {
    resize(v.size());
    if (!v.empty()) MPVG_CUDA(cudaMemcpy(p_, v.data(), v.size() * sizeof(T), cudaMemcpyHostToDevice));
  }
  std::vector<T> download(size_t n) const {
    std::vector<T> v(n);
    if (n) MPVG_CUDA(cudaMemcpy(v.data(), p_, n * sizeof(T), cudaMemcpyDeviceToHost));
    return v;
  }
  std::vector<T> download() const { return download(n_); }

  T* data() { return p_; }
  const T* data() const { return p_; }
  size_t size() const { return n_; }
  size_t capacity() const { return cap_; }
  size_t bytes() const { return cap_ * sizeof(T); }

 private:
  void release() {
    if (p_) cudaFreeAsync(p_, cudaStreamPerThread);
    p_ = nullptr;
    cap_ = 0;
    n_ = 0;
  }
  T* p_ = nullptr;
  size_t n_ = 0, cap_ = 0;
};

// Grid size for a one-thread-per-element launch.
inline unsigned grid_for(size_t n, unsigned block) { return static_cast<unsigned>((n + block - 1) / block); }

// Accumulates GPU time between pairs of events into named stage slots.
class StageTimer {
 public:
  explicit StageTimer(bool enabled) : enabled_(enabled) {}
  ~StageTimer() {
    for (auto& m : marks_) {
      cudaEventDestroy(m.first);
      cudaEventDestroy(m.second);
    }
  }
  // Starts timing a stage; stop() must follow before the next start().
  void start(double* slot) {
    if (!enabled_) return;
    cudaEvent_t a, b;
    MPVG_CUDA(cudaEventCreate(&a));
    MPVG_CUDA(cudaEventCreate(&b));
    MPVG_CUDA(cudaEventRecord(a));
    marks_.push_back({a, b});
    slots_.push_back(slot);
  }
  void stop() {
    if (!enabled_) return;
    MPVG_CUDA(cudaEventRecord(marks_.back().second));
  }
  // Waits for the GPU and adds every measured interval to its slot (ms).
  void collect() {
    if (!enabled_) return;
    for (size_t i = 0; i < marks_.size(); i++) {
      MPVG_CUDA(cudaEventSynchronize(marks_[i].second));
      float ms = 0;
      MPVG_CUDA(cudaEventElapsedTime(&ms, marks_[i].first, marks_[i].second));
      *slots_[i] += ms;
      cudaEventDestroy(marks_[i].first);
      cudaEventDestroy(marks_[i].second);
    }
    marks_.clear();
    slots_.clear();
  }

 private:
  bool enabled_;
  std::vector<std::pair<cudaEvent_t, cudaEvent_t>> marks_;
  std::vector<double*> slots_;
};

}  // namespace mpvg::gpu
