// svg2png: renders an SVG document to a PNG.
//
// The path from command to file, in order: CUDA's start-up begins on a
// thread of its own (gpu/backend.h GpuStartup) unless --backend cpu; the
// document is read, parsed and stroked meanwhile; the scene is encoded; the
// backend is chosen (--backend auto: gpu/cost_model.cpp, the CPU when it
// would finish before the GPU is ready); the frame is rendered, converted
// to 8 or 16 bits and written by mpvg's PNG encoder (no image library is
// loaded unless the document holds a JPEG, GIF or WebP image).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <thread>

#include "apps/cli.h"
#include "apps/image_io.h"
#include "core/error.h"
#include "gpu/backend.h"
#include "parsers/svg/svg_parser.h"

namespace {

using namespace mpvg;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Nanoseconds since the epoch at main()'s entry, and MPVG_T0 (the same
// clock, set by a benchmark just before it starts the process), for
// --stats' "process start".
int64_t main_entry_ns = 0;

int64_t epoch_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int run(const cli::Options& opt, GpuStartup& startup) {
  const auto t_start = Clock::now();
  double waited_ms = 0;  // for CUDA's start-up
  auto take_gpu = [&](std::string* why) {
    const auto t = Clock::now();
    std::unique_ptr<FrameRenderer> r = startup.take(why);
    waited_ms += ms_since(t);
    return r;
  };
  // Strokes are converted for the output's pixels (tolerance, hairlines).
  svg::ParseOptions parse_options;
  parse_options.allowed_dirs = opt.allow_read;
  parse_options.view = [&opt](double w, double h) {
    int width, height;
    Affine view;
    cli::output_geometry(opt, w, h, &width, &height, &view);
    return view;
  };
  svg::ParseResult doc = svg::parse_svg_file(opt.positional[0], parse_options);
  const double parse_ms = ms_since(t_start);
  if (!opt.quiet)
    for (const std::string& w : doc.warnings) std::fprintf(stderr, "svg2png: warning: %s\n", w.c_str());
  int width, height;
  Affine view;
  cli::output_geometry(opt, doc.scene.width, doc.scene.height, &width, &height, &view);
  RenderOptions ro = cli::render_options(opt, width, height, view);
  RenderStats stats;
  const RenderPlan plan = plan_render(ro);
  const EncodedScene enc = encode_for(doc.scene, plan, ro.gamma, &stats);

  // The backend.
  std::unique_ptr<FrameRenderer> gpu;
  std::string choice_note;
  if (opt.backend == Backend::Cuda) {
    std::string why;
    gpu = take_gpu(&why);
    if (!gpu) throw Error("CUDA backend unavailable: " + why);
  } else if (opt.backend == Backend::Auto) {
    CostInputs in;
    in.input_segments = enc.input_segment_count;
    in.unit_areas = double(plan.frame.ua_w) * plan.frame.ua_h;
    in.samples = plan.integ.samples;
    in.support = plan.integ.support;
    in.pixels = size_t(width) * size_t(height);
    in.cpu_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    std::string why_not;
    if (startup.done()) {
      gpu = take_gpu(&why_not);
      in.gpu_possible = gpu != nullptr;
    } else {
      in.gpu_possible = true;
      in.gpu_wait_ms = expected_gpu_startup_ms() - startup.elapsed_ms();
    }
    BackendChoice choice = choose_backend(in);
    if (choice.backend == Backend::Cuda && !gpu) {
      gpu = take_gpu(&why_not);
      if (!gpu) choice.why = why_not;
    }
    if (choice.backend == Backend::Cpu || !gpu) {
      gpu.reset();
      choice_note = "auto chose the CPU: " + (in.gpu_possible ? choice.why : why_not);
    } else {
      choice_note = "auto chose CUDA: " + choice.why;
    }
  }
  const auto t_render = Clock::now();
  std::vector<uint8_t> rgba8;
  std::vector<uint16_t> rgba16;
  if (gpu) {
    if (opt.bits == 16) rgba16 = to_rgba16(gpu->render(enc, ro, &stats), ro.gamma);
    else rgba8 = gpu->render_rgba8(enc, plan, ro, &stats);
  } else {
    ImageF img = render_cpu(enc, plan, ro, &stats);
    if (opt.bits == 16) rgba16 = to_rgba16(img, ro.gamma);
    else rgba8 = to_rgba8(img, ro.gamma);
  }
  const double render_ms = ms_since(t_render);
  const auto t_write = Clock::now();
  if (opt.bits == 16) write_png_rgba16(opt.output, width, height, rgba16);
  else write_png_rgba8(opt.output, width, height, rgba8);
  const double write_ms = ms_since(t_write);
  if (opt.stats) {
    if (const char* t0 = std::getenv("MPVG_T0"))
      std::fprintf(stderr, "process start (exec to main) %.3f ms\n", (main_entry_ns - std::atoll(t0)) * 1e-6);
    std::fprintf(stderr, "parse %.3f ms (stroke %.3f ms, %zu strokes)\n", parse_ms, doc.stroke_seconds * 1e3,
                 doc.stroked_paths);
    if (startup.started()) {
      if (!startup.done()) {
        std::fprintf(stderr, "CUDA start-up still running (not waited for)\n");
      } else {
        std::string why;
        if (!gpu) startup.take(&why);
        std::fprintf(stderr, "CUDA start-up %.3f ms from main()%s%s; waited for it %.3f ms\n", startup.ready_ms(),
                     why.empty() ? "" : ": ", why.c_str(), waited_ms);
      }
    }
    if (!choice_note.empty()) std::fprintf(stderr, "%s\n", choice_note.c_str());
    std::fprintf(stderr, "%s", cli::format_stats(stats).c_str());
    std::fprintf(stderr, "render + 8/16-bit conversion %.3f ms\nPNG %.3f ms\nwall %.3f ms\n", render_ms, write_ms,
                 ms_since(t_start));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  main_entry_ns = epoch_ns();
  cli::Options opt;
  try {
    if (!cli::parse(argc, argv, "svg2png", "svg", opt)) return 0;
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "svg2png: %s\n", e.message.c_str());
    return 2;
  }
  // Begun before anything else: the driver's initialisation overlaps the
  // document's reading and parsing.
  GpuStartup startup(opt.backend, cli::render_options(opt, 64, 64, Affine{}));
  int status = 0;
  try {
    status = run(opt, startup);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "svg2png: %s\n", e.what());
    status = 1;
  }
  // A start-up still running is not waited for (GpuStartup: no exit()).
  if (!startup.done()) {
    std::fflush(stdout);
    std::fflush(stderr);
    std::_Exit(status);
  }
  return status;
}
