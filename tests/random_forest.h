// Random forests for tests (test_forest, test_gpu): five scenes of several
// kinds (clip groups with paints of every kind and pattern tiles, nested
// transparency groups and masks, dashed strokes and mesh paints) and sizes
// (root squares of 64, 128 and 256 pixels), at their size or scaled.
#pragma once
#include <random>
#include <vector>

#include "core/mesh_build.h"
#include "core/renderer.h"
#include "tests/random_groups.h"
#include "tests/random_meshes.h"
#include "tests/random_scenes.h"

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

struct Page {
  Scene scene;
  RenderOptions options;
};

inline std::vector<Page> pages(uint32_t seed, const RenderOptions& like) {
  const int sizes[] = {37, 64, 90, 130, 48};
  std::vector<Page> out;
  for (int k = 0; k < 5; k++) {
    const int size = sizes[(seed + k) % 5];
    Page p;
    const int kinds[] = {0, 1, 2, 0, 2};
    switch (kinds[k]) {
      case 0: p.scene = random_scenes::clip_scene(seed * 10 + k, 3, size, true, like.aliased_paths); break;
      case 1: p.scene = random_groups::group_scene(seed * 10 + k, 3, size).scene; break;
      default: p.scene = stroke_mesh_scene(seed * 10 + k, size); break;
    }
    p.options = like;
    const double scale = k == 3 ? 1.5 : 1.0;
    p.options.width = static_cast<int>(size * scale);
    p.options.height = static_cast<int>(size * scale) - k;
    p.options.view = Affine::scale(scale, scale);
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace mpvg::random_forest
