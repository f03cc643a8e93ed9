// Print preview's files (lib/output/ink_output.h).
#include "lib/output/ink_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "lib/output/output_file.h"
#include "lib/output/png_writer.h"
#include "core/error.h"
#include "core/inks/inks.h"

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

// Is s well-formed UTF-8 (no overlong forms, surrogates or values past
// U+10FFFF)?
bool valid_utf8(const std::string& s) {
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const int n = c < 0x80 ? 0 : (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : -1;
    if (n < 0 || i + size_t(n) >= s.size()) return false;
    uint32_t v = n == 0 ? c : c & (0x3f >> n);
    for (int k = 1; k <= n; k++) {
      const unsigned char d = static_cast<unsigned char>(s[i + k]);
      if ((d >> 6) != 2) return false;
      v = v << 6 | (d & 0x3f);
    }
    if ((n == 1 && v < 0x80) || (n == 2 && v < 0x800) || (n == 3 && v < 0x10000) || v > 0x10ffff ||
        (v >= 0xd800 && v < 0xe000))
      return false;
    i += n + 1;
  }
  return true;
}

// FNV-1a, 32 bits: the tag of a shortened name.
uint32_t fnv1a(const std::string& s) {
  uint32_t h = 2166136261u;
  for (unsigned char c : s) h = (h ^ c) * 16777619u;
  return h;
}

}  // namespace

std::string plate_name(const std::string& ink) {
  // Bytes that name nothing else than themselves in a file name on every
  // common file system; '%' starts an escape.
  static const std::string reserved = "/\\:*?\"<>|%";
  const bool utf8 = valid_utf8(ink);
  std::string out;
  std::vector<size_t> cuts;  // character boundaries of the output
  for (unsigned char c : ink) {
    const bool keep = c >= 0x80 ? utf8 : c >= 0x20 && c < 0x7f && reserved.find(char(c)) == std::string::npos;
    if (!keep || c < 0x80 || c >= 0xc0) cuts.push_back(out.size());  // before an escape, ASCII or a lead byte
    if (keep) {
      out += char(c);
    } else {
      static const char hex[] = "0123456789ABCDEF";
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (out.size() <= kMaxPlateName) return out;
  // Too long for a file name beside its prefix: cut at a character
  // boundary, tagged with the whole name's hash.
  size_t at = 0;
  for (size_t end : cuts)
    if (end <= kMaxPlateName - 9) at = end;
  char tag[16];
  std::snprintf(tag, sizeof tag, "~%08x", fnv1a(ink));
  return out.substr(0, at) + tag;
}

std::vector<std::string> plate_names(const std::vector<std::string>& inks) {
  std::vector<std::string> out;
  std::vector<std::string> folded;  // ASCII case folded: names a case-blind file system tells apart
  for (const std::string& ink : inks) {
    const std::string base = plate_name(ink);
    std::string name = base;
    auto fold = [](std::string s) {
      for (char& c : s) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
      return s;
    };
    for (int k = 2; std::find(folded.begin(), folded.end(), fold(name)) != folded.end(); k++)
      name = base + "~" + std::to_string(k);
    folded.push_back(fold(name));
    out.push_back(name);
  }
  return out;
}

namespace {

// "out-1.tif" with "(Cyan)" before its extension; the name is a plate
// name (plate_names), and the result names a file in out's own folder.
std::string plane_path(const std::string& out, const std::string& name) {
  const size_t at = extension_at(out);
  const std::string path = out.substr(0, at) + "(" + name + ")" + out.substr(at);
  if (name.find('/') != std::string::npos ||
      std::filesystem::path(path).parent_path() != std::filesystem::path(out).parent_path())
    throw Error("a plate's file name would leave the output's folder: '" + path + "'");
  return path;
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
  // Every plate's path first: a name that cannot be written fails the
  // page before any plate is.
  const std::vector<std::string> plates = plate_names(page.names);
  std::vector<std::string> paths;
  for (const std::string& name : plates) paths.push_back(plane_path(out, name));
  for (size_t i = 0; i < n; i++) {
    for (size_t p = 0; p < pixels; p++) plane[p] = static_cast<uint8_t>(255 - inks[p * n + i]);
    write_output(paths[i], image::encode(image::Format::Tiff, g, options));
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
