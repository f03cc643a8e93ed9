// The GPU executor of the PNG stage's filtering and compression
// (core/output/png_encode.h): the 8-bit image never leaves the device; its rows
// are filtered (core/output/png_filter.h, a warp per row) and deflated
// (core/output/deflate.h: a warp per piece parses, a thread per chunk builds its
// codes, a block per chunk writes its bits, a block per chunk copies them
// into one zlib stream), and only the stream is copied back. The same
// bytes as the CPU executor gives.
#include "core/output/deflate.h"
#include "core/output/png_filter.h"
#include "gpu/png_encode.cuh"
#include "gpu/png_encode.h"

namespace mpvg::gpu {

namespace {

using namespace deflate;

constexpr unsigned kWarp = 32;

__global__ void k_png_translucent(const uint32_t* rgba, size_t n, uint32_t* translucent) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i < n && (rgba[i] >> 24) != 0xff) *translucent = 1;
}

// The layout the translucency flag gives: RGB or RGBA rows. The kernels
// after the flag read it on the device (their grids cover RGBA's sizes),
// so that the host does not wait for it.
__device__ png::FilterLayout layout_of(int width, int height, const uint32_t* translucent) {
  png::FilterLayout l;
  l.width = width;
  l.height = height;
  l.channels = *translucent ? 4 : 3;
  return l;
}

// A warp per row: the Up and Sub sums, the choice, the filtered bytes.
__global__ void k_png_filter(const uint8_t* rgba, int width, int height, const uint32_t* translucent, uint8_t* out) {
  const int y = static_cast<int>((blockIdx.x * size_t(blockDim.x) + threadIdx.x) / kWarp);
  const int lane = threadIdx.x % kWarp;
  if (y >= height) return;
  const png::FilterLayout l = layout_of(width, height, translucent);
  unsigned long long up = 0, sub = 0;
  for (int x = lane; x < l.width; x += kWarp) {
    uint32_t u, s;
    png::filter_costs(rgba, l, y, x, u, s);
    up += u;
    sub += s;
  }
  for (int o = kWarp / 2; o > 0; o /= 2) {
    up += __shfl_xor_sync(0xffffffffu, up, o);
    sub += __shfl_xor_sync(0xffffffffu, sub, o);
  }
  const uint8_t type = png::choose_filter(up, sub);
  uint8_t* row = out + size_t(y) * l.stride();
  if (lane == 0) row[0] = type;
  for (int x = lane; x < l.width; x += kWarp) png::filter_pixel(rgba, l, y, x, type, row + 1);
}

// The warp's positions q0 + lane enter the table, the last of equal hashes
// writing (the order of one thread); returns each lane's previous
// position of its hash as a distance (0: none). `enter`: the lane's
// position takes part.
__device__ uint32_t enter_group(const uint8_t* data, size_t q0, bool enter, size_t base, uint16_t* table) {
  const int lane = threadIdx.x % kWarp;
  const size_t q = q0 + lane;
  const uint32_t h = enter ? hash4(data + q) : (1u << kHashBits) + lane;  // lanes left out match no one
  const unsigned same = __match_any_sync(0xffffffffu, h);
  const unsigned below = same & ((1u << lane) - 1);
  uint32_t d = 0;
  if (enter) {
    if (below) d = static_cast<uint32_t>(lane - (31 - __clz(below)));
    else if (table[h] != kNoPosition) d = static_cast<uint32_t>(q - base - table[h]);
  }
  __syncwarp();
  if (enter && lane == 31 - __clz(same)) table[h] = static_cast<uint16_t>(q - base);
  __syncwarp();
  return d;
}

