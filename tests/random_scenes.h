// Random scenes for tests: fills and nested clip groups over random curved
// paths, full-cover rectangles (F1/C1 candidates in every cell), doubly
// wound ones (F0/C0 under even-odd) and half-plane boxes; solid paints, or
// paints of every kind (sweep gradients among them only when asked, so that
// the scenes of existing seeds stay what they were).
#pragma once
#include <random>

#include "core/scene.h"
#include "tests/oracle.h"
#include "frame/scene_builder.h"

namespace mpvg::random_scenes {

struct Gen {
  std::mt19937 rng;
  SceneBuilder& b;
  int max_depth;
  double size;
  // Paints of every kind (gradients, textures, patterns; opaque or not),
  // not only solid colours.
  bool rich_paints = false;
  // Half the paths drawn without antialiasing (ScenePath::aliased).
  bool aliased = false;
  // With rich paints: half the gradients become sweep gradients (their own
  // draws come after the others', so scenes without the flag are unchanged).
  bool sweep_gradients = false;

  Path shape() {
    std::uniform_int_distribution<int> kind(0, 9);
    const int k = kind(rng);
    Path p;
    if (k <= 1) {
      // Covers the whole image: F1 / C1 candidates in every cell.
      p.move_to({-10, -10});
      p.line_to({size + 10, -10});
      p.line_to({size + 10, size + 10});
      p.line_to({-10, size + 10});
      p.close();
      if (k == 1) {  // twice, same orientation: winding 2 (even-odd: F0 / C0)
        p.move_to({-12, -12});
        p.line_to({size + 12, -12});
        p.line_to({size + 12, size + 12});
        p.line_to({-12, size + 12});
        p.close();
      }
      return p;
    }
    if (k == 2) {  // a half-plane-ish box
      std::uniform_int_distribution<int> c(0, static_cast<int>(size));
      const double x = c(rng), y = c(rng);
      p.move_to({x, -10});
      p.line_to({size + 10, -10});
      p.line_to({size + 10, y});
      p.line_to({x, y});
      p.close();
      return p;
    }
    return oracle::random_path(rng, -8.0, size + 8.0, 1 + k % 2, 5);
  }

  bool alias() { return aliased && std::bernoulli_distribution(0.5)(rng); }

  FillRule rule() { return std::bernoulli_distribution(0.5)(rng) ? FillRule::EvenOdd : FillRule::NonZero; }

