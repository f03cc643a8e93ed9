// A reference compositor for tests, deliberately simple and independent of
// core/'s sampler: a scene described as a tree (fills, clip groups,
// transparency groups with masks) is rendered at a set of points by
// allocating one buffer per group, filling it with the group's content in
// painter's order, and compositing it onto its parent's buffer, all in
// double precision, as PDF 32000-1 §11.4 and W3C Compositing and Blending
// Level 1 describe it, with a shape of 0 or 1 at every point:
//   - isolated groups start transparent; non-isolated ones start from their
//     backdrop, and at the end its contribution is removed:
//     result = composite - (1 - alpha_g) backdrop, alpha_g the union of the
//     elements' alphas;
//   - a non-isolated group that changes nothing (opacity 1, normal, no
//     mask, not knockout, in a list that is not knockout) is no group: its
//     content composites straight onto the list it is in, as SceneBuilder
//     dissolves it. (The removal above would give the same colour, but as
//     alpha the union of the elements' alphas, which is not the alpha of a
//     composite with xor or source-atop in it.)
//   - in a knockout group every element is composited onto the group's
//     initial backdrop and replaces what came before where it covers; a
//     group covers where one of its fills does and its mask is not 0;
//   - a group's result times its opacity and its mask value is blended
//     onto its parent with its blend mode (source-over with B(Cb, Cs)), or
//     composited with its Porter-Duff operator (plus-lighter, source-atop,
//     xor: Compositing 1 §9.1 with Fa, Fb, and Compositing 2's clamped sum);
//   - a mask is a group evaluated on its own (isolated, whatever its
//     Group says, as SceneBuilder makes it): its result (times its own
//     mask) over its backdrop colour gives the luminance (weights . rgb of
//     the premultiplied colour) or the alpha, times its opacity, clamped to
//     [0, 1].
// The blend functions are the specification's, transcribed in double.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/paint/blend.h"
#include "core/scene.h"
#include "frame/scene_builder.h"

