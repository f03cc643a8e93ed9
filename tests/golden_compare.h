// Golden-image comparison shared by the golden tests (test_golden.cpp for
// SVG, test_pdf_golden.cpp for PDF): one tolerance, one failure panel, one
// way to regenerate.
//
// A reference is an 8-bit RGBA PNG reviewed by eye when it was made. The
// comparison is mpvg-compare's (lib/compare/image_compare.h), premultiplied, in
// 1/255 steps: it passes when no channel is off by more than 2 and at most
// 0.1 % of the pixels are off by more than 1. A mismatch writes expected | |difference| x 8 | actual into the given
// panel path and reports the numbers. MPVG_UPDATE_GOLDEN=1 rewrites the
// reference instead of comparing.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "lib/compare/image_compare.h"
#include "lib/output/image_io.h"
#include "frame/frame.h"
#include "parsers/svg/svg_parser.h"
#include "parsers/svg/svg_resources.h"
#include "tests/catch.h"

namespace mpvg::golden {

// Golden SVGs render at their intrinsic size, as svg2png without size
// options: po's view sets o's size and view (strokes are prepared for that
// scale while parsing).
inline void at_intrinsic_size(svg::ParseOptions& po, RenderOptions& o) {
  po.view = [&o](double w, double h) {
    o.width = static_cast<int>(std::lround(w));
    o.height = static_cast<int>(std::lround(h));
    o.view = Affine::scale(o.width / w, o.height / h);
    return o.view;
  };
}

// The files of `dir` whose extension is `ext` (".svg", ".pdf"), sorted.
inline std::vector<std::filesystem::path> inputs(const std::filesystem::path& dir, const std::string& ext) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ext) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// expected | |difference| x 8 | actual, each over a light checkerboard.
inline void write_failure_panel(const std::string& path, int w, int h, const std::vector<uint8_t>& expected,
                                const std::vector<uint8_t>& actual) {
  const int W = 3 * w + 8;
  std::vector<uint8_t> out(size_t(W) * h * 4, 255);
  auto over_checker = [&](const uint8_t* p, int x, int y, uint8_t* q) {
    const int bg = ((x / 4 + y / 4) % 2) ? 255 : 220;
    const int a = p[3];
    for (int c = 0; c < 3; c++) q[c] = static_cast<uint8_t>((p[c] * a + bg * (255 - a) + 127) / 255);
    q[3] = 255;
  };
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      const size_t i = (size_t(y) * w + x) * 4;
      over_checker(&expected[i], x, y, &out[(size_t(y) * W + x) * 4]);
      over_checker(&actual[i], x, y, &out[(size_t(y) * W + 2 * w + 8 + x) * 4]);
      int d = 0;
      for (int c = 0; c < 4; c++) d = std::max(d, std::abs(int(expected[i + c]) - int(actual[i + c])));
      uint8_t* q = &out[(size_t(y) * W + w + 4 + x) * 4];
      const int v = std::max(0, 255 - 8 * d);
      q[0] = 255;
      q[1] = q[2] = static_cast<uint8_t>(v);
      q[3] = 255;
    }
  write_png_rgba8(path, W, h, out);
}

// `actual` (w x h straight RGBA8) against the reference PNG `ref`, or,
// with MPVG_UPDATE_GOLDEN set, written to `ref`. On a mismatch the panel
// goes to `panel`. Reports through Catch2: call it inside a test case.
inline void check_golden(const std::string& name, const std::filesystem::path& ref, int w, int h,
                         const std::vector<uint8_t>& actual, const std::filesystem::path& panel) {
  if (std::getenv("MPVG_UPDATE_GOLDEN") != nullptr) {
    write_png_rgba8(ref.string(), w, h, actual);
    WARN("regenerated " << ref.string() << ": review it before committing");
    return;
  }
  // Read by the SVG frontend's own image decoder (straight alpha, as stored).
  std::ifstream file(ref, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::string why;
  const std::shared_ptr<Image> ref_image = svg::detail::decode_raster(bytes, &why);
  INFO(ref.string() << ": " << why);
  REQUIRE(ref_image);
  REQUIRE(ref_image->bits == 8);
  REQUIRE(ref_image->width == w);
  REQUIRE(ref_image->height == h);
  const std::vector<uint8_t>& expected = ref_image->rgba8;
  // Premultiplied, in 1/255 steps (lib/compare/image_compare.h: mpvg-compare's
  // comparison): no channel off by more than 2, at most 0.1 % of the
  // pixels off by more than 1.
  image_compare::Options o;
  o.fail = 1.5 / 255;
  o.failpercent = 0.1;
  o.hardfail = 2.5 / 255;
  o.warn = o.fail;
  const image_compare::Result r = image_compare::compare(image_compare::from_straight8(expected.data(), w, h, 4),
                                                         image_compare::from_straight8(actual.data(), w, h, 4), o);
  const double frac = double(r.failed) / (double(w) * h);
  if (r.verdict == image_compare::Verdict::Fail) {
    std::filesystem::create_directories(panel.parent_path());
    write_failure_panel(panel.string(), w, h, expected, actual);
  }
  INFO(name << ": max difference " << r.max_difference * 255 << "/255, " << frac * 100
            << "% of pixels off by more than 1/255 (panel in " << panel.string() << " on failure)");
  CHECK(r.max_difference <= o.hardfail);
  CHECK(frac <= 0.001);
}

}  // namespace mpvg::golden
