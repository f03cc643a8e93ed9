// Deflate (RFC 1951) cut for parallel executors, written once for both: the
// PNG stage's compression of filtered rows (core/output/png_filter.h).
//
// The data is cut into chunks of kChunk bytes, each one deflate block, and
// each chunk into pieces of kPiece bytes, each parsed by one thread:
//
//   data   |<---------------- chunk (one block) ---------------->|<-- next chunk ...
//          |piece|piece|piece| ...                         |piece|
//   stream [dynamic header][tokens of piece 0][piece 1]...[EOB][empty stored block]
//
// - Parse (parse_piece): greedy LZ77 over the piece alone (a match stops at
//   the piece's end). At each position the longest match among a few
//   fixed distances (1 and one pixel: runs and flat colour after the Sub
//   filter; two pixels; a row and a row and a pixel either way, two rows: a
//   row like the one above after either filter) and the latest position of
//   the same 4-byte hash (a table seeded with the 16 KiB before the piece).
//   A match may reach back before the piece and the chunk, up to 32 KiB.
// - Code (build_block_code): each chunk's symbol frequencies give its own
//   length-limited Huffman codes and the dynamic block header (3.2.7).
// - Write: every piece knows its tokens' bit count, so a scan over the
//   chunk's pieces gives each piece where its bits start; pieces write
//   concurrently into zeroed words (the words at a piece's ends are shared
//   with its neighbours, hence the OR). A chunk ends with its end-of-block
//   code and, unless it is the last, an empty stored block that pads it to
//   a byte boundary, so chunks' bytes simply follow one another. A chunk
//   that would come out larger than stored (noise) is stored instead.
//
// The per-chunk results (bytes, Adler-32 sums) join into one zlib stream
// (RFC 1950) in chunk order: the same bytes from either executor.
#pragma once
#include <cstddef>
#include <cstdint>

#include "core/hd.h"