namespace mpvg::reference {

using D3 = std::array<double, 3>;
using D4 = std::array<double, 4>;  // premultiplied r, g, b, a

inline double lum(const D3& c) { return 0.3 * c[0] + 0.59 * c[1] + 0.11 * c[2]; }

inline D3 clip_color(D3 c) {
  const double l = lum(c);
  const double n = std::min({c[0], c[1], c[2]}), x = std::max({c[0], c[1], c[2]});
  if (n < 0)
    for (double& v : c) v = l + (v - l) * l / (l - n);
  if (x > 1)
    for (double& v : c) v = l + (v - l) * (1 - l) / (x - l);
  return c;
}

inline D3 set_lum(const D3& c, double l) {
  const double d = l - lum(c);
  return clip_color({c[0] + d, c[1] + d, c[2] + d});
}

inline double sat(const D3& c) { return std::max({c[0], c[1], c[2]}) - std::min({c[0], c[1], c[2]}); }

inline D3 set_sat(const D3& c, double s) {
  // The spec's pseudocode on sorted channel indices.
  std::array<int, 3> i{0, 1, 2};
  std::sort(i.begin(), i.end(), [&](int a, int b) { return c[a] > c[b]; });
  D3 out{};
  if (c[i[0]] > c[i[2]]) {
    out[i[1]] = (c[i[1]] - c[i[2]]) * s / (c[i[0]] - c[i[2]]);
    out[i[0]] = s;
  }
  out[i[2]] = 0;
  return out;
}

inline double channel(uint32_t mode, double cb, double cs) {
  switch (mode) {
    case BLEND_MULTIPLY: return cb * cs;
    case BLEND_SCREEN: return cb + cs - cb * cs;
    case BLEND_OVERLAY: return channel(BLEND_HARD_LIGHT, cs, cb);
    case BLEND_DARKEN: return std::min(cb, cs);
    case BLEND_LIGHTEN: return std::max(cb, cs);
    case BLEND_COLOR_DODGE: return cb == 0 ? 0 : cs == 1 ? 1 : std::min(1.0, cb / (1 - cs));
    case BLEND_COLOR_BURN: return cb == 1 ? 1 : cs == 0 ? 0 : 1 - std::min(1.0, (1 - cb) / cs);
    case BLEND_HARD_LIGHT: return cs <= 0.5 ? channel(BLEND_MULTIPLY, cb, 2 * cs) : channel(BLEND_SCREEN, cb, 2 * cs - 1);
    case BLEND_SOFT_LIGHT: {
      if (cs <= 0.5) return cb - (1 - 2 * cs) * cb * (1 - cb);
      const double d = cb <= 0.25 ? ((16 * cb - 12) * cb + 4) * cb : std::sqrt(cb);
      return cb + (2 * cs - 1) * (d - cb);
    }
    case BLEND_DIFFERENCE: return std::fabs(cb - cs);
    case BLEND_EXCLUSION: return cb + cs - 2 * cb * cs;
    default: return cs;
  }
}

inline D3 blend(uint32_t mode, const D3& cb, const D3& cs) {
  switch (mode) {
    case BLEND_HUE: return set_lum(set_sat(cs, sat(cb)), lum(cb));
    case BLEND_SATURATION: return set_lum(set_sat(cb, sat(cs)), lum(cb));
    case BLEND_COLOR: return set_lum(cs, lum(cb));
    case BLEND_LUMINOSITY: return set_lum(cb, lum(cs));
    default: return {channel(mode, cb[0], cs[0]), channel(mode, cb[1], cs[1]), channel(mode, cb[2], cs[2])};
  }
}

// Premultiplied source s onto premultiplied backdrop b with a Porter-Duff
// operator, as §9.1 writes them: co = cs Fa + cb Fb, ao = as Fa + ab Fb,
// and plus-lighter as the clamped sum.
inline D4 porter_duff(uint32_t mode, const D4& b, const D4& s) {
  D4 o{};
  if (mode == BLEND_PLUS_LIGHTER) {
    for (int k = 0; k < 4; k++) o[k] = std::min(1.0, s[k] + b[k]);
    return o;
  }
  const double as = s[3], ab = b[3];
  const double fa = mode == BLEND_SOURCE_ATOP ? ab : 1 - ab;  // source-atop: Fa = ab; xor: Fa = 1 - ab
  const double fb = 1 - as;                                   // both: Fb = 1 - as
  for (int k = 0; k < 4; k++) o[k] = s[k] * fa + b[k] * fb;
  return o;
}

// Premultiplied source s over premultiplied backdrop b (§5.8 with §9.1.4).
inline D4 over(uint32_t mode, const D4& b, const D4& s) {
  if (mode == BLEND_PLUS_LIGHTER || mode == BLEND_SOURCE_ATOP || mode == BLEND_XOR) return porter_duff(mode, b, s);
  const double as = s[3], ab = b[3];
  D3 m{};
  auto straight = [](const D4& c) {
    D3 o{};
    for (int k = 0; k < 3; k++) o[k] = std::clamp(c[k] / c[3], 0.0, 1.0);
    return o;
  };
  if (as > 0 && ab > 0) m = blend(mode, straight(b), straight(s));
  D4 o{};
  for (int k = 0; k < 3; k++) o[k] = (1 - ab) * s[k] + (1 - as) * b[k] + as * ab * m[k];
  o[3] = as + ab * (1 - as);
  return o;
}

// ------------------------------------------------------------ scenes

// A scene as a tree. Fills name their geometry by the index SceneBuilder
// gave it (so that a test can find each fill's winding number); clip
// groups hold a union of clip paths (and nested clip-path groups are left
// to the clip tests of test_pruning.cpp).
struct Node {
  enum Kind { Fill, ClipGroup, Transparency } kind = Fill;
  uint32_t geometry = 0;           // Fill
  FillRule rule = FillRule::NonZero;
  RGBA color;                      // Fill: straight, sRGB-encoded
  std::vector<std::pair<uint32_t, FillRule>> clips;  // ClipGroup: union of these paths
  Group group;                     // Transparency
  std::unique_ptr<Node> mask;      // Transparency: its mask (a Transparency node), or null
  std::vector<std::unique_ptr<Node>> children;  // painter's order
};

// Is geometry g (with rule r) inside at point p? Provided by the test.
struct Inside {
  virtual bool operator()(size_t point, uint32_t geometry, FillRule rule) const = 0;
  virtual ~Inside() = default;
};

// Renders `root` (an isolated group) at `points` points; inside(i, g, r)
// tells whether point i is inside geometry g.
class Compositor {
 public:
  Compositor(size_t points, const Inside& inside) : n_(points), inside_(inside) {}

