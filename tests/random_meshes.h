// Random meshes for the mesh-paint tests (test_mesh, test_gpu): a
// subdivided lattice whose neighbouring triangles share edges exactly (as
// MuPDF's subdivided patches do), and free triangles that overlap, with
// either orientation.
#pragma once
#include <random>

#include "core/scene.h"

namespace random_meshes {

// An nx x ny lattice over [x0, x0 + w] x [y0, y0 + h], inner points
// jittered, each quad split into two triangles in alternating diagonals.
// ramp: colours carry t in [0, 1] (in .r) and the mesh gets a three-stop ramp.
inline mpvg::Mesh lattice(std::mt19937& rng, int nx, int ny, double x0, double y0, double w, double h,
                          bool ramp = false) {
  using namespace mpvg;
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec2> p;
  std::vector<RGBA> c;
  for (int j = 0; j <= ny; j++)
    for (int i = 0; i <= nx; i++) {
      const bool inner = i > 0 && j > 0 && i < nx && j < ny;
      const double jx = inner ? (u(rng) - 0.5) * 0.5 : 0, jy = inner ? (u(rng) - 0.5) * 0.5 : 0;
      p.push_back({x0 + (i + jx) * w / nx, y0 + (j + jy) * h / ny});
      const float t = static_cast<float>(u(rng));
      c.push_back(ramp ? RGBA{t, 0, 0, 1}
                       : RGBA{t, static_cast<float>(u(rng)), static_cast<float>(u(rng)),
                              u(rng) < 0.2 ? static_cast<float>(u(rng)) : 1.0f});
    }
  Mesh m;
  auto vertex = [&](int i, int j) { return MeshVertex{p[size_t(j) * (nx + 1) + i], c[size_t(j) * (nx + 1) + i]}; };
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      const MeshVertex a = vertex(i, j), b = vertex(i + 1, j), cc = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      if ((i + j) % 2) {
        m.vertices.insert(m.vertices.end(), {a, b, cc, a, cc, d});
      } else {
        m.vertices.insert(m.vertices.end(), {a, b, d, b, cc, d});
      }
    }
  if (ramp)
    m.ramp = {{0, RGBA{1, 0, 0, 1}}, {0.5, RGBA{0.2f, 0.9f, 0.1f, 1}}, {1, RGBA{0, 0, 1, 0.5f}}};
  return m;
}

// n triangles with corners anywhere in [x0, x0 + s]^2.
inline mpvg::Mesh free_triangles(std::mt19937& rng, int n, double x0, double s) {
  using namespace mpvg;
  std::uniform_real_distribution<double> u(0, 1);
  Mesh m;
  for (int k = 0; k < 3 * n; k++)
    m.vertices.push_back({{x0 + s * u(rng), x0 + s * u(rng)},
                          RGBA{static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng)), 1}});
  return m;
}

}  // namespace random_meshes
