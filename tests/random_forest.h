// Random forests for tests (test_forest, test_gpu): five scenes of several
// kinds (clip groups with paints of every kind and pattern tiles, or solid
// colours only; nested transparency groups and masks; dashed strokes and
// mesh paints; many small shapes) and sizes, at their size or scaled, all with root squares of
// one side (same_frame_grid, room left for wide filters' margins): 128
// pixels for odd seeds, 256 for even ones.
#pragma once
#include <random>
#include <vector>

#include "core/paint/mesh_build.h"
#include "frame/frame.h"
#include "tests/random_groups.h"
#include "tests/random_meshes.h"
#include "tests/random_scenes.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"

namespace mpvg::random_forest {

// Strokes (dashed, every join and cap) and a mesh paint: the stroke batch's
// and the mesh tables' indices are shifted by the merge too.
inline Scene stroke_mesh_scene(uint32_t seed, int size) {
  std::mt19937 rng(seed);
  SceneBuilder b(size, size);
  const Mesh mesh = random_meshes::lattice(rng, 3, 2, 2, 3, size - 6, size / 2.0, seed % 2 == 0);
  Paint mp;
  mp.type = PaintType::Mesh;
  mp.index = b.add_mesh(mesh);
  b.fill(b.add_geometry(mesh_outline(mesh)), Affine{}, FillRule::NonZero, mp);
  for (int k = 0; k < 3; k++) {
    StrokeStyle st;
    st.width = 1 + k * 2.5;
    st.join = static_cast<LineJoin>((seed + k) % 5);
    st.cap = static_cast<LineCap>((seed + k) % 3);
    if (k == 1) st.dashes = {4.0 + seed % 5, 2, 1, 2};
    Paint p;
    p.color = RGBA{0.1f * k, 0.8f, 0.3f, k == 2 ? 0.6f : 1.0f};
    b.stroke(b.add_geometry(oracle::random_path(rng, 0.0, double(size), 1 + k % 2, 4)), Affine{}, st, p);
  }
  return b.finish();
}

// Many small shapes (like a page of text): enough entries for a coarse
// grid of its own (tree_grid_levels), which the other scenes have not.
inline Scene dense_scene(uint32_t seed, int size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  SceneBuilder b(size, size);
  for (int k = 0; k < 700; k++) {
    const double x = u(rng) * size, y = u(rng) * size, r = 0.5 + 2.5 * u(rng);
    Path p;
    p.move_to({x, y - r});
    p.quad_to({x + r, y - r}, {x + r, y + r});
    p.line_to({x - r, y + r * u(rng)});
    p.close();
    Paint paint;
    paint.color = RGBA{float(u(rng)), float(u(rng)), 0.3f, k % 3 ? 1.0f : 0.5f};
    b.fill(b.add_geometry(p), Affine{}, FillRule::NonZero, paint);
  }
  return b.finish();
}

struct Page {
  Scene scene;
  RenderOptions options;
};

inline std::vector<Page> pages(uint32_t seed, const RenderOptions& like) {
  const int odd[] = {70, 90, 84, 66, 100}, even[] = {130, 200, 160, 140, 224};
  const int* sizes = seed % 2 ? odd : even;
  std::vector<Page> out;
  for (int k = 0; k < 5; k++) {
    // Scene 3 is drawn scaled up, into the same output sizes.
    const int out_size = sizes[(seed + k) % 5], size = k == 3 ? out_size * 4 / 5 : out_size;
    Page p;
    // Kind 3 has solid paints only: its sampler specialisation is not the
    // forest's.
    const int kinds[] = {0, 1, 2, 3, 4};
    switch (kinds[k]) {
      case 0: p.scene = random_scenes::clip_scene(seed * 10 + k, 3, size, true, like.aliased_paths); break;
      case 1: p.scene = random_groups::group_scene(seed * 10 + k, 3, size).scene; break;
      case 3: p.scene = random_scenes::clip_scene(seed * 10 + k, 3, size, false, like.aliased_paths); break;
      case 4: p.scene = dense_scene(seed * 10 + k, size); break;
      default: p.scene = stroke_mesh_scene(seed * 10 + k, size); break;
    }
    p.options = like;
    const double scale = double(out_size) / size;
    p.options.width = out_size;
    p.options.height = out_size - k;
    p.options.view = Affine::scale(scale, scale);
    out.push_back(std::move(p));
  }
  return out;
}

// The pages planned and encoded alone (plan_render, encode_for), and the
// forest frame's scenes that point at them (the vectors keep their
// elements where they are when the whole is moved).
struct Encoded {
  std::vector<RenderPlan> plans;
  std::vector<EncodedScene> scenes;
  std::vector<FrameScene> frame;
};

inline Encoded encoded(const std::vector<Page>& ps) {
  Encoded e;
  for (const Page& p : ps) {
    e.plans.push_back(plan_render(p.options));
    e.scenes.push_back(encode_for(p.scene, e.plans.back(), p.options.gamma));
  }
  for (size_t k = 0; k < ps.size(); k++) e.frame.push_back(FrameScene{&e.scenes[k], &e.plans[k], nullptr});
  return e;
}

}  // namespace mpvg::random_forest
