// The warp language (README, "Warps"): the text of a user-defined warp,
// parsed once into the bytecode of core/warp/warp_program.h.
//
//   program  := { name '=' expr ';' } expr ';' expr [ ';' ]
//   expr     := term { ('+' | '-') term }
//   term     := unary { ('*' | '/') unary }
//   unary    := ('-' | '+') unary | power
//   power    := primary [ '^' unary ]          (right to left: 2^3^2 = 2^9)
//   primary  := number | name | function '(' expr { ',' expr } ')' | '(' expr ')'
//
// The two last expressions are the X and Y of the scene point that output
// sample (x, y) shows; names: x, y, w and h (the image's width and height
// in pixels), pi, e, and those bound before (a binding may not rebind a
// name). Functions: sin cos tan atan2(y, x) sqrt exp log pow(a, b) (as ^)
// hypot min max abs floor clamp(v, lo, hi) mix(a, b, t).
#pragma once
#include <string>
#include <vector>

#include "core/warp/warp_program.h"

namespace mpvg {

struct WarpProgram {
  std::vector<WarpOp> ops;
  int stack = 0;  // values on the stack at most
  int slots = 0;  // names bound
};

// The program of `text`; throws ParseError with one line, "warp
// expression, column N: ..." (N counts bytes from 1), for text that is not
// a program or that passes the bounds of warp_program.h (operations,
// stack, names) or kWarpMaxNesting levels of nesting.
constexpr int kWarpMaxNesting = 256;
WarpProgram parse_warp_expression(const std::string& text);

}  // namespace mpvg
