// PNG output for the command-line tools and tests, through mpvg's own
// encoder (lib/output/png_writer.h): no image library to load at start-up.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mpvg {

// Writes straight-alpha RGBA, 8 or 16 bits per channel. path "-" writes to
// standard output. Throws mpvg::Error.
void write_png_rgba8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba);
void write_png_rgba16(const std::string& path, int width, int height, const std::vector<uint16_t>& rgba);

// Which library does the work ("mpvg PNG encoder, libdeflate 1.14").
std::string image_io_library();

}  // namespace mpvg
