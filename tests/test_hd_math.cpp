// core/hd_math.h against long double's functions: within one unit in the
// last place of float over sweeps of the arguments the pipeline gives them
// (sRGB transfers, Gaussian weights, lighting exponents, sweep angles) and
// at the special values. That both executors give the same bits is
// test_gpu's "golden images: the same bytes" (they run these very lines).
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "core/hd_math.h"
#include "core/output/srgb.h"
#include "tests/catch.h"

using namespace mpvg;

namespace {

// Units in the last place between got and the float nearest to want.
double ulps(float got, long double want) {
  const float w = static_cast<float>(want);
  if (got == w) return 0;
  const float gap = std::nextafter(std::fabs(w), INFINITY) - std::fabs(w);
  return std::fabs(static_cast<long double>(got) - want) / gap;
}

}  // namespace

TEST_CASE("hd_powf is pow within an ulp", "[hd_math]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> base(0.0f, 1.0f), expo(0.05f, 128.0f);
  double worst = 0;
  for (int i = 0; i < 200000; i++) {
    const float x = i < 100000 ? base(rng) : std::ldexp(base(rng), -static_cast<int>(i % 60));
    const float y = i % 3 == 0 ? 2.4f : i % 3 == 1 ? 1.0f / 2.4f : expo(rng);
    if (x == 0) continue;
    worst = std::max(worst, ulps(hd_powf(x, y), std::pow(static_cast<long double>(x), static_cast<long double>(y))));
  }
  INFO("worst " << worst << " ulp");
  CHECK(worst <= 1.0);
  CHECK(hd_powf(0.0f, 2.0f) == 0.0f);
  CHECK(hd_powf(0.0f, 0.0f) == 1.0f);
  CHECK(std::isinf(hd_powf(0.0f, -1.0f)));
  CHECK(hd_powf(1.0f, 1e30f) == 1.0f);
  CHECK(hd_powf(4.0f, 0.5f) == 2.0f);
  CHECK(std::isnan(hd_powf(-1.0f, 0.5f)));
  CHECK(std::isnan(hd_powf(NAN, 2.0f)));
}

TEST_CASE("hd_expf is exp within an ulp", "[hd_math]") {
  double worst = 0;
  for (float x = -100.0f; x <= 80.0f; x += 0.00137f)
    worst = std::max(worst, ulps(hd_expf(x), std::exp(static_cast<long double>(x))));
  INFO("worst " << worst << " ulp");
  CHECK(worst <= 1.0);
  CHECK(hd_expf(0.0f) == 1.0f);
  CHECK(hd_expf(-200.0f) == 0.0f);
  CHECK(std::isinf(hd_expf(200.0f)));
}

TEST_CASE("hd_atan2f is atan2 within an ulp, signed zeros included", "[hd_math]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> d(-100.0f, 100.0f);
  double worst = 0;
  for (int i = 0; i < 200000; i++) {
    const float y = d(rng), x = i % 7 == 0 ? 0.0f : d(rng);
    worst = std::max(worst, ulps(hd_atan2f(y, x), std::atan2(static_cast<long double>(y), static_cast<long double>(x))));
  }
  INFO("worst " << worst << " ulp");
  CHECK(worst <= 1.0);
  for (float y : {0.0f, -0.0f, 1.0f, -1.0f})
    for (float x : {0.0f, -0.0f, 1.0f, -1.0f}) {
      INFO(y << ", " << x);
      CHECK(hd_atan2f(y, x) == std::atan2(y, x));
    }
}

TEST_CASE("the sRGB transfer round-trips every 8-bit code", "[hd_math]") {
  for (int k = 0; k <= 255; k++) {
    const float c = k / 255.0f;
    CHECK(std::lround(linear_to_srgb(srgb_to_linear(c)) * 255.0f) == k);
  }
}

// Units in the last place of double between got and want.
double ulps_d(double got, long double want) {
  const double w = static_cast<double>(want);
  if (got == w) return 0;
  const double gap = std::nextafter(std::fabs(w), INFINITY) - std::fabs(w);
  return static_cast<double>(std::fabs(static_cast<long double>(got) - want) / gap);
}

TEST_CASE("hd_sincos_d, hd_atan2_d and hd_log2_d are within a few double ulps", "[hd_math]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-1000.0, 1000.0), small(-4.0, 4.0);
  double worst_sin = 0, worst_cos = 0, worst_atan = 0, worst_log = 0;
  for (int i = 0; i < 300000; i++) {
    const double x = i % 2 ? d(rng) : small(rng), y = d(rng);
    double s, c;
    hd_sincos_d(x, &s, &c);
    const long double lx = x;
    // Away from the zeros, where a double ulp of the argument is many of the value.
    const long double ls = std::sin(lx), lc = std::cos(lx);
    if (std::fabs(ls) > 1e-6L) worst_sin = std::max(worst_sin, ulps_d(s, ls));
    if (std::fabs(lc) > 1e-6L) worst_cos = std::max(worst_cos, ulps_d(c, lc));
    worst_atan = std::max(worst_atan, ulps_d(hd_atan2_d(y, x), std::atan2(static_cast<long double>(y), lx)));
    const double p = std::fabs(y) + 1e-300;
    if (std::fabs(p - 1.0) > 1e-3) worst_log = std::max(worst_log, ulps_d(hd_log2_d(p), std::log2(static_cast<long double>(p))));
  }
  INFO("worst sin " << worst_sin << ", cos " << worst_cos << ", atan2 " << worst_atan << ", log2 " << worst_log << " ulp");
  CHECK(worst_sin <= 3.0);
  CHECK(worst_cos <= 3.0);
  CHECK(worst_atan <= 4.0);
  CHECK(worst_log <= 4.0);
}
