// Blend modes (core/blend.h) against W3C Compositing and Blending Level 1
// transcribed in double precision, on random premultiplied colours, plus
// values worked out by hand and the identities the modes must keep.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "core/blend.h"
#include "tests/catch.h"
#include "tests/reference_compositor.h"

using namespace mpvg;

namespace {

std::array<double, 4> ref_over(uint32_t mode, const Rgba4& b, const Rgba4& s) {
  return reference::over(mode, {b.r, b.g, b.b, b.a}, {s.r, s.g, s.b, s.a});
}

Rgba4 random_color(std::mt19937& rng, bool opaque) {
  std::uniform_real_distribution<float> u(0, 1);
  // Corners of the cube now and then: the modes' special cases live there.
  auto channel = [&] {
    const float v = u(rng);
    return v < 0.1f ? 0.0f : v > 0.9f ? 1.0f : u(rng);
  };
  const float a = opaque ? 1.0f : channel();
  return Rgba4{channel() * a, channel() * a, channel() * a, a};
}

}  // namespace

TEST_CASE("every blend mode matches the specification's formulas on premultiplied colours", "[blend]") {
  std::mt19937 rng(5);
  for (uint32_t mode = 0; mode < BLEND_MODE_COUNT; mode++) {
    double worst = 0;
    for (int i = 0; i < 20000; i++) {
      const Rgba4 b = random_color(rng, i % 3 == 0), s = random_color(rng, i % 5 == 0);
      const Rgba4 got = blend_over(mode, b, s);
      const std::array<double, 4> ref = ref_over(mode, b, s);
      const double d = std::max({std::fabs(got.r - ref[0]), std::fabs(got.g - ref[1]), std::fabs(got.b - ref[2]),
                                 std::fabs(got.a - ref[3])});
      worst = std::max(worst, d);
    }
    INFO("mode " << mode << ": largest difference " << worst);
    CHECK(worst < 2e-5);
  }
}

TEST_CASE("blend modes: values worked out by hand", "[blend]") {
  auto one = [](uint32_t mode, float cb, float cs) { return blend_channel(mode, cb, cs); };
  CHECK(one(BLEND_MULTIPLY, 0.5f, 0.5f) == 0.25f);
  CHECK(one(BLEND_SCREEN, 0.5f, 0.5f) == 0.75f);
  CHECK(one(BLEND_OVERLAY, 0.25f, 0.5f) == 0.25f);           // 2 cs cb
  CHECK(one(BLEND_HARD_LIGHT, 0.25f, 0.75f) == Approx(0.625));  // screen(0.25, 0.5)
  CHECK(one(BLEND_SOFT_LIGHT, 0.25f, 0.75f) == Approx(0.375));  // D(0.25) = 0.5
  CHECK(one(BLEND_SOFT_LIGHT, 0.64f, 1.0f) == Approx(0.8));     // sqrt
  CHECK(one(BLEND_COLOR_DODGE, 0.5f, 0.75f) == 1.0f);
  CHECK(one(BLEND_COLOR_DODGE, 0.0f, 1.0f) == 0.0f);
  CHECK(one(BLEND_COLOR_BURN, 0.5f, 0.75f) == Approx(1.0 / 3));
  CHECK(one(BLEND_COLOR_BURN, 1.0f, 0.0f) == 1.0f);
  CHECK(one(BLEND_DIFFERENCE, 0.2f, 0.7f) == Approx(0.5));
  CHECK(one(BLEND_EXCLUSION, 0.5f, 0.5f) == 0.5f);
  // Luminosity: the source's luminance on the backdrop's hue and saturation.
  const Rgb3 red{1, 0, 0}, grey{0.5f, 0.5f, 0.5f};
  const Rgb3 l = blend_nonseparable(BLEND_LUMINOSITY, red, grey);
  CHECK(blend_lum(l) == Approx(0.5));
  CHECK(l.r > l.g);
  CHECK(l.g == Approx(l.b));
  // Colour of a grey source: a grey of the backdrop's luminance.
  const Rgb3 c = blend_nonseparable(BLEND_COLOR, red, grey);
  CHECK(c.r == Approx(0.3));
  CHECK(c.g == Approx(0.3));
  // Saturation from a grey source: the backdrop turns grey.
  const Rgb3 s = blend_nonseparable(BLEND_SATURATION, Rgb3{0.2f, 0.6f, 0.9f}, grey);
  CHECK(s.r == Approx(s.g));
  CHECK(s.g == Approx(s.b));
}

TEST_CASE("blend modes keep their identities and reduce to source-over", "[blend]") {
  std::mt19937 rng(9);
  for (int i = 0; i < 2000; i++) {
    const Rgba4 b = random_color(rng, false), s = random_color(rng, false);
    // Normal is source-over.
    const Rgba4 n = blend_over(BLEND_NORMAL, b, s);
    CHECK(n.r == Approx(s.r + (1 - s.a) * b.r).margin(1e-6));
    CHECK(n.a == Approx(s.a + (1 - s.a) * b.a).margin(1e-6));
    // Over a transparent backdrop every mode is the source, and a
    // transparent source leaves the backdrop.
    for (uint32_t mode = 0; mode < BLEND_MODE_COUNT; mode++) {
      const Rgba4 o = blend_over(mode, Rgba4{0, 0, 0, 0}, s);
      CHECK(o.g == Approx(s.g).margin(1e-6));
      const Rgba4 k = blend_over(mode, b, Rgba4{0, 0, 0, 0});
      CHECK(k.b == Approx(b.b).margin(1e-6));
    }
    // Multiply by opaque white and screen with opaque black change nothing.
    const Rgba4 ob{b.r, b.g, b.b, 1.0f};  // premultiplied channels stay valid at alpha 1
    CHECK(blend_over(BLEND_MULTIPLY, ob, Rgba4{1, 1, 1, 1}).r == Approx(ob.r).margin(1e-6));
    CHECK(blend_over(BLEND_SCREEN, ob, Rgba4{0, 0, 0, 1}).g == Approx(ob.g).margin(1e-6));
  }
}
