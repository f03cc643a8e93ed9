// stroke_stats: what stroking an SVG document's strokes costs. The document
// is parsed for rendering at a width (1024 px by default, as the paper's
// benchmark) and encoded for it; its strokes (centrelines, styles,
// transforms to pixels) are then built by:
//   - the stroke stage (stroker/stroke.h) on the CPU executor, one thread and
//     every core;
//   - in a CUDA build with a device, the stage on the GPU (device time of
//     its kernels, per kernel, and the upload of the centrelines).
//
// usage: stroke_stats [-w WIDTH_PIXELS] [-r REPEATS] FILE.svg...
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "frame/encoding.h"
#include "stroker/stroke_input.h"
#include "parsers/svg/svg_parser.h"
#ifdef MPVG_WITH_CUDA
#include "lib/backend/backend.h"
#include "gpu/stroke.h"
#endif

int main(int argc, char** argv) {
  int width = 1024, repeats = 5;
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; i += 2) {
    if (i + 1 >= argc) break;
    if (!std::strcmp(argv[i], "-w")) width = std::max(1, std::atoi(argv[i + 1]));
    if (!std::strcmp(argv[i], "-r")) repeats = std::max(1, std::atoi(argv[i + 1]));
  }
  if (i >= argc) {
    std::fprintf(stderr, "usage: stroke_stats [-w WIDTH_PIXELS] [-r REPEATS] FILE.svg...\n");
    return 2;
  }
  auto best_of = [&](auto f) {
    double best = 1e300;
    for (int k = 0; k < repeats; k++) {
      const auto t0 = std::chrono::steady_clock::now();
      f();
      best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
  };
  // FNV-1a of the output's bytes: a restructuring of the stage that keeps
  // its arithmetic shows the same hash, and the executors' hashes tell
  // whether they agree bit for bit.
  auto hash = [](const std::vector<mpvg::InputSegment>& v) {
    uint64_t h = 1469598103934665603ull;
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    for (size_t k = 0; k < v.size() * sizeof(mpvg::InputSegment); k++) h = (h ^ p[k]) * 1099511628211ull;
    return h;
  };
  const mpvg::svg::ParseOptions options = mpvg::svg::ParseOptions::at_width(width);
  for (; i < argc; i++) {
    try {
      mpvg::svg::ParseResult r;
      const double parse = best_of([&] { r = mpvg::svg::parse_svg_file(argv[i], options); });
      const double scale = r.scene.width > 0 ? width / r.scene.width : 1;
      const mpvg::StrokeBatch batch =
          mpvg::encode(r.scene, mpvg::Affine::scale(scale, scale), mpvg::Gamma::Srgb).strokes;
      size_t made = 0;
      const double one = best_of([&] { made = mpvg::stroke_cpu(batch, 1).size(); });
      const double all = best_of([&] { mpvg::stroke_cpu(batch, 0); });
      size_t by_type[4] = {};
      for (const auto& seg : batch.segments) by_type[std::min<uint32_t>(seg.curve.type, 3)]++;
      std::printf("%s: parse %.2f ms; %zu strokes, %zu centreline segments (types 0-3: %zu %zu %zu %zu)\n", argv[i],
                  parse, batch.strokes.size(), batch.segments.size(), by_type[0], by_type[1], by_type[2], by_type[3]);
      std::printf("  stage on the CPU: %zu segments (hash %016llx); %.2f ms on one thread, %.2f ms on every core\n", made,
                  static_cast<unsigned long long>(hash(mpvg::stroke_cpu(batch, 1))), one, all);
#ifdef MPVG_WITH_CUDA
      if (mpvg::cuda_available()) {
        const uint64_t gpu_hash = hash(mpvg::gpu::stroke_gpu(batch));
        // The first run loads the kernels; the best of the others, on
        // buffers kept from run to run.
        mpvg::gpu::StrokeGpuTimes best;
        mpvg::gpu::stroke_gpu(batch, &best, repeats + 1);
        std::printf("  stage on the GPU: %zu segments (hash %016llx); %.3f ms on the device (measure %.3f, count %.3f, write %.3f), "
                    "upload %.3f ms, %zu launches\n",
                    best.segments, static_cast<unsigned long long>(gpu_hash), best.device_ms(), best.measure_ms, best.count_ms, best.write_ms, best.upload_ms,
                    best.launches);
        std::printf("   ");
        for (const auto& [name, ms] : best.kernels) std::printf(" %s %.3f", name, ms);
        std::printf(" (ms; %zu round trips; run again: %zu parts, %zu fit items)\n", best.round_trips, best.part_refits,
                    best.fit_refits);
      }
#endif
    } catch (const std::exception& e) {
      std::fprintf(stderr, "stroke_stats: %s\n", e.what());
      return 1;
    }
  }
  return 0;
}
