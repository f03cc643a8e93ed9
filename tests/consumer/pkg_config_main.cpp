// The smallest consumer through pkg-config instead of CMake: built by
// tests/test_consumer.sh with `c++ -std=c++17 pkg_config_main.cpp
// $(pkg-config --cflags --libs mpvg)` against the installed prefix. Renders
// a 3 x 2 document that is one opaque red rectangle on the CPU and prints
// its size and first pixel, "3x2 255,0,0,255", for the script to compare.
#include <mpvg/mpvg.h>

#include <cstdio>

int main() {
  try {
    mpvg::Renderer renderer(mpvg::Device::Cpu);
    const mpvg::SvgDocument doc = mpvg::SvgDocument::from_data(
        "<svg xmlns='http://www.w3.org/2000/svg' width='3' height='2'><rect width='3' height='2' fill='red'/></svg>");
    mpvg::RenderSettings s;
    s.antialiasing = mpvg::Antialiasing::Box1x8;
    const mpvg::Bitmap img = renderer.render(doc, s);
    std::printf("%dx%d %d,%d,%d,%d\n", img.width, img.height, img.pixels8[0], img.pixels8[1], img.pixels8[2],
                img.pixels8[3]);
    return 0;
  } catch (const mpvg::Error& e) {
    std::fprintf(stderr, "pkg_config_main: %s\n", e.what());
    return 1;
  }
}
