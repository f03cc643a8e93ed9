// Blend modes and the Porter-Duff operators plus-lighter, source-atop and
// xor (core/paint/blend.h) against W3C Compositing and Blending Level 1 (and
// Level 2's plus-lighter) transcribed in double precision, on random
// premultiplied colours, plus values worked out by hand and the identities
// the modes must keep.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>

#include "core/paint/blend.h"
#include "core/scene.h"
#include "tests/catch.h"
#include "tests/reference_compositor.h"
#include "frame/scene_builder.h"

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
    // Over a transparent backdrop every mode is the source (source-atop:
    // nothing), and a transparent source leaves the backdrop (every mode
    // and operator here is bounded).
    for (uint32_t mode = 0; mode < BLEND_MODE_COUNT; mode++) {
      const Rgba4 o = blend_over(mode, Rgba4{0, 0, 0, 0}, s);
      const bool atop = mode == BLEND_SOURCE_ATOP;
      CHECK(o.g == Approx(atop ? 0 : s.g).margin(1e-6));
      CHECK(o.a == Approx(atop ? 0 : s.a).margin(1e-6));
      const Rgba4 k = blend_over(mode, b, Rgba4{0, 0, 0, 0});
      CHECK(k.r == Approx(b.r).margin(1e-6));
      CHECK(k.b == Approx(b.b).margin(1e-6));
      CHECK(k.a == Approx(b.a).margin(1e-6));
    }
    // Multiply by opaque white and screen with opaque black change nothing.
    const Rgba4 ob{b.r, b.g, b.b, 1.0f};  // premultiplied channels stay valid at alpha 1
    CHECK(blend_over(BLEND_MULTIPLY, ob, Rgba4{1, 1, 1, 1}).r == Approx(ob.r).margin(1e-6));
    CHECK(blend_over(BLEND_SCREEN, ob, Rgba4{0, 0, 0, 1}).g == Approx(ob.g).margin(1e-6));
  }
}

TEST_CASE("Porter-Duff operators: values worked out by hand", "[blend]") {
  auto check = [](uint32_t mode, Rgba4 b, Rgba4 s, std::array<float, 4> want) {
    const Rgba4 o = blend_over(mode, b, s);
    INFO("mode " << mode << ": " << o.r << " " << o.g << " " << o.b << " " << o.a);
    CHECK(o.r == Approx(want[0]).margin(1e-6));
    CHECK(o.g == Approx(want[1]).margin(1e-6));
    CHECK(o.b == Approx(want[2]).margin(1e-6));
    CHECK(o.a == Approx(want[3]).margin(1e-6));
  };
  // Premultiplied: backdrop (0.5, 0.25, 0) at 60 %, source (0.8, 0.4, 1) at 50 %.
  const Rgba4 b{0.3f, 0.15f, 0.0f, 0.6f}, s{0.4f, 0.2f, 0.5f, 0.5f};
  // plus-lighter: the sums, alpha 1.1 clamped to 1.
  check(BLEND_PLUS_LIGHTER, b, s, {0.7f, 0.35f, 0.5f, 1.0f});
  check(BLEND_PLUS_LIGHTER, Rgba4{0.9f, 0.1f, 0.5f, 0.9f}, Rgba4{0.6f, 0.2f, 0.5f, 0.6f}, {1.0f, 0.3f, 1.0f, 1.0f});
  // source-atop: cs ab + cb (1 - as) = (0.24 + 0.15, 0.12 + 0.075, 0.3), ao = ab.
  check(BLEND_SOURCE_ATOP, b, s, {0.39f, 0.195f, 0.3f, 0.6f});
  // xor: cs (1 - ab) + cb (1 - as) = (0.16 + 0.15, 0.08 + 0.075, 0.2),
  // ao = 0.5 + 0.6 - 2 * 0.3.
  check(BLEND_XOR, b, s, {0.31f, 0.155f, 0.2f, 0.5f});
  // Opaque onto opaque: source-atop is the source, xor is nothing,
  // plus-lighter the clamped sum.
  const Rgba4 red{1, 0, 0, 1}, blue{0, 0, 1, 1};
  check(BLEND_SOURCE_ATOP, red, blue, {0, 0, 1, 1});
  check(BLEND_XOR, red, blue, {0, 0, 0, 0});
  check(BLEND_PLUS_LIGHTER, red, blue, {1, 0, 1, 1});
  // Onto nothing: source-atop is nothing, the others are the source.
  const Rgba4 none{0, 0, 0, 0};
  check(BLEND_SOURCE_ATOP, none, s, {0, 0, 0, 0});
  check(BLEND_XOR, none, s, {0.4f, 0.2f, 0.5f, 0.5f});
  check(BLEND_PLUS_LIGHTER, none, s, {0.4f, 0.2f, 0.5f, 0.5f});
  // A transparent source leaves the backdrop: the three are bounded.
  for (uint32_t mode : {BLEND_PLUS_LIGHTER, BLEND_SOURCE_ATOP, BLEND_XOR}) check(mode, b, none, {0.3f, 0.15f, 0.0f, 0.6f});
  CHECK(blend_is_porter_duff(BLEND_XOR));
  CHECK_FALSE(blend_is_porter_duff(BLEND_LUMINOSITY));
  CHECK_FALSE(blend_separable(BLEND_PLUS_LIGHTER));
}

TEST_CASE("feBlend takes the blend modes and plus-lighter, not source-atop or xor", "[blend][filter]") {
  // feComposite has the Porter-Duff operators of its own; SceneBuilder keeps
  // feBlend's mode to what filters' blend_over calls are tested with.
  auto with_mode = [](BlendMode m) {
    SceneBuilder b(10, 10);
    FilterEffect f;
    f.source = std::make_shared<Scene>(SceneBuilder(10, 10).finish());
    f.region = FilterRect{0, 0, 10, 10};
    FilterPrimitive p;
    p.kind = FilterKind::Blend;
    p.subregion = f.region;
    p.blend_mode = static_cast<uint8_t>(m);
    f.primitives.push_back(p);
    b.add_filter(f);
  };
  CHECK_NOTHROW(with_mode(BlendMode::Luminosity));
  CHECK_NOTHROW(with_mode(BlendMode::PlusLighter));
  CHECK_THROWS(with_mode(BlendMode::SourceAtop));
  CHECK_THROWS(with_mode(BlendMode::Xor));
}
