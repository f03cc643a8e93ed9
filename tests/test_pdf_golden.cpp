// PDF golden images: every testdata/pdf/features/NAME.pdf (one feature
// each, written by scripts/make_pdf_features.py) rendered as pdf2png does
// at 72 dpi -- page 1 on white, CPU backend, box filter, 32 stratified
// samples, seed 0, sRGB -- must match NAME.png beside it, which was
// reviewed by eye against `mutool draw` when it was made. Comparison,
// tolerance and failure panels (<build>/golden-failures/pdf/NAME.png) are
// golden_compare.h's.
//
// A PDF without a golden must be listed in kPending with the reason; each
// run reports those as warnings. A PDF with neither fails, and so does a
// listed one that has a golden (take it off the list). References are
// regenerated only on purpose: MPVG_UPDATE_GOLDEN=1 ctest -R pdf_golden
// rewrites the existing ones; MPVG_UPDATE_GOLDEN=NAME,NAME... also writes
// the named pending ones.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "frame/frame.h"
#include "parsers/pdf/pdf_parser.h"
#include "tests/catch.h"
#include "tests/golden_compare.h"
#include "cpu/cpu_frame.h"

using namespace mpvg;
namespace fs = std::filesystem;

namespace {

// Features whose golden is not made yet, and why.
const std::map<std::string, std::string> kPending = {
};

// Page 1 at 1 pixel per point, as `pdf2png -r 72 --aa 1x32 --gamma srgb`.
std::vector<uint8_t> render_page(const fs::path& pdf_path, int* w, int* h) {
  const pdf::Document doc(pdf_path.string());
  const pdf::PageResult page = doc.page(0, 1.0);
  // No warning, but the one a MuPDF without ICC support gives pages with
  // ICC-based colours (drawn through their alternates: what the goldens
  // show).
  std::ostringstream warnings;
  size_t others = 0;
  for (const std::string& s : page.warnings) {
    warnings << "\n  " << s;
    others += s.rfind("this MuPDF has no ICC colour management", 0) != 0;
  }
  INFO("warnings:" << warnings.str());
  CHECK(others == 0);
  RenderOptions o;
  o.width = *w = std::max(1, static_cast<int>(std::ceil(page.scene.width - 1e-6)));
  o.height = *h = std::max(1, static_cast<int>(std::ceil(page.scene.height - 1e-6)));
  o.background = RGBA{1, 1, 1, 1};
  o.samples = 32;
  o.filter = Filter::Box;
  o.pattern = PatternKind::Stratified;
  o.seed = 0;
  o.gamma = Gamma::Srgb;
  o.backend = Backend::Cpu;
  return to_rgba8(render_cpu(page.scene, o), o.gamma);
}

// Whether MPVG_UPDATE_GOLDEN names `name` (a comma-separated list).
bool update_asks_for(const std::string& name) {
  const char* env = std::getenv("MPVG_UPDATE_GOLDEN");
  if (!env) return false;
  std::stringstream list(env);
  std::string item;
  while (std::getline(list, item, ','))
    if (item == name) return true;
  return false;
}

}  // namespace

TEST_CASE("pdf golden images", "[pdf][golden]") {
  const fs::path dir = fs::path(MPVG_SOURCE_DIR) / "testdata" / "pdf" / "features";
  const std::vector<fs::path> pdfs = golden::inputs(dir, ".pdf");
  REQUIRE(pdfs.size() >= 30);
  for (const fs::path& pdf : pdfs) {
    const std::string name = pdf.stem().string();
    const fs::path ref = fs::path(pdf).replace_extension(".png");
    const auto pending = kPending.find(name);
    SECTION(name) {
      const bool have_golden = fs::exists(ref);
      if (pending != kPending.end() && !update_asks_for(name)) {
        if (have_golden) FAIL(name << " has a golden now: take it off kPending");
        WARN("pending, no golden yet: " << name << ".pdf (" << pending->second << ")");
        continue;
      }
      if (!have_golden && std::getenv("MPVG_UPDATE_GOLDEN") == nullptr)
        FAIL(ref.string() << " is missing: make it (MPVG_UPDATE_GOLDEN=1, then review it) or list " << name
                          << " in kPending with the reason");
      int w, h;
      const std::vector<uint8_t> actual = render_page(pdf, &w, &h);
      golden::check_golden(name, ref, w, h, actual,
                           fs::path(MPVG_BINARY_DIR) / "golden-failures" / "pdf" / (name + ".png"));
    }
  }
}
