// fuzz_pdf: the PDF frontend end to end. The input is a PDF file, written
// to the scratch folder (mpvg::pdf::Document opens paths), opened by MuPDF;
// its first two pages are interpreted and lowered to scenes through mpvg's
// device (parsers/pdf/pdf_device.cpp) at the resolution pdf2png
// --scale-to 32 would choose, and rendered on the CPU at most 32 x 32
// pixels (fuzz_render.h); page 1 also lowered for --separations, its
// plates named (lib/output/ink_output.h). mpvg::Error (broken file, failing page) is an
// expected outcome; anything else escaping is a finding.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "lib/output/ink_output.h"
#include "core/error.h"
#include "fuzz/fuzz_render.h"
#include "parsers/pdf/pdf_parser.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mpvg;
  static const std::string path = fuzz::scratch_dir() + "/input-" + std::to_string(getpid()) + ".pdf";
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) __builtin_trap();
    if (size && std::fwrite(data, 1, size, f) != size) __builtin_trap();
    std::fclose(f);
  }
  try {
    pdf::Document doc(path);
    const int pages = std::min(doc.page_count(), 2);
    for (int i = 0; i < pages; i++) {
      try {
        // pdf2png --scale-to 32 (apps/pdf2png.cpp lower).
        pdf::PageResult page = doc.page(i, [](double w, double h) { return fuzz::kMaxSide / std::max(w, h); });
        const double scale = page.pixels_per_point;
        const double pw = std::ceil(page.scene.width * scale - 1e-6), ph = std::ceil(page.scene.height * scale - 1e-6);
        if (!(pw >= 0 && ph >= 0 && pw <= fuzz::kMaxSide && ph <= fuzz::kMaxSide)) continue;
        const int width = std::max(1, static_cast<int>(pw)), height = std::max(1, static_cast<int>(ph));
        fuzz::render_small(page.scene, Affine::scale(scale, scale), width, height, static_cast<unsigned>(size) + i);
      } catch (const Error&) {
      }
    }
    // Print preview's separations of page 1 (spots from the document):
    // the passes lowered, every plate's name a file name of its own.
    if (pages > 0) {
      try {
        pdf::PageOptions sep;
        sep.inks = pdf::InkModel::Separations;
        sep.budget = std::make_shared<MemoryBudget>(fuzz::kBudgetBytes);
        const pdf::PageResult page = doc.page(0, [](double w, double h) { return 8 / std::max(w, h); }, sep);
        for (const std::string& name : plate_names(page.ink_names))
          if (name.empty() || name.find_first_of("/\\") != std::string::npos || name.size() > kMaxPlateName + 12)
            __builtin_trap();
      } catch (const Error&) {
      }
    }
  } catch (const Error&) {
  }
  return 0;
}
