// PNG output for the command-line tools and tests. The product
// writes through OpenImageIO; builds configured with MPVG_IMAGE_IO=png (the
// GPU benchmark host, which cannot carry OpenImageIO) use libpng directly.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mpvg {

// Writes straight-alpha RGBA, 8 or 16 bits per channel. path "-" writes to
// standard output. Throws mpvg::Error.
void write_png_rgba8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba);
void write_png_rgba16(const std::string& path, int width, int height, const std::vector<uint16_t>& rgba);

// Which library does the work ("OpenImageIO 2.4.7" or "libpng 1.6.39").
std::string image_io_library();

}  // namespace mpvg
