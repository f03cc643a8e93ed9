// The memory budget of a render (svg2png and pdf2png --max-memory): what
// the front ends and the renderer may hold for one document or page.
//
// One MemoryBudget per render is charged by every stage whose memory grows
// with the input rather than the output, before it allocates: the scene's
// geometry and instances (SceneBuilder, the SVG converter's shapes, markers
// and text runs among them), its encoding, the stroke stage's and the
// abstraction's segments, mesh shadings' grids, filter graphs and their
// layers, decoded images and the frame's buffers. A charge that does not
// fit throws MemoryLimitError (a ResourceError) with one line, "WHAT needs N, the budget is M"
// (--max-memory), before the memory is taken; nothing is charged then.
//
// Within it, two consumers adapt instead of failing, from fixed shares of
// the limit (memory_shares) so that both executors make the same choices
// whatever else was charged: decoded images (decoded at the size they are
// drawn at, refused with a warning past their share) and the shortcut tree
// (TreeParams::max_entries: coarser cells instead of more levels). The
// frame's buffers are checked up front against their share ("the output
// of WxH pixels needs N, the budget is M").
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "core/error.h"

namespace mpvg {

// The input limit when none is given (svg2png and pdf2png --max-input, the
// library's readers): a stream such as /dev/zero is read up to it.
constexpr uint64_t kDefaultMaxInput = uint64_t(1) << 30;

// What a program's budget sets aside for the program itself (its code,
// libraries, fonts, a document's text and tree), uncounted elsewhere.
constexpr uint64_t kProgramBytes = uint64_t(64) << 20;

// "1 GiB", "1.5 GiB", "300 MiB", "12 KiB", "100 bytes".
inline std::string byte_size(uint64_t n) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double v = double(n);
  int u = 0;
  while (v >= 1024 && u < 6) v /= 1024, u++;
  char buf[32];
  if (u == 0) std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(n));
  else if (v == double(uint64_t(v))) std::snprintf(buf, sizeof buf, "%.0f %s", v, units[u]);
  else std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
  return buf;
}

// The shares of a budget of `bytes`.
struct MemoryShares {
  uint64_t images;  // decoded raster images of one document (RGBA8 and their mip chains)
  uint64_t tree;    // the shortcut tree's entries, all levels
  uint64_t frame;   // the output's buffers
};

inline MemoryShares memory_shares(uint64_t bytes) { return {bytes / 4, bytes / 4, bytes / 2}; }

// What a frame of width x height pixels holds while it is rendered and
// written: the float image (16 bytes a pixel), its 8- or 16-bit copy, and
// the PNG's filtered rows and compressed stream (about as much again).
inline uint64_t frame_bytes(int width, int height, int bits) {
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  return pixels * (16 + 2 * 4 * uint64_t(bits / 8));
}

// a * b, saturated at UINT64_MAX (sizes computed from a document's counts).
inline uint64_t mul_sat(uint64_t a, uint64_t b) { return b != 0 && a > UINT64_MAX / b ? UINT64_MAX : a * b; }
inline uint64_t add_sat(uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }

// The one budget of a render. Thread-safe: stages charge from any thread.
class MemoryBudget {
 public:
  explicit MemoryBudget(uint64_t limit) : limit_(limit) {}
  MemoryBudget(const MemoryBudget&) = delete;
  MemoryBudget& operator=(const MemoryBudget&) = delete;

  uint64_t limit() const { return limit_; }
  uint64_t used() const { return used_.load(std::memory_order_relaxed); }
  uint64_t available() const {
    const uint64_t u = used();
    return u >= limit_ ? 0 : limit_ - u;
  }

  // Takes `bytes` out of the budget, or returns false (nothing taken).
  bool try_charge(uint64_t bytes) {
    uint64_t u = used_.load(std::memory_order_relaxed);
    do {
      if (bytes > limit_ || u > limit_ - bytes) return false;
    } while (!used_.compare_exchange_weak(u, u + bytes, std::memory_order_relaxed));
    return true;
  }
  // Takes `bytes` for `what` ("a mesh shading's grid", "the strokes'
  // segments"), or throws MemoryLimitError: "the render needs 1.2 GiB or
  // more (WHAT: 900 MiB more), the budget is 1 GiB (--max-memory)".
  void charge(uint64_t bytes, const std::string& what) {
    if (try_charge(bytes)) return;
    const uint64_t need = add_sat(used(), bytes);
    // (Just past the limit, as charges that grow step by step end: "more".)
    const std::string needs = need / 101 * 100 < limit_ ? "more than " + byte_size(limit_)
                                                          : byte_size(need) + " or more";
    throw MemoryLimitError("the render needs " + needs + " (" + what + ": " + byte_size(bytes) + " more), the budget is " +
                        byte_size(limit_) + " (--max-memory)");
  }
  void release(uint64_t bytes) {
    uint64_t u = used_.load(std::memory_order_relaxed);
    while (!used_.compare_exchange_weak(u, u >= bytes ? u - bytes : 0, std::memory_order_relaxed)) {
    }
  }

 private:
  const uint64_t limit_;
  std::atomic<uint64_t> used_{0};
};

// Charges to an optional budget (null: nothing is counted).
inline void charge(MemoryBudget* b, uint64_t bytes, const std::string& what) {
  if (b) b->charge(bytes, what);
}

// A charge given back when it goes out of scope: memory a stage holds only
// while it runs (a filter graph's results, a stage's scratch lists).
class BudgetCharge {
 public:
  BudgetCharge() = default;
  BudgetCharge(MemoryBudget* b, uint64_t bytes, const std::string& what) : budget_(b) { add(bytes, what); }
  BudgetCharge(const BudgetCharge&) = delete;
  BudgetCharge& operator=(const BudgetCharge&) = delete;
  BudgetCharge(BudgetCharge&& o) noexcept : budget_(o.budget_), bytes_(o.bytes_) { o.bytes_ = 0; }
  BudgetCharge& operator=(BudgetCharge&& o) noexcept {
    if (this != &o) {
      reset();
      budget_ = o.budget_;
      bytes_ = o.bytes_;
      o.bytes_ = 0;
    }
    return *this;
  }
  explicit BudgetCharge(MemoryBudget* b) : budget_(b) {}
  ~BudgetCharge() { reset(); }
  void add(uint64_t bytes, const std::string& what) {
    if (!budget_) return;
    budget_->charge(bytes, what);
    bytes_ += bytes;
  }
  void reset() {
    if (budget_ && bytes_) budget_->release(bytes_);
    bytes_ = 0;
  }
  // Takes over `bytes` charged already (by a callee that hands them on).
  void adopt(uint64_t bytes) { bytes_ += budget_ ? bytes : 0; }
  // Keeps the charge for good (the memory outlives the stage).
  void keep() { bytes_ = 0; }
  uint64_t bytes() const { return bytes_; }

 private:
  MemoryBudget* budget_ = nullptr;
  uint64_t bytes_ = 0;
};

}  // namespace mpvg
