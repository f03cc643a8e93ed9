#include "core/paint/mesh_build.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.h"

namespace mpvg {

namespace {

// A triangle's corners, counter-clockwise (positive cross product), or
// false when it has no area.
bool oriented(Vec2& a, Vec2& b, Vec2& c) {
  const double area = cross(b - a, c - a);
  if (!(std::fabs(area) > 0) || !std::isfinite(area)) return false;
  if (area < 0) std::swap(b, c);
  return true;
}

using Point = std::pair<double, double>;
Point key(Vec2 p) { return {p.x, p.y}; }

// A triangle in pixels for the grid: its edges as lines whose positive
// side holds it (unit normals: values are distances in pixels), and its box.
struct PixelTriangle {
  double ex[3], ey[3], ec[3];
  double bx0, by0, bx1, by1;
  double slack;  // what "inside" must clear: rounding of coordinates this large

  PixelTriangle(Vec2 a, Vec2 b, Vec2 c) {
    if (cross(b - a, c - a) < 0) std::swap(b, c);
    const Vec2 v[3] = {a, b, c};
    for (int k = 0; k < 3; k++) {
      const Vec2 p = v[k], d = v[(k + 1) % 3] - p;
      const double len = std::hypot(d.x, d.y);
      ex[k] = -d.y / len;
      ey[k] = d.x / len;
      ec[k] = -(ex[k] * p.x + ey[k] * p.y);
    }
    bx0 = std::min({a.x, b.x, c.x});
    bx1 = std::max({a.x, b.x, c.x});
    by0 = std::min({a.y, b.y, c.y});
    by1 = std::max({a.y, b.y, c.y});
    slack = 1e-7 * (1 + std::max({std::fabs(bx0), std::fabs(bx1), std::fabs(by0), std::fabs(by1)}));
  }
};

enum class Overlap { None, Part, Whole };

// How the triangle meets the rectangle [x0, x1] x [y0, y1]: separating
// axes are the box's (the caller's cell range) and the three edge normals.
Overlap overlap(const PixelTriangle& t, double x0, double y0, double x1, double y1) {
  bool whole = true;
  for (int k = 0; k < 3; k++) {
    const double hi = t.ex[k] * (t.ex[k] > 0 ? x1 : x0) + t.ey[k] * (t.ey[k] > 0 ? y1 : y0) + t.ec[k];
    if (hi < 0) return Overlap::None;
    const double lo = t.ex[k] * (t.ex[k] > 0 ? x0 : x1) + t.ey[k] * (t.ey[k] > 0 ? y0 : y1) + t.ec[k];
    if (!(lo > t.slack)) whole = false;
  }
  return whole ? Overlap::Whole : Overlap::Part;
}

// The grid: w x h cells from (x0, y0), sx x sy cells a pixel. A cell is
// taken `widen` cells larger on every side than it is, against the
// sampler's float arithmetic (mesh_cell rounds its origin, scale and
// differences to float: a few units in the last place of |x0| sx + w).
struct MeshGrid {
  uint32_t w, h;
  double x0, y0, sx, sy, widen;

