// The GPU executor of the PNG stage's filtering and compression
// (core/png_encode.h): the 8-bit image never leaves the device; its rows
// are filtered (core/png_filter.h, a warp per row) and deflated
// (core/deflate.h: a warp per piece parses, a thread per chunk builds its
// codes, a block per chunk writes its bits, a block per chunk copies them
// into one zlib stream), and only the stream is copied back. The same
// bytes as the CPU executor gives.
#include "core/deflate.h"
#include "core/png_filter.h"
#include "gpu/context.cuh"
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

// A warp per row: the Up and Sub sums, the choice, the filtered bytes.
__global__ void k_png_filter(const uint8_t* rgba, png::FilterLayout l, uint8_t* out) {
  const int y = static_cast<int>((blockIdx.x * size_t(blockDim.x) + threadIdx.x) / kWarp);
  const int lane = threadIdx.x % kWarp;
  if (y >= l.height) return;
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

constexpr int kParseWarps = 2;  // per block: two hash tables of 16 KiB

// A warp per piece: the table seeded (each group of 32 positions at once,
// the last of equal hashes writing: the order of one thread), then each
// step's candidates evaluated by one lane each and the best taken; the
// tokens' symbols counted into the chunk's frequencies and the piece's
// Adler-32 part.
__global__ void k_deflate_parse(const uint8_t* data, size_t n, Candidates c, uint32_t* tokens, uint32_t* counts,
                                Frequencies* freq, AdlerPart* adler) {
  __shared__ uint16_t tables[kParseWarps][1 << kHashBits];
  const size_t piece = (blockIdx.x * size_t(blockDim.x) + threadIdx.x) / kWarp;
  const int lane = threadIdx.x % kWarp;
  if (piece >= piece_count(n)) return;
  uint16_t* table = tables[threadIdx.x / kWarp];
  const size_t begin = piece * kPiece, end = begin + kPiece < n ? begin + kPiece : n;
  const size_t base = seed_start(begin), seeded = seed_end(begin);
  for (int i = lane; i < (1 << kHashBits); i += kWarp) table[i] = kNoPosition;
  __syncwarp();
  for (size_t q0 = base; q0 < seeded; q0 += kWarp) {
    const size_t q = q0 + lane;
    const uint32_t h = q < seeded ? hash4(data + q) : 0xffffffffu;
    const unsigned same = __match_any_sync(0xffffffffu, h);
    if (q < seeded && lane == 31 - __clz(same)) table[h] = static_cast<uint16_t>(q - base);
    __syncwarp();
  }
  uint32_t* out = tokens + piece * kPiece;
  int count = 0;
  for (size_t p = begin; p < end;) {
    const uint32_t key = lane <= c.count ? candidate_key(data, p, end, base, c, lane, table) : 0;
    const uint32_t best = __reduce_max_sync(0xffffffffu, key);
    const uint32_t t = key_token(best, data[p]);
    if (lane == 0) out[count] = t;
    count++;
    p += token_length(t) ? token_length(t) : 1;
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

__global__ void k_deflate_code(const Frequencies* freq, size_t chunks, BlockCode* codes) {
  const size_t c = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (c < chunks) build_block_code(freq[c], c + 1 == chunks, codes[c]);
}

struct AtomicOr {
  __device__ void operator()(uint32_t* w, uint32_t v) const {
    if (v) atomicOr(w, v);
  }
};

// A block per chunk, a warp per piece: the pieces' bit counts, their scan,
// dynamic or stored, then every token written at its bit.
__global__ void k_deflate_write(const uint8_t* data, size_t n, const uint32_t* tokens, const uint32_t* counts,
                                const BlockCode* codes, const AdlerPart* piece_adler, uint32_t* slots,
                                uint32_t* sizes, AdlerPart* chunk_adler) {
  __shared__ unsigned long long start[kPiecesPerChunk + 1];
  __shared__ bool dynamic;
  const size_t chunk = blockIdx.x, chunks = chunk_count(n);
  const int warp = threadIdx.x / kWarp, lane = threadIdx.x % kWarp;
  const size_t begin = chunk * kChunk, end = begin + kChunk < n ? begin + kChunk : n;
  const bool final = chunk + 1 == chunks;
  const int pieces = static_cast<int>((end - begin + kPiece - 1) / kPiece);
  const size_t piece = chunk * kPiecesPerChunk + warp;
  const BlockCode& code = codes[chunk];
  uint32_t* slot = slots + chunk * (kSlotBytes / 4);
  for (size_t i = threadIdx.x; i < kSlotBytes / 4; i += blockDim.x) slot[i] = 0;
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
                               size_t chunks, uint8_t* out, uint32_t* length) {
  __shared__ size_t at;
  const size_t chunk = blockIdx.x;
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

png::ImageData PngStage::run(const uint32_t* rgba, int width, int height) {
  const size_t pixels = size_t(width) * height;
  if (!pixels) throw Error("PNG: empty image");
  launches = syncs = 0;
  auto launched = [&] {
    MPVG_LAUNCHED();
    launches++;
  };
  auto read = [&](const uint32_t* p) {
    uint32_t v = 0;
    MPVG_CUDA(cudaMemcpy(&v, p, sizeof v, cudaMemcpyDeviceToHost));
    syncs++;
    return v;
  };
  png::ImageData result;
  flag_.resize(1);
  MPVG_CUDA(cudaMemsetAsync(flag_.data(), 0, sizeof(uint32_t)));
  k_png_translucent<<<grid_for(pixels, 256), 256>>>(rgba, pixels, flag_.data());
  launched();
  result.channels = read(flag_.data()) ? 4 : 3;
  png::FilterLayout l;
  l.width = width;
  l.height = height;
  l.channels = result.channels;
  const size_t n = l.size();
  filtered_.resize(n);
  k_png_filter<<<grid_for(size_t(height) * kWarp, 128), 128>>>(reinterpret_cast<const uint8_t*>(rgba), l,
                                                                filtered_.data());
  launched();
  const size_t chunks = chunk_count(n), pieces = piece_count(n);
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
  const Candidates c = png_candidates(static_cast<uint32_t>(l.bpp()), static_cast<uint32_t>(l.stride()));
  k_deflate_parse<<<grid_for(pieces * kWarp, kParseWarps * kWarp), kParseWarps * kWarp>>>(
      filtered_.data(), n, c, tokens_.data(), counts_.data(), freq_.data(), piece_adler_.data());
  launched();
  k_deflate_code<<<grid_for(chunks, 32), 32>>>(freq_.data(), chunks, codes_.data());
  launched();
  k_deflate_write<<<unsigned(chunks), kPiecesPerChunk * kWarp>>>(filtered_.data(), n, tokens_.data(), counts_.data(),
                                                                 codes_.data(), piece_adler_.data(), slots_.data(),
                                                                 sizes_.data(), chunk_adler_.data());
  launched();
  k_deflate_join<<<unsigned(chunks), 256>>>(slots_.data(), sizes_.data(), chunk_adler_.data(), chunks, out_.data(),
                                            length_.data());
  launched();
  const uint32_t length = read(length_.data());
  result.zlib.resize(length);
  MPVG_CUDA(cudaMemcpy(result.zlib.data(), out_.data(), length, cudaMemcpyDeviceToHost));
  return result;
}

png::ImageData Context::Impl::download_png(bool linear) {
  convert_rgba8(linear);
  if (!png_stage) png_stage = std::make_unique<PngStage>();
  png::ImageData data = png_stage->run(rgba8.data(), out_width, out_height);
  launches += png_stage->launches;
  syncs += png_stage->syncs;
  return data;
}

png::ImageData compress_rgba8_gpu(const uint8_t* rgba, int width, int height) {
  const size_t pixels = size_t(width) * height;
  DeviceBuffer<uint32_t> image(pixels);
  if (pixels) MPVG_CUDA(cudaMemcpy(image.data(), rgba, 4 * pixels, cudaMemcpyHostToDevice));
  PngStage stage;
  return stage.run(image.data(), width, height);
}

}  // namespace mpvg::gpu
