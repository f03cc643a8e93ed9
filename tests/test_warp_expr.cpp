// The warp language (core/warp/warp_parse.h), the named warps
// (core/warp/warp_spec.h) and the interpreter
// (core/warp/warp_program.h): precedence and associativity, every function
// against the hd_math / IEEE operation it stands for (bit for bit),
// bindings, error lines with their columns, and hostile text (a million
// terms, deep nesting) refused in one line.
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include "core/error.h"
#include "core/warp/warp_parse.h"
#include "core/warp/warp_spec.h"
#include "tests/catch.h"

using namespace mpvg;

namespace {

struct Point {
  double x, y;
};

Point run_program(const WarpProgram& p, double x, double y, double w, double h) {
  Point out{NAN, NAN};
  REQUIRE(warp_run(p.ops.data(), uint32_t(p.ops.size()), x, y, w, h, &out.x, &out.y));
  return out;
}

Point run(const std::string& text, double x = 3.0, double y = 5.0, double w = 640.0, double h = 480.0) {
  return run_program(parse_warp_expression(text), x, y, w, h);
}

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The error line of make(text), or "(no error)".
template <class Make>
std::string error_from(Make make, const std::string& text) {
  try {
    make(text);
  } catch (const ParseError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string error_of(const std::string& text) { return error_from(parse_warp_expression, text); }

}  // namespace

TEST_CASE("warp language: precedence, associativity and the names", "[warp]") {
  CHECK(run("2 + 3 * 4; 2 ^ 3 ^ 2").x == 14.0f);
  CHECK(run("2 + 3 * 4; 2 ^ 3 ^ 2").y == 512.0f);
  CHECK(run("-2 ^ 2; (-2) ^ 2").x == -4.0f);
  CHECK(run("-2 ^ 2; (-2) ^ 2").y == 4.0f);
  CHECK(run("(-2) ^ 3; (-2) ^ 0.5").x == -8.0f);
  CHECK(std::isnan(run("(-2) ^ 3; (-2) ^ 0.5").y));
  CHECK(run("10 - 4 - 3; 64 / 4 / 2").x == 3.0f);
  CHECK(run("10 - 4 - 3; 64 / 4 / 2").y == 8.0f);  // (64 / 4) / 2, not 64 / (4 / 2)
  CHECK(run("2 * -3; --3").x == -6.0f);
  CHECK(run("2 * -3; --3").y == 3.0f);
  const Point p = run("x + w; y * h;", 1.5, 2.5, 100.0, 10.0);
  CHECK(p.x == 101.5f);
  CHECK(p.y == 25.0f);
  CHECK(run("pi; e").x == 3.14159265358979323846);
  CHECK(run("pi; e").y == 2.71828182845904523536);
  CHECK(run("1.5e2; .25").x == 150.0f);
  CHECK(run("1.5e2; .25").y == 0.25f);
}

TEST_CASE("warp language: the identity gives each sample back, bit for bit", "[warp]") {
  for (double x : {0.0, 0.5, 1023.984375, -3.25, 1e-30, 0.3f - 3.5})
    for (double y : {0.0, 767.5, 1e7}) {
      const Point p = run("x; y", x, y);
      CHECK(same(p.x, x));
      CHECK(same(p.y, y));
    }
}

TEST_CASE("warp language: each function is the operation it names, bit for bit", "[warp]") {
  const double a = 0.7, b = -2.3, c = 4.1;
  auto one = [&](const std::string& f) { return run(f + "; 0", a, b, c, 0.0).x; };
  double s, co;
  hd_sincos_d(a, &s, &co);
  CHECK(same(one("sin(x)"), s));
  CHECK(same(one("tan(x)"), s / co));
  hd_sincos_d(b, &s, &co);
  CHECK(same(one("cos(y)"), co));
  CHECK(same(one("atan2(y, x)"), hd_atan2_d(b, a)));
  CHECK(same(one("sqrt(w)"), std::sqrt(c)));
  CHECK(same(one("exp(y)"), hd_exp2_d(b * 1.44269504088896340736)));
  CHECK(same(one("log(w)"), hd_log2_d(c) * 0.69314718055994530942));
  CHECK(same(one("pow(w, x)"), hd_exp2_d(a * hd_log2_d(c))));
  CHECK(same(one("w ^ x"), hd_exp2_d(a * hd_log2_d(c))));
  CHECK(same(one("hypot(x, y)"), std::sqrt(a * a + b * b)));
  CHECK(same(one("min(x, y)"), b));
  CHECK(same(one("max(x, y)"), a));
  CHECK(same(one("abs(y)"), 2.3));
  CHECK(same(one("floor(y)"), -3.0));
  CHECK(same(one("clamp(w, y, x)"), a));
  CHECK(same(one("clamp(0.5, y, x)"), 0.5));
  CHECK(same(one("mix(x, w, 0.25)"), a + (c - a) * 0.25));
  // Within a few ulps of the functions they approximate.
  CHECK(std::fabs(one("exp(y)") - std::exp(b)) < 1e-15);
  CHECK(std::fabs(one("log(w)") - std::log(c)) < 1e-15);
  CHECK(std::fabs(one("w ^ x") - std::pow(c, a)) < 1e-14);
  CHECK(std::isinf(run("log(0); 0").x));
  CHECK(std::isnan(run("log(-1); 0").x));
  CHECK(std::isnan(run("sin(1 / 0); 0").x));
}

TEST_CASE("warp language: bindings, the paper's twist written out", "[warp]") {
  const std::string twist =
      "cx = w / 2; cy = h / 2; r = hypot(x - cx, y - cy);"
      "t = atan2(y - cy, x - cx) + 2 * exp(-r / 100);"
      "cx + r * cos(t); cy + r * sin(t)";
  const double x = 400.25, y = 123.5, w = 1024.0, h = 768.0;
  const Point p = run(twist, x, y, w, h);
  const double cx = w / 2, cy = h / 2;
  const double r = std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy));
  const double t = hd_atan2_d(y - cy, x - cx) + 2 * hd_exp2_d(-r / 100 * 1.44269504088896340736);
  double s, c;
  hd_sincos_d(t, &s, &c);
  CHECK(same(p.x, cx + r * c));
  CHECK(same(p.y, cy + r * s));
  const WarpProgram prog = parse_warp_expression(twist);
  CHECK(prog.slots == 4);
  CHECK(prog.stack <= 6);
}

