// The extension of the Python package `mpvg` (python/mpvg/): SVG to numpy arrays through libmpvg's public
// API (include/mpvg/mpvg.h), the pixels svg2png writes for the same
// options.
//
//   import mpvg
//   r = mpvg.Renderer()                     # "auto", "cpu" or "cuda"
//   img = r.render_svg("drawing.svg", width=512)   # H x W x 4 uint8
//   img = r.render_svg(b"<svg ...>...</svg>", bits=16)  # bytes: the document itself
//   with mpvg.Document("paper.pdf") as doc:  # PyMuPDF's shape: len, [i], pages
//       img = doc[0].render(scale_to=1024)
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <chrono>
#include <condition_variable>
#include <initializer_list>
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

// A Document used after close() (mpvg.ClosedError, a ValueError as
// Python's closed files raise).
struct ClosedError : mpvg::Error {
  using mpvg::Error::Error;
};

// The exception classes of mpvg (made in PYBIND11_MODULE; never freed).
struct ErrorTypes {
  PyObject *error, *document, *parse, *password, *unsupported, *resource, *memory_limit, *option, *closed;
};
ErrorTypes errors{};

// mpvg.NAME, a subclass of `bases`, added to the module.
PyObject* new_error(py::module_& m, const char* name, const char* doc, std::initializer_list<PyObject*> bases) {
  py::tuple t(bases.size());
  size_t k = 0;
  for (PyObject* b : bases) t[k++] = py::reinterpret_borrow<py::object>(b);
  PyObject* e = PyErr_NewExceptionWithDoc((std::string("mpvg.") + name).c_str(), doc, t.ptr(), nullptr);
  if (!e) throw py::error_already_set();
  m.add_object(name, py::handle(e));
  return e;
}

// The library's failures as mpvg's exceptions, the narrowest kind first;
// the message is the one line the CLIs print.
// What a PasswordError adds for Python callers (python -m mpvg names its
// --password instead).
constexpr const char* kPasswordHint = " (give it with password=...)";

void translate_error(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const ClosedError& e) {
    PyErr_SetString(errors.closed, e.what());
  } catch (const mpvg::OptionError& e) {
    PyErr_SetString(errors.option, e.what());
  } catch (const mpvg::PasswordError& e) {
    PyErr_SetString(errors.password, (std::string(e.what()) + kPasswordHint).c_str());
  } catch (const mpvg::ParseError& e) {
    PyErr_SetString(errors.parse, e.what());
  } catch (const mpvg::MemoryLimitError& e) {
    PyErr_SetString(errors.memory_limit, e.what());
  } catch (const mpvg::ResourceError& e) {
    PyErr_SetString(errors.resource, e.what());
  } catch (const mpvg::UnsupportedError& e) {
    PyErr_SetString(errors.unsupported, e.what());
  } catch (const mpvg::Error& e) {
    PyErr_SetString(errors.error, e.what());
  } catch (const std::bad_alloc&) {
    // core/error.h's error_message for it, as the CLIs print it.
    PyErr_SetString(errors.memory_limit,
                    "out of memory: the document needs more than this machine could give (see max_memory)");
  }
}

mpvg::Device device_named(const std::string& s) {
  if (s == "auto") return mpvg::Device::Auto;
  if (s == "cpu") return mpvg::Device::Cpu;
  if (s == "cuda") return mpvg::Device::Cuda;
  throw mpvg::OptionError("unknown backend '" + s + "' (auto, cpu or cuda)");
}

mpvg::Antialiasing antialiasing_named(const std::string& s) {
  if (s == "1x8") return mpvg::Antialiasing::Box1x8;
  if (s == "1x32") return mpvg::Antialiasing::Box1x32;
  if (s == "4x4x32") return mpvg::Antialiasing::Cardinal4x4x32;
  throw mpvg::OptionError("unknown antialiasing mode '" + s + "' (1x8, 1x32 or 4x4x32)");
}

mpvg::GammaMode gamma_named(const std::string& s) {
  if (s == "linear") return mpvg::GammaMode::Linear;
  if (s == "srgb") return mpvg::GammaMode::Srgb;
  throw mpvg::OptionError("unknown gamma '" + s + "' (linear or srgb)");
}

// None (transparent), a CSS colour, or (r, g, b[, a]) in [0, 1].
mpvg::Color color_from(const py::object& bg) {
  if (bg.is_none()) return {};
  if (py::isinstance<py::str>(bg)) return mpvg::Color::parse(bg.cast<std::string>());
  const std::vector<float> c = bg.cast<std::vector<float>>();
  if (c.size() != 3 && c.size() != 4)
    throw mpvg::OptionError("background takes a CSS colour or (r, g, b[, a]) with components in [0, 1]");
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
  throw mpvg::OptionError("unknown output device '" + device + "' (cpu or cuda)");
}

