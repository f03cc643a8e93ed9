// pdf2png: renders the pages of a PDF document to PNGs, like pdftoppm:
//
//   pdf2png [options] IN.pdf OUT-PREFIX      writes OUT-PREFIX-1.png, ...
//
// Page numbers are zero-padded to the digits of the page count, as
// pdftoppm does. Options of its own: -r/--dpi N (default 150), --scale-to N
// (the longer side in pixels), -x X -y Y -W W -H H (a crop window in
// pixels), -f N and -l N (first and last page), --singlefile (the first
// page only, written to OUT-PREFIX.png), --password P, --transparent (no
// white page background), --threads N (worker threads, default one per
// core, less the render threads with CUDA), --render-threads N (default 3 with CUDA, 1 on the CPU), --repeat N
// (the pages N times over, for benchmarks: later rounds run warm); IN.pdf
// "-" reads stdin. The rendering options
// are svg2png's (--aa, --gamma, --backend, --bits, --stats, -q).
//
// Pages flow through one process as a pipeline, so that no stage waits
// for another: worker threads (one MuPDF context and document clone each)
// interpret and lower pages into scenes and encode them; render threads
// (three with CUDA: one CUDA context, a gpu::Context and stream per thread,
// kept warm from page to page; one on the CPU) render them;
// the workers turn rendered images into PNG files, before they take new
// pages, so that at most `workers + 4` pages are in flight. A page that
// fails is reported and the others are still written; the exit status is
// 1 if any page failed. --stats prints each page's stage times and the
// whole job's throughput.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <queue>
#include <string>
#include <thread>
#include <vector>

#include "apps/cli.h"
#include "apps/png_writer.h"
#include "core/error.h"
#include "gpu/backend.h"
#include "parsers/pdf/pdf_parser.h"

namespace {

struct PdfOptions {
  double dpi = 150;
  int first = 1, last = -1;
  std::string password;
  bool transparent = false;
  bool singlefile = false;  // the first page only, to OUT-PREFIX.png
  int scale_to = 0;         // the longer side in pixels (overrides the resolution)
  int crop_x = 0, crop_y = 0, crop_w = 0, crop_h = 0;  // -x -y -W -H, pixels at the resolution
  int threads = 0;          // worker threads; 0: one per core
  int repeat = 1;           // --repeat N: the pages N times over (benchmarks: later rounds run warm)
  int render_threads = 0;   // threads rendering, each with its own backend state; 0: 3 with CUDA, 1 on the CPU
};

void usage() {
  std::printf(
      "Usage: pdf2png [OPTIONS] INPUT.pdf OUTPUT-PREFIX\n"
      "Renders the pages of INPUT to OUTPUT-PREFIX-1.png, OUTPUT-PREFIX-2.png, ... (page\n"
      "numbers zero-padded to the page count's digits, as pdftoppm writes them) with\n"
      "the mpvg rasterizer. INPUT '-' reads standard input.\n\n"
      "Pages:\n"
      "  -f N, -l N                first and last page (default: all)\n"
      "      --singlefile          the first page only, written to OUTPUT-PREFIX.png\n"
      "      --password P          the document's password\n"
      "Size:\n"
      "  -r, --dpi N               resolution (default 150)\n"
      "      --scale-to N          the longer side in pixels (instead of -r)\n"
      "  -x X -y Y -W W -H H       a crop window, in pixels at the resolution\n"
      "Output:\n"
      "      --transparent         no white page background\n"
      "      --bits 8|16           bits per channel of the PNG (default 8)\n"
      "Antialiasing (the paper's modes):\n"
      "      --aa MODE             4x4x32 (default), 1x32 or 1x8 (see svg2png --help)\n"
      "      --filter F, --samples N, --pattern P, --seed N, --gamma linear|srgb\n"
      "Execution:\n"
      "      --backend B           auto, cpu or cuda (default auto)\n"
      "      --threads N           worker threads: interpretation, lowering, PNG (default:\n"
      "                            one per core, less the render threads with CUDA)\n"
      "      --render-threads N    rendering threads (default 3 with CUDA, 1 on the CPU)\n"
      "      --stats               per-page stage times and the job's throughput\n"
      "      --repeat N            the pages N times over (benchmarks)\n"
      "  -q, --quiet               no warnings\n"
      "      --help, --version\n");
}

// Takes pdf2png's own options out of argv; the rest goes to cli::parse.
// Returns false after --help.
std::vector<char*> own_options(int argc, char** argv, PdfOptions& p) {
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; i++) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-?") {
      usage();
      return {};
    }
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw mpvg::cli::UsageError{a + " needs a value"};
      return argv[++i];
    };
    auto number = [&](double lo) {
      const std::string v = value();
      char* end = nullptr;
      const double d = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end || !(d >= lo) || !std::isfinite(d))
        throw mpvg::cli::UsageError{"invalid value '" + v + "' for " + a};
      return d;
    };
    if (a == "-r" || a == "--dpi")
      p.dpi = number(1);
    else if (a == "-f")
      p.first = static_cast<int>(number(1));
    else if (a == "-l")
      p.last = static_cast<int>(number(1));
    else if (a == "--password")
      p.password = value();
    else if (a == "--transparent")
      p.transparent = true;
    else if (a == "--singlefile")
      p.singlefile = true;
    else if (a == "--scale-to")
      p.scale_to = static_cast<int>(number(1));
    else if (a == "-x")
      p.crop_x = static_cast<int>(number(0));
    else if (a == "-y")
      p.crop_y = static_cast<int>(number(0));
    else if (a == "-W")
      p.crop_w = static_cast<int>(number(1));
    else if (a == "-H")
      p.crop_h = static_cast<int>(number(1));
    else if (a == "--threads")
      p.threads = static_cast<int>(number(1));
    else if (a == "--repeat")
      p.repeat = static_cast<int>(number(1));
    else if (a == "--render-threads")
      p.render_threads = static_cast<int>(number(1));
    else
      rest.push_back(argv[i]);
  }
  return rest;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// One page on its way through the pipeline.
