// mpvg as a library: SVG documents rendered to RGBA pixels by the same
// pipeline as svg2png, byte for byte what svg2png writes with the same
// options on the same backend. This is the only header a program
// includes; it needs the C++17 standard library and nothing else (no
// CUDA, no XML parser, no internal mpvg header).
//
//   #include <mpvg/mpvg.h>
//
//   mpvg::Renderer renderer;                      // auto: CUDA if a device exists
//   mpvg::SvgDocument doc = mpvg::SvgDocument::from_file("drawing.svg");
//   mpvg::RenderSettings s;
//   s.width = 512;                                // as svg2png -w 512
//   mpvg::Bitmap image = renderer.render(doc, s);  // image.pixels8: RGBA rows
//
// CMake: find_package(mpvg REQUIRED) and
// target_link_libraries(app PRIVATE mpvg::mpvg).
//
// Every failure (unreadable file, malformed XML, impossible size, a CUDA
// backend asked for without a device) throws mpvg::Error, or one of its
// kinds below, with a one-line message; running out of memory throws
// std::bad_alloc.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#if defined(__GNUC__) || defined(__clang__)
#define MPVG_API __attribute__((visibility("default")))
#else
#define MPVG_API
#endif

namespace mpvg {

// The library's one exception type. It is the very class the pipeline
// throws inside the library (core/error.h; the definitions are identical,
// and lib/mpvg_api.cpp, which sees both, skips this one), so a failure
// deep in the parser reaches the caller unchanged.
#ifndef MPVG_INTERNAL_ERROR_DEFINED
#define MPVG_INTERNAL_ERROR_DEFINED 1
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};
// Kinds of failure a caller may treat apart (Python: mpvg.ParseError, ...):
// the document is malformed (XML, PDF syntax, an invalid root or page);
// the work is valid but beyond this build or backend (no PDF support,
// device output without CUDA); the input or the machine's resources fall
// short (an unreadable file, --max-input, --max-memory, no CUDA device).
class ParseError : public Error {
 public:
  using Error::Error;
};
class UnsupportedError : public Error {
 public:
  using Error::Error;
};
class ResourceError : public Error {
 public:
  using Error::Error;
};
// Finer kinds: settings out of range or that cannot go together; a PDF
// encrypted without its password or with a wrong one; a render past its
// memory budget (RenderSettings::max_memory, --max-memory's; the machine
// running out is still std::bad_alloc). Catching the kind above still
// catches these.
class OptionError : public Error {
 public:
  using Error::Error;
};
class PasswordError : public ParseError {
 public:
  using ParseError::ParseError;
};
class MemoryLimitError : public ResourceError {
 public:
  using ResourceError::ResourceError;
};
#endif

// Where frames are rendered. Auto takes CUDA when a device can be used and
// the CPU otherwise (Renderer::note() says why): a Renderer pays CUDA's
// start-up once, so unlike svg2png's auto it does not weigh the start-up
// against the size of one frame. Cuda without a device is an error. The
// CPU backend is the reference: both give the same pixels with the box
// filters (1x8, 1x32) and agree within 1/255 with the wide one.
enum class Device { Auto, Cpu, Cuda };

// The paper's antialiasing modes (svg2png --aa).
enum class Antialiasing {
  Box1x8,          // "1x8": box filter, 8 stratified samples per pixel
  Box1x32,         // "1x32": box filter, 32 stratified samples per pixel
  Cardinal4x4x32,  // "4x4x32": cardinal cubic B-spline over 4x4 pixels, 32 blue-noise samples each
};

// The colour space samples are integrated in (svg2png --gamma): linear
// light, or sRGB values as most renderers blend.
enum class GammaMode { Linear, Srgb };

// A colour with straight (not premultiplied) alpha, sRGB components in [0, 1].
struct MPVG_API Color {
  float r = 0, g = 0, b = 0, a = 0;
  // Any CSS colour syntax ("white", "#ff8000", "rgba(0, 0, 255, 0.5)", ...),
  // as svg2png -b reads it. Throws mpvg::Error for text it cannot read.
  static Color parse(std::string_view css);
};

// How a document becomes pixels; the defaults are svg2png's.
struct RenderSettings {
  // Output size, as svg2png's -w, -h, -z and -a: width alone or height
  // alone keeps the document's aspect ratio (the other side rounded), both
  // stretch to exactly that size unless keep_aspect_ratio fits the
  // document inside them; without either, the document's own size (CSS
  // pixels) times zoom. Sizes must be positive, at most 32768 pixels.
  std::optional<double> width, height;
  double zoom = 1;
  bool keep_aspect_ratio = false;

