// Host side of mesh paints (core/paint/mesh.h evaluates them per sample): the
// area a mesh paints, and its records.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>

#include "core/memory_budget.h"
#include "core/paint/paint_data.h"
#include "core/scene.h"

namespace mpvg {

// The union of the mesh's triangles as one path in mesh space, to be filled
// with the non-zero rule: every triangle turned counter-clockwise, edges
// that two triangles share in opposite directions removed (a subdivided
// patch keeps its outline only), the rest chained into closed contours.
// Degenerate triangles are left out. An outline of more than max_edges
// edges is not made: an empty path, *over set (a soup of overlapping
// triangles, whose outline is as large as the mesh: fill its box instead,
// Mesh::area_by_triangles).
Path mesh_outline(const Mesh& m, size_t max_edges = SIZE_MAX, bool* over = nullptr);

// The part of the frame that is sampled, in the coordinates to_px maps to
// (the frame's unit areas, or a pattern tile's grid); unbounded by default.
struct MeshBounds {
  double x0 = -INFINITY, y0 = -INFINITY, x1 = INFINITY, y1 = INFINITY;
};

// Appends the triangles of m, mapped to pixels by to_px, and their grid to
// `out`, and returns the record (ramp = kNoMeshRamp; the caller sets it).
// color converts a vertex colour (straight, sRGB-encoded) to the colour
// space of integration; with a ramp the vertices' t is kept as it is.
// Degenerate triangles, and those outside `bounds`, are dropped; returns
// false when none is left.
//
// The grid covers what of the triangles' box lies in `bounds`, about a
// cell per triangle but no finer than a pixel; a cell lists every
// triangle that meets it (exactly: the triangle, not its box) from the
// top-most down to the first that covers it whole. Its memory is charged
// to `budget` (if any) and bounded: a grid whose lists would pass what
// entries can index, what the budget has left, or 32 items per triangle
// and cell (at least 2^25 items) is made coarser (at 1 x 1 it lists each
// triangle at most once).
// Throws ResourceError when even that does not fit.
bool build_mesh(const Mesh& m, const Affine& to_px, const std::function<Rgba4(const RGBA&)>& color,
                const MeshBounds& bounds, MemoryBudget* budget, PaintData& out, MeshRecord& rec);

}  // namespace mpvg
