#include "lib/pipeline/cli.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <mutex>

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/memory_budget.h"
#include "parsers/svg/svg_values.h"

namespace mpvg::cli {

namespace {

void usage(const char* program, const char* kind) {
  std::printf(
      "Usage: %s [OPTIONS] INPUT.%s OUTPUT.png\n"
      "Renders INPUT to a PNG with the mpvg rasterizer. '-' reads standard input or\n"
      "writes standard output.\n\n"
      "Size:\n"
      "  -w, --width N             output width in pixels (height keeps the aspect ratio)\n"
      "  -h, --height N            output height in pixels (width keeps the aspect ratio)\n"
      "  -z, --zoom F              scale the document's own size by F (default 1)\n"
      "  -a, --keep-aspect-ratio   with both -w and -h: fit inside, keep the aspect ratio\n"
      "  -d, --dpi N               pixels per inch of the document's in, cm, mm, pt and\n"
      "                            pc (default 96), written into the PNG (pHYs)\n"
      "  -i, --export-id ID        draw only the element with that id, the output its\n"
      "                            box (strokes, markers and filter regions included)\n"
      "      --query               print the drawn elements' ids and boxes as JSON on\n"
      "                            standard output (the root viewport's units); no PNG\n"
      "Output:\n"
      "  -o, --output FILE         output file (instead of the second argument)\n"
      "  -b, --background COLOR    background colour, e.g. white or #ffffff (default\n"
      "                            transparent)\n"
      "      --bits 8|16           bits per channel of the PNG (default 8)\n"
      "      --compression 0..9    PNG deflate level: 0 none, 1 mpvg's parallel deflate\n"
      "                            (on the GPU where it renders: the CPU's work for PNGs\n"
      "                            drops ~20x), 2-9 libdeflate's on the CPU (default 2)\n"
      "Antialiasing (the paper's modes):\n"
      "      --aa MODE             4x4x32: cardinal cubic B-spline over 4x4 unit areas,\n"
      "                            32 blue-noise samples each (512 per pixel; default)\n"
      "                            1x32, 1x8: box filter, 32 or 8 stratified samples\n"
      "      --filter F            box, hat, bspline, cardinal, mitchell, catmull-rom\n"
      "      --samples N           samples per unit area (blue noise: 8, 32 or 64)\n"
      "      --pattern P           blue or stratified\n"
      "      --seed N              sample pattern seed (default 0)\n"
      "      --gamma G             linear (integrate in linear light; default) or srgb\n"
      "                            (integrate sRGB values, as most renderers do)\n"
      "Input:\n"
      "      --allow-read DIR      let the document read files (images) in DIR's tree;\n"
      "                            repeatable. Only the document's own folder tree\n"
      "                            (the current directory's for '-') is readable\n"
      "                            otherwise; network URLs are never loaded\n"
      "Batches (several inputs in one process, overlapped):\n"
      "  -o OUTDIR IN1 IN2 ...     write OUTDIR/IN1.png, ... (OUTDIR is made if missing;\n"
      "                            one input too: -o names a folder unless it has an\n"
      "                            extension, as out.png)\n"
      "      --batch LIST          lines 'IN OUT' (tab or space separated); '-' reads\n"
      "                            the list from standard input\n"
      "      --shard I/N           only inputs I, I+N, I+2N, ... (0 <= I < N), e.g. one\n"
      "                            Slurm array task each\n"
      "      --devices LIST        CUDA devices to use, e.g. 0,1 (default: all)\n"
      "      --threads N           worker threads: parsing, PNG (default: one per core)\n"
      "      --render-threads N    render threads per device (default 2 with CUDA)\n"
      "      --frame-scenes N      small files rendered together as one frame, at most N\n"
      "                            (default 8 with CUDA and --compression 1, else 1)\n"
      "      --timeout S           give up on a file after S seconds (it fails; the\n"
      "                            others go on; a single file too)\n"
      "      --report FILE         one JSON line a file: input, output, status, ms,\n"
      "                            warnings, error\n"
      "Text:\n"
      "      --font-dir DIR        fonts for <text>: every font file in DIR's tree\n"
      "                            (repeatable), before the system's fonts\n"
      "      --languages LIST      the user's languages for systemLanguage and switch,\n"
      "                            e.g. de-CH,en (default en)\n"
      "Limits:\n"
      "      --max-memory SIZE     memory budget of one render, e.g. 2G (default: half\n"
      "                            of the machine's): large images are decoded\n"
      "                            smaller or refused, the tree stays coarser, an\n"
      "                            output that cannot fit is an error\n"
      "      --max-input SIZE      refuse inputs larger than SIZE (default 1G)\n"
      "Execution:\n"
      "      --backend B           auto, cpu or cuda (default auto: the CPU when it would\n"
      "                            finish before CUDA is ready, else cuda; see --stats)\n"
      "      --server              hand the job to a persistent renderer of this user\n"
      "                            (started on first use, keeps CUDA warm; also\n"
      "                            MPVG_SERVER=1); renders here if anything is wrong\n"
      "      --stats               print per-stage timings to standard error\n"
      "  -q, --quiet               no warnings\n"
      "      --help, --version\n",
      program, kind);
}

double number(const std::string& opt, const std::string& v) {
  double d = 0;
  const auto r = std::from_chars(v.data(), v.data() + v.size(), d);
  if (r.ec != std::errc() || r.ptr != v.data() + v.size() || !std::isfinite(d))
    throw UsageError{"option " + opt + " expects a number, got '" + v + "'"};
  return d;
}

long integer(const std::string& opt, const std::string& v, long lo, long hi) {
  long n = 0;
  const auto r = std::from_chars(v.data(), v.data() + v.size(), n);
  if (r.ec != std::errc() || r.ptr != v.data() + v.size() || n < lo || n > hi)
    throw UsageError{"option " + opt + " expects an integer from " + std::to_string(lo) + " to " +
                     std::to_string(hi) + ", got '" + v + "'"};
  return n;
}

}  // namespace

bool parse(int argc, char** argv, const char* program, const char* kind, Options& o) {
  for (int i = 1; i < argc; i++) {
    std::string a = argv[i];
    std::string val;
    bool has_inline = false;
    if (a.rfind("--", 0) == 0) {
      const size_t eq = a.find('=');
      if (eq != std::string::npos) {
        val = a.substr(eq + 1);
        a = a.substr(0, eq);
        has_inline = true;
      }
    }
    auto value = [&]() -> std::string {
      if (has_inline) return val;
      if (i + 1 >= argc) throw UsageError{"option " + a + " needs a value"};
      return argv[++i];
    };
    if (a == "--help" || a == "-?") {
      usage(program, kind);
      return false;
    } else if (a == "--version") {
      std::printf("%s (mpvg) 0.1\n", program);
      return false;
    } else if (a == "-w" || a == "--width") {
      o.width = number(a, value());
      if (!(*o.width > 0)) throw UsageError{"the width must be positive"};
    } else if (a == "-h" || a == "--height") {
      o.height = number(a, value());
      if (!(*o.height > 0)) throw UsageError{"the height must be positive"};
    } else if (a == "-z" || a == "--zoom") {
      o.zoom = number(a, value());
      if (!(o.zoom > 0)) throw UsageError{"the zoom must be positive"};
    } else if (a == "-d" || a == "--dpi") {
      o.dpi = number(a, value());
      // resvg's range: a resolution outside it is a typo.
      if (!(o.dpi >= 10 && o.dpi <= 4000)) throw UsageError{"--dpi takes 10 to 4000 pixels per inch"};
    } else if (a == "-i" || a == "--export-id") {
      o.export_id = value();
      if (o.export_id.empty()) throw UsageError{"--export-id needs an element's id"};
    } else if (a == "--query") {
      o.query = true;
    } else if (a == "--report") {
      o.report = value();
      if (o.report.empty()) throw UsageError{"--report needs a file name"};
    } else if (a == "-a" || a == "--keep-aspect-ratio") {
      o.keep_aspect = true;
    } else if (a == "-b" || a == "--background") {
      const std::string c = value();
      const auto col = svg::detail::parse_color(c);
      if (!col) throw UsageError{"cannot parse the background colour '" + c + "'"};
      o.background = *col;
    } else if (a == "-o" || a == "--output") {
      o.output = value();
    } else if (a == "--bits") {
      const long b = integer(a, value(), 8, 16);
      if (b != 8 && b != 16) throw UsageError{"--bits takes 8 or 16"};
      o.bits = static_cast<int>(b);
    } else if (a == "--compression") {
      o.compression = static_cast<int>(integer(a, value(), 0, 9));
    } else if (a == "--aa") {
      const std::string m = value();
      if (m != "1x8" && m != "1x32" && m != "4x4x32")
        throw UsageError{"unknown antialiasing mode '" + m + "' (known: 1x8, 1x32, 4x4x32)"};
      o.preset = m;
    } else if (a == "--filter") {
      const std::string f = value();
      Filter filter;
      if (!parse_filter(f, &filter))
        throw UsageError{"unknown filter '" + f + "' (box, hat, bspline, cardinal, mitchell, catmull-rom)"};
      o.filter = filter;
    } else if (a == "--samples") {
      o.samples = static_cast<int>(integer(a, value(), 1, 1024));
    } else if (a == "--pattern") {
      const std::string pt = value();
      if (pt == "blue") o.pattern = PatternKind::BlueNoise;
      else if (pt == "stratified") o.pattern = PatternKind::Stratified;
      else throw UsageError{"unknown sample pattern '" + pt + "' (blue or stratified)"};
    } else if (a == "--seed") {
      o.seed = static_cast<uint32_t>(integer(a, value(), 0, 4294967295L));
    } else if (a == "--gamma") {
      const std::string g = value();
      if (g == "linear") o.gamma = Gamma::Linear;
      else if (g == "srgb") o.gamma = Gamma::Srgb;
      else throw UsageError{"unknown --gamma '" + g + "' (linear or srgb)"};
    } else if (a == "--backend") {
      const std::string b = value();
      if (b == "auto") o.backend = Backend::Auto;
      else if (b == "cpu") o.backend = Backend::Cpu;
      else if (b == "cuda") o.backend = Backend::Cuda;
      else throw UsageError{"unknown backend '" + b + "' (auto, cpu or cuda)"};
    } else if (a == "--font-dir") {
      const std::string d = value();
      if (d.empty()) throw UsageError{"--font-dir needs a folder"};
      o.font_dirs.push_back(d);
    } else if (a == "--languages") {
      const std::string list = value();
      o.languages.clear();
      for (size_t pos = 0; pos <= list.size();) {
        size_t end = list.find(',', pos);
        if (end == std::string::npos) end = list.size();
        std::string tag = list.substr(pos, end - pos);
        tag.erase(0, tag.find_first_not_of(' '));
        tag.erase(tag.find_last_not_of(' ') + 1);
        if (!tag.empty()) o.languages.push_back(tag);
        pos = end + 1;
      }
      if (o.languages.empty()) throw UsageError{"--languages needs a list of language tags, e.g. en-US,de"};
    } else if (a == "--allow-read") {
      const std::string d = value();
      if (d.empty()) throw UsageError{"--allow-read needs a folder"};
      o.allow_read.push_back(d);
    } else if (a == "--batch") {
      o.batch_list = value();
      if (o.batch_list.empty()) throw UsageError{"--batch needs a list file (or '-')"};
    } else if (a == "--shard") {
      const std::string v = value();
      const size_t slash = v.find('/');
      if (slash == std::string::npos) throw UsageError{"--shard takes I/N, e.g. 0/4"};
      o.shard_count = static_cast<int>(integer(a, v.substr(slash + 1), 1, 1000000));
      o.shard_index = static_cast<int>(integer(a, v.substr(0, slash), 0, o.shard_count - 1));
    } else if (a == "--devices") {
      const std::string v = value();
      o.devices.clear();
      if (v != "all") {
        for (size_t pos = 0; pos <= v.size();) {
          const size_t end = std::min(v.find(',', pos), v.size());
          o.devices.push_back(static_cast<int>(integer(a, v.substr(pos, end - pos), 0, 1023)));
          pos = end + 1;
        }
      }
    } else if (a == "--threads") {
      o.threads = static_cast<int>(integer(a, value(), 1, 4096));
    } else if (a == "--render-threads") {
      o.render_threads = static_cast<int>(integer(a, value(), 1, 64));
    } else if (a == "--frame-scenes") {
      o.frame_scenes = static_cast<int>(integer(a, value(), 1, 4096));
    } else if (a == "--timeout") {
      o.timeout_s = number(a, value());
      if (!(o.timeout_s > 0)) throw UsageError{"--timeout takes a positive number of seconds"};
    } else if (a == "--max-memory") {
      o.max_memory = parse_size(a, value());
    } else if (a == "--max-input") {
      o.max_input = parse_size(a, value());
    } else if (a == "--server") {
      o.server = true;
    } else if (a == "--stats") {
      o.stats = true;
    } else if (a == "-q" || a == "--quiet") {
      o.quiet = true;
    } else if (a.size() > 1 && a[0] == '-') {
      throw UsageError{"unknown option '" + a + "' (see --help)"};
    } else {
      o.positional.push_back(a);
    }
  }
  if (!o.batch_list.empty()) {
    if (!o.positional.empty()) throw UsageError{"--batch takes its inputs from the list, not the command line"};
    o.batch = true;
  } else if (!o.output.empty() && !o.positional.empty()) {
    // svg2png -o names a folder (made if missing) with several inputs, or
    // when it is one, ends in '/' or has no extension ("-o out"); a file
    // only as "-o out.png" (or "-").
    std::error_code ec;
    const std::filesystem::path out(o.output);
    o.batch = o.positional.size() > 1 || o.output.back() == '/' || std::filesystem::is_directory(out, ec) ||
              (!o.output_optional && o.output != "-" && !out.has_extension());
  } else if (o.output.empty() && o.positional.size() == 2) {
    // (A folder as the second argument is refused when it is written,
    // "Is a directory": -o FOLDER writes into it.)
    o.output = o.positional[1];
    o.positional.pop_back();
  } else if (o.output.empty() && o.positional.size() > 2) {
    throw UsageError{"several inputs need -o OUTDIR"};
  }
  if (!o.batch && o.output.empty() && o.positional.size() == 1 && o.output_optional) o.output = "-";
  if (o.pattern == PatternKind::BlueNoise && o.samples && *o.samples != 8 && *o.samples != 32 && *o.samples != 64)
    throw UsageError{"blue-noise patterns have 8, 32 or 64 samples; use --pattern stratified for " +
                     std::to_string(*o.samples)};
  if (o.query) {
    if (o.batch || o.positional.size() != 1 || !o.output.empty())
      throw UsageError{std::string("--query takes one input and no output (usage: ") + program + " --query INPUT." +
                       kind + ")"};
    if (!o.export_id.empty()) throw UsageError{"--query lists every element: leave out --export-id"};
    return true;
  }
  if (!o.report.empty() && !o.batch) throw UsageError{"--report is for batches (-o OUTDIR or --batch LIST)"};
  if (!o.batch && (o.positional.size() != 1 || o.output.empty()))
    throw UsageError{std::string("expected an input and an output file (usage: ") + program + " [OPTIONS] INPUT." +
                     kind + " OUTPUT.png)"};
  return true;
}

void output_geometry(const Options& o, double dw, double dh, int* width, int* height, Affine* view) {
  if (!(dw > 0 && dh > 0)) throw Error("the document has no size to render");
  // A single requested dimension (or the zoom) keeps the aspect ratio; the
  // other dimension is rounded, and the document then fills the whole
  // image (a stretch of under half a pixel), as resvg does. Both -w and -h
  // stretch to exactly that size, unless --keep-aspect-ratio fits inside.
  double w = dw * o.zoom, h = dh * o.zoom;
  if (o.width && o.height) {
    w = *o.width;
    h = *o.height;
    if (o.keep_aspect) {
      const double s = std::min(w / dw, h / dh);
      w = dw * s;
      h = dh * s;
    }
  } else if (o.width) {
    w = *o.width;
    h = dh * (w / dw);
  } else if (o.height) {
    h = *o.height;
    w = dw * (h / dh);
  }
  if (!(w < 32768.5 && h < 32768.5)) throw Error("the output would be larger than 32768 pixels");
  *width = static_cast<int>(std::max(1L, std::lround(w)));
  *height = static_cast<int>(std::max(1L, std::lround(h)));
  *view = Affine::scale(*width / dw, *height / dh);
  check_frame(o, *width, *height);
}

uint64_t memory_budget(const Options& o) {
  if (o.max_memory) return o.max_memory;
  static const uint64_t machine = [] {
    uint64_t bytes = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
    // A control group's limit (cgroup v2), where one is set.
    if (FILE* f = std::fopen("/sys/fs/cgroup/memory.max", "r")) {
      unsigned long long limit = 0;
      if (std::fscanf(f, "%llu", &limit) == 1 && limit > 0) bytes = std::min<uint64_t>(bytes, limit);
      std::fclose(f);
    }
    return bytes;
  }();
  return std::max<uint64_t>(machine / 2, uint64_t(256) << 20);
}

void check_frame(const Options& o, int width, int height) {
  const uint64_t budget = memory_budget(o);
  const uint64_t need = frame_bytes(width, height, o.bits);
  if (need > memory_shares(budget).frame)
    throw MemoryLimitError("the output of " + std::to_string(width) + "x" + std::to_string(height) + " pixels needs " +
                byte_size(need) + ", the budget is " + byte_size(memory_shares(budget).frame) +
                " (--max-memory " + byte_size(budget) + " of which half is for the output)");
}

uint64_t parse_size(const std::string& option, const std::string& v) {
  double n = 0;
  const auto r = std::from_chars(v.data(), v.data() + v.size(), n);
  std::string unit = r.ec == std::errc() ? std::string(r.ptr, v.data() + v.size()) : std::string();
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'b') unit.pop_back();   // "GB", "GiB" as "G", "Gi"
  if (unit.size() > 1 && unit.back() == 'i') unit.pop_back();
  const std::string units = "kmgt";
  const size_t at = unit.empty() ? std::string::npos : units.find(unit);
  if (r.ec != std::errc() || !(n > 0) || !std::isfinite(n) || (!unit.empty() && (unit.size() != 1 || at == std::string::npos)))
    throw UsageError{"option " + option + " expects a size such as 512M or 4G, got '" + v + "'"};
  const double bytes = n * std::pow(1024.0, unit.empty() ? 0 : double(at + 1));
  if (bytes >= 1.8e19) throw UsageError{"option " + option + " is too large: '" + v + "'"};
  return static_cast<uint64_t>(bytes);
}

