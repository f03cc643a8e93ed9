// Host side of mesh paints (core/mesh.h evaluates them per sample): the
// area a mesh paints, and its records.
#pragma once
#include <functional>

#include "core/paint_data.h"
#include "core/scene.h"

namespace mpvg {

// The union of the mesh's triangles as one path in mesh space, to be filled
// with the non-zero rule: every triangle turned counter-clockwise, edges
// that two triangles share in opposite directions removed (a subdivided
// patch keeps its outline only), the rest chained into closed contours.
// Degenerate triangles are left out.
Path mesh_outline(const Mesh& m);

// Appends the triangles of m, mapped to pixels by to_px, and their grid to
// `out`, and returns the record (ramp = kNoMeshRamp; the caller sets it).
// color converts a vertex colour (straight, sRGB-encoded) to the colour
// space of integration; with a ramp the vertices' t is kept as it is.
// Degenerate triangles are dropped; returns false when none is left.
bool build_mesh(const Mesh& m, const Affine& to_px, const std::function<Rgba4(const RGBA&)>& color, PaintData& out,
                MeshRecord& rec);

}  // namespace mpvg
