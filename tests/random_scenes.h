// Random scenes for tests: fills and nested clip groups over random curved
// paths, full-cover rectangles (F1/C1 candidates in every cell), doubly
// wound ones (F0/C0 under even-odd) and half-plane boxes.
#pragma once
#include <random>

#include "core/scene.h"
#include "tests/oracle.h"

namespace mpvg::random_scenes {

struct Gen {
  std::mt19937 rng;
  SceneBuilder& b;
  int max_depth;
  double size;

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

  FillRule rule() { return std::bernoulli_distribution(0.5)(rng) ? FillRule::EvenOdd : FillRule::NonZero; }

  Paint paint() {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Paint p;
    p.color = RGBA{u(rng), u(rng), u(rng), std::bernoulli_distribution(0.5)(rng) ? 1.0f : u(rng)};
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
        b.fill(b.add_geometry(shape()), Affine{}, rule(), paint());
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
        b.clip(b.add_geometry(shape()), Affine{}, rule());
      }
    }
  }
};

inline Scene clip_scene(uint32_t seed, int max_depth, int size) {
  SceneBuilder b(size, size);
  Gen g{std::mt19937(seed), b, max_depth, double(size)};
  g.fill_list(0);
  return b.finish();
}

}  // namespace mpvg::random_scenes