// glibc raises its mmap threshold (up to 32 MiB) each time a large mmapped
// block is freed; blocks below it then come from per-thread arenas, which
// keep what is freed in them. The CPU stages' scratch, made on every core,
// then stays resident: 10^5 lines peaked at 1.28 GB on 16 cores, 0.94 GB
// on 2. A fixed 1 MiB threshold returns every large block when it is freed
// (0.92 GB on 16 cores, the same time).
void bound_allocator() {
#if defined(__GLIBC__)
  static std::once_flag once;
  std::call_once(once, [] {
    mallopt(M_MMAP_THRESHOLD, 1 << 20);
    // ... while the heaps keep 16 MiB above their top when they shrink
    // (M_TOP_PAD): with the fixed threshold the trim threshold stays at
    // its 128 KiB, so each tree level's small buffers gave their pages back
    // and faulted them in again (on the 2-core machine, --aa 1x32 on the
    // CPU: hawaii 0.87 -> 0.76 s wall, system time 0.27 -> 0.12 s, peak
    // RSS +6-10 MB; pdf2png 20 pages of asymptote 4.1 -> 3.4 s, system
    // time 1.4 -> 0.75 s, peak RSS 178 -> 205 MB, a pad kept per arena. A
    // 4 MiB pad saved nothing. BENCHMARKS.md, issue 50).
    mallopt(M_TOP_PAD, 16 << 20);
  });
#endif
}

