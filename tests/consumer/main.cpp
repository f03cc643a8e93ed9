// Renders through the installed mpvg package and checks pixels that follow
// from the documents: solid interiors, transparent or background corners,
// sizes, the stride contract, 16 bits, errors. Exits 1 on any failure.
// usage: mpvg_consumer SOURCE_DIR
#include <mpvg/mpvg.h>

#include <cstdio>
#include <string>
#include <vector>

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAILED", what.c_str());
  if (!ok) failures++;
}

// The RGBA of pixel (x, y), 8 bits.
std::vector<int> at(const mpvg::Bitmap& b, int x, int y) {
  const uint8_t* p = &b.pixels8[(static_cast<size_t>(y) * b.width + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

using RGBA = std::vector<int>;

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: mpvg_consumer SOURCE_DIR\n");
    return 2;
  }
  const std::string src = argv[1];
  try {
    mpvg::Renderer renderer(mpvg::Device::Auto);
    std::printf("renderer: %s%s%s\n", renderer.device() == mpvg::Device::Cuda ? "cuda" : "cpu",
                renderer.note().empty() ? "" : ", ", renderer.note().c_str());
    check(renderer.device() == mpvg::Device::Cpu || renderer.device() == mpvg::Device::Cuda,
          "the renderer resolves auto to a backend");

    // A 16 x 16 document with an 8 x 8 square at (4, 4), rendered at twice
    // its size: pixels 8..23 lie inside the square. The box filter of 1x8
    // gives exact colours where a pixel is wholly inside or outside.
    const char* square =
        "<svg xmlns='http://www.w3.org/2000/svg' width='16' height='16'>"
        "<rect x='4' y='4' width='8' height='8' fill='#3366cc'/></svg>";
    const mpvg::SvgDocument doc = mpvg::SvgDocument::from_data(square);
    check(doc.width() == 16 && doc.height() == 16, "the document's intrinsic size is 16 x 16");
    mpvg::RenderSettings s;
    s.zoom = 2;
    s.antialiasing = mpvg::Antialiasing::Box1x8;
    const mpvg::OutputSize size = doc.output_size(s);
    check(size.width == 32 && size.height == 32, "zoom 2 gives 32 x 32");
    const mpvg::Bitmap img = renderer.render(doc, s);
    check(img.width == 32 && img.height == 32 && img.bits == 8 && img.pixels8.size() == 32 * 32 * 4 &&
              img.pixels16.empty(),
          "an 8-bit 32 x 32 bitmap");
    check(at(img, 16, 16) == RGBA{0x33, 0x66, 0xcc, 255}, "the square's inside is #3366cc, opaque");
    check(at(img, 8, 8) == RGBA{0x33, 0x66, 0xcc, 255} && at(img, 23, 23) == RGBA{0x33, 0x66, 0xcc, 255},
          "the square's corner pixels are inside");
    const RGBA clear{0, 0, 0, 0};
    check(at(img, 0, 0) == clear && at(img, 7, 16) == clear && at(img, 24, 16) == clear,
          "outside the square is transparent");

    // Width alone keeps the aspect ratio; a background fills the outside.
    mpvg::RenderSettings w;
    w.width = 64;
    w.antialiasing = mpvg::Antialiasing::Box1x32;
    w.background = mpvg::Color::parse("white");
    const mpvg::Bitmap wide = renderer.render(doc, w);
    check(wide.width == 64 && wide.height == 64, "width 64 gives 64 x 64");
    check(at(wide, 1, 1) == RGBA{255, 255, 255, 255} && at(wide, 32, 32) == RGBA{0x33, 0x66, 0xcc, 255},
          "white background outside, the square inside");

    // Into the caller's buffer, with padding between rows left alone.
    const size_t stride = 32 * 4 + 8;
    std::vector<uint8_t> buffer(stride * 32, 0xab);
    renderer.render(doc, s, buffer.data(), stride, 32, 32);
    bool same = true, padding = true;
    for (int y = 0; y < 32; y++) {
      for (int i = 0; i < 32 * 4; i++) same &= buffer[y * stride + i] == img.pixels8[y * 32 * 4 + i];
      for (size_t i = 32 * 4; i < stride; i++) padding &= buffer[y * stride + i] == 0xab;
    }
    check(same, "rendering into a buffer with a stride gives the bitmap's pixels");
    check(padding, "the bytes between rows are untouched");
    bool threw = false;
    try {
      renderer.render(doc, s, buffer.data(), stride, 31, 32);
    } catch (const mpvg::Error&) {
      threw = true;
    }
    check(threw, "a buffer of the wrong size is refused with mpvg::Error");

    // 16 bits: the same colour, 257 times the 8-bit code.
    mpvg::RenderSettings d = s;
    d.bits = 16;
    const mpvg::Bitmap deep = renderer.render(doc, d);
    const uint16_t* p = &deep.pixels16[(16 * 32 + 16) * 4];
    check(deep.bits == 16 && deep.pixels8.empty() && deep.pixels16.size() == 32 * 32 * 4 && deep.stride() == 32 * 8,
          "a 16-bit bitmap");
    check(p[0] == 0x33 * 257 && p[1] == 0x66 * 257 && p[2] == 0xcc * 257 && p[3] == 65535,
          "16 bits: the square's inside is #3366cc, opaque");

    // A file of the test data: testdata/golden/opacity.svg (128 x 96) has
    // a white rectangle under everything and an opaque #ffcc00 rectangle
    // at x 104..112, y 16..80.
    const mpvg::SvgDocument file = mpvg::SvgDocument::from_file(src + "/testdata/golden/opacity.svg");
    mpvg::RenderSettings f;
    f.antialiasing = mpvg::Antialiasing::Box1x8;
    const mpvg::Bitmap page = renderer.render(file, f);
    check(page.width == 128 && page.height == 96, "opacity.svg renders at its size, 128 x 96");
    check(at(page, 108, 40) == RGBA{0xff, 0xcc, 0x00, 255}, "opacity.svg: the yellow rectangle");
    check(at(page, 1, 1) == RGBA{255, 255, 255, 255} && at(page, 126, 94) == RGBA{255, 255, 255, 255},
          "opacity.svg: white corners");

    // Unsupported content is reported.
    const mpvg::SvgDocument text = mpvg::SvgDocument::from_data(
        "<svg xmlns='http://www.w3.org/2000/svg' width='8' height='8'><foreignObject/></svg>");
    check(!text.warnings().empty(), "an unsupported element is reported as a warning");

    // Errors are mpvg::Error with a message.
    std::string message;
    try {
      // Parsed on first need.
      const mpvg::SvgDocument bad = mpvg::SvgDocument::from_data("<svg xmlns='http://www.w3.org/2000/svg'><rect</svg>");
      renderer.render(bad);
    } catch (const mpvg::Error& e) {
      message = e.what();
    }
    check(message.find("XML parse error") != std::string::npos, "malformed XML throws mpvg::Error: " + message);
    message.clear();
    try {
      mpvg::SvgDocument::from_file(src + "/testdata/no-such-file.svg");
    } catch (const std::runtime_error& e) {  // mpvg::Error is one
      message = e.what();
    }
    check(message.find("cannot read") != std::string::npos, "a missing file throws: " + message);
    threw = false;
    try {
      mpvg::RenderSettings bad;
      bad.bits = 12;
      renderer.render(doc, bad);
    } catch (const mpvg::Error&) {
      threw = true;
    }
    check(threw, "12 bits are refused");
  } catch (const std::exception& e) {
    std::printf("FAILED: unexpected exception: %s\n", e.what());
    return 1;
  }
  std::printf("%d failure(s)\n", failures);
  return failures ? 1 : 0;
}
