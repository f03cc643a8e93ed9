// fuzz_pdf: the PDF frontend end to end. The input is a PDF file, written
// to the scratch folder (mpvg::pdf::Document opens paths), opened by MuPDF;
// its first two pages are interpreted and lowered to scenes through mpvg's
// device (parsers/pdf/pdf_device.cpp) at the resolution pdf2png
// --scale-to 32 would choose, and rendered on the CPU at most 32 x 32
// pixels (fuzz_render.h). mpvg::Error (broken file, failing page) is an
// expected outcome; anything else escaping is a finding.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

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
  } catch (const Error&) {
  }
  return 0;
}
