// pdf2png: renders the pages of a PDF document to PNGs, like pdftoppm:
//
//   pdf2png [options] IN.pdf OUT-PREFIX      writes OUT-PREFIX-1.png, ...
//
// Page numbers are zero-padded to the digits of the page count, as
// pdftoppm does. Options of its own: -r/--dpi N (default 150), --scale-to N
// (the longer side in pixels), -x X -y Y -W W -H H (a crop window in
// pixels), -f N and -l N (first and last page), --singlefile (the first
// page only, written to OUT-PREFIX.png), --password P, --transparent (no
// white page background); IN.pdf "-" reads stdin. The rendering options
// are svg2png's (--aa, --gamma, --backend, --bits, --stats, -q).
//
// Work in progress (issue 11): one page after another on the calling
// thread. A page that fails is reported and the others are still written;
// the exit status is 1 if any page failed.
#include <cmath>
#include <cstdio>
#include <unistd.h>
#include <exception>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "apps/image_io.h"
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
};

// Takes pdf2png's own options out of argv; the rest goes to cli::parse.
std::vector<char*> own_options(int argc, char** argv, PdfOptions& p) {
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; i++) {
    const std::string a = argv[i];
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
    else
      rest.push_back(argv[i]);
  }
  return rest;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mpvg;
  cli::Options opt;
  PdfOptions pdf;
  try {
    std::vector<char*> rest = own_options(argc, argv, pdf);
    if (!cli::parse(static_cast<int>(rest.size()), rest.data(), "pdf2png", "pdf", opt)) return 0;
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "pdf2png: %s\n", e.message.c_str());
    return 2;
  }
  if (!pdf.transparent && opt.background.a == 0) opt.background = RGBA{1, 1, 1, 1};
  int failed = 0;
  try {
    const pdf::Document doc(opt.positional[0], pdf.password);
    const int count = doc.page_count();
    const int last = pdf.singlefile ? pdf.first : pdf.last < 0 ? count : std::min(pdf.last, count);
    const int digits = static_cast<int>(std::to_string(count).size());
    // A progress line on a terminal for multi-page jobs.
    const bool progress = !opt.quiet && last > pdf.first && isatty(fileno(stderr));
    for (int n = pdf.first; n <= last; n++) {
      if (progress) std::fprintf(stderr, "\rpdf2png: page %d of %d-%d ", n, pdf.first, last);
      char name[32];
      std::snprintf(name, sizeof name, "-%0*d.png", digits, n);
      const std::string out = opt.output + (pdf.singlefile ? std::string(".png") : std::string(name));
      try {
        // --scale-to: the resolution follows from the page's size.
        const pdf::PageResult page = doc.page(n - 1, [&pdf](double w, double h) {
          return pdf.scale_to > 0 ? pdf.scale_to / std::max(w, h) : pdf.dpi / 72.0;
        });
        const double scale = page.pixels_per_point;
        if (!opt.quiet)
          for (const std::string& w : page.warnings) std::fprintf(stderr, "pdf2png: page %d: warning: %s\n", n, w.c_str());
        int width = std::max(1, static_cast<int>(std::ceil(page.scene.width * scale - 1e-6)));
        int height = std::max(1, static_cast<int>(std::ceil(page.scene.height * scale - 1e-6)));
        // -x -y -W -H: a window of the page's pixels (the rest of the page if
        // -W or -H is absent), as pdftoppm crops.
        if (pdf.crop_x || pdf.crop_y || pdf.crop_w || pdf.crop_h) {
          width = pdf.crop_w ? pdf.crop_w : std::max(1, width - pdf.crop_x);
          height = pdf.crop_h ? pdf.crop_h : std::max(1, height - pdf.crop_y);
        }
        const Affine view = Affine::translate(-pdf.crop_x, -pdf.crop_y) * Affine::scale(scale, scale);
        RenderStats stats;
        const ImageF img = render(page.scene, cli::render_options(opt, width, height, view), &stats);
        if (opt.bits == 16)
          write_png_rgba16(out, width, height, to_rgba16(img, opt.gamma));
        else
          write_png_rgba8(out, width, height, to_rgba8(img, opt.gamma));
        if (opt.stats) std::fprintf(stderr, "page %d\n%s", n, cli::format_stats(stats).c_str());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%spdf2png: %s\n", progress ? "\n" : "", e.what());
        failed++;
      }
    }
    if (progress) std::fprintf(stderr, "\rpdf2png: %d pages, %d failed%*s\n", last - pdf.first + 1, failed, 12, "");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pdf2png: %s\n", e.what());
    return 1;
  }
  return failed ? 1 : 0;
}
