// main of the GPU tests: exits with 77, which CTest reports as "skipped",
// where no CUDA device can be used.
#include <cstdio>
#include <string>

#include "lib/backend/backend.h"

#if __has_include(<catch2/catch_session.hpp>) && !defined(MPVG_CATCH2_V2)
#include <catch2/catch_session.hpp>
#else
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#endif

int main(int argc, char* argv[]) {
  std::string why;
  if (!mpvg::cuda_available(&why)) {
    std::printf("skipped: %s\n", why.c_str());
    return 77;
  }
  return Catch::Session().run(argc, argv);
}