struct Job {
  int page = 0;  // 1-based
  std::string out;
  int width = 0, height = 0;
  mpvg::RenderOptions options;
  mpvg::RenderPlan plan;
  mpvg::EncodedScene scene;
  mpvg::ImageF image;          // --bits 16
  std::vector<uint8_t> rgba8;  // --bits 8 (converted where it was rendered)
  mpvg::RenderStats stats;
  double interpret_ms = 0, lower_ms = 0, render_ms = 0, png_ms = 0, write_ms = 0;  // png_ms includes write_ms
  std::vector<std::string> warnings;
};

// The pipeline's shared state; everything under `m`.
struct Pipeline {
  const PdfOptions& pdf;
  const mpvg::cli::Options& opt;
  int first = 1, last = 0, digits = 1;
  int tickets = 0;  // pages to render: the range, --repeat times over
  bool progress = false;

  std::mutex m;
  std::condition_variable cv;
  int next = 0;       // the next ticket to lower: page first + next % (last - first + 1)
  int in_flight = 0;  // pages taken and not yet finished
  int lowering = 0;   // pages being lowered now
  int max_in_flight = 1;
  int finished = 0, failed = 0;
  // --stats: each stage's time summed over the pages (ms), and how long
  // the render threads and the workers waited for work.
  struct Totals {
    double interpret = 0, lower = 0, encode = 0, preprocess = 0, render = 0, render_wall = 0, png = 0, write = 0;
    double render_idle = 0, worker_idle = 0;
  } totals;
  bool rendering_done = false;
  int renderers = 1;  // render threads still running
  // Lowered pages waiting for the renderer, lowest page first.
  struct Later {
    bool operator()(const std::unique_ptr<Job>& a, const std::unique_ptr<Job>& b) const { return a->page > b->page; }
  };
  std::priority_queue<std::unique_ptr<Job>, std::vector<std::unique_ptr<Job>>, Later> to_render;
  std::deque<std::unique_ptr<Job>> to_write;
  // 8-bit images of written pages, whose memory the render threads reuse:
  // fresh memory costs a page fault per 4 KiB while the copy from the
  // device fills it, many times the copy's own time in a virtual machine.
  std::vector<std::vector<uint8_t>> spare_rgba8;

