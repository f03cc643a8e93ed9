// Print preview's files (pdf2png --colorspace cmyk, --separations): a page
// drawn in inks (core/inks/inks.h) comes back from the renderer as its passes
// side by side in one RGBA image (pass p's three inks in r, g, b, opaque,
// 0 no ink); this turns it into
//   - a CMYK TIFF (--colorspace cmyk: the four process inks), or
//   - with separations: one TIFF of every ink (C, M, Y, K, then the spot
//     colours, separated, with their names), one grey TIFF per ink named
//     "OUT(Name).tif" as Ghostscript's tiffsep names and writes them (255
//     no ink, 0 full ink: the plate's film), and an RGB simulation of the
//     press sheet, overprint included, as OUT.png (core/inks/inks.h
//     inks_to_rgb).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lib/output/image_writer.h"

namespace mpvg {

struct InkPage {
  std::vector<std::string> names;  // C, M, Y, K, then the spots'
  std::vector<float> spot_cmyk;    // four a spot
  int width = 0;                   // a pass's width in the rendered image
  int gap = 0;                     // pixels between passes
  bool separations = false;
};

// The ink amounts of every pixel, interleaved (names.size() a pixel), out
// of the rendered image (width_all x height, straight RGBA 8-bit).
std::vector<uint8_t> gather_inks(const InkPage& page, int width_all, int height, const uint8_t* rgba);

// The file name part of an ink's plate, "OUT(NAME).tif": the ink's name
// as it is, but for bytes that a file name cannot hold or that would name
// something else (control characters, / \ : * ? " < > |, and bytes past
// ASCII unless the name is valid UTF-8), written %XX (hex, upper case),
// '%' itself as %25. A result longer than kMaxPlateName bytes is cut at a
// character boundary and ends in ~ and eight hex digits of the whole
// name's hash (FNV-1a). Document-controlled text never becomes a path:
// "../x" is "..%2Fx".
constexpr size_t kMaxPlateName = 120;
std::string plate_name(const std::string& ink);
// Every ink's plate name, unique even on a file system blind to case: a
// name equal to an earlier one but for ASCII case gets ~2, ~3, ...
std::vector<std::string> plate_names(const std::vector<std::string>& inks);

// Writes the page's files; `out` is the TIFF's path ("-": standard output,
// with no planes or simulation beside it). Throws mpvg::Error.
void write_ink_page(const InkPage& page, const std::string& out, int width_all, int height, const uint8_t* rgba,
                    const image::EncodeOptions& options);

}  // namespace mpvg
