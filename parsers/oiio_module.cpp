// Opening mpvg's OpenImageIO modules (parsers/oiio_module.h).
#include "parsers/oiio_module.h"

#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace mpvg {

namespace {

#ifdef MPVG_OIIO_MODULE_DIRS
// Relative places first, so that a tree installed with another --prefix, or
// moved, loads its own modules: in a shared object (libmpvg.so in its
// libdir, the Python wheel's mpvg/) mpvg/ beside it; in a program the
// install libdir's mpvg/ reached from the executable's bin/
// (MPVG_BIN_TO_LIBDIR, from apps/CMakeLists.txt: "../lib", or Debian's
// multiarch "../lib/x86_64-linux-gnu"), then the other usual libdirs beside
// bin/ (the build tree's apps/ and tests/ find build/lib/mpvg so). A shared
// object never looks beside the executable that loaded it: python3's
// /usr/lib/mpvg could be another mpvg's. The fixed paths CMake gives
// (MPVG_OIIO_MODULE_DIRS: the build tree, the configured libdir) last.
std::vector<std::string> module_dirs() {
  std::vector<std::string> dirs;
  auto add = [&](const std::filesystem::path& dir) {
    const std::string d = dir.lexically_normal().string();
    if (std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.push_back(d);
  };
  Dl_info info{};
  link_map* object = nullptr;
  const bool found = dladdr1(reinterpret_cast<void*>(&module_dirs), &info, reinterpret_cast<void**>(&object),
                             RTLD_DL_LINKMAP) != 0;
  // The main program's link map has an empty name.
  if (found && object && object->l_name && object->l_name[0]) {
    add(std::filesystem::path(object->l_name).parent_path() / "mpvg");
  } else {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      const std::filesystem::path bin = exe.parent_path();
#ifdef MPVG_BIN_TO_LIBDIR
      add(bin / MPVG_BIN_TO_LIBDIR / "mpvg");
#endif
      add(bin / ".." / "lib" / "mpvg");
#ifdef MPVG_LIBRARY_ARCHITECTURE
      add(bin / ".." / "lib" / MPVG_LIBRARY_ARCHITECTURE / "mpvg");
#endif
      add(bin / ".." / "lib64" / "mpvg");
    }
  }
  const std::string list = MPVG_OIIO_MODULE_DIRS;
  for (size_t pos = 0; pos <= list.size();) {
    const size_t end = std::min(list.find(':', pos), list.size());
    if (end > pos) add(list.substr(pos, end - pos));
    pos = end + 1;
  }
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
