// A minimal parallel loop for the CPU executor and the frontends: f(i) for
// every i in [0, n) on a few threads that take indices one at a time, so
// uneven items balance themselves. Deterministic as long as f(i) writes
// only what belongs to item i.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace mpvg {

// The machine's hardware threads, at least one.
inline int hardware_threads() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

// threads <= 0: one per hardware thread. An exception thrown by f stops the
// remaining items and is rethrown here once every thread has finished.
template <class F>
void parallel_for(size_t n, int threads, F&& f) {
  int nt = threads > 0 ? threads : hardware_threads();
  nt = std::max(1, std::min<int>(nt, static_cast<int>(std::min<size_t>(n, 1 << 20))));
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&]() {
    try {
      for (size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < n;) f(i);
    } catch (...) {
      next.store(n, std::memory_order_relaxed);
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < nt; i++) pool.emplace_back(worker);
  worker();
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace mpvg