  Pipeline(const PdfOptions& p, const mpvg::cli::Options& o) : pdf(p), opt(o) {}

  std::string output_name(int page) const {
    char name[32];
    std::snprintf(name, sizeof name, "-%0*d.png", digits, page);
    return opt.output + (pdf.singlefile ? std::string(".png") : std::string(name));
  }

  // Reports a page's end (under m): its error if any, its warnings and
  // stats, the progress line.
  void finish(const Job* job, int page, const std::string& error) {
    finished++;
    in_flight--;
    if (!error.empty()) failed++;
    const char* nl = progress ? "\r\033[K" : "";
    if (!error.empty()) std::fprintf(stderr, "%spdf2png: %s\n", nl, error.c_str());
    if (job && !opt.quiet)
      for (const std::string& w : job->warnings) std::fprintf(stderr, "%spdf2png: page %d: warning: %s\n", nl, page, w.c_str());
    if (job && opt.stats && error.empty()) {
      const mpvg::RenderStats& st = job->stats;
      totals.interpret += job->interpret_ms;
      totals.lower += job->lower_ms;
      totals.encode += st.encode_ms;
      totals.preprocess += st.abstract_ms + st.subdivide_ms + st.prune_ms;
      totals.render += st.schedule_ms + st.sample_ms;
      totals.render_wall += job->render_ms;
      totals.png += job->png_ms;
      totals.write += job->write_ms;
      std::fprintf(stderr,
                   "%spage %d: %dx%d, interpretation %.2f ms, lowering %.2f ms, encoding %.2f ms, preprocessing "
                   "%.2f ms, rendering %.2f ms, PNG %.2f ms\n%s",
                   nl, page, job->width, job->height, job->interpret_ms, job->lower_ms, st.encode_ms,
                   st.abstract_ms + st.subdivide_ms + st.prune_ms, st.schedule_ms + st.sample_ms, job->png_ms,
                   mpvg::cli::format_stats(st).c_str());
    }
    if (progress) std::fprintf(stderr, "\rpdf2png: %d of %d pages", finished, tickets);
    cv.notify_all();
  }

  // Interprets, lowers and encodes page n (outside m).
  std::unique_ptr<Job> lower(const mpvg::pdf::Document& doc, int n) {
    using namespace mpvg;
    auto job = std::make_unique<Job>();
    job->page = n;
    job->out = output_name(n);
    // --scale-to: the resolution follows from the page's size.
    pdf::PageResult page = doc.page(n - 1, [this](double w, double h) {
      return pdf.scale_to > 0 ? pdf.scale_to / std::max(w, h) : pdf.dpi / 72.0;
    });
    job->interpret_ms = page.interpret_ms;
    job->lower_ms = page.lower_ms;
    job->warnings = std::move(page.warnings);
    const double scale = page.pixels_per_point;
    int width = std::max(1, static_cast<int>(std::ceil(page.scene.width * scale - 1e-6)));
    int height = std::max(1, static_cast<int>(std::ceil(page.scene.height * scale - 1e-6)));
    // -x -y -W -H: a window of the page's pixels (the rest of the page if
    // -W or -H is absent), as pdftoppm crops.
    if (pdf.crop_x || pdf.crop_y || pdf.crop_w || pdf.crop_h) {
      width = pdf.crop_w ? pdf.crop_w : std::max(1, width - pdf.crop_x);
      height = pdf.crop_h ? pdf.crop_h : std::max(1, height - pdf.crop_y);
    }
    job->width = width;
    job->height = height;
    const Affine view = Affine::translate(-pdf.crop_x, -pdf.crop_y) * Affine::scale(scale, scale);
    job->options = cli::render_options(opt, width, height, view);
    job->plan = plan_render(job->options);
    job->scene = encode_for(page.scene, job->plan, job->options.gamma, &job->stats);
    return job;
  }

  void write(Job& job) {
    using namespace mpvg;
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<uint8_t> bytes =
        opt.bits == 16 ? png::encode_rgba16(job.width, job.height, to_rgba16(job.image, opt.gamma).data())
                       : png::encode_rgba8(job.width, job.height, job.rgba8.data());
    const auto t1 = std::chrono::steady_clock::now();
    png::write_file(job.out, bytes);
    job.write_ms = ms_since(t1);
    job.png_ms = ms_since(t0);
  }

