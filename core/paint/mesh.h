// Meshes of Gouraud-shaded triangles evaluated per sample (PDF's free-form
// and lattice-form meshes, its Coons and tensor-product patches as MuPDF
// subdivides them, and its function-based shadings sampled on a grid):
// the sample's triangle is found through the mesh's grid (MeshRecord), and
// its colour interpolated linearly over that triangle, then, for shadings
// with a Function, looked up in the ramp. Host/device code shared by both
// executors; the encoder (frame/encoding.cpp) prepares the records.
//
// Invariants (set up by the encoder, relied on here):
//   - a cell lists every triangle that meets it, from the top-most down
//     to the first one that covers the whole cell (the cell taken a little
//     larger against float rounding); those below it are left out, since
//     none can be the top-most at a point of the cell;
//   - a cell's list ascends, so the first containing triangle found from
//     the end is the top-most, as PDF paints later triangles over earlier
//     (and the search stops at the covering one at the latest);
//   - the area a mesh paint fills is the union of its triangles
//     (mesh_outline in core/paint/mesh_build.h), so a sample that no triangle
//     contains by this arithmetic lies on an edge within rounding: it
//     takes the colour of the nearest triangle of its cell (barycentric
//     coordinates clamped), not a colour extrapolated beyond the triangle;
//   - or (MESH_AREA_BY_TRIANGLES) the fill covers more than the union (its
//     box), and the triangles decide per sample: a sample outside all of
//     them beyond rounding is transparent.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/paint/gradient.h"
#include "core/hd.h"
#include "core/paint/paint.h"

namespace mpvg {

// The grid cell of pixel (px, py): clamped to the grid, so that points
// outside the mesh's box still find its border cells.
MPVG_HD_INLINE uint32_t mesh_cell(const MeshRecord& m, float px, float py) {
  const float fx = floorf((px - m.x0) * m.sx), fy = floorf((py - m.y0) * m.sy);
  const uint32_t i = fx <= 0.0f ? 0u : (fx >= float(m.grid_w - 1) ? m.grid_w - 1 : static_cast<uint32_t>(fx));
  const uint32_t j = fy <= 0.0f ? 0u : (fy >= float(m.grid_h - 1) ? m.grid_h - 1 : static_cast<uint32_t>(fy));
  return m.cells + j * m.grid_w + i;
}

// Premultiplied colour of mesh m at pixel (px, py); transparent where the
// cell lists no triangle.
MPVG_HD_NOINLINE inline Rgba4 mesh_at(const MeshRecord& m, const PaintTables& t, float px, float py) {
  // The grid spans the triangles' box. A point outside it is outside
  // every triangle: not painted where the area is the triangles', else the
  // colour at the nearest point of the box (a sliver inside it), found
  // without scanning every triangle of the edge cell it would clamp to
  // (at a seam listing them all; the margin around the image samples such
  // points, core/paint/image_border.h).
  {
    const float fx = (px - m.x0) * m.sx, fy = (py - m.y0) * m.sy;
    const float gw = float(m.grid_w), gh = float(m.grid_h), e = 1e-3f;
    if (!(fx >= 0.0f && fy >= 0.0f && fx <= gw && fy <= gh)) {
      if ((m.flags & MESH_AREA_BY_TRIANGLES) && !(fx >= -e && fy >= -e && fx <= gw + e && fy <= gh + e))
        return Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
      px = m.x0 + fminf(fmaxf(fx, e), gw - e) / m.sx;
      py = m.y0 + fminf(fmaxf(fy, e), gh - e) / m.sy;
    }
  }
  const uint32_t c = mesh_cell(m, px, py);
  const uint32_t first = t.mesh_cells[c], last = t.mesh_cells[c + 1];
  if (first == last) return Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  // The top-most containing triangle, or the one the point is least far
  // outside of (its smallest barycentric coordinate is the largest).
  float best = -INFINITY, bs = 0.0f, bt = 0.0f;
  uint32_t bi = t.mesh_items[last - 1];
  for (uint32_t k = last; k-- > first;) {
    const uint32_t i = t.mesh_items[k];
    const MeshTriangle& tr = t.mesh_triangles[i];
    const float dx = px - tr.ax, dy = py - tr.ay;
    const float s = tr.m00 * dx + tr.m01 * dy, u = tr.m10 * dx + tr.m11 * dy;
    const float d = fminf(fminf(s, u), 1.0f - s - u);
    if (d > best) {
      best = d;
      bs = s;
      bt = u;
      bi = i;
      if (d >= 0.0f) break;
    }
  }
  // Outside every triangle by more than float rounding (a millionth of
  // the triangle in barycentric terms; neighbours' shared edges meet well
  // within it): not painted, where the fill's area is not the union.
  if ((m.flags & MESH_AREA_BY_TRIANGLES) && best < -1e-6f) return Rgba4{0.0f, 0.0f, 0.0f, 0.0f};
  bs = fmaxf(bs, 0.0f);
  bt = fmaxf(bt, 0.0f);
  if (bs + bt > 1.0f) {
    const float k = 1.0f / (bs + bt);
    bs *= k;
    bt *= k;
  }
  const MeshTriangle& tr = t.mesh_triangles[bi];
  Rgba4 col{tr.c0.r + bs * tr.d1.r + bt * tr.d2.r, tr.c0.g + bs * tr.d1.g + bt * tr.d2.g,
            tr.c0.b + bs * tr.d1.b + bt * tr.d2.b, tr.c0.a + bs * tr.d1.a + bt * tr.d2.a};
  if (m.ramp != kNoMeshRamp) col = ramp_at(t.gradients[m.ramp], t.ramp_t, t.ramp_color, col.r);
  return Rgba4{col.r * col.a, col.g * col.a, col.b * col.a, col.a};
}

}  // namespace mpvg
