// Stage "abstract" on the GPU: one thread per input segment runs
// abstraction.h, first to count its pieces, then (after an exclusive scan)
// to write them in order. The initial stream (delimiters and each path's
// SEGMENT entries) is expanded in parallel over output entries.
#include <algorithm>

#include "core/geometry/abstraction.h"
#include "gpu/context.cuh"
#include "gpu/stroke.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 128;

__global__ void k_abstract_count(const InputSegment* in, size_t n, uint32_t* count) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n) count[i] = static_cast<uint32_t>(abstract_input_segment(in[i], nullptr));
}

// Writes the pieces at their offsets; a segment whose pieces would not fit
// in the output's capacity raises the overflow flag instead.
__global__ void k_abstract_write(const InputSegment* in, size_t n, const uint32_t* offset, size_t capacity,
                                 AbstractSegment* out, uint32_t* overflow) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  if (offset[i + 1] > capacity) {
    atomicOr(overflow, 1u);
    return;
  }
  abstract_input_segment(in[i], out + offset[i]);
}

// Length of each element of the placeholder stream once expanded.
__global__ void k_stream_lengths(const Entry* placeholders, size_t m, const uint32_t* path_input,
                                 const uint32_t* seg_offset, uint32_t* len) {
  const size_t s = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (s > m) return;
  if (s == m) {
    len[s] = 0;
    return;
  }
  const Entry e = placeholders[s];
  if (entry_is_delimiter(e)) {
    len[s] = 1;
    return;
  }
  const uint32_t p = entry_path(e);
  len[s] = seg_offset[path_input[p + 1]] - seg_offset[path_input[p]];
}

// Output entry j belongs to the stream element whose range holds it, and
// to the virtual cell of the root whose range holds that element (roots
// cover the stream in order: root_stream[2r] is root r's first element).
// Driven (pieces non-null), total bounds the stream, which is pos[m] long,
// and nothing is written if the pieces or the stream outgrow their pools.
__global__ void k_stream_expand(const Entry* placeholders, size_t m, const uint32_t* pos, const uint32_t* path_input,
                                const uint32_t* seg_offset, const uint32_t* root_stream, uint32_t nroots, size_t total,
                                Entry* out, uint32_t* out_cell, const uint32_t* pieces, size_t max_pieces) {
  const size_t j = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (j >= total) return;
  if (pieces && (*pieces > max_pieces || pos[m] > total || j >= pos[m])) return;
  size_t lo = 0, hi = m;  // last s with pos[s] <= j
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    if (pos[mid] <= j) lo = mid; else hi = mid;
  }
  uint32_t rlo = 0, rhi = nroots;  // last root starting at or before element lo
  while (rhi - rlo > 1) {
    const uint32_t mid = (rlo + rhi) / 2;
    if (root_stream[2 * mid] <= lo) rlo = mid; else rhi = mid;
  }
  const Entry e = placeholders[lo];
  out_cell[j] = rlo;
  if (entry_is_delimiter(e)) {
    out[j] = e;
    return;
  }
  const uint32_t p = entry_path(e);
  out[j] = make_entry(ENTRY_SEGMENT, p, seg_offset[path_input[p]] + static_cast<uint32_t>(j - pos[lo]));
}

// The virtual cells: root r's expanded entries.
__global__ void k_root_cells(const uint32_t* pos, const uint32_t* root_stream, uint32_t nroots, Cell* cells) {
  const uint32_t r = blockIdx.x * blockDim.x + threadIdx.x;
  if (r >= nroots) return;
  cells[r] = Cell{pos[root_stream[2 * r]], pos[root_stream[2 * r + 1]], 0, 0, 0, static_cast<uint16_t>(r)};
}