// A str or path-like object as a path (os.fspath).
std::string fspath(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

// The document a call takes, by one rule everywhere (the docstrings'
// "Input rule"): an os.PathLike, or a str that is a path, names a file;
// bytes, bytearray, memoryview (any 1-D byte buffer) or an object with
// .read() (an open binary file, io.BytesIO) is the document's data; a str
// whose first character after whitespace is '<' is SVG text (no path
// starts so; the resvg-py and PyMuPDF habit of passing the text itself);
// `data=` names the data explicitly (bytes-like or str). `what` names the
// data and `usage` says what is taken, in the TypeErrors.
struct Input {
  std::optional<std::string> path, data;
  bool text = false;  // data came as a str beginning with '<'
};

// Bytes of a buffer, a str (UTF-8) or what .read() returns.
std::optional<std::string> bytes_of(const py::object& o, const std::string& what) {
  if (py::isinstance<py::bytes>(o)) return o.cast<std::string>();
  if (py::isinstance<py::str>(o)) return o.cast<std::string>();
  if (PyObject_CheckBuffer(o.ptr())) {
    const py::buffer_info b = py::reinterpret_borrow<py::buffer>(o).request();
    if (b.ndim != 1 || b.itemsize != 1) throw py::type_error(what + " must be a one-dimensional buffer of bytes");
    return std::string(static_cast<const char*>(b.ptr), static_cast<size_t>(b.size));
  }
  return std::nullopt;
}

bool looks_like_markup(const std::string& s) {
  const size_t at = s.find_first_not_of(" \t\r\n\f\v\xef\xbb\xbf");  // (a UTF-8 byte order mark too)
  return at != std::string::npos && s[at] == '<';
}

Input input_from(const py::object& input, const py::object& data, const std::string& what, const char* usage) {
  Input in;
  if (!data.is_none()) {
    if (!input.is_none()) throw mpvg::OptionError("give the document or data=, not both");
    in.data = bytes_of(data, what);
    if (!in.data) throw py::type_error("data= takes " + what + " as bytes, bytearray, memoryview or str");
    return in;
  }
  if (input.is_none()) throw py::type_error(usage);
  if (py::isinstance<py::str>(input)) {
    std::string s = input.cast<std::string>();
    if (looks_like_markup(s)) {
      in.data = std::move(s);
      in.text = true;
    } else {
      in.path = std::move(s);
    }
  } else if (py::hasattr(input, "__fspath__")) {
    in.path = fspath(input);
  } else if (std::optional<std::string> b = bytes_of(input, what); b && !py::isinstance<py::str>(input)) {
    in.data = std::move(b);
  } else if (py::hasattr(input, "read")) {
    const py::object got = input.attr("read")();
    in.data = py::isinstance<py::str>(got) ? std::optional<std::string>(got.cast<std::string>()) : bytes_of(got, what);
    if (!in.data) throw py::type_error(std::string(usage) + ": its read() returned neither bytes nor str");
  } else {
    throw py::type_error(usage);
  }
  return in;
}

// Folders given as one str / path-like or a sequence of them.
std::vector<std::string> folders(const py::object& o) {
  std::vector<std::string> out;
  if (o.is_none()) return out;
  if (py::isinstance<py::str>(o) || py::hasattr(o, "__fspath__")) return {fspath(o)};
  for (const py::handle& d : o) out.push_back(fspath(py::reinterpret_borrow<py::object>(d)));
  return out;
}

// Language tags as a sequence of str, or one str of comma-separated tags
// (svg2png --languages en-US,de).
std::vector<std::string> language_tags(const py::object& o) {
  std::vector<std::string> tags;
  auto add = [&](std::string list) {
    for (size_t pos = 0; pos <= list.size();) {
      const size_t end = std::min(list.find(',', pos), list.size());
      std::string tag = list.substr(pos, end - pos);
      tag.erase(0, tag.find_first_not_of(' '));
      tag.erase(tag.find_last_not_of(' ') + 1);
      if (!tag.empty()) tags.push_back(tag);
      pos = end + 1;
    }
  };
  if (py::isinstance<py::str>(o)) add(o.cast<std::string>());
  else
    for (const py::handle& t : o) add(py::str(t).cast<std::string>());
  if (tags.empty()) throw mpvg::OptionError("languages needs a list of language tags, e.g. ['en-US', 'de']");
  return tags;
}

// A memory size: bytes (int) or svg2png --max-memory's text ("512M", "4G",
// "1.5GiB": binary units). None: 0, the default budget.
uint64_t memory_size(const py::object& o) {
  if (o.is_none()) return 0;
  if (!py::isinstance<py::str>(o)) {
    const long long n = o.cast<long long>();
    if (n <= 0) throw mpvg::OptionError("max_memory must be a positive number of bytes");
    return static_cast<uint64_t>(n);
  }
  const std::string v = o.cast<std::string>();
  size_t used = 0;
  double n = 0;
  try {
    n = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = v.substr(used);
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'b') unit.pop_back();
  if (unit.size() > 1 && unit.back() == 'i') unit.pop_back();
  const std::string units = "kmgt";
  const size_t at = unit.empty() ? std::string::npos : units.find(unit);
  if (used == 0 || !(n > 0) || !std::isfinite(n) || (!unit.empty() && (unit.size() != 1 || at == std::string::npos)))
    throw mpvg::OptionError("max_memory expects a size such as 512M or 4G, got '" + v + "'");
  const double bytes = n * std::pow(1024.0, unit.empty() ? 0 : double(at + 1));
  if (bytes >= 1.8e19) throw mpvg::OptionError("max_memory is too large: '" + v + "'");
  return static_cast<uint64_t>(bytes);
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
    throw mpvg::OptionError(std::string(what) + " must be H x W or H x W x C (C 1 to 4)");
  mpvg::Bitmap b;
  b.height = static_cast<int>(a.shape(0));
  b.width = static_cast<int>(a.shape(1));
  b.channels = a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 1;
  if (b.channels < 1 || b.channels > 4) throw mpvg::OptionError(std::string(what) + " must have 1 to 4 channels");
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

  py::array render_svg(const py::object& input, const py::object& data_arg, std::optional<double> width,
                       std::optional<double> height, std::optional<double> zoom, bool keep_aspect_ratio,
                       const std::string& aa, const std::string& gamma, const py::object& background, int bits,
                       uint32_t seed, const py::object& base_dir_arg, const py::object& allow_read_arg,
                       const py::object& font_dir, const py::object& languages, const py::object& max_memory) {
    const Input in = input_from(input, data_arg, "SVG data",
                                "render_svg takes a path (str or path-like), SVG text (a str starting with '<'), "
                                "the document's bytes or a file object");
    const std::string base_dir = fspath(base_dir_arg);
    const std::vector<std::string> allow_read = folders(allow_read_arg);
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
    s.font_dirs = folders(font_dir);
    if (!languages.is_none()) s.languages = language_tags(languages);
    s.max_memory = memory_size(max_memory);

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
  throw mpvg::OptionError("unknown page box '" + s + "' (media, crop, bleed, trim or art)");
}


// mpvg.Document: a PDF document and the renderer its pages are drawn with
// (made on the first render, on `backend`), in PyMuPDF's shape: a context
// manager, len(doc), doc[i] and iteration giving mpvg.Page objects,
// close() (after which every use raises mpvg.ClosedError). Calls from
// several Python threads take turns.
class PyDocument {
 public:
  PyDocument(const py::object& input, const std::optional<std::string>& password, const std::string& backend,
             const py::object& data)
      : backend_(device_named(backend)) {
    const Input in = input_from(input, data, "PDF data",
                                "Document takes a path (str or path-like), the document's bytes or a file object");
    if (in.text)
      throw mpvg::UnsupportedError("Document opens PDF documents: render SVG text with Renderer.render_svg");
    name_ = in.path ? *in.path : std::string();
    const std::string pw = password.value_or("");
    py::gil_scoped_release release;
    doc_ = std::make_shared<mpvg::PdfDocument>(in.path ? mpvg::PdfDocument::from_file(*in.path, pw)
                                                       : mpvg::PdfDocument::from_data(*in.data, pw));
  }

  // The open document (with the GIL held), or ClosedError.
  const std::shared_ptr<mpvg::PdfDocument>& doc() const {
    if (!doc_) throw ClosedError("the document is closed");
    return doc_;
  }

  // Closes the document and frees its renderer; pages that render_pages
  // streams already are rendered with the handle they hold. Idempotent.
  void close() {
    std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
    {
      py::gil_scoped_release release;  // a render on another thread holds the lock while it waits for the GIL
      lock.lock();
    }
    doc_.reset();
    renderer_.reset();
  }
  bool closed() const { return !doc_; }
  const std::string& name() const { return name_; }

  int len() const { return doc()->page_count(); }

  int index(int page) const {
    const int n = len();
    const int asked = page;
    if (page < 0) page += n;  // -1: the last page, as Python indexes
    if (page < 0 || page >= n)
      throw py::index_error("page " + std::to_string(asked) + " out of range (" + std::to_string(n) + " pages)");
    return page;
  }

  std::pair<double, double> page_size(int page, const std::string& box) const {
    return doc()->page_size(index(page), box_named(box));
  }

  std::vector<std::string> warnings() const { return doc()->warnings(); }

  std::string repr() const {
    if (!doc_) return "<mpvg.Document (closed)>";
    const int n = doc_->page_count();
    return "<mpvg.Document " + (name_.empty() ? std::string("from data") : "'" + name_ + "'") + ", " +
           std::to_string(n) + (n == 1 ? " page>" : " pages>");
  }

  // The output size: dpi (and dpi_y, pdftoppm's -ry), or scale_to (the
  // longer side, pdftoppm -scale-to), or width and/or height: one alone
  // keeps the aspect ratio (-scale-to-x W -scale-to-y -1), both stretch
  // (-scale-to-x W -scale-to-y H).
  static void size_settings(mpvg::PdfRenderSettings& s, double dpi, std::optional<double> dpi_y,
                            std::optional<int> scale_to, std::optional<int> width, std::optional<int> height) {
    s.dpi = dpi;
    s.dpi_y = dpi_y.value_or(0);
    if (dpi_y && !(*dpi_y > 0)) throw mpvg::OptionError("dpi_y must be positive");
    auto pixels = [](std::optional<int> v, const char* what) {
      if (v && (*v < 1 || *v > (1 << 20)))
        throw mpvg::OptionError(std::string(what) + " must be a number of pixels from 1 to 1048576");
    };
    pixels(scale_to, "scale_to");
    pixels(width, "width");
    pixels(height, "height");
    if (scale_to && (width || height)) throw mpvg::OptionError("scale_to cannot be given with width or height");
    if (scale_to) s.scale_to = *scale_to;
    if (width) s.scale_to_x = *width, s.scale_to_y = height ? *height : -1;
    else if (height) s.scale_to_y = *height, s.scale_to_x = -1;
  }

  static mpvg::PdfRenderSettings settings(double dpi, std::optional<double> dpi_y, std::optional<int> scale_to,
                                          std::optional<int> width, std::optional<int> height, const std::string& aa,
                                          const std::string& gamma, const py::object& background, int bits,
                                          uint32_t seed, const std::string& box, bool annotations,
                                          const std::string& thin_lines, const std::string& colorspace,
                                          const py::object& max_memory) {
    const mpvg::OutputColorSpace space = colorspace == "rgb"    ? mpvg::OutputColorSpace::Rgb
                                         : colorspace == "gray" ? mpvg::OutputColorSpace::Gray
                                         : colorspace == "cmyk" ? mpvg::OutputColorSpace::Cmyk
                                                                : throw mpvg::OptionError("unknown colorspace '" +
                                                                                          colorspace +
                                                                                          "' (rgb, gray or cmyk)");
    if (space == mpvg::OutputColorSpace::Cmyk && bits != 8) throw mpvg::OptionError("colorspace 'cmyk' renders 8 bits");
    if (thin_lines != "exact" && thin_lines != "snap")
      throw mpvg::OptionError("unknown thin_lines '" + thin_lines + "' (exact or snap)");
    mpvg::PdfRenderSettings s;
    size_settings(s, dpi, dpi_y, scale_to, width, height);
    s.antialiasing = antialiasing_named(aa);
    s.gamma = gamma_named(gamma);
    s.background = background.is_none() ? mpvg::Color{} : color_from(background);
    s.bits = bits;
    s.seed = seed;
    s.box = box_named(box);
    s.annotations = annotations;
    s.snap_thin_lines = thin_lines == "snap";
    s.colorspace = space;
    s.max_memory = memory_size(max_memory);
    return s;
  }

  py::object render(int page, double dpi, std::optional<double> dpi_y, std::optional<int> scale_to,
                    std::optional<int> width, std::optional<int> height, const std::string& aa,
                    const std::string& gamma, const py::object& background, int bits, uint32_t seed,
                    const std::string& box, bool annotations, const std::string& thin_lines,
                    const std::string& colorspace, const py::object& max_memory, const std::string& device) {
    const mpvg::PdfRenderSettings s = settings(dpi, dpi_y, scale_to, width, height, aa, gamma, background, bits, seed,
                                               box, annotations, thin_lines, colorspace, max_memory);
    const std::shared_ptr<mpvg::PdfDocument> doc = this->doc();
    const int i = index(page);
    const bool gpu = device_output(device, s);
    mpvg::Bitmap image;
    mpvg::DeviceBitmap on_gpu;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      if (!doc_) throw ClosedError("the document is closed");
      if (!renderer_) renderer_ = std::make_unique<mpvg::Renderer>(backend_);
      if (gpu) on_gpu = renderer_->render_device(*doc, i, s);
      else image = renderer_->render(*doc, i, s);
    }
    warn_page(i, doc->warnings());  // (also in .warnings)
    if (gpu) return py::cast(PyDeviceArray(std::move(on_gpu)));
    return array_of(std::move(image));
  }

  std::vector<int> page_list(const std::optional<std::vector<int>>& pages) const {
    std::vector<int> list;
    if (pages) {
      for (int p : *pages) list.push_back(index(p));
    } else {
      for (int p = 0, n = len(); p < n; p++) list.push_back(p);
    }
    return list;
  }

  py::object render_batch(const std::optional<std::vector<int>>& pages, double dpi, std::optional<double> dpi_y,
                          std::optional<int> scale_to, std::optional<int> width, std::optional<int> height,
                          const std::string& aa, const std::string& gamma, const py::object& background,
                          uint32_t seed, const std::string& box, bool annotations, const std::string& thin_lines,
                          int threads) {
    const mpvg::PdfRenderSettings s = settings(dpi, dpi_y, scale_to, width, height, aa, gamma, background, 8, seed,
                                               box, annotations, thin_lines, "rgb", py::none());
    const std::shared_ptr<mpvg::PdfDocument> doc = this->doc();
    const std::vector<int> list = page_list(pages);
    mpvg::DeviceBitmap b;
    {
      py::gil_scoped_release release;
      b = doc->render_batch(list, s, threads);
    }
    return py::cast(PyDeviceArray(std::move(b), static_cast<int>(list.size())));
  }

  // Is `device` the GPU (on_device) for a page rendered with s? Device output is 8-bit
  // RGBA.
  static bool device_output(const std::string& device, const mpvg::PdfRenderSettings& s) {
    const bool gpu = on_device(device);
    if (gpu && (s.colorspace != mpvg::OutputColorSpace::Rgb || s.bits != 8))
      throw mpvg::OptionError("device='cuda' renders 8-bit RGBA (colorspace='rgb', bits=8)");
    return gpu;
  }

  class PageStream;
  std::unique_ptr<PageStream> render_pages(const std::optional<std::vector<int>>& pages, double dpi,
                                           std::optional<double> dpi_y, std::optional<int> scale_to,
                                           std::optional<int> width, std::optional<int> height,
                                           const std::string& aa, const std::string& gamma,
                                           const py::object& background, int bits, uint32_t seed,
                                           const std::string& box, bool annotations, const std::string& thin_lines,
                                           const std::string& colorspace, const py::object& max_memory, int threads,
                                           const std::string& device);

  mpvg::Device backend_;

 private:
  std::shared_ptr<mpvg::PdfDocument> doc_;  // null once closed
  std::string name_;                         // the path it was opened from, or ""
  std::mutex mutex_;
  std::unique_ptr<mpvg::Renderer> renderer_;
};

// mpvg.Page: page `number` (0-based) of a Document (doc[i], iteration),
// which it keeps alive; what it does, it asks of the document.
class PyPage {
 public:
  PyPage(py::object doc, int number) : doc_(std::move(doc)), number_(number) {}
  PyDocument& doc() const { return doc_.cast<PyDocument&>(); }
  int number() const { return number_; }
  const py::object& parent() const { return doc_; }
  std::pair<double, double> size(const std::string& box) const { return doc().page_size(number_, box); }
  py::tuple rect() const {
    const auto [w, h] = size("crop");
    return py::make_tuple(0.0, 0.0, w, h);
  }
  std::string repr() const {
    if (doc().closed()) return "<mpvg.Page " + std::to_string(number_) + " of a closed document>";
    const auto [w, h] = size("crop");
    char b[96];
    std::snprintf(b, sizeof b, "<mpvg.Page %d: %g x %g pt>", number_, w, h);
    return b;
  }

 private:
  py::object doc_;
  int number_;
};

// doc[i]: the Page (negative i from the end; IndexError past either end).
py::object page_of(const py::object& self, int i) {
  return py::cast(PyPage(self, self.cast<PyDocument&>().index(i)));
}

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

  // doc: the document's handle, held while pages stream (close() leaves
  // them going).
  PageStream(std::shared_ptr<const mpvg::PdfDocument> doc, mpvg::Device backend, std::vector<int> pages,
             mpvg::PdfRenderSettings settings, int threads, bool on_gpu)
      : pages_(std::move(pages)) {
    worker_ = std::thread([this, doc, backend, settings, threads, on_gpu] {
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
          doc->render_pages_device(
              pages_, settings,
              [&](size_t k, mpvg::DeviceBitmap&& b, std::vector<std::string>&& warnings) {
                Result r;
                r.device_bitmap = std::move(b);
                r.warnings = std::move(warnings);
                keep(k, std::move(r));
              },
              failed, threads, [this] { return cancel_.load(); });
        else
          doc->render_pages(
              pages_, settings,
              [&](size_t k, mpvg::Bitmap&& b, std::vector<std::string>&& warnings) {
                Result r;
                r.bitmap = std::move(b);
                r.warnings = std::move(warnings);
                keep(k, std::move(r));
              },
              failed, backend, threads, [this] { return cancel_.load(); });
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
    const std::optional<std::vector<int>>& pages, double dpi, std::optional<double> dpi_y,
    std::optional<int> scale_to, std::optional<int> width, std::optional<int> height, const std::string& aa,
    const std::string& gamma, const py::object& background, int bits, uint32_t seed, const std::string& box,
    bool annotations, const std::string& thin_lines, const std::string& colorspace, const py::object& max_memory,
    int threads, const std::string& device) {
  const mpvg::PdfRenderSettings s = settings(dpi, dpi_y, scale_to, width, height, aa, gamma, background, bits, seed,
                                             box, annotations, thin_lines, colorspace, max_memory);
  const bool gpu = device_output(device, s);
  if (gpu && backend_ == mpvg::Device::Cpu)
    throw mpvg::OptionError("device='cuda' needs the 'cuda' or 'auto' backend");
  return std::make_unique<PageStream>(doc(), backend_, page_list(pages), s, threads, gpu);
}

}  // namespace

// The input rule, said in every docstring that takes a document.
#define MPVG_INPUT_RULE                                                                                        \
  "Input rule (the same wherever a document is taken): an os.PathLike, or a str that is a path,\n"           \
  "names a file; bytes, bytearray, memoryview or an object with .read() (an open binary file,\n"            \
  "io.BytesIO) is the document's data; a str whose first character after whitespace is '<' is\n"           \
  "SVG text; data= gives the data explicitly (bytes-like or str).\n"

// The size and rendering arguments every PDF render takes, and their text.
#define MPVG_PDF_SIZE_ARGS                                                                                    \
  py::arg("dpi") = 150.0, py::arg("dpi_y") = py::none(), py::arg("scale_to") = py::none(),                  \
      py::arg("width") = py::none(), py::arg("height") = py::none()
#define MPVG_PDF_SIZE_DOC                                                                                     \
  "Size (pdf2png's, as pdftoppm's options): dpi (-r; dpi_y, -ry, the vertical one where it differs),\n"     \
  "or scale_to=N (-scale-to N: the longer side N pixels, the aspect ratio kept), or width= and/or\n"        \
  "height= in pixels: one alone keeps the aspect ratio (-scale-to-x W -scale-to-y -1), both\n"              \
  "stretch the page to exactly that size (-scale-to-x W -scale-to-y H).\n"
#define MPVG_PDF_RENDER_DOC                                                                                   \
  "aa: '4x4x32', '1x32' or '1x8'. gamma: 'srgb' (PDF's) or 'linear'. background: a CSS colour,\n"          \
  "(r, g, b[, a]) or None (transparent). bits: 8 or 16. seed: the sample pattern's.\n"                       \
  "box: the page box ('media', 'crop', 'bleed', 'trim' or 'art'). annotations: draw them as printed.\n"     \
  "thin_lines: 'exact' or 'snap' (pdf2png --thin-lines).\n"                                                  \
  "colorspace: 'rgb' (H x W x 4, RGBA), 'gray' (pdf2png -gray: H x W x 1 over an opaque\n"                   \
  "background, H x W x 2 grey and alpha over a transparent one) or 'cmyk' (H x W x 4 ink\n"                 \
  "amounts, 0 none to 255 full, 8 bits: pdf2png --colorspace cmyk's TIFF, overprint simulated).\n"          \
  "max_memory: the page's memory budget, bytes or '512M' / '4G' (pdf2png --max-memory; None: half\n"        \
  "the machine's); past it mpvg.MemoryLimitError.\n"                                                         \
  "device: 'cpu' (a NumPy array) or 'cuda' (an mpvg.DeviceArray in CUDA memory, 8 bits, with\n"             \
  "the CUDA backend: torch.from_dlpack / cupy.asarray take it without a copy).\n"

PYBIND11_MODULE(_mpvg, m) {
  m.doc() =
      "mpvg: SVG and PDF documents rendered by the massively-parallel vector graphics pipeline (CPU or\n"
      "CUDA), as numpy arrays of straight-alpha sRGB RGBA pixels, the same values svg2png and pdf2png write.";
  m.attr("__version__") = MPVG_VERSION;

  // The exceptions (python/mpvg/__init__.py's docstring draws the tree).
  // Error stays a RuntimeError, as it was; OptionError and ClosedError are
  // ValueErrors too (bad arguments; a closed document, as closed files
  // raise), MemoryLimitError a MemoryError.
  errors.error = new_error(m, "Error", "Base of mpvg's errors; its message is the one line svg2png or pdf2png prints.",
                           {PyExc_RuntimeError});
  errors.document = new_error(m, "DocumentError", "The document cannot be opened or read (base of ParseError and PasswordError).",
                              {errors.error});
  errors.parse = new_error(m, "ParseError", "The document is malformed (XML, PDF syntax, an invalid root or page).",
                           {errors.document});
  errors.password = new_error(m, "PasswordError",
                              "The PDF is encrypted and no password, or a wrong one, was given (password=).",
                              {errors.document});
  errors.unsupported = new_error(m, "UnsupportedError",
                                 "Valid, but beyond this build or backend (no PDF support, device output without CUDA).",
                                 {errors.error});
  errors.resource = new_error(m, "ResourceError",
                              "The input or the machine falls short (an unreadable file, input or memory limits, no\n"
                              "CUDA device).",
                              {errors.error});
  errors.memory_limit = new_error(m, "MemoryLimitError",
                                  "The render needs more memory than its budget (max_memory) or the machine has.",
                                  {errors.resource, PyExc_MemoryError});
  errors.option = new_error(m, "OptionError", "An argument out of range, unknown, or not to be given with another one.",
                            {errors.error, PyExc_ValueError});
  errors.closed = new_error(m, "ClosedError", "The Document was closed.", {errors.error, PyExc_ValueError});
  py::register_exception_translator(&translate_error);

  // Classes that methods of others return, declared first so that their
  // signatures name them (mpvg._mpvg.Page, not the C++ type); their
  // methods are added below.
  py::class_<PyPage> page(m, "Page",
                          "A page of an mpvg.Document (doc[i], `for page in doc`), which it keeps open: its number,\n"
                          "its size in points, and render().");
  py::class_<PyDeviceArray> device_array(
      m, "DeviceArray",
      "An H x W x 4 uint8 image in CUDA memory owned by mpvg (render(..., device='cuda')),\n"
      "exposed through DLPack and __cuda_array_interface__: torch.from_dlpack(a) or\n"
      "cupy.asarray(a) take it without a copy. Ready on every stream when returned.");
  py::class_<PyCompareResult> compare_result(m, "CompareResult",
                                             "What mpvg.compare found (mpvg-compare's report). True when the images pass.");
  py::class_<PyDocument::PageStream> page_stream(m, "PageStream",
                                                 "The pages of Document.render_pages, in the order asked.");

  py::class_<PyRenderer>(m, "Renderer",
                         "Renders SVG documents on one backend, keeping its state (the CUDA context and device\n"
                         "buffers) from call to call. One per thread or worker: calls on one Renderer take turns.")
      .def(py::init<const std::string&>(), py::arg("backend") = "auto",
           "backend: 'auto' (CUDA when a device exists, else the CPU), 'cpu' or 'cuda' (mpvg.Error\n"
           "without a device).")
      .def_property_readonly("backend", &PyRenderer::backend, "The backend in use: 'cpu' or 'cuda'.")
      .def_property_readonly("note", &PyRenderer::note, "Why 'auto' chose the CPU, or ''.")
      .def_property_readonly("warnings", &PyRenderer::warnings,
                             "Features of the last document rendered approximately or not at all.")
      .def("render_svg", &PyRenderer::render_svg, py::arg("svg") = py::none(), py::kw_only(),
           py::arg("data") = py::none(), py::arg("width") = py::none(), py::arg("height") = py::none(),
           py::arg("zoom") = py::none(), py::arg("keep_aspect_ratio") = false, py::arg("aa") = "4x4x32",
           py::arg("gamma") = "linear", py::arg("background") = py::none(), py::arg("bits") = 8,
           py::arg("seed") = 0, py::arg("base_dir") = ".", py::arg("allow_read") = py::none(),
           py::arg("font_dir") = py::none(), py::arg("languages") = py::none(), py::arg("max_memory") = py::none(),
           "Renders an SVG document to an H x W x 4 array (uint8 for bits=8, uint16 for bits=16) of\n"
           "straight-alpha sRGB RGBA pixels: the pixels svg2png writes with the same options.\n\n"
           "svg: the document. " MPVG_INPUT_RULE
           "width, height, zoom, keep_aspect_ratio: the output size, as svg2png's -w, -h, -z, -a.\n"
           "aa: '4x4x32', '1x32' or '1x8'. gamma: 'linear' or 'srgb'. seed: sample pattern seed.\n"
           "background: None (transparent), a CSS colour or (r, g, b[, a]) in [0, 1].\n"
           "base_dir: where relative references of a document given as data resolve (a file's: its folder).\n"
           "allow_read: folders (a list, or one) whose files the document may read besides its own\n"
           "folder's tree (svg2png --allow-read).\n"
           "font_dir: folders (a list, or one) of fonts for <text>, before the system's (--font-dir).\n"
           "languages: the user's languages for systemLanguage, ['en-US', 'de'] or 'en-US,de'\n"
           "(--languages; default ['en']).\n"
           "max_memory: the render's memory budget, bytes or '512M' / '4G' (--max-memory; None: half\n"
           "the machine's); past it mpvg.MemoryLimitError.\n"
           "The GIL is released while parsing and rendering. Raises mpvg.ParseError for a malformed\n"
           "document, mpvg.ResourceError for an unreadable one, mpvg.OptionError for bad arguments.");

  py::class_<PyDocument>(m, "Document",
                         "A PDF document (MuPDF interprets it), in PyMuPDF's shape: `with mpvg.Document(p) as doc`,\n"
                         "len(doc), doc[i] (an mpvg.Page; negative from the end), `for page in doc`, doc.close().\n"
                         "Its pages render to arrays: the pixels pdf2png writes for the same options. Once closed,\n"
                         "every use raises mpvg.ClosedError.")
      .def(py::init<const py::object&, const std::optional<std::string>&, const std::string&, const py::object&>(),
           py::arg("document") = py::none(), py::arg("password") = py::none(), py::arg("backend") = "auto",
           py::kw_only(), py::arg("data") = py::none(),
           "document: the PDF. " MPVG_INPUT_RULE
           "(SVG text is refused with mpvg.UnsupportedError: Renderer.render_svg renders it.)\n"
           "password: for an encrypted one. backend: 'auto', 'cpu' or 'cuda', for the renderer its\n"
           "pages are drawn with.\n"
           "Raises mpvg.PasswordError (encrypted: no password or a wrong one), mpvg.ParseError (broken),\n"
           "mpvg.ResourceError (unreadable).")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyDocument& d, const py::args&) { d.close(); return false; },
           "Closes the document (exceptions go on).")
      .def("close", &PyDocument::close,
           "Closes the document and frees its renderer. Afterwards every use raises mpvg.ClosedError;\n"
           "render_pages streams already running finish with the handle they hold.")
      .def_property_readonly("is_closed", &PyDocument::closed, "Whether close() was called.")
      .def_property_readonly("name", &PyDocument::name, "The path it was opened from, or '' for data.")
      .def("__len__", &PyDocument::len, "The number of pages.")
      .def_property_readonly("page_count", &PyDocument::len, "The number of pages (PyMuPDF's name).")
      .def("__getitem__", &page_of, py::arg("index"),
           "Page `index` (0-based; negative from the end) as an mpvg.Page; IndexError past either end.")
      .def("load_page", &page_of, py::arg("index"), "doc[index] (PyMuPDF's name).")
      .def(
          "__iter__",
          [](py::object self) {
            PyDocument& d = self.cast<PyDocument&>();
            py::list pages;
            for (int i = 0, n = d.len(); i < n; i++) pages.append(py::cast(PyPage(self, i)));
            return py::iter(pages);
          },
          "The pages, first to last, as mpvg.Page objects.")
      .def("__repr__", &PyDocument::repr)
      .def("page_size", &PyDocument::page_size, py::arg("page"), py::arg("box") = "crop",
           "Width and height in points (1/72 inch) of page `page` (0-based; -1 the last) over `box`\n"
           "('media', 'crop', 'bleed', 'trim' or 'art'), after /Rotate.")
      .def_property_readonly("warnings", &PyDocument::warnings,
                             "Features of the last page rendered drawn approximately or not at all.")
      .def("render", &PyDocument::render, py::arg("page"), py::kw_only(), MPVG_PDF_SIZE_ARGS,
           py::arg("aa") = "4x4x32", py::arg("gamma") = "srgb", py::arg("background") = "white",
           py::arg("bits") = 8, py::arg("seed") = 0, py::arg("box") = "crop", py::arg("annotations") = true,
           py::arg("thin_lines") = "exact", py::arg("colorspace") = "rgb", py::arg("max_memory") = py::none(),
           py::arg("device") = "cpu",
           "Renders page `page` (0-based; -1 the last) to an H x W x 4 array (uint8, or uint16 for bits=16)\n"
           "of straight-alpha sRGB RGBA pixels: the pixels pdf2png writes with the same options.\n\n"
           MPVG_PDF_SIZE_DOC MPVG_PDF_RENDER_DOC
           "The GIL is released while the page is interpreted and rendered. Raises mpvg.Error.")
      .def("render_batch", &PyDocument::render_batch, py::arg("pages") = py::none(), py::kw_only(),
           MPVG_PDF_SIZE_ARGS, py::arg("aa") = "4x4x32", py::arg("gamma") = "srgb",
           py::arg("background") = "white", py::arg("seed") = 0, py::arg("box") = "crop",
           py::arg("annotations") = true, py::arg("thin_lines") = "exact", py::arg("threads") = 0,
           "Renders `pages` (0-based; None: every page) through pdf2png's page pipeline on the CUDA\n"
           "backend into one mpvg.DeviceArray of shape N x H x W x 4 (uint8), page k of `pages` at [k]:\n"
           "one tensor for a model, never through the host. Every page must have the same pixel size\n"
           "(scale_to or width and height give every page one). Other arguments as render().\n"
           "Raises mpvg.Error without a CUDA device, for pages of other sizes, or when a page fails.")
      .def("render_pages", &PyDocument::render_pages, py::arg("pages") = py::none(), py::kw_only(),
           MPVG_PDF_SIZE_ARGS, py::arg("aa") = "4x4x32", py::arg("gamma") = "srgb",
           py::arg("background") = "white", py::arg("bits") = 8, py::arg("seed") = 0, py::arg("box") = "crop",
           py::arg("annotations") = true, py::arg("thin_lines") = "exact", py::arg("colorspace") = "rgb",
           py::arg("max_memory") = py::none(), py::arg("threads") = 0, py::arg("device") = "cpu",
           py::keep_alive<0, 1>(),
           "Renders `pages` (0-based; None: every page) through pdf2png's page pipeline (worker threads\n"
           "interpreting pages while render threads render others, with CUDA on several streams) and\n"
           "returns an iterator over their arrays in the order asked, each what render() gives with the\n"
           "same arguments. A page that fails raises mpvg.Error when its turn comes; warnings go to\n"
           "Python's warnings module. threads: worker threads (0: one per core). device: 'cpu' (NumPy\n"
           "arrays) or 'cuda' (an mpvg.DeviceArray a page, left in CUDA memory: colorspace 'rgb', 8 bits).\n"
           "The GIL is released while it waits; Ctrl-C or dropping the iterator cancels the pages not yet\n"
           "started.");

  page.def_property_readonly("number", &PyPage::number, "The page's index in the document, 0-based (PyMuPDF's).")
      .def_property_readonly("parent", &PyPage::parent, "The Document it belongs to.")
      .def_property_readonly(
          "size", [](const PyPage& p) { return p.size("crop"); },
          "(width, height) in points (1/72 inch) of the crop box, after /Rotate: what render() covers.")
      .def_property_readonly("rect", &PyPage::rect, "(0, 0, width, height) in points, as PyMuPDF's page.rect.")
      .def("box_size", &PyPage::size, py::arg("box") = "crop",
           "(width, height) in points of the page box `box` ('media', 'crop', 'bleed', 'trim' or 'art').")
      .def(
          "render",
          [](const PyPage& p, double dpi, std::optional<double> dpi_y, std::optional<int> scale_to,
             std::optional<int> width, std::optional<int> height, const std::string& aa, const std::string& gamma,
             const py::object& background, int bits, uint32_t seed, const std::string& box, bool annotations,
             const std::string& thin_lines, const std::string& colorspace, const py::object& max_memory,
             const std::string& device) {
            return p.doc().render(p.number(), dpi, dpi_y, scale_to, width, height, aa, gamma, background, bits, seed,
                                  box, annotations, thin_lines, colorspace, max_memory, device);
          },
          py::kw_only(), MPVG_PDF_SIZE_ARGS, py::arg("aa") = "4x4x32", py::arg("gamma") = "srgb",
          py::arg("background") = "white", py::arg("bits") = 8, py::arg("seed") = 0, py::arg("box") = "crop",
          py::arg("annotations") = true, py::arg("thin_lines") = "exact", py::arg("colorspace") = "rgb",
          py::arg("max_memory") = py::none(), py::arg("device") = "cpu",
          "The page as an H x W x 4 array: Document.render(page.number, ...), the pixels pdf2png writes.\n\n"
          MPVG_PDF_SIZE_DOC MPVG_PDF_RENDER_DOC)
      .def("__repr__", &PyPage::repr);

  device_array.def_property_readonly("shape", &PyDeviceArray::shape)
      .def_property_readonly("dtype", [](const PyDeviceArray&) { return py::dtype::of<uint8_t>(); })
      .def_property_readonly("device", &PyDeviceArray::device, "The CUDA device it is on.")
      .def_property_readonly("__cuda_array_interface__", &PyDeviceArray::cuda_array_interface)
      .def("__dlpack__", &PyDeviceArray::dlpack, py::arg("stream") = py::none())
      .def("__dlpack_device__", &PyDeviceArray::dlpack_device)
      .def("to_host", &PyDeviceArray::to_host, "A NumPy copy (what device='cpu' renders).");

  compare_result.def_property_readonly("passed", &PyCompareResult::passed, "Equal within the thresholds (warnings pass).")
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

  page_stream.def("__iter__", [](py::object self) { return self; })
      .def("__next__", &PyDocument::PageStream::next)
      .def("close", &PyDocument::PageStream::stop, "Cancels the pages not yet started and waits for the rest.");
}