  Antialiasing antialiasing = Antialiasing::Cardinal4x4x32;
  std::uint32_t seed = 0;  // of the sample pattern (svg2png --seed)
  GammaMode gamma = GammaMode::Linear;
  Color background{0, 0, 0, 0};  // transparent
  int bits = 8;                  // per channel: 8 or 16

  // As svg2png's --font-dir (fonts for <text>: every font file in these
  // folders' trees, before the system's), --languages (the user's
  // languages for systemLanguage and <switch>, BCP 47 tags), --max-memory
  // (the budget of one parse and render in bytes; 0: half the machine's
  // memory; past it MemoryLimitError) and --allow-read (folders whose
  // files the document may read, added to the document's allowed_dirs).
  // A render with other values of these parses the document again.
  std::vector<std::string> font_dirs;
  std::vector<std::string> languages{"en"};
  std::uint64_t max_memory = 0;
  std::vector<std::string> allow_read;
};

// Pixel dimensions of an output.
struct OutputSize {
  int width = 0, height = 0;
};

// A rendered image: rows top to bottom, pixels RGBA with straight alpha,
// sRGB-encoded, exactly what svg2png writes into its PNG (same options,
// same backend). For 8 bits the pixels are in pixels8, for 16 bits in
// pixels16 (native byte order); the other vector is empty. A PDF page
// rendered in another colour space (PdfRenderSettings::colorspace) has
// other channels: see OutputColorSpace.
struct Bitmap {
  int width = 0, height = 0, bits = 8;
  int channels = 4;
  std::vector<std::uint8_t> pixels8;
  std::vector<std::uint16_t> pixels16;

  // Bytes from one row to the next.
  std::size_t stride() const { return static_cast<std::size_t>(width) * channels * (bits / 8); }
};

// A rendered 8-bit image left in CUDA device memory (Renderer::
// render_device): rows top to bottom, 4 bytes a pixel (RGBA, straight
// alpha, the bytes Bitmap::pixels8 would hold), width * 4 bytes a row. The
// memory is mpvg's, freed when the last copy of `pixels` goes; the render
// and the copy into it are finished when it is returned (no stream to wait
// on).
struct DeviceBitmap {
  int width = 0, height = 0;
  int device = 0;  // the CUDA device (cudaSetDevice's number)
  std::shared_ptr<std::uint8_t> pixels;
};

// A device bitmap's pixels copied to the host (as Bitmap::pixels8).
MPVG_API std::vector<std::uint8_t> download(const DeviceBitmap& bitmap);

// Images as files: a PNG (8 or 16 bits; grey, RGB, palette, with or
// without alpha) read into a straight-alpha RGBA Bitmap, and a Bitmap
// (1 to 4 channels: grey, grey and alpha, RGB, RGBA) written as a PNG
// with mpvg's encoder (no time or other varying metadata: equal pixels
// give equal files). Throw mpvg::Error.
MPVG_API Bitmap read_png(const std::string& path);
MPVG_API void write_png(const std::string& path, const Bitmap& bitmap);

// Golden-image comparison (mpvg-compare; the README's "Comparing images"):
// two images of one size, premultiplied, channels in [0, 1], a pixel's
// difference the largest over its channels; OpenImageIO idiff's
// thresholds, and an antialiasing-aware mode that forgives differences on
// antialiased edges whose surroundings are the same in both images.
struct CompareSettings {
  double fail = 1e-6;        // a pixel differing by more fails
  double failpercent = 0;    // the images fail when more than this % of pixels fail
  double hardfail = -1;      // < 0: none; else any pixel differing by more fails the images
  double warn = 1e-6, warnpercent = 0, hardwarn = -1;  // the same for a warning
  bool antialiasing = false;
  double aa_ring = 0.3;      // beside an edge, a difference up to this times its contrast is forgiven
};

enum class CompareVerdict { Pass, Warn, Fail };

struct CompareResult {
  CompareVerdict verdict = CompareVerdict::Pass;
  bool same_size = true;
  int width = 0, height = 0;
  std::size_t pixels = 0, differing = 0, failed = 0, warned = 0, antialiased = 0;
  double max_difference = 0;
  int max_x = 0, max_y = 0;
  double mean_difference = 0, rms_difference = 0;
  double psnr = 0;  // dB; +infinity for equal images
  Bitmap diff;      // with diff_image: a faded grey copy of a, failures red, warnings orange, forgiven yellow
  std::string json;  // the result as one JSON object (mpvg-compare --json)
};

// Compares two bitmaps (8 or 16 bits, 1 to 4 channels, straight alpha).
MPVG_API CompareResult compare(const Bitmap& a, const Bitmap& b, const CompareSettings& settings = {},
                               bool diff_image = false);

