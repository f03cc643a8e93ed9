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
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <optional>
#include <thread>
#include <unistd.h>

#include "apps/cli.h"
#include "apps/image_io.h"
#include "apps/pipeline.h"
#include "apps/server.h"
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

// CUDA's start-up and, once it has finished, the renderer it made: kept
// for every job of the process (the persistent renderer's too).
class Renderers {
 public:
  Renderers(Backend backend, const RenderOptions& like) : startup_(backend, like) {}
  GpuStartup& startup() { return startup_; }
  // The CUDA renderer, waiting for the start-up; nullptr with *why when
  // there is none.
  FrameRenderer* cuda(std::string* why) {
    if (!taken_) {
      renderer_ = startup_.take(&why_);
      taken_ = true;
    }
    if (!renderer_ && why) *why = why_;
    return renderer_.get();
  }

 private:
  GpuStartup startup_;
  std::unique_ptr<FrameRenderer> renderer_;
  bool taken_ = false;
  std::string why_;
};

// What the parser needs from the options: the read policy, the fonts, and
// the output's pixels (strokes are converted for them: tolerance,
// hairlines); `threads` converts strokes (0: every core).
svg::ParseOptions parse_options_for(const cli::Options& opt, int threads) {
  svg::ParseOptions o;
  o.allowed_dirs = opt.allow_read;
  o.font_dirs = opt.font_dirs;
  o.languages = opt.languages;
  o.threads = threads;
  o.view = [&opt](double w, double h) {
    int width, height;
    Affine view;
    cli::output_geometry(opt, w, h, &width, &height, &view);
    return view;
  };
  return o;
}

int run(const cli::Options& opt, Renderers& renderers) {
  const auto t_start = Clock::now();
  GpuStartup& startup = renderers.startup();
  double waited_ms = 0;  // for CUDA's start-up
  auto take_gpu = [&](std::string* why) {
    const auto t = Clock::now();
    FrameRenderer* r = renderers.cuda(why);
    waited_ms += ms_since(t);
    return r;
  };
  svg::ParseResult doc = svg::parse_svg_file(opt.positional[0], parse_options_for(opt, 0));
  const double parse_ms = ms_since(t_start);
  if (!opt.quiet)
    for (const std::string& w : doc.warnings) std::fprintf(stderr, "svg2png: warning: %s\n", w.c_str());
  int width, height;
  Affine view;
  cli::output_geometry(opt, doc.scene.width, doc.scene.height, &width, &height, &view);
  RenderOptions ro = cli::render_options(opt, width, height, view);
  ro.aliased_paths = has_aliased_paths(doc.scene);
  RenderStats stats;
  const RenderPlan plan = plan_render(ro);
  const EncodedScene enc = encode_for(doc.scene, plan, ro.gamma, &stats);

  // The backend.
  FrameRenderer* gpu = nullptr;
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
      // A one-shot process pays the context's teardown at exit (the
      // persistent renderer keeps its context).
      if (!server::serving()) in.gpu_teardown_ms = expected_gpu_teardown_ms();
    }
    BackendChoice choice = choose_backend(in);
    if (choice.backend == Backend::Cuda && !gpu) {
      gpu = take_gpu(&why_not);
      if (!gpu) choice.why = why_not;
    }
    if (choice.backend == Backend::Cpu || !gpu) {
      gpu = nullptr;
      if (!server::serving()) startup.cancel();
      char est[64];
      std::snprintf(est, sizeof est, " (CPU estimated %.1f ms)", choice.cpu_ms);
      choice_note = "auto chose the CPU: " + (in.gpu_possible ? choice.why : why_not + est);
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
    if (server::serving()) std::fprintf(stderr, "persistent renderer: pid %d\n", static_cast<int>(getpid()));
    if (const char* t0 = std::getenv("MPVG_T0"))
      std::fprintf(stderr, "process start (exec to main) %.3f ms\n", (main_entry_ns - std::atoll(t0)) * 1e-6);
    std::fprintf(stderr, "parse %.3f ms (stroke %.3f ms, %zu strokes)\n", parse_ms, doc.stroke_seconds * 1e3,
                 doc.stroked_paths);
    if (startup.started()) {
      if (!startup.done()) {
        std::fprintf(stderr, "CUDA start-up still running (not waited for)\n");
      } else {
        std::string why;
        if (!gpu) renderers.cuda(&why);
        const std::string phases = startup.phases();
        std::fprintf(stderr, "CUDA start-up took %.3f ms%s%s%s%s; waited for it %.3f ms\n", startup.ready_ms(),
                     phases.empty() ? "" : " (", phases.c_str(), phases.empty() ? "" : ")",
                     why.empty() ? "" : (": " + why).c_str(), waited_ms);
      }
    }
    if (!choice_note.empty()) std::fprintf(stderr, "%s\n", choice_note.c_str());
    std::fprintf(stderr, "%s", cli::format_stats(stats).c_str());
    std::fprintf(stderr, "render + 8/16-bit conversion %.3f ms\nPNG %.3f ms\nwall %.3f ms\n", render_ms, write_ms,
                 ms_since(t_start));
  }
  return 0;
}

