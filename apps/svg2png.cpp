// svg2png: renders an SVG document to a PNG.
//
// The path from command to file, in order: CUDA's start-up begins on a
// thread of its own (lib/backend/backend.h GpuStartup) unless --backend cpu; the
// document is read, parsed and stroked meanwhile; the scene is encoded; the
// backend is chosen (--backend auto: lib/backend/cost_model.cpp, the CPU when it
// would finish before the GPU is ready); the frame is rendered, converted
// to 8 or 16 bits and written by mpvg's PNG encoder (no image library is
// loaded unless the document holds a JPEG, GIF or WebP image).
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <unistd.h>

#include "lib/pipeline/cli.h"
#include "lib/output/image_io.h"
#include "lib/pipeline/json.h"
#include "lib/pipeline/pipeline.h"
#include "lib/output/png_writer.h"
#include "lib/server/server.h"
#include "core/error.h"
#include "frame/filter_layers.h"
#include "core/memory_budget.h"
#include "core/parallel.h"
#include "lib/backend/backend.h"
#include "parsers/svg/svg_parser.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_info.h"

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

// CUDA's start-up and, once it has finished, the renderers of the process's
// jobs (the persistent renderer runs several at once): the start-up's, and
// up to kMaxCuda - 1 more made for jobs that run while it is lent out.
// FrameRenderer is not thread-safe: a renderer serves one job at a time.
class Renderers {
 public:
  static constexpr size_t kMaxCuda = 4;
  Renderers(Backend backend, const RenderOptions& like) : startup_(backend, like) {}
  GpuStartup& startup() { return startup_; }
  // The start-up's CUDA renderer, waiting for the start-up; nullptr with
  // *why when there is none. Says whether CUDA works; to render, lend().
  FrameRenderer* cuda(std::string* why) {
    std::lock_guard<std::mutex> lock(mutex_);
    return first(why);
  }
  // A CUDA renderer for one job, given back when the lease ends (a job
  // that throws, or is cancelled, gives it back by unwinding): an idle one
  // (the start-up's first), else a new one, else the first one given back.
  // Empty, with *why, when CUDA does not work.
  struct GiveBack {
    Renderers* owner = nullptr;
    void operator()(FrameRenderer* r) const { owner->give_back(r); }
  };
  using Lease = std::unique_ptr<FrameRenderer, GiveBack>;
  Lease lend(std::string* why) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!first(why)) return Lease(nullptr, GiveBack{this});
    if (idle_.empty() && made_.size() + 1 < kMaxCuda) {
      try {
        made_.push_back(std::make_unique<FrameRenderer>(Backend::Cuda));
        idle_.push_back(made_.back().get());
      } catch (const std::exception& e) {
        if (why) *why = e.what();
        return Lease(nullptr, GiveBack{this});
      }
    }
    returned_.wait(lock, [&] { return !idle_.empty(); });
    FrameRenderer* r = idle_.back();
    idle_.pop_back();
    return Lease(r, GiveBack{this});
  }

 private:
  // Under mutex_.
  FrameRenderer* first(std::string* why) {
    if (!taken_) {
      first_ = startup_.take(&why_);
      taken_ = true;
      if (first_) idle_.push_back(first_.get());
    }
    if (!first_ && why) *why = why_;
    return first_.get();
  }
  void give_back(FrameRenderer* r) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      idle_.push_back(r);
    }
    returned_.notify_one();
  }

  GpuStartup startup_;
  std::mutex mutex_;
  std::condition_variable returned_;
  std::unique_ptr<FrameRenderer> first_;
  std::vector<std::unique_ptr<FrameRenderer>> made_;
  std::vector<FrameRenderer*> idle_;
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
  if (opt.dpi > 0) o.dpi = opt.dpi;
  o.export_id = opt.export_id;
  o.query = opt.query;
  // The images' share of the memory budget (core/memory_budget.h): RGBA8
  // and a mip chain of a third more, 16/3 bytes a texel; half of it for
  // the decoders that hold a whole image before it is reduced.
  const uint64_t images = memory_shares(cli::memory_budget(opt)).images;
  o.max_image_pixels = std::min<uint64_t>(o.max_image_pixels, images * 3 / 16);
  o.max_whole_image_pixels = std::min<uint64_t>(o.max_whole_image_pixels, images / 8);
  o.max_input_bytes = opt.max_input;
  o.budget = cli::make_budget(opt);
  o.view = [&opt](double w, double h) {
    int width, height;
    Affine view;
    cli::output_geometry(opt, w, h, &width, &height, &view);
    return view;
  };
  return o;
}