// The run of equal bytes data[p..] == data[p - d..] for every lane's p in
// the group [g, g + 32) of the piece [.., end), from equality ballots: a
// lane's run is its ones upward, and where it reaches the group's end the
// following groups' leading ones (shared by every such lane), up to a
// match's most.
__device__ uint32_t group_run(const uint8_t* data, size_t g, size_t end, uint32_t d) {
  const int lane = threadIdx.x % kWarp;
  auto equal = [&](size_t p) { return p < end && p >= d && data[p] == data[p - d]; };
  const unsigned bal = __ballot_sync(0xffffffffu, equal(g + lane));
  const unsigned mine = bal >> lane;  // zeros above the group: not equal
  uint32_t run = ~mine == 0 ? 32 : __ffs(~mine) - 1;
  if (bal >> 31) {  // some run reaches the group's end: its continuation
    uint32_t more = 0;
    for (size_t h = g + kWarp; more < kMaxMatch && h < end; h += kWarp) {
      const unsigned b = __ballot_sync(0xffffffffu, equal(h + lane));
      const uint32_t ones = ~b == 0 ? 32 : __ffs(~b) - 1;
      more += ones;
      if (ones < kWarp) break;
    }
    if (run == kWarp - lane) run += more;
  }
  return run;
}

constexpr int kParseWarps = 2;  // per block: two hash tables of 16 KiB

// A warp per piece: the table seeded, then group by group of 32 positions
// every position's previous occurrence (enter_group) and, where the parse
// has a token starting in the group, every position's best key (fixed
// candidates by group_run, the hash candidate by hash_key); the parse
// walks the group's keys. Then the tokens' symbols are counted into the
// chunk's frequencies, and the piece's Adler-32 part is summed. The same
// tokens as parse_piece.
__global__ void __launch_bounds__(kParseWarps * kWarp)
    k_deflate_parse(const uint8_t* data, int width, int height, const uint32_t* translucent, uint32_t* tokens,
                    uint32_t* counts, Frequencies* freq, AdlerPart* adler) {
  __shared__ uint16_t tables[kParseWarps][1 << kHashBits];
  const png::FilterLayout l = layout_of(width, height, translucent);
  const size_t n = l.size();
  const size_t piece = (blockIdx.x * size_t(blockDim.x) + threadIdx.x) / kWarp;
  const int lane = threadIdx.x % kWarp;
  if (piece >= piece_count(n)) return;
  const Candidates c = png_candidates(static_cast<uint32_t>(l.bpp()), static_cast<uint32_t>(l.stride()));
  uint16_t* table = tables[threadIdx.x / kWarp];
  const size_t begin = piece * kPiece, end = begin + kPiece < n ? begin + kPiece : n;
  const size_t base = seed_start(begin), seeded = seed_end(begin);
  for (int i = lane; i < (1 << kHashBits); i += kWarp) table[i] = kNoPosition;
  __syncwarp();
  // four groups' hashes loaded at once, then entered in order
  constexpr int kAhead = 4;
  for (size_t q0 = base; q0 < seeded; q0 += kAhead * kWarp) {
    uint32_t h[kAhead];
    for (int k = 0; k < kAhead; k++) {
      const size_t q = q0 + k * kWarp + lane;
      h[k] = q < seeded ? hash4(data + q) : (1u << kHashBits) + lane;  // lanes left out match no one
    }
    for (int k = 0; k < kAhead; k++) {
      const unsigned same = __match_any_sync(0xffffffffu, h[k]);
      if (h[k] < (1u << kHashBits) && lane == 31 - __clz(same)) table[h[k]] = static_cast<uint16_t>(q0 + k * kWarp + lane - base);
      __syncwarp();
    }
  }
  uint32_t* out = tokens + piece * kPiece;
  int count = 0;
  size_t next = begin;
  for (size_t g = begin; g < end; g += kWarp) {
    const size_t p = g + lane;
    const uint32_t d_hash = enter_group(data, g, p < end && hashed(p, end), base, table);
    if (next >= g + kWarp) continue;  // inside a match
    const uint32_t limit = p < end ? match_limit(p, end) : 0;
    uint32_t best = 0;
    for (int k = 0; k < c.count; k++) {
      // Nearest first: once every lane has a match as long as it may be, a
      // farther one can only tie, and ties go to the nearer.
      if (!__any_sync(0xffffffffu, p < end && key_length(best) < limit)) break;
      const uint32_t run = group_run(data, g, end, c.distance[k]);
      const uint32_t key = p < end && valid_distance(p, c.distance[k])
                               ? match_key(clamp_match(run, c.distance[k], limit), c.distance[k])
                               : 0;
      best = key > best ? key : best;
    }
    if (p < end) {
      const uint32_t h = hash_key(data, p, limit, d_hash, best, c);
      best = h > best ? h : best;
    }
    // The walk: a run of literals (lanes up to the next match) in one
    // step, each lane writing its own; a match by lane 0.
    const unsigned matches = __ballot_sync(0xffffffffu, best != 0);
    const int last = end - g < kWarp ? static_cast<int>(end - g) : static_cast<int>(kWarp);
    while (next < g + last) {
      const int at = static_cast<int>(next - g);
      const unsigned ahead = matches & (~0u << at);
      const int stop = ahead ? __ffs(ahead) - 1 : last;
      if (stop > at) {
        if (lane >= at && lane < stop) out[count + lane - at] = literal_token(data[p]);
        count += stop - at;
        next = g + stop;
        continue;
      }
      const uint32_t key = __shfl_sync(0xffffffffu, best, at);
      if (lane == 0) out[count] = match_token(key_length(key), key_distance(key));
      count++;
      next += key_length(key);
    }
  }
  if (lane == 0) counts[piece] = static_cast<uint32_t>(count);
  __syncwarp();
  Frequencies& f = freq[piece / kPiecesPerChunk];
  const auto add = [](uint32_t* counter, uint32_t v) { atomicAdd(counter, v); };
  for (int i = lane; i < count; i += kWarp) count_token(out[i], f, add);
  unsigned long long a = 0, b = 0;
  const size_t len = end - begin;
  for (size_t i = lane; i < len; i += kWarp) {
    a += data[begin + i];
    b += (len - i) * static_cast<unsigned long long>(data[begin + i]);
  }
  for (int o = kWarp / 2; o > 0; o /= 2) {
    a += __shfl_xor_sync(0xffffffffu, a, o);
    b += __shfl_xor_sync(0xffffffffu, b, o);
  }
  if (lane == 0) adler[piece] = AdlerPart{static_cast<uint32_t>(a % kAdlerBase), static_cast<uint32_t>(b % kAdlerBase), len};
}