  // A worker: writes rendered pages first, lowers new ones while there is
  // room, until every page is through. `doc`: the document to use, or null
  // for a clone of base_doc of its own (made on first use).
  void work(const mpvg::pdf::Document* doc) {
    std::unique_ptr<mpvg::pdf::Document> own;
    std::unique_lock<std::mutex> lock(m);
    for (;;) {
      const auto t_wait = std::chrono::steady_clock::now();
      cv.wait(lock, [&] {
        return !to_write.empty() || (next < tickets && in_flight < max_in_flight) ||
               (next >= tickets && rendering_done);
      });
      totals.worker_idle += ms_since(t_wait);
      if (!to_write.empty()) {
        std::unique_ptr<Job> job = std::move(to_write.front());
        to_write.pop_front();
        lock.unlock();
        std::string error;
        try {
          write(*job);
        } catch (const std::exception& e) {
          error = e.what();
        }
        job->image = mpvg::ImageF{};
        lock.lock();
        spare_rgba8.push_back(std::move(job->rgba8));
        finish(job.get(), job->page, error);
        continue;
      }
      if (next >= tickets) return;  // rendering done, nothing to write
      const int n = first + next++ % (last - first + 1);
      in_flight++;
      lowering++;
      lock.unlock();
      std::unique_ptr<Job> job;
      std::string error;
      try {
        if (!doc) {
          own = base_doc->clone(shared_context ? mpvg::pdf::Document::Context::Shared
                                               : mpvg::pdf::Document::Context::Independent);
          doc = own.get();
        }
        job = lower(*doc, n);
      } catch (const std::exception& e) {
        error = e.what();
        if (error.rfind("page ", 0) != 0) error = "page " + std::to_string(n) + ": " + error;
      }
      lock.lock();
      lowering--;
      if (job) {
        to_render.push(std::move(job));
        cv.notify_all();
      } else {
        finish(nullptr, n, error);
      }
    }
  }


  // A renderer: one backend state for every page it takes, until every
  // page is lowered and rendered.
  void render(mpvg::FrameRenderer& renderer) {
    std::unique_lock<std::mutex> lock(m);
    for (;;) {
      const auto t_wait = std::chrono::steady_clock::now();
      cv.wait(lock, [&] { return !to_render.empty() || (next >= tickets && lowering == 0); });
      totals.render_idle += ms_since(t_wait);
      if (to_render.empty()) break;
      std::unique_ptr<Job> job = std::move(const_cast<std::unique_ptr<Job>&>(to_render.top()));
      to_render.pop();
      std::vector<uint8_t> storage;
      if (!spare_rgba8.empty()) {
        storage = std::move(spare_rgba8.back());
        spare_rgba8.pop_back();
      }
      lock.unlock();
      std::string error;
      const auto t0 = std::chrono::steady_clock::now();
      try {
        if (opt.bits == 16)
          job->image = renderer.render(job->scene, job->options, &job->stats);
        else
          job->rgba8 = renderer.render_rgba8(job->scene, job->plan, job->options, &job->stats, std::move(storage));
      } catch (const std::exception& e) {
        error = "page " + std::to_string(job->page) + ": " + e.what();
      }
      job->scene = mpvg::EncodedScene{};
      job->render_ms = ms_since(t0);
      lock.lock();
      if (error.empty()) {
        to_write.push_back(std::move(job));
        cv.notify_all();
      } else {
        finish(job.get(), job->page, error);
      }
    }
    if (--renderers == 0) rendering_done = true;
    cv.notify_all();
  }

  const mpvg::pdf::Document* base_doc = nullptr;  // the document the others clone
  // MPVG_PDF_SHARED_CONTEXT=1: workers clone the first context
  // (fz_clone_context) instead of each having its own; for measurements.
  bool shared_context = false;
};

}  // namespace

