// Print preview's files (apps/ink_output.h).
#include "apps/ink_output.h"

#include <cmath>

#include "apps/output_file.h"
#include "apps/png_writer.h"
#include "core/inks.h"

namespace mpvg {

std::vector<uint8_t> gather_inks(const InkPage& page, int width_all, int height, const uint8_t* rgba) {
  const size_t n = page.names.size();
  std::vector<uint8_t> out(size_t(page.width) * height * n);
  for (int y = 0; y < height; y++)
    for (int x = 0; x < page.width; x++)
      for (size_t i = 0; i < n; i++) {
        const size_t column = (i / 3) * size_t(page.width + page.gap) + x;
        out[(size_t(y) * page.width + x) * n + i] = rgba[(size_t(y) * width_all + column) * 4 + i % 3];
      }
  return out;
}

namespace {

// Where the extension of a path's file name starts (its size if none).
size_t extension_at(const std::string& path) {
  const size_t dot = path.rfind('.');
  const size_t slash = path.rfind('/');
  return dot != std::string::npos && (slash == std::string::npos || dot > slash) ? dot : path.size();
}

// "out-1.tif" with "(Cyan)" before its extension.
std::string plane_path(const std::string& out, const std::string& name) {
  const size_t at = extension_at(out);
  return out.substr(0, at) + "(" + name + ")" + out.substr(at);
}

std::string with_extension(const std::string& out, const char* extension) {
  return out.substr(0, extension_at(out)) + "." + extension;
}

}  // namespace

void write_ink_page(const InkPage& page, const std::string& out, int width_all, int height, const uint8_t* rgba,
                    const image::EncodeOptions& options) {
  const std::vector<uint8_t> inks = gather_inks(page, width_all, height, rgba);
  const size_t n = page.names.size();
  const size_t pixels = size_t(page.width) * height;
  image::Raster r;
  r.width = page.width;
  r.height = height;
  r.channels = static_cast<int>(n);
  r.cmyk = true;
  r.data = inks.data();
  write_output(out, image::encode(image::Format::Tiff, r, options));
  if (!page.separations || out == "-") return;
  std::vector<uint8_t> plane(pixels);
  image::Raster g;
  g.width = page.width;
  g.height = height;
  g.channels = 1;
  g.data = plane.data();
  for (size_t i = 0; i < n; i++) {
    for (size_t p = 0; p < pixels; p++) plane[p] = static_cast<uint8_t>(255 - inks[p * n + i]);
    write_output(plane_path(out, page.names[i]), image::encode(image::Format::Tiff, g, options));
  }
  std::vector<uint8_t> sim(pixels * 4);
  std::vector<float> v(n);
  for (size_t p = 0; p < pixels; p++) {
    for (size_t i = 0; i < n; i++) v[i] = inks[p * n + i] / 255.0f;
    float rgb[3];
    inks_to_rgb(v.data(), static_cast<int>(n), page.spot_cmyk, rgb);
    for (int k = 0; k < 3; k++) sim[p * 4 + k] = static_cast<uint8_t>(std::lround(rgb[k] * 255));
    sim[p * 4 + 3] = 255;
  }
  write_output(with_extension(out, "png"), png::encode_rgba8(page.width, height, sim.data(), png::EncodeOptions{}));
}

}  // namespace mpvg
