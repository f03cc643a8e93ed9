// pdf2png: renders the pages of a PDF document to PNGs, like pdftoppm:
//
//   pdf2png [options] IN.pdf OUT-PREFIX      writes OUT-PREFIX-1.png, ...
//
// or to TIFFs or JPEGs with pdftoppm's -tiff (-tiffcompression) and -jpeg
// (-jpegopt), named .tif and .jpg as pdftoppm names them, encoded by
// OpenImageIO in a module loaded on first need (lib/output/image_writer.h;
// without it -tiff and -jpeg are refused before any page is rendered).
// They record the page's resolution; a JPEG has no alpha (--transparent is
// ignored) and 8 bits only.
//
// Page numbers are zero-padded to the digits of the page count, as
// pdftoppm does. Options of its own: -r/--dpi N (default 150), --scale-to N
// (the longer side in pixels), -x X -y Y -W W -H H (a crop window in
// pixels), -f N and -l N (first and last page), --singlefile (the first
// page only, written to OUT-PREFIX.png), --password P, --transparent (no
// white page background), --box media|crop|bleed|trim|art (the page box
// rendered, default crop; -cropbox is pdftoppm's spelling of --box crop),
// -gray and -mono (a greyscale or 1-bit PNG or TIFF, as pdftoppm's; apps/
// png_writer.h gives their formulas), --thin-lines exact|snap (snap:
// stroker/stroke_adjust.h), --gamma srgb by default (PDF composites device
// values), --threads N (worker threads, default one per
// core, less the render threads with CUDA), --render-threads N (default 3 with CUDA, 5 with --compression 1, 1 on the CPU), --repeat N
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
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <queue>
#include <string>
#include <vector>

#include "lib/pipeline/cli.h"
#include "lib/output/image_writer.h"
#include "lib/pipeline/pdf_page_job.h"
#include "lib/pipeline/pipeline.h"
#include "core/error.h"
#include "core/parallel.h"
#include "lib/backend/backend.h"
#include "parsers/pdf/output_intent.h"
#include "parsers/pdf/pdf_parser.h"

