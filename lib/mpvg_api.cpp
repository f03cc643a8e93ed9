// The public API (include/mpvg/mpvg.h) over the internal pipeline. Each
// step is the one svg2png takes, in the same order and with the same
// helpers (cli::output_geometry, cli::render_options from lib/pipeline/cli.cpp,
// which this library compiles too), so that a Bitmap is byte for byte the
// PNG's pixels.
#include "core/error.h"  // mpvg::Error (the public header's copy is skipped)
#include "mpvg/mpvg.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <new>
#include <type_traits>
#include <utility>

#include "lib/pipeline/cli.h"
#include "lib/compare/image_compare.h"
#include "lib/output/png_writer.h"
#include "core/memory_budget.h"
#include "frame/frame.h"
#include "frame/scene_info.h"
#include "lib/backend/backend.h"
#include "parsers/svg/svg_parser.h"
#include "parsers/svg/svg_resources.h"
#include "parsers/svg/svg_values.h"
#ifdef MPVG_HAVE_PDF
#include <thread>

#include "lib/output/ink_output.h"
#include "lib/pipeline/pdf_page_job.h"
#include "lib/pipeline/pipeline.h"
#include "parsers/pdf/pdf_parser.h"
#include "cpu/cpu_frame.h"
#endif

#define MPVG_HIDDEN __attribute__((visibility("hidden")))

namespace mpvg {

// The public header promises that its Error is this class; a change to
// core/error.h that breaks the promise should stop the build here.
static_assert(std::is_base_of_v<std::runtime_error, Error> && sizeof(Error) == sizeof(std::runtime_error) &&
              std::is_constructible_v<Error, const std::string&> && !std::is_default_constructible_v<Error>);

namespace {

// Runs f, turning any other std::exception (from the standard library or
// an image decoder) into mpvg::Error, as the public header documents.
template <class F>
auto guarded(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(e.what());
  }
}

const char* preset_name(Antialiasing aa) {
  switch (aa) {
    case Antialiasing::Box1x8: return "1x8";
    case Antialiasing::Box1x32: return "1x32";
    case Antialiasing::Cardinal4x4x32: return "4x4x32";
  }
  throw OptionError("unknown antialiasing mode");
}

// The settings as svg2png's parsed command line, checked as its option
// parser checks them.
cli::Options to_cli(const RenderSettings& s) {
  cli::Options o;
  auto positive = [](double v, const char* what) {
    if (!(std::isfinite(v) && v > 0)) throw OptionError(std::string("the ") + what + " must be positive");
  };
  if (s.width) positive(*s.width, "width");
  if (s.height) positive(*s.height, "height");
  positive(s.zoom, "zoom");
  o.width = s.width;
  o.height = s.height;
  o.zoom = s.zoom;
  o.keep_aspect = s.keep_aspect_ratio;
  const Color& c = s.background;
  for (float v : {c.r, c.g, c.b, c.a})
    if (!(v >= 0 && v <= 1)) throw OptionError("background components must lie in [0, 1]");
  o.background = RGBA{c.r, c.g, c.b, c.a};
  o.preset = preset_name(s.antialiasing);
  o.seed = s.seed;
  switch (s.gamma) {
    case GammaMode::Linear: o.gamma = Gamma::Linear; break;
    case GammaMode::Srgb: o.gamma = Gamma::Srgb; break;
    default: throw OptionError("unknown gamma mode");
  }
  if (s.bits != 8 && s.bits != 16) throw OptionError("bits must be 8 or 16, not " + std::to_string(s.bits));
  o.bits = s.bits;
  // svg2png's --font-dir, --languages, --max-memory, --allow-read, checked
  // as its option parser checks them.
  for (const std::string& d : s.font_dirs)
    if (d.empty()) throw OptionError("a font folder (--font-dir) must not be empty");
  o.font_dirs = s.font_dirs;
  for (const std::string& l : s.languages)
    if (l.empty()) throw OptionError("a language tag (--languages) must not be empty");
  if (s.languages.empty()) throw OptionError("languages needs a list of language tags, e.g. en-US,de");
  o.languages = s.languages;
  o.max_memory = s.max_memory;
  for (const std::string& d : s.allow_read)
    if (d.empty()) throw OptionError("a folder to read (--allow-read) must not be empty");
  o.allow_read = s.allow_read;
  return o;
}

bool same_view(const Affine& x, const Affine& y) {
  return x.a == y.a && x.b == y.b && x.c == y.c && x.d == y.d && x.e == y.e && x.f == y.f;
}

// What svg::parse_svg_file reads, kept so that the document can be parsed
// again for another output size.
std::string read_file(const std::string& path) { return svg::read_svg_file(path, kDefaultMaxInput); }

}  // namespace