std::shared_ptr<MemoryBudget> make_budget(const Options& o) {
  bound_allocator();
  auto b = std::make_shared<MemoryBudget>(memory_budget(o));
  // What the program itself holds whatever it renders (code, libraries,
  // fonts, the document's text and tree): counted so that the process's
  // peak stays near the budget, not a budget and more.
  b->try_charge(std::min<uint64_t>(kProgramBytes, b->limit() / 8));
  return b;
}

RenderOptions render_options(const Options& o, int width, int height, const Affine& view,
                             std::shared_ptr<MemoryBudget> budget) {
  RenderOptions r;
  r.budget = budget ? std::move(budget) : make_budget(o);
  r.width = width;
  r.height = height;
  r.view = view;
  r.background = o.background;
  // The preset, then what was given explicitly.
  if (o.preset == "1x8") {
    r.filter = Filter::Box;
    r.samples = 8;
    r.pattern = PatternKind::Stratified;
  } else if (o.preset == "1x32") {
    r.filter = Filter::Box;
    r.samples = 32;
    r.pattern = PatternKind::Stratified;
  } else {
    r.filter = Filter::Cardinal;
    r.samples = 32;
    r.pattern = PatternKind::BlueNoise;
  }
  if (o.filter) r.filter = *o.filter;
  if (o.samples) r.samples = *o.samples;
  if (o.pattern) r.pattern = *o.pattern;
  // Blue noise exists for 8, 32 and 64 samples; other counts take the
  // stratified pattern unless blue noise was asked for by name.
  if (!o.pattern && r.pattern == PatternKind::BlueNoise && r.samples != 8 && r.samples != 32 && r.samples != 64)
    r.pattern = PatternKind::Stratified;
  r.seed = o.seed;
  r.gamma = o.gamma;
  r.backend = o.backend;
  // The tree's share of the budget: 8 bytes an entry.
  r.tree.max_entries = std::min<uint64_t>(r.tree.max_entries, memory_shares(memory_budget(o)).tree / sizeof(Entry));
  return r;
}

