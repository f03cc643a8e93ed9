// Mesh paints (core/mesh.h, core/mesh_build.h) against references written
// from the definition in double precision:
//   - mesh_outline: the non-zero area of the outline is the union of the
//     triangles, point by point, and a lattice keeps only its border;
//   - mesh_at: the colour is the linear interpolation over the top-most
//     triangle containing the sample, through the ramp for shadings with a
//     Function, in either integration space, at random points of lattices
//     and of overlapping free triangles.
#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "core/encoding.h"
#include "core/error.h"
#include "core/mesh.h"
#include "core/mesh_build.h"
#include "core/srgb.h"
#include "tests/catch.h"
#include "tests/random_meshes.h"

using namespace mpvg;

namespace {

// Barycentric coordinates of q in triangle (a, b, c): q = a + s (b - a) + t (c - a).
std::optional<std::pair<double, double>> barycentric(Vec2 a, Vec2 b, Vec2 c, Vec2 q) {
  const double det = cross(b - a, c - a);
  if (det == 0) return std::nullopt;
  const Vec2 d = q - a;
  return std::make_pair(cross(d, c - a) / det, cross(b - a, d) / det);
}

// Non-zero winding of a path of lines at q (crossings of a ray to +x).
int winding(const Path& p, Vec2 q) {
  int w = 0;
  for (const Path::Segment& s : p.segments()) {
    const Vec2 a = p.points()[s.first_point], b = p.points()[s.first_point + 1];
    if ((a.y <= q.y) != (b.y <= q.y)) {
      const double x = a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y);
      if (x > q.x) w += b.y > a.y ? 1 : -1;
    }
  }
  return w;
}

// Is q inside a triangle of m, or within `margin` (barycentric) of an edge?
enum class Where { Inside, Outside, Edge };
Where where(const Mesh& m, Vec2 q, double margin) {
  Where w = Where::Outside;
  for (size_t i = 0; i < m.vertices.size(); i += 3) {
    const auto st = barycentric(m.vertices[i].p, m.vertices[i + 1].p, m.vertices[i + 2].p, q);
    if (!st) continue;
    const double d = std::min({st->first, st->second, 1 - st->first - st->second});
    if (d > margin) return Where::Inside;
    if (d > -margin) w = Where::Edge;
  }
  return w;
}

// The colour the definition gives at q (scene units): straight RGBA in the
// integration space, or nothing outside every triangle.
std::optional<std::array<double, 4>> reference(const Mesh& m, Vec2 q, Gamma gamma, double margin) {
  for (size_t i = m.vertices.size(); i >= 3; i -= 3) {
    const MeshVertex* v = &m.vertices[i - 3];
    const auto st = barycentric(v[0].p, v[1].p, v[2].p, q);
    if (!st) continue;
    const auto [s, t] = *st;
    const double d = std::min({s, t, 1 - s - t});
    if (d < -margin) continue;
    if (d < margin) return std::nullopt;  // on an edge: either side is right
    auto channel = [&](auto get) { return get(v[0].color) + s * (get(v[1].color) - get(v[0].color)) + t * (get(v[2].color) - get(v[0].color)); };
    const auto lin = [&](double c) { return gamma == Gamma::Linear ? double(srgb_to_linear(float(c))) : c; };
    if (m.ramp.empty())
      return std::array<double, 4>{channel([&](const RGBA& c) { return lin(c.r); }),
                                   channel([&](const RGBA& c) { return lin(c.g); }),
                                   channel([&](const RGBA& c) { return lin(c.b); }),
                                   channel([](const RGBA& c) { return double(c.a); })};
    const double x = std::clamp(channel([](const RGBA& c) { return double(c.r); }), 0.0, 1.0);
    size_t k = 0;
    while (k + 2 < m.ramp.size() && m.ramp[k + 1].offset <= x) k++;
    const ColorStop &a = m.ramp[k], &b = m.ramp[k + 1];
    const double f = (x - a.offset) / (b.offset - a.offset);
    // A ramp interpolates its stops in sRGB (Gradient::interpolation's default).
    auto mix = [&](double p, double q2) { return p + f * (q2 - p); };
    return std::array<double, 4>{lin(mix(a.color.r, b.color.r)), lin(mix(a.color.g, b.color.g)),
                                 lin(mix(a.color.b, b.color.b)), mix(a.color.a, b.color.a)};
  }
  return std::nullopt;
}