  // The cells [i0, i1] of an interval [lo, hi] of x (or y), clamped.
  static void range(double lo, double hi, double origin, double scale, double widen, uint32_t count, uint32_t& i0,
                    uint32_t& i1) {
    const double a = std::floor((lo - origin) * scale - widen), b = std::floor((hi - origin) * scale + widen);
    i0 = static_cast<uint32_t>(std::clamp(a, 0.0, double(count - 1)));
    i1 = static_cast<uint32_t>(std::clamp(b, 0.0, double(count - 1)));
  }
};

MeshGrid mesh_grid(double x0, double y0, double w, double h, uint32_t gw, uint32_t gh) {
  const double sx = gw / w, sy = gh / h;
  return MeshGrid{gw, gh, x0, y0, sx, sy, 1e-3 + 1e-6 * (std::fabs(x0) * sx + std::fabs(y0) * sy + gw + gh)};
}

// The triangles' box [x0, x1] x [y0, y1] less what rounding can put a
// point on its edge outside the triangle whose edge it is (which would
// otherwise cover no edge cell whole): what visit_cells judges cover in.
MeshBounds cover_box(double x0, double y0, double x1, double y1) {
  const double inset = 1e-5 * (1 + std::max({std::fabs(x0), std::fabs(y0), std::fabs(x1), std::fabs(y1)}));
  if (x1 - x0 > 4 * inset) x0 += inset, x1 -= inset;
  if (y1 - y0 > 4 * inset) y0 += inset, y1 -= inset;
  return MeshBounds{x0, y0, x1, y1};
}

// item(k, cell) for every triangle k, top-most first, and every cell it
// meets that no triangle above it covers whole: a sample in such a
// covered cell stops at the covering triangle (or one above it), so what
// lies below can never be its top-most. What a cell holds outside the
// triangles' box (cover_box) is in no triangle: a triangle covers the
// cell whole when it covers the cell's part within that box (a sample
// outside it takes the covering triangle's nearest colour, or none, as
// beyond any other triangle). Stops when item returns false.
template <class F>
bool visit_cells(const std::vector<PixelTriangle>& tris, const MeshGrid& g, const MeshBounds& box, F&& item) {
  const double mx0 = box.x0, my0 = box.y0, mx1 = box.x1, my1 = box.y1;
  const size_t words = (g.w + 63) / 64;
  std::vector<uint64_t> open(size_t(g.h) * words, ~uint64_t(0));  // bits past w are never read
  uint64_t open_cells = uint64_t(g.w) * g.h;
  for (size_t k = tris.size(); k-- > 0 && open_cells > 0;) {
    const PixelTriangle& t = tris[k];
    uint32_t i0, i1, j0, j1;
    MeshGrid::range(t.bx0, t.bx1, g.x0, g.sx, g.widen, g.w, i0, i1);
    MeshGrid::range(t.by0, t.by1, g.y0, g.sy, g.widen, g.h, j0, j1);
    for (uint32_t j = j0; j <= j1; j++) {
      uint64_t* row = &open[size_t(j) * words];
      const double cy0 = std::max(my0, g.y0 + (j - g.widen) / g.sy), cy1 = std::min(my1, g.y0 + (j + 1 + g.widen) / g.sy);
      for (uint32_t wd = i0 / 64; wd <= i1 / 64; wd++) {
        uint64_t bits = row[wd];
        if (wd == i0 / 64) bits &= ~uint64_t(0) << (i0 % 64);
        if (wd == i1 / 64 && i1 % 64 != 63) bits &= (uint64_t(2) << (i1 % 64)) - 1;
        while (bits) {
          const int b = __builtin_ctzll(bits);
          bits &= bits - 1;
          const uint32_t i = wd * 64 + static_cast<uint32_t>(b);
          const Overlap o = overlap(t, std::max(mx0, g.x0 + (i - g.widen) / g.sx), cy0,
                                    std::min(mx1, g.x0 + (i + 1 + g.widen) / g.sx), cy1);
          if (o == Overlap::None) continue;
          if (!item(k, size_t(j) * g.w + i)) return false;
          if (o == Overlap::Whole) {
            row[wd] &= ~(uint64_t(1) << b);
            open_cells--;
          }
        }
      }
    }
  }
  return true;
}

// Items a grid may hold whatever the mesh's size (128 MiB): longer lists
// cost every sample of a cell, a finer grid only memory.
constexpr uint64_t kMeshItems = uint64_t(1) << 25;

}  // namespace


Path mesh_outline(const Mesh& m, size_t max_edges, bool* over) {
  if (over) *over = false;
  // Every triangle's edges, counter-clockwise, as (lower point, higher
  // point) and the direction they run in: opposite directions of one pair
  // cancel, what is left runs the majority's way as many times as it has
  // more (what cancelling pairs one by one leaves).
  struct Edge {
    Point lo, hi;
    int dir;  // +1: lo -> hi
  };
  std::vector<Edge> edges;
  edges.reserve(m.vertices.size());
  for (size_t i = 0; i + 2 < m.vertices.size(); i += 3) {
    Vec2 v[3] = {m.vertices[i].p, m.vertices[i + 1].p, m.vertices[i + 2].p};
    if (!oriented(v[0], v[1], v[2])) continue;
    for (int k = 0; k < 3; k++) {
      const Point a = key(v[k]), b = key(v[(k + 1) % 3]);
      edges.push_back(a < b ? Edge{a, b, 1} : Edge{b, a, -1});
    }
  }
  std::sort(edges.begin(), edges.end(),
            [](const Edge& x, const Edge& y) { return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi); });
  // The directed edges left, (from, to) sorted, with multiplicity.
  std::vector<std::pair<Point, Point>> left;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    int net = 0;
    for (; j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi; j++) net += edges[j].dir;
    for (int k = 0; k < std::abs(net); k++)
      left.push_back(net > 0 ? std::make_pair(edges[i].lo, edges[i].hi) : std::make_pair(edges[i].hi, edges[i].lo));
    if (left.size() > max_edges) {
      if (over) *over = true;
      return Path{};
    }
    i = j;
  }
  edges = {};
  std::sort(left.begin(), left.end());
  // Every point has as many edges in as out: walks from a point return to
  // it. Each point's edges out are taken last first.
  std::vector<Point> from;          // the points edges leave, ascending
  std::vector<size_t> first, next;  // from[i]'s edges: left[first[i] .. next[i]) still to walk
  for (size_t e = 0; e < left.size(); e++)
    if (from.empty() || from.back() != left[e].first) {
      from.push_back(left[e].first);
      first.push_back(e);
    }
  next.resize(from.size());
  for (size_t i = 0; i < from.size(); i++) next[i] = i + 1 < from.size() ? first[i + 1] : left.size();
  auto out_of = [&](const Point& p) { return size_t(std::lower_bound(from.begin(), from.end(), p) - from.begin()); };
  Path path;
  for (size_t s = 0; s < from.size(); s++) {
    const Point start = from[s];
    while (next[s] > first[s]) {
      path.move_to({start.first, start.second});
      Point cur = start;
      do {
        const size_t i = out_of(cur);
        if (i == from.size() || from[i] != cur || next[i] == first[i]) break;  // (unbalanced: never)
        cur = left[--next[i]].second;
        if (cur != start) path.line_to({cur.first, cur.second});
      } while (cur != start);
      path.close();
    }
  }
  return path;
}