  std::vector<D4> render(const Node& root) {
    std::vector<bool> all(n_, true), shape;
    return group(root, std::vector<D4>(n_, D4{}), all, shape);
  }

 private:
  using Buffer = std::vector<D4>;

  // The result of group `g` (a Transparency node) over `backdrop`, at the
  // points where `live` (points outside the clips around it need nothing);
  // `shape` receives where it covers. A mask is always isolated.
  Buffer group(const Node& g, const Buffer& backdrop, const std::vector<bool>& live, std::vector<bool>& shape) {
    const Group& p = g.group;
    const bool isolated = p.isolated || p.mask != MaskType::None;
    Buffer buf = isolated ? Buffer(n_, D4{}) : backdrop;  // one buffer per group
    const Buffer initial = buf;
    std::vector<double> alpha_g(n_, 0.0);
    shape.assign(n_, false);
    list(g.children, live, p.knockout, initial, buf, alpha_g, shape);
    if (!isolated)
      for (size_t i = 0; i < n_; i++)
        for (int k = 0; k < 4; k++) buf[i][k] = k == 3 ? alpha_g[i] : buf[i][k] - (1 - alpha_g[i]) * backdrop[i][k];
    return buf;
  }

  // The fill list `items` into `buf` at the points where `live`.
  void list(const std::vector<std::unique_ptr<Node>>& items, const std::vector<bool>& live, bool knockout,
            const Buffer& initial, Buffer& buf, std::vector<double>& alpha_g, std::vector<bool>& shape) {
    for (const auto& item : items) {
      if (item->kind == Node::ClipGroup) {
        std::vector<bool> inner(n_, false);
        for (size_t i = 0; i < n_; i++)
          for (const auto& [geo, rule] : item->clips) inner[i] = inner[i] || (live[i] && inside_(i, geo, rule));
        list(item->children, inner, knockout, initial, buf, alpha_g, shape);
        continue;
      }
      if (item->kind == Node::Transparency && !knockout && !item->mask && !item->group.isolated &&
          item->group.opacity == 1 && item->group.blend == BlendMode::Normal && !item->group.knockout &&
          item->group.mask == MaskType::None) {
        list(item->children, live, knockout, initial, buf, alpha_g, shape);
        continue;
      }
      Buffer src(n_, D4{});
      std::vector<bool> covers(n_, false);
      uint32_t mode = BLEND_NORMAL;
      if (item->kind == Node::Fill) {
        const double a = item->color.a;
        for (size_t i = 0; i < n_; i++) {
          covers[i] = live[i] && inside_(i, item->geometry, item->rule);
          src[i] = D4{item->color.r * a, item->color.g * a, item->color.b * a, a};
        }
      } else {
        mode = static_cast<uint32_t>(item->group.blend);
        const std::vector<double> m = mask(item->mask.get(), live);
        src = group(*item, knockout ? initial : buf, live, covers);
        for (size_t i = 0; i < n_; i++) {
          covers[i] = covers[i] && live[i] && m[i] > 0;
          for (double& c : src[i]) c *= item->group.opacity * m[i];
        }
      }
      for (size_t i = 0; i < n_; i++) {
        if (!covers[i]) continue;
        shape[i] = true;
        if (knockout) {
          buf[i] = over(mode, initial[i], src[i]);
          alpha_g[i] = src[i][3];
        } else {
          buf[i] = over(mode, buf[i], src[i]);
          alpha_g[i] = alpha_g[i] + src[i][3] - alpha_g[i] * src[i][3];
        }
      }
    }
  }