// Compares mesh_at with the reference at n random points of [lo, hi]^2;
// returns the number of points compared (off edges, inside the mesh).
int compare(const Mesh& m, const Affine& view, Gamma gamma, std::mt19937& rng, double lo, double hi, int n) {
  SceneBuilder b(100, 100);
  Paint paint;
  paint.type = PaintType::Mesh;
  paint.index = b.add_mesh(m);
  b.fill(b.add_geometry(mesh_outline(m)), Affine{}, FillRule::NonZero, paint);
  const EncodedScene enc = encode(b.finish(), view, gamma);
  REQUIRE(enc.paint->meshes.size() == 1);
  const PaintTables tables = enc.paint->view(nullptr);
  std::uniform_real_distribution<double> u(lo, hi);
  const Affine inv = view.inverted();
  // Ramps refined for linear integration stay within 1/4096 of the exact
  // curve (test_paint); everything else is float rounding.
  const double tol = !m.ramp.empty() && gamma == Gamma::Linear ? 1.0 / 4096 : 1e-4;
  int compared = 0;
  double worst = 0;
  for (int k = 0; k < n; k++) {
    const Vec2 px{u(rng), u(rng)};
    const auto ref = reference(m, inv.apply(px), gamma, 1e-4);
    if (!ref) continue;
    compared++;
    const Rgba4 got = mesh_at(enc.paint->meshes[0], tables, float(px.x), float(px.y));
    const double a = (*ref)[3];
    const double d = std::max({std::fabs(got.r - (*ref)[0] * a), std::fabs(got.g - (*ref)[1] * a),
                               std::fabs(got.b - (*ref)[2] * a), std::fabs(got.a - a)});
    worst = std::max(worst, d);
    if (d > tol) {
      INFO("at pixel (" << px.x << ", " << px.y << ") ref " << (*ref)[0] << " " << (*ref)[1] << " " << (*ref)[2] << " "
                        << a << " got " << got.r << " " << got.g << " " << got.b << " " << got.a);
      CHECK(d <= tol);
    }
  }
  INFO("worst difference " << worst);
  CHECK(worst <= tol);
  return compared;
}

}  // namespace

TEST_CASE("a mesh's outline fills exactly the union of its triangles", "[paint][mesh]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 105);
  for (int k = 0; k < 12; k++) {
    INFO("case " << k);
    const Mesh m = k % 2 ? random_meshes::lattice(rng, 2 + k, 1 + k / 2, 10, 20, 80, 60)
                         : random_meshes::free_triangles(rng, 1 + k, 0, 100);
    const Path outline = mesh_outline(m);
    if (k % 2) {
      // Shared edges cancel: only the lattice's border is left.
      const int nx = 2 + k, ny = 1 + k / 2;
      CHECK(outline.segments().size() == size_t(2 * (nx + ny)));
    }
    int inside = 0;
    for (int i = 0; i < 4000; i++) {
      const Vec2 q{u(rng), u(rng)};
      const Where w = where(m, q, 1e-9);
      if (w == Where::Edge) continue;
      inside += w == Where::Inside;
      INFO("at (" << q.x << ", " << q.y << ")");
      REQUIRE((winding(outline, q) != 0) == (w == Where::Inside));
    }
    CHECK(inside > 100);
  }
}