namespace mpvg::deflate {

constexpr int kPiece = 4096;         // bytes parsed by one thread (a warp on the GPU)
constexpr int kPiecesPerChunk = 16;  // one block of 64 KiB
constexpr size_t kChunk = size_t(kPiece) * kPiecesPerChunk;
constexpr uint32_t kMinMatch = 3, kMaxMatch = 258, kWindow = 32768;
constexpr int kLitLenSymbols = 286, kDistSymbols = 30, kCodeLengthSymbols = 19;
constexpr int kEndOfBlock = 256;
constexpr int kMaxCandidates = 8;
// A chunk's bytes at most: stored, in blocks of at most 65,535 bytes with 5
// bytes of header each, rounded up to whole words.
constexpr size_t kStoredBlock = 65535;
constexpr size_t kSlotBytes = (kChunk + 5 * ((kChunk + kStoredBlock - 1) / kStoredBlock) + 3) / 4 * 4;
// The dynamic header at most: 17 bits, 19 x 3 bits, 316 lengths x (7 + 7).
constexpr int kHeaderWords = (17 + 19 * 3 + 316 * 14 + 31) / 32;

MPVG_HD_INLINE size_t chunk_count(size_t size) { return size ? (size + kChunk - 1) / kChunk : 1; }
MPVG_HD_INLINE size_t piece_count(size_t size) { return size ? (size + kPiece - 1) / kPiece : 1; }

// The distances a match is looked for at, nearest first.
struct Candidates {
  uint32_t distance[kMaxCandidates];
  int count = 0;
};

// For rows of `stride` bytes (filter byte included), `bpp` bytes per pixel.
MPVG_HD_INLINE Candidates png_candidates(uint32_t bpp, uint32_t stride) {
  Candidates c;
  const uint32_t want[kMaxCandidates] = {1, bpp, 2 * bpp, stride - bpp, stride, stride + bpp, 2 * stride, 0};
  for (int i = 0; i < kMaxCandidates; i++) {
    const uint32_t d = want[i];
    bool seen = d == 0 || d > kWindow;
    for (int j = 0; j < c.count && !seen; j++) seen = c.distance[j] == d;
    if (!seen) c.distance[c.count++] = d;
  }
  // nearest first: fewer extra bits for the same length
  for (int i = 1; i < c.count; i++)
    for (int j = i; j > 0 && c.distance[j - 1] > c.distance[j]; j--) {
      const uint32_t t = c.distance[j];
      c.distance[j] = c.distance[j - 1];
      c.distance[j - 1] = t;
    }
  return c;
}

// Tokens: a literal byte (length 0) or a match, length << 16 | distance.
MPVG_HD_INLINE uint32_t literal_token(uint8_t b) { return b; }
MPVG_HD_INLINE uint32_t match_token(uint32_t length, uint32_t distance) { return length << 16 | distance; }
MPVG_HD_INLINE uint32_t token_length(uint32_t t) { return t >> 16; }
MPVG_HD_INLINE uint32_t token_distance(uint32_t t) { return t & 0xffff; }

// A match of `run` equal bytes at distance d, where at most `limit` may be
// taken: its length, or 0 where it is shorter than worth coding: 3 bytes,
// 4 beyond 1 KiB back (whose distance codes carry 10 or more extra bits).
MPVG_HD_INLINE uint32_t clamp_match(uint32_t run, uint32_t d, uint32_t limit) {
  run = run < limit ? run : limit;
  return run >= (d > 1024 ? kMinMatch + 1 : kMinMatch) ? run : 0;
}

// Can position p reach back d bytes?
MPVG_HD_INLINE bool valid_distance(size_t p, uint32_t d) { return d != 0 && d <= p && d <= kWindow; }

// The length of the match at p with data[p - d ..], at most `limit` bytes
// (clamp_match's).
MPVG_HD_INLINE uint32_t match_length(const uint8_t* data, size_t p, uint32_t d, uint32_t limit) {
  if (!valid_distance(p, d)) return 0;
  const uint8_t* a = data + p;
  const uint8_t* b = a - d;
  uint32_t k = 0;
  while (k < limit && a[k] == b[k]) k++;
  return clamp_match(k, d, limit);
}

// The most bytes a match at p may take in the piece [.., end).
MPVG_HD_INLINE uint32_t match_limit(size_t p, size_t end) {
  return static_cast<uint32_t>(end - p < kMaxMatch ? end - p : kMaxMatch);
}

// A match as a key whose order is preference: longer, or as long and
// nearer (fewer extra bits); 0 for none. The parse takes the largest.
MPVG_HD_INLINE uint32_t match_key(uint32_t len, uint32_t d) { return len ? len << 16 | (0xffffu - d) : 0; }
MPVG_HD_INLINE uint32_t key_length(uint32_t key) { return key >> 16; }
MPVG_HD_INLINE uint32_t key_distance(uint32_t key) { return 0xffffu - (key & 0xffff); }
MPVG_HD_INLINE uint32_t key_token(uint32_t key, uint8_t literal) {
  return key ? match_token(key_length(key), key_distance(key)) : literal_token(literal);
}

// Besides the fixed distances, a hash table of 4-byte strings finds
// repeats anywhere in the window (text, patterns): the latest earlier
// position of the same hash, every position of the piece entered (as
// libdeflate's fast levels do), started from the kSeed bytes before the
// piece. So each position's previous occurrence is a property of the data,
// not of the parse, and positions can find theirs in parallel.
constexpr int kHashBits = 13;
constexpr uint32_t kSeed = 16384;
constexpr uint16_t kNoPosition = 0xffff;  // positions are kept relative to the piece's seed start

MPVG_HD_INLINE uint32_t hash4(const uint8_t* p) {
  const uint32_t v = p[0] | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
  return (v * 2654435761u) >> (32 - kHashBits);
}

// Where a piece's table starts: kSeed bytes before it (or the data's start).
MPVG_HD_INLINE size_t seed_start(size_t begin) { return begin > kSeed ? begin - kSeed : 0; }

// The positions whose strings seed the piece's table, in order (a later one
// replaces an earlier one of the same hash): [seed_start, begin - 3).
MPVG_HD_INLINE size_t seed_end(size_t begin) { return begin >= 3 + seed_start(begin) ? begin - 3 : seed_start(begin); }

// Does position p of the piece [.., end) enter the table (its 4 bytes are
// in the piece)?
MPVG_HD_INLINE bool hashed(size_t p, size_t end) { return p + 4 <= end; }

// The key of the hash candidate at distance d (0: none) given the best
// key of the fixed candidates; 0 where it cannot beat it (its distance is
// one of theirs, or they already take `limit` bytes from nearer), so that
// the comparison is only made where it can matter.
MPVG_HD_INLINE uint32_t hash_key(const uint8_t* data, size_t p, uint32_t limit, uint32_t d, uint32_t best,
                                 const Candidates& c) {
  if (d == 0) return 0;
  for (int k = 0; k < c.count; k++)
    if (c.distance[k] == d) return 0;
  if (key_length(best) == limit && d > key_distance(best)) return 0;
  return match_key(match_length(data, p, d, limit), d);
}

// Greedy LZ77 parse of the piece data[begin, end) into tokens; returns
// their count (at most end - begin). At a token's start the best of the
// fixed candidates and the hash's; then the token's length on. The
// executors' reference order; `table` has 1 << kHashBits entries.
MPVG_HD_INLINE int parse_piece(const uint8_t* data, size_t begin, size_t end, const Candidates& c, uint16_t* table,
                               uint32_t* tokens) {
  const size_t base = seed_start(begin);
  for (int i = 0; i < (1 << kHashBits); i++) table[i] = kNoPosition;
  for (size_t q = base; q < seed_end(begin); q++) table[hash4(data + q)] = static_cast<uint16_t>(q - base);
  int n = 0;
  size_t next = begin;
  for (size_t p = begin; p < end; p++) {
    uint32_t d_hash = 0;
    if (hashed(p, end)) {
      const uint32_t h = hash4(data + p);
      if (table[h] != kNoPosition) d_hash = static_cast<uint32_t>(p - base - table[h]);
      table[h] = static_cast<uint16_t>(p - base);
    }
    if (p != next) continue;
    const uint32_t limit = match_limit(p, end);
    uint32_t best = 0;
    for (int k = 0; k < c.count; k++) {
      const uint32_t key = match_key(match_length(data, p, c.distance[k], limit), c.distance[k]);
      best = key > best ? key : best;
    }
    const uint32_t h = hash_key(data, p, limit, d_hash, best, c);
    best = h > best ? h : best;
    const uint32_t t = key_token(best, data[p]);
    tokens[n++] = t;
    next = p + (token_length(t) ? token_length(t) : 1);
  }
  return n;
}

MPVG_HD_INLINE int floor_log2(uint32_t v) {
  int r = 0;
  while (v >>= 1) r++;
  return r;
}

// Length 3..258 -> symbol 257..285 and its extra bits (3.2.5).
MPVG_HD_INLINE int length_symbol(uint32_t length, int& extra_bits, uint32_t& extra) {
  if (length == kMaxMatch) {
    extra_bits = 0;
    extra = 0;
    return 285;
  }
  const uint32_t v = length - 3;
  const int e = v < 8 ? 0 : floor_log2(v) - 2;
  extra_bits = e;
  extra = v & ((1u << e) - 1);
  return 261 + 4 * e + static_cast<int>(v >> e) - 4;
}

// Distance 1..32768 -> symbol 0..29 and its extra bits (3.2.5).
MPVG_HD_INLINE int distance_symbol(uint32_t distance, int& extra_bits, uint32_t& extra) {
  const uint32_t v = distance - 1;
  if (v < 4) {
    extra_bits = 0;
    extra = 0;
    return static_cast<int>(v);
  }
  const int e = floor_log2(v) - 1;
  extra_bits = e;
  extra = v & ((1u << e) - 1);
  return 2 * e + static_cast<int>(v >> e);
}

// Symbol frequencies of one block.
struct Frequencies {
  uint32_t litlen[kLitLenSymbols];
  uint32_t dist[kDistSymbols];
};

template <class Add>
MPVG_HD_INLINE void count_token(uint32_t t, Frequencies& f, const Add& add) {
  const uint32_t len = token_length(t);
  if (!len) {
    add(&f.litlen[t], 1u);
    return;
  }
  int eb;
  uint32_t ex;
  add(&f.litlen[length_symbol(len, eb, ex)], 1u);
  add(&f.dist[distance_symbol(token_distance(t), eb, ex)], 1u);
}

// Huffman code lengths work on the used symbols sorted by frequency:
// keys frequency << 9 | symbol (frequencies < 2^23), unique, ascending.
MPVG_HD_INLINE uint32_t symbol_key(const uint32_t* freq, int s) {
  return freq[s] ? freq[s] << 9 | static_cast<uint32_t>(s) : 0;
}

// Where symbol s's key goes among the used symbols' (ascending): the count
// of smaller ones. Independent per symbol (a thread each on the GPU).
MPVG_HD_INLINE int key_rank(const uint32_t* freq, int n, int s) {
  const uint32_t k = symbol_key(freq, s);
  int r = 0;
  for (int t = 0; t < n; t++) {
    const uint32_t kt = symbol_key(freq, t);
    r += kt != 0 && kt < k;
  }
  return r;
}

// Code lengths (at most `limit` bits) for the `used` symbols whose keys are
// sorted ascending in key[] (which this overwrites); length[] of the
// alphabet must be zeroed. Huffman's lengths by Moffat and Katajainen's
// in-place method, then, where a length exceeds the limit, the lengths'
// counts are folded down and Kraft's sum restored by lengthening the
// deepest codes above the limit's (as miniz and zlib do); the most
// frequent symbols keep the shortest codes. At least two symbols must be
// used (the caller's job).
// `A` is scratch of `used` words.
MPVG_HD_INLINE void huffman_lengths_sorted(uint32_t* key, int used, int limit, uint8_t* length, uint32_t* A) {
  if (used < 2) {
    if (used) length[key[0] & 511] = 1;
    return;
  }
  // Moffat & Katajainen, "In-place calculation of minimum-redundancy codes"
  // (1995): A holds weights, then parent pointers, then depths.
  for (int i = 0; i < used; i++) A[i] = key[i] >> 9;
  {
    int root = 0, leaf = 2;
    A[0] += A[1];
    for (int next = 1; next < used - 1; next++) {
      if (leaf >= used || A[root] < A[leaf]) {
        A[next] = A[root];
        A[root++] = static_cast<uint32_t>(next);
      } else {
        A[next] = A[leaf++];
      }
      if (leaf >= used || (root < next && A[root] < A[leaf])) {
        A[next] += A[root];
        A[root++] = static_cast<uint32_t>(next);
      } else {
        A[next] += A[leaf++];
      }
    }
    A[used - 2] = 0;
    for (int next = used - 3; next >= 0; next--) A[next] = A[A[next]] + 1;
    int avail = 1, taken = 0, root2 = used - 2, next = used - 1;
    uint32_t depth = 0;
    while (avail > 0) {
      while (root2 >= 0 && A[root2] == depth) {
        taken++;
        root2--;
      }
      while (avail > taken) {
        A[next--] = depth;
        avail--;
      }
      avail = 2 * taken;
      depth++;
      taken = 0;
    }
  }
  // counts per length, folded to the limit
  uint32_t count[33] = {};
  for (int i = 0; i < used; i++) count[A[i] < 32 ? A[i] : 32]++;
  for (int l = limit + 1; l <= 32; l++) {
    count[limit] += count[l];
    count[l] = 0;
  }
  uint64_t kraft = 0;
  for (int l = 1; l <= limit; l++) kraft += uint64_t(count[l]) << (limit - l);
  while (kraft > (uint64_t(1) << limit)) {
    count[limit]--;
    for (int l = limit - 1; l > 0; l--)
      if (count[l]) {
        count[l]--;
        count[l + 1] += 2;
        break;
      }
    kraft--;
  }
  // the least frequent symbols (first in key) take the longest codes
  int i = 0;
  for (int l = limit; l > 0; l--)
    for (uint32_t k = 0; k < count[l]; k++) length[key[i++] & 511] = static_cast<uint8_t>(l);
}

// Code lengths for n <= kLitLenSymbols symbols of the given frequencies
// (unused symbols get 0): the keys sorted by rank, then the above.
MPVG_HD_INLINE void huffman_lengths(const uint32_t* freq, int n, int limit, uint8_t* length) {
  uint32_t key[kLitLenSymbols], A[kLitLenSymbols];
  int used = 0;
  for (int s = 0; s < n; s++) {
    length[s] = 0;
    used += freq[s] != 0;
  }
  for (int s = 0; s < n; s++)
    if (freq[s]) key[key_rank(freq, n, s)] = symbol_key(freq, s);
  huffman_lengths_sorted(key, used, limit, length, A);
}

// The frequencies a block's codes are built from: its symbols', the end
// of block once, and at least two codes in each alphabet (a single one-bit
// code is not a complete code, which strict decoders reject).
MPVG_HD_INLINE void ensure_two(uint32_t* q, int n) {
  int nz = 0;
  for (int s = 0; s < n; s++) nz += q[s] != 0;
  for (int s = 0; nz < 2; s++)
    if (!q[s]) {
      q[s] = 1;
      nz++;
    }
}

// A literal/length symbol's count for the codes: the end of block once.
MPVG_HD_INLINE uint32_t litlen_frequency(const Frequencies& f, int s) { return s == kEndOfBlock ? 1 : f.litlen[s]; }

MPVG_HD_INLINE void code_frequencies(const Frequencies& f, uint32_t* litlen, uint32_t* dist) {
  for (int s = 0; s < kLitLenSymbols; s++) litlen[s] = litlen_frequency(f, s);
  for (int s = 0; s < kDistSymbols; s++) dist[s] = f.dist[s];
  ensure_two(litlen, kLitLenSymbols);
  ensure_two(dist, kDistSymbols);
}

// The low `bits` bits of v in reverse order.
MPVG_HD_INLINE uint32_t reverse_bits(uint32_t v, int bits) {
#if defined(__CUDA_ARCH__)
  return __brev(v) >> (32 - bits);
#else
  uint32_t r = 0;
  for (int b = 0; b < bits; b++, v >>= 1) r = r << 1 | (v & 1);
  return r;
#endif
}

// Canonical codes (3.2.2): first[l], the first code of length l, from
// the count of shorter codes; a symbol's code is its length's first plus
// the count of smaller symbols of the same length (a thread per symbol on
// the GPU), bit-reversed: deflate sends a Huffman code's most significant
// bit first into a stream filled from each byte's least significant bit.
MPVG_HD_INLINE void first_codes(const uint8_t* length, int n, uint32_t* first) {
  uint32_t count[16] = {};
  for (int s = 0; s < n; s++) count[length[s]]++;
  count[0] = 0;
  uint32_t c = 0;
  first[0] = 0;
  for (int l = 1; l < 16; l++) {
    c = (c + count[l - 1]) << 1;
    first[l] = c;
  }
}

MPVG_HD_INLINE uint16_t canonical_code(const uint8_t* length, int s, const uint32_t* first) {
  const int l = length[s];
  if (!l) return 0;
  uint32_t rank = 0;
  for (int t = 0; t < s; t++) rank += length[t] == l;
  return static_cast<uint16_t>(reverse_bits(first[l] + rank, l));
}

MPVG_HD_INLINE void canonical_codes(const uint8_t* length, int n, uint16_t* code) {
  uint32_t first[16];
  first_codes(length, n, first);
  for (int s = 0; s < n; s++) code[s] = canonical_code(length, s, first);
}

// Writes bits into zeroed 32-bit words, least significant first (bit k of
// the stream: bit k % 32 of word k / 32, so little-endian words are the
// stream's bytes in order), through `Or` (a plain |= on the CPU, atomicOr
// on the GPU where a word is shared with another thread's bits).
template <class Or>
struct BitStream {
  uint32_t* words;
  size_t word;
  uint64_t acc = 0;
  int pending;
  Or combine;