TEST_CASE("warp language: one error line with its column", "[warp]") {
  CHECK(error_of("x +; y") == "warp expression, column 4: expected a value, found ';'");
  CHECK(error_of("x") == "warp expression, column 2: expected ';' and the Y expression after the X expression");
  CHECK(error_of("x; y; z") == "warp expression, column 7: unexpected 'z' after the Y expression");
  CHECK(error_of("foo(x); y") == "warp expression, column 1: unknown function 'foo'");
  CHECK(error_of("x; q") == "warp expression, column 4: unknown name 'q'");
  CHECK(error_of("sin(x, y); y") == "warp expression, column 6: 'sin' takes 1 argument");
  CHECK(error_of("atan2(x); y") == "warp expression, column 8: 'atan2' takes 2 arguments");
  CHECK(error_of("(x; y") == "warp expression, column 3: expected ')' to close the '(' at column 1");
  CHECK(error_of("1e999; y") == "warp expression, column 1: '1e999' is not a finite number");
  CHECK(error_of("x = 1; x; y") == "warp expression, column 1: 'x' is already defined");
  CHECK(error_of("a = 1; a = 2; a; a") == "warp expression, column 8: 'a' is already defined");
  CHECK(error_of("sin = 1; x; y") == "warp expression, column 1: 'sin' is a function, not a name to bind");
  CHECK(error_of("a = b; a; a") == "warp expression, column 5: unknown name 'b'");
  CHECK(error_of("x # 2; y") == "warp expression, column 3: expected ';' and the Y expression after the X expression");
  CHECK(error_of("") == "warp expression, column 1: expected a value, found the end of the text");
}

TEST_CASE("warp language: hostile text is refused in one line, in linear time", "[warp]") {
  const auto t0 = std::chrono::steady_clock::now();
  std::string terms = "x";
  for (int i = 0; i < 1000000; i++) terms += "+x";
  CHECK(error_of(terms + "; y").find("more than 65536 operations") != std::string::npos);
  const std::string deep = std::string(1000000, '(') + "x" + std::string(1000000, ')') + "; y";
  CHECK(error_of(deep).find("nested deeper than 256 levels") != std::string::npos);
  CHECK(error_of(std::string(1000000, '-') + "x; y").find("nested deeper than 256 levels") != std::string::npos);
  std::string pending = "x";
  for (int i = 0; i < 70; i++) pending = "x + (" + pending + ")";
  CHECK(error_of(pending + "; y").find("values pending at once") != std::string::npos);
  std::string names;
  for (int i = 0; i < 65; i++) names += "a" + std::to_string(i) + " = 1;";
  CHECK(error_of(names + "x; y").find("more than 64 names bound") != std::string::npos);
  CHECK(error_of(std::string(100, '1') + "; y").find("longer than 64 characters") != std::string::npos);
  // A large program within the bounds evaluates.
  std::string sum = "x";
  for (int i = 0; i < 20000; i++) sum += "+1";
  CHECK(run(sum + "; y", 0.0).x == 20000.0);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  INFO(s << " s");
  CHECK(s < 10.0);
}


