// Command-line options shared by the converters (svg2png now, pdf2png
// later), modelled on rsvg-convert.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "frame/frame.h"

namespace mpvg::cli {

struct Options {
  std::optional<double> width, height;  // requested output size in pixels
  double zoom = 1.0;
  bool keep_aspect = false;
  RGBA background{0, 0, 0, 0};
  // Antialiasing: a preset (1x8, 1x32, 4x4x32), then explicit --filter,
  // --samples and --pattern override its parts.
  std::string preset = "4x4x32";
  std::optional<Filter> filter;
  std::optional<int> samples;
  std::optional<PatternKind> pattern;
  uint32_t seed = 0;
  Gamma gamma = Gamma::Linear;
  Backend backend = Backend::Auto;
  int bits = 8;
  // --compression 0..9 (lib/output/png_writer.h); -1: png::kDefaultCpuLevel,
  // the same bytes on every backend (level 1 compresses on the device).
  int compression = -1;
  bool stats = false;
  bool quiet = false;
  // --allow-read: folders whose files the document may read (images)
  // besides its own folder tree.
  std::vector<std::string> allow_read;
  std::vector<std::string> font_dirs;  // --font-dir (repeatable)
  std::vector<std::string> languages{"en"};  // --languages (systemLanguage)
  std::vector<std::string> positional;
  std::string output;  // -o; else the second positional argument
  // pdf2png: the output may be left out (one input): standard output ("-").
  bool output_optional = false;

  // Batches (svg2png): -o OUTDIR with several inputs (or one, when OUTDIR
  // is a folder or ends in '/'), or --batch LIST (lines "IN OUT"; "-" reads
  // the list from standard input).
  bool batch = false;
  std::string batch_list;
  int shard_index = 0, shard_count = 1;  // --shard I/N: inputs I, I+N, I+2N, ... (0-based)
  std::vector<int> devices;              // --devices 0,2 (default: every visible one)
  int threads = 0;                       // --threads: worker threads (0: per core)
  int render_threads = 0;                // --render-threads per device (0: default)
  // --frame-scenes: most small items a render thread renders as one frame
  // (a forest, frame/forest.h); 0: the default, 8 with CUDA and the PNG
  // stage on the device (--compression 1), else 1.
  int frame_scenes = 0;
  bool server = false;                   // --server: the persistent renderer (lib/server/server.h)
  double timeout_s = 0;                  // --timeout S: per item of a batch (0: none)
  // --max-memory: the budget of one render (core/memory_budget.h); 0: half
  // of the machine's memory (or of the control group's limit).
  uint64_t max_memory = 0;
  uint64_t max_input = kDefaultMaxInput;  // --max-input: bytes of input read at most

  // svg2png: --dpi (rsvg-convert's -d, resvg's --dpi): pixels per inch of
  // the document's absolute units, and the PNG's pHYs; 0: 96, no pHYs.
  double dpi = 0;
  std::string export_id;  // --export-id / -i: that element alone, cropped to its box
  bool query = false;     // --query: the drawn elements' ids and boxes as JSON on stdout, no PNG
  std::string report;     // --report FILE: a batch's JSON lines, one a file
};

// Parses argv. Returns false after printing help or version (exit 0);
// throws UsageError on bad options.
struct UsageError {
  std::string message;
};
bool parse(int argc, char** argv, const char* program, const char* input_kind, Options& out);

// Output pixel size and scene-to-pixel transform for a document of the
// given intrinsic size. Throws mpvg::Error when no size can be derived.
void output_geometry(const Options& o, double doc_width, double doc_height, int* width, int* height, Affine* view);

// The options' render of width x height pixels. `budget`: the one the
// document's parse was charged to (its scene stays charged while it
// renders); null: a fresh one (make_budget).
RenderOptions render_options(const Options& o, int width, int height, const Affine& view,
                             std::shared_ptr<MemoryBudget> budget = nullptr);

// The memory budget of one render: --max-memory, or half of what the
// machine (or the control group it runs in) has.
uint64_t memory_budget(const Options& o);
// A budget of that size for one document or page, parse and render.
std::shared_ptr<MemoryBudget> make_budget(const Options& o);
// Makes the allocator hand large freed blocks back to the system (glibc: a
// fixed mmap threshold), so that the peak RSS follows what the budget
// counts, and keep a pad of small ones (M_TOP_PAD) for the next tree
// level; make_budget calls it, once per process.
void bound_allocator();

// Throws mpvg::Error when a frame of width x height pixels would not fit
// the budget ("the output of 32768x32768 pixels needs 32 GiB, the budget
// is 12 GiB (--max-memory)").
void check_frame(const Options& o, int width, int height);

// "512M", "4G", "1.5GiB", "1000000": bytes (binary units); throws
// UsageError naming `option` otherwise.
uint64_t parse_size(const std::string& option, const std::string& value);

// One line per stage, for --stats.
std::string format_stats(const RenderStats& st);

}  // namespace mpvg::cli
