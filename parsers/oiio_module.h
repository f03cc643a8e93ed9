// mpvg's OpenImageIO modules, opened on first need so that the converters
// start without loading OpenImageIO's ~260 libraries: the decoder of SVG
// images (svg/svg_image_decode_oiio.cpp, mpvg_oiio_decoder.so) and the
// TIFF/JPEG encoder (lib/output/image_encode_oiio.cpp, mpvg_oiio_encoder.so),
// built where MPVG_IMAGE_IO=oiio.
#pragma once
#include <string>

namespace mpvg {

struct OiioModule {
  void* entry = nullptr;  // the entry point asked for; null when there is no module
  std::string version;    // "OpenImageIO 2.4.7"
  std::string error;      // why there is none, one line
};

// Opens `file` ("mpvg_oiio_decoder.so") from fixed places only (no search
// path a document or the environment names): mpvg/ beside the shared object
// holding this code (libmpvg.so in any prefix, or loaded by Python), or in
// a program the install libdir's mpvg/ beside the executable's bin/ (lib/,
// Debian's lib/<multiarch>/), then the build tree and the configured
// libdir's mpvg/ (MPVG_OIIO_MODULE_DIRS, from CMake). Checks that it
// exports `entry` and mpvg_oiio_version; `what` ("decoder") names it in
// messages. A module is never closed: its state lives until the process
// ends. Call once per module (the callers keep the result).
OiioModule open_oiio_module(const char* file, const char* entry, const char* what);

}  // namespace mpvg