// The batch's (input, output) pairs: from --batch LIST or the command
// line's inputs with -o OUTDIR, then --shard's share. Two inputs that would
// write the same output are an error before anything renders.
std::vector<std::pair<std::string, std::string>> batch_items(const cli::Options& opt) {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, std::string>> items;
  if (!opt.batch_list.empty()) {
    std::string text;
    if (opt.batch_list == "-") {
      text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    } else {
      std::ifstream f(opt.batch_list, std::ios::binary);
      if (!f) throw Error("cannot read the batch list '" + opt.batch_list + "'");
      text.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    }
    // A line: IN and OUT separated by a tab (names with spaces), else by
    // the last run of spaces; blank lines and lines starting with '#' skip.
    size_t line_no = 0;
    for (size_t pos = 0; pos < text.size();) {
      const size_t end = std::min(text.find('\n', pos), text.size());
      std::string line = text.substr(pos, end - pos);
      pos = end + 1;
      line_no++;
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
      const size_t lead = line.find_first_not_of(" \t");
      if (lead == std::string::npos || line[lead] == '#') continue;
      line = line.substr(lead);
      size_t cut = line.find('\t');
      if (cut == std::string::npos) cut = line.find_last_of(' ');
      const std::string in = cut == std::string::npos ? "" : line.substr(0, line.find_last_not_of(" \t", cut) + 1);
      const std::string out = cut == std::string::npos ? "" : line.substr(line.find_first_not_of(" \t", cut));
      if (in.empty() || out.empty())
        throw Error(opt.batch_list + ":" + std::to_string(line_no) + ": expected 'IN OUT'");
      items.emplace_back(in, out);
    }
  } else {
    std::error_code ec;
    fs::create_directories(opt.output, ec);
    if (!fs::is_directory(opt.output)) throw Error("cannot make the output folder '" + opt.output + "'");
    for (const std::string& in : opt.positional) {
      if (in == "-") throw Error("standard input cannot be one of several inputs (use --batch)");
      items.emplace_back(in, (fs::path(opt.output) / fs::path(in).stem()).string() + ".png");
    }
  }
  std::vector<std::pair<std::string, std::string>> mine;
  for (size_t i = 0; i < items.size(); i++)
    if (int(i % opt.shard_count) == opt.shard_index) mine.push_back(items[i]);
  std::map<std::string, std::string> seen;
  int stdin_inputs = 0, stdout_outputs = 0;
  for (const auto& [in, out] : mine) {
    stdin_inputs += in == "-";
    stdout_outputs += out == "-";
    if (out == "-") continue;
    std::error_code ec;
    const std::string key = fs::weakly_canonical(fs::absolute(out), ec).string();
    auto [it, fresh] = seen.emplace(ec ? out : key, in);
    if (!fresh) throw Error("'" + it->second + "' and '" + in + "' would both be written to '" + out + "'");
  }
  if (stdin_inputs > 1 || stdout_outputs > 1)
    throw Error("standard input and standard output can each be used by one item of a batch only");
  return mine;
}

