// Shared by the fuzz targets (fuzz/README.md): a scratch folder that is the
// only place an input may make the code read from, and the size limits that
// keep one input's work bounded.
#pragma once
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace mpvg::fuzz {

// Output images are at most this many pixels on a side (the document's
// aspect ratio kept), so that rendering costs milliseconds.
constexpr int kMaxSide = 32;

// A fresh folder under $TMPDIR (or /tmp), made once per process and left
// for the system to clean; it holds copies of the two test fonts of
// testdata/fonts (so that text is shaped without the system's fonts) and a
// small PNG and SVG, which documents can reference as "a.png" and "a.svg".
inline const std::string& scratch_dir() {
  static const std::string dir = [] {
    namespace fs = std::filesystem;
    const char* tmp = std::getenv("TMPDIR");
    std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/mpvg-fuzz-XXXXXX";
    if (!mkdtemp(templ.data())) std::abort();
    std::error_code ec;
#ifdef MPVG_SOURCE_DIR
    const fs::path src(MPVG_SOURCE_DIR "/testdata");
    fs::create_directories(fs::path(templ) / "fonts", ec);
    for (const char* f : {"MpvgTestColor.ttf", "MpvgTestVF.ttf"})
      fs::copy_file(src / "fonts" / f, fs::path(templ) / "fonts" / f, ec);
    fs::copy_file(src / "images" / "rgba8.png", fs::path(templ) / "a.png", ec);
    fs::copy_file(src / "svgz" / "square.svg", fs::path(templ) / "a.svg", ec);
#endif
    return templ;
  }();
  return dir;
}

// The pixel size for a document of w x h units: its own size scaled down
// (never up) to fit kMaxSide, at least 1 x 1.
inline void clamp_output(double w, double h, int* width, int* height) {
  double s = 1;
  if (w > kMaxSide || h > kMaxSide) s = kMaxSide / (w > h ? w : h);
  double pw = w * s, ph = h * s;
  *width = pw < 1 ? 1 : pw > kMaxSide ? kMaxSide : static_cast<int>(pw + 0.5);
  *height = ph < 1 ? 1 : ph > kMaxSide ? kMaxSide : static_cast<int>(ph + 0.5);
}

}  // namespace mpvg::fuzz
