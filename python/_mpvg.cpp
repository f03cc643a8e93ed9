// The extension of the Python package `mpvg` (python/mpvg/): SVG to numpy arrays through libmpvg's public
// API (include/mpvg/mpvg.h), the pixels svg2png writes for the same
// options.
//
//   import mpvg
//   r = mpvg.Renderer()                     # "auto", "cpu" or "cuda"
//   img = r.render_svg("drawing.svg", width=512)   # H x W x 4 uint8
//   img = r.render_svg(b"<svg ...>...</svg>", bits=16)  # bytes: the document itself
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cstdio>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <optional>
#include <string>
#include <vector>

#include <mpvg/mpvg.h>

namespace py = pybind11;

namespace {

mpvg::Device device_named(const std::string& s) {
  if (s == "auto") return mpvg::Device::Auto;
  if (s == "cpu") return mpvg::Device::Cpu;
  if (s == "cuda") return mpvg::Device::Cuda;
  throw py::value_error("unknown backend '" + s + "' (auto, cpu or cuda)");
}

mpvg::Antialiasing antialiasing_named(const std::string& s) {
  if (s == "1x8") return mpvg::Antialiasing::Box1x8;
  if (s == "1x32") return mpvg::Antialiasing::Box1x32;
  if (s == "4x4x32") return mpvg::Antialiasing::Cardinal4x4x32;
  throw py::value_error("unknown antialiasing mode '" + s + "' (1x8, 1x32 or 4x4x32)");
}

mpvg::GammaMode gamma_named(const std::string& s) {
  if (s == "linear") return mpvg::GammaMode::Linear;
  if (s == "srgb") return mpvg::GammaMode::Srgb;
  throw py::value_error("unknown gamma '" + s + "' (linear or srgb)");
}

// None (transparent), a CSS colour, or (r, g, b[, a]) in [0, 1].
mpvg::Color color_from(const py::object& bg) {
  if (bg.is_none()) return {};
  if (py::isinstance<py::str>(bg)) return mpvg::Color::parse(bg.cast<std::string>());
  const std::vector<float> c = bg.cast<std::vector<float>>();
  if (c.size() != 3 && c.size() != 4)
    throw py::value_error("background takes a CSS colour or (r, g, b[, a]) with components in [0, 1]");
  return {c[0], c[1], c[2], c.size() == 4 ? c[3] : 1.0f};
}

// An H x W x 4 array that owns the bitmap's pixels (no copy).
template <class T>
py::array as_array(std::vector<T>&& pixels, int width, int height, int channels = 4) {
  auto owned = std::make_unique<std::vector<T>>(std::move(pixels));
  T* data = owned->data();
  py::capsule owner(owned.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  owned.release();
  const auto w = static_cast<py::ssize_t>(width), h = static_cast<py::ssize_t>(height);
  const auto s = static_cast<py::ssize_t>(sizeof(T)), c = static_cast<py::ssize_t>(channels);
  return py::array_t<T>({h, w, c}, {w * c * s, c * s, s}, data, owner);
}

// DLPack's C ABI (dmlc/dlpack's dlpack.h, 0.8), its three structs spelled
// out as the protocol fixes them: the header is not among the build's
// dependencies.
struct DLDevice {
  int32_t device_type;  // kDLCUDA
  int32_t device_id;
};
struct DLDataType {
  uint8_t code;  // kDLUInt
  uint8_t bits;
  uint16_t lanes;
};
struct DLTensor {
  void* data;
  DLDevice device;
  int32_t ndim;
  DLDataType dtype;
  int64_t* shape;
  int64_t* strides;  // null: row-major, compact
  uint64_t byte_offset;
};
struct DLManagedTensor {
  DLTensor dl_tensor;
  void* manager_ctx;
  void (*deleter)(DLManagedTensor* self);
};
constexpr int32_t kDLCUDA = 2;
constexpr uint8_t kDLUInt = 1;

// mpvg.DeviceArray: an H x W x 4 uint8 image in CUDA memory owned by mpvg
// (render(..., device="cuda")), handed to torch.from_dlpack, cupy.asarray
// or numba without a copy: __dlpack__ / __dlpack_device__ and
// __cuda_array_interface__ (version 3). The render and the copy into its
// memory are finished before it is returned, so no stream needs to wait;
// the memory lives as long as this object or a tensor made from it.
class PyDeviceArray {
 public:
  // count > 0: a batch of `count` images stacked in b's rows (N x H x W x 4).
  explicit PyDeviceArray(mpvg::DeviceBitmap b, int count = 0) : b_(std::move(b)), count_(count) {}

  std::vector<int64_t> dims() const {
    if (count_ > 0) return {count_, b_.height / count_, b_.width, 4};
    return {b_.height, b_.width, 4};
  }
  py::tuple shape() const { return py::cast(dims()); }
  int device() const { return b_.device; }

  py::dict cuda_array_interface() const {
    py::dict d;
    d["shape"] = shape();
    d["typestr"] = "|u1";
    d["data"] = py::make_tuple(reinterpret_cast<uintptr_t>(b_.pixels.get()), false);
    d["version"] = 3;
    d["strides"] = py::none();
    d["stream"] = py::none();  // nothing to wait for
    return d;
  }

  py::tuple dlpack_device() const { return py::make_tuple(kDLCUDA, b_.device); }

  py::object dlpack(const py::object& /*stream: the data is ready on every stream*/) const {
    struct Holder {
      std::shared_ptr<uint8_t> pixels;  // keeps the memory alive
      std::vector<int64_t> shape;
      DLManagedTensor tensor;
    };
    auto* h = new Holder{b_.pixels, dims(), {}};
    DLTensor& t = h->tensor.dl_tensor;
    t.data = h->pixels.get();
    t.device = DLDevice{kDLCUDA, b_.device};
    t.ndim = static_cast<int32_t>(h->shape.size());
    t.dtype = DLDataType{kDLUInt, 8, 1};
    t.shape = h->shape.data();
    t.strides = nullptr;
    t.byte_offset = 0;
    h->tensor.manager_ctx = h;
    h->tensor.deleter = [](DLManagedTensor* self) { delete static_cast<Holder*>(self->manager_ctx); };
    // A capsule not consumed (still named "dltensor") frees the tensor.
    PyObject* capsule = PyCapsule_New(&h->tensor, "dltensor", [](PyObject* c) {
      if (PyCapsule_IsValid(c, "dltensor")) {
        auto* m = static_cast<DLManagedTensor*>(PyCapsule_GetPointer(c, "dltensor"));
        if (m && m->deleter) m->deleter(m);
      }
    });
    if (!capsule) {
      delete h;
      throw py::error_already_set();
    }
    return py::reinterpret_steal<py::object>(capsule);
  }

  // A host copy, as NumPy (what render() with device="cpu" gives).
  py::array to_host() const {
    std::vector<uint8_t> pixels;
    {
      py::gil_scoped_release release;
      pixels = mpvg::download(b_);
    }
    py::array a = as_array(std::move(pixels), b_.width, b_.height);
    return count_ > 0 ? a.reshape(dims()) : a;
  }

 private:
  mpvg::DeviceBitmap b_;
  int count_ = 0;
};

// Where a render's pixels go: "cpu" (a NumPy array) or "cuda" (a
// DeviceArray, the CUDA backend only).
bool on_device(const std::string& device) {
  if (device == "cpu") return false;
  if (device == "cuda") return true;
  throw py::value_error("unknown output device '" + device + "' (cpu or cuda)");
}

// A str or path-like object as a path (os.fspath).
std::string fspath(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

// A path (str or path-like) or the document's bytes (bytes, bytearray,
// memoryview). `data` names the bytes and `usage` says what is taken, in
// the TypeErrors.
struct Input {
  std::optional<std::string> path, data;
};
Input input_from(const py::object& input, const char* data, const char* usage) {
  Input in;
  if (py::isinstance<py::str>(input)) {
    in.path = input.cast<std::string>();
  } else if (py::isinstance<py::bytes>(input)) {
    in.data = input.cast<std::string>();
  } else if (PyObject_CheckBuffer(input.ptr())) {
    const py::buffer_info b = py::reinterpret_borrow<py::buffer>(input).request();
    if (b.ndim != 1 || b.itemsize != 1) throw py::type_error(std::string(data) + " must be a one-dimensional buffer of bytes");
    in.data = std::string(static_cast<const char*>(b.ptr), static_cast<size_t>(b.size));
  } else if (py::hasattr(input, "__fspath__")) {
    in.path = fspath(input);
  } else {
    throw py::type_error(usage);
  }
  return in;
}

// A rendered bitmap as an H x W x 4 array (uint8, or uint16 for 16 bits).
py::array array_of(mpvg::Bitmap&& b) {
  return b.bits == 16 ? as_array(std::move(b.pixels16), b.width, b.height, b.channels)
                      : as_array(std::move(b.pixels8), b.width, b.height, b.channels);
}

// An array (H x W, or H x W x C with C 1 to 4; uint8 or uint16) as a
// Bitmap: grey, grey and alpha, RGB or RGBA, straight alpha.
mpvg::Bitmap bitmap_from_array(const py::object& object, const char* what) {
  const py::array a = py::array::ensure(object, py::array::c_style);
  if (!a) throw py::type_error(std::string(what) + " must be an array or a path");
  if (a.ndim() != 2 && a.ndim() != 3)
    throw py::value_error(std::string(what) + " must be H x W or H x W x C (C 1 to 4)");
  mpvg::Bitmap b;
  b.height = static_cast<int>(a.shape(0));
  b.width = static_cast<int>(a.shape(1));
  b.channels = a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 1;
  if (b.channels < 1 || b.channels > 4) throw py::value_error(std::string(what) + " must have 1 to 4 channels");
  const size_t n = static_cast<size_t>(a.size());
  if (a.dtype().is(py::dtype::of<uint8_t>())) {
    b.bits = 8;
    b.pixels8.assign(static_cast<const uint8_t*>(a.data()), static_cast<const uint8_t*>(a.data()) + n);
  } else if (a.dtype().is(py::dtype::of<uint16_t>())) {
    b.bits = 16;
    b.pixels16.assign(static_cast<const uint16_t*>(a.data()), static_cast<const uint16_t*>(a.data()) + n);
  } else {
    throw py::type_error(std::string(what) + " must be uint8 or uint16");
  }
  return b;
}

// The PNG at a path (str or path-like), read with the GIL released.
mpvg::Bitmap png_at(const py::object& path) {
  const std::string p = fspath(path);
  py::gil_scoped_release release;
  return mpvg::read_png(p);
}

// An image to compare: an array, or a PNG's path.
mpvg::Bitmap image_from(const py::object& object, const char* what) {
  if (py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__")) return png_at(object);
  return bitmap_from_array(object, what);
}

// mpvg.compare's result.
struct PyCompareResult {
  mpvg::CompareResult r;
  py::object diff = py::none();
  std::string verdict() const {
    return r.verdict == mpvg::CompareVerdict::Pass ? "PASS" : r.verdict == mpvg::CompareVerdict::Warn ? "WARNING" : "FAILURE";
  }
  bool passed() const { return r.verdict != mpvg::CompareVerdict::Fail; }
  std::string repr() const {
    char b[256];
    std::snprintf(b, sizeof b,
                  "<mpvg.CompareResult %s: %zu of %zu pixels differ, %zu fail, %zu warn, %zu antialiasing, max %.4g>",
                  verdict().c_str(), r.differing, r.pixels, r.failed, r.warned, r.antialiased, r.max_difference);
    return b;
  }
};

PyCompareResult compare_images(const py::object& a, const py::object& b, double fail, double failpercent,
                               std::optional<double> hardfail, double warn, double warnpercent,
                               std::optional<double> hardwarn, bool antialiasing, double aa_ring,
                               const py::object& diff) {
  mpvg::CompareSettings s;
  s.fail = fail, s.failpercent = failpercent, s.warn = warn, s.warnpercent = warnpercent;
  s.hardfail = hardfail.value_or(-1.0), s.hardwarn = hardwarn.value_or(-1.0);
  s.antialiasing = antialiasing;
  s.aa_ring = aa_ring;
  const mpvg::Bitmap x = image_from(a, "a"), y = image_from(b, "b");
  const bool want_diff = !diff.is_none() && !(py::isinstance<py::bool_>(diff) && !diff.cast<bool>());
  PyCompareResult out;
  {
    py::gil_scoped_release release;
    out.r = mpvg::compare(x, y, s, want_diff);
  }
  if (want_diff && out.r.same_size) {
    if (!py::isinstance<py::bool_>(diff)) mpvg::write_png(fspath(diff), out.r.diff);
    out.diff = array_of(std::move(out.r.diff));
  }
  return out;
}

// A page's warnings through Python's warnings module, "page N: ...".
void warn_page(int page, const std::vector<std::string>& warnings) {
  if (warnings.empty()) return;
  py::object warn = py::module_::import("warnings").attr("warn");
  for (const std::string& w : warnings) warn("page " + std::to_string(page + 1) + ": " + w);
}

// mpvg.Renderer: one mpvg::Renderer (with CUDA, one context and its device
// buffers) kept across calls. Calls from several Python threads take turns.
class PyRenderer {
 public:
  explicit PyRenderer(const std::string& backend) : renderer_(device_named(backend)) {}

  std::string backend() const { return renderer_.device() == mpvg::Device::Cuda ? "cuda" : "cpu"; }
  std::string note() const { return renderer_.note(); }
  std::vector<std::string> warnings() const { return warnings_; }

  py::array render_svg(const py::object& input, std::optional<double> width, std::optional<double> height,
                       std::optional<double> zoom, bool keep_aspect_ratio, const std::string& aa,
                       const std::string& gamma, const py::object& background, int bits, uint32_t seed,
                       const std::string& base_dir, const std::vector<std::string>& allow_read) {
    // A str (or path-like) names a file; bytes-like objects are the document.
    const Input in = input_from(input, "SVG data", "render_svg takes a path (str) or the SVG document (bytes)");
    const std::optional<std::string>& path = in.path;
    const std::optional<std::string>& data = in.data;
    mpvg::RenderSettings s;
    s.width = width;
    s.height = height;
    if (zoom) s.zoom = *zoom;
    s.keep_aspect_ratio = keep_aspect_ratio;
    s.antialiasing = antialiasing_named(aa);
    s.gamma = gamma_named(gamma);
    s.background = color_from(background);
    s.bits = bits;
    s.seed = seed;

    mpvg::Bitmap image;
    std::vector<std::string> warnings;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      const mpvg::SvgDocument doc = path ? mpvg::SvgDocument::from_file(*path, allow_read)
                                         : mpvg::SvgDocument::from_data(*data, base_dir, allow_read);
      image = renderer_.render(doc, s);
      warnings = doc.warnings();
    }
    warnings_ = std::move(warnings);
    return array_of(std::move(image));
  }

 private:
  mpvg::Renderer renderer_;
  std::mutex mutex_;
  std::vector<std::string> warnings_;
};

mpvg::PageBox box_named(const std::string& s) {
  if (s == "media") return mpvg::PageBox::Media;
  if (s == "crop") return mpvg::PageBox::Crop;
  if (s == "bleed") return mpvg::PageBox::Bleed;
  if (s == "trim") return mpvg::PageBox::Trim;
  if (s == "art") return mpvg::PageBox::Art;
  throw py::value_error("unknown page box '" + s + "' (media, crop, bleed, trim or art)");
}


// mpvg.Document: a PDF document and the renderer its pages are drawn with
// (made on the first render, on `backend`). Calls from several Python
// threads take turns.
class PyDocument {
 public:
  PyDocument(const py::object& input, const std::optional<std::string>& password, const std::string& backend)
      : backend_(device_named(backend)) {
    const Input in = input_from(input, "Document data",
                                "Document takes a path (str or path-like) or the document itself (bytes)");
    const std::string pw = password.value_or("");
    py::gil_scoped_release release;
    doc_ = std::make_unique<mpvg::PdfDocument>(in.path ? mpvg::PdfDocument::from_file(*in.path, pw)
                                                       : mpvg::PdfDocument::from_data(*in.data, pw));
  }

  int len() const { return doc_->page_count(); }

  int index(int page) const {
    const int n = doc_->page_count();
    if (page < 0) page += n;  // -1: the last page, as Python indexes
    if (page < 0 || page >= n) throw py::index_error("page " + std::to_string(page) + " out of range (" + std::to_string(n) + " pages)");
    return page;
  }

  std::pair<double, double> page_size(int page, const std::string& box) const {
    return doc_->page_size(index(page), box_named(box));
  }

  std::vector<std::string> warnings() const { return doc_->warnings(); }

  static mpvg::PdfRenderSettings settings(double dpi, const std::string& aa, const std::string& gamma,
                                          const py::object& background, int bits, uint32_t seed, const std::string& box,
                                          bool annotations, const std::string& thin_lines,
                                          const std::string& colorspace) {
    const mpvg::OutputColorSpace space = colorspace == "rgb"    ? mpvg::OutputColorSpace::Rgb
                                   : colorspace == "gray" ? mpvg::OutputColorSpace::Gray
                                   : colorspace == "cmyk" ? mpvg::OutputColorSpace::Cmyk
                                                          : throw py::value_error("unknown colorspace '" + colorspace +
                                                                                  "' (rgb, gray or cmyk)");
    if (space == mpvg::OutputColorSpace::Cmyk && bits != 8) throw py::value_error("colorspace 'cmyk' renders 8 bits");
    if (thin_lines != "exact" && thin_lines != "snap")
      throw py::value_error("unknown thin_lines '" + thin_lines + "' (exact or snap)");
    mpvg::PdfRenderSettings s;
    s.dpi = dpi;
    s.antialiasing = antialiasing_named(aa);
    s.gamma = gamma_named(gamma);
    s.background = background.is_none() ? mpvg::Color{} : color_from(background);
    s.bits = bits;
    s.seed = seed;
    s.box = box_named(box);
    s.annotations = annotations;
    s.snap_thin_lines = thin_lines == "snap";
    s.colorspace = space;
    return s;
  }

  py::object render(int page, double dpi, const std::string& aa, const std::string& gamma, const py::object& background,
                    int bits, uint32_t seed, const std::string& box, bool annotations, const std::string& thin_lines,
                    const std::string& colorspace, const std::string& device) {
    const mpvg::PdfRenderSettings s =
        settings(dpi, aa, gamma, background, bits, seed, box, annotations, thin_lines, colorspace);
    const int i = index(page);
    const bool gpu = device_output(device, s);
    mpvg::Bitmap image;
    mpvg::DeviceBitmap on_gpu;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      if (!renderer_) renderer_ = std::make_unique<mpvg::Renderer>(backend_);
      if (gpu) on_gpu = renderer_->render_device(*doc_, i, s);
      else image = renderer_->render(*doc_, i, s);
    }
    warn_page(i, doc_->warnings());  // (also in .warnings)
    if (gpu) return py::cast(PyDeviceArray(std::move(on_gpu)));
    return array_of(std::move(image));
  }

  py::object render_batch(const std::optional<std::vector<int>>& pages, double dpi, const std::string& aa,
                          const std::string& gamma, const py::object& background, uint32_t seed,
                          const std::string& box, bool annotations, const std::string& thin_lines, int threads) {
    const mpvg::PdfRenderSettings s =
        settings(dpi, aa, gamma, background, 8, seed, box, annotations, thin_lines, "rgb");
    std::vector<int> list;
    if (pages) {
      for (int p : *pages) list.push_back(index(p));
    } else {
      for (int p = 0; p < len(); p++) list.push_back(p);
    }
    mpvg::DeviceBitmap b;
    {
      py::gil_scoped_release release;
      b = doc_->render_batch(list, s, threads);
    }
    return py::cast(PyDeviceArray(std::move(b), static_cast<int>(list.size())));
  }

  // Is `device` the GPU (on_device) for a page rendered with s? Device output is 8-bit
  // RGBA.
  static bool device_output(const std::string& device, const mpvg::PdfRenderSettings& s) {
    const bool gpu = on_device(device);
    if (gpu && (s.colorspace != mpvg::OutputColorSpace::Rgb || s.bits != 8))
      throw py::value_error("device='cuda' renders 8-bit RGBA (colorspace='rgb', bits=8)");
    return gpu;
  }

  class PageStream;
  std::unique_ptr<PageStream> render_pages(const std::optional<std::vector<int>>& pages, double dpi,
                                           const std::string& aa, const std::string& gamma,
                                           const py::object& background, int bits, uint32_t seed,
                                           const std::string& box, bool annotations, const std::string& thin_lines,
                                           const std::string& colorspace, int threads, const std::string& device);

  mpvg::Device backend_;
  std::unique_ptr<mpvg::PdfDocument> doc_;

 private:
  std::mutex mutex_;
  std::unique_ptr<mpvg::Renderer> renderer_;
};

// doc.render_pages(...): an iterator over the pages' arrays, in the order
// asked, while mpvg::PdfDocument::render_pages runs them through pdf2png's
// pipeline on a thread of its own. At most kWindow pages past the one the
// iterator waits for are held; the pipeline's threads wait for the rest.
// Ctrl-C (or dropping the iterator) cancels the pages not yet started.
// The window is wider than the pipeline has pages in flight (workers + 4 +
// render threads), so that the page waited for is never behind a worker
// that waits for the window.
class PyDocument::PageStream {
 public:
  const size_t kWindow = 64 + 2 * size_t(std::max(1u, std::thread::hardware_concurrency()));

  PageStream(const PyDocument& doc, std::vector<int> pages, mpvg::PdfRenderSettings settings, int threads,
             bool on_gpu)
      : pages_(std::move(pages)) {
    worker_ = std::thread([this, &doc, settings, threads, on_gpu] {
      // A page's result, once the window has room for it.
      auto keep = [this](size_t k, Result&& r) {
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait(lock, [&] { return cancel_ || k < next_ + kWindow; });
        if (cancel_) return;
        done_[k] = std::move(r);
        cv_.notify_all();
      };
      auto failed = [this](size_t k, const std::string& message) {
        std::lock_guard<std::mutex> lock(m_);
        Result r;
        r.error = message.empty() ? "failed" : message;
        done_[k] = std::move(r);
        cv_.notify_all();
      };
      try {
        if (on_gpu)
          doc.doc_->render_pages_device(
              pages_, settings,
              [&](size_t k, mpvg::DeviceBitmap&& b, std::vector<std::string>&& warnings) {
                Result r;
                r.device_bitmap = std::move(b);
                r.warnings = std::move(warnings);
                keep(k, std::move(r));
              },
              failed, threads, [this] { return cancel_.load(); });
        else
          doc.doc_->render_pages(
              pages_, settings,
              [&](size_t k, mpvg::Bitmap&& b, std::vector<std::string>&& warnings) {
                Result r;
                r.bitmap = std::move(b);
                r.warnings = std::move(warnings);
                keep(k, std::move(r));
              },
              failed, doc.backend_, threads, [this] { return cancel_.load(); });
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(m_);
        error_ = e.what();
      }
      std::lock_guard<std::mutex> lock(m_);
      finished_ = true;
      cv_.notify_all();
    });
  }

  ~PageStream() { stop(); }

  void stop() {
    {
      std::lock_guard<std::mutex> lock(m_);
      cancel_ = true;
      cv_.notify_all();
    }
    if (worker_.joinable()) {
      py::gil_scoped_release release;
      worker_.join();
    }
  }

  // The next page's array (a DeviceArray on the GPU); its warnings through
  // Python's warnings module.
  py::object next() {
    if (next_ >= pages_.size()) throw py::stop_iteration();
    Result r;
    for (;;) {
      bool ready = false;
      {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait_for(lock, std::chrono::milliseconds(100),
                     [&] { return done_.count(next_) || finished_ || !error_.empty(); });
        if (done_.count(next_)) {
          r = std::move(done_[next_]);
          done_.erase(next_);
          next_++;
          cv_.notify_all();
          ready = true;
        } else if (!error_.empty() || finished_) {
          ready = false;
        } else {
          lock.unlock();
          py::gil_scoped_acquire acquire;
          if (PyErr_CheckSignals() != 0) {  // Ctrl-C: cancel, then raise it
            stop();
            throw py::error_already_set();
          }
          continue;
        }
      }
      if (ready) break;
      std::string why;
      {
        std::lock_guard<std::mutex> lock(m_);
        why = error_.empty() ? "page " + std::to_string(pages_[next_] + 1) + " was not rendered" : error_;
      }
      throw mpvg::Error(why);
    }
    if (!r.error.empty()) throw mpvg::Error(r.error);
    warn_page(pages_[next_ - 1], r.warnings);
    if (r.device_bitmap.pixels) return py::cast(PyDeviceArray(std::move(r.device_bitmap)));
    return array_of(std::move(r.bitmap));
  }

 private:
  struct Result {
    mpvg::Bitmap bitmap;
    mpvg::DeviceBitmap device_bitmap;  // with device output (render_pages_device)
    std::vector<std::string> warnings;
    std::string error;
  };
  std::vector<int> pages_;
  std::mutex m_;
  std::condition_variable cv_;
  std::map<size_t, Result> done_;
  size_t next_ = 0;
  std::atomic<bool> cancel_{false};
  bool finished_ = false;
  std::string error_;
  std::thread worker_;
};

std::unique_ptr<PyDocument::PageStream> PyDocument::render_pages(
    const std::optional<std::vector<int>>& pages, double dpi, const std::string& aa, const std::string& gamma,
    const py::object& background, int bits, uint32_t seed, const std::string& box, bool annotations,
    const std::string& thin_lines, const std::string& colorspace, int threads, const std::string& device) {
  const mpvg::PdfRenderSettings s =
      settings(dpi, aa, gamma, background, bits, seed, box, annotations, thin_lines, colorspace);
  const bool gpu = device_output(device, s);
  if (gpu && backend_ == mpvg::Device::Cpu) throw py::value_error("device='cuda' needs the 'cuda' or 'auto' backend");
  std::vector<int> list;
  if (pages) {
    for (int p : *pages) list.push_back(index(p));
  } else {
    for (int p = 0; p < len(); p++) list.push_back(p);
  }
  return std::make_unique<PageStream>(*this, std::move(list), s, threads, gpu);
}

}  // namespace

PYBIND11_MODULE(_mpvg, m) {
  m.doc() =
      "mpvg: SVG documents rendered by the massively-parallel vector graphics pipeline (CPU or CUDA),\n"
      "as numpy arrays of straight-alpha sRGB RGBA pixels, the same values svg2png writes.";
  m.attr("__version__") = MPVG_VERSION;
  // mpvg.Error is a RuntimeError: unreadable files, malformed SVG, bad sizes, no CUDA device.
  auto error = py::register_exception<mpvg::Error>(m, "Error", PyExc_RuntimeError);
  // Its kinds (core/error.h), registered after it so that they are tried first.
  py::register_exception<mpvg::ParseError>(m, "ParseError", error.ptr());
  py::register_exception<mpvg::UnsupportedError>(m, "UnsupportedError", error.ptr());
  py::register_exception<mpvg::ResourceError>(m, "ResourceError", error.ptr());

  py::class_<PyRenderer>(m, "Renderer",
                         "Renders SVG documents on one backend, keeping its state (the CUDA context and device\n"
                         "buffers) from call to call.")
      .def(py::init<const std::string&>(), py::arg("backend") = "auto",
           "backend: 'auto' (CUDA when a device exists, else the CPU), 'cpu' or 'cuda' (mpvg.Error\n"
           "without a device).")
      .def_property_readonly("backend", &PyRenderer::backend, "The backend in use: 'cpu' or 'cuda'.")
      .def_property_readonly("note", &PyRenderer::note, "Why 'auto' chose the CPU, or ''.")
      .def_property_readonly("warnings", &PyRenderer::warnings,
                             "Features of the last document rendered approximately or not at all.")
      .def("render_svg", &PyRenderer::render_svg, py::arg("svg"), py::kw_only(), py::arg("width") = py::none(),
           py::arg("height") = py::none(), py::arg("zoom") = py::none(), py::arg("keep_aspect_ratio") = false,
           py::arg("aa") = "4x4x32", py::arg("gamma") = "linear", py::arg("background") = py::none(),
           py::arg("bits") = 8, py::arg("seed") = 0, py::arg("base_dir") = ".",
           py::arg("allow_read") = std::vector<std::string>{},
           "Renders an SVG document to an H x W x 4 array (uint8 for bits=8, uint16 for bits=16) of\n"
           "straight-alpha sRGB RGBA pixels.\n\n"
           "svg: a path (str or path-like) or the document itself (bytes, bytearray, memoryview).\n"
           "width, height, zoom, keep_aspect_ratio: the output size, as svg2png's -w, -h, -z, -a.\n"
           "aa: '4x4x32', '1x32' or '1x8'. gamma: 'linear' or 'srgb'. seed: sample pattern seed.\n"
           "background: None (transparent), a CSS colour or (r, g, b[, a]) in [0, 1].\n"
           "base_dir: where relative image references of a document given as bytes resolve.\n"
           "allow_read: folders whose images the document may read besides its own folder's tree.\n"
           "The GIL is released while parsing and rendering. Raises mpvg.Error on failure.");

  py::class_<PyDocument>(m, "Document",
                         "A PDF document (MuPDF interprets it), whose pages render to arrays: the pixels pdf2png\n"
                         "writes for the same options.")
      .def(py::init<const py::object&, const std::optional<std::string>&, const std::string&>(), py::arg("document"),
           py::arg("password") = py::none(), py::arg("backend") = "auto",
           "document: a path (str or path-like) or the document's bytes. password: for an encrypted one.\n"
           "backend: 'auto', 'cpu' or 'cuda', for the renderer its pages are drawn with.\n"
           "Raises mpvg.Error for an unreadable, broken or locked document.")
      .def("__len__", &PyDocument::len, "The number of pages.")
      .def("page_size", &PyDocument::page_size, py::arg("page"), py::arg("box") = "crop",
           "Width and height in points (1/72 inch) of page `page` (0-based; -1 the last) over `box`\n"
           "('media', 'crop', 'bleed', 'trim' or 'art'), after /Rotate.")
      .def_property_readonly("warnings", &PyDocument::warnings,
                             "Features of the last page rendered drawn approximately or not at all.")
      .def("render", &PyDocument::render, py::arg("page"), py::kw_only(), py::arg("dpi") = 150.0,
           py::arg("aa") = "4x4x32", py::arg("gamma") = "srgb", py::arg("background") = "white",
           py::arg("bits") = 8, py::arg("seed") = 0, py::arg("box") = "crop", py::arg("annotations") = true,
           py::arg("thin_lines") = "exact", py::arg("colorspace") = "rgb", py::arg("device") = "cpu",
           "Renders page `page` (0-based; -1 the last) to an H x W x 4 array (uint8, or uint16 for bits=16)\n"
           "of straight-alpha sRGB RGBA pixels, as pdf2png -r DPI does.\n\n"
           "aa: '4x4x32', '1x32' or '1x8'. gamma: 'srgb' (PDF's) or 'linear'. background: a CSS colour,\n"
           "(r, g, b[, a]) or None (transparent). box: the page box. annotations: draw them as printed.\n"
           "thin_lines: 'exact' or 'snap' (pdf2png --thin-lines).\n"
           "colorspace: 'rgb' (H x W x 4, RGBA), 'gray' (pdf2png -gray: H x W x 1 over an opaque\n"
           "background, H x W x 2 grey and alpha over a transparent one) or 'cmyk' (H x W x 4 ink\n"
           "amounts, 0 none to 255 full, 8 bits: pdf2png --colorspace cmyk's TIFF, overprint simulated).\n"
           "device: 'cpu' (a NumPy array) or 'cuda' (an mpvg.DeviceArray in CUDA memory, 8 bits, with\n"
           "the CUDA backend: torch.from_dlpack / cupy.asarray take it without a copy).\n"
           "The GIL is released while the page is interpreted and rendered. Raises mpvg.Error.")
      .def("render_batch", &PyDocument::render_batch, py::arg("pages") = py::none(), py::kw_only(),
           py::arg("dpi") = 150.0, py::arg("aa") = "4x4x32", py::arg("gamma") = "srgb",
           py::arg("background") = "white", py::arg("seed") = 0, py::arg("box") = "crop",
           py::arg("annotations") = true, py::arg("thin_lines") = "exact", py::arg("threads") = 0,
           "Renders `pages` (0-based; None: every page) through pdf2png's page pipeline on the CUDA\n"
           "backend into one mpvg.DeviceArray of shape N x H x W x 4 (uint8), page k of `pages` at [k]:\n"
           "one tensor for a model, never through the host. Every page must have the same pixel size.\n"
           "Raises mpvg.Error without a CUDA device, for pages of other sizes, or when a page fails.")
      .def("render_pages", &PyDocument::render_pages, py::arg("pages") = py::none(), py::kw_only(),
           py::arg("dpi") = 150.0, py::arg("aa") = "4x4x32", py::arg("gamma") = "srgb",
           py::arg("background") = "white", py::arg("bits") = 8, py::arg("seed") = 0, py::arg("box") = "crop",
           py::arg("annotations") = true, py::arg("thin_lines") = "exact", py::arg("colorspace") = "rgb",
           py::arg("threads") = 0, py::arg("device") = "cpu", py::keep_alive<0, 1>(),
           "Renders `pages` (0-based; None: every page) through pdf2png's page pipeline (worker threads\n"
           "interpreting pages while render threads render others, with CUDA on several streams) and\n"
           "returns an iterator over their arrays in the order asked, each what render() gives. A page\n"
           "that fails raises mpvg.Error when its turn comes; warnings go to Python's warnings module.\n"
           "threads: worker threads (0: one per core). device: 'cpu' (NumPy arrays) or 'cuda' (an\n"
           "mpvg.DeviceArray a page, left in CUDA memory: colorspace 'rgb', 8 bits). The GIL is released\n"
           "while it waits; Ctrl-C or dropping the iterator cancels the pages not yet started.");

  py::class_<PyDeviceArray>(m, "DeviceArray",
                            "An H x W x 4 uint8 image in CUDA memory owned by mpvg (render(..., device='cuda')),\n"
                            "exposed through DLPack and __cuda_array_interface__: torch.from_dlpack(a) or\n"
                            "cupy.asarray(a) take it without a copy. Ready on every stream when returned.")
      .def_property_readonly("shape", &PyDeviceArray::shape)
      .def_property_readonly("dtype", [](const PyDeviceArray&) { return py::dtype::of<uint8_t>(); })
      .def_property_readonly("device", &PyDeviceArray::device, "The CUDA device it is on.")
      .def_property_readonly("__cuda_array_interface__", &PyDeviceArray::cuda_array_interface)
      .def("__dlpack__", &PyDeviceArray::dlpack, py::arg("stream") = py::none())
      .def("__dlpack_device__", &PyDeviceArray::dlpack_device)
      .def("to_host", &PyDeviceArray::to_host, "A NumPy copy (what device='cpu' renders).");

  py::class_<PyCompareResult>(m, "CompareResult",
                              "What mpvg.compare found (mpvg-compare's report). True when the images pass.")
      .def_property_readonly("passed", &PyCompareResult::passed, "Equal within the thresholds (warnings pass).")
      .def("__bool__", &PyCompareResult::passed)
      .def_property_readonly("verdict", &PyCompareResult::verdict, "'PASS', 'WARNING' or 'FAILURE'.")
      .def_property_readonly("same_size", [](const PyCompareResult& r) { return r.r.same_size; })
      .def_property_readonly("pixels", [](const PyCompareResult& r) { return r.r.pixels; })
      .def_property_readonly("differing", [](const PyCompareResult& r) { return r.r.differing; },
                             "Pixels that differ at all.")
      .def_property_readonly("failed", [](const PyCompareResult& r) { return r.r.failed; },
                             "Pixels over `fail`, not forgiven.")
      .def_property_readonly("warned", [](const PyCompareResult& r) { return r.r.warned; })
      .def_property_readonly("antialiased", [](const PyCompareResult& r) { return r.r.antialiased; },
                             "Pixels over a threshold forgiven as antialiasing.")
      .def_property_readonly("max_difference", [](const PyCompareResult& r) { return r.r.max_difference; })
      .def_property_readonly("max_at", [](const PyCompareResult& r) { return py::make_tuple(r.r.max_x, r.r.max_y); },
                             "(x, y) of the largest difference.")
      .def_property_readonly("mean_difference", [](const PyCompareResult& r) { return r.r.mean_difference; })
      .def_property_readonly("rms_difference", [](const PyCompareResult& r) { return r.r.rms_difference; })
      .def_property_readonly("psnr", [](const PyCompareResult& r) { return r.r.psnr; })
      .def_property_readonly("diff", [](const PyCompareResult& r) { return r.diff; },
                             "The diff image (H x W x 4 uint8) when asked for, else None.")
      .def_property_readonly("json", [](const PyCompareResult& r) { return r.r.json; })
      .def("__repr__", &PyCompareResult::repr);

  m.def("compare", &compare_images, py::arg("a"), py::arg("b"), py::kw_only(), py::arg("fail") = 1e-6,
        py::arg("failpercent") = 0.0, py::arg("hardfail") = py::none(), py::arg("warn") = 1e-6,
        py::arg("warnpercent") = 0.0, py::arg("hardwarn") = py::none(), py::arg("antialiasing") = false,
        py::arg("aa_ring") = 0.3, py::arg("diff") = py::none(),
        "Compares two images as mpvg-compare does: arrays (H x W [x C], C 1 to 4, uint8 or uint16,\n"
        "straight alpha) or PNG paths, premultiplied, channels in [0, 1].\n\n"
        "fail, failpercent, hardfail, warn, warnpercent, hardwarn: OpenImageIO idiff's thresholds.\n"
        "antialiasing: forgive differences on antialiased edges whose surroundings are the same in\n"
        "both images (aa_ring: within two pixels of an edge, a difference up to aa_ring times the\n"
        "edge's contrast is forgiven as a wider filter's ringing).\n"
        "diff: True for the diff image in .diff, or a path to write it to as a PNG as well.\n"
        "Returns an mpvg.CompareResult, true when the images pass.");
  m.def(
      "read_png",
      [](const py::object& path) { return array_of(png_at(path)); },
      py::arg("path"), "A PNG as an H x W x 4 array of straight-alpha RGBA (uint8, or uint16 for 16 bits).");
  m.def(
      "write_png",
      [](const py::object& path, const py::object& image) {
        const std::string p = fspath(path);
        const mpvg::Bitmap b = bitmap_from_array(image, "image");
        py::gil_scoped_release release;
        mpvg::write_png(p, b);
      },
      py::arg("path"), py::arg("image"),
      "Writes an array (H x W [x C], C 1 to 4: grey, grey and alpha, RGB, RGBA; uint8 or uint16) as a PNG\n"
      "with mpvg's encoder (no varying metadata: equal pixels, equal files).");

  py::class_<PyDocument::PageStream>(m, "PageStream", "The pages of Document.render_pages, in the order asked.")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &PyDocument::PageStream::next)
      .def("close", &PyDocument::PageStream::stop, "Cancels the pages not yet started and waits for the rest.");
}
