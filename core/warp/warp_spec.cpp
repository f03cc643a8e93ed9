// The named warps (warp_spec.h) written in the warp language, so that one
// parser and one interpreter serve them all: the spec's numbers are put
// into the program's text with 17 significant digits (a double's value
// read back exactly).
#include "core/warp/warp_spec.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/error.h"

namespace mpvg {

namespace {

[[noreturn]] void fail(const std::string& spec, const std::string& what) {
  throw ParseError("warp '" + spec + "': " + what);
}

// The comma-separated numbers after the spec's colon.
std::vector<double> numbers(const std::string& spec, const std::string& list) {
  std::vector<double> out;
  size_t i = 0;
  while (i <= list.size()) {
    const size_t j = std::min(list.find(',', i), list.size());
    double v = 0.0;
    const auto r = std::from_chars(list.data() + i, list.data() + j, v);
    if (i == j || r.ec != std::errc() || r.ptr != list.data() + j || !std::isfinite(v))
      fail(spec, "'" + list.substr(i, j - i) + "' is not a finite number");
    out.push_back(v);
    i = j + 1;
  }
  return out;
}

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "(%.17g)", v);
  return buf;
}

}  // namespace

WarpProgram warp_from_spec(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) fail(spec, "expected projective:, twist:, lens: or expr:");
  const std::string kind = spec.substr(0, colon), rest = spec.substr(colon + 1);
  std::string text;
  if (kind == "expr") {
    text = rest;
  } else if (kind == "projective") {
    const std::vector<double> m = numbers(spec, rest);
    if (m.size() != 9) fail(spec, "a projective warp takes 9 numbers, a 3 x 3 matrix by rows");
    text = "q = " + num(m[6]) + " * x + " + num(m[7]) + " * y + " + num(m[8]) + ";" +  //
           "(" + num(m[0]) + " * x + " + num(m[1]) + " * y + " + num(m[2]) + ") / q;" +
           "(" + num(m[3]) + " * x + " + num(m[4]) + " * y + " + num(m[5]) + ") / q";
  } else if (kind == "twist") {
    const std::vector<double> p = numbers(spec, rest);
    if (p.size() != 1 && p.size() != 4) fail(spec, "a twist takes ANGLE or ANGLE,CX,CY,R");
    if (p.size() == 4 && !(p[3] > 0.0)) fail(spec, "the radius R must be positive");
    const std::string cx = p.size() == 4 ? num(p[1]) : "w / 2", cy = p.size() == 4 ? num(p[2]) : "h / 2",
                      r = p.size() == 4 ? num(p[3]) : "hypot(w, h) / 2";
    text = "cx = " + cx + "; cy = " + cy + "; dx = x - cx; dy = y - cy;" +
           "t = " + num(p[0]) + " * pi / 180 * max(0, 1 - hypot(dx, dy) / " + r + ");" +
           "c = cos(t); s = sin(t);" + "cx + dx * c - dy * s; cy + dx * s + dy * c";
  } else if (kind == "lens") {
    const std::vector<double> p = numbers(spec, rest);
    if (p.size() != 4) fail(spec, "a lens takes CX,CY,R,POWER");
    if (!(p[2] > 0.0)) fail(spec, "the radius R must be positive");
    if (!(p[3] > 0.0)) fail(spec, "the power must be positive");
    // k = (r/R)^(POWER - 1): the scene distance over the sample distance,
    // 1 from the rim on (r/R clamped to 1), finite at the centre.
    text = "dx = x - " + num(p[0]) + "; dy = y - " + num(p[1]) + ";" + "k = clamp(hypot(dx, dy) / " + num(p[2]) +
           ", 1e-30, 1) ^ " + num(p[3] - 1.0) + ";" + num(p[0]) + " + dx * k; " + num(p[1]) + " + dy * k";
  } else {
    fail(spec, "unknown warp '" + kind + "' (projective, twist, lens or expr)");
  }
  try {
    return parse_warp_expression(text);
  } catch (const ParseError& e) {
    if (kind == "expr") throw;
    fail(spec, e.what());  // a built-in's text: a bug, reported as such
  }
}

}  // namespace mpvg