  MPVG_HD_INLINE BitStream(uint32_t* w, uint64_t bit, const Or& o)
      : words(w), word(static_cast<size_t>(bit >> 5)), pending(static_cast<int>(bit & 31)), combine(o) {}
  // bits <= 32, value < 2^bits
  MPVG_HD_INLINE void put(uint32_t value, int bits) {
    acc |= uint64_t(value) << pending;
    pending += bits;
    if (pending >= 32) {
      combine(words + word++, static_cast<uint32_t>(acc));
      acc >>= 32;
      pending -= 32;
    }
  }
  MPVG_HD_INLINE void flush() {
    if (pending > 0) combine(words + word, static_cast<uint32_t>(acc));
  }
};

// One block's codes and its dynamic header (BFINAL, BTYPE = 2, HLIT,
// HDIST, HCLEN, the code length code's lengths, the run-length coded code
// lengths), kept as bits from bit 0.
struct BlockCode {
  uint16_t litlen_code[kLitLenSymbols];
  uint8_t litlen_length[kLitLenSymbols];
  uint16_t dist_code[kDistSymbols];
  uint8_t dist_length[kDistSymbols];
  uint32_t header[kHeaderWords];
  uint32_t header_bits;
};

// copied as words between executors' buffers
static_assert(sizeof(BlockCode) % 4 == 0, "BlockCode is copied as 32-bit words");

struct PlainOr {
  MPVG_HD_INLINE void operator()(uint32_t* w, uint32_t v) const { *w |= v; }
};

// The block's header from its code lengths (set by the caller, with the
// codes): HLIT and HDIST, the code length code and the run-length coded
// lengths.
MPVG_HD_INLINE void write_block_header(BlockCode& b, bool final) {
  int nlit = kLitLenSymbols, ndist = kDistSymbols;
  while (nlit > 257 && !b.litlen_length[nlit - 1]) nlit--;
  while (ndist > 1 && !b.dist_length[ndist - 1]) ndist--;
  // the run-length coding of the lengths (3.2.7): 16 repeats the previous
  // length 3-6 times, 17 zero 3-10 times, 18 zero 11-138 times
  uint8_t all[kLitLenSymbols + kDistSymbols];
  const int total = nlit + ndist;
  for (int i = 0; i < nlit; i++) all[i] = b.litlen_length[i];
  for (int i = 0; i < ndist; i++) all[nlit + i] = b.dist_length[i];
  uint8_t sym[kLitLenSymbols + kDistSymbols], extra[kLitLenSymbols + kDistSymbols];
  int runs = 0;
  for (int i = 0; i < total;) {
    const uint8_t v = all[i];
    int run = 1;
    while (i + run < total && all[i + run] == v) run++;
    i += run;
    if (v == 0) {
      while (run >= 11) {
        const int r = run < 138 ? run : 138;
        sym[runs] = 18;
        extra[runs++] = static_cast<uint8_t>(r - 11);
        run -= r;
      }
      if (run >= 3) {
        sym[runs] = 17;
        extra[runs++] = static_cast<uint8_t>(run - 3);
        run = 0;
      }
    } else {
      sym[runs] = v;
      extra[runs++] = 0;
      run--;
      while (run >= 3) {
        const int r = run < 6 ? run : 6;
        sym[runs] = 16;
        extra[runs++] = static_cast<uint8_t>(r - 3);
        run -= r;
      }
    }
    for (; run > 0; run--) {
      sym[runs] = v;
      extra[runs++] = 0;
    }
  }
  uint32_t cf[kCodeLengthSymbols] = {};
  for (int i = 0; i < runs; i++) cf[sym[i]]++;
  ensure_two(cf, kCodeLengthSymbols);
  uint8_t cl[kCodeLengthSymbols];
  uint16_t cc[kCodeLengthSymbols];
  huffman_lengths(cf, kCodeLengthSymbols, 7, cl);
  canonical_codes(cl, kCodeLengthSymbols, cc);
  const uint8_t order[kCodeLengthSymbols] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
  int nclen = kCodeLengthSymbols;
  while (nclen > 4 && !cl[order[nclen - 1]]) nclen--;

  for (int i = 0; i < kHeaderWords; i++) b.header[i] = 0;
  BitStream<PlainOr> out(b.header, 0, PlainOr{});
  out.put(final ? 1u : 0u, 1);
  out.put(2, 2);
  out.put(static_cast<uint32_t>(nlit - 257), 5);
  out.put(static_cast<uint32_t>(ndist - 1), 5);
  out.put(static_cast<uint32_t>(nclen - 4), 4);
  for (int i = 0; i < nclen; i++) out.put(cl[order[i]], 3);
  uint32_t bits = 17 + 3 * nclen;
  for (int i = 0; i < runs; i++) {
    const int s = sym[i];
    out.put(cc[s], cl[s]);
    const int eb = s == 16 ? 2 : s == 17 ? 3 : s == 18 ? 7 : 0;
    if (eb) out.put(extra[i], eb);
    bits += cl[s] + eb;
  }
  out.flush();
  b.header_bits = bits;
}

// The block's codes from its frequencies, and its header. `final`: the
// stream's last block. (The GPU runs the same steps, the sorts a thread
// per symbol.)
MPVG_HD_INLINE void build_block_code(const Frequencies& f, bool final, BlockCode& b) {
  uint32_t lf[kLitLenSymbols], df[kDistSymbols];
  code_frequencies(f, lf, df);
  huffman_lengths(lf, kLitLenSymbols, 15, b.litlen_length);
  huffman_lengths(df, kDistSymbols, 15, b.dist_length);
  canonical_codes(b.litlen_length, kLitLenSymbols, b.litlen_code);
  canonical_codes(b.dist_length, kDistSymbols, b.dist_code);
  write_block_header(b, final);
}

// The bits a token takes under the block's codes.
MPVG_HD_INLINE uint32_t token_bits(uint32_t t, const BlockCode& b) {
  const uint32_t len = token_length(t);
  if (!len) return b.litlen_length[t];
  int eb, deb;
  uint32_t ex, dex;
  const int ls = length_symbol(len, eb, ex);
  const int ds = distance_symbol(token_distance(t), deb, dex);
  return b.litlen_length[ls] + eb + b.dist_length[ds] + deb;
}

template <class Or>
MPVG_HD_INLINE void put_token(BitStream<Or>& out, uint32_t t, const BlockCode& b) {
  const uint32_t len = token_length(t);
  if (!len) {
    out.put(b.litlen_code[t], b.litlen_length[t]);
    return;
  }
  int eb, deb;
  uint32_t ex, dex;
  const int ls = length_symbol(len, eb, ex);
  const int ds = distance_symbol(token_distance(t), deb, dex);
  out.put(b.litlen_code[ls], b.litlen_length[ls]);
  if (eb) out.put(ex, eb);
  out.put(b.dist_code[ds], b.dist_length[ds]);
  if (deb) out.put(dex, deb);
}

// A chunk's size in bytes written as a dynamic block: its header, tokens
// and end-of-block code, then (unless final) an empty stored block's 3
// header bits, the padding to a byte and LEN, NLEN.
MPVG_HD_INLINE size_t dynamic_bytes(uint64_t bits_before_end, const BlockCode& b, bool final) {
  const uint64_t bits = bits_before_end + b.litlen_length[kEndOfBlock];
  return final ? static_cast<size_t>((bits + 7) / 8) : static_cast<size_t>((bits + 3 + 7) / 8 + 4);
}

// ... and as stored blocks.
MPVG_HD_INLINE size_t stored_bytes(size_t n) {
  const size_t blocks = n ? (n + kStoredBlock - 1) / kStoredBlock : 1;
  return n + 5 * blocks;
}

// The end of a dynamic chunk, its tokens' bits ending at bit `at`.
template <class Or>
MPVG_HD_INLINE void put_block_end(uint32_t* words, uint64_t at, const BlockCode& b, bool final, const Or& combine) {
  BitStream<Or> out(words, at, combine);
  out.put(b.litlen_code[kEndOfBlock], b.litlen_length[kEndOfBlock]);
  if (!final) {
    out.put(0, 3);                        // BFINAL 0, BTYPE 00
    out.put(0, (8 - out.pending % 8) % 8);  // to the byte
    out.put(0xffff0000u, 32);              // LEN 0, NLEN 0xffff
  }
  out.flush();
}

// Byte j of data[begin, begin + n) written as stored blocks (3.2.4), the
// last one final where `final`: header byte, LEN, NLEN, then the bytes.
MPVG_HD_INLINE uint8_t stored_byte(const uint8_t* data, size_t n, bool final, size_t j) {
  const size_t block = j / (kStoredBlock + 5), at = j % (kStoredBlock + 5);
  const size_t first = block * kStoredBlock;
  const size_t len = n - first < kStoredBlock ? n - first : kStoredBlock;
  const bool last = first + len == n;
  switch (at) {
    case 0: return final && last ? 1 : 0;
    case 1: return static_cast<uint8_t>(len);
    case 2: return static_cast<uint8_t>(len >> 8);
    case 3: return static_cast<uint8_t>(~len);
    case 4: return static_cast<uint8_t>(~len >> 8);
    default: return data[first + at - 5];
  }
}

// Adler-32 (RFC 1950 8.2) in parts: for bytes b_0..b_{n-1}, A = sum b_i and
// B = sum (n - i) b_i, both mod 65521; parts join in order.
constexpr uint32_t kAdlerBase = 65521;

struct AdlerPart {
  uint32_t a = 0, b = 0;
  uint64_t n = 0;
};

MPVG_HD_INLINE AdlerPart adler_part(const uint8_t* data, size_t n) {
  AdlerPart p;
  p.n = n;
  uint64_t a = 0, b = 0;
  for (size_t i = 0; i < n; i++) {
    a += data[i];
    b += (n - i) * uint64_t(data[i]);
    if ((i & 4095) == 4095) {
      a %= kAdlerBase;
      b %= kAdlerBase;
    }
  }
  p.a = static_cast<uint32_t>(a % kAdlerBase);
  p.b = static_cast<uint32_t>(b % kAdlerBase);
  return p;
}

// The part of x's bytes followed by y's.
MPVG_HD_INLINE AdlerPart adler_join(const AdlerPart& x, const AdlerPart& y) {
  AdlerPart r;
  r.n = x.n + y.n;
  r.a = static_cast<uint32_t>((uint64_t(x.a) + y.a) % kAdlerBase);
  r.b = static_cast<uint32_t>((uint64_t(x.b) + (y.n % kAdlerBase) * x.a + y.b) % kAdlerBase);
  return r;
}

// The checksum of the whole: s1 = 1 + A, s2 = n + B.
MPVG_HD_INLINE uint32_t adler_value(const AdlerPart& p) {
  const uint32_t s1 = static_cast<uint32_t>((1 + uint64_t(p.a)) % kAdlerBase);
  const uint32_t s2 = static_cast<uint32_t>((p.n % kAdlerBase + p.b) % kAdlerBase);
  return s2 << 16 | s1;
}

}  // namespace mpvg::deflate