int main(int argc, char** argv) {
  using namespace mpvg;
  cli::Options opt;
  PdfOptions pdf;
  try {
    std::vector<char*> rest = own_options(argc, argv, pdf);
    if (rest.empty()) return 0;  // --help
    if (!cli::parse(static_cast<int>(rest.size()), rest.data(), "pdf2png", "pdf", opt)) return 0;
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "pdf2png: %s\n", e.message.c_str());
    return 2;
  }
  if (!pdf.transparent && opt.background.a == 0) opt.background = RGBA{1, 1, 1, 1};
  const auto t_start = std::chrono::steady_clock::now();
  Pipeline p(pdf, opt);
  try {
    const pdf::Document doc(opt.positional[0], pdf.password);
    const int count = doc.page_count();
    p.first = pdf.first;
    p.last = pdf.singlefile ? std::min(pdf.first, count) : pdf.last < 0 ? count : std::min(pdf.last, count);
    p.digits = static_cast<int>(std::to_string(count).size());
    const int pages = std::max(0, p.last - p.first + 1) * pdf.repeat;
    if (pages == 0) return 0;
    p.tickets = pages;
    // A progress line on a terminal for multi-page jobs.
    p.progress = !opt.quiet && pages > 1 && isatty(fileno(stderr));
    FrameRenderer renderer(opt.backend);
    if (!renderer.note().empty() && opt.stats) std::fprintf(stderr, "pdf2png: %s\n", renderer.note().c_str());
    const bool cuda = renderer.backend() == Backend::Cuda;
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    // With CUDA, a few render threads (own gpu::Context and stream each)
    // overlap one page's host work and copies with another's kernels; the
    // CPU backend uses every core for one page already.
    const int renderers = std::min(pages, pdf.render_threads > 0 ? pdf.render_threads : cuda ? 3 : 1);
    // The render threads wait on the device dozens of times a page: with
    // CUDA they keep cores of their own (workers on every core starved them:
    // asymptote 109 pages/s with 16 workers, 120 with 14; BENCHMARKS.md).
    const int workers =
        std::min(pages, pdf.threads > 0 ? pdf.threads : cuda ? std::max(1, cores - renderers) : cores);
    p.max_in_flight = workers + 4 + renderers;
    p.renderers = renderers;
    p.base_doc = &doc;
    const char* shared = std::getenv("MPVG_PDF_SHARED_CONTEXT");
    p.shared_context = shared && std::string(shared) == "1";
    std::vector<std::thread> threads;
    for (int i = 0; i < workers; i++) threads.emplace_back([&p, &doc, i] { p.work(i == 0 ? &doc : nullptr); });
    // This thread renders, with `renderers - 1` more; the workers lower and
    // write.
    std::vector<std::unique_ptr<FrameRenderer>> more;
    for (int i = 1; i < renderers; i++) more.push_back(std::make_unique<FrameRenderer>(renderer.backend()));
    for (auto& r : more) threads.emplace_back([&p, &r] { p.render(*r); });
    p.render(renderer);
    for (std::thread& t : threads) t.join();
    if (p.progress) std::fprintf(stderr, "\r\033[Kpdf2png: %d pages, %d failed\n", pages, p.failed);
    if (opt.stats) {
      const double s = ms_since(t_start) / 1000;
      std::fprintf(stderr, "pdf2png: %d pages in %.3f s (%.1f pages/s), %d workers, %d render threads, %s backend\n",
                   pages, s, pages / s, workers, renderers, cuda ? "cuda" : "cpu");
      const Pipeline::Totals& t = p.totals;
      const int ok = std::max(1, pages - p.failed);
      std::fprintf(stderr,
                   "pdf2png: per page (mean ms): interpretation %.2f, lowering %.2f, encoding %.2f, preprocessing "
                   "%.2f, rendering %.2f, render thread %.2f, PNG %.2f (of which writing the file %.2f); idle: "
                   "render threads %.0f%%, workers %.0f%%\n",
                   t.interpret / ok, t.lower / ok, t.encode / ok, t.preprocess / ok, t.render / ok,
                   t.render_wall / ok, t.png / ok, t.write / ok, 100 * t.render_idle / (renderers * s * 1000),
                   100 * t.worker_idle / (workers * s * 1000));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%spdf2png: %s\n", p.progress ? "\n" : "", e.what());
    return 1;
  }
  return p.failed ? 1 : 0;
}