namespace {

// pdftoppm's exit codes (its manual's EXIT CODES): 0 no error, 1 the PDF
// cannot be opened, 2 an output file cannot be written, 3 permissions
// (MuPDF renders what the password opens: never), 99 anything else.
constexpr int kExitOpen = 1, kExitOutput = 2, kExitOther = 99;

// A file pdf2png writes besides the pages (--report) cannot be written.
struct WriteError : mpvg::Error {
  using mpvg::Error::Error;
};

// The CUDA devices pdf2png renders on: --devices, or every one visible,
// counted before CUDA's start-up has finished (without waiting for the
// driver): CUDA_VISIBLE_DEVICES's entries where it is set, else the
// /dev/nvidiaN device files.
std::vector<int> pdf_devices(const mpvg::cli::Options& opt, bool cuda) {
  if (!opt.devices.empty()) return opt.devices;
  int n = 0;
  if (cuda) {
    if (const char* v = std::getenv("CUDA_VISIBLE_DEVICES")) {
      const std::string s = v;
      for (size_t at = 0; at < s.size();) {
        const size_t end = std::min(s.find(',', at), s.size());
        n += end > at;
        at = end + 1;
      }
    } else {
      std::error_code ec;
      for (const auto& e : std::filesystem::directory_iterator("/dev", ec)) {
        const std::string name = e.path().filename().string();
        n += name.size() > 6 && name.rfind("nvidia", 0) == 0 &&
             name.find_first_not_of("0123456789", 6) == std::string::npos;
      }
    }
  }
  std::vector<int> devices;
  for (int d = 0; d < n; d++) devices.push_back(d);
  if (devices.empty()) devices.push_back(0);
  return devices;
}

struct PdfOptions {
  double dpi = 150;
  double dpi_y = 0;         // -ry (0: dpi)
  int first = 1, last = -1;
  bool range_given = false;  // -f or -l
  bool odd = false, even = false;  // pdftoppm's -o and -e
  std::string pages;        // --pages LIST, as mutool takes them (1-3,5,N)
  std::string password;
  bool transparent = false;
  bool singlefile = false;  // the first page only, to OUT-PREFIX.png (.jpg, .tif)
  bool forcenum = false;    // -forcenum: -singlefile's name keeps the page number
  char sep = '-';           // -sep C: between the prefix and the page number
  bool progress = false;    // -progress: "PAGE LAST FILE" on stderr per page written
  int scale_to = 0;         // the longer side in pixels (overrides the resolution)
  int scale_to_x = 0, scale_to_y = 0;  // -scale-to-x/-y (pdf_page_job.h)
  std::string report;       // --report FILE: JSON lines, one a page
  int crop_x = 0, crop_y = 0, crop_w = 0, crop_h = 0;  // -x -y -W -H, pixels at the resolution
  mpvg::pdf::PageBox box = mpvg::pdf::PageBox::Crop;   // --box, -cropbox
  bool annotations = true;                              // -hide-annotations
  mpvg::pdf::ThinLines thin_lines = mpvg::pdf::ThinLines::Exact;  // --thin-lines
  mpvg::pdf::InkModel inks = mpvg::pdf::InkModel::Rgb;             // --colorspace cmyk, --separations
  std::string cmyk_profile;                                         // --cmyk-profile FILE
  bool gray = false, mono = false;                      // -gray, -mono
  mpvg::image::Format format = mpvg::image::Format::Png;  // -png, -jpeg, -tiff
  const char* format_flag = nullptr;                      // the one given, for messages
  mpvg::image::EncodeOptions encode;                      // -jpegopt, -tiffcompression
  int threads = 0;          // worker threads; 0: one per core
  int repeat = 1;           // --repeat N: the pages N times over (benchmarks: later rounds run warm)
  // Threads rendering, each with its own backend state: per device with
  // CUDA (0: 3, or 5 with --compression 1), 1 on the CPU.
  int render_threads = 0;
};

void usage() {
  std::printf(
      "Usage: pdf2png [OPTIONS] INPUT.pdf [OUTPUT-PREFIX]\n"
      "Renders the pages of INPUT to OUTPUT-PREFIX-1.png, OUTPUT-PREFIX-2.png, ... (page\n"
      "numbers zero-padded to the page count's digits, as pdftoppm writes them) with\n"
      "the mpvg rasterizer. INPUT '-' reads standard input. Without OUTPUT-PREFIX (or\n"
      "with '-') the one page selected is written to standard output.\n"
      "pdftoppm's options are taken with one dash or two (-singlefile, --singlefile).\n\n"
      "Pages:\n"
      "  -f N, -l N                first and last page (default: all)\n"
      "  -o, -e                    odd or even pages only (of those selected)\n"
      "      --pages LIST          pages as mutool takes them: 1-3,5,N (N: the last page;\n"
      "                            a range may run backwards, 3-1)\n"
      "  -singlefile               the first page only, written to OUTPUT-PREFIX.png\n"
      "                            (.jpg, .tif)\n"
      "  -forcenum                 with -singlefile: the page number all the same\n"
      "  -sep C                    the character between prefix and number (default -)\n"
      "      --password P          the document's password (also -upw P, -opw P)\n"
      "Size:\n"
      "  -r, --dpi N               resolution (default 150); -rx N, -ry N one axis's\n"
      "  -scale-to N               the longer side in pixels (instead of -r)\n"
      "  -scale-to-x N, -scale-to-y N\n"
      "                            the width or height in pixels; the other side keeps\n"
      "                            the resolution unless it is -1: then the aspect ratio\n"
      "                            (as pdftoppm)\n"
      "  -x X -y Y -W W -H H       a crop window, in pixels at the resolution (-sz N: W\n"
      "                            and H)\n"
      "      --box B               the page box rendered: media, crop (default), bleed,\n"
      "                            trim or art (PDF 32000-1 14.11.2)\n"
      "      -cropbox              --box crop (pdftoppm's spelling)\n"
      "      -hide-annotations     leave out annotations and form fields (drawn by\n"
      "                            default, as printed)\n"
      "Output:\n"
      "      -png                  PNG files (the default)\n"
      "      -jpeg                 JPEG files, OUTPUT-PREFIX-N.jpg (8 bits, no alpha)\n"
      "      -jpegopt OPTS         quality=N (1-100, default 75),progressive=y|n,\n"
      "                            optimize=y|n (as pdftoppm's)\n"
      "      -tiff                 TIFF files, OUTPUT-PREFIX-N.tif\n"
      "      -tiffcompression C    none, packbits, lzw, deflate (default) or jpeg (8-bit\n"
      "                            RGB; other TIFFs are deflated)\n"
      "                            (-jpeg and -tiff need OpenImageIO's module; both\n"
      "                            record the resolution; long spellings --jpeg etc.)\n"
      "      --colorspace C        rgb (default), gray (as -gray) or cmyk: a CMYK TIFF of\n"
      "                            the inks the page prints with, overprint (OP, op, OPM)\n"
      "                            and blend modes composited per ink, spot colours\n"
      "                            through their CMYK alternates\n"
      "      --cmyk-profile FILE   the press's ICC profile RGB colours and images are\n"
      "                            converted into for --colorspace cmyk and --separations\n"
      "                            (default: the document's output intent; without\n"
      "                            either, PDF's device formulas)\n"
      "      --separations         print preview with spot colours as inks of their own:\n"
      "                            OUT-N.tif (every ink, separated), OUT-N(Name).tif a\n"
      "                            grey plate per ink as Ghostscript's tiffsep writes\n"
      "                            them (0: full ink), OUT-N.png the press sheet in RGB\n"
      "      --transparent         no white page background\n"
      "      --bits 8|16           bits per channel of the PNG or TIFF (default 8)\n"
      "      -gray, --gray         greyscale: 0.30 R + 0.59 G + 0.11 B (grey and alpha\n"
      "                            with --transparent where not opaque)\n"
      "      -mono, --mono         1-bit PNG or TIFF: grey dithered as pdftoppm -mono\n"
      "                            does (a 4x4 dispersed-dot threshold matrix), over white\n"
      "      --compression 0..9    PNG deflate level (TIFF's, 1-9: default 1): 0 none, 1 mpvg's parallel deflate\n"
      "                            (on the GPU where it renders: the CPU's work for PNGs\n"
      "                            drops ~20x), 2-9 libdeflate's on the CPU (default 2)\n"
      "Antialiasing (the paper's modes):\n"
      "      --aa MODE             4x4x32 (default), 1x32 or 1x8 (see svg2png --help)\n"
      "      --filter F, --samples N, --pattern P, --seed N\n"
      "      --gamma G             srgb (default: integrate device colour values, as PDF\n"
      "                            composites and MuPDF, Poppler, Acrobat draw) or linear\n"
      "      --thin-lines M        exact (default: the exact coverage, as MuPDF draws) or\n"
      "                            snap (stroke adjustment: strokes and rectangles on the\n"
      "                            pixel grid, at least a pixel wide, as Poppler and\n"
      "                            Acrobat draw; PDF 32000-1 10.7.5)\n"
      "Limits:\n"
      "      --max-memory SIZE     memory budget of one page, e.g. 2G (default: half\n"
      "                            of the machine's); a page that cannot fit is an error\n"
      "      --max-input SIZE      refuse inputs larger than SIZE (default 1G)\n"
      "Execution:\n"
      "      --backend B           auto, cpu or cuda (default auto)\n"
      "      --threads N           worker threads: interpretation, lowering, PNG (default:\n"
      "                            one per core, less the render threads with CUDA)\n"
      "      --devices LIST        CUDA devices to use, e.g. 0,1 (default: all)\n"
      "      --render-threads N    rendering threads per device (default with CUDA 3, or\n"
      "                            5 with --compression 1; 1 on the CPU)\n"
      "      --frame-scenes N      small pages rendered together as one frame, at most N\n"
      "                            (default 8 with CUDA and --compression 1, else 1)\n"
      "      --stats               per-page stage times and the job's throughput\n"
      "      --repeat N            the pages N times over (benchmarks)\n"
      "      --timeout S           give up on a page after S seconds (it fails; the\n"
      "                            others go on)\n"
      "  -progress                 a line 'PAGE LAST FILE' on standard error for each\n"
      "                            page written (pdftoppm's)\n"
      "      --report FILE         one JSON line a page: input, output, status, ms,\n"
      "                            warnings, error\n"
      "  -q, --quiet               no warnings\n"
      "  -v, --version, -h, --help\n\n"
      "Exit status, as pdftoppm's: 0 every page written; 1 the document cannot be\n"
      "opened (missing, not a PDF, damaged, wrong password); 2 an output file cannot\n"
      "be written; 99 anything else: a bad option or page range, a page that failed\n"
      "(the other pages are still written).\n");
}

// svg2png's options that pdf2png would otherwise take from cli::parse and
// not use: refused, with what to use instead (issue 47).
const char* svg_only_option(const std::string& a) {
  struct Refused {
    const char* option;
    const char* instead;
  };
  static const Refused kRefused[] = {
      {"-w", "use -r DPI or --scale-to N"},         {"--width", "use -r DPI or --scale-to N"},
      {"--height", "use -r DPI or --scale-to N"},   {"-z", "use -r DPI"},
      {"--zoom", "use -r DPI"},                     {"-a", "use --scale-to N"},
      {"--keep-aspect-ratio", "use --scale-to N"},  {"-b", "pages are drawn on white, or on nothing with --transparent"},
      {"--background", "pages are drawn on white, or on nothing with --transparent"},
      {"--server", "pdf2png renders in-process"},
      {"--shard", "run one pdf2png per document, -f and -l for page ranges"},
      {"--batch", "run one pdf2png per document"},
      {"--font-dir", "a PDF carries or names its fonts"},
      {"--languages", "a PDF has no language switches"},
      {"--allow-read", "a PDF reads no other files"},
      {"-d", "use -r DPI"},
      {"-i", "pdf2png renders whole pages (-x, -y, -W, -H crop them)"},
      {"--export-id", "pdf2png renders whole pages (-x, -y, -W, -H crop them)"},
      {"--query", "pdfinfo -box lists a document's page boxes"},
  };
  for (const Refused& r : kRefused)
    if (a == r.option) return r.instead;
  return nullptr;
}

// pdftoppm's options, which it spells with one dash; pdf2png takes them
// with one or two.
bool pdftoppm_option(const std::string& name) {
  static const char* const kNames[] = {
      "singlefile", "forcenum", "sep",  "progress", "scale-to", "scale-to-x",      "scale-to-y", "rx",
      "ry",         "upw",      "opw",  "sz",       "cropbox",  "hide-annotations", "png",        "jpeg",
      "jpegopt",    "tiff",     "tiffcompression",  "gray",     "mono"};
  for (const char* n : kNames)
    if (name == n) return true;
  return false;
}

// Takes pdf2png's own options out of argv; the rest goes to cli::parse.
// Returns an empty vector after --help or -v.
std::vector<char*> own_options(int argc, char** argv, PdfOptions& p) {
  std::vector<char*> rest{argv[0]};
  double r = 0, rx = 0, ry = 0;  // -r, -rx, -ry (0: not given)
  for (int i = 1; i < argc; i++) {
    std::string a = argv[i];
    if (a.rfind("--", 0) == 0 && pdftoppm_option(a.substr(2))) a = a.substr(1);  // --singlefile: -singlefile
    if (a == "--help" || a == "-?" || a == "-h" || a == "-help") {  // pdftoppm's -h and -help too
      usage();
      return {};
    }
    if (a == "-v") {  // pdftoppm's spelling of --version
      std::printf("pdf2png (mpvg) 0.1\n");
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
    auto whole = [&](long lo, long hi) {  // an integer in [lo, hi]
      const std::string v = value();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (end == v.c_str() || *end || n < lo || n > hi)
        throw mpvg::cli::UsageError{"invalid value '" + v + "' for " + a + " (an integer from " + std::to_string(lo) +
                                    " to " + std::to_string(hi) + ")"};
      return static_cast<int>(n);
    };
    if (const char* instead = svg_only_option(a))
      throw mpvg::cli::UsageError{a + " is an svg2png option: " + instead};
    if (a == "-r" || a == "--dpi")
      r = number(1);
    else if (a == "-rx")
      rx = number(1);
    else if (a == "-ry")
      ry = number(1);
    else if (a == "-f" || a == "-l") {
      (a == "-f" ? p.first : p.last) = whole(1, 2147483647);
      p.range_given = true;
    }
    else if (a == "-o")  // pdftoppm's: odd pages (the output prefix is the second argument, or --output)
      p.odd = true;
    else if (a == "-e")
      p.even = true;
    else if (a == "--pages") {
      p.pages = value();
      if (p.pages.empty()) throw mpvg::cli::UsageError{"--pages needs a list, e.g. 1-3,5,N"};
    } else if (a == "--password" || a == "-upw" || a == "-opw")
      p.password = value();  // MuPDF takes the user's or the owner's
    else if (a == "--transparent")
      p.transparent = true;
    else if (a == "-singlefile")
      p.singlefile = true;
    else if (a == "-forcenum")
      p.forcenum = true;
    else if (a == "-sep") {
      const std::string v = value();
      if (v.size() != 1 || v == "/")
        throw mpvg::cli::UsageError{"-sep takes one character (not '/'), got '" + v + "'"};
      p.sep = v[0];
    } else if (a == "-progress")
      p.progress = true;
    else if (a == "--report") {
      p.report = value();
      if (p.report.empty()) throw mpvg::cli::UsageError{"--report needs a file name"};
    } else if (a == "-scale-to")
      p.scale_to = whole(1, 1 << 20);
    else if (a == "-scale-to-x" || a == "-scale-to-y") {
      const int v = whole(-1, 1 << 20);
      if (v == 0) throw mpvg::cli::UsageError{a + " takes a number of pixels, or -1 (keep the aspect ratio)"};
      (a == "-scale-to-x" ? p.scale_to_x : p.scale_to_y) = v;
    } else if (a == "-x")
      p.crop_x = whole(0, 1 << 20);
    else if (a == "-y")
      p.crop_y = whole(0, 1 << 20);
    else if (a == "-W")
      p.crop_w = whole(1, 1 << 20);
    else if (a == "-H")
      p.crop_h = whole(1, 1 << 20);
    else if (a == "-sz")
      p.crop_w = p.crop_h = whole(1, 1 << 20);
    else if (a == "--box") {
      const std::string v = value();
      using mpvg::pdf::PageBox;
      if (v == "media") p.box = PageBox::Media;
      else if (v == "crop") p.box = PageBox::Crop;
      else if (v == "bleed") p.box = PageBox::Bleed;
      else if (v == "trim") p.box = PageBox::Trim;
      else if (v == "art") p.box = PageBox::Art;
      else throw mpvg::cli::UsageError{"invalid value '" + v + "' for --box (media, crop, bleed, trim or art)"};
    } else if (a == "-cropbox")
      p.box = mpvg::pdf::PageBox::Crop;
    else if (a == "--colorspace") {
      const std::string v = value();
      if (v == "rgb") p.inks = mpvg::pdf::InkModel::Rgb;
      else if (v == "gray") p.gray = true;
      else if (v == "cmyk") p.inks = mpvg::pdf::InkModel::Cmyk;
      else throw mpvg::cli::UsageError{"invalid value '" + v + "' for --colorspace (rgb, gray or cmyk)"};
    } else if (a == "--cmyk-profile")
      p.cmyk_profile = value();
    else if (a == "--separations")
      p.inks = mpvg::pdf::InkModel::Separations;
    else if (a == "--thin-lines") {
      const std::string v = value();
      if (v == "exact") p.thin_lines = mpvg::pdf::ThinLines::Exact;
      else if (v == "snap") p.thin_lines = mpvg::pdf::ThinLines::Snap;
      else throw mpvg::cli::UsageError{"invalid value '" + v + "' for --thin-lines (exact or snap)"};
    } else if (a == "-hide-annotations" || a == "--hide-annotations")
      p.annotations = false;
    else if (a == "-png" || a == "--png" || a == "-jpeg" || a == "--jpeg" || a == "-tiff" || a == "--tiff") {
      // pdftoppm's output format flags: one of them.
      using mpvg::image::Format;
      const Format f = a.find("png") != std::string::npos ? Format::Png
                       : a.find("jpeg") != std::string::npos ? Format::Jpeg
                                                             : Format::Tiff;
      if (p.format_flag && f != p.format)
        throw mpvg::cli::UsageError{std::string(p.format_flag) + " and " + a + " cannot be given together"};
      p.format = f;
      p.format_flag = argv[i];
    } else if (a == "-jpegopt" || a == "--jpegopt") {
      // quality=N,progressive=y|n,optimize=y|n, any of them, as pdftoppm reads them.
      const std::string v = value();
      for (size_t at = 0; at <= v.size();) {
        const size_t end = std::min(v.find(',', at), v.size());
        const std::string item = v.substr(at, end - at);
        at = end + 1;
        const size_t eq = item.find('=');
        const std::string key = item.substr(0, eq), val = eq == std::string::npos ? "" : item.substr(eq + 1);
        char* stop = nullptr;
        const long q = std::strtol(val.c_str(), &stop, 10);
        if (key == "quality" && !val.empty() && !*stop && q >= 1 && q <= 100)
          p.encode.jpeg_quality = static_cast<int>(q);
        else if ((key == "progressive" || key == "optimize") && (val == "y" || val == "n"))
          (key == "progressive" ? p.encode.progressive : p.encode.optimize) = val == "y";
        else
          throw mpvg::cli::UsageError{"invalid value '" + v + "' for " + a +
                                      " (quality=1..100,progressive=y|n,optimize=y|n)"};
      }
    } else if (a == "-tiffcompression" || a == "--tiffcompression") {
      const std::string v = value();
      if (v != "none" && v != "packbits" && v != "jpeg" && v != "lzw" && v != "deflate")
        throw mpvg::cli::UsageError{"invalid value '" + v + "' for " + a + " (none, packbits, jpeg, lzw or deflate)"};
      p.encode.tiff_compression = v;
    }
    else if (a == "-gray" || a == "--gray")
      p.gray = true;
    else if (a == "-mono" || a == "--mono")
      p.mono = true;
    else if (a == "--threads")
      p.threads = static_cast<int>(number(1));
    else if (a == "--repeat")
      p.repeat = static_cast<int>(number(1));
    else if (a == "--render-threads")
      p.render_threads = static_cast<int>(number(1));
    else
      rest.push_back(argv[i]);
  }
  // -rx and -ry override -r for their axis.
  p.dpi = rx > 0 ? rx : r > 0 ? r : 150;
  const double y = ry > 0 ? ry : r > 0 ? r : 150;
  p.dpi_y = y != p.dpi ? y : 0;
  if (p.odd && p.even) throw mpvg::cli::UsageError{"-o (odd pages) and -e (even pages) cannot be given together"};
  if (!p.pages.empty() && p.range_given)
    throw mpvg::cli::UsageError{"--pages and -f/-l cannot be given together"};
  if (p.forcenum && !p.singlefile) p.forcenum = false;  // numbered anyway
  return rest;
}

// The pages a run renders, in order: runs of pages `step` apart (1 or 2,
// downwards when negative), so that a range of a document with 10^9 pages
// costs nothing.
struct Selection {
  struct Run {
    int start, step, count;
  };
  std::vector<Run> runs;
  long long total = 0;
  int last = 0;  // the last page in order (pdftoppm's -progress prints it)
  int page(long long t) const {
    for (const Run& r : runs) {
      if (t < r.count) return static_cast<int>(r.start + t * r.step);
      t -= r.count;
    }
    return 0;
  }
};

// A page number of a --pages list: digits, or N (the last page).
int list_page(const std::string& item, const std::string& v, int count) {
  if (v == "N") return count;
  char* end = nullptr;
  const long n = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || end == v.c_str() || *end || n < 1)
    throw mpvg::cli::UsageError{"--pages: '" + item + "' is not a page or a range (e.g. 1-3,5,N)"};
  if (n > count)
    throw mpvg::Error("--pages: page " + std::to_string(n) + " is past the last page (" + std::to_string(count) + ")");
  return static_cast<int>(n);
}

// -f/-l or --pages, then -o/-e, then -singlefile. Throws mpvg::Error for
// pages that do not exist, cli::UsageError for a list that does not parse.
Selection select_pages(const PdfOptions& pdf, int count) {
  std::vector<std::pair<int, int>> ranges;  // inclusive, either way round
  if (!pdf.pages.empty()) {
    for (size_t at = 0; at <= pdf.pages.size();) {
      const size_t end = std::min(pdf.pages.find(',', at), pdf.pages.size());
      const std::string item = pdf.pages.substr(at, end - at);
      at = end + 1;
      const size_t dash = item.find('-');
      const int a = list_page(item, item.substr(0, dash), count);
      ranges.emplace_back(a, dash == std::string::npos ? a : list_page(item, item.substr(dash + 1), count));
    }
  } else {
    if (pdf.first > count)
      throw mpvg::Error("the first page (" + std::to_string(pdf.first) + ") is past the last page (" +
                        std::to_string(count) + ")");
    if (pdf.last >= 0 && pdf.last < pdf.first)
      throw mpvg::Error("the last page (" + std::to_string(pdf.last) + ") is before the first page (" +
                        std::to_string(pdf.first) + ")");
    // -l past the last page: the pages there are, as pdftoppm.
    ranges.emplace_back(pdf.first, pdf.last < 0 ? count : std::min(pdf.last, count));
  }
  Selection sel;
  std::vector<std::pair<int, int>> taken;  // each run's lowest and highest page
  for (const auto& [a, b] : ranges) {
    const int dir = a <= b ? 1 : -1;
    int start = a;
    if ((pdf.odd && start % 2 == 0) || (pdf.even && start % 2 == 1)) start += dir;
    if ((b - start) * dir < 0) continue;  // no page of that parity
    const int step = (pdf.odd || pdf.even ? 2 : 1) * dir;
    const int n = (b - start) / step + 1;
    const int end = start + (n - 1) * step;
    const int lo = std::min(start, end), hi = std::max(start, end);
    for (const auto& [l, h] : taken)
      if (lo <= h && l <= hi)
        throw mpvg::cli::UsageError{"--pages names a page twice ('" + pdf.pages + "'): each page is written once"};
    taken.emplace_back(lo, hi);
    sel.runs.push_back({start, step, n});
    sel.total += n;
    sel.last = end;
  }
  if (sel.total == 0)
    throw mpvg::Error(std::string("no ") + (pdf.odd ? "odd" : "even") + " page among the pages selected");
  if (pdf.singlefile) {
    sel.runs.resize(1);
    sel.runs[0].count = 1;
    sel.total = 1;
    sel.last = sel.runs[0].start;
  }
  return sel;
}

// The press profile --cmyk-profile names (loaded once, in main).
std::shared_ptr<const mpvg::pdf::OutputProfile> cmyk_profile;

// Page n (1-based) of `doc` interpreted, lowered and encoded: a pipeline job.
std::unique_ptr<mpvg::pipeline::Job> lower(const PdfOptions& pdf, const mpvg::cli::Options& opt,
                                           const mpvg::pdf::Document& doc, int n, const std::string& out) {
  mpvg::PdfPageRequest r;
  r.dpi = pdf.dpi;
  r.dpi_y = pdf.dpi_y;
  r.scale_to = pdf.scale_to;
  r.scale_to_x = pdf.scale_to_x;
  r.scale_to_y = pdf.scale_to_y;
  r.crop_x = pdf.crop_x;
  r.crop_y = pdf.crop_y;
  r.crop_w = pdf.crop_w;
  r.crop_h = pdf.crop_h;
  r.page = mpvg::pdf::PageOptions(pdf.box);
  r.page.annotations = pdf.annotations;
  r.page.thin_lines = pdf.thin_lines;
  r.page.inks = pdf.inks;
  r.page.cmyk_profile = cmyk_profile;
  return mpvg::pdf_page_job(r, opt, doc, n, out);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mpvg;
  cli::Options opt;
  PdfOptions pdf;
  try {
    std::vector<char*> rest = own_options(argc, argv, pdf);
    if (rest.empty()) return 0;  // --help
    // PDF composites device colour values (PDF 32000-1 §11.3.3), and
    // antialiasing is its shape: integrated in sRGB values by default, as
    // MuPDF, Poppler and Acrobat draw (in linear light a 0.4 pt rule at
    // 150 dpi loses 40 % of its darkness).
    opt.gamma = Gamma::Srgb;
    opt.output_optional = true;  // no OUTPUT-PREFIX: standard output, as pdftoppm
    if (!cli::parse(static_cast<int>(rest.size()), rest.data(), "pdf2png", "pdf", opt)) return 0;
    // One document a run (cli::parse makes several inputs, or -o with a
    // folder, a batch): the others would be dropped without a word.
    if (opt.batch || opt.positional.size() != 1)
      throw cli::UsageError{"pdf2png renders one document a run (usage: pdf2png [OPTIONS] INPUT.pdf OUTPUT-PREFIX)"};
    // A PNG's bytes on a terminal are garbage and can upset it.
    if (opt.output == "-" && isatty(STDOUT_FILENO))
      throw cli::UsageError{"standard output is a terminal: redirect it, or give an OUTPUT-PREFIX"};
    if (opt.output == "-" && pdf.inks == pdf::InkModel::Separations)
      throw cli::UsageError{"--separations writes several files a page: give an OUTPUT-PREFIX"};
    if (pdf.gray && pdf.mono) throw cli::UsageError{"-gray and -mono cannot be given together"};
    if (pdf.mono && opt.bits == 16) throw cli::UsageError{"-mono writes 1-bit images: --bits 16 cannot be given with it"};
    if (pdf.format == image::Format::Jpeg && opt.bits == 16)
      throw cli::UsageError{"JPEG holds 8 bits: --bits 16 cannot be given with " + std::string(pdf.format_flag)};
    if (pdf.format == image::Format::Jpeg && pdf.mono)
      throw cli::UsageError{"JPEG has no 1-bit images: -mono cannot be given with " + std::string(pdf.format_flag)};
    // Print preview: ink amounts in a TIFF, integrated as they are, over
    // paper (no ink).
    if (pdf.inks != pdf::InkModel::Rgb) {
      const std::string flag = pdf.inks == pdf::InkModel::Cmyk ? "--colorspace cmyk" : "--separations";
      if (pdf.format == image::Format::Jpeg || (pdf.format_flag && pdf.format == image::Format::Png))
        throw cli::UsageError{flag + " writes TIFFs: " + pdf.format_flag + " cannot be given with it"};
      if (pdf.gray || pdf.mono) throw cli::UsageError{flag + " cannot be given with -gray or -mono"};
      if (opt.bits == 16) throw cli::UsageError{flag + " writes 8-bit inks: --bits 16 cannot be given with it"};
      if (opt.gamma == Gamma::Linear)
        throw cli::UsageError{flag + " integrates ink amounts as they are: --gamma linear cannot be given with it"};
      if (pdf.transparent) throw cli::UsageError{flag + " draws on paper: --transparent cannot be given with it"};
      pdf.format = image::Format::Tiff;
      if (!pdf.format_flag) pdf.format_flag = pdf.inks == pdf::InkModel::Cmyk ? "--colorspace cmyk" : "--separations";
      opt.background = RGBA{0, 0, 0, 1};
    } else if (!pdf.cmyk_profile.empty()) {
      throw cli::UsageError{"--cmyk-profile is for --colorspace cmyk or --separations"};
    }
    if (!pdf.cmyk_profile.empty()) {
      try {
        cmyk_profile = pdf::OutputProfile::from_file(pdf.cmyk_profile);
      } catch (const Error& e) {
        throw cli::UsageError{std::string("--cmyk-profile: ") + e.what()};
      }
    }
    // A TIFF's deflate level: --compression N (1-9), as a PNG's.
    if (pdf.format == image::Format::Tiff && opt.compression >= 1)
      pdf.encode.deflate_level = std::min(9, opt.compression);
    // -tiff and -jpeg without OpenImageIO's module: refused before any
    // page is rendered.
    std::string no;
    if (pdf.format != image::Format::Png && !image::encoder_available(&no))
      throw cli::UsageError{std::string(pdf.format_flag) + " needs OpenImageIO (" + no + ")"};
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "pdf2png: %s\n", e.message.c_str());
    return kExitOther;  // pdftoppm's 99
  }
  // A JPEG has no alpha: its pages are drawn over white, --transparent or not.
  if ((!pdf.transparent || pdf.format == image::Format::Jpeg) && opt.background.a == 0)
    opt.background = RGBA{1, 1, 1, 1};
  // CUDA starts on a thread of its own at once (~250 ms on the GPU host),
  // while the document opens and the workers lower the first pages.
  GpuStartup startup(opt.backend, cli::render_options(opt, 64, 64, Affine{}));
  // The document first: failing to open it is pdftoppm's exit 1.
  std::unique_ptr<pdf::Document> opened;
  try {
    opened = std::make_unique<pdf::Document>(opt.positional[0], pdf.password, opt.max_input);
  } catch (const PasswordError& e) {
    // (The library's message names no option: ours does.)
    std::fprintf(stderr, "pdf2png: %s%s\n", e.what(), pdf.password.empty() ? " (give it with --password)" : "");
    std::fflush(nullptr);
    std::_Exit(kExitOpen);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pdf2png: %s\n", error_message(e).c_str());
    std::fflush(nullptr);
    std::_Exit(kExitOpen);
  }
  std::FILE* report = nullptr;
  try {
    const pdf::Document& doc = *opened;
    const int count = doc.page_count();
    // Print preview without a press profile: said once for the document.
    if (pdf.inks != pdf::InkModel::Rgb && !cmyk_profile && !opt.quiet && count > 0 && !doc.has_output_intent())
      std::fprintf(stderr,
                   "pdf2png: warning: no CMYK output profile (the document has no output intent; --cmyk-profile "
                   "names one): RGB colours converted by PDF's device formulas, RGB black as black ink alone\n");
    const int digits = static_cast<int>(std::to_string(count).size());
    // No page to render is an error, as for pdftoppm (its exit 99): a
    // document without pages, a range past the last page, no page of the
    // parity asked for.
    if (count == 0) throw Error("'" + opt.positional[0] + "' has no pages");
    const Selection selection = select_pages(pdf, count);
    // Standard output takes one image.
    if (opt.output == "-" && (selection.total > 1 || pdf.repeat > 1))
      throw cli::UsageError{std::to_string(selection.total * pdf.repeat) +
                            " pages cannot all go to standard output: give an OUTPUT-PREFIX, or select one page "
                            "(-singlefile, -f N -l N)"};
    const long long range = selection.total;
    const long long requested = range * pdf.repeat;
    if (requested > 1000000000) throw Error("--repeat makes more than 10^9 pages");
    const int pages = static_cast<int>(requested);
    auto page_of = [&](int t) { return selection.page(t % range); };
    // OUT-PREFIX-07.png; -singlefile: OUT-PREFIX.png; standard output: "-".
    auto output_of = [&](int t) {
      if (opt.output == "-") return std::string("-");
      const char* ext = image::extension(pdf.format);  // png, jpg, tif
      if (pdf.singlefile && !pdf.forcenum) return opt.output + "." + ext;
      char name[48];
      std::snprintf(name, sizeof name, "%c%0*d.%s", pdf.sep, digits, page_of(t), ext);
      return opt.output + name;
    };
    // The thread counts are set before CUDA's start-up has finished: with a
    // GPU visible (its device files exist) they are CUDA's. If CUDA then
    // fails, one render thread renders on the CPU and the others stop.
    std::error_code ec;
    const bool cuda = startup.started() && std::filesystem::exists("/dev/nvidiactl", ec);
    std::once_flag started;
    std::unique_ptr<FrameRenderer> warm;  // the start-up's renderer, for render thread 0
    bool cuda_ok = false;
    std::string why;
    auto await_cuda = [&] {
      std::call_once(started, [&] {
        warm = startup.take(&why);
        cuda_ok = warm != nullptr;
        if (!cuda_ok && opt.stats && opt.backend == Backend::Auto)
          std::fprintf(stderr, "pdf2png: %s; rendering on the CPU\n", why.c_str());
      });
    };
    const int cores = hardware_threads();
    pipeline::Config c;
    c.program = "pdf2png";
    c.unit = "page";
    c.prepare_names[0] = "interpretation";
    c.prepare_names[1] = "lowering";
    c.tickets = pages;
    // With CUDA, a few render threads (own gpu::Context and stream each)
    // overlap one page's host work and copies with another's kernels; the
    // CPU backend uses every core for one page already.
    // With the PNG stage on the device (--compression 1) the workers idle
    // and more render threads pay: 5 made pgfmanual 222 pages/s against
    // 193-200 with 3 (H100, 16 cores; BENCHMARKS.md "Forest frames").
    // Every device asked for (--devices), or every one visible, with as
    // many render threads each.
    const std::vector<int> devices = pdf_devices(opt, cuda);
    const int per_device = pdf.render_threads > 0 ? pdf.render_threads : opt.compression == 1 ? 5 : 3;
    c.render_threads =
        std::min(pages, cuda ? per_device * static_cast<int>(devices.size()) : std::max(1, pdf.render_threads));
    // The render threads wait on the device dozens of times a page: with
    // CUDA they keep cores of their own (workers on every core starved them:
    // asymptote 109 pages/s with 16 workers, 120 with 14; BENCHMARKS.md).
    c.workers = std::min(pages, pdf.threads > 0 ? pdf.threads : cuda ? std::max(1, cores - c.render_threads) : cores);
    // A progress line on a terminal for multi-page jobs.
    c.progress = !opt.quiet && !pdf.progress && pages > 1 && isatty(fileno(stderr));
    // -progress: pdftoppm's line per page written.
    if (pdf.progress)
      c.written = [&](const pipeline::Job& job) {
        std::fprintf(stderr, "%d %d %s\n", page_of(job.index), selection.last, job.out.c_str());
      };
    if (!pdf.report.empty()) {
      report = std::fopen(pdf.report.c_str(), "w");
      if (!report) throw WriteError("cannot write the report '" + pdf.report + "': " + std::strerror(errno));
      c.report = report;
      c.report_input = [&](int t) { return opt.positional[0] + ":" + std::to_string(page_of(t)); };
      c.report_output = output_of;
    }
    c.stats = opt.stats;
    c.quiet = opt.quiet;
    c.bits = opt.bits;
    c.compression = opt.compression;
    c.color = pdf.mono ? png::Color::Mono : pdf.gray ? png::Color::Gray : png::Color::Rgb;
    c.format = pdf.format;
    c.encode = pdf.encode;
    // Small pages waiting together share a frame (frame/forest.h): one tree
    // build for several pages (--compression 1: pgfmanual 196-199 pages/s
    // against 172-178 with 3 render threads).
    c.forest_scenes = pipeline::forest_scenes_for(opt.frame_scenes, cuda, opt.compression);
    c.gamma = opt.gamma;
    // Worker 0 uses the document opened here; the others a clone each
    // (made on first use), with MuPDF contexts of their own unless
    // MPVG_PDF_SHARED_CONTEXT=1 (fz_clone_context; for measurements).
    const char* shared = std::getenv("MPVG_PDF_SHARED_CONTEXT");
    const bool shared_context = shared && std::string(shared) == "1";
    std::vector<std::unique_ptr<pdf::Document>> clones(c.workers);
    c.label = [&](int t) { return "page " + std::to_string(page_of(t)); };
    c.prepare = [&](int t, int w) {
      const pdf::Document* d = &doc;
      if (w > 0) {
        if (!clones[w])
          clones[w] = doc.clone(shared_context ? pdf::Document::Context::Shared : pdf::Document::Context::Independent);
        d = clones[w].get();
      }
      return lower(pdf, opt, *d, page_of(t), output_of(t));
    };
    c.make_renderer = [&](int r) -> std::unique_ptr<FrameRenderer> {
      if (opt.backend == Backend::Cpu) return std::make_unique<FrameRenderer>(Backend::Cpu);
      await_cuda();
      if (cuda_ok) {
        // The start-up's renderer (device 0) for the first thread on it.
        const int device = devices[static_cast<size_t>(r) % devices.size()];
        if (warm && device == warm->device()) return std::move(warm);
        return std::make_unique<FrameRenderer>(Backend::Cuda, device);
      }
      if (opt.backend == Backend::Cuda) {
        if (r == 0) throw Error("CUDA backend unavailable: " + why);
        return nullptr;
      }
      return r == 0 ? std::make_unique<FrameRenderer>(Backend::Cpu) : nullptr;
    };
    // MPVG_PDF_SYNC_START=1: wait for CUDA before the pipeline starts (the
    // earlier behaviour; for measurements).
    if (const char* sync = std::getenv("MPVG_PDF_SYNC_START"); sync && std::string(sync) == "1" &&
                                                              opt.backend != Backend::Cpu)
      await_cuda();
    c.timeout_s = opt.timeout_s;
    const pipeline::Result result = pipeline::run(c);
    if (opt.stats) std::fprintf(stderr, "%s", pipeline::summary(c, result, cuda_ok ? "cuda" : "cpu").c_str());
    // Every page is written: the process ends without tearing down CUDA
    // (100-150 ms on the GPU host; the driver frees it at exit) or MuPDF.
    std::fflush(nullptr);
    std::_Exit(result.write_failed ? kExitOutput : result.failed ? kExitOther : 0);
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "pdf2png: %s\n", e.message.c_str());
    std::fflush(nullptr);
    std::_Exit(kExitOther);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pdf2png: %s\n", error_message(e).c_str());
    // Not exit(): the start-up thread may still be running (GpuStartup).
    std::fflush(nullptr);
    std::_Exit(dynamic_cast<const WriteError*>(&e) ? kExitOutput : kExitOther);
  }
}