  Paint paint() {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Paint p;
    p.color = RGBA{u(rng), u(rng), u(rng), std::bernoulli_distribution(0.5)(rng) ? 1.0f : u(rng)};
    if (!rich_paints) return p;
    const int kind = std::uniform_int_distribution<int>(0, 4)(rng);
    const bool opaque = std::bernoulli_distribution(0.6)(rng);
    std::uniform_real_distribution<double> c(0.0, size);
    if (kind == 1 || kind == 2) {
      Gradient g;
      g.p0 = {c(rng), c(rng)};
      g.p1 = {c(rng), c(rng)};
      g.center = {c(rng), c(rng)};
      g.radius = 5 + c(rng) / 2;
      // Inside the end circle (the plane covered: opaque candidates) or anywhere.
      g.focal = std::bernoulli_distribution(0.5)(rng) ? g.center : Vec2{c(rng), c(rng)};
      for (int i = 0; i < 3; i++)
        g.stops.push_back({0.5 * i, RGBA{u(rng), u(rng), u(rng), opaque ? 1.0f : u(rng)}});
      g.spread = static_cast<Spread>(std::uniform_int_distribution<int>(0, 2)(rng));
      g.interpolation = std::bernoulli_distribution(0.5)(rng) ? ColorSpace::Srgb : ColorSpace::LinearRgb;
      p.type = kind == 1 ? PaintType::LinearGradient : PaintType::RadialGradient;
      if (sweep_gradients && std::bernoulli_distribution(0.5)(rng)) {
        // Any angles: backwards, past 360, negative, and now and then equal
        // (a pad step, or nothing for repeat and reflect); a skewed or
        // flipped gradient space about the centre.
        std::uniform_real_distribution<double> angle(-400.0, 400.0);
        g.start_angle = angle(rng);
        const int span = std::uniform_int_distribution<int>(0, 4)(rng);
        g.end_angle = span == 0 ? g.start_angle : span == 1 ? g.start_angle + 720 * u(rng) : angle(rng);
        g.extend_start = std::bernoulli_distribution(0.8)(rng);
        g.extend_end = std::bernoulli_distribution(0.8)(rng);
        g.xf = Affine::translate(g.center.x, g.center.y) *
               Affine::scale(std::bernoulli_distribution(0.3)(rng) ? -1.0 : 1.0, 0.5 + u(rng)) *
               Affine::skew_x_degrees(40 * u(rng) - 20) * Affine::translate(-g.center.x, -g.center.y);
        p.type = PaintType::SweepGradient;
      }
      p.index = b.add_gradient(g);
    } else if (kind == 3) {
      auto im = std::make_shared<Image>();
      im->width = std::uniform_int_distribution<int>(1, 9)(rng);
      im->height = std::uniform_int_distribution<int>(1, 9)(rng);
      std::uniform_int_distribution<int> byte(0, 255);
      for (int i = 0; i < im->width * im->height; i++)
        for (int k = 0; k < 4; k++) im->rgba8.push_back(uint8_t(k == 3 && opaque ? 255 : byte(rng)));
      Texture t;
      t.image = im;
      // From minified 4x to magnified 8x, rotated.
      const double scale = std::exp(std::uniform_real_distribution<double>(-1.4, 2.1)(rng));
      t.xf = Affine::translate(c(rng), c(rng)) * Affine::rotate_degrees(360 * u(rng)) * Affine::scale(scale, scale);
      t.filter = static_cast<TextureFilter>(std::uniform_int_distribution<int>(0, 2)(rng));
      t.wrap_x = static_cast<TextureWrap>(std::uniform_int_distribution<int>(0, 2)(rng));
      t.wrap_y = static_cast<TextureWrap>(std::uniform_int_distribution<int>(0, 2)(rng));
      p.type = PaintType::Texture;
      p.index = b.add_texture(t);
    } else if (kind == 4) {
      // A small tile of two solid shapes.
      SceneBuilder tb(7 + 10 * u(rng), 5 + 10 * u(rng));
      Gen inner{std::mt19937(rng()), tb, 0, 12.0};
      inner.aliased = aliased;
      tb.fill(tb.add_geometry(oracle::random_path(inner.rng, -2.0, 14.0, 1, 4)), Affine{}, inner.rule(), inner.paint(),
              inner.alias());
      tb.fill(tb.add_geometry(oracle::random_path(inner.rng, -2.0, 14.0, 2, 4)), Affine{}, inner.rule(), inner.paint(),
              inner.alias());
      Pattern pt;
      pt.tile = std::make_shared<Scene>(tb.finish());
      pt.xf = Affine::translate(c(rng), c(rng)) * Affine::rotate_degrees(360 * u(rng)) * Affine::scale(0.5 + u(rng), 0.5 + u(rng));
      p.type = PaintType::Pattern;
      p.index = b.add_pattern(pt);
    }
    return p;
  }

  void fill_list(int depth) {
    const int n = std::uniform_int_distribution<int>(1, 4)(rng);
    for (int i = 0; i < n; i++) {
      if (depth < max_depth && std::bernoulli_distribution(0.4)(rng)) {
        b.push();
        clip_union(depth + 1);
        b.activate();
        fill_list(depth + 1);
        b.pop();
      } else {
        b.fill(b.add_geometry(shape()), Affine{}, rule(), paint(), alias());
      }
    }
  }

  void clip_union(int depth) {
    const int n = std::uniform_int_distribution<int>(0, 3)(rng);
    for (int i = 0; i < n; i++) {
      if (depth < max_depth && std::bernoulli_distribution(0.3)(rng)) {
        b.push();
        clip_union(depth + 1);
        b.activate();
        clip_union(depth + 1);
        b.pop();
      } else {
        b.clip(b.add_geometry(shape()), Affine{}, rule(), alias());
      }
    }
  }
};

inline Scene clip_scene(uint32_t seed, int max_depth, int size, bool rich_paints = false, bool aliased = false,
                        bool sweep_gradients = false) {
  SceneBuilder b(size, size);
  Gen g{std::mt19937(seed), b, max_depth, double(size)};
  g.rich_paints = rich_paints;
  g.aliased = aliased;
  g.sweep_gradients = sweep_gradients;
  g.fill_list(0);
  return b.finish();
}

}  // namespace mpvg::random_scenes
