// Mesh paints (core/paint/mesh.h, core/paint/mesh_build.h) against references written
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

#include "frame/encoding.h"
#include "core/error.h"
#include "core/paint/mesh.h"
#include "core/paint/mesh_build.h"
#include "core/output/srgb.h"
#include "tests/catch.h"
#include "tests/random_meshes.h"
#include "frame/scene_builder.h"

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
int compare(const Mesh& m, const Affine& view, Gamma gamma, std::mt19937& rng, double lo, double hi, int n,
            const EncodeOptions& options = {}) {
  SceneBuilder b(100, 100);
  Paint paint;
  paint.type = PaintType::Mesh;
  paint.index = b.add_mesh(m);
  b.fill(b.add_geometry(mesh_outline(m)), Affine{}, FillRule::NonZero, paint);
  const EncodedScene enc = encode(b.finish(), view, gamma, options);
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

namespace {

// n triangles of side 0.3 s to s with corners in [0, s]^2 (each covers a
// good part of the mesh's box, as in a soup of large overlapping ones).
Mesh large_triangles(std::mt19937& rng, int n, double s) {
  std::uniform_real_distribution<double> u(0, 1);
  Mesh m;
  for (int k = 0; k < n; k++) {
    const double size = s * (0.3 + 0.7 * u(rng)), x = (s - size) * u(rng), y = (s - size) * u(rng);
    const Vec2 p[3] = {{x, y}, {x + size, y + size * u(rng)}, {x + size * u(rng), y + size}};
    for (const Vec2& q : p)
      m.vertices.push_back({q, RGBA{static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng)), 1}});
  }
  return m;
}

// The encoded mesh of m filled over its outline, with options.
EncodedScene encoded(const Mesh& m, const EncodeOptions& options = {}) {
  SceneBuilder b(100, 100);
  Paint paint;
  paint.type = PaintType::Mesh;
  paint.index = b.add_mesh(m);
  b.fill(b.add_geometry(Path::rectangle(0, 0, 100, 100)), Affine{}, FillRule::NonZero, paint);
  return encode(b.finish(), Affine{}, Gamma::Srgb, options);
}

}  // namespace

TEST_CASE("a mesh's grid lists triangles down to the first that covers the cell, in bounded memory",
          "[paint][mesh]") {
  std::mt19937 rng(17);
  SECTION("a soup of large overlapping triangles: the top-most colour everywhere, few items") {
    const Mesh m = large_triangles(rng, 3000, 100);
    const EncodedScene enc = encoded(m);
    const MeshRecord& r = enc.paint->meshes.at(0);
    const size_t cells = size_t(r.grid_w) * r.grid_h, items = enc.paint->mesh_items.size();
    INFO(cells << " cells, " << items << " items for 3000 triangles");
    // Listed by their boxes, every triangle would be in ~30 % of the cells.
    CHECK(items < 3000 * cells / 20);
    CHECK(compare(m, Affine{}, Gamma::Srgb, rng, 0, 100, 4000) > 3000);
  }
  SECTION("65,537 triangles over the whole grid (the item count past 2^32 of the old grid)") {
    // Two triangles splitting the square along a diagonal, alternately:
    // by their boxes, each would be listed in all 65,536 cells.
    Mesh m;
    for (int k = 0; k < 65537; k++) {
      const float c = static_cast<float>(k % 251) / 250;
      const Vec2 a = k % 2 ? Vec2{0, 0} : Vec2{100, 100};
      for (Vec2 p : {a, Vec2{100, 0}, Vec2{0, 100}}) m.vertices.push_back({p, RGBA{c, 0.5f, 1 - c, 1}});
    }
    const EncodedScene enc = encoded(m);
    const MeshRecord& r = enc.paint->meshes.at(0);
    const size_t cells = size_t(r.grid_w) * r.grid_h, items = enc.paint->mesh_items.size();
    INFO(r.grid_w << " x " << r.grid_h << " cells, " << items << " items");
    CHECK(items <= std::max<size_t>(32 * (65537 + cells), size_t(1) << 25));
    CHECK(enc.paint->mesh_cells.back() == items);
    // The two top-most triangles hold every point off the diagonal.
    const PaintTables t = enc.paint->view(nullptr);
    std::uniform_real_distribution<double> u(0, 100);
    for (int i = 0; i < 2000; i++) {
      const double x = u(rng), y = u(rng);
      if (std::fabs(x + y - 100) < 1e-3) continue;
      const int k = x + y < 100 ? 65535 : 65536;  // odd k: the upper-left half
      const float c = static_cast<float>(k % 251) / 250;
      const Rgba4 got = mesh_at(r, t, float(x), float(y));
      INFO("at (" << x << ", " << y << ")");
      REQUIRE(std::fabs(got.r - c) <= 1e-5);
      REQUIRE(std::fabs(got.b - (1 - c)) <= 1e-5);
    }
  }
  SECTION("a grid over the frame only: triangles outside it are left out") {
    // A lattice 10 times the frame's size around it.
    const Mesh m = random_meshes::lattice(rng, 200, 200, -450, -450, 1000, 1000);
    EncodeOptions o;
    o.frame_width = 100;
    o.frame_height = 100;
    const EncodedScene enc = encoded(m, o);
    const MeshRecord& r = enc.paint->meshes.at(0);
    INFO(enc.paint->mesh_triangles.size() << " triangles kept of 80,000");
    CHECK(enc.paint->mesh_triangles.size() < 80000 / 50);
    CHECK(r.x0 >= -1.0f);
    CHECK(r.x0 + r.grid_w / r.sx <= 101.0f);
    CHECK(compare(m, Affine{}, Gamma::Srgb, rng, 0, 100, 3000, o) > 2500);
  }
  SECTION("the budget: a coarser grid when the lists do not fit, an error when the triangles do not") {
    const Mesh m = large_triangles(rng, 2000, 100);
    const size_t full = encoded(m).paint->mesh_items.size();
    // The triangles and their pixel copies (112 bytes each), and half the items.
    auto budget = std::make_shared<MemoryBudget>(2000 * (72 + 112) + 4 * full / 2);
    EncodeOptions o;
    o.budget = budget.get();
    const EncodedScene enc = encoded(m, o);
    INFO(full << " items unbounded, " << enc.paint->mesh_items.size() << " within the budget");
    CHECK(enc.paint->mesh_items.size() < full);
    CHECK(budget->used() <= budget->limit());
    CHECK(budget->used() >= 2000 * 72 + 4 * enc.paint->mesh_items.size());
    // The same colours from the coarser grid (a budget of its own).
    // (compare fills the mesh's outline: its encoding is charged too.)
    const Path outline = mesh_outline(m);
    MemoryBudget again(budget->limit() + (outline.segments().size() + outline.contours().size()) * sizeof(InputSegment) + 4096);
    o.budget = &again;
    CHECK(compare(m, Affine{}, Gamma::Srgb, rng, 0, 100, 2000, o) > 1500);
    MemoryBudget tiny(2000 * 72);
    o.budget = &tiny;
    try {
      encoded(m, o);
      FAIL("no error");
    } catch (const ResourceError& e) {
      CHECK(std::string(e.what()).find("the budget is") != std::string::npos);
    }
  }
}
