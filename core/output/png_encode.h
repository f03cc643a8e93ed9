// A PNG's pixels as compressed, what the PNG stage gives (its filtering,
// core/output/png_filter.h, and deflate, core/output/deflate.h, are run by
// the CPU executor, cpu/png_encode.h, and the GPU's, gpu/png_encode.cu,
// to the same bytes); lib/output/png_writer.h wraps it in the PNG
// container.
#pragma once
#include <cstdint>
#include <vector>

namespace mpvg::png {

// A PNG's pixels as compressed: the channels written and the zlib stream
// of the filtered rows (what the IDAT chunks hold).
struct ImageData {
  int channels = 4;  // 3: every pixel opaque, written as RGB; 4: RGBA
  std::vector<uint8_t> zlib;
};

// A PNG's rows filtered (core/output/png_filter.h: a filter type byte, then
// the row's filtered bytes), not yet deflated: what the PNG stage's first
// half gives where the image was rendered (FrameRenderer::render_filtered),
// so that only deflate is left for the CPU (png::encode_filtered).
struct FilteredRows {
  int channels = 4;           // 3: every pixel opaque, written as RGB; 4: RGBA
  std::vector<uint8_t> rows;  // height rows of 1 + width * channels bytes
};

}  // namespace mpvg::png
