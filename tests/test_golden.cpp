// Golden images: every testdata/golden/NAME.svg rendered on the CPU backend
// (box filter, 32 samples, seed 0, sRGB) must match NAME.png, which was
// reviewed by eye when it was made.
//
// A mismatch writes expected | difference | actual into
// <build>/golden-failures/NAME.png and reports the numbers (comparison and
// tolerance in golden_compare.h). References are regenerated only on
// purpose: MPVG_UPDATE_GOLDEN=1 ctest -R golden.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "frame/frame.h"
#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "tests/golden_compare.h"
#include "cpu/cpu_frame.h"

using namespace mpvg;
namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> render_golden(const std::string& svg_path, int* w, int* h, Filter filter = Filter::Box,
                                   PatternKind pattern = PatternKind::Stratified, int threads = 0) {
  RenderOptions o;
  svg::ParseOptions po;
  golden::at_intrinsic_size(po, o);
  const svg::ParseResult doc = svg::parse_svg_file(svg_path, po);
  o.samples = 32;
  o.seed = 0;
  o.filter = filter;
  o.pattern = pattern;
  o.threads = threads;
  o.backend = Backend::Cpu;
  *w = o.width;
  *h = o.height;
  return to_rgba8(render_cpu(doc.scene, o), o.gamma);
}

}  // namespace

TEST_CASE("golden images", "[golden]") {
  const fs::path dir = fs::path(MPVG_SOURCE_DIR) / "testdata" / "golden";
  const std::vector<fs::path> svgs = golden::inputs(dir, ".svg");
  REQUIRE(svgs.size() >= 6);
  for (const fs::path& svg : svgs) {
    const std::string name = svg.stem().string();
    const fs::path ref = fs::path(svg).replace_extension(".png");
    SECTION(name) {
      int w, h;
      const std::vector<uint8_t> actual = render_golden(svg.string(), &w, &h);
      golden::check_golden(name, ref, w, h, actual,
                           fs::path(MPVG_BINARY_DIR) / "golden-failures" / (name + ".png"));
    }
  }
}

// Issue 32: the CPU executor's bytes do not depend on its thread count
// (fixed-point accumulation, one line of the prefilter a task), at the box
// and the cardinal presets. (CPU against CUDA: test_gpu.)
TEST_CASE("golden images: the same bytes with one thread and with every core", "[golden]") {
  const fs::path dir = fs::path(MPVG_SOURCE_DIR) / "testdata" / "golden";
  for (const fs::path& svg : golden::inputs(dir, ".svg")) {
    INFO(svg.filename().string());
    for (bool cardinal : {false, true}) {
      const Filter f = cardinal ? Filter::Cardinal : Filter::Box;
      const PatternKind k = cardinal ? PatternKind::BlueNoise : PatternKind::Stratified;
      int w, h;
      const std::vector<uint8_t> one = render_golden(svg.string(), &w, &h, f, k, 1);
      const std::vector<uint8_t> all = render_golden(svg.string(), &w, &h, f, k, 3);
      CHECK(one == all);
    }
  }
}
