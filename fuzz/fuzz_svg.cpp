// fuzz_svg: the SVG frontend end to end. The input is an SVG document,
// parsed as svg2png parses it (parse_svg_string; relative references
// resolve in the scratch folder, the only folder it may read; fonts: the
// two test fonts, not the system's), then encoded and rendered on the CPU at
// most 32 x 32 pixels (fuzz_render.h). mpvg::Error (malformed XML, no
// size, ...) is an expected outcome; anything else escaping is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "fuzz/fuzz_render.h"
#include "parsers/svg/svg_parser.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mpvg;
  const std::string& dir = fuzz::scratch_dir();
  svg::ParseOptions po;
  po.system_fonts = false;
  po.font_dirs = {dir + "/fonts"};
  po.threads = 1;
  po.view = [](double w, double h) {
    int width, height;
    Affine view;
    if (!fuzz::output_view(w, h, &width, &height, &view)) return Affine::scale(1, 1);
    return view;
  };
  try {
    svg::ParseResult doc =
        svg::parse_svg_string(std::string_view(reinterpret_cast<const char*>(data), size), dir, po);
    int width, height;
    Affine view;
    if (!fuzz::output_view(doc.scene.width, doc.scene.height, &width, &height, &view)) return 0;
    fuzz::render_small(doc.scene, view, width, height, static_cast<unsigned>(size));
  } catch (const Error&) {
  }
  return 0;
}
