// Raster images in SVG documents: PNG by libpng in the process
// (svg_image_decode_png.cpp); JPEG, GIF and WebP by OpenImageIO in a module
// opened on first need (svg_image_decode_oiio.cpp, mpvg_oiio_decoder.so),
// so that svg2png starts without loading OpenImageIO's ~260 libraries.
#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>
#include <mutex>

#include "parsers/svg/svg_resources.h"

namespace mpvg::svg::detail {

namespace {

using DecodeFn = void (*)(const std::vector<uint8_t>*, const char*, const DecodeRequest*, std::shared_ptr<Image>*,
                          std::string*, int*, int*);
using VersionFn = const char* (*)();

struct OiioModule {
  DecodeFn decode = nullptr;
  std::string version;  // "OpenImageIO 2.4.7"
  std::string error;    // why there is none
};

// Where the module may be: MPVG_OIIO_MODULE_DIRS (CMake, ':'-separated: the build folder,
// then the installed lib/mpvg), lib/mpvg beside the executable's bin/, and
// mpvg/ beside the shared library this code is in.
// Fixed places only: no search path a document or the environment names.
#ifdef MPVG_OIIO_MODULE_DIRS
std::vector<std::string> module_candidates() {
  std::vector<std::string> dirs;
  std::string list = MPVG_OIIO_MODULE_DIRS;
  for (size_t pos = 0; pos <= list.size();) {
    const size_t end = std::min(list.find(':', pos), list.size());
    if (end > pos) dirs.push_back(list.substr(pos, end - pos));
    pos = end + 1;
  }
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back((exe.parent_path().parent_path() / "lib" / "mpvg").string());
  // Beside the shared object holding this code (libmpvg.so installed in
  // another prefix, or loaded by Python): its folder's mpvg/.
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&module_candidates), &info) && info.dli_fname)
    dirs.push_back((std::filesystem::path(info.dli_fname).parent_path() / "mpvg").string());
  std::vector<std::string> files;
  for (const std::string& d : dirs) files.push_back(d + "/mpvg_oiio_decoder.so");
  return files;
}
#endif

const OiioModule& oiio_module() {
  static OiioModule module;
  static std::once_flag once;
  std::call_once(once, [] {
#ifndef MPVG_OIIO_MODULE_DIRS
    module.error = "built with MPVG_IMAGE_IO=png";
#else
    std::string tried;
    for (const std::string& file : module_candidates()) {
      if (access(file.c_str(), R_OK) != 0) {
        tried += (tried.empty() ? "" : ", ") + file;
        continue;
      }
      // Never closed: the decoder's state lives until the process ends.
      void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        const char* e = dlerror();
        module.error = "cannot load " + file + ": " + (e ? e : "unknown error");
        return;
      }
      auto decode = reinterpret_cast<DecodeFn>(dlsym(handle, "mpvg_oiio_decode"));
      auto version = reinterpret_cast<VersionFn>(dlsym(handle, "mpvg_oiio_version"));
      if (!decode || !version) {
        module.error = file + " is not mpvg's decoder module";
        return;
      }
      module.decode = decode;
      module.version = version();
      return;
    }
    module.error = "its decoder module is not installed (looked for " + tried + ")";
#endif
  });
  return module;
}

}  // namespace

bool oiio_decoder_available(std::string* why) {
  const OiioModule& m = oiio_module();
  if (!m.decode && why) *why = m.error;
  return m.decode != nullptr;
}

std::shared_ptr<Image> decode_raster(const std::vector<uint8_t>& bytes, std::string* why, const DecodeRequest& request,
                                     int* full_w, int* full_h) {
  const char* format = nullptr;
  const char* name = nullptr;
  switch (sniff_image(bytes, "")) {
    case ImageKind::Png: return decode_png(bytes, why, request, full_w, full_h);
    case ImageKind::Jpeg: format = "jpeg", name = "JPEG"; break;
    case ImageKind::Gif: format = "gif", name = "GIF"; break;
    case ImageKind::Webp: format = "webp", name = "WebP"; break;
    default:
      if (why) *why = "not a PNG, JPEG, GIF or WebP image";
      return nullptr;
  }
  std::string no;
  if (!oiio_decoder_available(&no)) {
    if (why) *why = std::string(name) + " images need OpenImageIO (" + no + ")";
    return nullptr;
  }
  std::shared_ptr<Image> image;
  int w = 0, h = 0;
  oiio_module().decode(&bytes, format, &request, &image, why, &w, &h);
  if (full_w) *full_w = w;
  if (full_h) *full_h = h;
  return image;
}

std::string image_decoder_library() {
  std::string no;
  const bool oiio = oiio_decoder_available(&no);
  return png_decoder_library() + "; " + (oiio ? oiio_module().version + " (module)" : "no OpenImageIO: " + no);
}

}  // namespace mpvg::svg::detail
