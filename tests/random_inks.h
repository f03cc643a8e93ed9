// Random ink pages (print preview, core/inks/inks.h) as the reference
// compositor's tree (tests/reference_compositor.h, namespace inks), and each
// of their passes built into a SceneBuilder the way a frontend builds it:
// a fill's colour is its three inks of the pass (0 where the pass has no
// ink), a fill that paints only some inks is wrapped in overprint_group()'s
// group where the pass needs one, and every group gets set_ink_blend()
// after its blend mode. N inks: CMYK and N - 4 spots. Fills draw ink
// amounts (a share exactly 0, as OPM 1 colours have), alphas 1 or between,
// and a third of them a painted mask (none, all, or random); groups draw
// every one of the 16 blend modes, opacity 0, 1 or between, isolation and
// knockout, nested with clip groups; half the pages start with an opaque
// no-ink fill (the paper inside the page, which blend modes then see).
#pragma once
#include <memory>
#include <random>

#include "core/inks/inks.h"
#include "core/scene.h"
#include "tests/random_scenes.h"
#include "tests/reference_compositor.h"
#include "frame/scene_builder.h"

namespace mpvg::random_inks {

using reference::inks::Node;

struct InkScene {
  int ink_count = 4;
  double size = 0;
  std::vector<Path> geometries;  // indexed by Node::geometry, clips' too
  Node root;                     // an isolated group holding the page
};

struct Gen {
  random_scenes::Gen shapes;  // geometry and fill rules (its builder unused)
  InkScene& out;
  int max_depth;

  std::mt19937& rng() { return shapes.rng; }
  float u() { return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng()); }
  bool chance(double p) { return std::bernoulli_distribution(p)(rng()); }
  uint32_t geometry(Path p) {
    out.geometries.push_back(std::move(p));
    return static_cast<uint32_t>(out.geometries.size() - 1);
  }

  std::unique_ptr<Node> fill() {
    auto n = std::make_unique<Node>();
    n->kind = Node::Fill;
    n->geometry = geometry(shapes.shape());
    n->rule = shapes.rule();
    // Values in [0, 1), a quarter exactly 0 (an exact 1 would sit on
    // color-dodge's and color-burn's discontinuities).
    for (int k = 0; k < out.ink_count; k++) n->inks.push_back(chance(0.25) ? 0.0 : double(u()));
    n->alpha = chance(0.5) ? 1.0 : double(u());
    if (chance(1.0 / 3)) {
      const float r = u();
      for (int k = 0; k < out.ink_count; k++) n->painted.push_back(r < 0.15f ? false : r < 0.3f ? true : chance(0.5));
      // A colour has no value for an ink it does not paint.
      for (int k = 0; k < out.ink_count; k++)
        if (!n->painted[k]) n->inks[k] = 0;
    }
    return n;
  }

  std::unique_ptr<Node> clip_group(int depth) {
    auto n = std::make_unique<Node>();
    n->kind = Node::ClipGroup;
    const int clips = std::uniform_int_distribution<int>(1, 2)(rng());
    for (int i = 0; i < clips; i++) {
      const uint32_t g = geometry(shapes.shape());
      n->clips.push_back({g, shapes.rule()});
    }
    list(depth + 1, n->children);
    return n;
  }

  std::unique_ptr<Node> group(int depth) {
    auto n = std::make_unique<Node>();
    n->kind = Node::Transparency;
    Group& g = n->group;
    const float o = u();
    g.opacity = o < 0.4f ? 1.0f : o < 0.45f ? 0.0f : u();
    g.blend = chance(0.3) ? BlendMode::Normal : static_cast<BlendMode>(std::uniform_int_distribution<int>(1, 15)(rng()));
    g.isolated = chance(0.5);
    g.knockout = chance(0.2);
    list(depth + 1, n->children);
    return n;
  }

  void list(int depth, std::vector<std::unique_ptr<Node>>& items) {
    const int n = std::uniform_int_distribution<int>(1, 4)(rng());
    for (int i = 0; i < n; i++) {
      const float r = u();
      if (depth < max_depth && r < 0.35f)
        items.push_back(group(depth));
      else if (depth < max_depth && r < 0.45f)
        items.push_back(clip_group(depth));
      else
        items.push_back(fill());
    }
  }
};

// A page of `ink_count` inks (4 or more).
inline InkScene ink_scene(uint32_t seed, int ink_count, int max_depth, int size) {
  InkScene s;
  s.ink_count = ink_count;
  s.size = size;
  s.root.kind = Node::Transparency;
  SceneBuilder unused(size, size);
  Gen g{random_scenes::Gen{std::mt19937(seed), unused, 0, double(size)}, s, max_depth};
  if (g.chance(0.5)) {  // the paper inside the page: opaque, no ink
    auto paper = std::make_unique<Node>();
    paper->kind = Node::Fill;
    Path p;
    p.move_to({-10, -10});
    p.line_to({size + 10.0, -10});
    p.line_to({size + 10.0, size + 10.0});
    p.line_to({-10, size + 10.0});
    p.close();
    paper->geometry = g.geometry(std::move(p));
    paper->inks.assign(ink_count, 0.0);
    s.root.children.push_back(std::move(paper));
  }
  g.list(0, s.root.children);
  return s;
}

// ------------------------------------------------------------ passes

struct PassBuilder {
  SceneBuilder& b;
  const InkPass& pass;

  void list(const std::vector<std::unique_ptr<Node>>& items) {
    for (const auto& n : items) {
      if (n->kind == Node::Fill) {
        auto ink = [&](int k) { return pass.inks[k] < 0 ? 0.0f : static_cast<float>(n->inks[pass.inks[k]]); };
        Paint p;
        p.color = RGBA{ink(0), ink(1), ink(2), static_cast<float>(n->alpha)};
        Group op;
        const bool wrap = !n->painted.empty() && overprint_group(pass, n->painted, &op);
        if (wrap) b.begin_group(op);
        b.fill(n->geometry, Affine{}, n->rule, p);
        if (wrap) b.end_group();
      } else if (n->kind == Node::ClipGroup) {
        b.push();
        for (const auto& [geo, rule] : n->clips) b.clip(geo, Affine{}, rule);
        b.activate();
        list(n->children);
        b.pop();
      } else {
        Group g = n->group;
        set_ink_blend(g, pass);
        b.begin_group(g);
        list(n->children);
        b.end_group();
      }
    }
  }
};

// Pass `pass` of page `s` as a scene; geometry i of the page is the scene's
// geometry i.
inline Scene pass_scene(const InkScene& s, const InkPass& pass) {
  SceneBuilder b(s.size, s.size);
  for (const Path& p : s.geometries) b.add_geometry(p);
  PassBuilder{b, pass}.list(s.root.children);
  return b.finish();
}

}  // namespace mpvg::random_inks
