// Golden images: every testdata/golden/NAME.svg rendered on the CPU backend
// (box filter, 32 samples, seed 0, sRGB) must match NAME.png, which was
// reviewed by eye when it was made.
//
// A mismatch writes expected | difference | actual into
// <build>/golden-failures/NAME.png and reports the numbers. References are
// regenerated only on purpose: MPVG_UPDATE_GOLDEN=1 ctest -R golden.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "apps/image_io.h"
#include "core/renderer.h"
#include "parsers/svg/svg_parser.h"
#include "parsers/svg/svg_resources.h"
#include "tests/catch.h"

using namespace mpvg;
namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> render_golden(const std::string& svg_path, int* w, int* h) {
  // Rendered at the intrinsic size, as svg2png without size options; the
  // strokes are prepared for that scale, with the view the render uses.
  RenderOptions o;
  svg::ParseOptions po;
  po.view = [&o](double w, double h) {
    o.width = static_cast<int>(std::lround(w));
    o.height = static_cast<int>(std::lround(h));
    o.view = Affine::scale(o.width / w, o.height / h);
    return o.view;
  };
  const svg::ParseResult doc = svg::parse_svg_file(svg_path, po);
  o.samples = 32;
  o.seed = 0;
  o.backend = Backend::Cpu;
  *w = o.width;
  *h = o.height;
  return to_rgba8(render_cpu(doc.scene, o), o.gamma);
}

// expected | |difference| x 8 | actual, each over a light checkerboard.
void write_failure_panel(const std::string& path, int w, int h, const std::vector<uint8_t>& expected,
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

}  // namespace

TEST_CASE("golden images", "[golden]") {
  const fs::path dir = fs::path(MPVG_SOURCE_DIR) / "testdata" / "golden";
  const bool update = std::getenv("MPVG_UPDATE_GOLDEN") != nullptr;
  std::vector<fs::path> svgs;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".svg") svgs.push_back(e.path());
  std::sort(svgs.begin(), svgs.end());
  REQUIRE(svgs.size() >= 6);
  for (const fs::path& svg : svgs) {
    const std::string name = svg.stem().string();
    const fs::path ref = fs::path(svg).replace_extension(".png");
    SECTION(name) {
      int w, h;
      const std::vector<uint8_t> actual = render_golden(svg.string(), &w, &h);
      if (update) {
        write_png_rgba8(ref.string(), w, h, actual);
        WARN("regenerated " << ref.string() << ": review it before committing");
        continue;
      }
      // Read by the frontend's own image decoder (straight alpha, as stored).
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
      // Premultiplied comparison, in 1/255 steps.
      int max_diff = 0;
      size_t over_one = 0;
      for (size_t i = 0; i < expected.size(); i += 4) {
        int d = 0;
        for (int c = 0; c < 4; c++) {
          const int e = c < 3 ? (expected[i + c] * expected[i + 3] + 127) / 255 : expected[i + 3];
          const int a = c < 3 ? (actual[i + c] * actual[i + 3] + 127) / 255 : actual[i + 3];
          d = std::max(d, std::abs(e - a));
        }
        max_diff = std::max(max_diff, d);
        over_one += d > 1 ? 1 : 0;
      }
      const double frac = double(over_one) / (double(w) * h);
      if (max_diff > 2 || frac > 0.001) {
        const fs::path out_dir = fs::path(MPVG_BINARY_DIR) / "golden-failures";
        fs::create_directories(out_dir);
        write_failure_panel((out_dir / (name + ".png")).string(), w, h, expected, actual);
      }
      INFO(name << ": max difference " << max_diff << "/255, " << frac * 100
                << "% of pixels off by more than 1/255 (panel in golden-failures/ on failure)");
      CHECK(max_diff <= 2);
      CHECK(frac <= 0.001);
    }
  }
}
