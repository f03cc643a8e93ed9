// Random scenes of nested transparency groups and masks, built twice: into
// a SceneBuilder, and as the reference compositor's tree
// (tests/reference_compositor.h). Every blend mode, isolated and
// non-isolated, knockout, opacity 0, 1 and between, luminance and alpha
// masks with transparent or opaque backdrops, masks on masks, clip groups
// around groups and inside masks, full-cover rectangles (so that pruning's
// rules fire), opaque and translucent colours. With porter_duff, groups
// also take the Porter-Duff operators (plus-lighter, source-atop, xor);
// without it the draws, and so every seed's scene, are what they were
// before those operators existed.
#pragma once
#include <memory>
#include <random>

#include "core/scene.h"
#include "tests/random_scenes.h"
#include "tests/reference_compositor.h"
#include "frame/scene_builder.h"

namespace mpvg::random_groups {

using reference::Node;

struct Gen {
  random_scenes::Gen shapes;  // geometry and fill rules
  int max_depth;
  bool porter_duff = false;  // groups' modes include plus-lighter, source-atop and xor

  std::mt19937& rng() { return shapes.rng; }
  SceneBuilder& b() { return shapes.b; }
  float u() { return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng()); }
  bool chance(double p) { return std::bernoulli_distribution(p)(rng()); }

  std::unique_ptr<Node> fill() {
    auto n = std::make_unique<Node>();
    n->kind = Node::Fill;
    n->geometry = b().add_geometry(shapes.shape());
    n->rule = shapes.rule();
    n->color = RGBA{u(), u(), u(), chance(0.5) ? 1.0f : u()};
    Paint p;
    p.color = n->color;
    b().fill(n->geometry, Affine{}, n->rule, p);
    return n;
  }

  std::unique_ptr<Node> clip_group(int depth) {
    auto n = std::make_unique<Node>();
    n->kind = Node::ClipGroup;
    b().push();
    const int clips = std::uniform_int_distribution<int>(1, 2)(rng());
    for (int i = 0; i < clips; i++) {
      const uint32_t g = b().add_geometry(shapes.shape());
      const FillRule r = shapes.rule();
      b().clip(g, Affine{}, r);
      n->clips.push_back({g, r});
    }
    b().activate();
    list(depth + 1, n->children);
    b().pop();
    return n;
  }

  Group params() {
    Group g;
    const float o = u();
    g.opacity = o < 0.4f ? 1.0f : o < 0.45f ? 0.0f : u();
    g.blend = chance(0.5) ? BlendMode::Normal : static_cast<BlendMode>(std::uniform_int_distribution<int>(1, 15)(rng()));
    // Drawn only with the flag: scenes without it stay the same.
    if (porter_duff && chance(0.4))
      g.blend = static_cast<BlendMode>(std::uniform_int_distribution<int>(int(BlendMode::PlusLighter), int(BlendMode::Xor))(rng()));
    g.isolated = chance(0.5);
    g.knockout = chance(0.2);
    return g;
  }

  std::unique_ptr<Node> mask(int depth) {
    auto n = std::make_unique<Node>();
    n->kind = Node::Transparency;
    n->group = params();
    n->group.mask = chance(0.5) ? MaskType::Luminance : MaskType::Alpha;
    if (n->group.opacity == 0.0f) n->group.opacity = 1.0f;
    if (chance(0.3)) n->group.backdrop = RGBA{u(), u(), u(), 1.0f};
    b().begin_group(n->group);
    if (depth < max_depth && chance(0.25)) n->mask = mask(depth + 1);
    list(depth + 1, n->children);
    b().end_group();
    return n;
  }

  std::unique_ptr<Node> group(int depth) {
    auto n = std::make_unique<Node>();
    n->kind = Node::Transparency;
    n->group = params();
    b().begin_group(n->group);
    if (depth < max_depth && chance(0.35)) n->mask = mask(depth + 1);
    list(depth + 1, n->children);
    b().end_group();
    return n;
  }

  void list(int depth, std::vector<std::unique_ptr<Node>>& out) {
    const int n = std::uniform_int_distribution<int>(1, 4)(rng());
    for (int i = 0; i < n; i++) {
      const float r = u();
      if (depth < max_depth && r < 0.35f)
        out.push_back(group(depth));
      else if (depth < max_depth && r < 0.45f)
        out.push_back(clip_group(depth));
      else
        out.push_back(fill());
    }
  }
};

struct GroupScene {
  Scene scene;
  Node root;  // an isolated group holding the top level
};

inline GroupScene group_scene(uint32_t seed, int max_depth, int size, bool porter_duff = false) {
  SceneBuilder b(size, size);
  Gen g{random_scenes::Gen{std::mt19937(seed), b, 0, double(size)}, max_depth, porter_duff};
  GroupScene out;
  out.root.kind = Node::Transparency;
  g.list(0, out.root.children);
  out.scene = b.finish();
  return out;
}

}  // namespace mpvg::random_groups
