// The PNG stage's filtering and compression on the CPU executor: an RGBA
// image becomes its filtered rows (core/output/png_filter.h), and those the zlib
// stream (RFC 1950) of a PNG's IDAT chunks, deflated by core/output/deflate.h's
// per-piece and per-chunk code in loops. The GPU executor
// (gpu/png_encode.cu) runs the same code before the image is copied back,
// so that only compressed bytes cross the bus: both give the same bytes.
// lib/output/png_writer.h wraps the stream in the PNG container.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/output/png_encode.h"

namespace mpvg::png {

// The filtered rows of a width x height RGBA image into `out`; returns the
// channels written: 3 where every pixel is opaque (as pdftoppm and mutool
// write pages), else 4. 16-bit samples are native-endian. threads: for
// this one image (0: every core; batches keep one per image).
int filter_image(const uint8_t* rgba, int width, int height, int threads, std::vector<uint8_t>& out);
int filter_image(const uint16_t* rgba, int width, int height, int threads, std::vector<uint8_t>& out);

// filter_image and deflate_zlib: an 8-bit image's PNG data.
ImageData compress_rgba8(const uint8_t* rgba, int width, int height, int threads = 1);

// The zlib stream of n filtered bytes (rows of `stride` bytes, `bpp`
// bytes per pixel) by the parallel deflate of core/output/deflate.h, into `out`.
void deflate_zlib(const uint8_t* data, size_t n, uint32_t bpp, uint32_t stride, int threads, std::vector<uint8_t>& out);

// ... as stored blocks: no compression (level 0).
void store_zlib(const uint8_t* data, size_t n, std::vector<uint8_t>& out);

}  // namespace mpvg::png
