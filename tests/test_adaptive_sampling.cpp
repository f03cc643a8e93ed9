// Adaptive sampling (core/sampling/sampling.h, unit_area_flat): a unit area that no
// segment of its leaf touches, under solid paints, is sampled once. Checked
// against brute force: every point of a flat unit area has the colour of its
// one sample, renders equal the average of every sample taken one by one,
// and --stats' count is what the leaves and unit areas say.
#include <cmath>
#include <random>

#include "cpu/cpu_stages.h"
#include "frame/encoding.h"
#include "core/sampling/integration.h"
#include "core/sampling/sampling.h"
#include "tests/catch.h"
#include "tests/random_scenes.h"

using namespace mpvg;

namespace {

constexpr int kSize = 64;

bool leaf_uniform(const ShortcutTree& t, const Cell& c) {
  for (uint32_t i = c.begin; i < c.end; i++)
    if (entry_varies(t.leaf_entries[i], t.paths.data())) return false;
  return true;
}

// What unit_area_flat reads: the stream, its segments and the path table.
SampleInputs inputs(const ShortcutTree& t) {
  return SampleInputs{t.leaf_entries.data(), t.segments.data(), t.paths.data(), nullptr};
}

ShortcutTree tree_of(const Scene& scene) {
  const EncodedScene enc = encode(scene, Affine{}, Gamma::Srgb);
  TreeParams params;
  params.min_segments = 4;
  return build_tree_cpu(enc, kSize, kSize, params);
}

}  // namespace

TEST_CASE("adaptive sampling: a flat unit area has one colour at every point", "[aa]") {
  size_t flat = 0, edged = 0, points = 0;
  for (uint32_t seed = 1; seed <= 40; seed++) {
    const ShortcutTree tree = tree_of(random_scenes::clip_scene(seed, 3, kSize));
    const SampleInputs in = inputs(tree);
    for (const Cell& c : tree.leaves) {
      if (leaf_uniform(tree, c)) continue;
      const uint32_t s = tree.root_size >> c.level;
      for (uint32_t uy = c.iy * s; uy < std::min<uint32_t>(c.iy * s + s, kSize); uy++)
        for (uint32_t ux = c.ix * s; ux < std::min<uint32_t>(c.ix * s + s, kSize); ux++) {
          if (!unit_area_flat(in, c.begin, c.end, ux, uy)) {
            edged++;
            continue;
          }
          flat++;
          const Rgba4 one = sample_tree_cpu(tree, float(ux) + 0.5f, float(uy) + 0.5f);
          // A 9 x 9 grid over the closed square's inside, corners included.
          for (int j = 0; j <= 8; j++)
            for (int i = 0; i <= 8; i++) {
              const float px = float(ux) + std::min(0.99999f, i / 8.0f), py = float(uy) + std::min(0.99999f, j / 8.0f);
              const Rgba4 c2 = sample_tree_cpu(tree, px, py);
              INFO("seed " << seed << " unit area " << ux << "," << uy << " point " << px << "," << py);
              REQUIRE(c2.r == one.r);
              REQUIRE(c2.g == one.g);
              REQUIRE(c2.b == one.b);
              REQUIRE(c2.a == one.a);
              points++;
            }
        }
    }
  }
  INFO(flat << " flat and " << edged << " other unit areas in leaves with geometry");
  CHECK(flat > 2000);
  CHECK(edged > 2000);
  CHECK(points == flat * 81);
}

TEST_CASE("adaptive sampling: renders equal every sample taken one by one", "[aa]") {
  const std::vector<SampleOffset> pattern = sample_pattern(PatternKind::BlueNoise, 32, 0);
  for (uint32_t seed = 50; seed <= 70; seed++) {
    const ShortcutTree tree = tree_of(random_scenes::clip_scene(seed, 3, kSize));
    RenderTimes times;
    const ImageF img = render_tree_cpu(tree, kSize, kSize, pattern, PaintRecord{}, 1, &times);
    // The brute force: every pixel's 32 samples, and the count adaptive
    // sampling should have taken (1 per uniform leaf, 1 per flat unit area,
    // 32 per other).
    const SampleInputs in = inputs(tree);
    uint64_t expected = 0;
    for (const Cell& c : tree.leaves) {
      if (leaf_uniform(tree, c)) {
        expected++;
        continue;
      }
      const uint32_t s = tree.root_size >> c.level;
      for (uint32_t uy = c.iy * s; uy < std::min<uint32_t>(c.iy * s + s, kSize); uy++)
        for (uint32_t ux = c.ix * s; ux < std::min<uint32_t>(c.ix * s + s, kSize); ux++)
          expected += unit_area_flat(in, c.begin, c.end, ux, uy) ? 1 : 32;
    }
    CHECK(times.samples == expected);
    CHECK(times.samples < uint64_t(kSize) * kSize * 32);  // something was saved
    float worst = 0;
    for (int y = 0; y < kSize; y++)
      for (int x = 0; x < kSize; x++) {
        float sum[4] = {0, 0, 0, 0};
        for (const SampleOffset& o : pattern) {
          const Rgba4 c = sample_tree_cpu(tree, float(x) + o.x, float(y) + o.y);
          sum[0] += c.r, sum[1] += c.g, sum[2] += c.b, sum[3] += c.a;
        }
        for (int ch = 0; ch < 4; ch++)
          worst = std::max(worst, std::fabs(sum[ch] / 32.0f - img.rgba[(size_t(y) * kSize + x) * 4 + ch]));
      }
    INFO("seed " << seed);
    CHECK(worst < 1e-5f);
  }
}
