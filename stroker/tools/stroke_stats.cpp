// stroke_stats: how long converting an SVG document's strokes to fills
// takes (stroke::stroke_to_fill, timed inside the SVG frontend), against
// the whole parse, and how much geometry the strokes add.
//
// usage: stroke_stats [-w WIDTH_PIXELS] [-r REPEATS] FILE.svg...
// (strokes prepared for rendering at that width, 1024 by default, as the
// paper's benchmark)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "parsers/svg/svg_parser.h"

int main(int argc, char** argv) {
  mpvg::svg::ParseOptions options = mpvg::svg::ParseOptions::at_width(1024);
  int repeats = 5;
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; i += 2) {
    if (i + 1 >= argc) break;
    if (!std::strcmp(argv[i], "-w")) options = mpvg::svg::ParseOptions::at_width(std::max(1, std::atoi(argv[i + 1])));
    if (!std::strcmp(argv[i], "-r")) repeats = std::max(1, std::atoi(argv[i + 1]));
  }
  if (i >= argc) {
    std::fprintf(stderr, "usage: stroke_stats [-w WIDTH_PIXELS] [-r REPEATS] FILE.svg...\n");
    return 2;
  }
  for (; i < argc; i++) {
    try {
      // The best of a few runs, for both numbers.
      double best_parse = 1e300, best_stroke = 1e300;
      mpvg::svg::ParseResult r;
      for (int k = 0; k < repeats; k++) {
        const auto t0 = std::chrono::steady_clock::now();
        r = mpvg::svg::parse_svg_file(argv[i], options);
        const double parse = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        best_parse = std::min(best_parse, parse);
        best_stroke = std::min(best_stroke, r.stroke_seconds);
      }
      size_t segments = 0;
      for (const mpvg::Path& g : r.scene.geometries) segments += g.segments().size();
      std::printf("%s: %zu strokes converted in %.2f ms (parse %.2f ms in all, strokes %.0f%% of it); "
                  "%zu paths, %zu segments in the scene\n",
                  argv[i], r.stroked_paths, best_stroke * 1e3, best_parse * 1e3, 100 * best_stroke / best_parse,
                  r.scene.paths.size(), segments);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "stroke_stats: %s\n", e.what());
      return 1;
    }
  }
  return 0;
}