TEST_CASE("mesh colours interpolate over the top-most triangle, through the ramp for function shadings",
          "[paint][mesh]") {
  std::mt19937 rng(5);
  int compared = 0;
  for (Gamma gamma : {Gamma::Srgb, Gamma::Linear}) {
    for (int k = 0; k < 6; k++) {
      INFO("gamma " << int(gamma) << " case " << k);
      const Affine view = Affine::translate(3, -2) * Affine::rotate_degrees(17.0 * k) * Affine::scale(1.5, 1.25);
      const Mesh lattice = random_meshes::lattice(rng, 3 + k, 2 + k, 10, 10, 80, 70, k % 2 == 1);
      const Mesh free = random_meshes::free_triangles(rng, 2 + 3 * k, 0, 100);
      compared += compare(lattice, view, gamma, rng, -60, 200, 3000);
      compared += compare(free, view, gamma, rng, -60, 200, 3000);
    }
  }
  INFO(compared << " points compared");
  CHECK(compared > 6000);
}

TEST_CASE("degenerate meshes are rejected or paint nothing", "[paint][mesh]") {
  SceneBuilder b(10, 10);
  Mesh bad;
  bad.vertices = {{{0, 0}, RGBA{1, 0, 0, 1}}, {{1, 1}, RGBA{1, 0, 0, 1}}};
  CHECK_THROWS_AS(b.add_mesh(bad), Error);
  Mesh flat;  // all three corners on a line: no area anywhere
  flat.vertices = {{{0, 0}, RGBA{1, 0, 0, 1}}, {{1, 1}, RGBA{1, 0, 0, 1}}, {{2, 2}, RGBA{1, 0, 0, 1}}};
  CHECK(mesh_outline(flat).empty());
  Paint paint;
  paint.type = PaintType::Mesh;
  paint.index = b.add_mesh(flat);
  b.fill(b.add_geometry(Path::rectangle(0, 0, 10, 10)), Affine{}, FillRule::NonZero, paint);
  const EncodedScene enc = encode(b.finish(), Affine{}, Gamma::Srgb);
  CHECK(enc.paint->meshes.empty());
  CHECK(enc.paint->paints[0].kind == PAINT_SOLID);
  CHECK(enc.paint->paints[0].a == 0.0f);
}

TEST_CASE("a mesh filled over its box paints exactly its triangles (area_by_triangles)", "[paint][mesh]") {
  // The same colours where a triangle holds the point, transparent off
  // every triangle, against the brute-force classification.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-10, 110);
  int inside = 0, outside = 0;
  for (int k = 0; k < 8; k++) {
    Mesh m = k % 2 ? random_meshes::lattice(rng, 3 + k, 2 + k, 10, 10, 80, 70)
                   : random_meshes::free_triangles(rng, 5 + 7 * k, 0, 100);
    m.area_by_triangles = true;
    SceneBuilder b(100, 100);
    Paint paint;
    paint.type = PaintType::Mesh;
    paint.index = b.add_mesh(m);
    b.fill(b.add_geometry(Path::rectangle(-10, -10, 110, 110)), Affine{}, FillRule::NonZero, paint);
    const EncodedScene enc = encode(b.finish(), Affine{}, Gamma::Srgb);
    const PaintTables tables = enc.paint->view(nullptr);
    for (int i = 0; i < 3000; i++) {
      const Vec2 q{u(rng), u(rng)};
      const Where w = where(m, q, 1e-4);
      if (w == Where::Edge) continue;
      const Rgba4 got = mesh_at(enc.paint->meshes[0], tables, float(q.x), float(q.y));
      INFO("case " << k << " at (" << q.x << ", " << q.y << ")");
      if (w == Where::Outside) {
        outside++;
        REQUIRE(got.a == 0.0f);
      } else {
        const auto ref = reference(m, q, Gamma::Srgb, 1e-4);
        if (!ref) continue;  // on an edge of the top-most triangle
        inside++;
        CHECK(std::fabs(got.a - (*ref)[3]) <= 1e-4);
        CHECK(std::fabs(got.r - (*ref)[0] * (*ref)[3]) <= 1e-4);
      }
    }
  }
  CHECK(inside > 1000);
  CHECK(outside > 1000);
}