// An SVG document. It is parsed when first needed, for the output size of
// that need, and again only when a render asks for another size (strokes
// are converted to fills for the output's pixels, so the parsed scene
// depends on the scale): rendering a document once parses it once, as
// svg2png does. Images it references are read from data: URIs and from
// files in its own folder's tree or in allowed_dirs (real paths, symbolic
// links resolved), never from the network. Safe to share between threads.
class MPVG_API SvgDocument {
 public:
  // Reads the file (its folder is where relative references resolve).
  // Throws mpvg::Error "cannot read 'PATH': reason".
  static SvgDocument from_file(const std::string& path, const std::vector<std::string>& allowed_dirs = {});
  // SVG text in memory (copied); base_dir is where its relative references
  // resolve and whose tree it may read.
  static SvgDocument from_data(std::string_view svg, const std::string& base_dir = ".",
                               const std::vector<std::string>& allowed_dirs = {});

  ~SvgDocument();
  SvgDocument(SvgDocument&&) noexcept;
  SvgDocument& operator=(SvgDocument&&) noexcept;

  // These functions, like Renderer::render, parse the document when it has
  // not been parsed yet, and then throw mpvg::Error for a malformed one:
  // "XML parse error at line N: ...", or a message naming a non-SVG root
  // or an invalid size.

  // Intrinsic size in CSS pixels (the root's width and height, or its
  // viewBox's).
  double width() const;
  double height() const;
  // The output size settings give for this document (what render returns).
  // Throws mpvg::Error for invalid settings.
  OutputSize output_size(const RenderSettings& settings) const;
  // One short line per feature rendered approximately or not at all
  // (text, filters, ...), deduplicated, from the latest parse.
  std::vector<std::string> warnings() const;

