// stroke_stats: how long converting an SVG document's strokes to fills
// takes (stroke::stroke_to_fill, timed inside the SVG frontend), against
// the whole parse, and how much geometry the strokes add.
//
// usage: stroke_stats [-w WIDTH_PIXELS] [-r REPEATS] FILE.svg...
// (strokes prepared for rendering at that width, 1024 by default, as the
// paper's benchmark)
//
// It also runs the stroke stage (core/stroke.h) on the same strokes: on
// the CPU executor (one thread, then every core) and, in a CUDA build with
// a device, on the GPU (device time of its kernels, and the upload of the
// centrelines), with the segments each one makes.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "core/stroke_input.h"
#include "stroker/stroker.h"
#include "parsers/svg/svg_parser.h"
#ifdef MPVG_WITH_CUDA
#include "gpu/backend.h"
#include "gpu/stroke.h"
#endif

int main(int argc, char** argv) {
  mpvg::svg::ParseOptions options = mpvg::svg::ParseOptions::at_width(1024);
  auto best_of = [](int n, auto f) {
    double best = 1e300;
    for (int k = 0; k < n; k++) {
      const auto t0 = std::chrono::steady_clock::now();
      f();
      best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
  };
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
      // The stroke stage on the same strokes.
      mpvg::svg::ParseOptions collect = options;
      collect.collect_strokes = true;
      const mpvg::StrokeBatch batch = mpvg::svg::parse_svg_file(argv[i], collect).strokes;
      // The old stroker on the same batch (its centrelines and styles back
      // as Paths), for its segment count, closing lines included.
      size_t old_segments = 0;
      for (const mpvg::stroking::StrokeRecord& rec : batch.strokes) {
        mpvg::Path p;
        for (const mpvg::stroking::StrokeSubpath& sp : batch.subpaths) {
          if (&rec != &batch.strokes[sp.stroke]) continue;
          p.move_to(sp.start);
          for (uint32_t k = 0; k < sp.segment_count; k++) {
            const mpvg::stroking::Curve& c = batch.segments[sp.first_segment + k].curve;
            if (c.type == mpvg::stroking::CURVE_LINE) p.line_to(c.p[1]);
            if (c.type == mpvg::stroking::CURVE_QUAD) p.quad_to(c.p[1], c.p[2]);
            if (c.type == mpvg::stroking::CURVE_RQUAD) p.rquad_to(c.p[1], c.p[2], c.w);
            if (c.type == mpvg::stroking::CURVE_CUBIC) p.cubic_to(c.p[1], c.p[2], c.p[3]);
          }
          if (sp.flags & mpvg::stroking::SUBPATH_CLOSED) p.close();
        }
        mpvg::stroke::Style st;
        st.width = 2 * rec.h;
        st.join = static_cast<mpvg::stroke::Join>(rec.join);
        st.cap = static_cast<mpvg::stroke::Cap>(rec.cap);
        st.miter_limit = rec.miter_limit;
        st.dashes.assign(batch.dashes.begin() + rec.dash_first, batch.dashes.begin() + rec.dash_first + rec.dash_count);
        st.dash_offset = rec.dash_offset;
        const mpvg::Affine xf{rec.xf[0], rec.xf[1], rec.xf[2], rec.xf[3], rec.xf[4], rec.xf[5]};
        const mpvg::Path g = mpvg::stroke::stroke_to_fill(p, st, xf);
        old_segments += g.segments().size();
        for (const mpvg::Path::Contour& c : g.contours()) {
          if (c.segment_count == 0) continue;
          const mpvg::Path::Segment& last = g.segments()[c.first_segment + c.segment_count - 1];
          const mpvg::Vec2 end = g.points()[last.first_point + mpvg::segment_degree(last.type)];
          if (!(end == g.points()[c.start_point])) old_segments++;
        }
      }
      size_t made = 0;
      const double one = best_of(repeats, [&] { made = mpvg::stroke_cpu(batch, 1).size(); });
      const double all = best_of(repeats, [&] { mpvg::stroke_cpu(batch, 0); });
      std::printf("  stage on the CPU: %zu strokes, %zu centreline segments -> %zu segments (old stroker %zu); "
                  "%.2f ms on one thread, %.2f ms on every core\n",
                  batch.strokes.size(), batch.segments.size(), made, old_segments, one, all);
#ifdef MPVG_WITH_CUDA
      if (mpvg::cuda_available()) {
        mpvg::gpu::StrokeGpuTimes best;
        best.measure_ms = 1e300;
        for (int k = 0; k < repeats + 1; k++) {  // the first run loads the kernels
          mpvg::gpu::StrokeGpuTimes t;
          mpvg::gpu::stroke_gpu(batch, &t);
          if (k > 0 && t.device_ms() < best.device_ms()) best = t;
        }
        std::printf("  stage on the GPU: %zu segments; %.3f ms on the device (measure %.3f, count %.3f, write %.3f), "
                    "upload %.3f ms, %zu launches\n",
                    best.segments, best.device_ms(), best.measure_ms, best.count_ms, best.write_ms, best.upload_ms,
                    best.launches);
        std::printf("   ");
        for (const auto& [name, ms] : best.kernels) std::printf(" %s %.3f", name, ms);
        std::printf(" (ms; %zu round trips)\n", best.round_trips);
      }
#endif
    } catch (const std::exception& e) {
      std::fprintf(stderr, "stroke_stats: %s\n", e.what());
      return 1;
    }
  }
  return 0;
}