bool build_mesh(const Mesh& m, const Affine& to_px, const std::function<Rgba4(const RGBA&)>& color,
                const MeshBounds& bounds, MemoryBudget* budget, PaintData& out, MeshRecord& rec) {
  const bool ramp = !m.ramp.empty();
  const size_t tri_base = out.mesh_triangles.size();
  // The triangles in pixels, counter-clockwise, and their boxes.
  std::vector<PixelTriangle> tris;
  const size_t given = m.vertices.size() / 3;
  BudgetCharge scratch(budget, mul_sat(given, sizeof(PixelTriangle)), "a mesh shading's triangles");
  BudgetCharge kept(budget, mul_sat(given, sizeof(MeshTriangle)), "a mesh shading's triangles");
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (size_t i = 0; i + 2 < m.vertices.size(); i += 3) {
    const MeshVertex* v = &m.vertices[i];
    const Vec2 a = to_px.apply(v[0].p), b = to_px.apply(v[1].p), c = to_px.apply(v[2].p);
    const Vec2 e1 = b - a, e2 = c - a;
    const double det = cross(e1, e2);
    // No area within float precision: never the only triangle of a point.
    if (!std::isfinite(det) || !(std::fabs(det) > 1e-9 * (dot(e1, e1) + dot(e2, e2)))) continue;
    PixelTriangle pt(a, b, c);
    // Nothing of it can be sampled: left out.
    if (pt.bx1 < bounds.x0 || pt.bx0 > bounds.x1 || pt.by1 < bounds.y0 || pt.by0 > bounds.y1) continue;
    MeshTriangle t{};
    t.ax = static_cast<float>(a.x);
    t.ay = static_cast<float>(a.y);
    // (s, t) solve s e1 + t e2 = p - a, relative to a's float position.
    t.m00 = static_cast<float>(e2.y / det);
    t.m01 = static_cast<float>(-e2.x / det);
    t.m10 = static_cast<float>(-e1.y / det);
    t.m11 = static_cast<float>(e1.x / det);
    Rgba4 c3[3];
    for (int k = 0; k < 3; k++) {
      const RGBA& col = v[k].color;
      c3[k] = ramp ? Rgba4{col.r, 0.0f, 0.0f, 1.0f} : color(col);
    }
    t.c0 = c3[0];
    t.d1 = Rgba4{c3[1].r - c3[0].r, c3[1].g - c3[0].g, c3[1].b - c3[0].b, c3[1].a - c3[0].a};
    t.d2 = Rgba4{c3[2].r - c3[0].r, c3[2].g - c3[0].g, c3[2].b - c3[0].b, c3[2].a - c3[0].a};
    out.mesh_triangles.push_back(t);
    x0 = std::min(x0, pt.bx0);
    y0 = std::min(y0, pt.by0);
    x1 = std::max(x1, pt.bx1);
    y1 = std::max(y1, pt.by1);
    tris.push_back(pt);
  }
  const size_t n = tris.size();
  if (n == 0) return false;
  if (tri_base + n > UINT32_MAX) throw ResourceError("a mesh shading has more triangles than a frame can index");
  const MeshBounds cover = cover_box(x0, y0, x1, y1);
  // The grid spans what of the triangles can be sampled.
  x0 = std::max(x0, bounds.x0);
  y0 = std::max(y0, bounds.y0);
  x1 = std::min(x1, bounds.x1);
  y1 = std::min(y1, bounds.y1);
  const double w = std::max(x1 - x0, 1e-6), h = std::max(y1 - y0, 1e-6);
  // About one cell per triangle, square-ish, at most 1024 a side and no
  // finer than the frame's pixels.
  const double cells = std::min<double>(double(n), 65536.0);
  const long max_w = std::clamp(long(std::ceil(w)), 1L, 1024L), max_h = std::clamp(long(std::ceil(h)), 1L, 1024L);
  uint32_t gw = static_cast<uint32_t>(std::clamp(std::lround(std::sqrt(cells * w / h)), 1L, max_w));
  uint32_t gh = static_cast<uint32_t>(std::clamp(std::lround(std::ceil(cells / gw)), 1L, max_h));
  // The item list: within what entries can index, what the budget has
  // left, and 32 items per triangle and cell or kMeshItems (a finer grid
  // that lists every triangle in many cells is coarsened instead: memory
  // stays proportional to the mesh, and samples still stop at the
  // top-most triangle that holds them).
  const size_t item_base = out.mesh_items.size();
  const uint64_t index_room = uint64_t(UINT32_MAX) - std::min<uint64_t>(UINT32_MAX, item_base);
  const uint64_t budget_room = budget ? budget->available() / sizeof(uint32_t) : UINT64_MAX;
  std::vector<uint32_t> count;
  uint64_t total = 0;
  for (;;) {
    const MeshGrid g = mesh_grid(x0, y0, w, h, gw, gh);
    const uint64_t cap =
        std::min({index_room, budget_room, std::max<uint64_t>(32 * (uint64_t(n) + uint64_t(gw) * gh), kMeshItems)});
    count.assign(size_t(gw) * gh + 1, 0);
    total = 0;
    const bool fits = visit_cells(tris, g, cover, [&](size_t, size_t c) {
      count[c + 1]++;
      return ++total <= cap;
    });
    if (fits) break;
    if (gw == 1 && gh == 1)
      throw ResourceError("a mesh shading's grid needs " + byte_size(mul_sat(total, sizeof(uint32_t))) +
                          " or more, the budget has " + byte_size(mul_sat(std::min(budget_room, index_room), 4)) +
                          " left (--max-memory)");
    gw = std::max(1u, gw / 2);
    gh = std::max(1u, gh / 2);
  }
  charge(budget, (count.size() + total) * sizeof(uint32_t), "a mesh shading's grid");
  // The triangles stay (those left out given back), their pixel copies go.
  kept.reset();
  charge(budget, n * sizeof(MeshTriangle), "a mesh shading's triangles");
  for (size_t c = 1; c < count.size(); c++) count[c] += count[c - 1];
  rec = MeshRecord{};
  rec.x0 = static_cast<float>(x0);
  rec.y0 = static_cast<float>(y0);
  rec.sx = static_cast<float>(gw / w);
  rec.sy = static_cast<float>(gh / h);
  rec.grid_w = static_cast<uint16_t>(gw);
  rec.grid_h = static_cast<uint16_t>(gh);
  rec.ramp = kNoMeshRamp;
  rec.cells = static_cast<uint32_t>(out.mesh_cells.size());
  for (uint32_t c : count) out.mesh_cells.push_back(static_cast<uint32_t>(item_base + c));
  out.mesh_items.resize(item_base + total);
  // Triangles come top-most first: each cell's list is written from its
  // end, so that it ascends.
  std::vector<uint32_t> fill(count.begin() + 1, count.end());
  visit_cells(tris, mesh_grid(x0, y0, w, h, gw, gh), cover, [&](size_t k, size_t c) {
    out.mesh_items[item_base + --fill[c]] = static_cast<uint32_t>(tri_base + k);
    return true;
  });
  return true;
}

}  // namespace mpvg
