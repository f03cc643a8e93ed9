// Parser tests as text (issue 14): each testdata/svg-dumps/NAME.svg holds
// one feature (its comment says what the scene must contain) and
// NAME.dump the expected scene dump and warnings, written once by
// scripts/new-svg-dump.sh and read through before it was committed. A
// changed dump is a changed parse: read the difference, never regenerate
// a file to make this pass.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/catch.h"
#include "tests/svg_dump_text.h"

namespace fs = std::filesystem;

namespace {

std::string read(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// "line N: expected '...', got '...'" for the first line that differs.
std::string first_difference(const std::string& want, const std::string& got) {
  std::istringstream a(want), b(got);
  std::string la, lb;
  for (int n = 1;; n++) {
    const bool ea = !std::getline(a, la), eb = !std::getline(b, lb);
    if (ea && eb) return "identical";
    if (ea || eb || la != lb)
      return "line " + std::to_string(n) + ": expected '" + (ea ? "<end>" : la) + "', got '" + (eb ? "<end>" : lb) +
             "'";
  }
}

}  // namespace

TEST_CASE("scene dumps: each feature's SVG parses to its expected dump", "[svg][dumps]") {
  const fs::path dir = fs::path(MPVG_SOURCE_DIR) / "testdata" / "svg-dumps";
  std::vector<fs::path> cases;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".svg") cases.push_back(e.path());
  std::sort(cases.begin(), cases.end());
  REQUIRE(cases.size() >= 20);
  int skipped = 0;
  for (const fs::path& svg : cases) {
    fs::path expected = svg;
    expected.replace_extension(".dump");
    INFO(svg.filename().string());
    REQUIRE(fs::exists(expected));
    const std::string want = read(expected), got = svg_test::dump_text(svg.string());
#if !defined(MPVG_HAVE_TEXT)
    // Built without the text stage (no FreeType, e.g. the GPU host): <text>
    // is ignored with another warning, and the dumps of text features, made
    // with it, cannot match.
    if (want.find("text not rendered") != std::string::npos || want.find("<text>") != std::string::npos) {
      skipped++;
      continue;
    }
#endif
    INFO(first_difference(want, got));
    CHECK(got == want);
  }
  if (skipped) std::printf("test_svg_dumps: %d dumps of text features skipped (built without text)\n", skipped);
}