// svg2png -o OUTDIR IN... / --batch LIST: the pipeline of apps/pipeline.h,
// parsing and PNG on worker threads, rendering on every device asked for.
int run_batch(const cli::Options& opt, Renderers& renderers) {
  const std::vector<std::pair<std::string, std::string>> items = batch_items(opt);
  if (items.empty()) return 0;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  // The backend: with auto, CUDA wherever a device works (a batch
  // amortises its start-up), the CPU otherwise.
  std::string why;
  bool cuda = false;
  if (opt.backend != Backend::Cpu) {
    cuda = renderers.cuda(&why) != nullptr;
    if (!cuda && opt.backend == Backend::Cuda) throw Error("CUDA backend unavailable: " + why);
  }
  std::vector<int> devices = opt.devices;
  if (cuda && devices.empty())
    for (int d = 0; d < cuda_device_count(); d++) devices.push_back(d);
  if (cuda)
    for (int d : devices)
      if (d >= cuda_device_count())
        throw Error("no CUDA device " + std::to_string(d) + " (" + std::to_string(cuda_device_count()) + " visible)");
  pipeline::Config c;
  c.program = "svg2png";
  c.unit = "file";
  c.prepare_names[0] = "parsing";
  c.prepare_names[1] = "stroking";
  c.tickets = static_cast<int>(items.size());
  // With CUDA: a few render threads per device (each its own context state
  // and stream), the other cores prepare and write; on the CPU every render
  // thread renders one file on one core (a batch's files are the
  // parallelism).
  const int per_device = opt.render_threads > 0 ? opt.render_threads : 2;
  c.render_threads = cuda ? per_device * static_cast<int>(devices.size()) : (opt.render_threads > 0 ? opt.render_threads : cores);
  c.workers = opt.threads > 0 ? opt.threads : cuda ? std::max(1, cores - c.render_threads) : cores;
  c.progress = !opt.quiet && items.size() > 1 && isatty(fileno(stderr));
  c.stats = opt.stats;
  c.quiet = opt.quiet;
  c.bits = opt.bits;
  c.gamma = opt.gamma;
  c.label = [&](int t) { return items[t].first; };
  c.prepare = [&](int t, int) {
    auto job = std::make_unique<pipeline::Job>();
    job->label = items[t].first;
    job->out = items[t].second;
    const auto t0 = Clock::now();
    // One thread each: the workers are the parallelism.
    svg::ParseResult doc = svg::parse_svg_file(items[t].first, parse_options_for(opt, 1));
    job->prepare_ms[1] = doc.stroke_seconds * 1e3;
    job->prepare_ms[0] = ms_since(t0) - job->prepare_ms[1];
    job->warnings = std::move(doc.warnings);
    Affine view;
    cli::output_geometry(opt, doc.scene.width, doc.scene.height, &job->width, &job->height, &view);
    job->options = cli::render_options(opt, job->width, job->height, view);
    job->options.aliased_paths = has_aliased_paths(doc.scene);
    if (!cuda) job->options.threads = 1;
    job->plan = plan_render(job->options);
    job->scene = encode_for(doc.scene, job->plan, job->options.gamma, &job->stats);
    return job;
  };
  c.make_renderer = [&](int r) -> std::unique_ptr<FrameRenderer> {
    // Renderers of their own (the start-up's stays for the next job): the
    // kernels are loaded and the memory pool is warm already.
    if (!cuda) return std::make_unique<FrameRenderer>(Backend::Cpu);
    return std::make_unique<FrameRenderer>(Backend::Cuda, devices[r % devices.size()]);
  };
  c.timeout_s = opt.timeout_s;
  const pipeline::Result result = pipeline::run(c);
  if (opt.stats) {
    if (!cuda && opt.backend == Backend::Auto) std::fprintf(stderr, "svg2png: on the CPU: %s\n", why.c_str());
    std::fprintf(stderr, "%s", pipeline::summary(c, result, cuda ? "cuda" : "cpu").c_str());
  }
  if (result.abandoned > 0) {
    // A thread is still inside a file that timed out, using this
    // function's data: the process ends here, every other output written.
    std::fflush(nullptr);
    std::_Exit(1);
  }
  return result.failed ? 1 : 0;
}

// svg2png's whole job, in-process or inside the persistent renderer.
int svg2png_main(int argc, char** argv, std::unique_ptr<Renderers>& renderers) {
  cli::Options opt;
  try {
    if (!cli::parse(argc, argv, "svg2png", "svg", opt)) return 0;
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "svg2png: %s\n", e.message.c_str());
    return 2;
  }
  // Begun before anything else: the driver's initialisation overlaps the
  // document's reading and parsing. The persistent renderer starts it
  // with its first job and keeps it.
  if (!renderers) renderers = std::make_unique<Renderers>(opt.backend, cli::render_options(opt, 64, 64, Affine{}));
  try {
    return opt.batch ? run_batch(opt, *renderers) : run(opt, *renderers);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "svg2png: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  main_entry_ns = epoch_ns();
  std::unique_ptr<Renderers> renderers;
  if (argc == 2 && std::string(argv[1]) == server::kServeArgument) {
    // The persistent renderer: CUDA starts at once, jobs come later.
    renderers = std::make_unique<Renderers>(Backend::Auto, cli::render_options(cli::Options{}, 64, 64, Affine{}));
    const int status = server::serve([&](int job_argc, char** job_argv) {
      main_entry_ns = epoch_ns();
      return svg2png_main(job_argc, job_argv, renderers);
    });
    std::fflush(nullptr);
    std::_Exit(status);
  }
  if (server::requested(argc, argv))
    if (const std::optional<int> status = server::forward(argc, argv)) return *status;
  const int status = svg2png_main(argc, argv, renderers);
  // Once the output is written, the process ends without tearing CUDA down:
  // destroying the context and unloading its modules took 100-150 ms of
  // every run on the GPU host (the driver frees it all at exit anyway),
  // and a start-up still running must not be raced by exit()'s static
  // destructors (GpuStartup).
  if (renderers && renderers->startup().started()) {
    std::fflush(nullptr);
    std::_Exit(status);
  }
  return status;
}
