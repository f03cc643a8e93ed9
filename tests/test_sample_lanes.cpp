// Sample lanes (core/sampling/sampling.h, sample_cell_lanes): the CPU's
// sampler steps a unit area's samples together over their leaf's stream.
// Each lane's colour must be sample_cell's for the same point bit for bit,
// in every sampler specialisation, on random scenes of clip groups, paints
// of every kind, aliased paths and transparency groups; and a line piece's
// tests (LineTest, as selects) must take the decisions abstract_side's
// rules state, in their order of precedence.
#include <cstring>
#include <random>

#include "cpu/cpu_stages.h"
#include "frame/encoding.h"
#include "core/sampling/sampling.h"
#include "tests/catch.h"
#include "tests/random_groups.h"
#include "tests/random_scenes.h"

using namespace mpvg;

namespace {

constexpr int kSize = 64;

ShortcutTree tree_of(const Scene& scene) {
  const EncodedScene enc = encode(scene, Affine{}, Gamma::Srgb);
  TreeParams params;
  params.min_segments = 4;
  return build_tree_cpu(enc, kSize, kSize, params);
}

bool same_bits(const Rgba4& a, const Rgba4& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every leaf with entries: a few of its unit areas, each with a random
// number of samples (one lane, one chunk, a chunk and a lane, several
// chunks) at random points, some on a 1/8 grid (ties with vertices and
// shortcuts); lanes against one by one in the specialisation `kinds` and
// in the general one. Returns the samples compared.
uint64_t compare_lanes(const ShortcutTree& tree, uint32_t kinds, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const int counts[] = {1, 5, 16, 17, 32, 40};
  uint64_t compared = 0;
  for (uint32_t l = 0; l < tree.leaves.size(); l++) {
    const Cell& c = tree.leaves[l];
    if (c.begin == c.end) continue;
    const uint32_t s = tree.root_size >> c.level;
    for (int trial = 0; trial < 3; trial++) {
      const uint32_t ux = c.ix * s + rng() % s, uy = c.iy * s + rng() % s;
      if (ux >= uint32_t(kSize) || uy >= uint32_t(kSize)) continue;
      const int n = counts[rng() % 6];
      std::vector<float> px(n), py(n);
      for (int k = 0; k < n; k++) {
        float fx = u(rng), fy = u(rng);
        if (k % 3 == 0) fx = float(rng() % 8) / 8.0f, fy = float(rng() % 8) / 8.0f;
        px[k] = float(ux) + fx;
        py[k] = float(uy) + fy;
      }
      for (uint32_t kk : {kinds, uint32_t(SAMPLE_ALL)}) {
        std::vector<Rgba4> together(n), one(n);
        sample_leaf_cpu(tree, l, kk, px.data(), py.data(), n, together.data(), one.data());
        for (int k = 0; k < n; k++) {
          INFO("seed " << seed << " kinds " << kk << " leaf " << l << " sample " << k << " of " << n << " at "
                       << px[k] << "," << py[k]);
          REQUIRE(same_bits(together[k], one[k]));
          compared++;
        }
      }
    }
  }
  return compared;
}

uint32_t kinds_of(const ShortcutTree& tree, bool aliasing) {
  return tree.roots.empty() ? uint32_t(SAMPLE_ALL) : tree.roots[0].kinds[aliasing];
}

// abstract_side's rules for a line piece (abstract_segment.h), as branches
// in their order: vertical; at an endpoint's height; outside the x-range;
// the chord (left of it: +1).
int line_side_rules(float x0, float y0, float x1, float y1, float px, float py) {
  const float xmin = std::min(x0, x1), xmax = std::max(x0, x1);
  auto cmp = [](float a, float b) { return a < b ? 1 : (a > b ? -1 : 0); };
  if (xmin == xmax) return cmp(px, xmin);
  if (py == y0) return cmp(px, x0);
  if (py == y1) return cmp(px, x1);
  if (px <= xmin) return 1;
  if (px >= xmax) return -1;
  float d = (py - y0) * (x1 - x0) - (px - x0) * (y1 - y0);
  if (!(y1 > y0)) d = -d;
  return d > 0.0f ? 1 : (d < 0.0f ? -1 : 0);
}

}  // namespace

TEST_CASE("sample lanes: each lane is sample_cell's colour, bit for bit", "[lanes]") {
  uint64_t compared = 0;
  for (uint32_t seed = 1; seed <= 12; seed++) {
    for (int variant = 0; variant < 4; variant++) {
      const bool rich = variant & 1, aliased = variant & 2;
      const ShortcutTree tree = tree_of(random_scenes::clip_scene(seed, 3, kSize, rich, aliased));
      compared += compare_lanes(tree, kinds_of(tree, aliased), seed * 8 + variant);
    }
    for (bool porter_duff : {false, true}) {
      const ShortcutTree tree = tree_of(random_groups::group_scene(seed, 4, kSize, porter_duff).scene);
      compared += compare_lanes(tree, kinds_of(tree, false), seed * 8 + 4 + porter_duff);
    }
  }
  INFO(compared << " samples compared");
  CHECK(compared > 200000);
}

TEST_CASE("sample lanes: a line's tests as selects take the rules' decisions", "[lanes]") {
  std::mt19937 rng(7);
  // Coordinates on a coarse grid: vertical pieces, points at endpoints'
  // heights, on the chord and at the x-range's ends are frequent.
  auto coord = [&] { return float(int(rng() % 9)) * 0.5f; };
  uint64_t ties = 0;
  for (int i = 0; i < 200000; i++) {
    AbstractSegment s{};
    s.x0 = coord(), s.y0 = coord(), s.x1 = coord(), s.y1 = coord();
    s.flags = ABSTRACT_LINE;
    const float px = coord(), py = coord();
    const int want = line_side_rules(s.x0, s.y0, s.x1, s.y1, px, py);
    if (s.y0 != s.y1 && std::min(s.y0, s.y1) <= py && py <= std::max(s.y0, s.y1)) {
      INFO(s.x0 << "," << s.y0 << " - " << s.x1 << "," << s.y1 << " at " << px << "," << py);
      REQUIRE(abstract_side(s, px, py) == want);
      ties += want == 0;
    }
    const bool up = s.y1 > s.y0;
    const bool rows = up ? (py >= s.y0 && py < s.y1) : (py >= s.y1 && py < s.y0);
    REQUIRE(abstract_ray_winding(s, px, py) == (rows && want > 0 ? (up ? 1 : -1) : 0));
  }
  CHECK(ties > 1000);
}

TEST_CASE("sample lanes: a curve's tests as selects decide as abstract_side", "[lanes]") {
  // The abstract segments of random scenes' curved paths, at random points
  // of their boxes and at the ties: endpoints' heights, the x-range's ends,
  // the apex's coordinates.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-0.25f, 1.25f);
  uint64_t quads = 0, cubics = 0, implicit = 0;
  for (uint32_t seed = 1; seed <= 20; seed++) {
    const ShortcutTree tree = tree_of(random_scenes::clip_scene(seed, 3, kSize, seed % 2 == 0));
    for (const AbstractSegment& s : tree.segments) {
      const uint32_t type = abstract_type(s);
      if (type == ABSTRACT_LINE) continue;
      (type == ABSTRACT_QUAD ? quads : cubics)++;
      const float xs[] = {s.x0, s.x1, s.cx, abstract_xmin(s), abstract_xmax(s)};
      const float ys[] = {s.y0, s.y1, s.cy};
      for (int i = 0; i < 40; i++) {
        float px = abstract_xmin(s) + u(rng) * (abstract_xmax(s) - abstract_xmin(s));
        float py = abstract_ymin(s) + u(rng) * (abstract_ymax(s) - abstract_ymin(s));
        if (i % 4 == 1) px = xs[rng() % 5];
        if (i % 4 == 2) py = ys[rng() % 3];
        const int side = type == ABSTRACT_QUAD ? CurveTest<ABSTRACT_QUAD>(s).side(px, py)
                                               : CurveTest<ABSTRACT_CUBIC>(s).side(px, py);
        const int wind = type == ABSTRACT_QUAD ? CurveTest<ABSTRACT_QUAD>(s).winding(px, py)
                                               : CurveTest<ABSTRACT_CUBIC>(s).winding(px, py);
        INFO("seed " << seed << " type " << type << " " << s.x0 << "," << s.y0 << " - " << s.x1 << "," << s.y1
                     << " at " << px << "," << py);
        if (!abstract_horizontal(s) && abstract_ymin(s) <= py && py <= abstract_ymax(s)) {
          REQUIRE(side == abstract_side(s, px, py));
          const float d = abstract_chord(s, px, py);
          implicit += px > abstract_xmin(s) && px < abstract_xmax(s) && py != s.y0 && py != s.y1 &&
                      ((s.flags & ABSTRACT_BULGE_LEFT) ? d > 0.0f : d < 0.0f);
        }
        REQUIRE(wind == abstract_ray_winding(s, px, py));
      }
    }
  }
  INFO(quads << " quadratic and " << cubics << " cubic pieces, " << implicit << " points on a bulge side");
  CHECK(quads > 1000);
  CHECK(cubics > 1000);
  CHECK(implicit > 10000);
}
