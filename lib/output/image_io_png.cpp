// The image writer of builds without OpenImageIO: mpvg's own PNG encoder.
#include "lib/output/image_io.h"
#include "lib/output/png_writer.h"

namespace mpvg {

void write_png_rgba8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba) {
  // One image, every core: rows filtered and deflated in strips.
  png::EncodeOptions options;
  options.threads = 0;
  png::write_file(path, png::encode_rgba8(width, height, rgba.data(), options));
}

void write_png_rgba16(const std::string& path, int width, int height, const std::vector<uint16_t>& rgba) {
  png::EncodeOptions options;
  options.threads = 0;
  png::write_file(path, png::encode_rgba16(width, height, rgba.data(), options));
}

std::string image_io_library() { return "mpvg PNG encoder, " + png::compressor(); }

}  // namespace mpvg
