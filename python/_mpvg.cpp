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

#include <memory>
#include <mutex>
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
py::array as_array(std::vector<T>&& pixels, int width, int height) {
  auto owned = std::make_unique<std::vector<T>>(std::move(pixels));
  T* data = owned->data();
  py::capsule owner(owned.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  owned.release();
  const auto w = static_cast<py::ssize_t>(width), h = static_cast<py::ssize_t>(height);
  const auto s = static_cast<py::ssize_t>(sizeof(T));
  return py::array_t<T>({h, w, py::ssize_t(4)}, {w * 4 * s, 4 * s, s}, data, owner);
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
    std::optional<std::string> path, data;
    if (py::isinstance<py::str>(input)) {
      path = input.cast<std::string>();
    } else if (py::isinstance<py::bytes>(input)) {
      data = input.cast<std::string>();
    } else if (PyObject_CheckBuffer(input.ptr())) {
      const py::buffer_info b = py::reinterpret_borrow<py::buffer>(input).request();
      if (b.ndim != 1 || b.itemsize != 1) throw py::type_error("SVG data must be a one-dimensional buffer of bytes");
      data = std::string(static_cast<const char*>(b.ptr), static_cast<size_t>(b.size));
    } else if (py::hasattr(input, "__fspath__")) {
      path = py::str(py::module_::import("os").attr("fspath")(input)).cast<std::string>();
    } else {
      throw py::type_error("render_svg takes a path (str) or the SVG document (bytes)");
    }
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
    return image.bits == 16 ? as_array(std::move(image.pixels16), image.width, image.height)
                            : as_array(std::move(image.pixels8), image.width, image.height);
  }

 private:
  mpvg::Renderer renderer_;
  std::mutex mutex_;
  std::vector<std::string> warnings_;
};

}  // namespace

PYBIND11_MODULE(_mpvg, m) {
  m.doc() =
      "mpvg: SVG documents rendered by the massively-parallel vector graphics pipeline (CPU or CUDA),\n"
      "as numpy arrays of straight-alpha sRGB RGBA pixels, the same values svg2png writes.";
  m.attr("__version__") = MPVG_VERSION;
  // mpvg.Error is a RuntimeError: unreadable files, malformed SVG, bad sizes, no CUDA device.
  py::register_exception<mpvg::Error>(m, "Error", PyExc_RuntimeError);

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
}
