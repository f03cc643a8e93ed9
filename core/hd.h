// Host/device annotation shared by every per-element function of the pipeline.
//
// The paper's per-element decisions (implicit tests, split rules, pruning
// rules, the flat-clipping machine, filter weights) are written once in core/
// headers. nvcc compiles them into kernels (gpu/); g++ compiles the very same
// source for the CPU executor (core/), where MPVG_HD expands to nothing.
#pragma once

#if defined(__CUDACC__)
#define MPVG_HD __host__ __device__
#define MPVG_HD_INLINE __host__ __device__ __forceinline__
// Kept out of line in kernels (cold, large paths such as a pattern tile's
// evaluation, so that they do not raise the register count of the hot loop).
#define MPVG_HD_NOINLINE __host__ __device__ __noinline__
#define MPVG_HD_ALWAYS_INLINE __host__ __device__ __forceinline__
#else
#define MPVG_HD
#define MPVG_HD_INLINE inline
#define MPVG_HD_NOINLINE
// Small functions of loops the host compiler must vectorise (a call in the
// body, left out of line by its heuristics, stops it).
#if defined(__GNUC__)
#define MPVG_HD_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define MPVG_HD_ALWAYS_INLINE inline
#endif
#endif
