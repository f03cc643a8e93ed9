// svg2png: renders an SVG document to a PNG.
#include <chrono>
#include <cstdio>
#include <exception>

#include "apps/cli.h"
#include "apps/image_io.h"
#include "core/error.h"
#include "gpu/backend.h"
#include "parsers/svg/svg_parser.h"

int main(int argc, char** argv) {
  using namespace mpvg;
  cli::Options opt;
  try {
    if (!cli::parse(argc, argv, "svg2png", "svg", opt)) return 0;
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "svg2png: %s\n", e.message.c_str());
    return 2;
  }
  try {
    // Strokes are converted for the output's pixels (tolerance, hairlines).
    svg::ParseOptions parse_options;
    parse_options.allowed_dirs = opt.allow_read;
    parse_options.view = [&opt](double w, double h) {
      int width, height;
      Affine view;
      cli::output_geometry(opt, w, h, &width, &height, &view);
      return view;
    };
    const auto t0 = std::chrono::steady_clock::now();
    svg::ParseResult doc = svg::parse_svg_file(opt.positional[0], parse_options);
    const double parse_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (!opt.quiet)
      for (const std::string& w : doc.warnings) std::fprintf(stderr, "svg2png: warning: %s\n", w.c_str());
    int width, height;
    Affine view;
    cli::output_geometry(opt, doc.scene.width, doc.scene.height, &width, &height, &view);
    RenderStats stats;
    const ImageF img = render(doc.scene, cli::render_options(opt, width, height, view), &stats);
    if (!stats.note.empty() && !opt.quiet) std::fprintf(stderr, "svg2png: note: %s\n", stats.note.c_str());
    if (opt.bits == 16)
      write_png_rgba16(opt.output, width, height, to_rgba16(img, opt.gamma));
    else
      write_png_rgba8(opt.output, width, height, to_rgba8(img, opt.gamma));
    if (opt.stats) {
      std::fprintf(stderr, "parse %.3f ms (stroke %.3f ms, %zu strokes)\n", parse_ms, doc.stroke_seconds * 1e3,
                   doc.stroked_paths);
      std::fprintf(stderr, "%s", cli::format_stats(stats).c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "svg2png: %s\n", e.what());
    return 1;
  }
  return 0;
}