constexpr int kCodeThreads = 320;  // a thread per symbol of both alphabets

// A block per chunk: the frequencies, the symbols sorted a thread each
// (key_rank), the two alphabets' lengths and codes on a thread of their
// own each, then the header: build_block_code's steps.
__global__ void __launch_bounds__(kCodeThreads)
    k_deflate_code(const Frequencies* freq, int width, int height, const uint32_t* translucent, BlockCode* codes) {
  __shared__ uint32_t lf[kLitLenSymbols], df[kDistSymbols], lkey[kLitLenSymbols], dkey[kDistSymbols];
  __shared__ uint32_t la[kLitLenSymbols], da[kDistSymbols], lfirst[16], dfirst[16];
  __shared__ int lused, dused;
  __shared__ BlockCode b;
  const size_t chunk = blockIdx.x, chunks = chunk_count(layout_of(width, height, translucent).size());
  if (chunk >= chunks) return;
  const int t = threadIdx.x;
  // code_frequencies: the counts, the end of block, two codes at least
  if (t < kLitLenSymbols) lf[t] = litlen_frequency(freq[chunk], t);
  else if (t - kLitLenSymbols < kDistSymbols) df[t - kLitLenSymbols] = freq[chunk].dist[t - kLitLenSymbols];
  __syncthreads();
  if (t == 0) ensure_two(lf, kLitLenSymbols);
  if (t == kWarp) ensure_two(df, kDistSymbols);
  __syncthreads();
  const int lu = __syncthreads_count(t < kLitLenSymbols && lf[t] != 0);
  const int du = __syncthreads_count(t - kLitLenSymbols < kDistSymbols && t >= kLitLenSymbols && df[t - kLitLenSymbols] != 0);
  if (t == 0) {
    lused = lu;
    dused = du;
  }
  __syncthreads();
  if (t < kLitLenSymbols) {
    b.litlen_length[t] = 0;
    if (lf[t]) lkey[key_rank(lf, kLitLenSymbols, t)] = symbol_key(lf, t);
  } else if (t - kLitLenSymbols < kDistSymbols) {
    const int s = t - kLitLenSymbols;
    b.dist_length[s] = 0;
    if (df[s]) dkey[key_rank(df, kDistSymbols, s)] = symbol_key(df, s);
  }
  __syncthreads();
  if (t == 0) {
    huffman_lengths_sorted(lkey, lused, 15, b.litlen_length, la);
    first_codes(b.litlen_length, kLitLenSymbols, lfirst);
  } else if (t == kWarp) {
    huffman_lengths_sorted(dkey, dused, 15, b.dist_length, da);
    first_codes(b.dist_length, kDistSymbols, dfirst);
  }
  __syncthreads();
  if (t < kLitLenSymbols) b.litlen_code[t] = canonical_code(b.litlen_length, t, lfirst);
  else if (t - kLitLenSymbols < kDistSymbols) b.dist_code[t - kLitLenSymbols] = canonical_code(b.dist_length, t - kLitLenSymbols, dfirst);
  __syncthreads();
  if (t == 0) write_block_header(b, chunk + 1 == chunks);
  __syncthreads();
  const uint32_t* from = reinterpret_cast<const uint32_t*>(&b);
  uint32_t* to = reinterpret_cast<uint32_t*>(codes + chunk);
  for (size_t i = t; i < sizeof(BlockCode) / 4; i += blockDim.x) to[i] = from[i];
}