  // The values of mask `m` (1 everywhere without one).
  std::vector<double> mask(const Node* m, const std::vector<bool>& live) {
    std::vector<double> v(n_, 1.0);
    if (!m) return v;
    const std::vector<double> own = mask(m->mask.get(), live);
    std::vector<bool> shape;
    const Buffer r = group(*m, Buffer(n_, D4{}), live, shape);
    const Group& g = m->group;
    const double ba = g.backdrop.a;
    const D4 bc{g.backdrop.r * ba, g.backdrop.g * ba, g.backdrop.b * ba, ba};
    for (size_t i = 0; i < n_; i++) {
      D4 c = r[i];
      for (double& x : c) x *= own[i];
      double value = c[3];
      if (g.mask == MaskType::Luminance) {
        for (int k = 0; k < 4; k++) c[k] += (1 - r[i][3] * own[i]) * bc[k];
        value = g.luminance[0] * c[0] + g.luminance[1] * c[1] + g.luminance[2] * c[2];
      }
      v[i] = std::clamp(value, 0.0, 1.0) * g.opacity;
    }
    return v;
  }

  size_t n_;
  const Inside& inside_;
};

// ================================================================ inks
//
// The same compositor for pages in N inks (print preview; PDF 32000-1
// §8.6.6 separations, §11.3.4-11.3.5 blending, §11.7.4 overprint), written
// from the specification and not from core/inks/inks.cpp's passes: one colour is
// N ink amounts (0: none, the paper; 1: full) and an alpha, premultiplied,
// every point evaluated in all N channels at once, a buffer per group as
// above (isolated / non-isolated with the backdrop's contribution removed,
// knockout onto the initial backdrop, opacity once; no masks, no clip-path
// nesting beyond clip groups, no Porter-Duff operators). Nothing is
// dissolved: a group is always a group.
//   - compositing (§11.3.6) is source-over per ink with blend result B:
//       co = (1 - ab) cs + (1 - as) cb + as ab B(Cb / ab, Cs / as)
//       ao = as + ab (1 - as);
//     the formula is affine in the colour, so it reads the same on ink
//     amounts as on their complements; only B cares;
//   - the blending space is subtractive (§11.3.4): a separable mode's B
//     is applied to complemented values and complemented back,
//       B_sub(cb, cs) = 1 - B(1 - cb, 1 - cs),
//     for every ink, process and spot (§11.7.4.2: separable modes apply to
//     spot colorants too); Normal is B = cs either way;
//   - a non-separable mode (§11.3.5.3; Hue, Saturation, Color, Luminosity)
//     takes C, M, Y complemented as R, G, B, applies the RGB function and
//     complements back; K is the backdrop's for Hue, Saturation and Color
//     and the source's for Luminosity; spot inks blend as Normal (B = cs);
//   - overprint (§11.7.4.3, compatible overprint): a fill paints only the
//     inks its `painted` mask names (empty: all); an unpainted ink has the
//     source value 0 (the colour has no component for it) and B = Cb, so
//     that the backdrop's ink stays where the fill is opaque. The fill's
//     alpha and shape are the same for every ink; a fill painting nothing
//     still adds its alpha;
//   - a page is composited over the paper: opaque, no ink. Over it the ink
//     amounts of a premultiplied result stay what they are (c + (1 - a) 0)
//     and alpha becomes 1; a test that wants blend modes inside the page
//     to see the paper puts an opaque no-ink fill first.
namespace inks {

using Ink = std::vector<double>;  // N premultiplied ink amounts, then alpha

struct Node {
  enum Kind { Fill, ClipGroup, Transparency } kind = Fill;
  uint32_t geometry = 0;  // Fill: the geometry's index (SceneBuilder's)
  FillRule rule = FillRule::NonZero;
  std::vector<double> inks;  // Fill: N straight ink amounts in [0, 1]
  double alpha = 1;          // Fill
  std::vector<bool> painted;  // Fill: the inks it paints (empty: every ink)
  std::vector<std::pair<uint32_t, FillRule>> clips;  // ClipGroup: union of these paths
  Group group;  // Transparency: opacity, blend (the 16 modes), isolated, knockout
  std::vector<std::unique_ptr<Node>> children;  // painter's order
};

// B_sub of a separable mode on one ink.
inline double subtractive_channel(uint32_t mode, double cb, double cs) {
  return 1 - channel(mode, 1 - cb, 1 - cs);
}

// B(Cb, Cs) in N inks (straight), with `painted` (empty: all) telling
// which inks the source paints.
inline std::vector<double> blend_inks(uint32_t mode, const std::vector<double>& cb, const std::vector<double>& cs,
                                      const std::vector<bool>& painted) {
  const size_t n = cb.size();
  std::vector<double> m(n);
  if (mode < BLEND_HUE) {
    for (size_t i = 0; i < n; i++) m[i] = subtractive_channel(mode, cb[i], cs[i]);
  } else {
    const D3 b{1 - cb[0], 1 - cb[1], 1 - cb[2]}, s{1 - cs[0], 1 - cs[1], 1 - cs[2]};
    const D3 rgb = blend(mode, b, s);
    for (int i = 0; i < 3; i++) m[i] = 1 - rgb[i];
    m[3] = mode == BLEND_LUMINOSITY ? cs[3] : cb[3];
    for (size_t i = 4; i < n; i++) m[i] = cs[i];
  }
  for (size_t i = 0; i < n && i < painted.size(); i++)
    if (!painted[i]) m[i] = cb[i];
  return m;
}

// Is B(Cb, Cs) within `eps` of one of its discontinuities (straight ink
// values), where float arithmetic cannot decide which side the exact
// result is on? Hue's SetSat of the source's C, M, Y, and Saturation's of
// the backdrop's, jump at a grey (an exact grey gives grey, the least
// saturation a full hue); color-dodge (complemented) at cb = 0, cs = 1,
// i.e. backdrop ink 1 under source ink 0; color-burn at cb = 1, cs = 0,
// backdrop ink 0 under source ink 1.
inline bool near_discontinuity(uint32_t mode, const std::vector<double>& cb, const std::vector<double>& cs,
                               double eps) {
  auto range = [](const std::vector<double>& c) {
    return std::max({c[0], c[1], c[2]}) - std::min({c[0], c[1], c[2]});
  };
  if (mode == BLEND_HUE) return range(cs) < eps;
  if (mode == BLEND_SATURATION) return range(cb) < eps;
  for (size_t i = 0; i < cb.size(); i++) {
    if (mode == BLEND_COLOR_DODGE && cb[i] > 1 - eps && cs[i] < eps) return true;
    if (mode == BLEND_COLOR_BURN && cb[i] < eps && cs[i] > 1 - eps) return true;
  }
  return false;
}

// Premultiplied source s over premultiplied backdrop b (N inks + alpha);
// *fragile (if given) becomes true where B is near a discontinuity.
inline Ink over(uint32_t mode, const Ink& b, const Ink& s, const std::vector<bool>& painted = {},
                bool* fragile = nullptr) {
  const size_t n = b.size() - 1;
  const double as = s[n], ab = b[n];
  std::vector<double> m(n, 0.0);
  if (as > 0 && ab > 0) {
    std::vector<double> cb(n), cs(n);
    // Rounded to 2^-32 (far below float's precision, far above double's
    // noise): a grey that exact arithmetic gives (a backdrop removed from
    // itself, say) stays exactly grey, where Hue and Saturation's SetSat
    // would turn a difference of 1e-17 into a saturated colour.
    auto straight = [](double c, double a) { return std::ldexp(std::round(std::ldexp(std::clamp(c / a, 0.0, 1.0), 32)), -32); };
    for (size_t i = 0; i < n; i++) {
      cb[i] = straight(b[i], ab);
      cs[i] = straight(s[i], as);
    }
    m = blend_inks(mode, cb, cs, painted);
    if (fragile && near_discontinuity(mode, cb, cs, 1e-4)) *fragile = true;
  }
  Ink o(n + 1);
  for (size_t i = 0; i < n; i++) o[i] = (1 - ab) * s[i] + (1 - as) * b[i] + as * ab * m[i];
  o[n] = as + ab * (1 - as);
  return o;
}

// A result over the paper (opaque, no ink).
inline Ink over_paper(Ink c) {
  c.back() = 1;
  return c;
}

// Renders `root` (an isolated group over transparency) at `points` points
// in `ink_count` inks.
class Compositor {
 public:
  Compositor(size_t points, int ink_count, const Inside& inside)
      : n_(points), inks_(ink_count), inside_(inside), fragile_(points, false) {}

