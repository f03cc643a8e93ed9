// svg_dump FILE.svg: prints the text tests/test_svg_dumps.cpp compares
// (svg_test::dump_text), for scripts/new-svg-dump.sh.
#include <cstdio>
#include <exception>

#include "tests/svg_dump_text.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: svg_dump FILE.svg\n");
    return 2;
  }
  try {
    std::fputs(svg_test::dump_text(argv[1]).c_str(), stdout);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "svg_dump: %s\n", e.what());
    return 1;
  }
  return 0;
}