struct AtomicOr {
  __device__ void operator()(uint32_t* w, uint32_t v) const {
    if (v) atomicOr(w, v);
  }
};

// A block per chunk, a warp per piece: the pieces' bit counts, their scan,
// dynamic or stored, then every token written at its bit.
__global__ void __launch_bounds__(kPiecesPerChunk * kWarp)
    k_deflate_write(const uint8_t* data, int width, int height, const uint32_t* translucent, const uint32_t* tokens,
                    const uint32_t* counts, const BlockCode* codes, const AdlerPart* piece_adler, uint32_t* slots,
                    uint32_t* sizes, AdlerPart* chunk_adler) {
  __shared__ unsigned long long start[kPiecesPerChunk + 1];
  __shared__ bool dynamic;
  __shared__ BlockCode code;
  const size_t n = layout_of(width, height, translucent).size();
  const size_t chunk = blockIdx.x, chunks = chunk_count(n);
  if (chunk >= chunks) return;
  const int warp = threadIdx.x / kWarp, lane = threadIdx.x % kWarp;
  const size_t begin = chunk * kChunk, end = begin + kChunk < n ? begin + kChunk : n;
  const bool final = chunk + 1 == chunks;
  const int pieces = static_cast<int>((end - begin + kPiece - 1) / kPiece);
  const size_t piece = chunk * kPiecesPerChunk + warp;
  uint32_t* slot = slots + chunk * (kSlotBytes / 4);
  for (size_t i = threadIdx.x; i < kSlotBytes / 4; i += blockDim.x) slot[i] = 0;
  for (size_t i = threadIdx.x; i < sizeof(BlockCode) / 4; i += blockDim.x)
    reinterpret_cast<uint32_t*>(&code)[i] = reinterpret_cast<const uint32_t*>(codes + chunk)[i];
  __syncthreads();
  const uint32_t* t = tokens + piece * kPiece;
  const int count = warp < pieces ? static_cast<int>(counts[piece]) : 0;
  unsigned long long bits = 0;
  for (int i = lane; i < count; i += kWarp) bits += token_bits(t[i], code);
  for (int o = kWarp / 2; o > 0; o /= 2) bits += __shfl_xor_sync(0xffffffffu, bits, o);
  if (lane == 0) start[warp + 1] = bits;
  __syncthreads();
  if (threadIdx.x == 0) {
    start[0] = code.header_bits;
    for (int k = 0; k < pieces; k++) start[k + 1] += start[k];
    const size_t dyn = dynamic_bytes(start[pieces], code, final), stored = stored_bytes(end - begin);
    dynamic = dyn <= stored;
    sizes[chunk] = static_cast<uint32_t>(dynamic ? dyn : stored);
    AdlerPart sum;
    for (int k = 0; k < pieces; k++) sum = adler_join(sum, piece_adler[chunk * kPiecesPerChunk + k]);
    chunk_adler[chunk] = sum;
  }
  __syncthreads();
  if (!dynamic) {
    uint8_t* bytes = reinterpret_cast<uint8_t*>(slot);
    const size_t total = stored_bytes(end - begin);
    for (size_t j = threadIdx.x; j < total; j += blockDim.x) bytes[j] = stored_byte(data + begin, end - begin, final, j);
    return;
  }
  for (int i = threadIdx.x; i < kHeaderWords; i += blockDim.x) AtomicOr{}(slot + i, code.header[i]);
  if (threadIdx.x == 0) put_block_end(slot, start[pieces], code, final, AtomicOr{});
  if (warp >= pieces) return;
  unsigned long long at = start[warp];
  for (int i0 = 0; i0 < count; i0 += kWarp) {
    const int i = i0 + lane;
    const uint32_t b = i < count ? token_bits(t[i], code) : 0;
    uint32_t before = b;  // inclusive scan over the lanes
    for (int o = 1; o < kWarp; o *= 2) {
      const uint32_t v = __shfl_up_sync(0xffffffffu, before, o);
      if (lane >= o) before += v;
    }
    if (i < count) {
      BitStream<AtomicOr> out(slot, at + before - b, AtomicOr{});
      put_token(out, t[i], code);
      out.flush();
    }
    at += __shfl_sync(0xffffffffu, before, kWarp - 1);
  }
}

