// The batch pipeline of pdf2png (pages) and svg2png (files): items flow
// through one process so that no stage waits for another. Worker threads
// prepare items (a PDF page interpreted and lowered, an SVG file parsed and
// stroked) and encode their scenes; render threads (each with its own
// FrameRenderer: with CUDA its own context state and stream, on the device
// it was made for) render them, lowest index first, several small ones
// waiting together as one forest frame (frame/forest.h); the workers turn
// rendered images (with CUDA, their PNG rows filtered on the device) into
// PNG files before they take new items, so that at
// most `workers + 4 + render threads x forest_scenes` items are in flight.
// An item that fails is reported and every other one is still written.
#pragma once
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "lib/output/image_writer.h"
#include "lib/output/ink_output.h"
#include "lib/output/png_writer.h"
#include "core/output/png_encode.h"
#include "frame/frame.h"
#include "lib/backend/backend.h"

namespace mpvg::pipeline {

// One item on its way through.
struct Job {
  int index = 0;       // the ticket it came from: render order, messages
  std::string label;   // "page 3", "tiger.svg": how messages name it
  std::string out;     // the PNG's path ("-": standard output)
  // The resolution the file records (PNG's pHYs, TIFF's and JPEG's
  // density; 0: none); dpi_y where the vertical one differs (0: dpi).
  double dpi = 0, dpi_y = 0;
  // Print preview: the image holds ink passes side by side, written as
  // lib/output/ink_output.h writes them (8 bits).
  std::shared_ptr<const InkPage> inks;
  int width = 0, height = 0;
  RenderOptions options;
  RenderPlan plan;
  EncodedScene scene;
  // A scene with filter effects, left for the render thread to encode (its
  // renderer renders their layers, on its device with CUDA); scene is
  // empty until then.
  std::shared_ptr<const Scene> filtered;
  ImageF image;               // --bits 16
  std::vector<uint8_t> rgba8; // --bits 8 (converted where it was rendered)
  FrameRenderer::DeviceImage device_image;  // Config::device_output: the 8 bits left on the device
  png::ImageData png;         // --bits 8, compressed where it was rendered (level 1 on the GPU)
  png::FilteredRows png_rows; // --bits 8, PNG rows filtered where it was rendered (CUDA), deflated by a worker
  RenderStats stats;
  double prepare_ms[2] = {0, 0};  // the front end's two stages (Config::prepare_names)
  double render_ms = 0, png_ms = 0, write_ms = 0;  // png_ms includes write_ms
  std::vector<std::string> warnings;
};

// Config::forest_scenes for --frame-scenes `asked` (0: the default): 8
// with CUDA and the PNG stage on the device (--compression 1), where the
// render threads bound a job; else 1, each item its own frame (at the
// default PNG level forest frames did not pay, with the rows filtered on
// the device either: BENCHMARKS.md "Forest frames", "PNG rows filtered on
// the device").
inline int forest_scenes_for(int asked, bool cuda, int compression) {
  return asked > 0 ? asked : cuda && compression == 1 ? 8 : 1;
}

struct Config {
  const char* program = "";  // message prefix: "pdf2png"
  const char* unit = "";     // "page", "file": progress line and summary
  const char* prepare_names[2] = {"", ""};  // "interpretation", "lowering"
  int tickets = 0;           // items to go through
  int workers = 1;
  int render_threads = 1;
  bool progress = false;     // a progress line on standard error (a terminal)
  bool stats = false;        // per-item stage times and the job's summary
  bool quiet = false;        // no warnings
  int bits = 8;
  int compression = -1;  // cli::Options::compression (1: compressed by CUDA render threads)
  // The PNG's colours (pdf2png's -gray, -mono): grey and mono images are
  // made from the rendered RGBA by the workers (png::encode_gray8/16), so
  // --compression 1 compresses them on the CPU, never on the device.
  // Mono takes 8 bits (bits == 8).
  png::Color color = png::Color::Rgb;
  // The files' format (pdf2png's -png, -jpeg, -tiff) and its options; TIFF
  // and JPEG are encoded by the workers through image::encode_rgba8/16 (the
  // OpenImageIO module: the caller checks image::encoder_available first),
  // with Job::dpi. compression and the device's PNG stage apply to PNG only.
  image::Format format = image::Format::Png;
  image::EncodeOptions encode;
  // Most items a render thread renders as one forest frame (frame/forest.h:
  // one tree build for several small items waiting together); 1: each
  // item its own frame.
  int forest_scenes = 1;
  Gamma gamma = Gamma::Linear;
  // --timeout: seconds an item may spend from the start of its preparation
  // to the end of its rendering (0: no limit). An item past it fails with
  // "timed out after S s" and is never written; the thread working on it
  // finishes its stage and then drops it (a stage cannot be interrupted),
  // and run() returns without waiting for it (Result::abandoned).
  double timeout_s = 0;
  // Prepares ticket t (0-based) on worker w (0 .. workers-1): the scene
  // encoded, options, plan, size and output path set. Throws on failure.
  std::function<std::unique_ptr<Job>(int t, int w)> prepare;
  // How a failure of prepare names ticket t ("page 4", "a.svg").
  std::function<std::string(int t)> label;
  // The renderer of render thread r, made on that thread (so that it binds
  // its device there). Throws when it cannot be made (reported once); a
  // nullptr means the thread is not needed. Items left when no render
  // thread remains fail, counted in one line.
  std::function<std::unique_ptr<FrameRenderer>(int r)> make_renderer;
  // Library use (libmpvg's PdfDocument::render_pages): `deliver` takes
  // each rendered item instead of a file being written (called by the
  // workers, several at once, in no set order), `failed` hears of each
  // item that fails (its ticket and message); with `failed` set nothing is
  // printed.
  std::function<void(Job& job)> deliver;
  // With CUDA render threads, 8 bits: items render into device memory
  // (Job::device_image, FrameRenderer::render_rgba8_device) for `deliver`,
  // one frame each.
  bool device_output = false;
  std::function<void(int ticket, const std::string& error)> failed;
  // Called for each item written (under the pipeline's lock, in the order
  // they finish): pdf2png's -progress.
  std::function<void(const Job& job)> written;
  // --report FILE: one JSON object a line for each item as it finishes
  // (report_line), flushed line by line; null: none.
  std::FILE* report = nullptr;
  // The item's input and output as the report names them ("a.svg",
  // "a.png"; "doc.pdf", "doc-3.png").
  std::function<std::string(int t)> report_input, report_output;
};

// The report's line for ticket t: {"input": ..., "output": ..., "status":
// "ok" | "failed" | "timed out", "ms": wall time from its start to its
// end, "warnings": [...], "error": "..." (failed only)}.
std::string report_line(const std::string& input, const std::string& output, const char* status, double ms,
                        const std::vector<std::string>& warnings, const std::string& error);

// What went through; totals in ms over the items that succeeded.
struct Result {
  int finished = 0, failed = 0;
  int unrendered = 0;  // of the failed: no renderer could take them
  int timed_out = 0;   // of the failed: past Config::timeout_s
  int write_failed = 0;  // of the failed: rendered, but its file could not be written
  int frames = 0;      // frames rendered (a forest frame renders several items)
  // Threads still busy with an item that timed out when run() returned:
  // the process should end with std::_Exit (they use the caller's data).
  int abandoned = 0;
  double seconds = 0;
  double prepare[2] = {0, 0}, encode = 0, preprocess = 0, render = 0, render_wall = 0, png = 0, write = 0;
  double render_idle = 0, worker_idle = 0;  // time the threads waited for work
};

// Runs every ticket through. A job of several items ends with a summary
// line on standard error ("svg2png: 203 files, 201 written, 2 failed"),
// on a terminal or not; -q leaves it out when nothing failed.
Result run(const Config& config);

// The summary --stats prints after a job (two lines).
std::string summary(const Config& config, const Result& r, const char* backend);

}  // namespace mpvg::pipeline