// ------------------------------------------------------------------ Color

Color Color::parse(std::string_view css) {
  const std::optional<RGBA> c = svg::detail::parse_color(css);
  if (!c) throw Error("cannot parse the colour '" + std::string(css) + "'");
  return Color{c->r, c->g, c->b, c->a};
}

// ------------------------------------------------------------ SvgDocument

// The Impl classes are nested in exported classes, which would export them
// too; they are the library's own.
struct MPVG_HIDDEN SvgDocument::Impl {
  std::string text, base_dir;
  std::vector<std::string> allowed_dirs;

  // The latest parse and the scene-to-pixel transform it was made for.
  // Renders hold their own reference, so a parse for another size on
  // another thread never pulls a scene from under an encoder.
  std::mutex mutex;
  std::shared_ptr<const svg::ParseResult> parsed;
  Affine parsed_view;
  // What else the parse depends on (fonts, languages, the read policy,
  // the memory budget, which its scene stays charged to while it renders).
  struct ParseKey {
    std::vector<std::string> font_dirs, languages, allow_read;
    uint64_t max_memory = 0;
    bool operator==(const ParseKey& k) const {
      return font_dirs == k.font_dirs && languages == k.languages && allow_read == k.allow_read &&
             max_memory == k.max_memory;
    }
  };
  ParseKey parsed_key;
  std::shared_ptr<MemoryBudget> parsed_budget;

  static ParseKey key_of(const cli::Options& o) { return {o.font_dirs, o.languages, o.allow_read, o.max_memory}; }

  // The document parsed for o's output (svg2png's steps: strokes converted
  // for the view the output geometry gives), that geometry, and in
  // *budget the budget the parse was charged to (its render's too).
  std::shared_ptr<const svg::ParseResult> parse_for(const cli::Options& o, int* width, int* height, Affine* view,
                                                    std::shared_ptr<MemoryBudget>* budget = nullptr) {
    std::lock_guard<std::mutex> lock(mutex);
    const ParseKey key = key_of(o);
    if (parsed && key == parsed_key) {
      cli::output_geometry(o, parsed->scene.width, parsed->scene.height, width, height, view);
      if (same_view(*view, parsed_view)) {
        if (budget) *budget = parsed_budget;
        return parsed;
      }
    }
    // svg2png's parse_options_for (apps/svg2png.cpp): the read policy,
    // the fonts, the images' share of the memory budget (RGBA8 and a mip
    // chain of a third more, 16/3 bytes a texel; half of it for decoders
    // that hold a whole image), one budget for the parse and the render.
    svg::ParseOptions po;
    po.allowed_dirs = allowed_dirs;
    po.allowed_dirs.insert(po.allowed_dirs.end(), o.allow_read.begin(), o.allow_read.end());
    po.font_dirs = o.font_dirs;
    po.languages = o.languages;
    const uint64_t images = memory_shares(cli::memory_budget(o)).images;
    po.max_image_pixels = std::min<uint64_t>(po.max_image_pixels, images * 3 / 16);
    po.max_whole_image_pixels = std::min<uint64_t>(po.max_whole_image_pixels, images / 8);
    po.budget = cli::make_budget(o);
    po.view = [&o](double w, double h) {
      int pw, ph;
      Affine v;
      cli::output_geometry(o, w, h, &pw, &ph, &v);
      return v;
    };
    auto result = std::make_shared<const svg::ParseResult>(svg::parse_svg_string(text, base_dir, po));
    cli::output_geometry(o, result->scene.width, result->scene.height, width, height, view);
    parsed = std::move(result);
    parsed_view = *view;
    parsed_key = key;
    parsed_budget = po.budget;
    if (budget) *budget = parsed_budget;
    return parsed;
  }

  // The latest parse, or one at the document's own size.
  std::shared_ptr<const svg::ParseResult> any_parse() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (parsed) return parsed;
    }
    int w, h;
    Affine view;
    return parse_for(cli::Options{}, &w, &h, &view);
  }
};