// A block per chunk: its bytes copied to their place in the stream; the
// last block adds the zlib header, the Adler-32 trailer and the length.
__global__ void k_deflate_join(const uint32_t* slots, const uint32_t* sizes, const AdlerPart* chunk_adler,
                               int width, int height, const uint32_t* translucent, uint8_t* out, uint32_t* length) {
  __shared__ size_t at;
  const size_t chunk = blockIdx.x, chunks = chunk_count(layout_of(width, height, translucent).size());
  if (chunk >= chunks) return;
  if (threadIdx.x == 0) {
    size_t o = 2;
    for (size_t k = 0; k < chunk; k++) o += sizes[k];
    at = o;
  }
  __syncthreads();
  const uint8_t* from = reinterpret_cast<const uint8_t*>(slots + chunk * (kSlotBytes / 4));
  for (size_t j = threadIdx.x; j < sizes[chunk]; j += blockDim.x) out[at + j] = from[j];
  if (chunk + 1 == chunks && threadIdx.x == 0) {
    out[0] = 0x78;  // deflate, 32 KiB window
    out[1] = 0x01;  // no dictionary, check bits (0x7801 % 31 == 0)
    AdlerPart sum;
    for (size_t k = 0; k < chunks; k++) sum = adler_join(sum, chunk_adler[k]);
    const uint32_t v = adler_value(sum);
    const size_t e = at + sizes[chunk];
    for (int i = 0; i < 4; i++) out[e + i] = static_cast<uint8_t>(v >> (24 - 8 * i));
    *length = static_cast<uint32_t>(e + 4);
  }
}

}  // namespace

void PngStage::launch_filter(const uint32_t* rgba, int width, int height) {
  const size_t pixels = size_t(width) * height;
  MPVG_CUDA(cudaMemsetAsync(flag_.data(), 0, sizeof(uint32_t)));
  k_png_translucent<<<grid_for(pixels, 256), 256>>>(rgba, pixels, flag_.data());
  MPVG_LAUNCHED();
  k_png_filter<<<grid_for(size_t(height) * kWarp, 128), 128>>>(reinterpret_cast<const uint8_t*>(rgba), width, height,
                                                                flag_.data(), filtered_.data());
  MPVG_LAUNCHED();
  launches += 2;
}

