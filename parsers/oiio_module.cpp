// Opening mpvg's OpenImageIO modules (parsers/oiio_module.h).
#include "parsers/oiio_module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace mpvg {

namespace {

#ifdef MPVG_OIIO_MODULE_DIRS
std::vector<std::string> module_dirs() {
  std::vector<std::string> dirs;
  const std::string list = MPVG_OIIO_MODULE_DIRS;
  for (size_t pos = 0; pos <= list.size();) {
    const size_t end = std::min(list.find(':', pos), list.size());
    if (end > pos) dirs.push_back(list.substr(pos, end - pos));
    pos = end + 1;
  }
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back((exe.parent_path().parent_path() / "lib" / "mpvg").string());
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&module_dirs), &info) && info.dli_fname)
    dirs.push_back((std::filesystem::path(info.dli_fname).parent_path() / "mpvg").string());
  return dirs;
}
#endif

}  // namespace

OiioModule open_oiio_module(const char* file, const char* entry, const char* what) {
  OiioModule module;
#ifndef MPVG_OIIO_MODULE_DIRS
  (void)file;
  (void)entry;
  (void)what;
  module.error = "built with MPVG_IMAGE_IO=png";
#else
  std::string tried;
  for (const std::string& dir : module_dirs()) {
    const std::string path = dir + "/" + file;
    if (access(path.c_str(), R_OK) != 0) {
      tried += (tried.empty() ? "" : ", ") + path;
      continue;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* e = dlerror();
      module.error = "cannot load " + path + ": " + (e ? e : "unknown error");
      return module;
    }
    void* fn = dlsym(handle, entry);
    auto version = reinterpret_cast<const char* (*)()>(dlsym(handle, "mpvg_oiio_version"));
    if (!fn || !version) {
      module.error = path + " is not mpvg's " + what + " module";
      return module;
    }
    module.entry = fn;
    module.version = version();
    return module;
  }
  module.error = std::string("its ") + what + " module is not installed (looked for " + tried + ")";
#endif
  return module;
}

}  // namespace mpvg