SvgDocument::SvgDocument(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SvgDocument::~SvgDocument() = default;
SvgDocument::SvgDocument(SvgDocument&&) noexcept = default;
SvgDocument& SvgDocument::operator=(SvgDocument&&) noexcept = default;

SvgDocument SvgDocument::from_file(const std::string& path, const std::vector<std::string>& allowed_dirs) {
  return guarded([&] {
    auto impl = std::make_unique<Impl>();
    impl->text = read_file(path);
    // The folder parse_svg_file resolves against.
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    impl->base_dir = dir.empty() ? std::string(".") : dir.string();
    impl->allowed_dirs = allowed_dirs;
    return SvgDocument(std::move(impl));
  });
}

SvgDocument SvgDocument::from_data(std::string_view svg, const std::string& base_dir,
                                   const std::vector<std::string>& allowed_dirs) {
  return guarded([&] {
    auto impl = std::make_unique<Impl>();
    impl->text = std::string(svg);
    impl->base_dir = base_dir.empty() ? std::string(".") : base_dir;
    impl->allowed_dirs = allowed_dirs;
    return SvgDocument(std::move(impl));
  });
}

double SvgDocument::width() const {
  return guarded([&] { return impl_->any_parse()->scene.width; });
}

double SvgDocument::height() const {
  return guarded([&] { return impl_->any_parse()->scene.height; });
}

OutputSize SvgDocument::output_size(const RenderSettings& settings) const {
  return guarded([&] {
    const cli::Options o = to_cli(settings);
    const std::shared_ptr<const svg::ParseResult> doc = impl_->any_parse();
    OutputSize size;
    Affine view;
    cli::output_geometry(o, doc->scene.width, doc->scene.height, &size.width, &size.height, &view);
    return size;
  });
}

std::vector<std::string> SvgDocument::warnings() const {
  return guarded([&] { return impl_->any_parse()->warnings; });
}

// ------------------------------------------------------------ PdfDocument

#ifdef MPVG_HAVE_PDF
struct MPVG_HIDDEN PdfDocument::Impl {
  std::unique_ptr<pdf::Document> doc;
  std::mutex mutex;  // MuPDF: one thread at a time per document handle
  std::vector<std::string> warnings;

  // Page `index` as pdf2png's pipeline job (lib/pipeline/pdf_page_job.h), its
  // warnings kept as the latest.
  std::unique_ptr<pipeline::Job> job(int index, const PdfPageRequest& request, const cli::Options& o);
};
#else
struct MPVG_HIDDEN PdfDocument::Impl {};
#endif

namespace {

#ifndef MPVG_HAVE_PDF
[[noreturn]] void no_pdf() { throw UnsupportedError("this build of mpvg has no PDF support (MuPDF was not found)"); }
#endif

DeviceBitmap device_bitmap(FrameRenderer::DeviceImage&& d) {
  DeviceBitmap out;
  out.width = d.width;
  out.height = d.height;
  out.device = d.device;
  out.pixels = std::move(d.data);
  return out;
}

#ifdef MPVG_HAVE_PDF
pdf::PageBox to_box(PageBox b) {
  switch (b) {
    case PageBox::Media: return pdf::PageBox::Media;
    case PageBox::Crop: return pdf::PageBox::Crop;
    case PageBox::Bleed: return pdf::PageBox::Bleed;
    case PageBox::Trim: return pdf::PageBox::Trim;
    case PageBox::Art: return pdf::PageBox::Art;
  }
  throw OptionError("unknown page box");
}

// pdf2png's options for these settings (its defaults where they agree).
cli::Options to_cli(const PdfRenderSettings& s) {
  if (!(std::isfinite(s.dpi) && s.dpi > 0)) throw OptionError("the resolution must be positive");
  // pdf2png's -ry, -scale-to, -scale-to-x/-y, checked as its parser does.
  if (!(std::isfinite(s.dpi_y) && s.dpi_y >= 0)) throw OptionError("the vertical resolution must be positive");
  if (s.scale_to < 0 || s.scale_to > (1 << 20)) throw OptionError("scale_to must be a positive number of pixels");
  for (int v : {s.scale_to_x, s.scale_to_y})
    if (v < -1 || v > (1 << 20))
      throw OptionError("scale_to_x and scale_to_y take a number of pixels, or -1 (keep the aspect ratio)");
  RenderSettings r;
  r.antialiasing = s.antialiasing;
  r.seed = s.seed;
  r.gamma = s.gamma;
  r.background = s.background;
  // Print preview (pdf2png --colorspace cmyk): ink amounts integrated as
  // they are, over paper (no ink).
  if (s.colorspace == OutputColorSpace::Cmyk) {
    if (s.bits != 8) throw OptionError("CMYK pages are rendered with 8 bits a channel");
    if (s.gamma == GammaMode::Linear)
      throw OptionError("CMYK integrates ink amounts as they are: not with linear gamma");
    r.background = Color{0, 0, 0, 1};
  }
  r.bits = s.bits;
  r.max_memory = s.max_memory;
  return to_cli(r);
}

// pdf2png's page request for these settings.
PdfPageRequest to_request(const PdfRenderSettings& s) {
  PdfPageRequest r;
  r.dpi = s.dpi;
  r.dpi_y = s.dpi_y;
  r.scale_to = s.scale_to;
  r.scale_to_x = s.scale_to_x;
  r.scale_to_y = s.scale_to_y;
  r.page = pdf::PageOptions(to_box(s.box));
  r.page.annotations = s.annotations;
  r.page.thin_lines = s.snap_thin_lines ? pdf::ThinLines::Snap : pdf::ThinLines::Exact;
  if (s.colorspace == OutputColorSpace::Cmyk) r.page.inks = pdf::InkModel::Cmyk;
  return r;
}

// Device bitmaps hold what render_rgba8_device leaves: 8-bit RGBA.
void check_device_output(const PdfRenderSettings& s) {
  if (s.bits != 8) throw OptionError("device bitmaps hold 8 bits a channel");
  if (s.colorspace != OutputColorSpace::Rgb)
    throw OptionError("device bitmaps hold RGBA pixels: render gray or CMYK to the host");
}

void check_page(const pdf::Document& doc, int index) {
  if (index < 0 || index >= doc.page_count())
    throw Error("page " + std::to_string(index + 1) + " is past the last page (" + std::to_string(doc.page_count()) +
                ")");
}

// pdf2png's pipeline over `pages` of `doc`, a document handle per worker
// (MuPDF: one thread per context), rendered by `first` and, on more render
// threads with CUDA, renderers like it; cancelled() is asked before each
// page; deliver and failed as pipeline::Config's.
void run_pages(const pdf::Document& doc, const std::vector<int>& pages, const PdfPageRequest& request,
               const cli::Options& o, std::unique_ptr<FrameRenderer> first, int threads, bool device_output,
               const std::function<bool()>& cancelled, const std::function<void(pipeline::Job&)>& deliver,
               const std::function<void(int, const std::string&)>& failed) {
  const bool cuda = first->backend() == Backend::Cuda;
  const int device = first->device();
  const int count = static_cast<int>(pages.size());
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  pipeline::Config c;
  c.program = "mpvg";
  c.unit = "page";
  c.tickets = count;
  // With CUDA, render threads (a context's stream each) overlap one page's
  // host work and copies with another's kernels. MPVG_RENDER_THREADS and
  // MPVG_PIPELINE_STATS=1 (the pipeline's summary on standard error) are
  // for measurements.
  const char* rt = std::getenv("MPVG_RENDER_THREADS");
  const int render_threads = rt && std::atoi(rt) > 0 ? std::atoi(rt) : 3;
  const char* st = std::getenv("MPVG_PIPELINE_STATS");
  c.render_threads = std::min(count, cuda ? render_threads : 1);
  c.workers = std::min(count, threads > 0 ? threads : cuda ? std::max(1, cores - c.render_threads) : cores);
  const bool stats = st && std::string(st) == "1";
  c.quiet = true;
  c.bits = o.bits;
  c.gamma = o.gamma;
  c.forest_scenes = 1;
  c.device_output = device_output;
  std::vector<std::unique_ptr<pdf::Document>> clones(c.workers);
  c.label = [&](int t) { return "page " + std::to_string(pages[t] + 1); };
  c.prepare = [&](int t, int w) {
    if (cancelled && cancelled()) throw Error("cancelled");
    if (!clones[w]) clones[w] = doc.clone();
    return pdf_page_job(request, o, *clones[w], pages[t] + 1, "");
  };
  std::mutex first_lock;
  c.make_renderer = [&](int) -> std::unique_ptr<FrameRenderer> {
    std::lock_guard<std::mutex> lock(first_lock);
    if (first) return std::move(first);
    return std::make_unique<FrameRenderer>(cuda ? Backend::Cuda : Backend::Cpu, device);
  };
  c.deliver = deliver;
  c.failed = failed;
  const pipeline::Result r = pipeline::run(c);
  if (stats) std::fprintf(stderr, "%s\n", pipeline::summary(c, r, cuda ? "cuda" : "cpu").c_str());
}

// Grey of RGBA pixels as pdf2png -gray writes it (png::gray_of), with
// alpha where `alpha`.
template <class T>
std::vector<T> gray_pixels(const std::vector<T>& rgba, bool alpha) {
  const size_t n = rgba.size() / 4, channels = alpha ? 2 : 1;
  std::vector<T> out(n * channels);
  for (size_t i = 0; i < n; i++) {
    const T* p = rgba.data() + 4 * i;
    out[i * channels] = static_cast<T>(png::gray_of(p[0], p[1], p[2]));
    if (alpha) out[i * 2 + 1] = p[3];
  }
  return out;
}

// A rendered job's pixels as a Bitmap (pipeline.h: rgba8, or image for 16
// bits; print preview's passes side by side for CMYK), in the settings'
// colour space.
Bitmap bitmap_of(pipeline::Job& job, const PdfRenderSettings& settings, Gamma gamma) {
  Bitmap out;
  out.width = job.width;
  out.height = job.height;
  out.bits = settings.bits;
  if (job.inks) {
    out.width = job.inks->width;
    out.channels = static_cast<int>(job.inks->names.size());
    out.pixels8 = gather_inks(*job.inks, job.width, job.height, job.rgba8.data());
    return out;
  }
  if (settings.bits == 16) out.pixels16 = to_rgba16(job.image, gamma);
  else out.pixels8 = std::move(job.rgba8);
  if (settings.colorspace == OutputColorSpace::Gray) {
    const bool alpha = settings.background.a < 1;
    out.channels = alpha ? 2 : 1;
    if (settings.bits == 16) out.pixels16 = gray_pixels(out.pixels16, alpha);
    else out.pixels8 = gray_pixels(out.pixels8, alpha);
  }
  return out;
}
#endif

}  // namespace

#ifdef MPVG_HAVE_PDF
std::unique_ptr<pipeline::Job> PdfDocument::Impl::job(int index, const PdfPageRequest& request,
                                                      const cli::Options& o) {
  check_page(*doc, index);
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<pipeline::Job> j = pdf_page_job(request, o, *doc, index + 1, "");
  warnings = j->warnings;
  return j;
}
#endif

PdfDocument::PdfDocument(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
PdfDocument::~PdfDocument() = default;
PdfDocument::PdfDocument(PdfDocument&&) noexcept = default;
PdfDocument& PdfDocument::operator=(PdfDocument&&) noexcept = default;

PdfDocument PdfDocument::from_file(const std::string& path, const std::string& password) {
#ifdef MPVG_HAVE_PDF
  return guarded([&] {
    auto impl = std::make_unique<Impl>();
    impl->doc = std::make_unique<pdf::Document>(path, password, kDefaultMaxInput);
    return PdfDocument(std::move(impl));
  });
#else
  (void)path, (void)password;
  no_pdf();
#endif
}

PdfDocument PdfDocument::from_data(std::string_view pdf, const std::string& password) {
#ifdef MPVG_HAVE_PDF
  return guarded([&] {
    auto impl = std::make_unique<Impl>();
    auto bytes = std::make_shared<const std::vector<unsigned char>>(pdf.begin(), pdf.end());
    impl->doc = std::make_unique<pdf::Document>(std::move(bytes), "<bytes>", password);
    return PdfDocument(std::move(impl));
  });
#else
  (void)pdf, (void)password;
  no_pdf();
#endif
}

int PdfDocument::page_count() const {
#ifdef MPVG_HAVE_PDF
  return impl_->doc->page_count();
#else
  no_pdf();
#endif
}

std::pair<double, double> PdfDocument::page_size(int index, PageBox box) const {
#ifdef MPVG_HAVE_PDF
  return guarded([&] {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->doc->page_size(index, to_box(box));
  });
#else
  (void)index, (void)box;
  no_pdf();
#endif
}

OutputSize PdfDocument::output_size(int index, const PdfRenderSettings& settings) const {
#ifdef MPVG_HAVE_PDF
  return guarded([&] {
    to_cli(settings);  // the same checks
    const auto [w, h] = page_size(index, settings.box);
    // pdf_page_job's sizing (pdftoppm's -r/-ry, -scale-to, -scale-to-x/-y).
    double sx = 1, sy = 1;
    page_scale(to_request(settings), w, h, &sx, &sy);
    return OutputSize{page_pixels(w, sx), page_pixels(h, sy)};
  });
#else
  (void)index, (void)settings;
  no_pdf();
#endif
}

void PdfDocument::render_pages(const std::vector<int>& pages, const PdfRenderSettings& settings, const PageSink& sink,
                               const PageFailure& failed, Device device, int threads,
                               const std::function<bool()>& cancelled) const {
#ifdef MPVG_HAVE_PDF
  guarded([&] {
    const cli::Options o = to_cli(settings);
    const PdfPageRequest request = to_request(settings);
    for (int p : pages) check_page(*impl_->doc, p);
    if (pages.empty()) return;
    const Backend backend = device == Device::Cpu ? Backend::Cpu : device == Device::Cuda ? Backend::Cuda : Backend::Auto;
    // The first render thread's renderer, made here: it tells whether CUDA
    // is there (and Device::Cuda without it throws before any page).
    run_pages(*impl_->doc, pages, request, o, std::make_unique<FrameRenderer>(backend), threads, false, cancelled,
              [&](pipeline::Job& job) {
                sink(static_cast<size_t>(job.index), bitmap_of(job, settings, o.gamma), std::move(job.warnings));
              },
              [&](int t, const std::string& message) { failed(static_cast<size_t>(t), message); });
  });
#else
  (void)pages, (void)settings, (void)sink, (void)failed, (void)device, (void)threads, (void)cancelled;
  no_pdf();
#endif
}

void PdfDocument::render_pages_device(const std::vector<int>& pages, const PdfRenderSettings& settings,
                                      const DevicePageSink& sink, const PageFailure& failed, int threads,
                                      const std::function<bool()>& cancelled) const {
#ifdef MPVG_HAVE_PDF
  guarded([&] {
    check_device_output(settings);
    const cli::Options o = to_cli(settings);
    const PdfPageRequest request = to_request(settings);
    for (int p : pages) check_page(*impl_->doc, p);
    if (pages.empty()) return;
    // The page's own device image (FrameRenderer::render_rgba8_device),
    // handed on as it is.
    run_pages(*impl_->doc, pages, request, o, std::make_unique<FrameRenderer>(Backend::Cuda), threads, true,
              cancelled,
              [&](pipeline::Job& job) {
                sink(static_cast<size_t>(job.index), device_bitmap(std::move(job.device_image)),
                     std::move(job.warnings));
              },
              [&](int t, const std::string& message) { failed(static_cast<size_t>(t), message); });
  });
#else
  (void)pages, (void)settings, (void)sink, (void)failed, (void)threads, (void)cancelled;
  no_pdf();
#endif
}

DeviceBitmap PdfDocument::render_batch(const std::vector<int>& pages, const PdfRenderSettings& settings,
                                       int threads) const {
#ifdef MPVG_HAVE_PDF
  return guarded([&] {
    check_device_output(settings);
    const cli::Options o = to_cli(settings);
    const PdfPageRequest request = to_request(settings);
    if (pages.empty()) throw Error("no pages to render");
    OutputSize size{};
    for (size_t k = 0; k < pages.size(); k++) {
      check_page(*impl_->doc, pages[k]);
      const OutputSize s = output_size(pages[k], settings);
      if (k == 0) size = s;
      if (s.width != size.width || s.height != size.height)
        throw Error("page " + std::to_string(pages[k] + 1) + " is " + std::to_string(s.width) + "x" +
                    std::to_string(s.height) + " pixels, page " + std::to_string(pages[0] + 1) + " " +
                    std::to_string(size.width) + "x" + std::to_string(size.height) + ": a batch takes one size");
    }
    auto first = std::make_unique<FrameRenderer>(Backend::Cuda);
    const int device = first->device();
    const size_t image = size_t(size.width) * size.height * 4;
    DeviceBitmap out;
    out.width = size.width;
    out.height = size.height * static_cast<int>(pages.size());
    out.device = device;
    out.pixels = FrameRenderer::device_alloc(image * pages.size(), device);
    std::mutex lock;
    std::string failure;
    run_pages(*impl_->doc, pages, request, o, std::move(first), threads, true, nullptr,
              [&](pipeline::Job& job) {
                FrameRenderer::copy_on_device(job.device_image,
                                              out.pixels.get() + image * static_cast<size_t>(job.index));
                job.device_image = {};
              },
              [&](int, const std::string& message) {
                std::lock_guard<std::mutex> g(lock);
                if (failure.empty()) failure = message;
              });
    if (!failure.empty()) throw Error(failure);
    return out;
  });
#else
  (void)pages, (void)settings, (void)threads;
  no_pdf();
#endif
}

std::vector<std::string> PdfDocument::warnings() const {
#ifdef MPVG_HAVE_PDF
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->warnings;
#else
  return {};
#endif
}

// --------------------------------------------------------------- Renderer

struct MPVG_HIDDEN Renderer::Impl {
  std::unique_ptr<FrameRenderer> frames;

  // Renders doc as svg2png does; `expect`, when given, is the size the
  // caller's buffer has, checked before any rendering.
  Bitmap render(SvgDocument::Impl& doc, const RenderSettings& settings, const OutputSize* expect) {
    const cli::Options o = to_cli(settings);
    int width, height;
    Affine view;
    std::shared_ptr<MemoryBudget> budget;
    const std::shared_ptr<const svg::ParseResult> parsed = doc.parse_for(o, &width, &height, &view, &budget);
    if (expect && (expect->width != width || expect->height != height))
      throw OptionError("the buffer is " + std::to_string(expect->width) + "x" + std::to_string(expect->height) +
                  " pixels, the output " + std::to_string(width) + "x" + std::to_string(height));
    RenderOptions ro = cli::render_options(o, width, height, view, budget);
    ro.aliased_paths = has_aliased_paths(parsed->scene);
    Bitmap out;
    out.width = width;
    out.height = height;
    out.bits = o.bits;
    if (o.bits == 16) {
      const EncodedScene enc = encode_for(parsed->scene, ro);
      out.pixels16 = to_rgba16(frames->render(enc, ro), ro.gamma);
    } else {
      // The same bytes as to_rgba8(render(...)) (lib/backend/backend.h), converted
      // on the device with CUDA.
      const RenderPlan plan = plan_render(ro);
      const EncodedScene enc = encode_for(parsed->scene, plan, ro.gamma);
      out.pixels8 = frames->render_rgba8(enc, plan, ro);
    }
    return out;
  }
};

Renderer::Renderer(Device device) : impl_(std::make_unique<Impl>()) {
  guarded([&] {
    const Backend b = device == Device::Cpu ? Backend::Cpu : device == Device::Cuda ? Backend::Cuda : Backend::Auto;
    impl_->frames = std::make_unique<FrameRenderer>(b);
  });
}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Device Renderer::device() const { return impl_->frames->backend() == Backend::Cuda ? Device::Cuda : Device::Cpu; }

std::string Renderer::note() const { return impl_->frames->note(); }

Bitmap Renderer::render(const PdfDocument& doc, int index, const PdfRenderSettings& settings) {
#ifdef MPVG_HAVE_PDF
  return guarded([&] {
    // pdf2png's steps: the page as its pipeline job (lib/pipeline/pdf_page_job.h),
    // rendered as its render threads render it.
    const cli::Options o = to_cli(settings);
    const std::unique_ptr<pipeline::Job> job = doc.impl_->job(index, to_request(settings), o);
    if (o.bits == 16) job->image = impl_->frames->render(job->scene, job->options);
    else job->rgba8 = impl_->frames->render_rgba8(job->scene, job->plan, job->options);
    return bitmap_of(*job, settings, job->options.gamma);
  });
#else
  (void)doc, (void)index, (void)settings;
  no_pdf();
#endif
}

namespace {

// Throws unless b is a non-empty image of 1 to 4 channels whose pixels
// vector (8 or 16 bits) holds exactly its pixels.
void check_bitmap(const Bitmap& b, const std::string& what) {
  if (b.width <= 0 || b.height <= 0 || b.channels < 1 || b.channels > 4 || (b.bits != 8 && b.bits != 16) ||
      (b.bits == 8 ? b.pixels8.size() : b.pixels16.size()) != size_t(b.width) * size_t(b.height) * size_t(b.channels))
    throw Error(what + ": the bitmap's size, channels or bits are inconsistent");
}

image_compare::Picture picture_of(const Bitmap& b, const char* which) {
  check_bitmap(b, std::string("compare: image ") + which);
  return b.bits == 16 ? image_compare::from_straight16(b.pixels16.data(), b.width, b.height, b.channels)
                      : image_compare::from_straight8(b.pixels8.data(), b.width, b.height, b.channels);
}

}  // namespace

Bitmap read_png(const std::string& path) {
  return guarded([&] {
    const std::string data = read_file(path);
    std::string why;
    const std::shared_ptr<Image> image = svg::detail::decode_raster(std::vector<uint8_t>(data.begin(), data.end()), &why);
    if (!image) throw Error(path + ": " + (why.empty() ? "not a PNG" : why));
    Bitmap out;
    out.width = image->width;
    out.height = image->height;
    out.bits = image->bits;
    out.pixels8 = std::move(image->rgba8);  // the decoded image is this call's alone
    out.pixels16 = std::move(image->rgba16);
    return out;
  });
}

void write_png(const std::string& path, const Bitmap& b) {
  guarded([&] {
    check_bitmap(b, "write_png");
    // As RGBA (grey expanded; opaque images are written as RGB).
    auto rgba = [&](const auto& px) {
      using T = typename std::decay_t<decltype(px)>::value_type;
      const T full = b.bits == 8 ? T(255) : T(65535);
      std::vector<T> out(size_t(b.width) * b.height * 4);
      const int c = b.channels;
      for (size_t i = 0, m = size_t(b.width) * b.height; i < m; i++) {
        const T* p = &px[i * c];
        T* q = &out[i * 4];
        q[0] = p[0], q[1] = c >= 3 ? p[1] : p[0], q[2] = c >= 3 ? p[2] : p[0];
        q[3] = c == 2 ? p[1] : c == 4 ? p[3] : full;
      }
      return out;
    };
    png::write_file(path, b.bits == 8 ? png::encode_rgba8(b.width, b.height, rgba(b.pixels8).data())
                                      : png::encode_rgba16(b.width, b.height, rgba(b.pixels16).data()));
  });
}

CompareResult compare(const Bitmap& a, const Bitmap& b, const CompareSettings& s, bool diff_image) {
  return guarded([&] {
    image_compare::Options o;
    o.fail = s.fail, o.failpercent = s.failpercent, o.warn = s.warn, o.warnpercent = s.warnpercent;
    if (s.hardfail >= 0) o.hardfail = s.hardfail;
    if (s.hardwarn >= 0) o.hardwarn = s.hardwarn;
    o.antialiasing = s.antialiasing;
    o.aa_ring = s.aa_ring;
    std::vector<uint8_t> diff;
    const image_compare::Result r = image_compare::compare(picture_of(a, "a"), picture_of(b, "b"), o, diff_image ? &diff : nullptr);
    CompareResult out;
    out.verdict = r.verdict == image_compare::Verdict::Pass   ? CompareVerdict::Pass
                  : r.verdict == image_compare::Verdict::Warn ? CompareVerdict::Warn
                                                        : CompareVerdict::Fail;
    out.same_size = r.same_size;
    out.width = r.width, out.height = r.height;
    out.pixels = r.pixels, out.differing = r.differing, out.failed = r.failed, out.warned = r.warned;
    out.antialiased = r.antialiased;
    out.max_difference = r.max_difference, out.max_x = r.max_x, out.max_y = r.max_y;
    out.mean_difference = r.mean_difference, out.rms_difference = r.rms_difference, out.psnr = r.psnr;
    if (diff_image && r.same_size) {
      out.diff.width = a.width;
      out.diff.height = a.height;
      out.diff.pixels8 = std::move(diff);
    }
    out.json = image_compare::to_json(r, o);
    return out;
  });
}

std::vector<uint8_t> download(const DeviceBitmap& bitmap) {
  return guarded([&] {
    FrameRenderer::DeviceImage d;
    d.data = bitmap.pixels;
    d.width = bitmap.width;
    d.height = bitmap.height;
    d.device = bitmap.device;
    return FrameRenderer::download(d);
  });
}

DeviceBitmap Renderer::render_device(const SvgDocument& doc, const RenderSettings& settings) {
  return guarded([&] {
    if (settings.bits != 8) throw OptionError("device bitmaps hold 8 bits a channel");
    const cli::Options o = to_cli(settings);
    int width, height;
    Affine view;
    std::shared_ptr<MemoryBudget> budget;
    const std::shared_ptr<const svg::ParseResult> parsed = doc.impl_->parse_for(o, &width, &height, &view, &budget);
    RenderOptions ro = cli::render_options(o, width, height, view, budget);
    ro.aliased_paths = has_aliased_paths(parsed->scene);
    const RenderPlan plan = plan_render(ro);
    const EncodedScene enc = encode_for(parsed->scene, plan, ro.gamma);
    return device_bitmap(impl_->frames->render_rgba8_device(enc, plan, ro));
  });
}

DeviceBitmap Renderer::render_device(const PdfDocument& doc, int index, const PdfRenderSettings& settings) {
#ifdef MPVG_HAVE_PDF
  return guarded([&] {
    check_device_output(settings);
    const cli::Options o = to_cli(settings);
    const std::unique_ptr<pipeline::Job> job = doc.impl_->job(index, to_request(settings), o);
    return device_bitmap(impl_->frames->render_rgba8_device(job->scene, job->plan, job->options));
  });
#else
  (void)doc, (void)index, (void)settings;
  no_pdf();
#endif
}

Bitmap Renderer::render(const SvgDocument& doc, const RenderSettings& settings) {
  return guarded([&] { return impl_->render(*doc.impl_, settings, nullptr); });
}

void Renderer::render(const SvgDocument& doc, const RenderSettings& settings, void* pixels, std::size_t stride,
                      int width, int height) {
  guarded([&] {
    if (!pixels || width <= 0 || height <= 0) throw OptionError("no pixel buffer given");
    const size_t row = static_cast<size_t>(width) * 4 * (settings.bits / 8);
    if (stride < row)
      throw OptionError("the stride (" + std::to_string(stride) + " bytes) is shorter than a row (" + std::to_string(row) +
                  " bytes)");
    const OutputSize expect{width, height};
    const Bitmap b = impl_->render(*doc.impl_, settings, &expect);
    const uint8_t* src = b.bits == 16 ? reinterpret_cast<const uint8_t*>(b.pixels16.data()) : b.pixels8.data();
    for (int y = 0; y < height; y++)
      std::memcpy(static_cast<uint8_t*>(pixels) + y * stride, src + y * row, row);
  });
}

}  // namespace mpvg
