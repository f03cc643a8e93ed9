// Golden images of text in scripts and features the resvg suite covers
// thinly: Arabic joining and bidi reordering, Devanagari reordering and
// conjuncts, vertical writing, a variable font's weight axis. Each
// testdata/golden-text/NAME.svg is rendered on the CPU backend (box
// filter, 32 samples, seed 0, sRGB) with only these fonts, no system
// ones, so that the render does not depend on the machine's font set:
//   testdata/fonts (MpvgTestVF.ttf, made by scripts/make-test-font.py),
//   Debian's fonts-dejavu-core, fonts-lohit-deva, fonts-wqy-microhei.
// Without one of those packages the test says so and skips. Tolerance
// and failure panels: golden_compare.h; references were reviewed by eye
// and are regenerated only on purpose (MPVG_UPDATE_GOLDEN=1).
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

TEST_CASE("golden images of text", "[golden][text]") {
  const std::vector<std::string> system_dirs = {"/usr/share/fonts/truetype/dejavu",
                                                "/usr/share/fonts/truetype/lohit-devanagari",
                                                "/usr/share/fonts/truetype/wqy"};
  for (const std::string& d : system_dirs)
    if (!fs::exists(d)) {
      WARN("skipped: " << d
                       << " is missing (Debian packages fonts-dejavu-core, fonts-lohit-deva, fonts-wqy-microhei)");
      return;
    }
  const fs::path dir = fs::path(MPVG_SOURCE_DIR) / "testdata" / "golden-text";
  const std::vector<fs::path> svgs = golden::inputs(dir, ".svg");
  REQUIRE(svgs.size() >= 4);
  for (const fs::path& svg : svgs) {
    const std::string name = svg.stem().string();
    SECTION(name) {
      RenderOptions o;
      svg::ParseOptions po;
      po.font_dirs = {(fs::path(MPVG_SOURCE_DIR) / "testdata" / "fonts").string()};
      po.font_dirs.insert(po.font_dirs.end(), system_dirs.begin(), system_dirs.end());
      po.system_fonts = false;
      golden::at_intrinsic_size(po, o);
  const svg::ParseResult doc = svg::parse_svg_file(svg.string(), po);
      for (const std::string& w : doc.warnings) INFO(w);
      CHECK(doc.warnings.empty());
      o.samples = 32;
      o.seed = 0;
      o.backend = Backend::Cpu;
      const std::vector<uint8_t> actual = to_rgba8(render_cpu(doc.scene, o), o.gamma);
      golden::check_golden(name, fs::path(svg).replace_extension(".png"), o.width, o.height, actual,
                           fs::path(MPVG_BINARY_DIR) / "golden-failures" / (name + ".png"));
    }
  }
}
