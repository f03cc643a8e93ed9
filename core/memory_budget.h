// The memory budget of a render (svg2png and pdf2png --max-memory): what
// the front ends and the renderer may hold for one document or page. The
// budget is charged where memory grows with the input rather than the
// output: decoded images (parsers: decoded at the size they are drawn,
// refused past their share), the shortcut tree (TreeParams::max_entries:
// coarser cells instead of more levels), and the frame's buffers (refused
// up front: "needs N GiB, the budget is M GiB").
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace mpvg {

// "1 GiB", "1.5 GiB", "300 MiB", "12 KiB", "100 bytes".
inline std::string byte_size(uint64_t n) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double v = double(n);
  int u = 0;
  while (v >= 1024 && u < 4) v /= 1024, u++;
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

}  // namespace mpvg
