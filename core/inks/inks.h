// Inks: the colour model of print preview (PDF 32000-1 §8.6.6 separations,
// §11.3.4-11.3.5 blending in subtractive spaces, §11.7.4 overprint). A
// page is drawn in N colorants, the process inks cyan, magenta, yellow and
// black and then the document's spot colours; a channel holds an ink
// amount in [0, 1], 0 none (the paper), and composites like any colour
// channel (source-over is the same formula per channel).
//
// Scenes carry three colour channels, so an ink page is drawn in passes:
// pass p carries inks 3p, 3p + 1, 3p + 2 in r, g, b (C, M, Y in pass 0; K
// and the first two spots in pass 1; ...), over a backdrop of no ink,
// integrated without any transfer (Gamma::Srgb: values as they are). Every
// sample of every pass is computed on its own, as the paper's samples
// are: the passes of one page are one N-channel evaluation, three channels
// at a time. What differs between channels is how groups meet their
// backdrop, which the scene's Group says per channel (ChannelRule):
//   - blend modes are subtractive: separable ones complement every ink
//     before and after B (multiply darkens, screen lightens, as on paper);
//     non-separable ones take C, M, Y complemented as R, G, B, give K the
//     backdrop's value (hue, saturation, color) or the source's
//     (luminosity), and blend spots with Normal (§11.3.5.3);
//   - overprint (§11.7.4.3, compatible overprint): an element that paints
//     only some inks (OP/op true: a Separation or DeviceN colour paints its
//     colorants; with OPM 1 a DeviceCMYK colour paints its non-zero
//     components) is a group of its own whose other channels keep the
//     backdrop (B = Cb), so that a black text overprinting a cyan
//     background leaves the cyan under it.
// The reference compositor of tests/ evaluates the same rules in N channels
// at once; test_inks checks the passes against it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene.h"

namespace mpvg {

// The process inks come first, in this order.
constexpr int kProcessInks = 4;

// What sits in each of a pass's three channels: an ink index, or -1.
struct InkPass {
  int inks[3] = {-1, -1, -1};
};

// The passes of n inks (n >= 1): ceil(n / 3).
std::vector<InkPass> ink_passes(int ink_count);

// Sets g's channel rules and subtractive flag for its blend mode in pass
// `pass` (Normal and the Porter-Duff operators change nothing).
void set_ink_blend(Group& g, const InkPass& pass);

// The group an element painting only the inks where painted[i] is true
// needs in `pass` (its other channels kept as the backdrop), into *g;
// false when it paints every ink of the pass (no group needed).
bool overprint_group(const InkPass& pass, const std::vector<bool>& painted, Group* g);

// An RGB rendering of ink amounts (a press sheet on screen, the simulation
// MuPDF and Ghostscript show without an ICC profile): spots add their CMYK
// equivalents (`spot_cmyk`, four per spot) times their amount to the
// process inks, clamped; then r = 1 - min(1, c + k), g and b likewise.
void inks_to_rgb(const float* inks, int ink_count, const std::vector<float>& spot_cmyk, float rgb[3]);

}  // namespace mpvg
