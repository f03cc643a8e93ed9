// The PNG stage's filtering and compression on the GPU, as a plain C++
// interface for tests and tools (a frame's own goes through
// gpu::Context::render_png, on the image it rendered).
#pragma once
#include <cstdint>

#include "core/output/png_encode.h"

namespace mpvg::gpu {

// png::compress_rgba8 run on the current device: the pixels are uploaded,
// filtered and deflated there, the stream copied back.
png::ImageData compress_rgba8_gpu(const uint8_t* rgba, int width, int height);

}  // namespace mpvg::gpu
