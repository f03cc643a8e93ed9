// The warps a user names (svg2png / pdf2png --warp, the library's and
// Python's warp settings), each a program of the warp language
// (warp_parse.h) run by the one interpreter (warp_program.h). A warp maps
// each output sample (x, y) of a w x h image to the scene point it shows,
// so the picture is the scene moved by the warp's inverse:
//
//   projective:a,b,c,d,e,f,g,h,i  X = (a x + b y + c) / (g x + h y + i),
//                                 Y = (d x + e y + f) / (g x + h y + i)
//   twist:ANGLE[,CX,CY,R]         samples turned about (CX, CY) (default
//                                 the image's centre) by ANGLE degrees
//                                 at the centre, falling linearly to none
//                                 at radius R (default half the diagonal)
//   lens:CX,CY,R,POWER            within radius R of (CX, CY), a sample at
//                                 distance r shows the scene at R (r/R)^POWER
//                                 (POWER > 1 magnifies the centre); outside,
//                                 the scene as it is
//   expr:X;Y                      a program of the warp language
#pragma once
#include <string>

#include "core/warp/warp_parse.h"

namespace mpvg {

// The program of a spec as above; throws ParseError with one line ("warp
// 'twist:...': ...") for a spec it cannot take.
WarpProgram warp_from_spec(const std::string& spec);

}  // namespace mpvg
