// The shortcut tree's invariant (paper §4): in every cell of every level,
// the winding number of every path about every sample equals a brute-force
// count of ray-curve crossings over the whole input, in double precision.
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include "cpu/cpu_stages.h"
#include "frame/encoding.h"
#include "core/sampling/sampling.h"
#include "core/tree/subdivision.h"
#include "tests/catch.h"
#include "tests/oracle.h"
#include "frame/scene_builder.h"

using namespace mpvg;

namespace {

Scene random_fill_scene(uint32_t seed, int npaths, double lo, double hi, int size) {
  std::mt19937 rng(seed);
  SceneBuilder b(size, size);
  for (int i = 0; i < npaths; i++) {
    const uint32_t g = b.add_geometry(oracle::random_path(rng, lo, hi, 1 + i % 3, 7));
    Paint p;
    p.color = RGBA{0.5f, 0.25f, 1.0f, 1.0f};
    b.fill(g, Affine{}, i % 2 ? FillRule::EvenOdd : FillRule::NonZero, p);
  }
  return b.finish();
}

// Winding of every path about (px, py) from the entries of one cell.
std::vector<int> cell_windings(const TreeLevel& level, const Cell& c, const ShortcutTree& tree, size_t npaths,
                               float px, float py) {
  std::vector<int> w(npaths, 0);
  for (uint32_t i = c.begin; i < c.end; i++) {
    const Entry e = level.entries[i];
    if (entry_is_delimiter(e)) continue;
    w[entry_path(e)] += entry_winding(e, entry_segment(e, tree.segments.data()), px, py);
  }
  return w;
}

struct Check {
  size_t points = 0, comparisons = 0, skipped = 0;
};

void check_tree_windings(const Scene& scene, int size, uint32_t seed, int npoints, Check& out) {
  const EncodedScene enc = encode(scene, Affine{}, Gamma::Srgb);
  const oracle::Windings brute(enc.segments, scene.paths.size());
  TreeParams params;
  params.keep_levels = true;
  params.prune = false;
  params.min_segments = 0;
  const ShortcutTree tree = build_tree_cpu(enc, size, size, params);
  REQUIRE(tree.levels.size() >= 2);
  std::vector<std::map<std::pair<int, int>, size_t>> index(tree.levels.size());
  for (size_t l = 0; l < tree.levels.size(); l++)
    for (size_t k = 0; k < tree.levels[l].cells.size(); k++)
      index[l][{tree.levels[l].cells[k].ix, tree.levels[l].cells[k].iy}] = k;

  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(0.0f, float(size));
  std::uniform_int_distribution<int> grid(0, size * 4 - 1);
  for (int n = 0; n < npoints; n++) {
    // Random points, and points on the quarter-pixel grid, which includes
    // every cell corner and edge.
    const bool on_grid = n % 4 == 0;
    const float px = on_grid ? grid(rng) * 0.25f : coord(rng);
    const float py = on_grid ? grid(rng) * 0.25f : coord(rng);
    const auto expect = brute.at(px, py, 1e-3);
    if (!expect) {
      out.skipped++;
      continue;
    }
    out.points++;
    for (size_t l = 0; l < tree.levels.size(); l++) {
      const uint32_t s = tree.root_size >> l;
      const auto it = index[l].find({int(px) / int(s), int(py) / int(s)});
      if (it == index[l].end()) continue;  // an ancestor is a leaf
      const TreeLevel& level = tree.levels[l];
      const std::vector<int> got = cell_windings(level, level.cells[it->second], tree, scene.paths.size(), px, py);
      INFO("level " << l << " cell (" << it->first.first << ", " << it->first.second << ") point (" << px << ", "
                    << py << ")");
      REQUIRE(got == *expect);
      out.comparisons++;
    }
  }
}

}  // namespace

TEST_CASE("tree windings match brute force at every level, random curved paths", "[tree]") {
  Check c;
  for (uint32_t seed = 1; seed <= 12; seed++) {
    const Scene scene = random_fill_scene(seed, 5, -12.0, 76.0, 64);
    check_tree_windings(scene, 64, 100 + seed, 1500, c);
  }
  INFO("points " << c.points << " comparisons " << c.comparisons << " skipped " << c.skipped);
  CHECK(c.points > 12000);
  CHECK(c.comparisons > 60000);
}

TEST_CASE("tree windings match brute force for pixel-aligned rectangles", "[tree]") {
  // Edges on cell boundaries, shared vertices and collinear edges: the ties
  // that half-open conventions must resolve consistently.
  Check c;
  for (uint32_t seed = 1; seed <= 8; seed++) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> coord(-4, 36);
    SceneBuilder b(32, 32);
    for (int i = 0; i < 6; i++) {
      Path p;
      for (int k = 0; k < 1 + i % 2; k++) {
        const double x0 = coord(rng), y0 = coord(rng), x1 = coord(rng), y1 = coord(rng);
        p.move_to({x0, y0});
        p.line_to({x1, y0});
        p.line_to({x1, y1});
        p.line_to({x0, y1});
        p.close();
      }
      Paint paint;
      b.fill(b.add_geometry(p), Affine{}, i % 2 ? FillRule::EvenOdd : FillRule::NonZero, paint);
    }
    check_tree_windings(b.finish(), 32, 7 * seed, 1500, c);
  }
  INFO("points " << c.points << " comparisons " << c.comparisons);
  CHECK(c.points > 5000);
}