png::ImageData PngStage::run(const uint32_t* rgba, int width, int height) {
  const size_t pixels = size_t(width) * height;
  if (!pixels) throw Error("PNG: empty image");
  launches = syncs = 0;
  auto launched = [&] {
    MPVG_LAUNCHED();
    launches++;
  };
  // Sizes for RGBA rows, the larger layout: the kernels find the image's
  // own from the flag on the device.
  png::FilterLayout l;
  l.width = width;
  l.height = height;
  l.channels = 4;
  const size_t n = l.size(), chunks = chunk_count(n), pieces = piece_count(n);
  flag_.resize(1);
  filtered_.resize(n);
  tokens_.resize(pieces * kPiece);
  counts_.resize(pieces);
  freq_.resize(chunks);
  codes_.resize(chunks);
  piece_adler_.resize(pieces);
  chunk_adler_.resize(chunks);
  slots_.resize(chunks * (kSlotBytes / 4));
  sizes_.resize(chunks);
  out_.resize(2 + chunks * kSlotBytes + 4);
  length_.resize(1);
  MPVG_CUDA(cudaMemsetAsync(freq_.data(), 0, chunks * sizeof(Frequencies)));
  launch_filter(rgba, width, height);
  k_deflate_parse<<<grid_for(pieces * kWarp, kParseWarps * kWarp), kParseWarps * kWarp>>>(
      filtered_.data(), width, height, flag_.data(), tokens_.data(), counts_.data(), freq_.data(),
      piece_adler_.data());
  launched();
  k_deflate_code<<<unsigned(chunks), kCodeThreads>>>(freq_.data(), width, height, flag_.data(), codes_.data());
  launched();
  k_deflate_write<<<unsigned(chunks), kPiecesPerChunk * kWarp>>>(filtered_.data(), width, height, flag_.data(),
                                                                 tokens_.data(), counts_.data(), codes_.data(),
                                                                 piece_adler_.data(), slots_.data(), sizes_.data(),
                                                                 chunk_adler_.data());
  launched();
  k_deflate_join<<<unsigned(chunks), 256>>>(slots_.data(), sizes_.data(), chunk_adler_.data(), width, height,
                                            flag_.data(), out_.data(), length_.data());
  launched();
  // One round trip: the flag and the length, then the stream.
  uint32_t head[2];
  MPVG_CUDA(cudaMemcpyAsync(&head[0], flag_.data(), sizeof(uint32_t), cudaMemcpyDeviceToHost));
  MPVG_CUDA(cudaMemcpyAsync(&head[1], length_.data(), sizeof(uint32_t), cudaMemcpyDeviceToHost));
  MPVG_CUDA(cudaStreamSynchronize(0));
  syncs++;
  png::ImageData result;
  result.channels = head[0] ? 4 : 3;
  result.zlib.resize(head[1]);
  MPVG_CUDA(cudaMemcpy(result.zlib.data(), out_.data(), head[1], cudaMemcpyDeviceToHost));
  return result;
}

png::FilteredRows PngStage::filter(const uint32_t* rgba, int width, int height, std::vector<uint8_t> storage) {
  const size_t pixels = size_t(width) * height;
  if (!pixels) throw Error("PNG: empty image");
  launches = syncs = 0;
  png::FilterLayout l;
  l.width = width;
  l.height = height;
  l.channels = 4;
  const size_t n4 = l.size();
  l.channels = 3;
  const size_t n3 = l.size();
  flag_.resize(1);
  filtered_.resize(n4);
  launch_filter(rgba, width, height);
  // The flag with the opaque layout's bytes: what every opaque page needs.
  png::FilteredRows out;
  out.rows = std::move(storage);
  out.rows.resize(n3);
  uint32_t translucent = 0;
  MPVG_CUDA(cudaMemcpyAsync(&translucent, flag_.data(), sizeof(uint32_t), cudaMemcpyDeviceToHost));
  MPVG_CUDA(cudaMemcpyAsync(out.rows.data(), filtered_.data(), n3, cudaMemcpyDeviceToHost));
  MPVG_CUDA(cudaStreamSynchronize(0));
  syncs++;
  out.channels = translucent ? 4 : 3;
  if (translucent) {
    out.rows.resize(n4);
    MPVG_CUDA(cudaMemcpy(out.rows.data() + n3, filtered_.data() + n3, n4 - n3, cudaMemcpyDeviceToHost));
    syncs++;
  }
  return out;
}

png::ImageData compress_rgba8_gpu(const uint8_t* rgba, int width, int height) {
  const size_t pixels = size_t(width) * height;
  DeviceBuffer<uint32_t> image(pixels);
  if (pixels) MPVG_CUDA(cudaMemcpy(image.data(), rgba, 4 * pixels, cudaMemcpyHostToDevice));
  PngStage stage;
  return stage.run(image.data(), width, height);
}

}  // namespace mpvg::gpu