// Driven: level 0's counts and the segments' (none if they outgrew their
// pools).
__global__ void k_stream_size(const uint32_t* pieces, size_t max_pieces, const uint32_t* total, size_t max_total,
                              uint32_t nroots, uint32_t* size, uint32_t* drive) {
  const bool over = *pieces > max_pieces || *total > max_total;
  if (over) drive[DRIVE_OVERFLOW] = 1;
  drive[DRIVE_SEGMENTS] = over ? 0u : *pieces;
  drive[DRIVE_MOST_ENTRIES] = max(drive[DRIVE_MOST_ENTRIES], *total);
  drive[DRIVE_MOST_CELLS] = max(drive[DRIVE_MOST_CELLS], nroots);
  size[0] = over ? 0u : *total;
  size[1] = over ? 0u : nroots;
}

}  // namespace

// Stage "stroke": the fills' segments uploaded, the strokes' built after
// them on the device, then every path's segments grouped and the first of
// each path found, on the device too.
void Context::Impl::stroke(const EncodedScene& scene) {
  staging.begin(HostStaging::room(scene.segments.size() * sizeof(InputSegment)));
  staging.put(input, scene.segments);
  ninput = scene.segments.size();
  if (!stroke_stage) stroke_stage = std::make_unique<StrokeStage>();
  ninput += stroke_stage->run(scene.strokes, input, ninput, prim, host_words);
  group_by_path(input, ninput, scene.paths.size(), path_input, prim);
}

void Context::Impl::abstract_upload(const EncodedScene& scene) {
  paths.upload(scene.paths);
  placeholders.upload(scene.stream);
  npaths = scene.paths.size();
  scene_depth = 0;
  int32_t d = 0;
  for (const Entry& e : scene.stream) {
    if (entry_opens(e)) scene_depth = std::max(scene_depth, ++d);
    if (entry_closes(e)) d--;
  }
  if (scene.strokes.empty()) {
    ninput = scene.segments.size();
    // First input segment of each path; segments come grouped by path.
    std::vector<uint32_t> first(npaths + 1, 0);
    for (const InputSegment& s : scene.segments) first[s.path + 1]++;
    for (size_t p = 0; p < npaths; p++) first[p + 1] += first[p];
    staging.begin(HostStaging::room(scene.segments.size() * sizeof(InputSegment)) +
                  HostStaging::room(first.size() * sizeof(uint32_t)));
    staging.put(input, scene.segments);
    staging.put(path_input, first);
  }
}

void Context::Impl::abstract(const EncodedScene& scene) {
  abstract_upload(scene);
  const size_t n = ninput;

  uint32_t* count = (u32[0].resize(n + 1), u32[0].data());
  uint32_t* offset = (u32[1].resize(n + 1), u32[1].data());
  MPVG_CUDA(cudaMemset(count + n, 0, sizeof(uint32_t)));
  if (n) {
    k_abstract_count<<<grid_for(n, kBlock), kBlock>>>(input.data(), n, count);
    launched();
  }
  prim.exclusive_sum(count, offset, n + 1);
  // Pieces go into the capacity the segment buffer has (at least four per
  // input segment); the stream's length is scanned meanwhile, and one round
  // trip reads both totals and the overflow flag.
  overflow.resize(1);
  MPVG_CUDA(cudaMemsetAsync(overflow.data(), 0, sizeof(uint32_t)));
  segments.resize(std::max(segments.capacity(), 4 * n + 64));
  auto write = [&]() {
    if (!n) return;
    k_abstract_write<<<grid_for(n, kBlock), kBlock>>>(input.data(), n, offset, segments.size(), segments.data(),
                                                      overflow.data());
    launched();
  };
  write();
  const size_t m = scene.stream.size();
  uint32_t* len = (u32[2].resize(m + 1), u32[2].data());
  uint32_t* pos = (u32[3].resize(m + 1), u32[3].data());
  k_stream_lengths<<<grid_for(m + 1, kBlock), kBlock>>>(placeholders.data(), m, path_input.data(), offset, len);
  launched();
  prim.exclusive_sum(len, pos, m + 1);
  uint32_t pieces = 0, total = 0, failed = 0;
  read_words({{offset + n, &pieces}, {pos + m, &total}, {overflow.data(), &failed}});
  if (failed) {
    segments.resize(pieces);
    MPVG_CUDA(cudaMemsetAsync(overflow.data(), 0, sizeof(uint32_t)));
    write();
    read_words({{overflow.data(), &failed}});
    if (failed) throw Error("abstraction overflowed its grown buffer");
  }
  nsegments = pieces;
  segments.resize(pieces);
  most_entries = std::max(most_entries, size_t(total));
  most_cells = std::max(most_cells, roots.size());

  // The initial stream, as one virtual cell per root.
  const uint32_t nroots = static_cast<uint32_t>(roots.size());
  level.entries.resize(total);
  level.entry_cell.resize(total);
  level.nentries = total;
  level.driven = false;
  if (total) {
    k_stream_expand<<<grid_for(total, kBlock), kBlock>>>(placeholders.data(), m, pos, path_input.data(), offset,
                                                         root_stream.data(), nroots, total, level.entries.data(),
                                                         level.entry_cell.data(), nullptr, 0);
    launched();
  }
  level.cells.resize(nroots);
  level.ncells = nroots;
  k_root_cells<<<grid_for(nroots, kBlock), kBlock>>>(pos, root_stream.data(), nroots, level.cells.data());
  launched();
}

