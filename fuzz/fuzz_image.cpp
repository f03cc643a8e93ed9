// fuzz_image: raster image decoding as an SVG <image> does it
// (parsers/svg/svg_image.cpp: decode_raster on the fetched bytes): PNG by
// libpng in the process, JPEG, GIF and WebP by OpenImageIO in its module
// (mpvg_oiio_decoder.so, where the build has it). The decoded image must be
// as large as its header says. The same bytes then go through gunzip
// (svgz images) with a small output bound.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "parsers/svg/svg_resources.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mpvg::svg::detail;
  const std::vector<uint8_t> bytes(data, data + size);
  std::string why;
  // The <image> path's bound is 2^28 pixels; a smaller one here keeps every
  // input's memory under libFuzzer's -rss_limit_mb (the bound itself is
  // what is tested, not its size).
  DecodeRequest request;
  request.max_pixels = request.max_whole_pixels = size_t(1) << 20;
  if (std::shared_ptr<mpvg::Image> image = decode_raster(bytes, &why, request)) {
    if (image->width <= 0 || image->height <= 0) __builtin_trap();
    const size_t n = size_t(image->width) * size_t(image->height) * 4;
    if (image->bits == 8 ? image->rgba8.size() != n : image->rgba16.size() != n) __builtin_trap();
  }
  (void)gunzip(bytes, &why, size_t(1) << 20);
  return 0;
}
