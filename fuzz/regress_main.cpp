// A main() for the fuzz targets in builds without libFuzzer: every file
// given (a folder: every file in its tree, in name order; after
// --prefix=P, only the files of later folders whose names start with P) is
// run once through LLVMFuzzerTestOneInput, as libFuzzer does with -runs=0. The
// regression tests (fuzz_regress_<target>) run the committed corpora and
// crash cases this way in the ordinary, unsanitized build and, under ASan
// and UBSan, in the sanitized one (MPVG_SANITIZE).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define MPVG_REGRESS_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MPVG_REGRESS_ASAN 1
#endif
#endif
#ifdef MPVG_REGRESS_ASAN
#include <sanitizer/common_interface_defs.h>
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

// The input being run, for the process's last words: a sanitizer's report
// or an escaping exception says where it happened, not which of a corpus's
// thousands of files made it happen. Null between inputs (a leak report at
// exit belongs to no single input).
const char* g_running = nullptr;

void say_input() {
  if (g_running) std::fprintf(stderr, "fuzz_regress: while running %s\n", g_running);
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::string prefix;
  for (int i = 1; i < argc; i++) {
    const std::string arg = argv[i];
    if (arg.rfind("--prefix=", 0) == 0) {
      prefix = arg.substr(9);
      continue;
    }
    const fs::path p(arg);
    if (fs::is_directory(p)) {
      for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file() && e.path().filename().string().rfind(prefix, 0) == 0) files.push_back(e.path());
    } else if (fs::exists(p)) {
      files.push_back(p);
    } else {
      std::fprintf(stderr, "%s: no such file or folder\n", argv[i]);
      return 1;
    }
  }
  std::sort(files.begin(), files.end());
#ifdef MPVG_REGRESS_ASAN
  __sanitizer_set_death_callback(say_input);
#endif
  static const std::terminate_handler next = std::set_terminate([] {
    say_input();
    next();
  });
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) {
      std::fprintf(stderr, "%s: cannot read\n", f.c_str());
      return 1;
    }
    g_running = f.c_str();
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    g_running = nullptr;
  }
  std::printf("%zu inputs ran\n", files.size());
  return 0;
}