// Driven: the same kernels into pools of max_segments pieces and a level 0
// of max_entries; the counts stay on the device.
void Context::Impl::abstract_driven(const EncodedScene& scene, size_t max_segments, size_t max_entries) {
  abstract_upload(scene);
  const size_t n = ninput;
  uint32_t* count = (u32[0].resize(n + 1), u32[0].data());
  uint32_t* offset = (u32[1].resize(n + 1), u32[1].data());
  MPVG_CUDA(cudaMemsetAsync(count + n, 0, sizeof(uint32_t)));
  if (n) {
    k_abstract_count<<<grid_for(n, kBlock), kBlock>>>(input.data(), n, count);
    launched();
  }
  prim.exclusive_sum(count, offset, n + 1);
  segments.resize(max_segments);
  nsegments = max_segments;  // a bound until settle()
  if (n) {
    k_abstract_write<<<grid_for(n, kBlock), kBlock>>>(input.data(), n, offset, max_segments, segments.data(),
                                                      drive.data() + DRIVE_OVERFLOW);
    launched();
  }
  const size_t m = scene.stream.size();
  uint32_t* len = (u32[2].resize(m + 1), u32[2].data());
  uint32_t* pos = (u32[3].resize(m + 1), u32[3].data());
  k_stream_lengths<<<grid_for(m + 1, kBlock), kBlock>>>(placeholders.data(), m, path_input.data(), offset, len);
  launched();
  prim.exclusive_sum(len, pos, m + 1);
  const uint32_t nroots = static_cast<uint32_t>(roots.size());
  level.entries.resize(max_entries);
  level.entry_cell.resize(max_entries);
  level.nentries = max_entries;
  level.size.resize(2);
  level.driven = true;
  level.bound = false;
  if (max_entries) {
    k_stream_expand<<<grid_for(max_entries, kBlock), kBlock>>>(
        placeholders.data(), m, pos, path_input.data(), offset, root_stream.data(), nroots, max_entries,
        level.entries.data(), level.entry_cell.data(), offset + n, max_segments);
    launched();
  }
  level.cells.resize(nroots);
  level.ncells = nroots;
  k_root_cells<<<grid_for(nroots, kBlock), kBlock>>>(pos, root_stream.data(), nroots, level.cells.data());
  launched();
  k_stream_size<<<1, 1>>>(offset + n, max_segments, pos + m, max_entries, nroots, level.size.data(), drive.data());
  launched();
}

}  // namespace mpvg::gpu