  std::vector<Ink> render(const Node& root) {
    std::vector<bool> all(n_, true), shape;
    fragile_.assign(n_, false);
    return group(root, Buffer(n_, Ink(inks_ + 1, 0.0)), all, shape);
  }

  // The points where some blend of the last render was near a
  // discontinuity of its function (near_discontinuity, within 1e-4):
  // there a float implementation may rightly land on the other side.
  const std::vector<bool>& ill_conditioned() const { return fragile_; }

 private:
  using Buffer = std::vector<Ink>;

  Buffer group(const Node& g, const Buffer& backdrop, const std::vector<bool>& live, std::vector<bool>& shape) {
    const Group& p = g.group;
    Buffer buf = p.isolated ? Buffer(n_, Ink(inks_ + 1, 0.0)) : backdrop;
    const Buffer initial = buf;
    std::vector<double> alpha_g(n_, 0.0);
    shape.assign(n_, false);
    list(g.children, live, p.knockout, initial, buf, alpha_g, shape);
    if (!p.isolated)
      for (size_t i = 0; i < n_; i++) {
        for (int k = 0; k < inks_; k++) buf[i][k] -= (1 - alpha_g[i]) * backdrop[i][k];
        buf[i][inks_] = alpha_g[i];
      }
    return buf;
  }