TEST_CASE("tree windings match brute force for geometry far outside the image", "[tree]") {
  Check c;
  for (uint32_t seed = 20; seed < 26; seed++) {
    const Scene scene = random_fill_scene(seed, 4, -400.0, 500.0, 64);
    check_tree_windings(scene, 64, seed, 1000, c);
  }
  CHECK(c.points > 4000);
}

TEST_CASE("tree windings are exact for extrema just beside cell edges", "[tree]") {
  // Monotonization ends pieces at x- and y-extrema, where the curve is
  // tangent to the cell's corner tests. Put such endpoints within a hair of
  // cell edges (multiples of 4 px), where float implicit tests cannot tell
  // the sides apart: only exact endpoint decisions keep the cells right.
  Check c;
  const double deltas[] = {-0.05, -1e-3, -1e-5, 0.0, 1e-5, 1e-3, 0.05};
  uint32_t seed = 0;
  for (double dx : deltas) {
    for (double dy : deltas) {
      std::mt19937 rng(++seed);
      std::uniform_int_distribution<int> cell(1, 7);
      std::uniform_real_distribution<double> off(2.0, 9.0);
      SceneBuilder b(32, 32);
      for (int i = 0; i < 4; i++) {
        // Closed shapes of two cubic arms meeting at an extremum (a bottom
        // or top with a horizontal tangent, or a side with a vertical one)
        // that sits at (4m + dx, 4n + dy).
        const double ex = 4 * cell(rng) + dx, ey = 4 * cell(rng) + dy;
        const double w = off(rng), h = (i % 2 ? -1.0 : 1.0) * off(rng);
        const double k = 0.2 + 0.2 * (i % 3);
        Path p;
        p.move_to({ex - w, ey + h});
        p.cubic_to({ex - w, ey + k * h}, {ex - 0.5 * w, ey}, {ex, ey});
        p.cubic_to({ex + 0.4 * w, ey}, {ex + w, ey + k * h}, {ex + w, ey + h});
        p.close();
        Path q;
        q.move_to({ex + h, ey - w});
        q.cubic_to({ex + k * h, ey - w}, {ex, ey - 0.5 * w}, {ex, ey});
        q.cubic_to({ex, ey + 0.4 * w}, {ex + k * h, ey + w}, {ex + h, ey + w});
        q.close();
        Paint paint;
        b.fill(b.add_geometry(p), Affine{}, FillRule::NonZero, paint);
        b.fill(b.add_geometry(q), Affine{}, FillRule::EvenOdd, paint);
      }
      check_tree_windings(b.finish(), 32, seed, 1200, c);
    }
  }
  INFO("points " << c.points << " comparisons " << c.comparisons);
  CHECK(c.points > 30000);
}

// The subdivision's one scan (SplitScan, core/tree/subdivision.h) against its
// two passes (a segmented sum of windings, then the sum of the pairs'
// output counts), on random runs of pairs with identity slots between
// cells, scanned in order and as a parallel scan would: chunks scanned on
// their own, then each chunk's prefix combined in front.
TEST_CASE("subdivision: one scan consolidates windings and counts outputs as two passes do", "[tree]") {
  std::mt19937 rng(77);
  size_t checked = 0;
  for (int trial = 0; trial < 300; trial++) {
    std::vector<SplitScan> items;
    std::vector<int32_t> want_wind;
    std::vector<uint32_t> want_count;  // inclusive
    std::vector<char> slot;
    uint32_t total = 0;
    const int cells = 1 + static_cast<int>(rng() % 6);
    for (int c = 0; c < cells; c++) {
      for (int gap = c > 0 ? static_cast<int>(rng() % 3) : 0; gap > 0; gap--) {  // slots between cells
        items.push_back(SplitScan{0, 0, 0, 0});
        want_wind.push_back(0);
        want_count.push_back(total);
        slot.push_back(1);
      }
      for (int runs = 1 + static_cast<int>(rng() % 5); runs > 0; runs--) {
        const int len = 1 + static_cast<int>(rng() % 5);
        int32_t sum = 0;
        for (int k = 0; k < len; k++) {
          const uint32_t flags = rng() % 8;
          const int32_t w = static_cast<int32_t>(rng() % 5) - 2;
          const bool head = k == 0, last = k == len - 1;
          sum = (head ? 0 : sum) + w;
          total += split_output_count(flags, last, sum);
          items.push_back(split_scan_item(flags, w, head, last));
          want_wind.push_back(sum);
          want_count.push_back(total);
          slot.push_back(0);
        }
      }
    }
    std::vector<SplitScan> seq(items.size());
    std::inclusive_scan(items.begin(), items.end(), seq.begin(), SplitScanOp{});
    // Chunks of random sizes scanned alone, then the prefix before each
    // chunk combined in front of its elements.
    std::vector<SplitScan> par(items.size());
    SplitScan carry{0, 0, 0, 0};
    bool have_carry = false;
    for (size_t a = 0; a < items.size();) {
      const size_t b = std::min(items.size(), a + 1 + rng() % 7);
      SplitScan local = items[a];
      for (size_t j = a; j < b; j++) {
        if (j > a) local = SplitScanOp{}(local, items[j]);
        par[j] = have_carry ? SplitScanOp{}(carry, local) : local;
      }
      carry = par[b - 1];
      have_carry = true;
      a = b;
    }
    for (size_t j = 0; j < items.size(); j++) {
      INFO("trial " << trial << " pair " << j);
      REQUIRE(seq[j].count == want_count[j]);
      REQUIRE(par[j].count == want_count[j]);
      if (!slot[j]) {
        REQUIRE(seq[j].last == want_wind[j]);
        REQUIRE(par[j].last == want_wind[j]);
      }
      checked++;
    }
  }
  CHECK(checked > 3000);
}
