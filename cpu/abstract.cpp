// Stage "abstract" on the CPU: abstraction.h per input segment.
#include <algorithm>
#include <numeric>

#include "core/geometry/abstraction.h"
#include "core/parallel.h"
#include "cpu/cpu_stages.h"

namespace mpvg {

std::vector<AbstractSegment> abstract_cpu(const std::vector<InputSegment>& input) {
  // Count, scan, write: the shape of the GPU version, and no reallocation;
  // the two passes on every core, in chunks (each segment writes its own
  // count, then its own pieces: the same array whatever the threads).
  constexpr size_t kChunk = 512;
  const size_t n = input.size(), chunks = (n + kChunk - 1) / kChunk;
  const int threads = n < 2 * kChunk ? 1 : hardware_threads();
  std::vector<uint32_t> offset(n + 1, 0);
  parallel_for(chunks, threads, [&](size_t c) {
    for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); i++)
      offset[i + 1] = static_cast<uint32_t>(abstract_input_segment(input[i], nullptr));
  });
  std::inclusive_scan(offset.begin(), offset.end(), offset.begin());
  std::vector<AbstractSegment> out(offset.back());
  parallel_for(chunks, threads, [&](size_t c) {
    for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); i++)
      abstract_input_segment(input[i], out.data() + offset[i]);
  });
  return out;
}

std::vector<Entry> initial_stream(const EncodedScene& scene, const std::vector<AbstractSegment>& segments,
                                  std::vector<uint32_t>* at) {
  // Abstract segments come out grouped by path, in stream order.
  std::vector<uint32_t> first(scene.paths.size() + 1, 0);
  for (const AbstractSegment& s : segments) first[s.path + 1]++;
  std::inclusive_scan(first.begin(), first.end(), first.begin());
  std::vector<Entry> out;
  out.reserve(segments.size() + scene.stream.size());
  if (at) at->clear();
  for (const Entry& e : scene.stream) {
    if (at) at->push_back(static_cast<uint32_t>(out.size()));
    if (entry_is_delimiter(e)) {
      out.push_back(e);
      continue;
    }
    const uint32_t p = entry_path(e);
    for (uint32_t k = first[p]; k < first[p + 1]; k++) out.push_back(make_entry(ENTRY_SEGMENT, p, k));
  }
  if (at) at->push_back(static_cast<uint32_t>(out.size()));
  return out;
}

}  // namespace mpvg