  void list(const std::vector<std::unique_ptr<Node>>& items, const std::vector<bool>& live, bool knockout,
            const Buffer& initial, Buffer& buf, std::vector<double>& alpha_g, std::vector<bool>& shape) {
    for (const auto& item : items) {
      if (item->kind == Node::ClipGroup) {
        std::vector<bool> inner(n_, false);
        for (size_t i = 0; i < n_; i++)
          for (const auto& [geo, rule] : item->clips) inner[i] = inner[i] || (live[i] && inside_(i, geo, rule));
        list(item->children, inner, knockout, initial, buf, alpha_g, shape);
        continue;
      }
      Buffer src(n_, Ink(inks_ + 1, 0.0));
      std::vector<bool> covers(n_, false);
      uint32_t mode = BLEND_NORMAL;
      std::vector<bool> painted;
      if (item->kind == Node::Fill) {
        painted = item->painted;
        Ink c(inks_ + 1, 0.0);
        for (int k = 0; k < inks_; k++) {
          const bool p = painted.empty() || painted[k];
          c[k] = p ? item->inks[k] * item->alpha : 0.0;  // an unpainted ink: source value 0
        }
        c[inks_] = item->alpha;
        for (size_t i = 0; i < n_; i++) {
          covers[i] = live[i] && inside_(i, item->geometry, item->rule);
          src[i] = c;
        }
      } else {
        mode = static_cast<uint32_t>(item->group.blend);
        src = group(*item, knockout ? initial : buf, live, covers);
        for (size_t i = 0; i < n_; i++) {
          covers[i] = covers[i] && live[i];
          for (double& c : src[i]) c *= item->group.opacity;
        }
      }
      for (size_t i = 0; i < n_; i++) {
        if (!covers[i]) continue;
        shape[i] = true;
        bool fragile = false;
        if (knockout) {
          buf[i] = over(mode, initial[i], src[i], painted, &fragile);
          alpha_g[i] = src[i][inks_];
        } else {
          buf[i] = over(mode, buf[i], src[i], painted, &fragile);
          alpha_g[i] = alpha_g[i] + src[i][inks_] - alpha_g[i] * src[i][inks_];
        }
        if (fragile) fragile_[i] = true;
      }
    }
  }

  size_t n_;
  int inks_;
  const Inside& inside_;
  std::vector<bool> fragile_;
};

}  // namespace inks

}  // namespace mpvg::reference