// A job's document: its bytes when they have been read already (else run()
// reads opt.positional[0]), and the folder its relative references and its
// read policy start from.
struct Document {
  const std::string* text = nullptr;
  std::string base_dir;
};

// The folder parse_svg_file resolves a file's references against: its
// own, the current one for "-".
std::string folder_of(const std::string& path) {
  const std::filesystem::path dir = path == "-" ? std::filesystem::path() : std::filesystem::path(path).parent_path();
  return dir.empty() ? std::string(".") : dir.string();
}

// Where a job's results go: its messages (warnings, errors, --stats: what
// an in-process run prints on stderr) and its PNG, encoded, handed to
// `write`. `checkpoint(stage)` is called between stages: the persistent
// renderer's throws there when the job's client has gone.
struct JobIO {
  FILE* messages = stderr;
  std::function<void(const std::vector<uint8_t>& png)> write;
  std::function<void(const char* stage)> checkpoint = [](const char*) {};
};

int run(const cli::Options& opt, const Document& source, Renderers& renderers, const JobIO& io) {
  const auto t_start = Clock::now();
  FILE* const err = io.messages;
  GpuStartup& startup = renderers.startup();
  double waited_ms = 0;  // for CUDA's start-up
  Renderers::Lease lease;
  auto take_gpu = [&](std::string* why) {
    const auto t = Clock::now();
    lease = renderers.lend(why);
    waited_ms += ms_since(t);
    return lease.get();
  };
  const std::string read = source.text ? std::string() : svg::read_svg_file(opt.positional[0], opt.max_input);
  // One budget for the document: its parse, then its render.
  svg::ParseOptions po = parse_options_for(opt, 0);
  svg::ParseResult doc = svg::parse_svg_string(source.text ? *source.text : read, source.base_dir, po);
  const double parse_ms = ms_since(t_start);
  io.checkpoint("after parsing");
  if (!opt.quiet)
    for (const std::string& w : doc.warnings) std::fprintf(err, "svg2png: warning: %s\n", w.c_str());
  int width, height;
  Affine view;
  cli::output_geometry(opt, doc.scene.width, doc.scene.height, &width, &height, &view);
  RenderOptions ro = cli::render_options(opt, width, height, view, po.budget);
  ro.aliased_paths = has_aliased_paths(doc.scene);
  RenderStats stats;
  const RenderPlan plan = plan_render(ro);
  // Filter effects render layers while encoding: a filtered scene is encoded
  // once the backend is chosen, by its renderer (on the device with CUDA).
  const bool filtered = has_filters(doc.scene);
  EncodedScene enc;
  if (!filtered) enc = encode_for(doc.scene, plan, ro.gamma, &stats);

  // The backend.
  FrameRenderer* gpu = nullptr;
  std::string choice_note;
  if (opt.backend == Backend::Cuda) {
    std::string why;
    gpu = take_gpu(&why);
    if (!gpu) throw Error("CUDA backend unavailable: " + why);
  } else if (opt.backend == Backend::Auto) {
    CostInputs in;
    in.input_segments = filtered ? segment_count(doc.scene) : enc.input_segment_count;
    in.unit_areas = double(plan.frame.ua_w) * plan.frame.ua_h;
    in.samples = plan.integ.samples;
    in.support = plan.integ.support;
    in.pixels = size_t(width) * size_t(height);
    in.cpu_threads = hardware_threads();
    std::string why_not;
    if (startup.done()) {
      // Whether CUDA works; a renderer is lent only if it is chosen.
      in.gpu_possible = renderers.cuda(&why_not) != nullptr;
    } else {
      in.gpu_possible = true;
      in.gpu_wait_ms = expected_gpu_startup_ms() - startup.elapsed_ms();
      // A one-shot process pays the context's teardown at exit (the
      // persistent renderer keeps its context).
      if (!server::serving()) in.gpu_teardown_ms = expected_gpu_teardown_ms();
    }
    BackendChoice choice = choose_backend(in);
    if (choice.backend == Backend::Cuda) {
      gpu = take_gpu(&why_not);
      if (!gpu) choice.why = why_not;
    }
    if (choice.backend == Backend::Cpu || !gpu) {
      gpu = nullptr;
      lease.reset();
      if (!server::serving()) startup.cancel();
      char est[64];
      std::snprintf(est, sizeof est, " (CPU estimated %.1f ms)", choice.cpu_ms);
      choice_note = "auto chose the CPU: " + (in.gpu_possible ? choice.why : why_not + est);
    } else {
      choice_note = "auto chose CUDA: " + choice.why;
    }
  }
  if (filtered) enc = gpu ? gpu->encode(doc.scene, plan, ro, &stats) : encode_for(doc.scene, plan, ro.gamma, &stats);
  if (!opt.quiet)
    for (const std::string& w : stats.warnings) std::fprintf(err, "svg2png: warning: %s\n", w.c_str());
  io.checkpoint("before rendering");
  const auto t_render = Clock::now();
  std::vector<uint8_t> rgba8;
  std::vector<uint16_t> rgba16;
  png::ImageData compressed;  // level 1 on the GPU: filtered and deflated there
  if (gpu) {
    if (opt.bits == 16) rgba16 = to_rgba16(gpu->render(enc, ro, &stats), ro.gamma);
    else if (opt.compression == 1) {
      try {
        compressed = gpu->render_png(enc, plan, ro, &stats);
      } catch (const Error&) {
        // The PNG stage's buffers (five bytes a pixel) did not fit the
        // device: the frame again, compressed on the CPU.
        rgba8 = gpu->render_rgba8(enc, plan, ro, &stats);
      }
    }
    else rgba8 = gpu->render_rgba8(enc, plan, ro, &stats);
  } else {
    if (opt.bits == 16) rgba16 = to_rgba16(render_cpu(enc, plan, ro, &stats), ro.gamma);
    else rgba8 = render_cpu_rgba8(enc, plan, ro, &stats);
  }
  lease.reset();  // the next job may have it while this one is written
  const double render_ms = ms_since(t_render);
  io.checkpoint("before encoding");
  const auto t_write = Clock::now();
  // One image, every core: rows filtered and deflated in strips.
  png::EncodeOptions png_options;
  png_options.threads = 0;
  if (opt.compression >= 0) png_options.level = opt.compression;
  std::vector<uint8_t> png =
      !compressed.zlib.empty()
          ? png::wrap(width, height, 8, compressed.channels, compressed.zlib.data(), compressed.zlib.size())
      : opt.bits == 16 ? png::encode_rgba16(width, height, rgba16.data(), png_options)
                       : png::encode_rgba8(width, height, rgba8.data(), png_options);
  if (opt.dpi > 0) png::set_resolution(png, opt.dpi);
  io.write(png);
  const double write_ms = ms_since(t_write);
  if (opt.stats) {
    if (server::serving()) std::fprintf(err, "persistent renderer: pid %d\n", static_cast<int>(getpid()));
    const char* t0 = std::getenv("MPVG_T0");
    if (t0 && !server::serving())
      std::fprintf(err, "process start (exec to main) %.3f ms\n", (main_entry_ns - std::atoll(t0)) * 1e-6);
    std::fprintf(err, "parse %.3f ms (%zu strokes, built by the stroke stage)\n", parse_ms, doc.stroked_paths);
    if (startup.started()) {
      if (!startup.done()) {
        std::fprintf(err, "CUDA start-up still running (not waited for)\n");
      } else {
        std::string why;
        if (!gpu) renderers.cuda(&why);
        const std::string phases = startup.phases();
        std::fprintf(err, "CUDA start-up took %.3f ms%s%s%s%s; waited for it %.3f ms\n", startup.ready_ms(),
                     phases.empty() ? "" : " (", phases.c_str(), phases.empty() ? "" : ")",
                     why.empty() ? "" : (": " + why).c_str(), waited_ms);
      }
    }
    if (!choice_note.empty()) std::fprintf(err, "%s\n", choice_note.c_str());
    std::fprintf(err, "%s", cli::format_stats(stats).c_str());
    std::fprintf(err, "render + %s %.3f ms\nPNG %.3f ms\nwall %.3f ms\n",
                 compressed.zlib.empty() ? "8/16-bit conversion" : "PNG filtering and deflate on the device", render_ms, write_ms,
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

// svg2png -o OUTDIR IN... / --batch LIST: the pipeline of lib/pipeline/pipeline.h,
// parsing and PNG on worker threads, rendering on every device asked for.
int run_batch(const cli::Options& opt, Renderers& renderers) {
  const std::vector<std::pair<std::string, std::string>> items = batch_items(opt);
  if (items.empty()) return 0;
  const int cores = hardware_threads();
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
  c.prepare_names[1] = "setup";  // strokes are built by the render's stroke stage
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
  c.compression = opt.compression;
  // Small files waiting together share a frame (frame/forest.h).
  c.forest_scenes = pipeline::forest_scenes_for(opt.frame_scenes, cuda, opt.compression);
  c.gamma = opt.gamma;
  c.label = [&](int t) { return items[t].first; };
  c.prepare = [&](int t, int) {
    auto job = std::make_unique<pipeline::Job>();
    job->label = items[t].first;
    job->out = items[t].second;
    job->dpi = opt.dpi;
    const auto t0 = Clock::now();
    // One thread each: the workers are the parallelism.
    const svg::ParseOptions po = parse_options_for(opt, 1);
    svg::ParseResult doc = svg::parse_svg_file(items[t].first, po);
    job->prepare_ms[0] = ms_since(t0);
    const auto t1 = Clock::now();
    job->warnings = std::move(doc.warnings);
    Affine view;
    cli::output_geometry(opt, doc.scene.width, doc.scene.height, &job->width, &job->height, &view);
    job->options = cli::render_options(opt, job->width, job->height, view, po.budget);
    job->options.aliased_paths = has_aliased_paths(doc.scene);
    if (!cuda) job->options.threads = 1;
    job->plan = plan_render(job->options);
    if (cuda && has_filters(doc.scene)) {
      job->filtered = std::make_shared<const Scene>(std::move(doc.scene));  // layers on the render thread's device
    } else {
      job->scene = encode_for(doc.scene, job->plan, job->options.gamma, &job->stats);
      job->warnings.insert(job->warnings.end(), job->stats.warnings.begin(), job->stats.warnings.end());
    }
    job->prepare_ms[1] = ms_since(t1) - job->stats.encode_ms;
    return job;
  };
  c.make_renderer = [&](int r) -> std::unique_ptr<FrameRenderer> {
    // Renderers of their own (the start-up's stays for the next job): the
    // kernels are loaded and the memory pool is warm already.
    if (!cuda) return std::make_unique<FrameRenderer>(Backend::Cpu);
    return std::make_unique<FrameRenderer>(Backend::Cuda, devices[r % devices.size()]);
  };
  c.timeout_s = opt.timeout_s;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> report(nullptr, std::fclose);
  if (!opt.report.empty()) {
    report.reset(std::fopen(opt.report.c_str(), "w"));
    if (!report) throw Error("cannot write the report '" + opt.report + "': " + std::strerror(errno));
    c.report = report.get();
    c.report_input = [&](int t) { return items[t].first; };
    c.report_output = [&](int t) { return items[t].second; };
  }
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

// The client's side of the persistent renderer: the job handed over with
// absolute paths (the server's folder is not ours), its messages printed
// and its PNG written here, with this process's umask and rights. nullopt,
// with *why, when it must render in-process.
std::optional<int> through_server(const cli::Options& opt, int argc, char** argv, const std::string& text,
                                  const std::function<void()>& writing, std::string* why) {
  namespace fs = std::filesystem;
  std::error_code ec;
  auto absolute = [&](const std::string& p) { return fs::absolute(p, ec).string(); };
  server::Request job;
  job.args.assign(argv, argv + argc);
  const std::string& path = opt.positional[0];
  job.document = path == "-" ? path : absolute(path);
  job.base_dir = absolute(folder_of(path));
  for (const std::string& d : opt.allow_read) job.allow_read.push_back(absolute(d));
  for (const std::string& d : opt.font_dirs) job.font_dirs.push_back(absolute(d));
  if (ec) {
    *why = "no current folder: " + ec.message();
    return std::nullopt;
  }
  job.text = text;
  const std::optional<server::Reply> reply = server::forward(job, why);
  if (!reply) return std::nullopt;
  std::fwrite(reply->messages.data(), 1, reply->messages.size(), stderr);
  std::fflush(stderr);
  if (reply->status == 0) {
    writing();
    png::write_file(opt.output, reply->png);
  }
  return reply->status;
}

// svg2png --query: the drawn elements with an id and their boxes, as one
// JSON object on standard output (an element a line), no PNG.
int query(const cli::Options& opt) {
  const svg::ParseOptions po = parse_options_for(opt, 0);
  const svg::ParseResult doc = svg::parse_svg_file(opt.positional[0], po);
  if (!opt.quiet)
    for (const std::string& w : doc.warnings) std::fprintf(stderr, "svg2png: warning: %s\n", w.c_str());
  std::string out = "{\"width\": " + json::number(doc.scene.width) + ", \"height\": " + json::number(doc.scene.height) +
                    ", \"elements\": [";
  for (size_t i = 0; i < doc.elements.size(); i++) {
    const svg::ElementBox& e = doc.elements[i];
    out += std::string(i ? "," : "") + "\n  {\"id\": " + json::quote(e.id) + ", \"x\": " + json::number(e.x) +
           ", \"y\": " + json::number(e.y) + ", \"width\": " + json::number(e.width) +
           ", \"height\": " + json::number(e.height) + "}";
  }
  out += doc.elements.empty() ? "]}\n" : "\n]}\n";
  std::fwrite(out.data(), 1, out.size(), stdout);
  if (std::fflush(stdout) != 0) throw Error(std::string("cannot write standard output: ") + std::strerror(errno));
  return 0;
}

// --timeout for one file: when the file is not written after S seconds the
// process ends (exit 1) with one line, as a batch fails an item. Once the
// PNG is being written it finishes (writing() waits for a deadline being
// handled), so a file is written whole or not at all.
class Deadline {
 public:
  Deadline(double seconds, std::string input) : input_(std::move(input)), seconds_(seconds) {
    if (seconds > 0) watch_ = std::thread([this] { watch(); });
  }
  ~Deadline() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      state_ = State::Done;
    }
    changed_.notify_all();
    if (watch_.joinable()) watch_.join();
  }
  // Called before the output is written: no timeout from here on.
  void writing() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (state_ == State::Running) state_ = State::Writing;
  }

 private:
  enum class State { Running, Writing, Done };
  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (changed_.wait_for(lock, std::chrono::duration<double>(seconds_), [&] { return state_ != State::Running; }))
      return;
    // (The lock held: the render cannot start writing meanwhile.)
    std::fprintf(stderr, "svg2png: %s: timed out after %g s (--timeout)\n", input_.c_str(), seconds_);
    std::fflush(nullptr);
    std::_Exit(1);
  }
  std::string input_;
  double seconds_;
  std::mutex mutex_;
  std::condition_variable changed_;
  State state_ = State::Running;
  std::thread watch_;
};