 private:
  friend class Renderer;
  struct Impl;
  explicit SvgDocument(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The page box a PDF page is rendered over (PDF 32000-1 §14.11.2; the
// CropBox by default, as MuPDF and pdf2png render).
enum class PageBox { Media, Crop, Bleed, Trim, Art };

// The pixels of a rendered PDF page (pdf2png's --colorspace):
//   Rgb:  RGBA, straight alpha (4 channels);
//   Gray: grey as pdf2png -gray writes it (0.30 R + 0.59 G + 0.11 B of the
//         RGB render, pdftoppm's), 1 channel over an opaque background,
//         grey and alpha (2) over a transparent one;
//   Cmyk: the four process inks the page prints with (0 none, 255 full;
//         overprint simulated, spot colours through their alternates,
//         RGB through the document's output intent), the pixels of
//         pdf2png --colorspace cmyk's TIFF; 8 bits, 4 channels, sRGB
//         gamma (ink amounts are integrated as they are), drawn on paper
//         whatever the background.
enum class OutputColorSpace { Rgb, Gray, Cmyk };

// How a PDF page becomes pixels; the defaults are pdf2png's.
struct PdfRenderSettings {
  double dpi = 150;  // output pixels per inch (72 points); > 0
  Antialiasing antialiasing = Antialiasing::Cardinal4x4x32;
  std::uint32_t seed = 0;
  GammaMode gamma = GammaMode::Srgb;  // PDF composites device values
  Color background{1, 1, 1, 1};       // white paper; {0, 0, 0, 0}: transparent
  int bits = 8;                       // per channel: 8 or 16
  PageBox box = PageBox::Crop;
  bool annotations = true;            // annotations and form fields, as printed
  bool snap_thin_lines = false;       // pdf2png --thin-lines snap
  OutputColorSpace colorspace = OutputColorSpace::Rgb;
  // The size as pdf2png's (pdftoppm's) -ry, -scale-to, -scale-to-x and
  // -scale-to-y give it: dpi_y > 0 the vertical resolution (0: dpi);
  // scale_to > 0 the longer side in pixels (the aspect ratio kept; it wins
  // over the others); scale_to_x (scale_to_y) > 0 the width (height) in
  // pixels, the other axis at its resolution, or, when that one is -1,
  // scaled alike (the aspect ratio kept). 0: not given.
  double dpi_y = 0;
  int scale_to = 0;
  int scale_to_x = 0, scale_to_y = 0;
  // pdf2png's --max-memory: the budget of one page's lowering and render in
  // bytes (0: half the machine's memory); past it MemoryLimitError.
  std::uint64_t max_memory = 0;
};

// A PDF document, interpreted by MuPDF (where the library was built with
// it; elsewhere from_file and from_data throw mpvg::Error saying so).
// Pages are interpreted when rendered, for the resolution of the render.
// Safe to share between threads (one page is interpreted at a time).
class MPVG_API PdfDocument {
 public:
  // Throws mpvg::Error: unreadable, broken, encrypted without the
  // password, or a wrong password.
  static PdfDocument from_file(const std::string& path, const std::string& password = "");
  // The document's bytes (copied).
  static PdfDocument from_data(std::string_view pdf, const std::string& password = "");

  ~PdfDocument();
  PdfDocument(PdfDocument&&) noexcept;
  PdfDocument& operator=(PdfDocument&&) noexcept;

  int page_count() const;
  // Width and height in points of page `index`'s (0-based) box, after
  // /Rotate and /UserUnit. Throws mpvg::Error for a page past the last.
  std::pair<double, double> page_size(int index, PageBox box = PageBox::Crop) const;
  // The pixel size of page `index` rendered with `settings`.
  OutputSize output_size(int index, const PdfRenderSettings& settings = {}) const;
  // One line per feature of the last page rendered that was drawn
  // approximately or not at all.
  std::vector<std::string> warnings() const;

  // Renders `pages` (0-based; any order, repeats allowed) through
  // pdf2png's page pipeline: worker threads (`threads`, 0: one per core,
  // less the render threads with CUDA), each with a document handle of its
  // own, interpret and lower pages while render threads (with CUDA three,
  // each with its own stream; on the CPU one) render others. Each page's
  // bitmap, the pixels Renderer::render gives, goes to sink(position in
  // `pages`, bitmap, warnings), and each failure to failed(position,
  // message), from the pipeline's threads: several at once, in no set
  // order. Returns when every page is through. A sink that throws fails
  // that page. `cancelled`, when given, is asked before each page is
  // interpreted: once it says true the pages left fail at once
  // ("cancelled").
  using PageSink = std::function<void(std::size_t position, Bitmap&& bitmap, std::vector<std::string>&& warnings)>;
  using PageFailure = std::function<void(std::size_t position, const std::string& message)>;
  void render_pages(const std::vector<int>& pages, const PdfRenderSettings& settings, const PageSink& sink,
                    const PageFailure& failed, Device device = Device::Auto, int threads = 0,
                    const std::function<bool()>& cancelled = nullptr) const;

  // `pages` through the same pipeline on the CUDA backend, straight into
  // one device allocation: a DeviceBitmap `pages.size()` images tall,
  // image k (page pages[k]) at rows k * h .. (k + 1) * h - 1, 8 bits.
  // Every page must have the same pixel size (checked before any page
  // renders); a page that fails fails the batch. Throws mpvg::Error
  // (no CUDA device, sizes, a page's failure).
  DeviceBitmap render_batch(const std::vector<int>& pages, const PdfRenderSettings& settings = {},
                            int threads = 0) const;

  // render_pages on the CUDA backend with each page's 8-bit RGBA pixels
  // left on the device: sink gets the DeviceBitmap Renderer::render_device
  // gives, never copied through the host. Throws mpvg::Error without a
  // CUDA device.
  using DevicePageSink =
      std::function<void(std::size_t position, DeviceBitmap&& bitmap, std::vector<std::string>&& warnings)>;
  void render_pages_device(const std::vector<int>& pages, const PdfRenderSettings& settings,
                           const DevicePageSink& sink, const PageFailure& failed, int threads = 0,
                           const std::function<bool()>& cancelled = nullptr) const;

 private:
  friend class Renderer;
  struct Impl;
  explicit PdfDocument(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Renders documents one after another on one backend, keeping its state
// between them: with CUDA the context, the kernels and the device buffers
// (which grow to the largest frame) live as long as the Renderer. Not
// thread-safe: one Renderer per rendering thread.
class MPVG_API Renderer {
 public:
  // Throws mpvg::Error for Device::Cuda without a usable device.
  explicit Renderer(Device device = Device::Auto);
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // The backend in use: Cpu or Cuda (Auto resolved at construction).
  Device device() const;
  // Why Auto chose the CPU, or empty.
  std::string note() const;

  // Renders doc into a new bitmap of doc.output_size(settings).
  Bitmap render(const SvgDocument& doc, const RenderSettings& settings = {});
  // Renders into the caller's memory: height rows of width RGBA pixels
  // (uint8_t or, for 16 bits, uint16_t channels), row r starting at byte
  // r * stride of pixels. width and height must be doc.output_size(settings)
  // and stride at least width * 4 * bits / 8 bytes (and even for 16 bits);
  // bytes between rows are left alone.
  void render(const SvgDocument& doc, const RenderSettings& settings, void* pixels, std::size_t stride, int width,
              int height);
  // Renders page `index` (0-based) of a PDF document: the pixels pdf2png
  // writes for the same settings on the same backend.
  Bitmap render(const PdfDocument& doc, int index, const PdfRenderSettings& settings = {});
  // As render(), 8 bits only, the pixels left on the device (the CUDA
  // backend only: mpvg::Error on the CPU), never copied through the host.
  DeviceBitmap render_device(const SvgDocument& doc, const RenderSettings& settings = {});
  DeviceBitmap render_device(const PdfDocument& doc, int index, const PdfRenderSettings& settings = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mpvg