namespace {

Point run_spec(const std::string& spec, double x, double y, double w = 640.0, double h = 480.0) {
  return run_program(warp_from_spec(spec), x, y, w, h);
}

std::string spec_error(const std::string& spec) { return error_from(warp_from_spec, spec); }

}  // namespace

TEST_CASE("named warps: projective, twist and lens map samples as their formulas say", "[warp]") {
  // Projective: the identity exactly; a homography against the formula.
  for (double x : {0.0, 17.25, 639.5}) {
    const Point p = run_spec("projective:1,0,0,0,1,0,0,0,1", x, 100.5);
    CHECK(same(p.x, x));
    CHECK(same(p.y, 100.5));
  }
  const Point q = run_spec("projective:2,0.5,10,0.25,1,-3,0.001,0.002,1", 40.0, 20.0);
  const double den = 0.001 * 40.0 + 0.002 * 20.0 + 1.0;
  CHECK(same(q.x, (2.0 * 40.0 + 0.5 * 20.0 + 10.0) / den));
  CHECK(same(q.y, (0.25 * 40.0 + 1.0 * 20.0 + -3.0) / den));
  // Twist: the centre stays; a point at radius r < R turns by ANGLE (1 - r/R)
  // about the centre, keeping its distance; beyond R nothing turns.
  const Point c = run_spec("twist:90", 320.0f, 240.0f);
  CHECK(c.x == 320.0f);
  CHECK(c.y == 240.0f);
  const Point t = run_spec("twist:90,100,100,50", 125.0f, 100.0f);  // r = 25: turned by 45 degrees
  CHECK(std::fabs(t.x - (100.0f + 25.0f * std::cos(0.78539816339744831))) < 1e-9);
  CHECK(std::fabs(t.y - (100.0f + 25.0f * std::sin(0.78539816339744831))) < 1e-9);
  const Point o = run_spec("twist:90,100,100,50", 170.0f, 100.0f);
  CHECK(o.x == 170.0f);
  CHECK(o.y == 100.0f);
  // Lens: r -> R (r/R)^POWER inside, unchanged outside, the centre fixed.
  const Point l = run_spec("lens:100,100,40,2", 110.0f, 100.0f);  // r = 10: shows r = 40 (10/40)^2 = 2.5
  CHECK(std::fabs(l.x - 102.5) < 1e-12);
  CHECK(l.y == 100.0f);
  const Point m = run_spec("lens:100,100,40,2", 100.0f, 100.0f);
  CHECK(m.x == 100.0f);
  CHECK(m.y == 100.0f);
  const Point n = run_spec("lens:100,100,40,2", 150.0f, 130.0f);
  CHECK(n.x == 150.0f);
  CHECK(n.y == 130.0f);
  const Point e = run_spec("expr:x * 2; y + w", 3.0f, 4.0f);
  CHECK(e.x == 6.0f);
  CHECK(e.y == 644.0f);
}

TEST_CASE("named warps: a spec they cannot take is one error line", "[warp]") {
  CHECK(spec_error("twirl:3") == "warp 'twirl:3': unknown warp 'twirl' (projective, twist, lens or expr)");
  CHECK(spec_error("lens") == "warp 'lens': expected projective:, twist:, lens: or expr:");
  CHECK(spec_error("projective:1,2,3") == "warp 'projective:1,2,3': a projective warp takes 9 numbers, a 3 x 3 matrix by rows");
  CHECK(spec_error("twist:ab") == "warp 'twist:ab': 'ab' is not a finite number");
  CHECK(spec_error("twist:30,1,2") == "warp 'twist:30,1,2': a twist takes ANGLE or ANGLE,CX,CY,R");
  CHECK(spec_error("twist:30,1,2,0") == "warp 'twist:30,1,2,0': the radius R must be positive");
  CHECK(spec_error("lens:1,2,3,-1") == "warp 'lens:1,2,3,-1': the power must be positive");
  CHECK(spec_error("lens:1,,3,2") == "warp 'lens:1,,3,2': '' is not a finite number");
  CHECK(spec_error("expr:x;") == "warp expression, column 3: expected a value, found the end of the text");
}