// svg2png's whole job in this process; a single file goes to the
// persistent renderer when it is asked for and serves us.
int svg2png_main(int argc, char** argv, std::unique_ptr<Renderers>& renderers) {
  cli::Options opt;
  try {
    if (!cli::parse(argc, argv, "svg2png", "svg", opt)) return 0;
    // A PNG's bytes on a terminal are garbage and can upset it (rsvg-convert
    // and resvg write only to a pipe or a file there, too).
    if (!opt.batch && opt.output == "-" && isatty(STDOUT_FILENO))
      throw cli::UsageError{"standard output is a terminal: redirect it, or name an output file"};
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "svg2png: %s\n", e.message.c_str());
    return 2;
  }
  if (opt.query) {
    try {
      return query(opt);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "svg2png: %s\n", error_message(e).c_str());
      return 1;
    }
  }
  // Batches stay in-process: the pipeline amortises start-up itself.
  const bool hand_over = !opt.batch && server::requested(argc, argv);
  // Begun before anything else: the driver's initialisation overlaps the
  // document's reading and parsing.
  auto start = [&] {
    if (!renderers) renderers = std::make_unique<Renderers>(opt.backend, cli::render_options(opt, 64, 64, Affine{}));
  };
  if (!hand_over) start();
  try {
    if (opt.batch) return run_batch(opt, *renderers);
    const std::string& path = opt.positional[0];
    Deadline deadline(opt.timeout_s, path);
    Document source{nullptr, folder_of(path)};
    std::string text;
    if (hand_over) {
      // Read here, with this process's rights; the bytes serve the
      // in-process render too if the server does not (standard input
      // cannot be read twice).
      text = svg::read_svg_file(path, opt.max_input);
      source.text = &text;
      std::string why;
      if (const std::optional<int> status = through_server(opt, argc, argv, text, [&] { deadline.writing(); }, &why)) return *status;
      if (opt.stats) std::fprintf(stderr, "persistent renderer: not used (%s); rendering in-process\n", why.c_str());
      start();
    }
    JobIO io;
    io.write = [&](const std::vector<uint8_t>& png) {
      deadline.writing();
      png::write_file(opt.output, png);
    };
    return run(opt, source, *renderers, io);
  } catch (const ParseError& e) {
    // What is wrong in which file ("svg2png: a.svg: XML parse error at
    // line 3, column 13: ..."), as a batch names its items.
    const std::string& path = opt.positional[0];
    std::fprintf(stderr, "svg2png: %s: %s\n", path == "-" ? "standard input" : path.c_str(), error_message(e).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "svg2png: %s\n", error_message(e).c_str());
    return 1;
  }
}

