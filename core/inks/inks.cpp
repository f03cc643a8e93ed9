// Inks (core/inks/inks.h): passes, the per-channel rules of groups, and the
// RGB simulation of a press sheet.
#include "core/inks/inks.h"

#include <algorithm>

namespace mpvg {

std::vector<InkPass> ink_passes(int ink_count) {
  std::vector<InkPass> passes((std::max(ink_count, 1) + 2) / 3);
  for (int i = 0; i < ink_count; i++) passes[i / 3].inks[i % 3] = i;
  return passes;
}

void set_ink_blend(Group& g, const InkPass& pass) {
  if (g.blend == BlendMode::Normal || g.blend >= BlendMode::PlusLighter) return;
  g.subtractive = true;
  const bool separable = g.blend < BlendMode::Hue;
  for (int k = 0; k < 3; k++) {
    const int ink = pass.inks[k];
    if (separable || ink < 3) {
      g.channels[k] = ChannelRule::Blend;  // C, M, Y together as complemented RGB
    } else if (ink == 3) {
      g.channels[k] = g.blend == BlendMode::Luminosity ? ChannelRule::Source : ChannelRule::Backdrop;
    } else {
      g.channels[k] = ChannelRule::Source;  // spots (and empty channels): Normal
    }
  }
}

bool overprint_group(const InkPass& pass, const std::vector<bool>& painted, Group* g) {
  bool all = true;
  Group out;
  for (int k = 0; k < 3; k++) {
    const int ink = pass.inks[k];
    const bool p = ink >= 0 && ink < static_cast<int>(painted.size()) && painted[ink];
    if (!p && ink >= 0) {
      out.channels[k] = ChannelRule::Backdrop;
      all = false;
    }
  }
  if (all) return false;
  *g = out;
  return true;
}

void inks_to_rgb(const float* inks, int ink_count, const std::vector<float>& spot_cmyk, float rgb[3]) {
  float cmyk[4] = {0, 0, 0, 0};
  for (int k = 0; k < std::min(ink_count, kProcessInks); k++) cmyk[k] = inks[k];
  for (int s = 0; s + kProcessInks < ink_count && size_t(4 * s + 3) < spot_cmyk.size(); s++)
    for (int k = 0; k < 4; k++) cmyk[k] += inks[kProcessInks + s] * spot_cmyk[4 * s + k];
  for (int k = 0; k < 3; k++) rgb[k] = 1.0f - std::min(1.0f, cmyk[k] + cmyk[3]);
}

}  // namespace mpvg
