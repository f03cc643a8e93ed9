// Real roots of a t^2 - 2 b t + c = 0 (note the -2b), after Blinn, "How to
// solve a quadratic equation" (IEEE CG&A 2005): pick, for each root, the
// formula that adds numbers of the same sign, so that no root loses its
// significant digits to cancellation:
//   q = b + sign(b) sqrt(b^2 - a c),   roots q / a and c / q.
// Degenerate cases (a == 0: linear; a == b == 0: none or all) are explicit.
#pragma once
#include <cmath>

#include "core/hd.h"

namespace mpvg {

// Writes the real roots in ascending order; returns how many (0, 1 or 2).
// A double root is reported once. An identically zero polynomial has no
// isolated roots and reports none.
MPVG_HD_INLINE int solve_quadratic(double a, double b, double c, double roots[2]) {
  if (a == 0.0) {
    if (b == 0.0) return 0;
    roots[0] = c / (2.0 * b);
    return 1;
  }
  const double disc = b * b - a * c;
  if (disc < 0.0) return 0;
  if (disc == 0.0) {
    roots[0] = b / a;
    return 1;
  }
  const double sq = sqrt(disc);
  const double q = b >= 0.0 ? b + sq : b - sq;
  double r0 = q / a;
  double r1 = c / q;  // q != 0: |q| >= sqrt(disc) > 0
  if (r0 > r1) {
    const double t = r0;
    r0 = r1;
    r1 = t;
  }
  roots[0] = r0;
  roots[1] = r1;
  return r0 == r1 ? 1 : 2;
}

}  // namespace mpvg