// One job inside the persistent renderer, on a thread of its own: the
// client's arguments with its absolute paths, its document's bytes; the
// messages and the PNG go back to the client.
server::Reply job_in_server(const server::Request& job, const std::function<void(const char*)>& checkpoint,
                            Renderers& renderers) {
  struct Messages {
    char* data = nullptr;
    size_t size = 0;
    FILE* file = open_memstream(&data, &size);
    ~Messages() {
      if (file) std::fclose(file);
      std::free(data);
    }
  } messages;
  if (!messages.file) throw std::bad_alloc();
  server::Reply reply;
  std::vector<char*> argv;
  for (const std::string& a : job.args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  try {
    cli::Options opt;
    cli::parse(static_cast<int>(job.args.size()), argv.data(), "svg2png", "svg", opt);
    // The client's paths, made absolute; is_directory(-o) in parse may
    // have looked here: the job is one file whatever it saw.
    opt.batch = false;
    opt.positional = {job.document};
    opt.allow_read = job.allow_read;
    opt.font_dirs = job.font_dirs;
    JobIO io;
    io.messages = messages.file;
    io.write = [&](const std::vector<uint8_t>& png) { reply.png = png; };
    io.checkpoint = checkpoint;
    reply.status = run(opt, Document{&job.text, job.base_dir}, renderers, io);
  } catch (const cli::UsageError& e) {
    std::fprintf(messages.file, "svg2png: %s\n", e.message.c_str());
    reply.status = 2;
  } catch (const std::exception& e) {
    std::fprintf(messages.file, "svg2png: %s\n", error_message(e).c_str());
    reply.status = 1;
  }
  if (reply.status != 0) reply.png.clear();
  std::fclose(messages.file);
  messages.file = nullptr;
  reply.messages.assign(messages.data, messages.size);
  return reply;
}

}  // namespace

int main(int argc, char** argv) {
  main_entry_ns = epoch_ns();
  if (argc >= 2 && std::string(argv[1]) == server::kCredentialsArgument) return server::credentials_main(argc, argv);
  std::unique_ptr<Renderers> renderers;
  if (argc == 2 && std::string(argv[1]) == server::kServeArgument) {
    // The persistent renderer: CUDA starts at once, jobs come later.
    renderers = std::make_unique<Renderers>(Backend::Auto, cli::render_options(cli::Options{}, 64, 64, Affine{}));
    const int status = server::serve(
        [&](const server::Request& job, const std::function<void(const char*)>& checkpoint) {
          return job_in_server(job, checkpoint, *renderers);
        });
    std::fflush(nullptr);
    std::_Exit(status);
  }
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