std::string format_stats(const RenderStats& s) {
  char buf[1024], png_line[64] = "";
  // where the frame compressed its PNG (FrameRenderer::render_png)
  if (s.png_ms > 0) std::snprintf(png_line, sizeof png_line, "png %.3f ms\n", s.png_ms);
  char samples_line[96] = "";  // adaptive sampling: evaluated, not weighed
  if (s.pixels > 0 && s.samples > 0)
    std::snprintf(samples_line, sizeof samples_line, "samples %.1f per pixel (evaluated)\n",
                  double(s.samples) / double(s.pixels));
  char filter_line[96] = "";  // filter layers, inside encode
  if (s.filter_layers > 0)
    std::snprintf(filter_line, sizeof filter_line, "filter layers %zu, %.3f ms (in encode)\n", s.filter_layers,
                  s.filter_ms);
  std::snprintf(buf, sizeof buf,
                "backend %s%s%s\n"
                "encode %.3f ms\n%sstroke %.3f ms\nabstract %.3f ms\nsubdivide %.3f ms\nprune %.3f ms\nschedule %.3f ms\n"
                "sample+integrate %.3f ms\n%s%stotal %.3f ms\n"
                "input segments %zu, abstract segments %zu, depth %d, leaves %zu, leaf entries %zu, "
                "tree %.2f MiB\n",
                s.backend.c_str(), s.note.empty() ? "" : ": ", s.note.c_str(), s.encode_ms, filter_line, s.stroke_ms,
                s.abstract_ms,
                s.subdivide_ms, s.prune_ms, s.schedule_ms, s.sample_ms, samples_line, png_line, s.total_ms, s.input_segments,
                s.abstract_segments, s.depth, s.leaves, s.leaf_entries, s.tree_bytes / 1048576.0);
  return buf;
}

}  // namespace mpvg::cli
