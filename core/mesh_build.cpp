#include "core/mesh_build.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

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

}  // namespace

Path mesh_outline(const Mesh& m) {
  // Directed edges left after cancelling opposite pairs, with multiplicity.
  std::map<std::pair<Point, Point>, int> edges;
  for (size_t i = 0; i + 2 < m.vertices.size(); i += 3) {
    Vec2 v[3] = {m.vertices[i].p, m.vertices[i + 1].p, m.vertices[i + 2].p};
    if (!oriented(v[0], v[1], v[2])) continue;
    for (int k = 0; k < 3; k++) {
      const Point a = key(v[k]), b = key(v[(k + 1) % 3]);
      auto back = edges.find({b, a});
      if (back != edges.end()) {
        if (--back->second == 0) edges.erase(back);
      } else {
        edges[{a, b}]++;
      }
    }
  }
  // Every point has as many edges in as out: walks from a point return to it.
  std::map<Point, std::vector<Point>> out;
  for (const auto& [e, n] : edges)
    for (int k = 0; k < n; k++) out[e.first].push_back(e.second);
  Path path;
  for (auto& [start, next] : out) {
    while (!next.empty()) {
      path.move_to({start.first, start.second});
      Point cur = start;
      do {
        std::vector<Point>& from = out[cur];
        const Point to = from.back();
        from.pop_back();
        cur = to;
        if (cur != start) path.line_to({cur.first, cur.second});
      } while (cur != start);
      path.close();
    }
  }
  return path;
}

bool build_mesh(const Mesh& m, const Affine& to_px, const std::function<Rgba4(const RGBA&)>& color, PaintData& out,
                MeshRecord& rec) {
  const bool ramp = !m.ramp.empty();
  const uint32_t tri_base = static_cast<uint32_t>(out.mesh_triangles.size());
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  std::vector<std::array<double, 4>> boxes;  // each kept triangle's box in pixels
  for (size_t i = 0; i + 2 < m.vertices.size(); i += 3) {
    const MeshVertex* v = &m.vertices[i];
    const Vec2 a = to_px.apply(v[0].p), b = to_px.apply(v[1].p), c = to_px.apply(v[2].p);
    const Vec2 e1 = b - a, e2 = c - a;
    const double det = cross(e1, e2);
    // No area within float precision: never the only triangle of a point.
    if (!std::isfinite(det) || !(std::fabs(det) > 1e-9 * (dot(e1, e1) + dot(e2, e2)))) continue;
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
    const double bx0 = std::min({a.x, b.x, c.x}), bx1 = std::max({a.x, b.x, c.x});
    const double by0 = std::min({a.y, b.y, c.y}), by1 = std::max({a.y, b.y, c.y});
    boxes.push_back({bx0, by0, bx1, by1});
    x0 = std::min(x0, bx0);
    y0 = std::min(y0, by0);
    x1 = std::max(x1, bx1);
    y1 = std::max(y1, by1);
  }
  const size_t n = boxes.size();
  if (n == 0) return false;
  // About one cell per triangle, square-ish cells, at most 1024 a side.
  const double w = std::max(x1 - x0, 1e-6), h = std::max(y1 - y0, 1e-6);
  const double cells = std::min<double>(double(n), 65536.0);
  const uint32_t gw = static_cast<uint32_t>(std::clamp(std::lround(std::sqrt(cells * w / h)), 1L, 1024L));
  const uint32_t gh = static_cast<uint32_t>(std::clamp(std::lround(std::ceil(cells / gw)), 1L, 1024L));
  rec = MeshRecord{};
  rec.x0 = static_cast<float>(x0);
  rec.y0 = static_cast<float>(y0);
  rec.sx = static_cast<float>(gw / w);
  rec.sy = static_cast<float>(gh / h);
  rec.grid_w = gw;
  rec.grid_h = gh;
  rec.ramp = kNoMeshRamp;
  // The cells a box meets, widened by a thousandth of a cell against the
  // sampler's float rounding.
  auto range = [](double lo, double hi, double origin, double scale, uint32_t count, uint32_t& i0, uint32_t& i1) {
    const double a = std::floor((lo - origin) * scale - 1e-3), b = std::floor((hi - origin) * scale + 1e-3);
    i0 = static_cast<uint32_t>(std::clamp(a, 0.0, double(count - 1)));
    i1 = static_cast<uint32_t>(std::clamp(b, 0.0, double(count - 1)));
  };
  std::vector<uint32_t> count(size_t(gw) * gh + 1, 0);
  for (const auto& bx : boxes) {
    uint32_t i0, i1, j0, j1;
    range(bx[0], bx[2], x0, gw / w, gw, i0, i1);
    range(bx[1], bx[3], y0, gh / h, gh, j0, j1);
    for (uint32_t j = j0; j <= j1; j++)
      for (uint32_t i = i0; i <= i1; i++) count[size_t(j) * gw + i + 1]++;
  }
  for (size_t c = 1; c < count.size(); c++) count[c] += count[c - 1];
  const uint32_t item_base = static_cast<uint32_t>(out.mesh_items.size());
  rec.cells = static_cast<uint32_t>(out.mesh_cells.size());
  for (uint32_t c : count) out.mesh_cells.push_back(item_base + c);
  out.mesh_items.resize(item_base + count.back());
  std::vector<uint32_t> fill(count.begin(), count.end() - 1);
  for (size_t k = 0; k < n; k++) {
    const auto& bx = boxes[k];
    uint32_t i0, i1, j0, j1;
    range(bx[0], bx[2], x0, gw / w, gw, i0, i1);
    range(bx[1], bx[3], y0, gh / h, gh, j0, j1);
    for (uint32_t j = j0; j <= j1; j++)
      for (uint32_t i = i0; i <= i1; i++) out.mesh_items[item_base + fill[size_t(j) * gw + i]++] = tri_base + uint32_t(k);
  }
  return true;
}

}  // namespace mpvg
